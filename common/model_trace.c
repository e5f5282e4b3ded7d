/* model_trace.c - BVH traversal inside a model: the renderer's hottest loop.
 *
 * Flat node array, explicit stack, both children tested with the slab test
 * and the nearer one visited first; the farther is pushed with its entry
 * distance so that it is skipped on pop if a closer hit was found meanwhile. */
#include "model.h"

typedef struct {
    uint32_t node;
    real tnear;
} StackEntry;

int model_intersect(const Model *m, const Ray *r, real tmax, ModelHit *hit)
{
    const BvhNode *nodes = m->bvh.nodes;
    if (m->bvh.node_count == 0)
        return 0;
    real tn;
    if (!bvh_node_hit(&nodes[0], r, tmax, &tn))
        return 0;
    StackEntry stack[BVH_MAX_DEPTH];
    uint32_t sp = 0, idx = 0;
    int found = 0;
    for (;;) {
        const BvhNode *n = &nodes[idx];
        if (n->count) {
            const Tri *tri = &m->tris[n->first];
            for (uint32_t i = 0; i < n->count; i++) {
                real t, b1, b2;
                if (tri_intersect(r, &tri[i], tmax, &t, &b1, &b2)) {
                    tmax = t;
                    hit->t = t;
                    hit->b1 = b1;
                    hit->b2 = b2;
                    hit->tri = n->first + i;
                    found = 1;
                }
            }
        } else {
            real t0, t1;
            const uint32_t c = n->first;
            int h0 = bvh_node_hit(&nodes[c], r, tmax, &t0);
            int h1 = bvh_node_hit(&nodes[c + 1], r, tmax, &t1);
            if (h0 && h1) {
                if (t1 < t0) {
                    idx = c + 1;
                    stack[sp++] = (StackEntry){c, t0};
                } else {
                    idx = c;
                    stack[sp++] = (StackEntry){c + 1, t1};
                }
                continue;
            }
            if (h0 | h1) {
                idx = h0 ? c : c + 1;
                continue;
            }
        }
        do {
            if (sp == 0)
                return found;
            --sp;
        } while (stack[sp].tnear > tmax * BVH_FUDGE);
        idx = stack[sp].node;
    }
}

int model_occluded(const Model *m, const Ray *r, real tmax)
{
    const BvhNode *nodes = m->bvh.nodes;
    if (m->bvh.node_count == 0)
        return 0;
    real tn;
    if (!bvh_node_hit(&nodes[0], r, tmax, &tn))
        return 0;
    uint32_t stack[BVH_MAX_DEPTH];
    uint32_t sp = 0, idx = 0;
    for (;;) {
        const BvhNode *n = &nodes[idx];
        if (n->count) {
            const Tri *tri = &m->tris[n->first];
            for (uint32_t i = 0; i < n->count; i++) {
                real t, b1, b2;
                if (tri_intersect(r, &tri[i], tmax, &t, &b1, &b2))
                    return 1;
            }
        } else {
            real t0, t1;
            const uint32_t c = n->first;
            int h0 = bvh_node_hit(&nodes[c], r, tmax, &t0);
            int h1 = bvh_node_hit(&nodes[c + 1], r, tmax, &t1);
            if (h0 && h1) {
                /* order still pays for shadow rays: the nearer child more likely occludes */
                idx = t1 < t0 ? c + 1 : c;
                stack[sp++] = t1 < t0 ? c : c + 1;
                continue;
            }
            if (h0 | h1) {
                idx = h0 ? c : c + 1;
                continue;
            }
        }
        if (sp == 0)
            return 0;
        idx = stack[--sp];
    }
}
