/* scene_default.h - the built-in scene used when no scene file is given. */
#ifndef LANRAY_SCENE_DEFAULT_H
#define LANRAY_SCENE_DEFAULT_H

#include "scene/scene.h"

/* A floor, three spheres, a textured quad (two triangles), a smooth torus-knot
 * model, a point light and a soft spot light.  The model's BVH uses opt. */
int scene_default(Scene **out, const BvhOptions *opt, Err *err);
/* The torus-knot mesh (also used by tests): segments x sides quads. */
int mesh_torus_knot(Mesh *m, int segments, int sides, Err *err);

#endif
