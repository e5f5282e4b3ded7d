/* camera.h - the pinhole camera.
 *
 * Orientation is yaw (about world +y), pitch (up/down) and roll (about the
 * view direction), in degrees; at zero the camera looks down -z with +y up
 * and +x to the right.  A look-at target is turned into the same angles.
 * Zoom is the distance of the view plane, whose width is 2: the horizontal
 * field of view is 2*atan(1/zoom).
 *
 * Per frame, camera_frame computes u, v and k once; the ray through image
 * position (x, y) (pixels, top-left origin, fractional for sub-samples) then
 * has direction u*x + v*y + k: two multiply-adds per ray. */
#ifndef LANRAY_CAMERA_H
#define LANRAY_CAMERA_H

#include "geom/ray.h"

typedef struct {
    vec3 pos;
    real yaw, pitch, roll; /* degrees */
    real zoom;
} Camera;

typedef struct {
    vec3 org, u, v, k;
    vec3 right, up, forward;
    int width, height;
} CameraFrame;

Camera camera_from_angles(vec3 pos, real yaw, real pitch, real roll, real zoom);
/* Fails (returns -1) when target == pos. */
int camera_look_at(Camera *c, vec3 pos, vec3 target, real roll, real zoom);
/* Zoom for a horizontal field of view in degrees (0 < fov < 180). */
real camera_zoom_for_fov(real fov_degrees);
void camera_basis(const Camera *c, vec3 *right, vec3 *up, vec3 *forward);
CameraFrame camera_frame(const Camera *c, int width, int height);

/* Unnormalised direction through image position (x, y). */
static inline vec3 camera_dir(const CameraFrame *f, real x, real y)
{
    return v3_add(v3_add(v3_scale(f->u, x), v3_scale(f->v, y)), f->k);
}

#endif
