/* camera_path.h - a scripted camera flight: timed camera keys, interpolated.
 *
 * A path file (docs/scene.md "Camera paths") has one key a line:
 *
 *     key TIME CAMERA-KEYS
 *
 * TIME in seconds, increasing from line to line; CAMERA-KEYS as a scene's
 * `camera` directive takes them (position, lookat or yaw/pitch/roll, fov or
 * zoom, ortho or fisheye, aperture and focus), read by the same table.
 * Between keys the position and the angles follow a Catmull-Rom spline
 * through the keys (smooth at every key; yaw the short way round), the zoom
 * changes geometrically and the lens, the width of an orthographic view and
 * a fisheye's angle linearly.  Before the first key and after the last the
 * camera holds still.  Every key has the same projection, and a lens on all
 * keys or on none. */
#ifndef LANRAY_CAMERA_PATH_H
#define LANRAY_CAMERA_PATH_H

#include "base/err.h"
#include "geom/camera.h"

#define CAMERA_PATH_MAX_KEYS 100000
#define CAMERA_PATH_MAX_BYTES ((size_t)16 << 20)

typedef struct {
    real t;
    Camera cam;
} PathKey;

typedef struct {
    PathKey *keys;
    uint32_t count;
} CameraPath;

/* Parses text (modified in place); errors name name:line. */
int camera_path_parse(char *text, size_t len, const char *name, CameraPath *out, Err *err);
int camera_path_load(const char *path, CameraPath *out, Err *err);
void camera_path_free(CameraPath *p);
/* The camera at time t (clamped to the keys' times). */
Camera camera_path_at(const CameraPath *p, real t);
/* The time of the last key. */
real camera_path_end(const CameraPath *p);

#endif
