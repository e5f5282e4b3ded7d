/* model_cut.c - a model with cutouts on a SIMD path: its solid triangles
 * in the wide tree, its cut ones in a binary tree of their own.
 *
 * The wide tree is the model's own (the same boxes, the same leaves and
 * triangle indices), built from a copy of the triangles in which each cut
 * one is a point (its three corners the first): a point's determinant is
 * 0, so no lane of any kernel ever hits it.  The cut triangles, copied
 * bit for bit, go into a small binary tree (ModelCut), walked by the
 * scalar test with each hit tested against its mask (model_trace.c).
 * The closest hit is the least (t, triangle index) of the two walks: the
 * same hit as the binary walk of the whole model gives on the scalar
 * path, so every path keeps giving the same picture, and only the cut
 * triangles pay the binary walk (a building's few leaves and chains, not
 * the building).  A model more than half cut keeps the binary walk of the
 * whole, as on the scalar path: the wide walk would mostly meet points. */
#include <stdlib.h>
#include <string.h>

#include "model/model.h"

void model_cut_free(ModelCut *c)
{
    if (!c)
        return;
    bvh_destroy(&c->bvh);
    free(c->tris);
    free(c->ids);
    free(c);
}

/* Whether triangle i's material cuts. */
static int cut_at(const Model *m, uint32_t i) { return material_cuts(&m->materials[m->mat_ids[i]]); }

/* The cut triangles' tree, and their copies and indices in its leaf order. */
static int cut_tree(Model *m, uint32_t n, Err *err)
{
    ModelCut *c = calloc(1, sizeof *c);
    uint32_t *which = malloc((size_t)n * sizeof *which);
    Aabb *boxes = malloc((size_t)n * sizeof *boxes);
    if (c)
        c->tris = malloc((size_t)n * sizeof *c->tris), c->ids = malloc((size_t)n * sizeof *c->ids);
    int rc = c && which && boxes && c->tris && c->ids ? 0 : err_set(err, "model: out of memory for its cutouts");
    for (uint32_t i = 0, j = 0; rc == 0 && i < m->tri_count; i++)
        if (cut_at(m, i))
            which[j] = i, boxes[j++] = tri_box(&m->tris[i]);
    const BvhOptions opt = bvh_options_default(BVH_SAH);
    if (rc == 0)
        rc = bvh_build(&c->bvh, boxes, n, &opt, err);
    for (uint32_t j = 0; rc == 0 && j < n; j++) {
        c->ids[j] = which[c->bvh.prims[j]];
        c->tris[j] = m->tris[c->ids[j]];
    }
    if (rc == 0) {
        free(c->bvh.prims);
        c->bvh.prims = NULL;
        m->cut = c;
    } else {
        model_cut_free(c);
    }
    free(which);
    free(boxes);
    return rc;
}

int model_cut_build(Model *m, int path, Err *err)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < m->tri_count; i++)
        n += (uint32_t)cut_at(m, i);
    if (n == 0) /* materials that cut, on no triangle */
        return wide_build(&m->wide, &m->bvh, m->tris, path, err);
    if (n > m->tri_count / 2) /* mostly cut: the whole binary tree, no wide walk of points */
        return 0;
    if (cut_tree(m, n, err))
        return -1;
    Tri *solid = malloc((size_t)m->tri_count * sizeof *solid);
    int rc = solid ? 0 : err_set(err, "model: out of memory for its cutouts");
    if (rc == 0) {
        memcpy(solid, m->tris, (size_t)m->tri_count * sizeof *solid);
        for (uint32_t i = 0; i < m->tri_count; i++)
            if (cut_at(m, i))
                for (int k = 1; k < 3; k++)
                    memcpy(solid[i].v[k], solid[i].v[0], sizeof solid[i].v[0]);
        rc = wide_build(&m->wide, &m->bvh, solid, path, err);
    }
    free(solid);
    if (rc) { /* the cut tree is walked after the wide one: not one without the other */
        model_cut_free(m->cut);
        m->cut = NULL;
    }
    return rc;
}
