/* model.c - building models from meshes and reordering them into leaf order. */
#include "model/model.h"

#include <stdlib.h>

#include "base/bigmem.h"
#include <string.h>

#include "base/simd.h"

Model *model_alloc(uint32_t tri_count, uint32_t node_count, uint32_t material_count, unsigned attrs)
{
    const int normals = attrs & MESH_NORMALS, uvs = attrs & MESH_UVS, mat_ids = attrs & MESH_MATERIALS,
              colours = attrs & MESH_COLOURS;
    Model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    size_t tc = tri_count ? tri_count : 1;
    m->tri_count = tri_count;
    m->tris = bigmem_alloc(tc * sizeof *m->tris);
    m->normals = normals ? malloc(tc * 3 * sizeof *m->normals) : NULL;
    m->uvs = uvs ? malloc(tc * 6 * sizeof *m->uvs) : NULL;
    m->mat_ids = mat_ids ? malloc(tc * sizeof *m->mat_ids) : NULL;
    m->colours = colours ? malloc(tc * 3 * sizeof *m->colours) : NULL;
    m->material_count = material_count;
    m->materials = material_count ? malloc(material_count * sizeof *m->materials) : NULL;
    m->bvh.node_count = node_count;
    m->bvh.prim_count = tri_count;
    if (node_count && bvh_alloc_nodes(&m->bvh, node_count))
        m->bvh.nodes = NULL;
    if (!m->tris || (normals && !m->normals) || (uvs && !m->uvs) || (mat_ids && !m->mat_ids) ||
        (colours && !m->colours) || (material_count && !m->materials) || (node_count && !m->bvh.nodes)) {
        model_destroy(m);
        return NULL;
    }
    return m;
}

void model_destroy(Model *m)
{
    if (!m)
        return;
    bvh_destroy(&m->bvh);
    wide_destroy(m->wide);
    model_cut_free(m->cut);
    free(m->tris);
    free(m->normals);
    free(m->uvs);
    free(m->mat_ids);
    free(m->colours);
    free(m->tangents);
    free(m->materials);
    for (uint32_t i = 0; i < m->texture_count; i++)
        texture_destroy(m->textures[i]);
    free(m->textures);
    free(m);
}

/* Where a build takes the triangles from, in their first order: a mesh
 * (model_from_mesh) or the model's own arrays (model_rebuild).  The
 * passes read it where it is, so that a model made from a mesh never
 * holds the triangles in the mesh's order: that copy was 36 bytes a
 * triangle of fresh memory, a tenth of a build's page faults. */
typedef struct {
    const vec3 *pos;   /* a mesh's corners, 3 a triangle, or NULL */
    const Tri *tris;   /* else the model's triangles */
    const vec3 *nrm;   /* 3 a triangle, or NULL */
    const real *uvs;   /* 6 a triangle, or NULL */
    const uint32_t *mids;
    const vec3 *cols;  /* 3 a triangle, or NULL */
} Source;

static Tri source_tri(const Source *s, uint64_t i)
{
    if (!s->pos)
        return s->tris[i];
    Tri t;
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++)
            t.v[k][a] = s->pos[3 * i + (uint64_t)k].e[a];
    return t;
}

/* The passes over every triangle around the tree, on the build's pool
 * (which the tree's passes share: bvh_build_on). */
typedef struct {
    const Source *src;
    Aabb *boxes;
    Aabb bounds[BVH_POOL_MAX];
    const uint32_t *order; /* leaf order */
    Tri *tris;
    vec3 *nrm, *cols;
    real *uvs;
    uint32_t *mids;
} Pass;

static void pass_boxes(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    Pass *w = ctx;
    Aabb bounds = w->bounds[thread];
    for (uint64_t i = lo; i < hi; i++) {
        const Tri t = source_tri(w->src, i);
        w->boxes[i] = tri_box(&t);
        bounds = aabb_union(bounds, w->boxes[i]);
    }
    w->bounds[thread] = bounds;
}

/* How far ahead the reordering asks for a source triangle: the gather
 * from the file's order waited on a cache miss per triangle, a tenth of
 * the bunny's two-thread build. */
#define REORDER_AHEAD 16

static void pass_reorder(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    Pass *w = ctx;
    const Source *s = w->src;
    for (uint64_t i = lo; i < hi; i++) {
        if (i + REORDER_AHEAD < hi) {
            const uint32_t q = w->order[i + REORDER_AHEAD];
            const char *at = s->pos ? (const char *)&s->pos[3 * (uint64_t)q] : (const char *)&s->tris[q];
            __builtin_prefetch(at);
            __builtin_prefetch(at + sizeof(Tri) - 1);
        }
        uint32_t p = w->order[i];
        w->tris[i] = source_tri(s, p);
        if (w->nrm)
            memcpy(&w->nrm[3 * i], &s->nrm[3 * (uint64_t)p], 3 * sizeof *w->nrm);
        if (w->uvs)
            memcpy(&w->uvs[6 * i], &s->uvs[6 * (uint64_t)p], 6 * sizeof *w->uvs);
        if (w->mids)
            w->mids[i] = s->mids[p];
        if (w->cols)
            memcpy(&w->cols[3 * i], &s->cols[3 * (uint64_t)p], 3 * sizeof *w->cols);
    }
}

/* Builds m's tree over the n triangles of src and puts them, with their
 * attributes, into m in leaf order; the model's old arrays are freed
 * (src may be them). */
static int model_build_bvh(Model *m, const Source *src, const BvhOptions *opt, Pool *pool, Err *err)
{
    uint32_t n = m->tri_count;
    Pass w;
    memset(&w, 0, sizeof w);
    w.src = src;
    w.boxes = bigmem_alloc((n ? n : 1) * sizeof *w.boxes);
    if (!w.boxes)
        return err_set(err, "model: out of memory");
    for (int k = 0; k < BVH_POOL_MAX; k++)
        w.bounds[k] = aabb_empty();
    pool_for(pool, n, BVH_POOL_GRAIN, pass_boxes, &w);
    m->bounds = aabb_empty();
    for (int k = 0; k < BVH_POOL_MAX; k++) /* minima and maxima: any order gives the same */
        m->bounds = aabb_union(m->bounds, w.bounds[k]);
    Bvh bvh;
    int rc = bvh_build_on(&bvh, w.boxes, n, opt, pool, err);
    free(w.boxes);
    if (rc)
        return rc;
    size_t tc = n ? n : 1;
    Tri *tris = bigmem_alloc(tc * sizeof *tris);
    vec3 *nrm = src->nrm ? malloc(tc * 3 * sizeof *nrm) : NULL;
    real *uvs = src->uvs ? malloc(tc * 6 * sizeof *uvs) : NULL;
    uint32_t *mids = src->mids ? malloc(tc * sizeof *mids) : NULL;
    vec3 *cols = src->cols ? malloc(tc * 3 * sizeof *cols) : NULL;
    if (!tris || (src->nrm && !nrm) || (src->uvs && !uvs) || (src->mids && !mids) || (src->cols && !cols)) {
        free(tris);
        free(nrm);
        free(uvs);
        free(mids);
        free(cols);
        bvh_destroy(&bvh);
        return err_set(err, "model: out of memory");
    }
    w.order = bvh.prims, w.tris = tris, w.nrm = nrm, w.uvs = uvs, w.mids = mids, w.cols = cols;
    pool_for(pool, n, BVH_POOL_GRAIN, pass_reorder, &w);
    free(m->tris);
    free(m->normals);
    free(m->uvs);
    free(m->mat_ids);
    free(m->colours);
    m->tris = tris;
    m->normals = nrm;
    m->uvs = uvs;
    m->mat_ids = mids;
    m->colours = cols;
    free(m->tangents); /* in the old order: model_prepare_simd makes them again */
    m->tangents = NULL;
    free(bvh.prims);
    bvh.prims = NULL;
    bvh_destroy(&m->bvh);
    m->bvh = bvh;
    return 0;
}

int model_from_mesh(Model **out, const Mesh *mesh, const BvhOptions *opt, Err *err)
{
    *out = NULL;
    uint32_t n = mesh->tri_count;
    for (uint32_t i = 0; mesh->mat && i < n; i++)
        if (mesh->mat[i] >= mesh->material_count)
            return err_set(err, "model: triangle %u uses material %u of %u", i, mesh->mat[i], mesh->material_count);
    /* no triangles yet: model_build_bvh puts them in, in leaf order */
    Model *m = model_alloc(0, 0, mesh->material_count, 0);
    if (!m)
        return err_set(err, "model: out of memory for %u triangles", n);
    m->tri_count = n;
    if (mesh->material_count)
        memcpy(m->materials, mesh->materials, mesh->material_count * sizeof *m->materials);
    if (mesh->texture_count) {
        m->textures = calloc(mesh->texture_count, sizeof *m->textures);
        for (uint32_t i = 0; m->textures && i < mesh->texture_count; i++, m->texture_count++)
            if (!(m->textures[i] = texture_copy(mesh->textures[i])))
                break;
        if (m->texture_count != mesh->texture_count) {
            model_destroy(m);
            return err_set(err, "model: out of memory for textures");
        }
    }
    const Source src = {mesh->pos, NULL, mesh->nrm, mesh->uv, mesh->mat, mesh->col};
    Pool *pool = bvh_pool_create(n, opt);
    int rc = model_build_bvh(m, &src, opt, pool, err);
    pool_destroy(pool);
    if (rc) {
        model_destroy(m);
        return -1;
    }
    *out = m;
    return 0;
}

int model_rebuild(Model *m, const BvhOptions *opt, Err *err)
{
    wide_destroy(m->wide);
    m->wide = NULL;
    const Source src = {NULL, m->tris, m->normals, m->uvs, m->mat_ids, m->colours};
    Pool *pool = bvh_pool_create(m->tri_count, opt);
    int rc = model_build_bvh(m, &src, opt, pool, err);
    pool_destroy(pool);
    return rc;
}

ModelBytes model_bytes(const Model *m)
{
    ModelBytes b;
    b.tris = (size_t)m->tri_count * sizeof *m->tris;
    b.tree = (size_t)m->bvh.node_count * sizeof(BvhNode) + (m->bvh.prims ? (size_t)m->bvh.prim_count * 4 : 0);
    b.wide = wide_bytes(m->wide);
    b.attributes = (size_t)m->tri_count * ((m->normals ? 3 * sizeof(vec3) : 0) + (m->uvs ? 6 * sizeof(real) : 0) +
                                           (m->mat_ids ? sizeof(uint32_t) : 0) +
                                           (m->colours ? 3 * sizeof(vec3) : 0) +
                                           (m->tangents ? 3 * sizeof(vec3) : 0)) +
                   (size_t)m->material_count * sizeof(Material);
    return b;
}

/* Whether any material of the model cuts holes where it can: triangles
 * with texture coordinates, materials and textures. */
static int model_cuts(const Model *m)
{
    if (!m->uvs || !m->mat_ids || !m->textures)
        return 0;
    for (uint32_t i = 0; i < m->material_count; i++)
        if (material_cuts(&m->materials[i]))
            return 1;
    return 0;
}

int model_prepare_simd(Model *m, Err *err)
{
    m->cutout = model_cuts(m);
    for (uint32_t i = 0; m->uvs && m->textures && i < m->material_count; i++) {
        const Material *mt = &m->materials[i];
        if ((material_bumps(mt) && texture_make_data_levels(m->textures[mt->normal_map])) ||
            (material_metal_mapped(mt) && texture_make_data_levels(m->textures[mt->metal_map])) ||
            (material_occludes(mt) && texture_make_data_levels(m->textures[mt->ao_map])))
            return err_set(err, "out of memory for a data texture's levels");
    }
    if (model_tangents_build(m, err))
        return -1;
    SimdPath p = simd_path();
    if (m->wide && m->wide_path == (int)p)
        return 0;
    wide_destroy(m->wide);
    m->wide = NULL;
    model_cut_free(m->cut);
    m->cut = NULL;
    m->wide_path = (int)p;
    if (p == SIMD_SCALAR)
        return 0;
    if (m->cutout)
        return model_cut_build(m, (int)p, err);
    return wide_build(&m->wide, &m->bvh, m->tris, (int)p, err);
}
