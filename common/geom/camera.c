/* camera.c - camera orientation and per-frame ray constants. */
#include "geom/camera.h"

#include "base/dmath.h"
#include "base/sample.h"

static const real DEG = REAL_PI / R(180);

Camera camera_from_angles(vec3 pos, real yaw, real pitch, real roll, real zoom)
{
    Camera c = {.pos = pos, .yaw = yaw, .pitch = pitch, .roll = roll, .zoom = zoom, .kind = CAMERA_PINHOLE};
    return c;
}

int camera_look_at(Camera *c, vec3 pos, vec3 target, real roll, real zoom)
{
    vec3 d = v3_sub(target, pos);
    real len = v3_len(d);
    if (!(len > R(0)) || !isfinite(len))
        return -1;
    d = v3_scale(d, R(1) / len);
    /* forward = (-sin(yaw) cos(pitch), sin(pitch), -cos(yaw) cos(pitch)) */
    real pitch = asin(real_clamp(d.y, R(-1), R(1)));
    real yaw = (d.x == R(0) && d.z == R(0)) ? R(0) : atan2(-d.x, -d.z);
    *c = camera_from_angles(pos, yaw / DEG, pitch / DEG, roll, zoom);
    return 0;
}

real camera_zoom_for_fov(real fov) { return R(1) / dmath_tanr(fov * DEG * R(0.5)); }

void camera_basis(const Camera *c, vec3 *right, vec3 *up, vec3 *forward)
{
    real cy, sy, cp, sp;
    dmath_sincosr(c->yaw * DEG, &sy, &cy);
    dmath_sincosr(c->pitch * DEG, &sp, &cp);
    vec3 f = v3(-sy * cp, sp, -cy * cp);
    /* right does not depend on pitch: no degenerate case looking straight up or down */
    vec3 r = v3(cy, R(0), -sy);
    vec3 u = v3_cross(r, f);
    real cr, sr;
    dmath_sincosr(c->roll * DEG, &sr, &cr);
    *right = v3_add(v3_scale(r, cr), v3_scale(u, sr));
    *up = v3_sub(v3_scale(u, cr), v3_scale(r, sr));
    *forward = f;
}

int camera_same(const Camera *a, const Camera *b)
{
    return a->pos.x == b->pos.x && a->pos.y == b->pos.y && a->pos.z == b->pos.z && a->yaw == b->yaw &&
           a->pitch == b->pitch && a->roll == b->roll && a->zoom == b->zoom && a->kind == b->kind &&
           a->size == b->size && a->fov == b->fov && a->aperture == b->aperture && a->focus == b->focus;
}

CameraFrame camera_frame(const Camera *c, int width, int height)
{
    CameraFrame fr;
    camera_basis(c, &fr.right, &fr.up, &fr.forward);
    fr.org = c->pos;
    fr.width = width;
    fr.height = height;
    /* the view plane is 2 wide at distance zoom; square pixels */
    real px = R(2) / (real)width;
    fr.u = v3_scale(fr.right, px);
    fr.v = v3_scale(fr.up, -px);
    fr.k = v3_add(v3_sub(v3_scale(fr.forward, c->zoom), fr.right), v3_scale(fr.up, (real)height * px * R(0.5)));
    fr.kind = c->kind;
    fr.cx = (real)width * R(0.5);
    fr.cy = (real)height * R(0.5);
    fr.rad_per_px = R(0);
    fr.lens_radius = c->kind == CAMERA_PINHOLE ? c->aperture * R(0.5) : R(0);
    fr.focus = c->focus;
    if (c->kind == CAMERA_ORTHO) {
        /* the view rectangle, size wide, centred on the camera's position */
        real w = c->size / (real)width;
        fr.u = v3_scale(fr.right, w);
        fr.v = v3_scale(fr.up, -w);
        fr.org = v3_add(v3_sub(c->pos, v3_scale(fr.right, c->size * R(0.5))), v3_scale(fr.up, (real)height * w * R(0.5)));
    } else if (c->kind == CAMERA_FISHEYE) {
        /* fov / 2 at the circle's edge, half the width from the centre */
        fr.rad_per_px = c->fov * DEG * R(0.5) / fr.cx;
    }
    return fr;
}

void camera_lens_ray(const CameraFrame *f, real x, real y, real lu, real lv, vec3 *org, vec3 *dir)
{
    vec3 d = v3_norm(camera_dir(f, x, y));
    vec3 focal = v3_madd(f->org, d, f->focus / v3_dot(d, f->forward));
    real dx, dy;
    sample_disc(lu, lv, &dx, &dy);
    *org = v3_add(f->org, v3_scale(v3_add(v3_scale(f->right, dx), v3_scale(f->up, dy)), f->lens_radius));
    *dir = v3_norm(v3_sub(focal, *org));
}

int camera_ray(const CameraFrame *f, real x, real y, vec3 *org, vec3 *dir)
{
    switch (f->kind) {
    case CAMERA_ORTHO:
        *org = v3_add(v3_add(f->org, v3_scale(f->u, x)), v3_scale(f->v, y));
        *dir = f->forward;
        return 1;
    case CAMERA_FISHEYE: {
        real dx = x - f->cx, dy = f->cy - y; /* up is +dy */
        real r = sqrt(dx * dx + dy * dy);
        if (r > f->cx) /* outside the image circle (its radius is half the width) */
            return 0;
        real theta = r * f->rad_per_px;
        vec3 side = r > R(0) ? v3_add(v3_scale(f->right, dx / r), v3_scale(f->up, dy / r)) : f->right;
        *org = f->org;
        real st, ct;
        dmath_sincosr(theta, &st, &ct);
        *dir = v3_norm(v3_add(v3_scale(f->forward, ct), v3_scale(side, st)));
        return 1;
    }
    default:
        *org = f->org;
        *dir = v3_norm(camera_dir(f, x, y));
        return 1;
    }
}

int camera_project(const CameraFrame *f, vec3 p, real *x, real *y, real *dist)
{
    const vec3 d = v3_sub(p, f->org);
    const real dr = v3_dot(d, f->right), du = v3_dot(d, f->up), df = v3_dot(d, f->forward);
    switch (f->kind) {
    case CAMERA_ORTHO: /* rays along forward from the view rectangle */
        if (!(df > R(0)))
            return 0;
        *x = dr / v3_dot(f->u, f->right);
        *y = du / v3_dot(f->v, f->up);
        *dist = df;
        return 1;
    case CAMERA_FISHEYE: {
        const real len = v3_len(d);
        if (!(len > R(0)))
            return 0;
        const real side = sqrt(dr * dr + du * du);
        const real r = atan2(side, df) / f->rad_per_px; /* the angle from forward, as pixels from the centre */
        if (r > f->cx)
            return 0;
        *x = f->cx + (side > R(0) ? r * dr / side : R(0));
        *y = f->cy - (side > R(0) ? r * du / side : R(0));
        *dist = len;
        return 1;
    }
    default: { /* d is along u x + v y + k, whose forward part is k's */
        if (!(df > R(0)))
            return 0;
        const real s = v3_dot(f->k, f->forward) / df;
        *x = (s * dr - v3_dot(f->k, f->right)) / v3_dot(f->u, f->right);
        *y = (s * du - v3_dot(f->k, f->up)) / v3_dot(f->v, f->up);
        *dist = v3_len(d);
        return 1;
    }
    }
}
