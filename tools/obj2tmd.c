/* obj2tmd - converts a Wavefront OBJ model into a .tmd file (a serialised BVH).
 *
 *   obj2tmd [--bvh sbt|mst|sah] [--leaf N] [--axis longest|alternate] [--smooth] in.obj out.tmd
 *
 * Prints a summary; on any error prints it with file and line, exits 1 and
 * leaves no output file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "obj.h"
#include "timer.h"
#include "tmd.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: obj2tmd [--bvh sbt|mst|sah] [--leaf N] [--axis longest|alternate] [--smooth] in.obj out.tmd\n"
               "  --bvh     BVH builder: sbt (spatial median), mst (bottom-up, smallest merged box), sah (default)\n"
               "  --leaf    most triangles per leaf, 1..255 (default 4)\n"
               "  --axis    SBT split axis: longest (default) or alternate (x, y, z in turn)\n"
               "  --smooth  compute smooth vertex normals where the OBJ has none\n");
}

int main(int argc, char **argv)
{
    BvhOptions bo = bvh_options_default(BVH_SAH);
    ObjOptions oo = {0};
    const char *in = NULL, *out = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--bvh") == 0 && i + 1 < argc) {
            if (bvh_kind_parse(argv[++i], &bo.kind)) {
                fprintf(stderr, "obj2tmd: unknown BVH kind '%s' (sbt, mst or sah)\n", argv[i]);
                return 2;
            }
        } else if (strcmp(a, "--leaf") == 0 && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 255) {
                fprintf(stderr, "obj2tmd: --leaf wants 1..255, got '%s'\n", argv[i]);
                return 2;
            }
            bo.max_leaf = (uint32_t)v;
        } else if (strcmp(a, "--axis") == 0 && i + 1 < argc) {
            i++;
            if (strcmp(argv[i], "alternate") == 0)
                bo.sbt_alternate = 1;
            else if (strcmp(argv[i], "longest") != 0) {
                fprintf(stderr, "obj2tmd: --axis wants longest or alternate, got '%s'\n", argv[i]);
                return 2;
            }
        } else if (strcmp(a, "--smooth") == 0) {
            oo.smooth = 1;
        } else if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "obj2tmd: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        } else if (!in) {
            in = a;
        } else if (!out) {
            out = a;
        } else {
            usage(stderr);
            return 2;
        }
    }
    if (!in || !out) {
        usage(stderr);
        return 2;
    }
    Err err = {{0}};
    Mesh mesh;
    ObjStats st;
    double t0 = timer_now();
    if (obj_read(in, &oo, &mesh, &st, &err)) {
        fprintf(stderr, "obj2tmd: %s\n", err.msg);
        return 1;
    }
    double t1 = timer_now();
    if (mesh.tri_count == 0) {
        fprintf(stderr, "obj2tmd: %s: no usable triangles (%lu faces, %lu degenerate)\n", in, st.faces, st.degenerate);
        mesh_free(&mesh);
        return 1;
    }
    Model *model;
    int rc = model_from_mesh(&model, &mesh, &bo, &err);
    double t2 = timer_now();
    mesh_free(&mesh);
    if (rc) {
        fprintf(stderr, "obj2tmd: %s: %s\n", in, err.msg);
        return 1;
    }
    if (tmd_write(out, model, &err)) {
        fprintf(stderr, "obj2tmd: %s\n", err.msg);
        model_destroy(model);
        return 1;
    }
    printf("%s -> %s\n", in, out);
    printf("  vertices %lu, faces %lu, triangles %u, degenerate dropped %lu\n", st.vertices, st.faces,
           model->tri_count, st.degenerate);
    printf("  attributes: %s%s%s\n", model->normals ? "normals " : "", model->uvs ? "uvs " : "",
           model->mat_ids ? "materials" : (model->normals || model->uvs ? "" : "positions only"));
    printf("  bvh %s: %u nodes, depth %u, SAH cost %.2f\n", bvh_kind_name(bo.kind), model->bvh.node_count,
           model->bvh.depth, bvh_sah_cost(&model->bvh));
    printf("  parse %.3f s, build %.3f s\n", t1 - t0, t2 - t1);
    model_destroy(model);
    return 0;
}
