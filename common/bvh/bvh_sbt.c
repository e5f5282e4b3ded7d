/* bvh_sbt.c - the space balanced tree: top-down, split at the spatial median.
 *
 * Each node is cut in the middle of the box its primitives' centres occupy,
 * along its longest axis (or x, y, z in turn).  Cheap and predictable; on
 * uneven geometry it makes deeper, less efficient trees than the SAH, which
 * is the comparison users run it for. */
#include <stdlib.h>

#include "bvh/bvh_build.h"

/* Moves primitives with centre[axis] < split to the front; returns their count. */
static uint32_t partition(const Builder *b, uint32_t first, uint32_t count, int axis, real split)
{
    uint32_t i = first, j = first + count;
    while (i < j) {
        if (b->centres[b->perm[i]].e[axis] < split)
            i++;
        else {
            uint32_t t = b->perm[i];
            b->perm[i] = b->perm[--j];
            b->perm[j] = t;
        }
    }
    return i - first;
}

static int sbt_step(const Builder *b, const BuildTask *t, BuildTask kids[2])
{
    if (t->count <= b->opt->max_leaf)
        return 0;
    vec3 ext = aabb_extent(t->cbox);
    int axis = b->opt->sbt_alternate ? (int)((t->depth - 1) % 3) : v3_max_axis(ext);
    uint32_t nl = 0;
    for (int tries = 0; tries < 3; tries++, axis = (axis + 1) % 3) {
        if (ext.e[axis] <= R(0))
            continue;
        real split = t->cbox.min.e[axis] + ext.e[axis] * R(0.5);
        nl = partition(b, t->first, t->count, axis, split);
        if (nl > 0 && nl < t->count)
            break;
    }
    if (nl == 0 || nl == t->count) /* all centres coincide: split by count */
        nl = t->count / 2;
    kids[0].first = t->first, kids[0].count = nl;
    kids[1].first = t->first + nl, kids[1].count = t->count - nl;
    for (int k = 0; k < 2; k++)
        builder_bounds(b, kids[k].first, kids[k].count, &kids[k].box, &kids[k].cbox);
    return 2;
}

int bvh_build_sbt(Builder *b, Err *err) { return builder_run(b, sbt_step, NULL, err); }
