/* bvh_sbt.c - the space balanced tree: top-down, split at the spatial median.
 *
 * Each node is cut in the middle of the box its primitives' centres occupy,
 * along its longest axis (or x, y, z in turn).  Cheap and predictable; on
 * uneven geometry it makes deeper, less efficient trees than the SAH, which
 * is the comparison users run it for. */
#include <stdlib.h>

#include "bvh_build.h"

/* Moves primitives with centre[axis] < split to the front; returns their count. */
static uint32_t partition(Builder *b, uint32_t first, uint32_t count, int axis, real split)
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

typedef struct {
    int32_t node;
    uint32_t depth;
} Task;

int bvh_build_sbt(Builder *b, Err *err)
{
    Task *tasks = malloc(b->n * sizeof *tasks + sizeof *tasks);
    if (!tasks)
        return err_set(err, "bvh: out of memory");
    Aabb box, cbox;
    builder_bounds(b, 0, b->n, &box, &cbox);
    BuildNode root = {box, -1, -1, 0, b->n};
    int32_t r = builder_add(b, root);
    uint32_t nt = 0;
    tasks[nt++] = (Task){r, 0};
    while (nt && r >= 0) {
        Task t = tasks[--nt];
        BuildNode node = b->nodes[t.node];
        if (node.count <= b->opt->max_leaf)
            continue;
        builder_bounds(b, node.first, node.count, &box, &cbox);
        vec3 ext = aabb_extent(cbox);
        int axis = b->opt->sbt_alternate ? (int)(t.depth % 3) : v3_max_axis(ext);
        uint32_t nl = 0;
        for (int tries = 0; tries < 3; tries++, axis = (axis + 1) % 3) {
            if (ext.e[axis] <= R(0))
                continue;
            real split = cbox.min.e[axis] + ext.e[axis] * R(0.5);
            nl = partition(b, node.first, node.count, axis, split);
            if (nl > 0 && nl < node.count)
                break;
        }
        if (nl == 0 || nl == node.count) /* all centres coincide: split by count */
            nl = node.count / 2;
        Aabb lb, rb;
        builder_bounds(b, node.first, nl, &lb, NULL);
        builder_bounds(b, node.first + nl, node.count - nl, &rb, NULL);
        int32_t l = builder_add(b, (BuildNode){lb, -1, -1, node.first, nl});
        r = l < 0 ? -1 : builder_add(b, (BuildNode){rb, -1, -1, node.first + nl, node.count - nl});
        if (r < 0)
            break;
        b->nodes[t.node].left = l;
        b->nodes[t.node].right = r;
        tasks[nt++] = (Task){l, t.depth + 1};
        tasks[nt++] = (Task){r, t.depth + 1};
    }
    free(tasks);
    if (r < 0)
        return err_set(err, "bvh: out of memory");
    b->root = 0;
    return 0;
}
