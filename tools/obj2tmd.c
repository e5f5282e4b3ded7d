/* obj2tmd - converts a Wavefront OBJ model into a .tmd file (a serialised
 * BVH).  Its options and exit statuses are in the table in main (obj2tmd
 * --help prints them; docs/tools.md has the same text).
 *
 * Prints a summary; on any error prints it with file and line, exits 1 and
 * leaves no output file.  The output is checked before the work: it must
 * not be the input (by file, not by name), and its directory must take a
 * file. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "app/cli.h"
#include "base/fileio.h"
#include "model/import.h"
#include "model/model_load.h"
#include "model/obj.h"
#include "base/opt.h"
#include "base/progress.h"
#include "base/timer.h"
#include "model/tmd.h"

static const char *const axis_names[] = {"longest", "alternate", NULL};

/* What the progress line says: the step under way (set by main, read by
 * the progress thread). */
typedef struct {
    _Atomic(const char *) step, file;
} Step;

static void show_step(void *ctx, double elapsed, char *line, size_t size)
{
    Step *s = ctx;
    char t[32];
    progress_duration(elapsed, t, sizeof t);
    snprintf(line, size, "%s %s (%s)", atomic_load(&s->step), atomic_load(&s->file), t);
}

/* Warnings go to standard error as they come (cli_warning); the summary
 * counts them all. */
static CliWarnings warnings = {"obj2tmd", "further warnings are counted in the summary", 0};

/* The same file, whatever the names: one device and inode. */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* What the command line says. */
typedef struct {
    int bvh_kind, leaf, axis, smooth, quiet, threads, strict;
    const char *in, *out;
    ModelFormat format; /* the input's, by its name (model_format, asked once: it may ask Assimp) */
} Args;

/* Parses the command line into a: OPT_GO, or the exit status. */
static int parse_args(Args *a, int argc, char **argv)
{
    *a = (Args){.bvh_kind = BVH_SAH, .leaf = (int)bvh_options_default(BVH_SAH).max_leaf};
    const Opt opts[] = {
        {.name = "--bvh", .kind = OPT_CHOICE, .dst = &a->bvh_kind, .choices = bvh_kind_names,
         .help = "builder: sbt (spatial median), mst (bottom-up, smallest merged box), sah (surface area)"},
        {.name = "--leaf", .kind = OPT_INT, .dst = &a->leaf, .arg = "N", .lo = 1, .hi = 255,
         .help = "most triangles per leaf"},
        {.name = "--axis", .kind = OPT_CHOICE, .dst = &a->axis, .choices = axis_names,
         .help = "SBT split axis: the box's longest, or x, y, z in turn"},
        {.name = "--threads", .kind = OPT_INT, .dst = &a->threads, .arg = "T", .lo = 0, .hi = 64,
         .help = "builder threads, 0 = one per core (the tree is the same for any number)", .def = "0: all cores"},
        {.name = "--smooth", .kind = OPT_FLAG, .dst = &a->smooth, .help = "smooth vertex normals where the model has none: an OBJ's faces outside any smoothing group (s; faces in a group are smoothed by it anyway), another format's faces where they meet at less than 45 degrees (STL)"},
        {.name = "--strict", .kind = OPT_FLAG, .dst = &a->strict,
         .help = "make every warning an error (an undefined material, a missing library, skipped elements, ...)"},
        {.name = "--quiet", .kind = OPT_FLAG, .dst = &a->quiet, .help = "print errors only: no summary, no progress"},
        {0},
    };
    const char *args[2] = {NULL, NULL};
    OptSpec spec = {.prog = "obj2tmd", .synopsis = "[options] in.obj|in.ply|in.stl|in.gltf|in.glb|in.tmd|... out.tmd",
                    .about = "Converts a Wavefront OBJ model (with its MTL materials) into a .tmd file: the triangles in\n"
                    "the order of a bounding volume hierarchy, ready to render (docs/tmd.md).  PLY, STL, glTF 2.0\n"
                    "and other formats are read through Assimp, chosen by the extension (docs/models.md); a .tmd\n"
                    "has its tree built again with the options given.  On a terminal, a conversion longer than a\n"
                    "second shows the step under way.",
                    .opts = opts, .args = args, .min_args = 2, .max_args = 2, .missing = "needs an input and an output",
                    .exits = "  0  converted\n"
                    "  1  an error in the OBJ (file and line named), no usable triangle, an unwritable output, or the\n"
                    "     output is the input; no output file is left\n"
                    "  2  bad command line, or an output not named .tmd\n"};
    int go = opt_run(&spec, argc, argv);
    a->in = args[0], a->out = args[1];
    return go;
}

/* The output checked before the work: not the input, named .tmd, in a
 * directory that takes a file.  0, or the exit status. */
static int check_output(const char *in, const char *out)
{
    Err err = {{0}};
    if (same_file(in, out)) {
        fprintf(stderr, "obj2tmd: %s is the input file %s; name another output\n", out, in);
        return 1;
    }
    size_t on = strlen(out);
    if (on < 4 || strcasecmp(out + on - 4, ".tmd") != 0) {
        fprintf(stderr, "obj2tmd: %s: the output is a .tmd file; name it so (a reader takes a model by its extension)\n",
                out);
        return 2;
    }
    AtomicFile probe;
    if (file_atomic_open(&probe, out, &err)) {
        fprintf(stderr, "obj2tmd: %s\n", err.msg);
        return 1;
    }
    file_atomic_abort(&probe);
    return 0;
}

/* The mesh from an OBJ by its own reader, or from PLY, STL, glTF and the
 * rest through Assimp (import.h), with its statistics: 0, or the exit
 * status. */
static int read_mesh(const Args *a, Mesh *mesh, ObjStats *st)
{
    Err err = {{0}};
    ObjOptions oo = {.smooth = a->smooth, .strict = a->strict, .warn = a->quiet ? NULL : cli_warning,
                   .warn_ctx = &warnings};
    const ModelFormat f = a->format;
    if (f == MODEL_FORMAT_UNKNOWN) { /* read as OBJ, such a file gave the OBJ reader's puzzles */
        fprintf(stderr, "obj2tmd: %s: not a model format by its name's extension; obj2tmd reads .obj, .tmd (its tree "
                        "built again), and through Assimp .ply, .stl, .gltf, .glb, .fbx, .dae, .3ds, ... (docs/models.md)\n",
                a->in);
        return 1;
    }
    if (f == MODEL_FORMAT_IMPORT) {
        ImportStats is;
        if (import_read(a->in, &oo, mesh, &is, &err) == 0) {
            st->smoothed = is.smoothed;
            st->vertices = is.vertices, st->faces = is.triangles + is.degenerate, st->degenerate = is.degenerate;
            st->skipped[OBJ_SKIP_LINE] = is.lines, st->skipped[OBJ_SKIP_POINT] = is.points;
            st->coloured = is.coloured, st->colours = mesh->col != NULL, st->colours_ignored = is.colours_ignored;
            st->warnings = is.warnings, st->missing_textures = is.missing_textures;
            st->optics_mtl = is.optics, st->emit_strengths = is.strengths, st->speculars = is.speculars;
            return 0;
        }
    } else if (obj_read(a->in, &oo, mesh, st, &err) == 0) {
        return 0;
    }
    fprintf(stderr, "obj2tmd: %s\n", err.msg);
    return 1;
}

/* The summary: what was read, what was built, how long it took. */
static void print_summary(const Args *a, const Model *model, const ObjStats *st, const BvhOptions *bo, double parse_s,
                          double build_s)
{
    printf("%s -> %s\n", a->in, a->out);
    if (a->format == MODEL_FORMAT_TMD)
        printf("  triangles %u (a .tmd: its tree built again)\n", model->tri_count);
    else
        printf("  vertices %lu, faces %lu, triangles %u, degenerate dropped %lu\n", st->vertices, st->faces,
               model->tri_count, st->degenerate);
    printf("  attributes: %s%s%s%s", model->normals ? "normals " : "", model->uvs ? "uvs " : "",
           model->colours ? "vertex-colours " : "",
           model->mat_ids ? "materials" : (model->normals || model->uvs || model->colours ? "" : "positions only"));
    if (model->texture_count)
        printf(", textures %u", model->texture_count);
    printf("\n");
    const Aabb b = model->bounds;
    printf("  bounds x %g..%g, y %g..%g, z %g..%g (size %g x %g x %g)\n", (double)b.min.x, (double)b.max.x,
           (double)b.min.y, (double)b.max.y, (double)b.min.z, (double)b.max.z, (double)(b.max.x - b.min.x),
           (double)(b.max.y - b.min.y), (double)(b.max.z - b.min.z));
    printf("  bvh %s: %u nodes, depth %u, SAH cost %.2f\n", bvh_kind_name(bo->kind), model->bvh.node_count,
           model->bvh.depth, bvh_sah_cost(&model->bvh));
    printf("  parse %.3f s, build %.3f s\n", parse_s, build_s);
    struct stat sb;
    if (stat(a->in, &sb) == 0 && parse_s > 0)
        printf("  read %.1f MB at %.1f MB/s\n", (double)sb.st_size / 1e6, (double)sb.st_size / 1e6 / parse_s);
    if (st->warnings)
        printf("  warnings %lu: undefined materials %lu, missing material libraries %lu, missing textures %lu, "
               "files found by name %lu%s\n",
               st->warnings, st->undefined_mtl, st->missing_mtllib, st->missing_textures, st->found_elsewhere,
               st->colours_ignored ? ", vertex colours ignored" : "");
    if (st->smoothed)
        printf("  smooth normals: %lu triangles (%s)\n", st->smoothed,
               st->smoothing ? "by smoothing group, s"
               : a->format == MODEL_FORMAT_OBJ ? "--smooth"
                                                         : "--smooth, edges sharper than 45 degrees kept");
    if (st->optics_mtl)
        printf("  materials with reflection, glass, transparency or emission (%s): %lu\n",
               a->format == MODEL_FORMAT_OBJ ? "illum, Ni, d, Ke" : "metal, transmission, opacity, emission",
               st->optics_mtl);
    if (st->emit_strengths)
        printf("  emission strengths (KHR_materials_emissive_strength): %lu materials\n", st->emit_strengths);
    if (st->speculars)
        printf("  speculars (KHR_materials_specular): %lu materials\n", st->speculars);
    if (st->coloured)
        printf("  vertex colours: %lu coloured vertices, %s\n", st->coloured,
               st->colours ? "kept as the diffuse colour" : "ignored (the model has materials)");
    int any = 0;
    for (int k = 0; k < OBJ_SKIP_KINDS; k++)
        if (st->skipped[k])
            printf("%s %lu %s", any++ ? "," : "  skipped:", st->skipped[k], obj_skip_name((ObjSkip)k));
    if (any)
        printf("\n");
}

/* The model to write: the input's mesh with its tree built, or a .tmd's
 * tree built again with the options given (a model converted once,
 * compared across builders); the reading's seconds in *parse_s.  0, or
 * the exit status. */
static int make_model(const Args *a, const BvhOptions *bo, Step *step, Model **model, ObjStats *st, double *parse_s)
{
    Err err = {{0}};
    const double t0 = timer_now();
    memset(st, 0, sizeof *st);
    *parse_s = 0;
    if (a->format == MODEL_FORMAT_TMD) {
        if (a->smooth) {
            fprintf(stderr, "obj2tmd: %s: --smooth needs the model's source, not a .tmd\n", a->in);
            return 2;
        }
        atomic_store(&step->step, "rebuilding the tree of");
        if (model_load(a->in, bo, 1, 0, model, &err)) {
            fprintf(stderr, "obj2tmd: %s\n", err.msg);
            return 1;
        }
        return 0;
    }
    Mesh mesh;
    int rc = read_mesh(a, &mesh, st);
    *parse_s = timer_now() - t0;
    if (rc == 0 && mesh.tri_count == 0) {
        fprintf(stderr, "obj2tmd: %s: no usable triangles (%lu faces, %lu degenerate)\n", a->in, st->faces, st->degenerate);
        mesh_free(&mesh);
        rc = 1;
    }
    if (rc == 0) {
        atomic_store(&step->step, bo->kind == BVH_MST   ? "building the MST tree of"
                                  : bo->kind == BVH_SBT ? "building the SBT tree of"
                                                        : "building the SAH tree of");
        if (model_from_mesh(model, &mesh, bo, &err)) {
            fprintf(stderr, "obj2tmd: %s: %s\n", a->in, err.msg);
            rc = 1;
        }
        mesh_free(&mesh);
    }
    return rc;
}

/* Reads, builds and writes, the progress line saying which: 0, or the
 * exit status. */
static int convert(const Args *a)
{
    Err err = {{0}};
    BvhOptions bo = bvh_options_default((BvhKind)a->bvh_kind);
    bo.max_leaf = (uint32_t)a->leaf;
    bo.sbt_alternate = a->axis == 1;
    bo.threads = cli_threads(a->threads);
    Step step;
    atomic_init(&step.step, "reading");
    atomic_init(&step.file, a->in);
    Progress *prog = progress_start("obj2tmd", !a->quiet, show_step, &step);
    Model *model = NULL;
    ObjStats st;
    double parse_s;
    const double t0 = timer_now();
    int rc = make_model(a, &bo, &step, &model, &st, &parse_s);
    const double t2 = timer_now();
    if (rc == 0) {
        atomic_store(&step.step, "writing");
        atomic_store(&step.file, a->out);
        if (tmd_write(a->out, model, &err)) {
            fprintf(stderr, "obj2tmd: %s\n", err.msg);
            rc = 1;
        }
    }
    progress_stop(prog);
    if (rc == 0 && !a->quiet)
        print_summary(a, model, &st, &bo, parse_s, t2 - t0 - parse_s);
    model_destroy(model);
    return rc;
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc == OPT_GO) {
        file_atomic_on_signals(); /* interrupted, nothing half-written is left */
        a.format = model_format(a.in);
        rc = check_output(a.in, a.out);
        if (rc == 0)
            rc = convert(&a);
    }
    return rc;
}
