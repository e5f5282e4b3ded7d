/* material.c - the material's field table (see material.h and field.h).
 * The table's order is the wire's and the groups say what a material
 * pays for: a mirror's reflectance and roughness, a dielectric's index,
 * colour and absorption, an emitter's radiance travel only where set. */
#include "shading/material.h"

#include <stdio.h>
#include <string.h>

#define OFF(f) offsetof(Material, f)
enum { GROUP_MIRROR = 1, GROUP_DIELECTRIC = 2, GROUP_EMIT = 3, GROUP_CHECKER = 4, GROUP_CUTOUT = 5, GROUP_NORMAL = 6, GROUP_EMIT_MAP = 7, GROUP_METAL_MAP = 8,
       GROUP_OCCLUSION = 9, GROUP_BUMP = 10, GROUP_COAT = 11,
       GROUP_EDGE = 12, GROUP_BLEND = 13 };

static const Field fields[] = {
    {.key = "diffuse", .type = FIELD_VEC, .off = OFF(kd), .hi = FIELD_INF, .def = 0.8,
     .shown_default = "0.8 0.8 0.8 (0 0 0 with `reflect` or `ior`)",
     .doc = "diffuse colour (linear light), multiplied by the texture"},
    {.key = "specular", .type = FIELD_VEC, .off = OFF(ks), .hi = FIELD_INF, .doc = "Phong highlight colour"},
    {.key = "shininess", .type = FIELD_REAL, .off = OFF(shininess), .hi = FIELD_INF, .def = 1,
     .doc = "Phong exponent: larger is a smaller, sharper highlight"},
    {.key = "texture", .type = FIELD_NAME, .off = OFF(texture), .def = -1,
     .doc = "a `texture` by its name, multiplying the diffuse colour"},
    {.key = "reflect", .type = FIELD_VEC, .group = GROUP_MIRROR, .off = OFF(kr), .hi = FIELD_INF,
     .doc = "mirror reflectance: the colour of a metal; with `ior`, a mirror share over the glass, whose "
            "Fresnel reflection keeps 1 - max(reflect) of its strength"},
    {.key = "roughness", .type = FIELD_REAL, .group = GROUP_MIRROR, .off = OFF(roughness), .hi = 1,
     .doc = "a rough metal's or frosted glass's GGX roughness: how far its reflection (and refraction) spreads "
            "(0: a perfect mirror, clear glass); needs `reflect` or `ior`"},
    {.key = "ior", .type = FIELD_REAL, .group = GROUP_DIELECTRIC, .flags = FIELD_ZERO_OK, .off = OFF(ior),
     .lo = 0.0625, .hi = 16, .shown_default = "none",
     .doc = "index of refraction: a dielectric (glass, water), reflecting by Fresnel and transmitting the rest"},
    {.key = "transmit", .type = FIELD_VEC, .group = GROUP_DIELECTRIC, .off = OFF(kt), .hi = FIELD_INF,
     .shown_default = "1 1 1 (clear)", .doc = "a dielectric's transmitted colour; needs `ior`"},
    {.key = "absorb", .type = FIELD_VEC, .group = GROUP_DIELECTRIC, .off = OFF(absorb), .hi = FIELD_INF,
     .doc = "a dielectric's absorption per unit length inside it (Beer-Lambert); needs `ior`"},
    {.key = "emit", .type = FIELD_VEC, .group = GROUP_EMIT, .off = OFF(ke), .hi = FIELD_INF,
     .doc = "emitted radiance, seen and reflected (a lamp: see below)"},
    {.key = "checker", .type = FIELD_VEC, .group = GROUP_CHECKER, .off = OFF(kc), .hi = FIELD_INF,
     .doc = "a checker pattern's second colour: squares of `diffuse` and this"},
    {.key = "checker_size", .type = FIELD_REAL, .group = GROUP_CHECKER, .flags = FIELD_ZERO_OK, .off = OFF(checker_size),
     .lo = 1e-9, .hi = FIELD_INF, .shown_default = "1 (with `checker`)",
     .doc = "a square's side: world units (a solid pattern), or texture units with `checker_uv`; needs `checker`"},
    {.key = "checker_uv", .type = FIELD_FLAG, .group = GROUP_CHECKER, .off = OFF(checker_uv),
     .doc = "the pattern on the surface's texture coordinates (2D), not in space (3D); needs `checker`"},
    /* a model's own materials only (cutouts: MTL map_d, glTF alphaMode
     * MASK; normal maps: MTL norm, glTF normalTexture; emission textures:
     * MTL map_Ke, glTF emissiveTexture; glTF's metal-roughness and
     * occlusion textures):
     * on the wire and in
     * .tmd files, not scene-file keywords (a scene's spheres, planes,
     * triangles and instances are solid and take their normals as given) */
    {.key = "mask", .type = FIELD_NAME, .group = GROUP_CUTOUT, .flags = FIELD_WIRE, .off = OFF(mask),
     .doc = "a cutout's texture: where its opacity (its alpha, or a grey image's level) is under `cutoff`, the "
            "surface is not there"},
    {.key = "cutoff", .type = FIELD_REAL, .group = GROUP_CUTOUT, .flags = FIELD_WIRE | FIELD_ZERO_OK, .off = OFF(cutoff),
     .lo = 1e-6, .hi = 2, .doc = "the opacity under which a cutout's texels are holes (above 1: all); 0: no cutout"},
    {.key = "normal_map", .type = FIELD_NAME, .group = GROUP_NORMAL, .flags = FIELD_WIRE, .off = OFF(normal_map),
     .doc = "a normal map's texture: its texels, read as data, are the shading normal in the surface's tangent frame"},
    {.key = "normal_scale", .type = FIELD_REAL, .group = GROUP_NORMAL, .flags = FIELD_WIRE | FIELD_ZERO_OK,
     .off = OFF(normal_scale), .lo = 1e-6, .hi = 16,
     .doc = "how far the normal map tilts the normal (its x and y times this); 0: no normal map"},
    {.key = "bump_height", .type = FIELD_REAL, .group = GROUP_BUMP, .flags = FIELD_WIRE | FIELD_ZERO_OK,
     .off = OFF(bump_height), .lo = 1e-9, .hi = 1e9,
     .doc = "with a normal map: it is a grey height map instead, its white this far above its black (the model's "
            "units), shading as the displaced surface would; 0: a normal map"},
    {.key = "emit_map", .type = FIELD_NAME, .group = GROUP_EMIT_MAP, .flags = FIELD_WIRE, .off = OFF(emit_map),
     .doc = "an emission texture: the emitted radiance is `emit` times its colour"},
    {.key = "emit_mapped", .type = FIELD_FLAG, .group = GROUP_EMIT_MAP, .flags = FIELD_WIRE, .off = OFF(emit_mapped),
     .doc = "whether `emit_map` names a texture (0: no emission texture)"},
    {.key = "metal_map", .type = FIELD_NAME, .group = GROUP_METAL_MAP, .flags = FIELD_WIRE, .off = OFF(metal_map),
     .doc = "a metal-roughness texture: its blue scales the metal share (`reflect` over `diffuse`), its green "
            "`roughness`"},
    {.key = "metal_mapped", .type = FIELD_FLAG, .group = GROUP_METAL_MAP, .flags = FIELD_WIRE,
     .off = OFF(metal_mapped), .doc = "whether `metal_map` names a texture (0: none)"},
    {.key = "ao_map", .type = FIELD_NAME, .group = GROUP_OCCLUSION, .flags = FIELD_WIRE, .off = OFF(ao_map),
     .doc = "an occlusion texture: its red darkens the ambient light"},
    {.key = "ao_strength", .type = FIELD_REAL, .group = GROUP_OCCLUSION, .flags = FIELD_WIRE | FIELD_ZERO_OK,
     .off = OFF(ao_strength), .lo = 1e-6, .hi = 1,
     .doc = "how much: the ambient light times 1 + this x (red - 1); 0: no occlusion texture"},
    {.key = "coat", .type = FIELD_REAL, .group = GROUP_COAT, .off = OFF(coat), .hi = 1,
     .doc = "a clear coat's strength: a varnish of index 1.5 over the surface, reflecting Fresnel's share of the "
            "light (4% head on, all at grazing) times this, the rest of the surface lit by what it lets through"},
    {.key = "coat_roughness", .type = FIELD_REAL, .group = GROUP_COAT, .off = OFF(coat_roughness), .hi = 1,
     .doc = "how far the coat's reflection spreads (0: a mirror-smooth varnish); needs `coat`"},
    {.key = "reflect_edge", .type = FIELD_VEC, .group = GROUP_EDGE, .off = OFF(kre), .hi = 1,
     .shown_default = "none", .doc = "a metal's reflectance at grazing angles (1 1 1 for a real metal, glTF's): "
                                     "`reflect` is then its colour head on, rising to this as the view grazes "
                                     "(Schlick's (1 - cos)^5); needs `reflect`"},
    {.key = "mask_blend", .type = FIELD_FLAG, .group = GROUP_BLEND, .flags = FIELD_WIRE, .off = OFF(mask_blend),
     .doc = "the cutout's opacity above its cutoff blends the surface with what lies behind (glTF's alphaMode BLEND) "
            "instead of leaving it solid"},
};

static const FieldRule rules[] = {
    {RULE_NEEDS, "transmit", "ior", "'transmit' of material needs 'ior' (a dielectric)", NULL},
    {RULE_NEEDS, "absorb", "ior", "'absorb' of material needs 'ior' (a dielectric)", NULL},
    {RULE_NEEDS, "roughness", "reflect",
     "'roughness' of material needs 'reflect' (a rough metal) or 'ior' (frosted glass)", "ior"},
    {RULE_NEEDS, "checker_size", "checker", "'checker_size' of material needs 'checker' (the second colour)", NULL},
    {RULE_NEEDS, "checker_uv", "checker", "'checker_uv' of material needs 'checker' (the second colour)", NULL},
    {RULE_NEEDS, "coat_roughness", "coat", "'coat_roughness' of material needs 'coat' (a clear coat)", NULL},
    {RULE_NEEDS, "reflect_edge", "reflect", "'reflect_edge' of material needs 'reflect' (a metal's colour head on)",
     NULL},
    {0, NULL, NULL, NULL, NULL},
};

const FieldKind material_kind = {.name = "material", .size = sizeof(Material), .fields = fields,
                                 .count = sizeof fields / sizeof *fields, .rules = rules, .group_count = 13};

Material material_default(void)
{
    Material m;
    memset(&m, 0, sizeof m);
    field_defaults(&material_kind, &m, sizeof m, 0);
    return m;
}

void material_file_defaults(Material *m, FieldSet given)
{
    const FieldKind *k = &material_kind;
    if ((field_given(k, given, "reflect") || field_given(k, given, "ior")) && !field_given(k, given, "diffuse"))
        m->kd = v3_splat(R(0));
    if (field_given(k, given, "ior") && !field_given(k, given, "transmit"))
        m->kt = v3_splat(R(1));
    if (field_given(k, given, "checker") && !field_given(k, given, "checker_size"))
        m->checker_size = R(1);
}

Material material_unmetal(Material m)
{
    m.metal_map = 0, m.metal_mapped = 0;
    m.kr = m.ks = m.kre = v3_splat(R(0));
    m.roughness = 0;
    m.shininess = R(1);
    return m;
}

Material material_untextured(Material m)
{
    if (material_metal_mapped(&m))
        m = material_unmetal(m);
    m.texture = -1;
    m.mask = 0, m.cutoff = 0, m.mask_blend = 0;
    m.normal_map = 0, m.normal_scale = 0, m.bump_height = 0;
    m.emit_map = 0, m.emit_mapped = 0;
    m.ao_map = 0, m.ao_strength = 0;
    return m;
}

const char *material_problem(const Material *m, char *buf, size_t size)
{
    if (field_problem(&material_kind, m, 0, buf, size))
        return buf;
    /* a texture index a material does not use (its gate off) stays 0 */
    const struct {
        int32_t index;
        int used;
        const char *what, *gate;
    } maps[] = {{m->mask, material_cuts(m), "a mask", "a cutoff"},
                {m->normal_map, material_bumps(m), "a normal map", "a normal_scale"},
                {m->emit_map, material_emit_mapped(m), "an emission texture", "emit_mapped"},
                {m->metal_map, material_metal_mapped(m), "a metal-roughness texture", "metal_mapped"},
                {m->ao_map, material_occludes(m), "an occlusion texture", "an ao_strength"}};
    for (size_t i = 0; i < sizeof maps / sizeof *maps; i++)
        if (!maps[i].used && maps[i].index != 0) {
            snprintf(buf, size, "%s (texture %d) without %s", maps[i].what, maps[i].index, maps[i].gate);
            return buf;
        }
    if (material_coats(m) && material_dielectric(m)) {
        snprintf(buf, size, "a coat on a dielectric (its own Fresnel reflection is its coat)");
        return buf;
    }
    if (m->mask_blend && !(material_cuts(m) && material_dielectric(m) && m->ior == R(1))) {
        snprintf(buf, size, "a mask_blend without a cutout's mask or a see-through blend (ior 1) to blend");
        return buf;
    }
    if (material_heights(m) && !material_bumps(m)) {
        snprintf(buf, size, "a bump_height without a normal map (a normal_scale) to be its height map");
        return buf;
    }
    return NULL;
}
