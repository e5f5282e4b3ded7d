/* material.h - surface description shared by scene objects and model triangles. */
#ifndef LANRAY_MATERIAL_H
#define LANRAY_MATERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "base/vec.h"

typedef struct {
    vec3 kd;        /* diffuse colour */
    vec3 ks;        /* specular colour (Phong) */
    real shininess; /* Phong exponent */
    int32_t texture; /* index into the scene's textures, -1 for none; multiplies kd */
    /* what a ray does at the surface beyond local shading; all zero (as
     * the initialisers that leave them out give) for a plain surface */
    vec3 kr;         /* mirror reflectance: the colour of a metal */
    real roughness;  /* 0: a perfect mirror; up to 1: reflected rays spread
                      * over a lobe this wide (settings rough_samples of them) */
    real ior;        /* > 0: a dielectric (glass) of this index of refraction,
                      * reflecting by Fresnel and transmitting the rest */
    vec3 kt;         /* a dielectric's transmitted colour (1 1 1: clear) */
    vec3 absorb;     /* a dielectric's absorption per unit length inside (Beer-Lambert) */
    vec3 ke;         /* emitted radiance, seen and reflected */
} Material;

#define MATERIAL_IOR_MIN R(0.0625)
#define MATERIAL_IOR_MAX R(16)

static inline int material_reflects(const Material *m) { return m->kr.x > R(0) || m->kr.y > R(0) || m->kr.z > R(0); }
static inline int material_dielectric(const Material *m) { return m->ior > R(0); }
static inline int material_emits(const Material *m) { return m->ke.x > R(0) || m->ke.y > R(0) || m->ke.z > R(0); }
static inline int material_rough(const Material *m) { return material_reflects(m) && m->roughness > R(0); }

/* Whether the material does anything beyond local shading. */
static inline int material_has_optics(const Material *m)
{
    return material_reflects(m) || material_dielectric(m) || material_emits(m);
}

/* What is wrong with a material's reflection, refraction and emission, or NULL. */
static inline const char *material_optics_problem(const Material *m)
{
    if (!v3_is_finite(m->kr) || !v3_is_finite(m->kt) || !v3_is_finite(m->absorb) || !v3_is_finite(m->ke) ||
        !isfinite(m->ior) || !isfinite(m->roughness))
        return "reflection, transmission, absorption and emission must be finite";
    if (v3_min_comp(m->kr) < R(0) || v3_min_comp(m->kt) < R(0) || v3_min_comp(m->absorb) < R(0) ||
        v3_min_comp(m->ke) < R(0))
        return "reflection, transmission, absorption and emission must not be negative";
    if (!(m->roughness >= R(0) && m->roughness <= R(1)))
        return "roughness must be from 0 to 1";
    if (m->ior < R(0) || (m->ior > R(0) && !(m->ior >= MATERIAL_IOR_MIN && m->ior <= MATERIAL_IOR_MAX)))
        return "index of refraction out of range (0: none; else 1/16..16)";
    if (material_dielectric(m) && material_reflects(m))
        return "a dielectric reflects by Fresnel's equations and takes no mirror reflectance";
    return NULL;
}

static inline Material material_default(void)
{
    Material m = {.kd = v3(R(0.8), R(0.8), R(0.8)), .ks = v3(R(0), R(0), R(0)), .shininess = R(1), .texture = -1};
    return m;
}

#endif
