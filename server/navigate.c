/* navigate.c - see navigate.h. */
#include "navigate.h"

#include <math.h>

void nav_init(Nav *n, vec3 centre, real radius)
{
    *n = (Nav){0};
    n->vel = v3_splat(0);
    n->centre = centre;
    n->radius = radius > R(0) && isfinite(radius) ? radius : R(1);
    n->speed = n->radius / (real)NAV_CROSS_S;
}

int nav_move(Nav *n, Camera *c, vec3 want, int fast, double dt)
{
    if (!(dt > 0))
        return 0;
    if (dt > 0.25) /* a stall (a slow frame) is not a leap */
        dt = 0.25;
    const real top = n->speed * (fast ? R(3) : R(1));
    const vec3 target = v3_scale(want, top);
    /* exponential ease: the same path whatever the steps' sizes */
    const real k = (real)(1.0 - exp(-dt / NAV_EASE_S));
    n->vel = v3_add(n->vel, v3_scale(v3_sub(target, n->vel), k));
    if (v3_len(n->vel) < R(1e-3) * n->speed && v3_len(want) == R(0)) {
        n->vel = v3_splat(0);
        return 0;
    }
    vec3 r, u, f;
    camera_basis(c, &r, &u, &f);
    const real s = (real)dt;
    c->pos = v3_add(c->pos, v3_scale(r, n->vel.x * s));
    c->pos = v3_add(c->pos, v3_scale(v3(0, 1, 0), n->vel.y * s));
    c->pos = v3_add(c->pos, v3_scale(f, n->vel.z * s));
    return 1;
}

void nav_frame_all(const Nav *n, Camera *c, int width, int height)
{
    vec3 r, u, f;
    camera_basis(c, &r, &u, &f);
    /* the narrower half-angle of the view (its zoom is the wider side's) */
    real t = c->zoom > R(0) ? R(1) / c->zoom : R(1);
    if (height < width)
        t *= (real)height / (real)width;
    const real half = atan(t);
    c->pos = v3_sub(n->centre, v3_scale(f, n->radius * R(1.1) / sin(half)));
}

/* How far ahead an orbit turns round (and a pan follows): the view axis's
 * point nearest the scene's centre, or a radius ahead where that is
 * behind, beside or at the camera. */
static real orbit_depth(const Nav *n, const Camera *c, vec3 f)
{
    const real d = v3_dot(v3_sub(n->centre, c->pos), f);
    return d > R(0.25) * n->radius ? d : n->radius;
}

void nav_orbit(Nav *n, Camera *c, real yaw, real pitch)
{
    vec3 r, u, f;
    camera_basis(c, &r, &u, &f);
    if (!n->orbiting || !camera_same(c, &n->orbited)) {
        const real d = orbit_depth(n, c, f);
        n->pivot = v3_add(c->pos, v3_scale(f, d));
        n->pivot_d = d;
    }
    c->yaw += yaw;
    c->pitch = real_clamp(c->pitch + pitch, -89, 89);
    camera_basis(c, &r, &u, &f);
    c->pos = v3_sub(n->pivot, v3_scale(f, n->pivot_d));
    n->orbited = *c;
    n->orbiting = 1;
}

void nav_pan(const Nav *n, Camera *c, double dx, double dy, int width)
{
    if (width < 1)
        return;
    vec3 r, u, f;
    camera_basis(c, &r, &u, &f);
    /* world units a pixel: the view plane is 2 wide at distance zoom */
    const real per_px = c->kind == CAMERA_ORTHO ? c->size / (real)width
                                                : R(2) * orbit_depth(n, c, f) / (c->zoom * (real)width);
    c->pos = v3_add(c->pos, v3_scale(r, -(real)dx * per_px));
    c->pos = v3_add(c->pos, v3_scale(u, (real)dy * per_px));
}
