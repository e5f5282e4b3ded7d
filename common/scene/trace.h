/* trace.h - rays against a whole prepared scene: closest hit, any hit, and
 * the surface (point, normals, texture coordinates, material) at a hit. */
#ifndef LANRAY_TRACE_H
#define LANRAY_TRACE_H

#include "scene/world.h"

typedef enum { HIT_NONE = 0, HIT_SPHERE, HIT_PLANE, HIT_TRIANGLE, HIT_INSTANCE } HitKind;

typedef struct {
    real t, b1, b2;   /* distance; barycentrics of vertices 1 and 2 for triangles */
    HitKind kind;
    uint32_t index;   /* sphere, plane, scene triangle or instance */
    uint32_t sub;     /* triangle inside the instance's model */
} Hit;

typedef struct {
    vec3 p;           /* hit point */
    vec3 ng;          /* geometric normal, unit, facing the incoming ray */
    vec3 ns;          /* shading normal, unit, same side as ng */
    real u, v;        /* texture coordinates (when has_uv) */
    int has_uv;
    const Material *mat;
    const Texture *tex; /* the material's texture (the scene's, or a model's own), or NULL */
    const Texture *etex; /* a model's own material's emission texture (where it has texture
                          * coordinates), or NULL: trace_emission */
    vec3 colour;      /* a model's vertex colour here, the diffuse colour in place of mat->kd (when has_colour) */
    int has_colour;
    uint32_t object;  /* identifies the surface for adaptive anti-aliasing */
    real err;         /* bound on the rounding error of each coordinate of p */
    vec3 ps;          /* where shadow rays start (before trace_offset_origin): p,
                       * or on a smooth triangle the point lifted onto the surface
                       * its vertex normals describe (trace_terminator_point) */
    real ps_err;      /* the same bound for ps */
    int smooth;       /* ns comes from vertex normals */
    int inside;       /* the ray arrived from behind the surface's outward normal
                       * (a sphere's centre side, a triangle's back): it leaves a solid */
    /* a model's normal-mapped triangle (where its texture coordinates span
     * it): the map, its tilt and the triangle's tangent frame, which
     * trace_surface_bump applies to ns; nmap NULL: none */
    const Texture *nmap;
    real nscale;
    real nheight;     /* > 0: nmap is a height map, its white this far up (material.h's bump_height) */
    vec3 dpdu, dpdv;  /* how the point moves with u and with v, in the world */
    int ns_turned;    /* ns was turned round to face the viewer */
    vec3 nv;          /* the smooth normal: ns before a normal map tilts it */
    int bumped;       /* trace_surface_bump tilted ns from nv */
    Material local;   /* the hit's own material (a mapped metal's, a blend's: trace_surface_local), which mat then names */
    vec3 local_tex;   /* where local_read: the colour texture's sample that tinted a mapped metal's
                       * mirror, which the diffuse colour takes too (read once: trace_surface_texel) */
    int local_read;   /* local_tex holds it */
    const Texture *mtex; /* a model's own material's metal-roughness texture (where it has texture
                          * coordinates) not yet applied, or NULL: trace_surface_metal */
    const Texture *aotex; /* a model's own material's occlusion texture (where it has texture
                           * coordinates), or NULL: trace_occlusion */
    const Texture *btex; /* a model's own material's blending mask (material_blends) not yet
                          * applied, or NULL: trace_surface_blend */
} Surface;

/* The closest hit: the smallest t, ties decided by a fixed rule (trace.c),
 * so that every traversal order and every SIMD path finds the same one. */
/* The material of triangle `tri` of instance `instance`: the scene's
 * material overriding the model's, else the model's own, else the scene's
 * first (NULL where the scene has none). */
const Material *trace_instance_material(const World *w, uint32_t instance, uint32_t tri);
int trace_closest(const World *w, const Ray *r, Hit *hit);
/* n <= TRACE_PACKET rays at once: each gets exactly trace_closest's hit
 * (kind HIT_NONE for a miss); coherent rays (a line of pixels, the
 * sub-samples of a pixel) share the walk down the trees. */
#define TRACE_PACKET 8
void trace_closest_packet(const World *w, const Ray *rays, int n, Hit *hits);
/* The same for rays that share no walk (rays that part): each alone, as
 * trace_closest, by pairs (trace_closest_pair). */
void trace_closest_each(const World *w, const Ray *rays, int n, Hit *hits);
/* trace_closest of rays a and b, their walks interleaved where the world
 * has a tree to walk; bits 0 and 1: whether each hit. */
uint32_t trace_closest_pair(const World *w, const Ray *a, const Ray *b, Hit *ha, Hit *hb);
/* The same for rays sent on from surfaces (mirrors, glass), which may
 * part: where they would go ray by ray inside the model's walk, they go
 * ray by ray from the start. */
void trace_closest_bounced(const World *w, const Ray *rays, int n, Hit *hits);
/* The mask of the n rays that are blocked before their tmax (trace_occluded each). */
uint32_t trace_occluded_packet(const World *w, const Ray *rays, int n, const real *tmax, const WorldLight *towards);
/* Shadow rays that glass lets through (settings glass_shadows): the mask
 * of the rays blocked before their tmax by something that is no
 * dielectric, and in *glass those of the others that cross a surface that
 * may be one (World.glassy): what of a light reaches them is what a walk
 * through the dielectrics (shade.c) finds.  In a scene without
 * dielectrics, trace_occluded_packet and *glass = 0. */
uint32_t trace_shadow_packet(const World *w, const Ray *rays, int n, const real *tmax, const WorldLight *towards,
                             uint32_t *glass);
/* trace_closest among the surfaces that may be dielectrics alone (the
 * glass planes and World.glassy's primitives; all of them in a scene
 * without): the walk through glass of a shadow ray trace_shadow let pass. */
int trace_closest_glass(const World *w, const Ray *r, Hit *hit);
/* trace_shadow_packet for one ray. */
int trace_shadow(const World *w, const Ray *r, real tmax, const WorldLight *towards, int *glass);
/* The point at barycentrics (b1, b2) of triangle v0 v1 v2, as trace_surface
 * computes a scene triangle's hit point, and the bound on the rounding error
 * of each of its coordinates (for trace_offset_origin). */
vec3 trace_triangle_point(vec3 v0, vec3 v1, vec3 v2, real b1, real b2, real *err);
/* Whether anything blocks r before tmax.  A shadow ray towards a light
 * (`towards`, or NULL) passes the light's own lamp (scene.h). */
int trace_occluded(const World *w, const Ray *r, real tmax, const WorldLight *towards);
/* Whether hit h is on part of light l's lamp. */
int trace_lamp_part(const World *w, const WorldLight *l, const Hit *h);
/* Whether h is on any light's lamp. */
int trace_any_lamp(const World *w, const Hit *h);
/* How far a ray that ends at h came, in the units of the absorption
 * (`absorb`) of the material there: a model's own material absorbs per
 * unit of the model (glTF's attenuation distance is the model's), so on
 * an instance scaled by s the world's t is s of them; a scene's material
 * (an instance's override too) per unit of the world. */
static inline real trace_absorb_t(const World *w, const Hit *h)
{
    if (h->kind == HIT_INSTANCE) {
        const WorldInstance *in = &w->instances[h->index];
        if (in->material < 0 && in->scale != R(1))
            return h->t / in->scale;
    }
    return h->t;
}
void trace_surface(const World *w, const Ray *r, const Hit *hit, Surface *out);
/* sf's material as one of its own to change (Surface.local, copied from
 * sf->mat unless it is that already), which sf->mat then names: where a
 * hit's blend mask, Filter Glossy or the caustics setting change it. */
static inline Material *trace_surface_local(Surface *sf)
{
    if (sf->mat != &sf->local)
        sf->local = *sf->mat;
    sf->mat = &sf->local;
    return &sf->local;
}
/* Tilts sf->ns as its normal map says (nothing without one, or a second
 * time), the map read over the footprint fp (NULL: at the point): after
 * trace_surface, once the caller knows the footprint. */
void trace_surface_bump_apply(Surface *sf, const TexFootprint *fp);
/* (each of these three asks inline whether there is anything to do: a
 * call a hit for nothing was some 15 instructions, three a bounce) */
static inline void trace_surface_bump(Surface *sf, const TexFootprint *fp)
{
    if (sf->nmap)
        trace_surface_bump_apply(sf, fp);
}
/* The radiance the surface emits: its material's `emit`, times its
 * emission texture's colour at the hit where it has one (read over the
 * footprint fp, or at one point where fp is NULL, by the view's filter). */
vec3 trace_emission(const World *w, const Surface *sf, const TexFootprint *fp);
/* What share of the ambient light reaches the surface: 1, or where its
 * material has an occlusion texture, 1 + strength x (its red there - 1),
 * the texel read as a fraction (c / 255: the data it is) over the
 * footprint fp (NULL: at the point). */
real trace_occlusion(const Surface *sf, const TexFootprint *fp);
/* A mapped metal's material at the hit (glTF's metal-roughness texture:
 * material.h), where sf->mtex says it has one not yet applied: the texel's
 * blue scales the metal share (kr = base x factor x blue, tinted by the
 * base colour texture there; kd the rest of the base; its rim kre, white,
 * factor x blue), its green the
 * roughness (and the highlight's exponent with it, as import.c matches
 * them), into sf->local, which sf->mat then names.  Read over the
 * footprint fp (NULL: at the point): after trace_surface, once the caller
 * knows the footprint, before it reads the material. */
void trace_surface_metal_apply(const World *w, Surface *sf, const TexFootprint *fp);
static inline void trace_surface_metal(const World *w, Surface *sf, const TexFootprint *fp)
{
    if (sf->mtex)
        trace_surface_metal_apply(w, sf, fp);
}
/* A blending material's see-through share at the hit (material.h's
 * mask_blend: glTF's alphaMode BLEND with an alpha texture), where
 * sf->btex says it is not yet applied: the mask's opacity a there scales
 * what the surface reflects (diffuse, highlight, mirror) and it lets
 * 1 - (1 - transmit) a through, into sf->local, which sf->mat then names
 * (after trace_surface_metal, over what it made).  The texel at the point,
 * as the cutout's test reads it. */
void trace_surface_blend_apply(Surface *sf);
static inline void trace_surface_blend(Surface *sf)
{
    if (sf->btex)
        trace_surface_blend_apply(sf);
}
/* The colour texture's sample at the hit (sf->tex set), over fp (NULL:
 * at the point): read by trace_surface_metal already where it made the
 * hit's metal with the same footprint, else now. */
static inline vec3 trace_surface_texel(const World *w, const Surface *sf, const TexFootprint *fp)
{
    return sf->local_read ? sf->local_tex : texture_sample(sf->tex, sf->u, sf->v, fp, w->view.settings.filter);
}

/* How the surface at hit h changes over a sample's footprint (dpdx,
 * dpdy: raydiff.h): its texture coordinates (*fp) and its shading normal
 * (sf->ns as it faces the ray). */
void trace_surface_change(const World *w, const Hit *h, const Surface *sf, vec3 dpdx, vec3 dpdy, TexFootprint *fp,
                          vec3 *dndx, vec3 *dndy);

/* Moves p off the surface along n (the side the new ray leaves on) by just
 * more than the rounding error of p, so that the new ray cannot hit the
 * surface it starts on, whatever the scale or position of the scene.  Like
 * Wächter & Binder ("A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6) the offset grows with the
 * magnitude of the numbers involved rather than being a fixed epsilon; its
 * size is the error bound `err` of the primitive's hit point (PBRT 3.9), and
 * each coordinate is then rounded away from the surface (nextafter) so the
 * addition cannot land back on it. */
vec3 trace_offset_origin(vec3 p, vec3 n, real err);
/* How far a ray along unit l that leaves a smooth triangle starts from
 * its hit point p towards the point lifted onto the curved surface (ps,
 * trace_terminator_point): 0 (from p) to 1 (from ps), by how nearly l
 * grazes the flat facet, as Cycles' shadow terminator geometry offset
 * takes it (cut-off 0.1 of the cosines with ng and the smooth normal).  Only a ray that
 * skims or dips below the facet needs the lift to clear its own mesh; on a
 * detailed scan whose vertex normals splay at every ridge, a lift for every
 * ray put the origins of lit points inside the next fold (a dragon's
 * direct light 14% darker than Cycles' and than its own unlifted one). */
#define TRACE_LIFT_CUTOFF R(0.1)
static inline real trace_lift_share(const Surface *sf, vec3 l)
{
    const real c = TRACE_LIFT_CUTOFF, ngl = v3_dot(sf->ng, l), nl = v3_dot(sf->nv, l);
    return real_clamp(nl < c ? R(2) - (ngl + nl) / c : R(1) - ngl / c, R(0), R(1));
}
/* The origin of a ray leaving sf on the side it was seen from, offset off
 * it (trace_offset_origin): from p lifted a share a (0..1) of the way to
 * ps. */
vec3 trace_lifted_origin(const Surface *sf, real a);
/* That origin for a ray along unit l: from p, or a smooth triangle's p
 * lifted towards ps by trace_lift_share. */
static inline vec3 trace_leave_origin(const Surface *sf, vec3 l)
{
    return trace_lifted_origin(sf, sf->smooth ? trace_lift_share(sf, l) : R(0));
}

/* The mirror direction of a ray along d off sf: about the shading
 * normal, or about the flat facet where that would send it into the
 * surface (a smooth low-poly mirror near its outline): both integrators. */
static inline vec3 trace_reflected(vec3 d, const Surface *sf)
{
    const vec3 r = v3_reflect(d, sf->ns);
    return v3_dot(r, sf->ng) > R(0) ? r : v3_reflect(d, sf->ng);
}

/* The shadow terminator (Hanika, "Hacking the Shadow Terminator", Ray
 * Tracing Gems II ch. 4, 2021): a coarse mesh with smooth vertex normals is
 * shaded as a curved surface but shadows itself as the flat triangles it is,
 * so near the boundary between light and dark the triangles' own neighbours
 * cut triangle-shaped dark patches into what the normals light.  A shadow
 * ray starts instead from p moved onto the curved surface the normals
 * describe: p is projected onto the tangent plane of each vertex that it
 * lies below (p - min(0, (p - v_i).n_i) n_i), and the three results are
 * blended with the barycentrics (b0, b1, b2).  n must face the side the
 * shadow rays leave on.  *err grows by the rounding of the lift. */
vec3 trace_terminator_point(vec3 p, const vec3 v[3], const vec3 n[3], real b1, real b2, real *err);

#endif
