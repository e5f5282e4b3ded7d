/* scene_gltf.h - a glTF's own camera and lights (model/gltf_scene.h: what
 * Blender's exporter writes of a scene, KHR_lights_punctual) taken into a
 * scene, placed as an instance places the model's meshes: for a glTF
 * opened directly (`lanray-render scene.glb`, scene_preview) and for a
 * scene file's `instance MODEL lights camera`, so that a scene exported
 * from Blender can be put in a scene file and keep its lamps and its view. */
#ifndef LANRAY_SCENE_GLTF_H
#define LANRAY_SCENE_GLTF_H

#include "scene/scene.h"

/* What to take, and what was taken. */
enum { SCENE_GLTF_LIGHTS = 1, SCENE_GLTF_CAMERA = 2 };

/* Whether path names a glTF (by its ending, as the importer is chosen). */
int scene_gltf_is(const char *path);

/* From the glTF at path (its JSON read again; the importer read its
 * meshes): with SCENE_GLTF_LIGHTS in `want`, each light it gives added to
 * s (those a float holds, in lanray's units); with SCENE_GLTF_CAMERA, s's
 * camera made its first camera (glTF's vertical field of view across the
 * file's aspect ratio, else 4:3, as lanray's horizontal one).  Both placed
 * by `place` (its translate, rotate and scale; NULL: as the file has them).
 * *got: the bits of `want` taken (a file without lights or camera is no
 * error here, nor lights or a camera that cannot be placed: past a
 * float's range, or looking nowhere; a path that is no glTF has neither).
 * 0, or -1 with err set (out of memory). */
int scene_gltf_take(Scene *s, const char *path, const Instance *place, int want, int *got, Err *err);

#endif
