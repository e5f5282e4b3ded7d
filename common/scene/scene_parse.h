/* scene_parse.h - the text scene format (docs/scene.md).
 *
 * One directive per line, then keyword/value pairs in any order:
 *   sphere centre 0 1 0 radius 1 material red
 * Errors name the file, the line and what was expected. */
#ifndef LANRAY_SCENE_PARSE_H
#define LANRAY_SCENE_PARSE_H

#include <stddef.h>

#include "scene/scene.h"

/* Parses scene text (NUL-terminated, modified in place); relative file names
 * are resolved against dir.  `bvh` is the builder for models read from OBJ;
 * when `force` is set, .tmd models are rebuilt with it too.  The scene comes
 * back checked (scene_check). */
int scene_parse(char *text, size_t len, const char *name, const char *dir, const BvhOptions *bvh, int force,
                Scene **out, Err *err);
int scene_load(const char *path, const BvhOptions *bvh, int force, Scene **out, Err *err);
/* A camera from a `camera` directive's fields alone, "position 0 1 5
 * lookat 0 0 0 fov 40" (lanray-render --camera, named `name` in errors),
 * or a whole `camera ...` line (camera_line's); -1 with the reason. */
int scene_parse_camera(const char *text, const char *name, Camera *out, Err *err);

#endif
