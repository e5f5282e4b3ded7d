/* scene_preview.h - a scene to look at one model: `lanray-render model.obj`. */
#ifndef LANRAY_SCENE_PREVIEW_H
#define LANRAY_SCENE_PREVIEW_H

#include "scene/scene.h"

/* The model (.obj or .tmd, see model_load) at the origin, seen from the
 * front, right and above by a camera that frames its bounding sphere, lit
 * by a key light over the camera's shoulder and a dim fill from the other
 * side, with shadows.  The scene comes back checked (scene_check).
 * smooth: vertex normals where the model has none (model_load's). */
int scene_preview(const char *model_path, const BvhOptions *bvh, int rebuild, int smooth, Scene **out, Err *err);

#endif
