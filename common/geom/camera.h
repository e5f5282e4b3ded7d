/* camera.h - the cameras: pinhole, orthographic and fisheye.
 *
 * Orientation is yaw (about world +y), pitch (up/down) and roll (about the
 * view direction), in degrees; at zero the camera looks down -z with +y up
 * and +x to the right.  A look-at target is turned into the same angles.
 * Zoom is the distance of the view plane, whose width is 2: the horizontal
 * field of view is 2*atan(1/zoom).
 *
 * Per frame, camera_frame computes u, v and k once; the pinhole ray through
 * image position (x, y) (pixels, top-left origin, fractional for
 * sub-samples) then has direction u*x + v*y + k: two multiply-adds per ray.
 *
 * An orthographic camera sends parallel rays along its view direction from
 * a view rectangle `size` world units wide.  A fisheye camera is
 * equidistant: a pixel's angle from the view direction grows with its
 * distance from the image centre, reaching fov/2 at the left and right
 * edges (fov up to 360 degrees: the whole sphere); pixels outside that
 * circle see nothing (the background).  camera_ray gives their rays. */
#ifndef LANRAY_CAMERA_H
#define LANRAY_CAMERA_H

#include "geom/ray.h"

typedef enum { CAMERA_PINHOLE = 0, CAMERA_ORTHO = 1, CAMERA_FISHEYE = 2 } CameraKind;

#define CAMERA_FISHEYE_MAX R(360)

typedef struct {
    vec3 pos;
    real yaw, pitch, roll; /* degrees */
    real zoom;             /* pinhole */
    CameraKind kind;
    real size;             /* orthographic: the view's width in world units */
    real fov;              /* fisheye: the field of view across the width, degrees (0, 360] */
    real aperture, focus;  /* pinhole: a lens this wide (0: none) in focus at this distance */
} Camera;

typedef struct {
    vec3 org, u, v, k;     /* pinhole; orthographic: a ray starts at org + u*x + v*y */
    vec3 right, up, forward;
    int width, height;
    CameraKind kind;
    real cx, cy, rad_per_px;            /* fisheye: image centre, angle per pixel (radians) */
    real lens_radius, focus;            /* thin lens */
} CameraFrame;

Camera camera_from_angles(vec3 pos, real yaw, real pitch, real roll, real zoom);
/* The same camera, field by field (a struct may hold padding). */
int camera_same(const Camera *a, const Camera *b);
/* Fails (returns -1) when target == pos. */
int camera_look_at(Camera *c, vec3 pos, vec3 target, real roll, real zoom);
/* Zoom for a horizontal field of view in degrees (0 < fov < 180). */
real camera_zoom_for_fov(real fov_degrees);
void camera_basis(const Camera *c, vec3 *right, vec3 *up, vec3 *forward);
CameraFrame camera_frame(const Camera *c, int width, int height);

/* The ray through image position (x, y): 0 where the camera sees nothing
 * there (outside a fisheye's circle).  *dir is unit length. */
int camera_ray(const CameraFrame *f, real x, real y, vec3 *org, vec3 *dir);

/* A thin lens: the ray through image position (x, y) from the point (lu,
 * lv) of the unit square mapped onto the lens (a disc of the aperture's
 * diameter about the camera's position, in its right-up plane).  Every
 * such ray of one position meets the pinhole ray of that position at the
 * focus distance (measured along the view direction): points there are
 * sharp, others blur with their distance from that plane. */
void camera_lens_ray(const CameraFrame *f, real x, real y, real lu, real lv, vec3 *org, vec3 *dir);

/* The image position (x, y) whose ray (camera_ray) passes through point p,
 * and p's distance along that ray from its origin: 0 where no ray of the
 * camera does (behind it, outside a fisheye's circle, past an orthographic
 * view's back).  The position may lie outside the frame. */
int camera_project(const CameraFrame *f, vec3 p, real *x, real *y, real *dist);

/* Unnormalised pinhole direction through image position (x, y). */
static inline vec3 camera_dir(const CameraFrame *f, real x, real y)
{
    return v3_add(v3_add(v3_scale(f->u, x), v3_scale(f->v, y)), f->k);
}

#endif
