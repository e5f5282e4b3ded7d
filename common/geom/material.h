/* material.h - surface description shared by scene objects and model triangles. */
#ifndef LANRAY_MATERIAL_H
#define LANRAY_MATERIAL_H

#include <stdint.h>

#include "base/vec.h"

typedef struct {
    vec3 kd;        /* diffuse colour */
    vec3 ks;        /* specular colour (Phong) */
    real shininess; /* Phong exponent */
    int32_t texture; /* index into the scene's textures, -1 for none; multiplies kd */
} Material;

static inline Material material_default(void)
{
    Material m = {v3(R(0.8), R(0.8), R(0.8)), v3(R(0), R(0), R(0)), R(1), -1};
    return m;
}

#endif
