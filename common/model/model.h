/* model.h - a triangle model with its own BVH: what a .tmd file holds.
 *
 * Triangles are stored in BVH leaf order, so a leaf's range indexes the
 * triangle arrays directly (bvh.prims is NULL).  Optional attributes exist
 * only when the model uses them: a flat, untextured, single-material model
 * carries nothing but positions and the tree. */
#ifndef LANRAY_MODEL_H
#define LANRAY_MODEL_H

#include "bvh/bvh.h"
#include "geom/intersect.h"
#include "model/mesh.h"
#include "bvh/wide.h"

/* A model's cut triangles on a SIMD path (model_cut.c): their own binary
 * tree, copies of them in its leaf order, and each one's index in the
 * model. */
typedef struct {
    Bvh bvh;
    Tri *tris;
    uint32_t *ids;
} ModelCut;

typedef struct {
    Bvh bvh;
    Tri *tris;
    uint32_t tri_count;
    vec3 *normals;      /* 3 per triangle, or NULL (flat shading) */
    real *uvs;          /* 6 per triangle, or NULL */
    uint32_t *mat_ids;  /* 1 per triangle, or NULL (one material for all) */
    vec3 *colours;      /* 3 per triangle: vertex colours, the diffuse colour
                         * where the model's material applies; or NULL */
    vec3 *tangents;     /* 3 per triangle: each corner's unit tangent, smooth across
                         * the triangles of a vertex, for normal maps (zero where
                         * none); made by model_tangents_build, or NULL */
    Material *materials;
    uint32_t material_count;
    Texture **textures;  /* the materials' textures (MTL map_Kd), or NULL */
    uint32_t texture_count;
    Aabb bounds;
    Wide *wide;         /* the tree collapsed for the SIMD path, or NULL: binary traversal */
    int wide_path;      /* the SimdPath it was built for */
    int cutout;         /* some material cuts holes (material.h): set by model_prepare_simd;
                         * each hit on a cut triangle is tested against its mask (model_hole) */
    ModelCut *cut;      /* on a SIMD path, the cut triangles apart (the wide tree holds the
                         * rest), or NULL: the scalar path walks the whole binary tree */
} Model;

/* A hit in a model: t, barycentrics b1 and b2, triangle.  The wide
 * kernels' own hit, so that their packets write the caller's hits. */
typedef WideHit ModelHit;

/* Builds a model from a mesh (the mesh is not modified; its textures are copied). */
int model_from_mesh(Model **out, const Mesh *mesh, const BvhOptions *opt, Err *err);
/* Replaces the BVH with one of another kind, keeping the triangles. */
int model_rebuild(Model *m, const BvhOptions *opt, Err *err);
void model_destroy(Model *m);
/* Allocates a model with room for the given counts and attributes (MESH_*
 * flags; used by the .tmd reader). */
Model *model_alloc(uint32_t tri_count, uint32_t node_count, uint32_t material_count, unsigned attrs);

/* What a loaded model holds, in bytes (make bench compares it with Embree's). */
typedef struct {
    size_t tris, tree, wide, attributes;
} ModelBytes;
ModelBytes model_bytes(const Model *m);

/* A copy of m for tracing only, its triangles where an instance puts them
 * (R (s x) + T), in m's order under m's tree refitted, its wide tree made
 * for the SIMD path in use: no attributes, materials or textures (a hit's
 * triangle names m's).  For small models (scene/world.c). */
int model_place(Model **out, const Model *m, const mat3 *rot, vec3 translate, real scale, Err *err);

/* Builds (or drops) the wide tree for the SIMD path in use, finds
 * whether the model cuts holes (then its cut triangles go apart:
 * model_cut_build), and gives its data textures (normal maps,
 * metal-roughness and occlusion textures) their levels
 * (texture_make_data_levels); called by world_build, before any thread
 * traces. */
int model_prepare_simd(Model *m, Err *err);
/* Triangle tri's dp/du and dp/dv (how its points move with its texture
 * coordinates, as pbrt's triangles without tangents take them), and the
 * side its texture lies on: 1 or 2 by the sign of its coordinates'
 * determinant, 0 where they span no area (nothing written).  The model
 * has texture coordinates. */
int model_tri_frame(const Model *m, uint32_t tri, vec3 *dpdu, vec3 *dpdv);
/* The tangents of a model whose materials read a normal map, once
 * (model_tangents.c); nothing for other models. */
int model_tangents_build(Model *m, Err *err);
/* m's wide tree for `path` without its cut triangles, and those in
 * m->cut (model_cut.c). */
int model_cut_build(Model *m, int path, Err *err);
void model_cut_free(ModelCut *c);

/* The texture coordinates of triangle `tri` at barycentrics (b1, b2), as
 * shading interpolates them (the model has them). */
static inline void model_uv(const Model *m, uint32_t tri, real b1, real b2, real *u, real *v)
{
    const real *uv = &m->uvs[6 * tri];
    *u = (R(1) - b1 - b2) * uv[0] + b1 * uv[2] + b2 * uv[4];
    *v = (R(1) - b1 - b2) * uv[1] + b1 * uv[3] + b2 * uv[5];
}

/* Whether a hit on triangle `tri` at barycentrics (b1, b2) falls in a hole
 * of its material's cutout: the mask's opacity at the hit's texture
 * coordinates (interpolated as shading interpolates them) under the
 * cutoff.  Only for a model with m->cutout. */
static inline int model_hole(const Model *m, uint32_t tri, real b1, real b2)
{
    const Material *mt = &m->materials[m->mat_ids[tri]];
    if (!material_cuts(mt))
        return 0;
    real u, v;
    model_uv(m, tri, b1, b2, &u, &v);
    return texture_coverage(m->textures[mt->mask], u, v) < mt->cutoff;
}

/* Closest hit nearer than tmax in model space: the smallest t, and of equal
 * t the smallest triangle index, whatever the path (see wide.h).  With
 * `at_tmax`, a hit at exactly tmax counts too (the scene's tie rule, trace.c). */
int model_intersect_bvh(const Model *m, const Ray *r, real tmax, int at_tmax, ModelHit *hit);
static inline int model_intersect(const Model *m, const Ray *r, real tmax, int at_tmax, ModelHit *hit)
{
    /* inline: a ray that meets one model (a scene of one) calls the SIMD
     * walk from the top level directly */
    if (m->wide && !m->cut)
        return m->wide->closest(m->wide, r, tmax, at_tmax ? UINT32_MAX : 0, hit);
    return model_intersect_bvh(m, r, tmax, at_tmax, hit);
}
/* Any hit nearer than tmax: shadow rays stop at the first occluder. */
int model_occluded_bvh(const Model *m, const Ray *r, real tmax);
static inline int model_occluded(const Model *m, const Ray *r, real tmax)
{
    return m->wide && !m->cut ? m->wide->any(m->wide, r, tmax) : model_occluded_bvh(m, r, tmax);
}
/* The same for n <= WIDE_PACKET rays at once (a packet where the SIMD path
 * has one): the mask of the rays that hit; each ray's answer is what the
 * single-ray call gives. */
uint32_t model_intersect_each(const Model *m, const Ray *const *rays, int n, const real *tmax, const int *at_tmax,
                              ModelHit *hits);
/* After a packet's wide walk of a model with its cut triangles apart
 * (`found` its hits): each ray's walk of the cut ones, the hit so far its
 * limit; the mask of the rays that hit either. */
uint32_t model_cut_closest_each(const Model *m, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                ModelHit *hits, uint32_t found);
static inline uint32_t model_intersect_packet(const Model *m, const Ray *const *rays, int n, const real *tmax,
                                              const int *at_tmax, ModelHit *hits)
{
    if (!m->wide || n < 2)
        return model_intersect_each(m, rays, n, tmax, at_tmax, hits);
    uint32_t tie[WIDE_PACKET];
    for (int i = 0; i < n; i++)
        tie[i] = at_tmax[i] ? UINT32_MAX : 0;
    const uint32_t found = m->wide->closest_packet(m->wide, rays, n, tmax, tie, hits);
    return m->cut ? model_cut_closest_each(m, rays, n, tmax, tie, hits, found) : found;
}
uint32_t model_occluded_packet(const Model *m, const Ray *const *rays, int n, const real *tmax);
/* Geometric (flat) normal of triangle i, not normalised. */
static inline vec3 model_face_normal(const Model *m, uint32_t i)
{
    const Tri *t = &m->tris[i];
    vec3 a = tri_vertex(t, 0);
    return v3_cross(v3_sub(tri_vertex(t, 1), a), v3_sub(tri_vertex(t, 2), a));
}

#endif
