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
#include "app/flight.h"
#include "base/fileio.h"
#include "image/image.h"
#include "base/opt.h"
#include "base/progress.h"
#include "render/render.h"
#include "scene/camera_path.h"
#include "scene/scene_fields.h"
#include "base/simd.h"
#include "base/timer.h"

/* Frames above this are rendered in bands of BAND_BYTES, written as they finish. */
#define WHOLE_FRAME_BYTES ((uint64_t)256 << 20)
#define BAND_BYTES ((uint64_t)32 << 20)


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
static int write_profile(RenderPool *pool, const World *scene, int width, int height, uint8_t *pixels,
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
            uint8_t *dst = pixels + (size_t)y * width * render_pixel_bytes(&scene->view.settings);
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

/* What the command line says. */
typedef struct {
    const char *out, *profile, *scene_path, *path;
    const char *camera; /* --camera */
    double at;
    int width, height, repeat, quiet, segment, threads, linear, simd_given, stats;
    int width_given, height_given, force_bvh, bvh_kind, band_lines, smooth;
    int shading, shadows, filter, shading_given, shadows_given, filter_given;
    int depth, fresnel, glass, depth_given, cutoff_given, fresnel_given, glass_given;
    double cutoff;
    int light_samples, rough_samples, lens_samples, exposure_given, tonemap, tonemap_given;
    int sampling, sampling_given, limit, limit_given, lights, lights_given, integrator, integrator_given;
    int emitters, emitters_given, roulette, roulette_given, contrast, contrast_given, denoise, denoise_given;
    CliLightPaths paths;
    int still_frame, progressive;
    Flight flight; /* --server-frame: a server's frames, along --path */
    double exposure;
    CliAa aa;
    CliEnvironment env;
} Args;

/* Parses the command line into a: OPT_GO, or the exit status. */
/* The path integrator's options (parse_args' table, out of its length). */
#define RENDER_PATH_OPTS(a) \
    {.name = "--integrator", .kind = OPT_CHOICE, .dst = &(a)->integrator, \
     .choices = field_words(&settings_kind, "integrator"), .seen = &(a)->integrator_given, \
     .help = "Whitted's (lights, shadows, mirrors, glass; emission lights nothing), or a path tracer's: light that " \
             "bounces, emission that lights (docs/renderer.md)", \
     .def = "the scene's, else whitted"}, \
    {.name = "--emitter-sampling", .kind = OPT_CHOICE, .dst = &(a)->emitters, \
     .choices = field_words(&settings_kind, "emitter_sampling"), .seen = &(a)->emitters_given, \
     .help = "path: emissive surfaces found by next-event estimation and by bounces, weighed together (MIS), or " \
             "by one alone (the same picture, other noise)", \
     .def = "the scene's, else mis"}, \
    {.name = "--roulette", .kind = OPT_INT, .dst = &(a)->roulette, .arg = "N", .lo = 0, .hi = SCENE_MAX_DEPTH, \
     .seen = &(a)->roulette_given, .help = "path: bounces before Russian roulette may end a path", \
     .def = "the scene's, else 5"}, \
    {.name = "--denoise", .kind = OPT_CHOICE, .dst = &(a)->denoise, .choices = field_words(&settings_kind, "denoise"), \
     .seen = &(a)->denoise_given, \
     .help = "path: filter the frame's noise out, guided by the surfaces each pixel saw first (their colours, " \
             "normals, distances; docs/renderer.md)", \
     .def = "the scene's, else off"}, \
    CLI_LIGHT_PATHS_OPTS(&(a)->paths)

/* lanray-render --help's text above the options, and its exit statuses */
static const char render_about[] =
    "Renders one frame: the built-in scene without an argument, a scene file (docs/scene.md), or a\n"
    "preview of one model (camera framed on it, two lights).  On a terminal, a render longer than\n"
    "a second shows its progress.  Frames over 256 MB are rendered in bands written as they finish.";
static const char render_exits[] = "  0  the image was written\n"
                                   "  1  an error: the scene, the output file or its directory, memory; nothing is "
                                   "left behind\n"
                                   "  2  bad command line, or an image format it does not write (-o x.jpg)\n";

static int parse_args(Args *a, int argc, char **argv)
{
    *a = (Args){.out = "lanray.png", .width = 1024, .height = 768, .repeat = 1, .bvh_kind = BVH_SAH,
                .shading = SHADE_PHONG, .shadows = 1, .filter = FILTER_ANISOTROPIC, .depth = 5,
                .fresnel = FRESNEL_EXACT, .glass = 1, .cutoff = 0.01, .sampling = SAMPLING_BUDGET,
                .limit = LIMIT_BACKGROUND, .aa = {4, 1, 0},
                .flight = {.temporal = TEMPORAL_DEFAULT_FRAMES, .whitted_temporal = TEMPORAL_WHITTED_FRAMES}};
    const Opt opts[] = {
        {.name = "--output", .alias = "-o", .kind = OPT_STRING, .dst = &a->out, .arg = "FILE",
         .help = "the image: .png (tagged sRGB, or linear with --linear), .ppm, or .hdr (Radiance RGBE: high dynamic "
                 "range, the light itself)"},
        {.name = "--width", .kind = OPT_INT, .dst = &a->width, .arg = "W", .lo = 1, .hi = RENDER_MAX_SIDE,
         .help = "frame width in pixels", .def = "the scene's, else 1024", .seen = &a->width_given},
        {.name = "--height", .kind = OPT_INT, .dst = &a->height, .arg = "H", .lo = 1, .hi = RENDER_MAX_SIDE,
         .help = "frame height in pixels", .def = "the scene's, else 768", .seen = &a->height_given},
        {.name = "--aa", .kind = OPT_CUSTOM, .dst = &a->aa, .arg = "N|adaptive[:N]", .parse = cli_parse_aa, .range = CLI_AA_RANGE,
         .help = "anti-aliasing: N x N samples, or one and N x N where neighbours differ",
         .def = "the scene's, else adaptive:4"},
        {.name = "--threads", .kind = OPT_INT, .dst = &a->threads, .arg = "T", .lo = 0, .hi = RENDER_MAX_THREADS,
         .help = "render threads, 0 = one per core", .def = "0: all cores"},
        {.name = "--bvh", .kind = OPT_CHOICE, .dst = &a->bvh_kind, .choices = bvh_kind_names, .seen = &a->force_bvh,
         .help = "BVH builder for models; given, it rebuilds .tmd models too"},
        CLI_SMOOTH_OPT(&a->smooth),
        {.name = "--shading", .kind = OPT_CHOICE, .dst = &a->shading, .choices = field_words(&settings_kind, "shading"), .seen = &a->shading_given,
         .help = "Phong, or diffuse only", .def = "the scene's, else phong"},
        {.name = "--shadows", .kind = OPT_CHOICE, .dst = &a->shadows, .choices = field_words(&settings_kind, "shadows"), .seen = &a->shadows_given,
         .help = "shadow rays", .def = "the scene's, else on"},
        {.name = "--filter", .kind = OPT_CHOICE, .dst = &a->filter, .choices = texture_filter_names, .seen = &a->filter_given,
         .help = "texture filtering: one texel, four, mip-maps by the ray's footprint, or mip-maps along it (a procedural checker: at "
                 "a point with nearest, else over the footprint; an environment: its mip-map by the footprint with the last two)",
         .def = "the scene's, else anisotropic"},
        {.name = "--depth", .kind = OPT_INT, .dst = &a->depth, .arg = "N", .lo = 0, .hi = SCENE_MAX_DEPTH, .seen = &a->depth_given,
         .help = "bounces of reflected and refracted rays after the camera ray", .def = "the scene's, else 5"},
        {.name = "--cutoff", .kind = OPT_REAL, .dst = &a->cutoff, .arg = "W", .rlo = 0, .rhi = 0.999, .seen = &a->cutoff_given,
         .help = "skip a secondary ray that can add less than W to the pixel", .def = "the scene's, else 0.01"},
        {.name = "--fresnel", .kind = OPT_CHOICE, .dst = &a->fresnel, .choices = field_words(&settings_kind, "fresnel"), .seen = &a->fresnel_given,
         .help = "a dielectric's reflectance: Fresnel's equations or Schlick's approximation",
         .def = "the scene's, else exact"},
        {.name = "--depth-limit", .kind = OPT_CHOICE, .dst = &a->limit, .choices = field_words(&settings_kind, "depth_limit"), .seen = &a->limit_given,
         .help = "what a mirror's or glass's ray cut at the depth limit returns", .def = "the scene's, else background"},
        {.name = "--glass-shadows", .kind = OPT_CHOICE, .dst = &a->glass, .choices = field_words(&settings_kind, "glass_shadows"), .seen = &a->glass_given,
         .help = "shadow rays through dielectrics: stopped, or tinted by their colour", .def = "the scene's, else tinted"},
        {.name = "--sampling", .kind = OPT_CHOICE, .dst = &a->sampling, .choices = field_words(&settings_kind, "sampling"), .seen = &a->sampling_given,
         .help = "area lights, a lens, rough mirrors: their K x K points shared by a pixel's rays (budget: costs add), or "
                 "taken by every ray (product: costs multiply)", .def = "the scene's, else budget"},
        {.name = "--light-sampling", .kind = OPT_CHOICE, .dst = &a->lights, .choices = field_words(&settings_kind, "light_sampling"),
         .seen = &a->lights_given, .help = "area lights: every point at every pixel, or one point until a pixel's 3 x 3 "
                                          "neighbours disagree (penumbrae, edges) and every point there",
         .def = "the scene's, else full"},
        RENDER_PATH_OPTS(a),
        {.name = "--contrast", .kind = OPT_INT, .dst = &a->contrast, .arg = "CODES", .lo = 0, .hi = 255,
         .seen = &a->contrast_given,
         .help = "adaptive anti-aliasing also refines where a neighbour's colour differs by more than CODES in a "
                 "channel; 255: never (surfaces and lights only)",
         .def = "the scene's, else 15"},
        {.name = "--still-frame", .kind = OPT_INT, .dst = &a->still_frame, .arg = "K", .lo = 0, .hi = 11, .def = "0",
         .help = "path, N x N samples, N a power of two: the picture of a server's still frame K on its way (--still-aa "
                 "N): the first 2^(K-1) samples of each pixel's N x N; 0 = all"},
        {.name = "--progressive", .kind = OPT_FLAG, .dst = &a->progressive,
         .help = "path, N x N samples, N a power of two: render them in batches that double them (1, 2, 4 ... a "
                 "pixel) and write the picture after each, the file replaced whole (an interruption leaves the last); "
                 "the last is the same picture"},
        {.name = "--light-samples", .kind = OPT_INT, .dst = &a->light_samples, .arg = "K", .lo = 0, .hi = LIGHT_MAX_SAMPLES,
         .help = "shadow rays of every sphere and rect light: K x K a pixel (product: a ray); 0 = each light's own",
         .def = "0"},
        {.name = "--rough-samples", .kind = OPT_INT, .dst = &a->rough_samples, .arg = "K", .lo = 0, .hi = SCENE_MAX_SAMPLES,
         .help = "rays of a rough mirror: K x K a pixel (product: a ray); 0 = the scene's",
         .def = "0: the scene's, else 6 (product: 4)"},
        {.name = "--lens-samples", .kind = OPT_INT, .dst = &a->lens_samples, .arg = "K", .lo = 0, .hi = SCENE_MAX_SAMPLES,
         .help = "rays through a camera's lens: K x K a pixel (product: a pixel sample); 0 = the scene's",
         .def = "0: the scene's, else 3 (product: 4)"},
        {.name = "--exposure", .kind = OPT_REAL, .dst = &a->exposure, .arg = "STOPS", .rlo = -32, .rhi = 32,
         .seen = &a->exposure_given, .help = "8-bit output shows the light times 2^STOPS", .def = "the scene's, else 0"},
        CLI_TONEMAP_OPT(&a->tonemap, &a->tonemap_given),
        {.name = "--linear", .kind = OPT_FLAG, .dst = &a->linear,
         .help = "write linear light (PNG tagged gAMA 1.0) instead of sRGB"},
        CLI_ENVIRONMENT_OPTS(&a->env),
        CLI_CAMERA_OPT(&a->camera),
        {.name = "--path", .kind = OPT_STRING, .dst = &a->path, .arg = "FILE",
         .help = "a camera path (docs/scene.md): render its camera at --at in place of the scene's"},
        {.name = "--at", .kind = OPT_REAL, .dst = &a->at, .arg = "T", .rlo = 0, .rhi = 1e9,
         .help = "the time on --path, seconds", .def = "0"},
        FLIGHT_OPTS(&a->flight),
        {.name = "--repeat", .kind = OPT_INT, .dst = &a->repeat, .arg = "N", .lo = 1, .hi = 100000,
         .help = "render the frame N times, report the best and mean time (benchmarks)"},
        {.name = "--segment", .kind = OPT_INT, .dst = &a->segment, .arg = "LINES", .lo = 0, .hi = RENDER_MAX_SIDE,
         .help = "render as segments of LINES lines one after another, as clients do; 0 = whole frame"},
        {.name = "--band", .kind = OPT_INT, .dst = &a->band_lines, .arg = "LINES", .lo = 0, .hi = RENDER_MAX_SIDE,
         .help = "hold only LINES lines in memory, writing each band as it is done; 0 = the whole frame up to 256 MB, "
                 "bands of 32 MB above"},
        {.name = "--profile", .kind = OPT_STRING, .dst = &a->profile, .arg = "FILE",
         .help = "also time every line alone, write 'line,microseconds' to FILE (for tools/schedsim)"},
        {.name = "--simd", .kind = OPT_CUSTOM, .parse = cli_parse_simd, .arg = "PATH", .range = CLI_SIMD_RANGE,
         .seen = &a->simd_given, .help = "traversal path (every path gives the same pixels)", .def = CLI_SIMD_DEFAULT},
        {.name = "--stats", .kind = OPT_FLAG, .dst = &a->stats,
         .help = "print the models' memory per triangle (triangles, tree, wide tree, attributes)"},
        {.name = "--quiet", .kind = OPT_FLAG, .dst = &a->quiet, .help = "print only the timing line: no scene line, no progress, no warnings about the model"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "lanray-render", .synopsis = "[scene | model.obj | model.tmd] [options]",
                    .about = render_about, .opts = opts, .args = args, .max_args = 1, .exits = render_exits};
    int go = opt_run(&spec, argc, argv);
    a->scene_path = args[0];
    return go;
}

/* --camera, or --path: the path's camera at --at in place of the
 * scene's, the path kept for --server-frame (0, or 1; 2 for a camera that
 * cannot be read). */
static int apply_path(Scene *scene, const Args *a, CameraPath *path, Err *err)
{
    if (a->camera && a->path) {
        fprintf(stderr, "lanray-render: --camera and --path each give the camera: give one\n");
        return 2;
    }
    if (cli_put_camera(scene, a->camera, err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 2;
    }
    if (!a->path)
        return 0;
    if (camera_path_load(a->path, path, err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 1;
    }
    scene->camera = camera_path_at(path, (real)a->at);
    return 0;
}

/* The command line's settings over the scene's: 0, or 2 for a .hdr asked to
 * be linear or exposed. */
static int apply_settings(Scene *scene, Args *a)
{
    RenderSettings *rs = &scene->settings;
    if (a->aa.given || !rs->sampling_given) /* a still image is anti-aliased unless the scene or the user says */
        rs->aa = a->aa.aa, rs->adaptive = a->aa.adaptive;
    if (a->shading_given)
        rs->shading = (ShadeModel)a->shading;
    if (a->shadows_given)
        rs->shadows = a->shadows;
    if (a->filter_given)
        rs->filter = (TextureFilter)a->filter;
    if (a->depth_given)
        rs->depth = a->depth;
    if (a->cutoff_given)
        rs->cutoff = (real)a->cutoff;
    if (a->fresnel_given)
        rs->fresnel = (FresnelModel)a->fresnel;
    if (a->glass_given)
        rs->glass_shadows = a->glass;
    if (a->sampling_given)
        rs->sampling = (Sampling)a->sampling;
    if (a->lights_given)
        rs->light_sampling = (LightSampling)a->lights;
    if (a->integrator_given)
        rs->integrator = (Integrator)a->integrator;
    if (a->emitters_given)
        rs->emitter_sampling = (EmitterSampling)a->emitters;
    if (a->roulette_given)
        rs->roulette = a->roulette;
    cli_put_light_paths(rs, &a->paths);
    if (a->contrast_given)
        rs->contrast = a->contrast;
    if (a->denoise_given)
        rs->denoise = a->denoise;
    if (a->limit_given)
        rs->depth_limit = (DepthLimit)a->limit;
    if (a->still_frame) {
        const int m = progressive_batches(rs);
        if (a->still_frame > m) {
            fprintf(stderr, "lanray-render: --still-frame %d: %s\n", a->still_frame,
                    m ? "past the last still frame of these samples (N x N takes 2 log2 N + 1)"
                      : "a path-traced frame of N x N samples a pixel, N a power of two, goes in still frames; this "
                        "one does not");
            return 2;
        }
        rs->batches = a->still_frame;
    }
    if (a->flight.frames && (a->still_frame || a->progressive || a->repeat > 1)) {
        fprintf(stderr, "lanray-render: --server-frame: a server's frames, not with --still-frame, --progressive or --repeat\n");
        return 2;
    }
    if (a->progressive && (!progressive_batches(rs) || a->repeat > 1)) {
        fprintf(stderr, "lanray-render: --progressive: %s\n",
                a->repeat > 1 ? "one frame, not --repeat's"
                              : "a path-traced frame of N x N samples a pixel, N a power of two, goes in batches; this "
                                "one does not");
        return 2;
    }
    if (a->rough_samples)
        rs->rough_samples = a->rough_samples;
    if (a->lens_samples)
        rs->lens_samples = a->lens_samples;
    if (a->light_samples) /* the view's, as a server's still frames take it */
        rs->light_samples = a->light_samples;
    rs->linear = a->linear;
    if (a->exposure_given)
        rs->exposure = (real)a->exposure;
    if (a->tonemap_given)
        rs->tonemap = (Tonemap)a->tonemap;
    rs->hdr = image_is_hdr(a->out);
    if (rs->hdr && (a->linear || a->exposure_given || a->tonemap_given)) {
        fprintf(stderr, "lanray-render: --linear, --exposure and --tonemap are for 8-bit output (.png, .ppm); a .hdr "
                        "keeps the light itself\n");
        return 2;
    }
    if (!a->width_given && rs->width)
        a->width = rs->width;
    if (!a->height_given && rs->height)
        a->height = rs->height;
    return 0;
}

/* The output's encoding for a frame of settings rs. */
static ImageEncoding encoding_of(const RenderSettings *rs)
{
    return rs->hdr ? IMAGE_RGBE : rs->linear ? IMAGE_LINEAR : IMAGE_SRGB;
}

/* A render: what job_open makes, job_close alone frees. */
typedef struct {
    Scene *scene;
    World *world; /* built from scene */
    BvhOptions bvh;
    RenderPool *pool;
    uint8_t *pixels;
    uint8_t *shown; /* settings denoise: the filtered frame, colours alone */
    Denoiser *denoiser; /* ... and its scratch, made before rendering */
    ImageWriter *wr;
    int banded, band;
    uint32_t bpp;
    double load_s;
    CameraPath path; /* --path's */
} Job;

static void job_close(Job *j)
{
    image_writer_abort(j->wr);
    free(j->pixels);
    free(j->shown);
    denoiser_destroy(j->denoiser);
    render_pool_destroy(j->pool);
    world_destroy(j->world);
    scene_destroy(j->scene);
    camera_path_free(&j->path);
}

/* The scene with its settings, the frame's memory (whole, or in bands), the
 * output file under its temporary name and the pool: 0, or the exit status. */
static int job_open(Job *j, Args *a, Err *err)
{
    file_atomic_on_signals(); /* interrupted, nothing half-written is left */
    if (!a->simd_given && cli_simd_env(err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 2;
    }
    /* a wrong output name fails before the scene is even loaded: a bad
     * command line (a directory that is not there fails later, 1) */
    if (image_check_name(a->out, err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 2;
    }
    a->threads = cli_threads(a->threads);
    j->bvh = bvh_options_default((BvhKind)a->bvh_kind);
    double t0 = timer_now();
    if (!a->quiet)
        cli_show_warnings("lanray-render");
    if (cli_open_scene(a->scene_path, &j->bvh, a->force_bvh, a->smooth, &j->scene, err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 1;
    }
    int rc = apply_settings(j->scene, a);
    if (rc == 0 && cli_put_environment(j->scene, &a->env, a->scene_path, err)) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        rc = 1;
    }
    if (rc == 0)
        rc = apply_path(j->scene, a, &j->path, err);
    if (rc)
        return rc;
    if (scene_check(j->scene, err) || !(j->world = world_build(j->scene, NULL, err))) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 1;
    }
    j->load_s = timer_now() - t0;
    cli_warn_scene("lanray-render", j->scene);
    const int width = a->width, height = a->height;
    j->bpp = render_pixel_bytes(&j->scene->settings);
    uint64_t frame_bytes = (uint64_t)width * (uint64_t)height * j->bpp;
    j->banded = a->band_lines ? a->band_lines < height : frame_bytes > WHOLE_FRAME_BYTES;
    j->band = !j->banded ? height : a->band_lines ? a->band_lines : (int)(BAND_BYTES / ((uint64_t)width * j->bpp));
    if (j->band < 1)
        j->band = 1;
    if (j->banded && (a->profile || a->progressive || a->flight.frames || j->scene->settings.denoise))
        rc = err_set(err, "%dx%d is rendered in bands (%.1f GB whole); %s needs the whole frame", width, height,
                     (double)frame_bytes / 1e9,
                     a->profile ? "--profile" : a->progressive ? "--progressive" : a->flight.frames ? "--server-frame" : "denoising");
    else /* with the denoiser's planes (84 bytes a pixel) and the frame it writes, a flight's history */
        rc = cli_check_memory((uint64_t)width * (uint64_t)j->band * j->bpp +
                                  (j->scene->settings.denoise
                                       ? denoiser_bytes((uint32_t)width, (uint32_t)height) +
                                             (uint64_t)width * height * render_colour_bytes(&j->scene->settings)
                                       : 0) +
                                  (a->flight.frames ? flight_bytes(&j->scene->settings, &a->flight, width, height) : 0),
                              j->banded ? "a band of the frame" : j->scene->settings.denoise ? "the frame with its denoiser"
                                                                                              : "the frame",
                              err);
    const RenderSettings *rs = &j->scene->settings;
    if (rc == 0) /* the file exists, under a temporary name, before any rendering */
        rc = image_writer_open(a->out, width, height, encoding_of(rs), &j->wr, err);
    j->pool = rc ? NULL : render_pool_create(a->threads, err);
    j->pixels = j->pool ? malloc((size_t)width * (size_t)j->band * j->bpp) : NULL;
    if (j->pixels && rs->denoise &&
        (!(j->shown = malloc((size_t)width * (size_t)height * render_colour_bytes(rs))) ||
         !(j->denoiser = denoiser_create(render_pool_pool(j->pool), (uint32_t)width, (uint32_t)height)))) {
        free(j->pixels);
        j->pixels = NULL;
    }
    if (rc == 0 && (!j->pool || !j->pixels))
        rc = j->pool ? err_set(err, "out of memory for %d lines of %d pixels", j->band, width) : -1;
    if (rc) {
        fprintf(stderr, "lanray-render: %s\n", err->msg);
        return 1;
    }
    return 0;
}

/* The rendered frame filtered by its guides into j->shown, its time added
 * to the frame's (each of --repeat's, as the server filters each frame). */
static int denoise_now(Job *j, const Args *a, double *best, double *sum, Err *err)
{
    const RenderSettings *rs = &j->scene->settings;
    const double t = timer_now();
    const int rc = denoise_frame(j->denoiser, j->pixels, (uint32_t)a->width, (uint32_t)a->height, render_colour_bytes(rs),
                                 rs->linear, j->shown, err);
    const double dt = timer_now() - t;
    *best += dt, *sum += dt * a->repeat;
    return rc;
}

/* The picture of the batches so far (j->pixels, filtered where denoised),
 * written to the output whole, replacing it (a temporary file renamed). */
static int write_so_far(Job *j, const Args *a, int samples, Err *err)
{
    const RenderSettings *rs = &j->scene->settings;
    double unused = 0, also = 0;
    if (j->shown && denoise_now(j, a, &unused, &also, err))
        return -1;
    ImageWriter *wr;
    if (image_writer_open(a->out, a->width, a->height, encoding_of(rs), &wr, err))
        return -1;
    if (image_writer_rows(wr, j->shown ? j->shown : j->pixels, a->height, err) || image_writer_close(wr, err))
        return -1;
    if (!a->quiet)
        printf("wrote %s: %d sample%s a pixel\n", a->out, samples, samples == 1 ? "" : "s");
    fflush(stdout);
    return 0;
}

/* --progressive: the frame's batches one after another, each rendered as
 * sums and added to those before as a server adds them (render/progressive.h),
 * the picture written after each but the last (job_render writes that): the
 * same picture as in one pass, bit for bit. */
static int render_batches(Job *j, const Args *a, RayStats *st, Err *err)
{
    RenderSettings *rs = &j->world->view.settings;
    const int batches = progressive_upto(rs);
    const uint64_t n = (uint64_t)a->width * (uint64_t)a->height;
    const uint32_t reals = progressive_reals(rs);
    real *acc = calloc(n * reals, sizeof(real));
    uint8_t *sums = malloc(n * reals * sizeof(real));
    int rc = acc && sums ? 0 : err_set(err, "out of memory for the sums of %dx%d pixels", a->width, a->height);
    for (int b = 1; b <= batches && rc == 0; b++) {
        RayStats part;
        rs->batch = b;
        rc = render_span(j->pool, j->world, a->width, a->height, 0, n, sums, &part, NULL, err);
        if (rc == 0)
            progressive_frame_add(rs, acc, sums, n, j->pixels);
        rs->batch = 0;
        ray_stats_add(st, part);
        if (rc == 0 && b < batches)
            rc = write_so_far(j, a, (int)progressive_end(b), err);
    }
    free(acc);
    free(sums);
    return rc;
}

/* The frame, --repeat times, by segments; in bands the last pass writes them. */
static int job_render(Job *j, const Args *a, RayStats *st, double *best, double *sum, Err *err)
{
    Watch watch;
    memset(&watch, 0, sizeof watch);
    watch.pixels = (uint64_t)a->width * (uint64_t)a->height * (uint64_t)a->repeat;
    if (a->progressive) /* every batch a pass over the frame */
        watch.pixels *= (uint64_t)progressive_upto(&j->scene->settings);
    if (a->flight.frames) /* every frame a pass */
        watch.pixels *= (uint64_t)a->flight.frames;
    watch.width = a->width;
    render_pool_watch(j->pool, &watch.counts);
    Progress *prog = progress_start("lanray-render", !a->quiet, show_progress, &watch);
    int rc = 0, seg = a->segment && a->segment < j->band ? a->segment : j->band; /* a band holds a segment */
    *best = 1e30, *sum = 0;
    for (int f = 0; f < a->repeat && rc == 0; f++) {
        double t = timer_now();
        *st = (RayStats){0, 0, 0};
        if (a->progressive || a->flight.frames) {
            rc = a->progressive ? render_batches(j, a, st, err)
                                : flight_render(j->pool, j->world, j->scene, &j->path, &a->flight, a->width,
                                                a->height, j->pixels, st, err);
            *sum = *best = timer_now() - t;
            break;
        }
        for (int y = 0; rc == 0 && y < a->height; y += seg) {
            RayStats part;
            int n = y + seg <= a->height ? seg : a->height - y;
            uint8_t *dst = j->pixels + (j->banded ? 0 : (size_t)y * a->width * j->bpp);
            rc = render_lines(j->pool, j->world, a->width, a->height, y, n, dst, &part, err);
            ray_stats_add(st, part);
            if (rc == 0 && j->banded && f == a->repeat - 1) /* in bands, the last pass writes */
                rc = image_writer_rows(j->wr, j->pixels, n, err) ? (j->wr = NULL, -1) : 0;
        }
        double dt = timer_now() - t;
        *sum += dt;
        *best = fmin(*best, dt);
    }
    progress_stop(prog);
    render_pool_watch(j->pool, NULL);
    if (rc == 0 && a->profile)
        rc = write_profile(j->pool, j->world, a->width, a->height, j->pixels, a->profile, err);
    if (rc == 0 && j->shown) /* settings denoise: the frame filtered (in the timing: a client's frame is filtered too) */
        rc = denoise_now(j, a, best, sum, err);
    if (rc == 0 && !j->banded)
        rc = image_writer_rows(j->wr, j->shown ? j->shown : j->pixels, a->height, err) ? (j->wr = NULL, -1) : 0;
    ImageWriter *wr = j->wr;
    j->wr = NULL;
    if (rc == 0)
        rc = image_writer_close(wr, err);
    else
        image_writer_abort(wr);
    return rc;
}

/* The BVH kinds the scene's models were built with: a .tmd keeps its own
 * tree (the line said the --bvh default, "sah", for an MST file); the
 * option's kind where there is no model, the kinds joined by '+' where
 * models differ. */
static void bvh_text(const Job *j, char *out, size_t size)
{
    unsigned seen = 0;
    for (uint32_t i = 0; i < j->scene->model_count; i++)
        seen |= 1u << j->scene->models[i]->bvh.kind;
    if (!seen)
        seen = 1u << j->bvh.kind;
    out[0] = 0;
    for (int k = 0; k < BVH_KIND_COUNT; k++)
        if (seen >> k & 1) {
            const size_t at = strlen(out);
            snprintf(out + at, size - at, "%s%s", at ? "+" : "", bvh_kind_name((BvhKind)k));
        }
}

/* The timing line (what benchmarks read), the memory table, the file's name. */
static void report(const Job *j, const Args *a, RayStats st, double best, double sum)
{
    char bvh[32];
    bvh_text(j, bvh, sizeof bvh);
    const RenderSettings *rs = &j->scene->settings;
    double rays = (double)ray_stats_total(&st);
    char second[64] = "";
    if (st.secondary) /* a scene with mirrors or glass */
        snprintf(second, sizeof second, " + %llu secondary", (unsigned long long)st.secondary);
    printf("%dx%d aa %d%s %s shadows %s bvh %s threads %d simd %s (%s): frame %.4f s (mean %.4f s over %d), "
           "%.2f Mrays/s (%llu camera + %llu shadow%s rays)\n",
           a->width, a->height, rs->aa, rs->adaptive ? " adaptive" : "", rs->integrator == INTEGRATOR_PATH ? "path-traced" : rs->shading == SHADE_PHONG ? "phong" : "diffuse",
           rs->shadows ? "on" : "off", bvh, a->threads, simd_name(simd_path()), REAL_NAME, best,
           sum / a->repeat, a->repeat, rays / best * 1e-6, (unsigned long long)st.primary, (unsigned long long)st.shadow,
           second);
    if (a->stats)
        print_memory(j->scene);
    if (!a->quiet)
        printf("wrote %s\n", a->out);
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    Err err = {{0}};
    Job j = {0};
    rc = job_open(&j, &a, &err);
    if (rc == 0) {
        if (!a.quiet)
            printf("scene: %s, %llu triangles, %u spheres, %u planes, %u lights; loaded in %.3f s\n",
                   a.scene_path ? a.scene_path : "built-in default", (unsigned long long)scene_triangle_count(j.scene),
                   j.scene->sphere_count, j.scene->plane_count, j.scene->light_count, j.load_s);
        fflush(stdout);
        RayStats st = {0, 0, 0};
        double best = 0, sum = 0;
        if (job_render(&j, &a, &st, &best, &sum, &err)) {
            fprintf(stderr, "lanray-render: %s\n", err.msg);
            rc = 1;
        } else {
            report(&j, &a, st, best, sum);
        }
    }
    job_close(&j);
    return rc;
}
