/* model_trace.c - rays against a model's triangles: the renderer's hottest
 * loop (the traversal itself is in bvh_traverse.h). */
#include "bvh_traverse.h"
#include "model.h"

typedef struct {
    const Model *m;
    ModelHit *hit;
} ClosestCtx;

static inline __attribute__((always_inline)) int leaf_closest(void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    const Tri *tri = &c->m->tris[first];
    int found = 0;
    for (uint32_t i = 0; i < count; i++) {
        real t, b1, b2;
        if (tri_intersect(r, &tri[i], *tmax, &t, &b1, &b2)) {
            *tmax = t;
            *c->hit = (ModelHit){t, b1, b2, first + i};
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
    ClosestCtx c = {m, hit};
    return bvh_closest(&m->bvh, r, &tmax, leaf_closest, &c);
}

int model_occluded(const Model *m, const Ray *r, real tmax) { return bvh_any(&m->bvh, r, tmax, leaf_any, m); }
