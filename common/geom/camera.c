/* camera.c - camera orientation and per-frame ray constants. */
#include "geom/camera.h"

static const real DEG = REAL_PI / R(180);

Camera camera_from_angles(vec3 pos, real yaw, real pitch, real roll, real zoom)
{
    Camera c = {pos, yaw, pitch, roll, zoom};
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

real camera_zoom_for_fov(real fov) { return R(1) / tan(fov * DEG * R(0.5)); }

void camera_basis(const Camera *c, vec3 *right, vec3 *up, vec3 *forward)
{
    real cy = cos(c->yaw * DEG), sy = sin(c->yaw * DEG);
    real cp = cos(c->pitch * DEG), sp = sin(c->pitch * DEG);
    vec3 f = v3(-sy * cp, sp, -cy * cp);
    /* right does not depend on pitch: no degenerate case looking straight up or down */
    vec3 r = v3(cy, R(0), -sy);
    vec3 u = v3_cross(r, f);
    real cr = cos(c->roll * DEG), sr = sin(c->roll * DEG);
    *right = v3_add(v3_scale(r, cr), v3_scale(u, sr));
    *up = v3_sub(v3_scale(u, cr), v3_scale(r, sr));
    *forward = f;
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
    return fr;
}
