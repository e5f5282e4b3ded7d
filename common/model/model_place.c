/* model_place.c - a small model moved into world space, for tracing.
 *
 * An instance's rays are moved into its model's space, ray by ray: for a
 * model of a few triangles the move costs more than the walk it saves (a
 * cube instanced twice in models/example.scene: a ray's move, 150
 * instructions, and the model's packet walk, 330 a ray, for 12
 * triangles).  A placed copy holds the triangles where the instance puts
 * them, in the model's order, under the model's own tree with its boxes
 * fitted again, so that a hit's triangle and barycentrics name what they
 * name in the model (shading reads the model) and the tie rule of equal
 * distances picks the same triangle. */
#include "model/model.h"

#include <string.h>

/* The boxes of node i's subtree fitted to the placed triangles. */
static Aabb refit(BvhNode *nodes, const Tri *tris, uint32_t i)
{
    BvhNode *n = &nodes[i];
    Aabb b = aabb_empty();
    if (n->count) {
        for (uint32_t k = n->first; k < n->first + n->count; k++)
            for (int v = 0; v < 3; v++)
                aabb_grow(&b, tri_vertex(&tris[k], v));
    } else {
        const Aabb l = refit(nodes, tris, n->first), r = refit(nodes, tris, n->first + 1);
        b.min = v3_min(l.min, r.min);
        b.max = v3_max(l.max, r.max);
    }
    for (int a = 0; a < 3; a++)
        n->bmin[a] = b.min.e[a], n->bmax[a] = b.max.e[a];
    return b;
}

int model_place(Model **out, const Model *m, const mat3 *rot, vec3 translate, real scale, Err *err)
{
    *out = NULL;
    Model *p = model_alloc(m->tri_count, m->bvh.node_count, 0, 0);
    if (!p)
        return err_set(err, "model: out of memory placing %u triangles", m->tri_count);
    for (uint32_t i = 0; i < m->tri_count; i++)
        for (int v = 0; v < 3; v++) {
            /* as the instance's world box is made (world.c): R (s x) + T */
            const vec3 x = v3_add(v3_scale(m3_apply(rot, tri_vertex(&m->tris[i], v)), scale), translate);
            for (int a = 0; a < 3; a++)
                p->tris[i].v[v][a] = x.e[a];
        }
    if (m->bvh.node_count) {
        memcpy(p->bvh.nodes, m->bvh.nodes, m->bvh.node_count * sizeof *p->bvh.nodes);
        p->bounds = refit(p->bvh.nodes, p->tris, 0);
    }
    p->bvh.depth = m->bvh.depth;
    p->bvh.kind = m->bvh.kind;
    if (model_prepare_simd(p, err)) {
        model_destroy(p);
        return -1;
    }
    *out = p;
    return 0;
}
