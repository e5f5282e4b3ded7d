/* material.h - surface description shared by scene objects and model triangles. */
#ifndef LANRAY_MATERIAL_H
#define LANRAY_MATERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "base/field.h"
#include "base/vec.h"
#include "shading/optics.h"

#include <math.h>

typedef struct {
    vec3 kd;        /* diffuse colour */
    vec3 ks;        /* specular colour (Phong) */
    real shininess; /* Phong exponent */
    int32_t texture; /* index into the scene's textures, -1 for none; multiplies kd */
    /* what a ray does at the surface beyond local shading; all zero (as
     * the initialisers that leave them out give) for a plain surface */
    vec3 kr;         /* mirror reflectance: the colour of a metal */
    real roughness;  /* 0: a perfect mirror; up to 1: a rough metal's or a
                      * frosted dielectric's GGX roughness (shading/ggx.h: a
                      * lobe of width roughness^2) */
    real ior;        /* > 0: a dielectric (glass) of this index of refraction,
                      * reflecting by Fresnel and transmitting the rest */
    vec3 kt;         /* a dielectric's transmitted colour (1 1 1: clear) */
    vec3 absorb;     /* a dielectric's absorption per unit length inside (Beer-Lambert) */
    vec3 ke;         /* emitted radiance, seen and reflected */
    /* a procedural checker pattern: squares of kd and kc */
    vec3 kc;           /* the second colour */
    real checker_size; /* > 0: a square's side, in world units (solid) or texture units; 0: no pattern */
    int checker_uv;    /* 1: on the surface's texture coordinates (2D); 0: in space (3D, solid) */
    /* a cutout (leaves, a fence, a chain: MTL map_d, glTF alphaMode MASK):
     * where the opacity of texture `mask` at the hit's texture coordinates
     * is under `cutoff`, the surface is not there; cutoff 0: solid (as the
     * initialisers that leave these out give).  A model's own materials
     * only (model.h's model_cut). */
    int32_t mask;
    real cutoff;
    /* a normal map (glTF normalTexture, MTL norm): texture `normal_map`'s
     * texels, read as data (code / 255 x 2 - 1, not sRGB), are the shading
     * normal in the surface's tangent frame (u, v, normal), their x and y
     * times normal_scale; normal_scale 0: none (as the initialisers that
     * leave these out give).  A model's own materials only. */
    int32_t normal_map;
    real normal_scale;
    /* > 0: normal_map is a grey height map (MTL bump, map_Bump), not a
     * normal map: its white lies this far above its black, in the model's
     * units, and the shading normal is the displaced surface's (Blinn's
     * bump mapping); 0: a normal map (normal_scale then tilts it). */
    real bump_height;
    /* an emission texture (glTF emissiveTexture, MTL map_Ke): the emitted
     * radiance is ke times its colour at the hit (a screen, a lit panel);
     * emit_mapped 0: none (as the initialisers that leave these out give).
     * A model's own materials only. */
    int32_t emit_map;
    int emit_mapped;
    /* a metal-roughness texture (glTF metallicRoughnessTexture): where it
     * is, a hit's metal share is its blue times the factor kr holds (kr =
     * kd x metallicFactor) and its roughness its green times `roughness`,
     * kd the base colour (trace.c's surface_metal); metal_mapped 0: none.
     * A model's own materials only. */
    int32_t metal_map;
    int metal_mapped;
    /* an occlusion texture (glTF occlusionTexture): the ambient light a
     * hit takes is times 1 + ao_strength x (its red - 1); ao_strength 0:
     * none.  A model's own materials only. */
    int32_t ao_map;
    real ao_strength;
    /* a clear coat (a varnish; a plastic's or a glTF non-metal's own
     * specular reflection): a dielectric layer of index MATERIAL_COAT_IOR
     * over the rest of the surface.  Seen at cosine c it reflects coat x
     * Fresnel's share at c (4% head on, all of it at grazing) as the GGX
     * lobe of coat_roughness (the roughness a glTF gives; shading/ggx.h),
     * and the rest of the surface
     * takes 1 - that; coat 0: none (as the initialisers that leave these
     * out give). */
    real coat;
    real coat_roughness;
    /* a metal's reflectance at grazing angles (glTF's metals, Cycles'
     * Principled metals: white): kr is then its colour head on, and at
     * cosine c between the view and the mirror's (or a facet's) normal it
     * reflects kr + (kre - kr) (1 - c)^5 (Schlick; material_mirror_at);
     * all 0: kr at every angle (as the initialisers that leave it out
     * give).  A real metal's rim brightens towards white. */
    vec3 kre;
    /* 1: the cutout's mask does not only cut (its texels under cutoff are
     * holes) but blends: where its opacity a is above the cutoff the
     * surface is a see-through blend of a of itself (glTF's alphaMode
     * BLEND, its base colour texture's alpha; trace_surface_blend: its
     * reflecting terms times a, what it lets through 1 - (1 - transmit) a);
     * 0: solid there.  A model's own materials only, with a cutout and a
     * see-through blend (ior 1). */
    int mask_blend;
} Material;

#define MATERIAL_COAT_IOR R(1.5)

#define MATERIAL_CUTOFF_MAX R(2) /* above 1: every texel of a mask a hole */
#define MATERIAL_NORMAL_SCALE_MAX R(16)
#define MATERIAL_BUMP_HEIGHT_MAX R(1e9)
#define MATERIAL_IOR_MIN R(0.0625)
#define MATERIAL_IOR_MAX R(16)

static inline int material_reflects(const Material *m) { return m->kr.x > R(0) || m->kr.y > R(0) || m->kr.z > R(0); }
static inline int material_dielectric(const Material *m) { return m->ior > R(0); }
static inline int material_emits(const Material *m) { return m->ke.x > R(0) || m->ke.y > R(0) || m->ke.z > R(0); }
static inline int material_rough(const Material *m) { return material_reflects(m) && m->roughness > R(0); }
/* Frosted glass: a dielectric whose facets, of GGX roughness `roughness`,
 * reflect and refract (the path integrator's; the Whitted integrator's
 * glass stays clear). */
static inline int material_frosted(const Material *m) { return material_dielectric(m) && m->roughness > R(0); }
static inline int material_checkered(const Material *m) { return m->checker_size > R(0); }
/* A see-through blend (glTF's alphaMode BLEND, an MTL's dissolve): a
 * clear dielectric of index 1, which lets light through unbent, times its
 * transmitted colour. */
static inline int material_null(const Material *m) { return m->ior == R(1) && m->roughness == R(0); }
static inline int material_cuts(const Material *m) { return m->cutoff > R(0); }
static inline int material_blends(const Material *m) { return m->mask_blend != 0 && material_cuts(m); }
static inline int material_bumps(const Material *m) { return m->normal_scale > R(0); }
static inline int material_heights(const Material *m) { return m->bump_height > R(0); }
static inline int material_emit_mapped(const Material *m) { return m->emit_mapped != 0; }
static inline int material_metal_mapped(const Material *m) { return m->metal_mapped != 0; }
static inline int material_occludes(const Material *m) { return m->ao_strength > R(0); }
static inline int material_coats(const Material *m) { return m->coat > R(0); }
static inline int material_edged(const Material *m) { return m->kre.x > R(0) || m->kre.y > R(0) || m->kre.z > R(0); }

/* The mirror reflectance of m seen at cosine c to its normal: kr, or
 * with kre the colour that rises from kr towards kre as the view grazes. */
static inline vec3 material_mirror_at(const Material *m, real c)
{
    return material_edged(m) ? v3_add(m->kr, v3_scale(v3_sub(m->kre, m->kr), optics_schlick_weight(c))) : m->kr;
}

/* The mean of material_mirror_at over the hemisphere's cosine-weighted
 * directions: kr + (kre - kr) / 21 (the mean of (1 - c)^5 at weight 2c). */
static inline vec3 material_mirror_mean(const Material *m)
{
    return material_edged(m) ? v3_add(m->kr, v3_scale(v3_sub(m->kre, m->kr), R(1) / R(21))) : m->kr;
}
/* Whether the textures the material names (its colour's, a cutout's mask,
 * a normal map, an emission, metal-roughness or occlusion texture) are among
 * `count`; one of the others it does not use must be 0. */
static inline int material_textures_in(const Material *m, int32_t count)
{
    return m->texture >= -1 && m->texture < count &&
           (material_cuts(m) ? m->mask >= 0 && m->mask < count : m->mask == 0) &&
           (material_bumps(m) ? m->normal_map >= 0 && m->normal_map < count : m->normal_map == 0) &&
           (material_emit_mapped(m) ? m->emit_map >= 0 && m->emit_map < count : m->emit_map == 0) &&
           (material_metal_mapped(m) ? m->metal_map >= 0 && m->metal_map < count : m->metal_map == 0) &&
           (material_occludes(m) ? m->ao_map >= 0 && m->ao_map < count : m->ao_map == 0);
}
/* Whether a surface of this material needs its texture coordinates. */
static inline int material_wants_uv(const Material *m) { return m->texture >= 0 || (material_checkered(m) && m->checker_uv); }

/* The diffuse colour kd of a checkered material at point p (solid) or
 * texture coordinates (u, v): kd or kc by the parity of the square, the
 * squares' corners at whole multiples of the size from the origin.  kd
 * where the pattern needs coordinates the surface lacks. */
static inline vec3 material_checker(const Material *m, vec3 kd, vec3 p, real u, real v, int has_uv)
{
    const real k = R(1) / m->checker_size;
    long n;
    if (m->checker_uv) {
        if (!has_uv)
            return kd;
        n = (long)floor(u * k) + (long)floor(v * k);
    } else {
        n = (long)floor(p.x * k) + (long)floor(p.y * k) + (long)floor(p.z * k);
    }
    return n & 1 ? m->kc : kd;
}
/* The mean over [x - w/2, x + w/2] of the square wave that is +1 on the
 * even squares (floor(x) even) and -1 on the odd ones: the difference of
 * its integral, a triangle wave, at the box's ends over the width (Inigo
 * Quilez's filtered checkerboard); the wave itself at a point (w ~ 0). */
static inline real material_square_mean(real x, real w)
{
    if (!(w > R(1e-4)))
        return (long)floor(x) & 1 ? R(-1) : R(1);
    const real a = (x - R(0.5) * w) * R(0.5), b = (x + R(0.5) * w) * R(0.5);
    return R(2) * (fabs(a - floor(a) - R(0.5)) - fabs(b - floor(b) - R(0.5))) / w;
}

/* material_checker averaged over a sample's footprint, a box `width`
 * wide on each axis (world units for the solid pattern, texture units on
 * x and y with checker_uv): its two colours in the shares of the box that
 * each covers, which the parity of a product of square waves gives, axis
 * by axis (the box is separable).  Far off, where a footprint covers many
 * squares, the floor turns to their mean instead of the moire that one
 * point a sample makes of them. */
static inline vec3 material_checker_box(const Material *m, vec3 kd, vec3 p, real u, real v, int has_uv, vec3 width)
{
    const real k = R(1) / m->checker_size;
    real even;
    if (m->checker_uv) {
        if (!has_uv)
            return kd;
        even = material_square_mean(u * k, width.x * k) * material_square_mean(v * k, width.y * k);
    } else {
        even = material_square_mean(p.x * k, width.x * k) * material_square_mean(p.y * k, width.y * k) *
               material_square_mean(p.z * k, width.z * k);
    }
    const real t = R(0.5) - R(0.5) * even; /* the odd squares' share */
    return v3_add(v3_scale(kd, R(1) - t), v3_scale(m->kc, t));
}

/* Whether the material does anything beyond local shading. */
static inline int material_has_optics(const Material *m)
{
    return material_reflects(m) || material_dielectric(m) || material_emits(m);
}

/* The material's fields (field.h): the scene file's `material` keys, the
 * wire's and the .tmd's material, their checks and docs. */
extern const FieldKind material_kind;

/* Every field at its default: a grey diffuse surface, no texture. */
Material material_default(void);

/* The Phong exponent that matches a microfacet lobe of this (GGX)
 * roughness: 2 / a^2 - 2, a = roughness^2, at least 1; 20000 (a point of
 * light) for a nearly smooth one.  How an imported metal's highlight
 * (the Whitted integrator's light on it) follows its roughness, in the
 * importer and at a metal-roughness texture's texel. */
static inline real material_phong_exponent(real roughness)
{
    const real a = roughness * roughness;
    return a > R(0.01) ? real_max(R(2) / (a * a) - R(2), R(1)) : R(20000);
}

/* Whether a clear coat is smooth enough to be a mirror: a roughness up to
 * 0.1, whose GGX lobe (width 0.01) is nearly a point of light.  The
 * Whitted integrator traces its reflected ray (and shows the point of a
 * light); the path integrator takes it as a mirror share, which a point
 * light, having no size, does not show in (a lobe of that exponent made
 * fireflies of every diffuse bounce that met it: a point light's caustic). */
static inline int material_coat_smooth(const Material *m) { return m->coat_roughness <= R(0.1); }

/* m without its metal-roughness texture: diffuse in its base colour (kd),
 * no mirror, no highlight, as a material whose texture is not read at all. */
Material material_unmetal(Material m);
/* m without any texture (where its textures did not come along): no
 * colour texture, holes, tilt, glow, metal map or occlusion. */
Material material_untextured(Material m);

/* The defaults that follow from what a scene file gave: a mirror or a
 * glass is that alone unless a diffuse colour is given, and a glass is
 * clear unless a transmitted colour is. */
void material_file_defaults(Material *m, FieldSet given);

/* What is wrong with a material's values (a field out of its range, a
 * dielectric with a mirror reflectance), into buf; or NULL. */
const char *material_problem(const Material *m, char *buf, size_t size);

#endif
