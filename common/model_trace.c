/* model_trace.c - rays against a model's triangles: the renderer's hottest
 * loop (the traversal itself is in bvh_traverse.h). */
#include "bvh_traverse.h"
#include "model.h"

typedef struct {
    const Model *m;
    ModelHit *hit;
    uint32_t best; /* triangle of the hit so far; 0 at first, so a hit at exactly tmax is not taken */
} ClosestCtx;

static inline __attribute__((always_inline)) int leaf_closest(void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    const Tri *tri = &c->m->tris[first];
    int found = 0;
    for (uint32_t i = 0; i < count; i++) {
        real t, b1, b2;
        /* ties go to the smaller index, so the wide kernels, visiting in
         * another order, find the same triangle */
        if (tri_solve(r, &tri[i], &t, &b1, &b2) && (t < *tmax || (t == *tmax && first + i < c->best))) {
            *tmax = t;
            *c->hit = (ModelHit){t, b1, b2, first + i};
            c->best = first + i;
            found = 1;
        }
    }
    return found;
}

static inline __attribute__((always_inline)) int leaf_any(const void *vctx, uint32_t first, uint32_t count,
                                                          const Ray *r, real tmax)
{
    const Tri *tri = &((const Model *)vctx)->tris[first];
    for (uint32_t i = 0; i < count; i++) {
        real t, b1, b2;
        if (tri_intersect(r, &tri[i], tmax, &t, &b1, &b2))
            return 1;
    }
    return 0;
}

int model_intersect(const Model *m, const Ray *r, real tmax, ModelHit *hit)
{
    if (m->wide) {
        WideHit wh;
        if (!m->wide->closest(m->wide, r, tmax, &wh))
            return 0;
        *hit = (ModelHit){wh.t, wh.b1, wh.b2, wh.tri};
        return 1;
    }
    ClosestCtx c = {m, hit, 0};
    return bvh_closest(&m->bvh, r, &tmax, leaf_closest, &c);
}

int model_occluded(const Model *m, const Ray *r, real tmax)
{
    if (m->wide)
        return m->wide->any(m->wide, r, tmax);
    return bvh_any(&m->bvh, r, tmax, leaf_any, m);
}
