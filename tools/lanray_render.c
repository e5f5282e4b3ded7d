/* lanray-render - the standalone renderer: one frame of a scene to an image.
 * Its options and exit statuses are in the table in main (lanray-render
 * --help prints them; docs/tools.md has the same text).
 *
 * Without a scene it renders the built-in default scene; a model alone
 * (.obj, .tmd) gets a preview scene.  The output file is created before
 * rendering starts, so a bad name or directory fails at once; a frame too
 * large to hold in memory is rendered in bands, each written to the file as
 * it finishes.  Prints the frame time and rays per second (camera rays plus
 * shadow rays). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/cli.h"
#include "base/fileio.h"
#include "image/image.h"
#include "base/opt.h"
#include "base/progress.h"
#include "render/render.h"
#include "base/simd.h"
#include "base/timer.h"

/* Frames above this are rendered in bands of BAND_BYTES, written as they finish. */
#define WHOLE_FRAME_BYTES ((uint64_t)256 << 20)
#define BAND_BYTES ((uint64_t)32 << 20)

static const char *const shading_names[] = {"phong", "diffuse", NULL};
static const char *const onoff_names[] = {"off", "on", NULL};
static const char *const filter_names[] = {"nearest", "bilinear", "trilinear", "anisotropic", NULL};

static const char *const fresnel_names[] = {"exact", "schlick", NULL};
static const char *const glass_names[] = {"opaque", "tinted", NULL};
static const char *const sampling_names[] = {"budget", "product", NULL};
static const char *const limit_names[] = {"black", "background", "ambient", "local", NULL};

typedef struct {
    RenderProgress counts;
    uint64_t pixels; /* of the whole job */
    int width;
} Watch;

static void show_progress(void *ctx, double elapsed, char *line, size_t size)
{
    Watch *w = ctx;
    uint64_t done = atomic_load_explicit(&w->counts.pixels, memory_order_relaxed);
    uint64_t rays = atomic_load_explicit(&w->counts.rays, memory_order_relaxed);
    double f = w->pixels ? (double)done / (double)w->pixels : 0;
    char left[32];
    progress_duration(f > 0 ? elapsed * (1 - f) / f : -1, left, sizeof left);
    snprintf(line, size, "%llu of %llu lines (%.0f%%), %.2f Mrays/s, %s left",
             (unsigned long long)(done / (uint64_t)w->width), (unsigned long long)(w->pixels / (uint64_t)w->width),
             100 * f, (double)rays / elapsed * 1e-6, left);
}

/* Per-line cost, for the scheduler simulator (tools/schedsim): the pure
 * rendering work of every line.  The frame is rendered line by line, top to
 * bottom, PROFILE_PASSES times; each line keeps its fastest pass, because
 * interference only ever adds time.  Passes run in frame order, as a client
 * renders a segment: timing one line several times in a row would find its
 * geometry in the cache and make the costly lines look cheaper than they are
 * inside a segment.  A call into the pool costs a hand-off when the pool has
 * worker threads; the simulator models it as the per-segment overhead, so it
 * is measured on a one-pixel call and taken off. */
static int write_profile(RenderPool *pool, const Scene *scene, int width, int height, uint8_t *pixels,
                         const char *profile, Err *err)
{
    enum { PROFILE_PASSES = 15, PROFILE_CALLS = 64 };
    FILE *pf = fopen(profile, "w");
    double *line = calloc((size_t)height, sizeof *line);
    int rc = 0;
    if (!pf)
        rc = err_set(err, "%s: cannot write", profile);
    else if (!line)
        rc = err_set(err, "out of memory for the profile");
    double call = 1e30;
    for (int k = 0; rc == 0 && k < PROFILE_CALLS; k++) {
        double a = timer_now();
        rc = render_span(pool, scene, width, height, 0, 1, pixels, NULL, NULL, err);
        call = fmin(call, timer_now() - a);
    }
    for (int k = 0; rc == 0 && k < PROFILE_PASSES; k++)
        for (int y = 0; rc == 0 && y < height; y++) {
            double a = timer_now();
            uint8_t *dst = pixels + (size_t)y * width * render_pixel_bytes(scene);
            rc = render_lines(pool, scene, width, height, y, 1, dst, NULL, err);
            double t = timer_now() - a;
            line[y] = k == 0 ? t : fmin(line[y], t);
        }
    for (int y = 0; rc == 0 && y < height; y++)
        fprintf(pf, "%d,%.1f\n", y, fmax(line[y] - call, 0.0) * 1e6);
    free(line);
    if (pf && fclose(pf) != 0 && rc == 0)
        rc = err_set(err, "%s: write failed", profile);
    return rc;
}

/* --stats: what the scene's models hold, per triangle */
static void print_memory(const Scene *s)
{
    ModelBytes sum = {0, 0, 0, 0};
    uint64_t tris = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        ModelBytes b = model_bytes(s->models[i]);
        sum.tris += b.tris, sum.tree += b.tree, sum.wide += b.wide, sum.attributes += b.attributes;
        tris += s->models[i]->tri_count;
    }
    if (tris == 0)
        return;
    double n = (double)tris, all = (double)(sum.tris + sum.tree + sum.wide + sum.attributes);
    printf("memory: %llu model triangles, %.1f bytes/triangle (triangles %.1f + tree %.1f + wide tree %.1f + "
           "attributes %.1f)\n",
           (unsigned long long)tris, all / n, (double)sum.tris / n, (double)sum.tree / n, (double)sum.wide / n,
           (double)sum.attributes / n);
}

int main(int argc, char **argv)
{
    const char *out = "lanray.png", *profile = NULL;
    int width = 1024, height = 768, repeat = 1, quiet = 0, segment = 0, threads = 0, linear = 0, simd_given = 0,
        stats = 0;
    int width_given = 0, height_given = 0, force_bvh = 0, bvh_kind = BVH_SAH, band_lines = 0;
    int shading = SHADE_PHONG, shadows = 1, filter = FILTER_ANISOTROPIC, shading_given = 0, shadows_given = 0, filter_given = 0;
    int depth = 5, fresnel = FRESNEL_EXACT, glass = 1, depth_given = 0, cutoff_given = 0, fresnel_given = 0, glass_given = 0;
    double cutoff = 0.01;
    int light_samples = 0, rough_samples = 0, lens_samples = 0, exposure_given = 0;
    int sampling = SAMPLING_BUDGET, sampling_given = 0, limit = LIMIT_BACKGROUND, limit_given = 0;
    double exposure = 0;
    CliAa aa = {4, 1, 0};
    const Opt opts[] = {
        {.name = "--output", .alias = "-o", .kind = OPT_STRING, .dst = &out, .arg = "FILE",
         .help = "the image: .png (tagged sRGB, or linear with --linear), .ppm, or .hdr (Radiance RGBE: high dynamic "
                 "range, the light itself)"},
        {.name = "--width", .kind = OPT_INT, .dst = &width, .arg = "W", .lo = 1, .hi = RENDER_MAX_SIDE,
         .help = "frame width in pixels", .def = "the scene's, else 1024", .seen = &width_given},
        {.name = "--height", .kind = OPT_INT, .dst = &height, .arg = "H", .lo = 1, .hi = RENDER_MAX_SIDE,
         .help = "frame height in pixels", .def = "the scene's, else 768", .seen = &height_given},
        {.name = "--aa", .kind = OPT_CUSTOM, .dst = &aa, .arg = "N|adaptive[:N]", .parse = cli_parse_aa, .range = CLI_AA_RANGE,
         .help = "anti-aliasing: N x N samples, or one and N x N where neighbours differ",
         .def = "the scene's, else adaptive:4"},
        {.name = "--threads", .kind = OPT_INT, .dst = &threads, .arg = "T", .lo = 0, .hi = RENDER_MAX_THREADS,
         .help = "render threads, 0 = one per core", .def = "0: all cores"},
        {.name = "--bvh", .kind = OPT_CHOICE, .dst = &bvh_kind, .choices = cli_bvh_names, .seen = &force_bvh,
         .help = "BVH builder for models; given, it rebuilds .tmd models too"},
        {.name = "--shading", .kind = OPT_CHOICE, .dst = &shading, .choices = shading_names, .seen = &shading_given,
         .help = "Phong, or diffuse only", .def = "the scene's, else phong"},
        {.name = "--shadows", .kind = OPT_CHOICE, .dst = &shadows, .choices = onoff_names, .seen = &shadows_given,
         .help = "shadow rays", .def = "the scene's, else on"},
        {.name = "--filter", .kind = OPT_CHOICE, .dst = &filter, .choices = filter_names, .seen = &filter_given,
         .help = "texture filtering: one texel, four, mip-maps by the ray's footprint, or mip-maps along it",
         .def = "the scene's, else anisotropic"},
        {.name = "--depth", .kind = OPT_INT, .dst = &depth, .arg = "N", .lo = 0, .hi = SCENE_MAX_DEPTH, .seen = &depth_given,
         .help = "bounces of reflected and refracted rays after the camera ray", .def = "the scene's, else 5"},
        {.name = "--cutoff", .kind = OPT_REAL, .dst = &cutoff, .arg = "W", .rlo = 0, .rhi = 0.999, .seen = &cutoff_given,
         .help = "skip a secondary ray that can add less than W to the pixel", .def = "the scene's, else 0.01"},
        {.name = "--fresnel", .kind = OPT_CHOICE, .dst = &fresnel, .choices = fresnel_names, .seen = &fresnel_given,
         .help = "a dielectric's reflectance: Fresnel's equations or Schlick's approximation",
         .def = "the scene's, else exact"},
        {.name = "--depth-limit", .kind = OPT_CHOICE, .dst = &limit, .choices = limit_names, .seen = &limit_given,
         .help = "what a mirror's or glass's ray cut at the depth limit returns", .def = "the scene's, else background"},
        {.name = "--glass-shadows", .kind = OPT_CHOICE, .dst = &glass, .choices = glass_names, .seen = &glass_given,
         .help = "shadow rays through dielectrics: stopped, or tinted by their colour", .def = "the scene's, else tinted"},
        {.name = "--sampling", .kind = OPT_CHOICE, .dst = &sampling, .choices = sampling_names, .seen = &sampling_given,
         .help = "area lights, a lens, rough mirrors: their K x K points shared by a pixel's rays (budget: costs add), or "
                 "taken by every ray (product: costs multiply)", .def = "the scene's, else budget"},
        {.name = "--light-samples", .kind = OPT_INT, .dst = &light_samples, .arg = "K", .lo = 0, .hi = LIGHT_MAX_SAMPLES,
         .help = "shadow rays of every sphere and rect light: K x K a pixel (product: a ray); 0 = each light's own",
         .def = "0"},
        {.name = "--rough-samples", .kind = OPT_INT, .dst = &rough_samples, .arg = "K", .lo = 0, .hi = SCENE_MAX_SAMPLES,
         .help = "rays of a rough mirror: K x K a pixel (product: a ray); 0 = the scene's",
         .def = "0: the scene's, else 6 (product: 4)"},
        {.name = "--lens-samples", .kind = OPT_INT, .dst = &lens_samples, .arg = "K", .lo = 0, .hi = SCENE_MAX_SAMPLES,
         .help = "rays through a camera's lens: K x K a pixel (product: a pixel sample); 0 = the scene's",
         .def = "0: the scene's, else 3 (product: 4)"},
        {.name = "--exposure", .kind = OPT_REAL, .dst = &exposure, .arg = "STOPS", .rlo = -32, .rhi = 32,
         .seen = &exposure_given, .help = "8-bit output shows the light times 2^STOPS", .def = "the scene's, else 0"},
        {.name = "--linear", .kind = OPT_FLAG, .dst = &linear,
         .help = "write linear light (PNG tagged gAMA 1.0) instead of sRGB"},
        {.name = "--repeat", .kind = OPT_INT, .dst = &repeat, .arg = "N", .lo = 1, .hi = 100000,
         .help = "render the frame N times, report the best and mean time (benchmarks)"},
        {.name = "--segment", .kind = OPT_INT, .dst = &segment, .arg = "LINES", .lo = 0, .hi = RENDER_MAX_SIDE,
         .help = "render as segments of LINES lines one after another, as clients do; 0 = whole frame"},
        {.name = "--band", .kind = OPT_INT, .dst = &band_lines, .arg = "LINES", .lo = 0, .hi = RENDER_MAX_SIDE,
         .help = "hold only LINES lines in memory, writing each band as it is done; 0 = the whole frame up to 256 MB, "
                 "bands of 32 MB above"},
        {.name = "--profile", .kind = OPT_STRING, .dst = &profile, .arg = "FILE",
         .help = "also time every line alone, write 'line,microseconds' to FILE (for tools/schedsim)"},
        {.name = "--simd", .kind = OPT_CUSTOM, .parse = cli_parse_simd, .arg = "PATH", .range = CLI_SIMD_RANGE,
         .seen = &simd_given, .help = "traversal path (every path gives the same pixels)", .def = CLI_SIMD_DEFAULT},
        {.name = "--stats", .kind = OPT_FLAG, .dst = &stats,
         .help = "print the models' memory per triangle (triangles, tree, wide tree, attributes)"},
        {.name = "--quiet", .kind = OPT_FLAG, .dst = &quiet, .help = "print only the timing line: no scene line, no progress"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "lanray-render", .synopsis = "[scene | model.obj | model.tmd] [options]",
                    .about = "Renders one frame: the built-in scene without an argument, a scene file (docs/scene.md), or a\n"
                    "preview of one model (camera framed on it, two lights).  On a terminal, a render longer than\n"
                    "a second shows its progress.  Frames over 256 MB are rendered in bands written as they finish.",
                    .opts = opts, .args = args, .max_args = 1,
                    .exits = "  0  the image was written\n"
                    "  1  an error: the scene, the output file or its directory, memory; nothing is left behind\n"
                    "  2  bad command line, or an image format it does not write (-o x.jpg)\n"};
    int go = opt_run(&spec, argc, argv);
    if (go != OPT_GO)
        return go;
    Err err = {{0}};
    file_atomic_on_signals(); /* interrupted, nothing half-written is left */
    if (!simd_given && cli_simd_env(&err)) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        return 2;
    }
    /* a wrong output name fails before the scene is even loaded: a bad
     * command line (a directory that is not there fails later, 1) */
    if (image_check_name(out, &err)) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        return 2;
    }
    threads = cli_threads(threads);
    BvhOptions bvh = bvh_options_default((BvhKind)bvh_kind);
    Scene *scene;
    double t0 = timer_now();
    if (cli_open_scene(args[0], &bvh, force_bvh, &scene, &err)) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        return 1;
    }
    RenderSettings *rs = &scene->settings;
    if (aa.given || !rs->sampling_given) /* a still image is anti-aliased unless the scene or the user says */
        rs->aa = aa.aa, rs->adaptive = aa.adaptive;
    if (shading_given)
        rs->shading = (ShadeModel)shading;
    if (shadows_given)
        rs->shadows = shadows;
    if (filter_given)
        rs->filter = (TextureFilter)filter;
    if (depth_given)
        rs->depth = depth;
    if (cutoff_given)
        rs->cutoff = (real)cutoff;
    if (fresnel_given)
        rs->fresnel = (FresnelModel)fresnel;
    if (glass_given)
        rs->glass_shadows = glass;
    if (sampling_given)
        rs->sampling = (Sampling)sampling;
    if (limit_given)
        rs->depth_limit = (DepthLimit)limit;
    if (rough_samples)
        rs->rough_samples = rough_samples;
    if (lens_samples)
        rs->lens_samples = lens_samples;
    for (uint32_t i = 0; light_samples && i < scene->light_count; i++)
        if (light_is_area(&scene->lights[i]))
            scene->lights[i].samples = light_samples;
    rs->linear = linear;
    if (exposure_given)
        rs->exposure = (real)exposure;
    const int hdr = image_is_hdr(out);
    if (hdr && (linear || exposure_given)) {
        fprintf(stderr, "lanray-render: --linear and --exposure are for 8-bit output (.png, .ppm); a .hdr keeps the light "
                        "itself\n");
        scene_destroy(scene);
        return 2;
    }
    rs->hdr = hdr;
    if (!width_given && rs->width)
        width = rs->width;
    if (!height_given && rs->height)
        height = rs->height;
    if (scene_prepare(scene, &err)) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        scene_destroy(scene);
        return 1;
    }
    double t1 = timer_now();
    cli_warn_scene("lanray-render", scene);
    const uint32_t bpp = render_pixel_bytes(scene);
    uint64_t frame_bytes = (uint64_t)width * (uint64_t)height * bpp;
    int banded = band_lines ? band_lines < height : frame_bytes > WHOLE_FRAME_BYTES;
    int band = !banded ? height : band_lines ? band_lines : (int)(BAND_BYTES / ((uint64_t)width * bpp));
    if (band < 1)
        band = 1;
    int rc = 0;
    if (banded && profile)
        rc = err_set(&err, "%dx%d is rendered in bands (%.1f GB whole); --profile needs the whole frame", width, height,
                     (double)frame_bytes / 1e9);
    else
        rc = cli_check_memory((uint64_t)width * (uint64_t)band * bpp, banded ? "a band of the frame" : "the frame", &err);
    ImageWriter *wr = NULL;
    if (rc == 0) /* the file exists, under a temporary name, before any rendering */
        rc = image_writer_open(out, width, height, hdr ? IMAGE_RGBE : linear ? IMAGE_LINEAR : IMAGE_SRGB, &wr, &err);
    RenderPool *pool = rc ? NULL : render_pool_create(threads, &err);
    uint8_t *pixels = pool ? malloc((size_t)width * (size_t)band * bpp) : NULL;
    if (rc == 0 && (!pool || !pixels))
        rc = pool ? err_set(&err, "out of memory for %d lines of %d pixels", band, width) : -1;
    if (rc) {
        fprintf(stderr, "lanray-render: %s\n", err.msg);
        image_writer_abort(wr);
        free(pixels);
        render_pool_destroy(pool);
        scene_destroy(scene);
        return 1;
    }
    if (!quiet)
        printf("scene: %s, %llu triangles, %u spheres, %u planes, %u lights; loaded in %.3f s\n",
               args[0] ? args[0] : "built-in default", (unsigned long long)scene_triangle_count(scene),
               scene->sphere_count, scene->plane_count, scene->light_count, t1 - t0);
    fflush(stdout);
    Watch watch;
    memset(&watch, 0, sizeof watch);
    watch.pixels = (uint64_t)width * (uint64_t)height * (uint64_t)repeat;
    watch.width = width;
    render_pool_watch(pool, &watch.counts);
    Progress *prog = progress_start("lanray-render", !quiet, show_progress, &watch);
    double best = 1e30, sum = 0;
    RayStats st = {0, 0, 0};
    int seg = segment && segment < band ? segment : band; /* a band holds a segment */
    for (int f = 0; f < repeat && rc == 0; f++) {
        double a = timer_now();
        st = (RayStats){0, 0, 0};
        for (int y = 0; rc == 0 && y < height; y += seg) {
            RayStats part;
            int n = y + seg <= height ? seg : height - y;
            uint8_t *dst = pixels + (banded ? 0 : (size_t)y * width * bpp);
            rc = render_lines(pool, scene, width, height, y, n, dst, &part, &err);
            ray_stats_add(&st, part);
            if (rc == 0 && banded && f == repeat - 1) /* in bands, the last pass writes */
                rc = image_writer_rows(wr, pixels, n, &err) ? (wr = NULL, -1) : 0;
        }
        double dt = timer_now() - a;
        sum += dt;
        best = fmin(best, dt);
    }
    progress_stop(prog);
    render_pool_watch(pool, NULL);
    if (rc == 0 && profile)
        rc = write_profile(pool, scene, width, height, pixels, profile, &err);
    if (rc == 0 && !banded)
        rc = image_writer_rows(wr, pixels, height, &err) ? (wr = NULL, -1) : 0;
    if (rc == 0)
        rc = image_writer_close(wr, &err);
    else
        image_writer_abort(wr);
    if (rc)
        fprintf(stderr, "lanray-render: %s\n", err.msg);
    else {
        double rays = (double)ray_stats_total(&st);
        char second[64] = "";
        if (st.secondary) /* a scene with mirrors or glass */
            snprintf(second, sizeof second, " + %llu secondary", (unsigned long long)st.secondary);
        printf("%dx%d aa %d%s %s shadows %s bvh %s threads %d simd %s (%s): frame %.4f s (mean %.4f s over %d), "
               "%.2f Mrays/s (%llu camera + %llu shadow%s rays)\n",
               width, height, rs->aa, rs->adaptive ? " adaptive" : "", rs->shading == SHADE_PHONG ? "phong" : "diffuse",
               rs->shadows ? "on" : "off", bvh_kind_name(bvh.kind), threads, simd_name(simd_path()), REAL_NAME, best, sum / repeat, repeat,
               rays / best * 1e-6, (unsigned long long)st.primary, (unsigned long long)st.shadow, second);
        if (stats)
            print_memory(scene);
        if (!quiet)
            printf("wrote %s\n", out);
    }
    free(pixels);
    render_pool_destroy(pool);
    scene_destroy(scene);
    return rc ? 1 : 0;
}
