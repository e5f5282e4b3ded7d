/* build_bench - lanray's BVH build timed the way tools/bench/embree_ref
 * times Embree's (make bench, tools/bench/bench-render).
 *
 *   build_bench FILE.obj sbt|mst|sah THREADS
 *
 * Reads the OBJ once, then makes the model from the mesh BUILDS + 1 times
 * (model_from_mesh: the triangles copied in the file's order, their boxes,
 * the tree, its layout and the triangles put in leaf order): Embree's
 * timed rtcCommitScene goes from its vertex and index buffers to a tree
 * it can trace, with its own copy of the triangles in its leaves.  Like
 * Embree's, the figure is the median of BUILDS builds after one untimed
 * build; the first, which like obj2tmd's starts with memory the process
 * never touched, is printed apart.  Each build starts from the file's
 * order, as each of Embree's starts from its buffers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/timer.h"
#include "model/model.h"
#include "model/obj.h"

#define BUILDS 3

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    BvhKind kind;
    char *end = NULL;
    long threads = argc == 4 ? strtol(argv[3], &end, 10) : 0;
    if (argc != 4 || bvh_kind_parse(argv[2], &kind) || !end || *end || threads < 1 || threads > 64) {
        fprintf(stderr, "usage: build_bench FILE.obj sbt|mst|sah THREADS (1..64)\n");
        return 2;
    }
    Err err = {{0}};
    ObjOptions oo = {0};
    ObjStats st;
    memset(&st, 0, sizeof st);
    Mesh mesh;
    if (obj_read(argv[1], &oo, &mesh, &st, &err)) {
        fprintf(stderr, "build_bench: %s\n", err.msg);
        return 1;
    }
    BvhOptions bo = bvh_options_default(kind);
    bo.threads = (uint32_t)threads;
    double t[BUILDS + 1];
    Model *m = NULL;
    for (int b = 0; b <= BUILDS; b++) {
        model_destroy(m);
        double t0 = timer_now();
        if (model_from_mesh(&m, &mesh, &bo, &err)) {
            fprintf(stderr, "build_bench: %s: %s\n", argv[1], err.msg);
            mesh_free(&mesh);
            return 1;
        }
        t[b] = timer_now() - t0;
    }
    qsort(t + 1, BUILDS, sizeof *t, cmp_double);
    printf("build_bench: %s threads %ld, %u triangles: first %.3f s, build %.3f s (median of %d); "
           "nodes %u, depth %u, SAH cost %.2f\n",
           bvh_kind_name(kind), threads, m->tri_count, t[0], t[1 + BUILDS / 2], BUILDS, m->bvh.node_count, m->bvh.depth,
           bvh_sah_cost(&m->bvh));
    model_destroy(m);
    mesh_free(&mesh);
    return 0;
}
