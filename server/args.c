/* args.c - see args.h. */
#include "args.h"

#include <stdlib.h>

#include "app/flight.h"
#include "base/opt.h"
#include "model/model_load.h"
#include "net/msg.h"
#include "net/pixcodec.h"
#include "scene/scene_fields.h"
#include "upscale.h"

_Static_assert(CLI_MAX_SEGMENT == SERVER_MAX_SIDE, "a segment is at most the tallest frame");

/* --compress: how clients code their pixels (net/pixcodec.h) */
static const char *const compress_words[] = {"raw", "lz4", "zstd", NULL};
static const uint32_t compress_codings[] = {PIX_RAW, PIX_LZ4, PIX_ZSTD | PIX_PREDICT};

/* --pipeline */
static const char *const pipeline_words[] = {"off", "on", NULL};

/* --announce */
static const char *const announce_words[] = {"auto", "yes", "no", NULL};

/* --moving-lights: the scene's (-1), or a LightSampling + 1 */
static const char *const moving_lights_words[] = {"scene", "full", "adaptive", NULL};

/* The server's configuration from what the options said. */
static void config_from_args(Args *a)
{
    ServerConfig *cfg = &a->cfg;
    if (cfg->token && !*cfg->token)
        cfg->token = NULL;
    cfg->tail = sched_tail_rules[a->tail];
    cfg->warmup = (uint32_t)a->warmup;
    cfg->stall_timeout = a->stall;
    cfg->handshake_timeout = a->handshake;
    cfg->refine = a->still.given;
    cfg->still_aa = a->still.aa;
    cfg->still_adaptive = a->still.adaptive;
    cfg->still_lights = a->still_lights;
    /* the scene's by default: adaptive light sampling is a fifth faster on
     * whole 512x384 frames, but slower on the small frames and segments of
     * a flight at a render scale (docs/tradeoff.md) */
    cfg->moving_lights = a->moving_lights_given ? a->moving_lights - 1 : -1;
    cfg->moving_light_samples = a->moving_light_samples;
    cfg->coding = compress_codings[a->compress];
    cfg->pipeline = a->pipeline;
    a->bvh.kind = (BvhKind)a->bvh_kind;
    a->headless |= a->discard;
}

/* lanray-server --help's text above and below the options */
static const char server_about[] =
    "Holds the scene (the built-in one without an argument; a model alone gets a preview scene), hands\n"
    "out segments of each frame to lanray-client processes and shows the frames in a window, or writes\n"
    "them when headless or without a display.  In the window: W/S A/D R/F move (Shift: faster; the speed\n"
    "follows the scene's size), a mouse drag or the arrows look, a right or middle drag orbits round the\n"
    "middle of the view (with Shift, pans), V captures the mouse for mouse look (Esc lets it go), +/- or\n"
    "the wheel zoom, C frames the whole scene, Home resets, K prints the view as a scene's camera line\n"
    "and puts it on the clipboard (for a scene file or lanray-render --camera), Space toggles --rotate, P\n"
    "saves the picture shown (lanray-screenshot-N.png, or .hdr, in the folder the server runs in), Tab\n"
    "shows the panel (frame rate, render scale, samples, each client's lines/s and share, segment size),\n"
    "T/Shift+T the frame-rate target up/down, N the still quality (off, 2x2, adaptive 4x4, 4x4,\n"
    "path-traced on to 16x16 and 32x32), L light sampling, M shading, H shadows, U a scaled frame smooth\n"
    "or in blocks (--upscale), F11 full screen; Esc or Q quits.  The window resizes, and the frames with\n"
    "it: a larger window renders more pixels (the view starts again at each new size); a frame larger\n"
    "than the screen opens a window that fits it.\n"
    "A scene file is followed while it runs: an edit to it or to the models and textures it names is\n"
    "read again and sent between frames; an error keeps the last good scene and is shown with its line.\n"
    "A scene file or a model dropped on the window (from a file manager) is opened in its place, followed\n"
    "in turn.\n"
    "SIGUSR1 prints per-client statistics.";
static const char server_exits[] =
    "  0  every requested frame was written (--frames N), or stopped by the window, SIGINT or SIGTERM\n"
    "     when no count was asked\n"
    "  1  an error: the scene, the address, memory, a frame that could not be written\n"
    "  2  bad command line\n"
    "  3  --verify: a frame differed from the reference\n"
    "  4  stopped (SIGINT, SIGTERM, the window) before the requested frames were done\n";

/* The denoiser's options, and the history's before it */
#define DENOISE_OPTS(a) \
    {.name = "--denoise", .kind = OPT_FLAG, .dst = &(a)->denoise, .seen = &(a)->denoise_given, \
     .help = "path-traced frames filtered by what each pixel saw first (settings denoise on): clients send each " \
             "pixel's guide, 11 bytes, beside its colour; a scene that asks for it is denoised without"}, \
    {.name = "--denoise-threads", .kind = OPT_INT, .dst = &(a)->cfg.denoise_threads, .arg = "T", .lo = 0, \
     .hi = POOL_MAX_THREADS, .help = "threads of the denoiser, 0 = one per core", .def = "0"}, \
    CLI_TEMPORAL_OPT(&(a)->cfg.temporal, "path-traced and denoised: "), \
    CLI_WHITTED_TEMPORAL_OPT(&(a)->cfg.whitted_temporal, "")

/* --moving-lights and --moving-light-samples: the area lights of the
 * frames that are not still ones */
#define MOVING_LIGHTS_OPTS(a) \
    {.name = "--moving-lights", .kind = OPT_CHOICE, .dst = &(a)->moving_lights, .choices = moving_lights_words, \
     .seen = &(a)->moving_lights_given, \
     .help = "area lights in the frames that are not still ones: the scene's light_sampling, every point at every " \
             "pixel, or adaptive (one probe a pixel, every point in penumbrae: docs/tradeoff.md)", \
     .def = "scene"}, \
    {.name = "--moving-light-samples", .kind = OPT_INT, .dst = &(a)->moving_light_samples, .arg = "K", \
     .hi = LIGHT_MAX_SAMPLES, \
     .help = "area lights in the frames that are not still ones: K x K points a pixel (lanray-render " \
             "--light-samples K); fewer points, a finer render scale at --target-fps (docs/realtime.md); 0 = " \
             "each light's own", \
     .def = "0"}

/* The integrator, its clamp, glossy filter and caustics, and the view
 * transform: how the picture looks, over the scene's settings */
#define LOOK_OPTS(a) \
    {.name = "--integrator", .kind = OPT_CHOICE, .dst = &(a)->integrator, .seen = &(a)->integrator_given, \
     .choices = field_words(&settings_kind, "integrator"), .def = "the scene's, else whitted", \
     .help = "Whitted's, or a path tracer's: light that bounces (in a window, converging when the view stops)"}, \
    CLI_LIGHT_PATHS_OPTS(&(a)->paths), \
    CLI_TONEMAP_OPT(&(a)->tonemap, &(a)->tonemap_given)

int args_parse(Args *a, int argc, char **argv)
{
    *a = (Args){.cfg = {.listen_addr = "127.0.0.1", .port = PROTO_DEFAULT_PORT, .token = getenv("LANRAY_TOKEN"),
                        .width = 1024, .height = 768, .tail = sched_tail_smart, .stall_timeout = 30,
                        .handshake_timeout = 10, .temporal = TEMPORAL_DEFAULT_FRAMES,
                        .whitted_temporal = TEMPORAL_WHITTED_FRAMES},
                .bvh = bvh_options_default(BVH_SAH), .out_dir = "frames", .tail = 1, .bvh_kind = BVH_SAH, .compress = 2, .pipeline = 1,
                .stall = 30, .handshake = 10, .aa = {1, 0, 0}};
    ServerConfig *cfg = &a->cfg;
    const Opt opts[] = {
        {.name = "--port", .kind = OPT_INT, .dst = &cfg->port, .arg = "P", .lo = 0, .hi = 65535,
         .help = "TCP port, 0 = any free one (the 'listening on' line says which)"},
        {.name = "--listen", .kind = OPT_STRING, .dst = &cfg->listen_addr, .arg = "ADDR",
         .help = "address to listen on: a name or an IPv4/IPv6 address; not loopback needs --token or --insecure"},
        {.name = "--token", .kind = OPT_STRING, .dst = &cfg->token, .arg = "T",
         .help = "shared secret clients must prove (or LANRAY_TOKEN in the environment)", .def = "none"},
        {.name = "--insecure", .kind = OPT_FLAG, .dst = &cfg->insecure, .help = "allow a non-loopback address without a token"},
        {.name = "--width", .kind = OPT_INT, .dst = &cfg->width, .arg = "W", .lo = 1, .hi = SERVER_MAX_SIDE,
         .help = "frame width in pixels", .def = "the scene's, else 1024", .seen = &a->width_given},
        {.name = "--height", .kind = OPT_INT, .dst = &cfg->height, .arg = "H", .lo = 1, .hi = SERVER_MAX_SIDE,
         .help = "frame height in pixels", .def = "the scene's, else 768", .seen = &a->height_given},
        {.name = "--fixed-size", .kind = OPT_FLAG, .dst = &a->fixed_size,
         .help = "in a window, the frames keep --width x --height whatever the window's size (drawn scaled to fit "
                 "it); without it (and without --verify) they follow the window's size"},
        {.name = "--segment", .kind = OPT_CUSTOM, .dst = &cfg->segment_lines, .arg = "LINES|auto", .parse = cli_parse_segment,
         .range = CLI_SEGMENT_RANGE, .help = "lines per segment handed to a client", .def = "auto"},
        {.name = "--tail", .kind = OPT_CHOICE, .dst = &a->tail, .choices = sched_tail_names,
         .help = "how the last segments of a frame are cut and shared (docs/scaling.md)"},
        {.name = "--bvh", .kind = OPT_CHOICE, .dst = &a->bvh_kind, .choices = bvh_kind_names, .seen = &a->force_bvh,
         .help = "BVH builder for models; given, it rebuilds .tmd models too"},
        CLI_SMOOTH_OPT(&a->smooth),
        CLI_CAMERA_OPT(&a->camera),
        {.name = "--aa", .kind = OPT_CUSTOM, .dst = &a->aa, .arg = "N|adaptive[:N]", .parse = cli_parse_aa, .range = CLI_AA_RANGE,
         .help = "anti-aliasing", .def = "the scene's, else 1"},
        LOOK_OPTS(a),
        {.name = "--rotate", .kind = OPT_REAL, .dst = &a->rotate, .arg = "DEG",
         .help = "turn every model instance by DEG about y after each frame (Space toggles it in the window)"},
        {.name = "--path", .kind = OPT_STRING, .dst = &a->path, .arg = "FILE",
         .help = "fly the camera along a path (docs/scene.md); headless without --frames, stop at its end and print "
                 "the frame rate held"},
        {.name = "--path-step", .kind = OPT_REAL, .dst = &a->path_step, .arg = "S", .rlo = 0, .rhi = 1e6,
         .help = "seconds of the path a frame, 0 = the time that passes (a frame N shows the path at (N-1) x S)",
         .def = "0"},
        {.name = "--still-aa", .kind = OPT_CUSTOM, .dst = &a->still, .arg = "N|adaptive[:N]", .parse = cli_parse_aa,
         .range = CLI_AA_RANGE,
         .help = "refine: a frame whose camera and scene did not change since the frame before is rendered with these "
                 "samples (adaptive:4 is lanray-render's picture); path-traced, N x N of N a power of two comes in "
                 "still frames that each add as many samples as all before (1, 2, 4 ... N x N a pixel), else in "
                 "frames of 2x2, 4x4 ... N x N",
         .def = "none: every frame with --aa; in a window, a path-traced scene's 32"},
        {.name = "--still-light-samples", .kind = OPT_INT, .dst = &a->still_lights, .arg = "K", .hi = LIGHT_MAX_SAMPLES,
         .help = "with --still-aa, the still frames after the first take four times the area lights' points a "
                 "side, from the largest light's own up to K x K (lanray-render's picture with --light-samples K): "
                 "soft shadows without grain; 0 = each light's own",
         .def = "0"},
        {.name = "--compress", .kind = OPT_CHOICE, .dst = &a->compress, .choices = compress_words,
         .help = "how clients send their pixels: raw, LZ4, or zstd level 1 after a left-neighbour predictor (a "
                 "rendered 2-line segment to 0.35 and 0.20 of its bytes: docs/scaling.md); a packet that would not "
                 "shrink goes raw",
         .def = "zstd"},
        {.name = "--pipeline", .kind = OPT_CHOICE, .dst = &a->pipeline, .choices = pipeline_words,
         .help = "start the next frame as soon as the current one has no fresh work left, where its view is known "
                 "(a path, an animation, a camera that moves or stays): clients with nothing left render it rather "
                 "than wait; frames are still shown in order (docs/scaling.md)",
         .def = "on"},
        {.name = "--announce", .kind = OPT_CHOICE, .dst = &a->announce, .choices = announce_words,
         .help = "announce the server on the LAN (DNS-SD over mDNS, through avahi-daemon): _lanray._tcp, the protocol "
                 "version as a subtype, TXT proto, size, token; clients started without an address find it",
         .def = "auto: where it listens beyond loopback"},
        MOVING_LIGHTS_OPTS(a),
        {.name = "--target-fps", .kind = OPT_REAL, .dst = &a->target_fps, .arg = "F", .rlo = 0, .rhi = 1000, .seen = &a->target_given,
         .help = "while the view moves, render fewer pixels (a render scale of 1 to 8 in quarter steps, chosen from the "
                 "frame times measured) to hold F frames a second; 0 = every pixel",
         .def = "0; in a window, a path-traced scene's 10"},
        {.name = "--render-scale", .kind = OPT_REAL, .dst = &a->render_scale, .arg = "K", .rlo = 0, .rhi = 8,
         .help = "moving frames always at render scale K (1 to 8 in quarter steps: 2.5 renders 2/5 of each side) rather "
                 "than as --target-fps chooses; 0 = as it chooses", .def = "0"},
        {.name = "--upscale", .kind = OPT_CHOICE, .dst = &cfg->upscale, .choices = upscale_names,
         .help = "how a frame rendered at a render scale fills the window and the frames written: smooth (bilinear "
                 "between its pixels) or blocks (its pixels as rendered, each a block)",
         .def = "smooth"},
        {.name = "--max-fps", .kind = OPT_REAL, .dst = &a->max_fps, .arg = "F", .rlo = 0, .rhi = 1000,
         .help = "start at most F frames a second (the rest of the time the farm idles); 0 = no limit", .def = "0"},
        {.name = "--linear", .kind = OPT_FLAG, .dst = &a->linear,
         .help = "frames in linear light (PNG tagged gAMA 1.0) instead of sRGB"},
        CLI_ENVIRONMENT_OPTS(&a->env),
        {.name = "--hdr", .kind = OPT_FLAG, .dst = &a->hdr,
         .help = "high dynamic range frames: clients send RGBE, frames are written as .hdr (Radiance); the window shows "
                 "them after the scene's exposure, through --tonemap's curve"},
        DENOISE_OPTS(a),
        {.name = "--headless", .kind = OPT_FLAG, .dst = &a->headless, .help = "no window: write frames to --out"},
        {.name = "--frames", .kind = OPT_INT, .dst = &a->frames, .arg = "N", .lo = 0, .hi = 100000000,
         .help = "stop after N frames, 0 = run until stopped"},
        {.name = "--out", .kind = OPT_STRING, .dst = &a->out_dir, .arg = "DIR",
         .help = "headless: write DIR/frame-NNNNN.png, or .hdr with --hdr (DIR and its parents are created)"},
        {.name = "--discard", .kind = OPT_FLAG, .dst = &a->discard, .help = "headless, and throw frames away (benchmarks)"},
        {.name = "--verify", .kind = OPT_STRING, .dst = &a->verify_path, .arg = "REF.png",
         .help = "compare every frame with a reference; exit 3 if any pixel differs"},
        {.name = "--wait-clients", .kind = OPT_INT, .dst = &a->wait_clients, .arg = "N", .lo = 0, .hi = 4096,
         .help = "start the first frame only once N clients have joined"},
        {.name = "--warmup", .kind = OPT_INT, .dst = &a->warmup, .arg = "N", .lo = 0, .hi = 1000000,
         .help = "leave the first N frames out of the summary (the first carries the assets)"},
        {.name = "--stall-timeout", .kind = OPT_INT, .dst = &a->stall, .arg = "S", .lo = 1, .hi = 86400,
         .help = "seconds a client may hold work without a result before it is dropped"},
        {.name = "--handshake-timeout", .kind = OPT_INT, .dst = &a->handshake, .arg = "S", .lo = 1, .hi = 3600,
         .help = "seconds a new connection has to finish the handshake"},
        {.name = "--quiet", .kind = OPT_FLAG, .dst = &cfg->quiet, .help = "print errors and the listening line only"},
        {.name = "--machine-summary", .kind = OPT_FLAG, .dst = &a->machine_summary,
         .help = "end with one 'summary key=value ...' line for scripts (tools/bench/bench-scaling)"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "lanray-server", .synopsis = "[scene | model.obj | model.tmd] [options]",
                    .about = server_about, .opts = opts, .args = args, .max_args = 1, .exits = server_exits};
    int go = opt_run(&spec, argc, argv);
    a->scene_path = args[0];
    config_from_args(a);
    return go;
}
int args_apply(Scene *scene, const Args *a, const char *path, Err *err)
{
    scene->settings.denoise = a->denoise; /* as hdr, fixed: the pixels' size follows it */
    if (a->aa.given) {
        scene->settings.aa = a->aa.aa;
        scene->settings.adaptive = a->aa.adaptive;
    }
    if (a->integrator_given)
        scene->settings.integrator = (Integrator)a->integrator;
    cli_put_light_paths(&scene->settings, &a->paths);
    if (a->tonemap_given)
        scene->settings.tonemap = (Tonemap)a->tonemap;
    scene->settings.linear = a->linear;
    scene->settings.hdr = a->hdr;
    if (a->camera) /* each reading: the file's camera moved is not a move */
        scene->camera = a->cam;
    return cli_put_environment(scene, &a->env, path, err);
}

int args_smooth_for(const Args *a, const char *path) { return a->smooth && path && model_load_knows(path); }

