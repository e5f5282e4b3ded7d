/* model_trace.c - rays against a model's triangles: the renderer's hottest
 * loop (the traversal itself is in bvh_traverse.h). */
#include "bvh/bvh_traverse.h"
#include "model/model.h"

typedef struct {
    const Model *m;
    ModelHit *hit;
    uint32_t best; /* triangle of the hit so far; at first 0 (a hit at exactly tmax is not taken) or UINT32_MAX */
} ClosestCtx;

/* The closest hit among triangles tris[first .. first + count), triangle
 * i named ids[i] (the model's index; i itself without ids); with `cut`, a
 * hit in a hole of its material's mask is none (model_hole), so camera
 * rays see what is behind and shadow rays pass.  Ties go to the smaller
 * index, so the wide kernels, visiting in another order, find the same
 * triangle.  Inlined with constant ids and cut: a model without cutouts
 * pays nothing for them in its leaves. */
static inline __attribute__((always_inline)) int closest_in(ClosestCtx *c, const Tri *tris, const uint32_t *ids,
                                                            int cut, uint32_t first, uint32_t count, const Ray *r,
                                                            real *tmax)
{
    int found = 0;
    for (uint32_t i = first; i < first + count; i++) {
        real t, b1, b2;
        const uint32_t id = ids ? ids[i] : i;
        if (tri_solve(r, &tris[i], &t, &b1, &b2) && (t < *tmax || (t == *tmax && id < c->best)) &&
            !(cut && model_hole(c->m, id, b1, b2))) {
            *tmax = t;
            *c->hit = (ModelHit){t, b1, b2, id};
            c->best = id;
            found = 1;
        }
    }
    return found;
}

/* Whether any of those triangles blocks the ray before tmax (closest_in's
 * names and holes). */
static inline __attribute__((always_inline)) int any_in(const Model *m, const Tri *tris, const uint32_t *ids, int cut,
                                                        uint32_t first, uint32_t count, const Ray *r, real tmax)
{
    for (uint32_t i = first; i < first + count; i++) {
        real t, b1, b2;
        if (tri_intersect(r, &tris[i], tmax, &t, &b1, &b2) && !(cut && model_hole(m, ids ? ids[i] : i, b1, b2)))
            return 1;
    }
    return 0;
}

/* The leaves of the three walks: a model's binary tree, the same with
 * cutouts (the scalar path), and a model's cut triangles apart
 * (model_cut.c: copies of the model's triangles, named by its indices). */
static inline __attribute__((always_inline)) int leaf_closest(void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    return closest_in(c, c->m->tris, NULL, 0, first, count, r, tmax);
}

static inline __attribute__((always_inline)) int leaf_any(const void *vctx, uint32_t first, uint32_t count,
                                                          const Ray *r, real tmax)
{
    return any_in(vctx, ((const Model *)vctx)->tris, NULL, 0, first, count, r, tmax);
}

static inline __attribute__((always_inline)) int leaf_closest_cut(void *vctx, uint32_t first, uint32_t count,
                                                                  const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    return closest_in(c, c->m->tris, NULL, 1, first, count, r, tmax);
}

static inline __attribute__((always_inline)) int leaf_any_cut(const void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real tmax)
{
    return any_in(vctx, ((const Model *)vctx)->tris, NULL, 1, first, count, r, tmax);
}

static inline __attribute__((always_inline)) int leaf_apart_closest(void *vctx, uint32_t first, uint32_t count,
                                                                    const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    return closest_in(c, c->m->cut->tris, c->m->cut->ids, 1, first, count, r, tmax);
}

static inline __attribute__((always_inline)) int leaf_apart_any(const void *vctx, uint32_t first, uint32_t count,
                                                                const Ray *r, real tmax)
{
    const Model *m = vctx;
    return any_in(m, m->cut->tris, m->cut->ids, 1, first, count, r, tmax);
}

/* Without a wide tree (double builds, other CPUs): the binary walk, each
 * cut triangle's hit tested against its mask; with the cut triangles
 * apart (a SIMD path), the wide walk of the rest, then theirs. */
int model_intersect_bvh(const Model *m, const Ray *r, real tmax, int at_tmax, ModelHit *hit)
{
    ClosestCtx c = {m, hit, at_tmax ? UINT32_MAX : 0};
    if (m->cut) {
        const int found = m->wide->closest(m->wide, r, tmax, c.best, hit);
        if (found)
            tmax = hit->t, c.best = hit->tri;
        return bvh_closest(&m->cut->bvh, r, &tmax, leaf_apart_closest, &c) | found;
    }
    if (m->cutout)
        return bvh_closest(&m->bvh, r, &tmax, leaf_closest_cut, &c);
    return bvh_closest(&m->bvh, r, &tmax, leaf_closest, &c);
}

uint32_t model_cut_closest_each(const Model *m, const Ray *const *rays, int n, const real *tmax, const uint32_t *tie,
                                ModelHit *hits, uint32_t found)
{
    for (int i = 0; i < n; i++) {
        const int had = found >> i & 1;
        ClosestCtx c = {m, &hits[i], had ? hits[i].tri : tie[i]};
        real t = had ? hits[i].t : tmax[i];
        found |= (uint32_t)bvh_closest(&m->cut->bvh, rays[i], &t, leaf_apart_closest, &c) << i;
    }
    return found;
}

int model_occluded_bvh(const Model *m, const Ray *r, real tmax)
{
    if (m->cut)
        return m->wide->any(m->wide, r, tmax) || bvh_any(&m->cut->bvh, r, tmax, leaf_apart_any, m);
    return m->cutout ? bvh_any(&m->bvh, r, tmax, leaf_any_cut, m) : bvh_any(&m->bvh, r, tmax, leaf_any, m);
}

/* A packet ray by ray: no wide tree, or a packet of one. */
uint32_t model_intersect_each(const Model *m, const Ray *const *rays, int n, const real *tmax, const int *at_tmax,
                              ModelHit *hits)
{
    uint32_t found = 0;
    for (int i = 0; i < n; i++)
        found |= (uint32_t)model_intersect(m, rays[i], tmax[i], at_tmax[i], &hits[i]) << i;
    return found;
}

uint32_t model_occluded_packet(const Model *m, const Ray *const *rays, int n, const real *tmax)
{
    if (m->wide && n >= 2) {
        uint32_t hit = m->wide->any_packet(m->wide, rays, n, tmax);
        for (int i = 0; m->cut && i < n; i++) /* the cut triangles apart, ray by ray */
            if (!(hit >> i & 1))
                hit |= (uint32_t)bvh_any(&m->cut->bvh, rays[i], tmax[i], leaf_apart_any, m) << i;
        return hit;
    }
    uint32_t hit = 0;
    for (int i = 0; i < n; i++)
        hit |= (uint32_t)model_occluded(m, rays[i], tmax[i]) << i;
    return hit;
}
