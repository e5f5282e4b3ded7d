/* lanray-server - holds the scene, hands out segments to clients, shows or
 * writes frames.  Its options and exit statuses are in the table in main
 * (lanray-server --help prints them; docs/tools.md has the same text).
 *
 * Without a scene it serves the built-in default scene.  With a display it
 * opens a window (keys in server/display.c); with --headless, or when there
 * is no display, it writes DIR/frame-NNNNN.png (with --hdr, .hdr: the
 * clients send RGBE pixels, and the window shows them after the scene's
 * exposure).  SIGUSR1 prints per-client statistics; they are printed at exit
 * too. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/flight.h"
#include "display.h"
#include "framewriter.h"
#include "image/image.h"
#include "model/model_load.h"
#include "base/fileio.h"
#include "base/log.h"
#include "base/opt.h"
#include "base/srgb.h"
#include "render/pixel.h"
#include "render/render.h"
#include "scene/camera_path.h"
#include "scene/scene_fields.h"
#include "scene/scene_parse.h"
#include "net/mdns.h"
#include "net/msg.h"
#include "net/net.h"
#include "net/pixcodec.h"
#include "framerate.h"
#include "pace.h"
#include "panel.h"
#include "server.h"
#include "upscale.h"
#include "watch.h"
#include "window.h"
#include "base/timer.h"

static volatile sig_atomic_t stop_flag, stats_flag;
static void on_stop(int sig) { (void)sig; stop_flag = 1; }
static void on_stats(int sig) { (void)sig; stats_flag = 1; }

/* once: a second SIGINT or SIGTERM ends the server at once (flags
 * SA_RESETHAND), where the first asks it to stop */
static void on_signal(int sig, void (*fn)(int), int once)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = fn;
    sa.sa_flags = once ? SA_RESETHAND : 0;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
}

typedef struct {
    const char *out_dir; /* NULL: frames are discarded (benchmarks) */
    Display *display;
    Server *server;
    Scene *scene;
    int width, height; /* the frames' (in a window, they follow its size) */
    int asked_w, asked_h; /* the size the scene (or the command line) asked last */
    uint8_t *view; /* settings hdr: the RGBE frame as sRGB codes for the window */
    uint32_t frames_done, frames_wanted;
    double last_title;
    const char *name; /* the scene's file name, for the title (NULL: the built-in scene) */
    const char *scene_path; /* its path (NULL: the built-in scene): --scene's, or */
    char *dropped;          /* ... a file dropped on the window since, which it points to */
    FrameRate rate;   /* the window's frame rate */
    int screenshot;
    uint8_t *shown;       /* the frame the window shows (P saves it), */
    uint32_t shown_frame; /* and its number */
    const char *progname;
    /* --verify: every frame compared with a reference image */
    const char *verify_path;
    uint8_t *verify;
    uint64_t wrong_frames, wrong_pixels;
    uint64_t write_failures;
    FrameWriter *writer;   /* headless: the frames written on a thread of their own (NULL: here) */
    /* --path: the camera flies it; the frames from the first to the one at its end */
    CameraPath path;
    uint32_t path_final;   /* the frame that shows the path's end (0: not set yet) */
    double path_t0, path_t1; /* when the first and that frame were shown */
    int refine;            /* --still-aa: still frames after the path's end, up to the converged one */
    double converged_t;    /* when it was shown, */
    uint32_t converged_frame; /* and its number */
    double still_t;        /* when the first still frame after the path's end (whole) was shown, 0: not yet */
    /* --target-fps: the render scale of the moving frames (quarter steps, upscale.h) */
    Pace pace;
    double last_frame_t;
    uint64_t scale_sum, scaled_frames;
    double longest;          /* the longest moving frame's time (a stutter), */
    uint32_t longest_frame;  /* and its number */
    int scales_before[2];    /* the last two moving frames' scales in a row (0: a still frame or none) */
    uint32_t scale_changes, scale_returns; /* a scale other than the frame before's; the one before that again */
    /* live edits: the scene file and its files watched, read again when one
     * changes; the new scene waits for the server to take it */
    Watch *watch;
    Scene *pending;
    double edit_t;         /* when the last event came (0: none waiting) */
    char edit_error[600];  /* the last read's error, shown in the title until a good read */
    Window win;            /* the window's controls and panel */
    int animate;           /* --rotate turns the instances (R toggles it) */
    double rotate, path_step, max_fps;
    MdnsAnnounce *mdns;    /* the farm announced on the LAN, or NULL */
} App;

/* Pixels of a frame that differ from the reference (--verify): a farm test
 * (tests/cli/chaos.sh, tools/bench/loadtest) checks every frame without writing it. */
static void verify_frame(App *a, uint32_t frame, const uint8_t *pixels)
{
    uint64_t wrong = 0, n = (uint64_t)a->width * a->height;
    for (uint64_t i = 0; i < n; i++)
        wrong += memcmp(pixels + 3 * i, a->verify + 3 * i, 3) != 0;
    if (wrong) {
        /* the usual cause, said once: a reference made with other settings
         * (lanray-render's default anti-aliasing is adaptive 4, a server's 1) */
        const RenderSettings *rs = &a->scene->settings;
        char aa[32];
        snprintf(aa, sizeof aa, "%s%d", rs->adaptive ? "adaptive:" : "", rs->aa);
        fprintf(stderr, "lanray-server: frame %u: %llu pixels differ from %s%s%s%s\n", frame, (unsigned long long)wrong,
                a->verify_path, a->wrong_frames ? "" : " (is it the server's picture? it renders --aa ",
                a->wrong_frames ? "" : aa,
                a->wrong_frames ? "" : ", and lanray-render adaptive:4 unless told: render the reference with the "
                                       "server's --aa and the scene's settings)");
        a->wrong_frames++;
        a->wrong_pixels += wrong;
    }
}

/* A frame's name (.hdr where the frames are high dynamic range) and what
 * its values are. */
static ImageEncoding frame_name(const App *a, const char *stem, uint32_t n, char *path, size_t size)
{
    const RenderSettings *rs = &a->scene->settings;
    snprintf(path, size, "%s-%05u.%s", stem, n, rs->hdr ? "hdr" : "png");
    return rs->hdr ? IMAGE_RGBE : rs->linear ? IMAGE_LINEAR : IMAGE_SRGB;
}

/* Writes a frame under its name, now. */
static int write_frame(const App *a, const char *stem, uint32_t n, const uint8_t *pixels, Err *err, char *path,
                       size_t size)
{
    return image_write(path, a->width, a->height, pixels, frame_name(a, stem, n, path, size), err);
}

/* `failed` frames that could not be written, the first said in err. */
static void count_write_failures(App *a, int failed, const Err *err)
{
    if (failed) {
        fprintf(stderr, "lanray-server: %s%s\n", err->msg, failed > 1 ? " (and more frames)" : "");
        a->write_failures += (uint64_t)failed;
    }
}

/* A headless frame to its file: queued for the writer's thread, or
 * written here where there is none; failures said and counted. */
static void save_frame(App *a, const uint8_t *pixels)
{
    char stem[4096], path[FRAMEWRITER_PATH];
    Err err;
    snprintf(stem, sizeof stem, "%s/frame", a->out_dir);
    int failed;
    if (a->writer)
        failed = framewriter_put(a->writer, path, pixels, frame_name(a, stem, a->frames_done, path, sizeof path), &err);
    else
        failed = write_frame(a, stem, a->frames_done, pixels, &err, path, sizeof path) != 0;
    count_write_failures(a, failed, &err);
}

/* The pace line's steadiness: how often a moving frame's scale differs
 * from the frame before's, and how often it is the one before that again
 * (the sharpness flickering). */
static void count_scale_change(App *a, int scale)
{
    const int *b = a->scales_before;
    a->scale_changes += b[1] && scale != b[1];
    a->scale_returns += b[0] && scale != b[1] && scale == b[0];
    a->scales_before[0] = b[1];
    a->scales_before[1] = scale;
}

/* --target-fps: a moving frame's time (from the frame before's end) sets
 * the next moving frame's render scale; a still frame is whole anyway. */
static void pace_frame(App *a)
{
    const double now = timer_now(), started = now - server_last_frame_time(a->server);
    double dt = a->last_frame_t > 0 ? now - a->last_frame_t : 0;
    if (a->scales_before[1] == 0 && dt > now - started) /* the first moving frame: not the wait before it */
        dt = now - started;
    a->last_frame_t = now;
    if (server_frame_still(a->server)) {
        pace_still(&a->pace, now);
        a->scales_before[0] = a->scales_before[1] = 0;
        return;
    }
    const int scale = server_frame_scale(a->server);
    count_scale_change(a, scale);
    a->scale_sum += (uint64_t)scale;
    a->scaled_frames++;
    if (dt > a->longest)
        a->longest = dt, a->longest_frame = a->frames_done;
    const int next = pace_shown(&a->pace, now, started, scale, (uint32_t)a->width, (uint32_t)a->height);
    if (a->pace.target > 0)
        server_set_scale(a->server, next);
}

/* Pixels [first, first + count) of a frame as the window shows them:
 * settings hdr's RGBE as sRGB codes of its light (in the view buffer),
 * after the exposure and through the view transform (--tonemap: the
 * frames keep the light, the window shows what an 8-bit frame would),
 * else as they are. */
static const uint8_t *window_rgb(App *a, const uint8_t *pixels, size_t first, size_t count)
{
    if (!a->view)
        return pixels;
    const double gain = pow(2.0, (double)a->scene->settings.exposure);
    const Tonemap tm = a->scene->settings.tonemap;
    uint8_t *out = a->view + first * 3;
    if (tm == TONEMAP_NONE) {
        srgb_from_rgbe(pixels, count, gain, out);
        return out;
    }
    for (size_t i = 0; i < count; i++) {
        double c[3];
        rgbe_decode(pixels + 4 * i, c);
        pixel_put_codes(out + 3 * i, v3((real)(c[0] * gain), (real)(c[1] * gain), (real)(c[2] * gain)), R(1), tm, 0);
    }
    return out;
}

/* The frame shown, kept for P: the window's picture waits for a change
 * once it converged, and a screenshot taken with the next frame (as it
 * was) saved nothing until the view moved, and then a moving frame. */
static void keep_shown(App *a, uint32_t frame, const uint8_t *pixels)
{
    const size_t bytes = (size_t)a->width * a->height * render_colour_bytes(&a->scene->settings);
    if (!a->shown && !(a->shown = malloc(bytes)))
        return; /* P says so */
    memcpy(a->shown, pixels, bytes);
    a->shown_frame = frame;
}

/* P: the frame shown, saved now (lanray-screenshot-NNNNN.png, or .hdr). */
static void save_screenshot(const App *a)
{
    char path[512];
    Err err;
    if (!a->shown)
        fprintf(stderr, "lanray-server: no frame shown yet to save\n");
    else if (write_frame(a, "lanray-screenshot", a->shown_frame, a->shown, &err, path, sizeof path))
        fprintf(stderr, "lanray-server: %s\n", err.msg);
    else
        fprintf(stderr, "lanray-server: saved %s\n", path);
}

/* The frames' size, where the window's changed it (server_set_size): the
 * window's view made again, the kept frame when next kept; -1 where there
 * is no memory for the view (the frame is not shown). */
static int follow_frame_size(App *a)
{
    int w, h;
    server_size(a->server, &w, &h);
    if (w == a->width && h == a->height)
        return 0;
    uint8_t *view = a->view ? malloc((size_t)w * h * 3) : NULL;
    if (a->view && !view)
        return -1;
    free(a->view), a->view = view;
    free(a->shown), a->shown = NULL;
    a->width = a->win.width = w;
    a->height = a->win.height = h;
    return 0;
}

static void on_frame(void *ctx, uint32_t frame, const uint8_t *pixels)
{
    App *a = ctx;
    a->frames_done++;
    framerate_add(&a->rate, timer_now());
    if (a->verify)
        verify_frame(a, frame, pixels);
    if (a->display && follow_frame_size(a) == 0) {
        display_show(a->display, window_rgb(a, pixels, 0, (size_t)a->width * a->height), a->width, a->height);
        keep_shown(a, frame, pixels);
    } else if (a->out_dir) {
        save_frame(a, pixels);
    }
    if (a->path.count && a->frames_done == 1)
        a->path_t0 = timer_now();
    pace_frame(a);
    if (a->path_final && a->frames_done == a->path_final)
        a->path_t1 = timer_now();
    if (a->path_final && a->refine && a->frames_done == a->path_final + 1)
        a->still_t = timer_now();
    /* headless, no count: the flight is the job, and with refinement the
     * still frames after it up to the converged picture */
    const int last = a->path_final && (a->refine ? a->frames_done > a->path_final && server_frame_converged(a->server)
                                                 : a->frames_done == a->path_final);
    if (last) {
        a->converged_t = a->refine ? timer_now() : 0;
        a->converged_frame = a->frames_done;
        if (!a->frames_wanted && !a->display)
            stop_flag = 1;
    }
    if (a->frames_wanted && a->frames_done >= a->frames_wanted)
        stop_flag = 1;
}

/* A still frame's segment as it comes (server_on_lines): on the window
 * over the frame before, so that a long still frame (the lamp's 144 points
 * a pixel, a path-traced view's last batches) refines where the clients
 * have been rather than all at its end. */
static void on_lines(void *ctx, uint32_t frame, uint32_t first, uint32_t count, const uint8_t *pixels)
{
    App *a = ctx;
    (void)frame;
    int w, h;
    server_size(a->server, &w, &h);
    if (!a->display || w != a->width || h != a->height) /* a new size comes with a whole frame first */
        return;
    display_lines(a->display, first, count, window_rgb(a, pixels, first, count));
}

/* --path: frame `frame`'s camera, at (frame - 1) x --path-step seconds, or
 * without a step at the time since the first frame was shown (the flight's
 * own speed, whatever the frame rate). */
static void path_next(App *app, uint32_t frame)
{
    if (!app->path.count || app->path_final)
        return;
    const double step = app->path_step;
    double t = step > 0 ? (frame - 1) * step : frame > 1 && app->path_t0 > 0 ? timer_now() - app->path_t0 : 0;
    const double end = (double)camera_path_end(&app->path);
    if (t >= end) {
        t = end;
        app->path_final = frame;
    }
    Camera c = camera_path_at(&app->path, (real)t);
    server_set_camera(app->server, &c);
}

/* Nothing on its way that would change the picture: no animation, no
 * flight, no move, turn, setting or edit pending. */
static int nothing_moves(const App *a)
{
    const int flying = a->path.count && !a->path_final;
    return !a->animate && !flying && !server_changes_pending(a->server) && !a->pending;
}

/* Whether frame `frame` is past the job: the frames asked for, or
 * headless, the flight (and its converged frame). */
static int past_the_job(const App *a, uint32_t frame)
{
    if (a->frames_wanted)
        return frame > a->frames_wanted;
    return a->path.count && a->path_final && !a->display && frame > a->path_final &&
           (!a->refine || server_newest_converged(a->server));
}

/* Pipelined frames (--pipeline): whether the next frame may start before
 * the one before it is shown, that is whether its view is known now. */
static int may_start_ahead(const App *a)
{
    if (a->max_fps > 0)
        return 0;
    if (a->path.count && a->path_step <= 0 && a->path_t0 <= 0)
        return 0; /* the flight's clock starts when its first frame is shown */
    /* a window whose newest frame is still (converged): the next waits for a change */
    return !(a->display && server_newest_converged(a->server) && nothing_moves(a));
}

/* Before each frame starts: its per-frame changes (the animation's turn,
 * the camera on its path); 0 for a frame past the job, which does not
 * start, ahead or not (a frame handed to the history's stage is not shown
 * yet, and a tiny one after it was rendered and written before the loop
 * saw the job done: history.sh's served flight of 3 frames wrote 4). */
static int next_frame(void *ctx, uint32_t frame, int ahead)
{
    App *a = ctx;
    if (past_the_job(a, frame) || (ahead && !may_start_ahead(a)))
        return 0;
    if (a->animate && frame > 1)
        server_turn_instances(a->server, (real)a->rotate);
    path_next(a, frame);
    return 1;
}

_Static_assert(CLI_MAX_SEGMENT == SERVER_MAX_SIDE, "a segment is at most the tallest frame");

/* What the command line says. */
typedef struct {
    ServerConfig cfg;
    BvhOptions bvh;
    const char *scene_path, *out_dir, *verify_path;
    int headless, force_bvh, discard, frames, wait_clients, tail, bvh_kind, width_given, height_given, smooth;
    int warmup, stall, handshake, machine_summary, linear, hdr;
    int denoise; /* --denoise, or the first scene's settings denoise: fixed for the server's life */
    int denoise_given;
    int fixed_size; /* --fixed-size: the window's frames keep their size */
    const char *camera; /* --camera, */
    Camera cam;         /* ... read once (open_scene) */
    int integrator, integrator_given, tonemap, tonemap_given;
    CliLightPaths paths;
    CliAa aa;
    double rotate;
    const char *path;
    double path_step;
    CliAa still;
    int still_lights;
    int moving_lights, moving_lights_given, moving_light_samples;
    int compress, announce, pipeline;
    double target_fps, max_fps, render_scale;
    int target_given;
    CliEnvironment env;
} Args;

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

/* Parses the command line into a: OPT_GO, or the exit status. */
static int parse_args(Args *a, int argc, char **argv)
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

/* Everything main opens, closed by app_close alone, whatever was reached. */
static void app_close(App *a)
{
    mdns_withdraw(a->mdns);
    server_destroy(a->server);
    framewriter_destroy(a->writer);
    free(a->verify);
    free(a->view);
    free(a->shown);
    display_close(a->display);
    scene_destroy(a->scene);
    scene_destroy(a->pending);
    watch_close(a->watch);
    camera_path_free(&a->path);
    free(a->dropped);
}

/* The command line's settings over a scene's own, the scene of `path` (at
 * the start, on every reading of an edited scene, for a file dropped on
 * the window); -1 where its environment cannot be put. */
static int apply_overrides(Scene *scene, const Args *a, const char *path, Err *err)
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

/* The scene, with the command line's settings over its own, and the frame
 * size: 0, or the exit status. */
static int open_scene(App *app, Args *a, Err *err)
{
    ServerConfig *cfg = &a->cfg;
    if (!cfg->quiet)
        cli_show_warnings("lanray-server");
    if (cli_open_scene(a->scene_path, &a->bvh, a->force_bvh, a->smooth, &app->scene, err)) {
        fprintf(stderr, "lanray-server: %s\n", err->msg);
        return 1;
    }
    Scene *scene = app->scene;
    if (a->camera && scene_parse_camera(a->camera, "--camera", &a->cam, err)) { /* a bad command line */
        fprintf(stderr, "lanray-server: %s\n", err->msg);
        return 2;
    }
    a->denoise = a->denoise || scene->settings.denoise;
    if (apply_overrides(scene, a, a->scene_path, err)) {
        fprintf(stderr, "lanray-server: %s\n", err->msg);
        return 1;
    }
    if (a->still_lights && !a->still.given) {
        fprintf(stderr, "lanray-server: --still-light-samples refines the still frames of --still-aa: give both\n");
        return 2;
    }
    if (a->render_scale > 0 && (a->render_scale < 1 || a->render_scale * UPSCALE_ONE != floor(a->render_scale * UPSCALE_ONE) ||
                                a->target_given)) {
        fprintf(stderr, "lanray-server: --render-scale %g: %s\n", a->render_scale,
                a->target_given ? "a fixed scale or --target-fps's, not both" : "a scale of 1 to 8 in quarter steps (2.75, 3)");
        return 2;
    }
    if (a->hdr && (a->linear || a->verify_path)) { /* (--tonemap: the window's, the frames keep the light) */
        fprintf(stderr, "lanray-server: --hdr frames keep the light itself: %s\n",
                a->linear ? "--linear is for 8-bit frames"
                          : "--verify compares 8-bit frames (compare the .hdr files instead)");
        return 2;
    }
    if (!a->width_given && scene->settings.width)
        cfg->width = scene->settings.width;
    if (!a->height_given && scene->settings.height)
        cfg->height = scene->settings.height;
    if (cfg->width > SERVER_MAX_SIDE || cfg->height > SERVER_MAX_SIDE) {
        fprintf(stderr, "lanray-server: the scene asks for %dx%d; a server frame is at most %dx%d (lanray-render renders larger ones)\n",
                cfg->width, cfg->height, SERVER_MAX_SIDE, SERVER_MAX_SIDE);
        return 1;
    }
    /* the frame being assembled, and a reference to compare with */
    const uint64_t frame_bytes = (uint64_t)cfg->width * cfg->height * render_pixel_bytes(&scene->settings);
    if (cli_check_memory(frame_bytes + (a->verify_path || a->hdr ? (uint64_t)cfg->width * cfg->height * 3 : 0), "the frame",
                         err)) {
        fprintf(stderr, "lanray-server: %dx%d: %s\n", cfg->width, cfg->height, err->msg);
        return 1;
    }
    cli_warn_scene("lanray-server", scene);
    if (a->path && camera_path_load(a->path, &app->path, err)) {
        fprintf(stderr, "lanray-server: %s\n", err->msg);
        return 1;
    }
    app->out_dir = a->discard ? NULL : a->out_dir;
    app->scene_path = a->scene_path;
    app->name = a->scene_path ? file_basename(a->scene_path) : NULL;
    app->width = app->asked_w = cfg->width;
    app->height = app->asked_h = cfg->height;
    app->frames_wanted = (uint32_t)a->frames;
    app->refine = a->still.given;
    pace_init(&app->pace, a->target_fps);
    if (a->render_scale > 0) /* no target: the pace keeps it */
        app->pace.scale = (int)(a->render_scale * UPSCALE_ONE);
    return 0;
}

/* The reference (--verify), the window or the frames' folder, and the
 * server listening: 0, or the exit status. */
static int open_outputs(App *app, Args *a, Err *err)
{
    const ServerConfig *cfg = &a->cfg;
    if (a->verify_path) {
        int vw, vh;
        if (image_read_png(a->verify_path, &vw, &vh, &app->verify, err)) {
            fprintf(stderr, "lanray-server: %s\n", err->msg);
            return 1;
        }
        if (vw != cfg->width || vh != cfg->height) {
            fprintf(stderr, "lanray-server: %s is %dx%d, the frames are %dx%d\n", a->verify_path, vw, vh, cfg->width,
                    cfg->height);
            return 1;
        }
        app->verify_path = a->verify_path;
    }
    if (!a->headless && !display_available()) {
        fprintf(stderr, "lanray-server: no display; writing frames to %s/\n", a->out_dir);
        a->headless = 1;
    }
    if (!a->headless) {
        app->display = display_open(cfg->width, cfg->height, err);
        if (!app->display) {
            fprintf(stderr, "lanray-server: cannot open a window (%s); writing frames to %s/\n", err->msg, a->out_dir);
            a->headless = 1;
        }
    }
    if (app->display && a->hdr && !(app->view = malloc((size_t)cfg->width * cfg->height * 3))) {
        fprintf(stderr, "lanray-server: out of memory for the window's %dx%d view\n", cfg->width, cfg->height);
        return 1;
    }
    app->server = server_create(cfg, app->scene, err);
    /* the frames' directory only once the server listens: a server that
     * cannot start leaves nothing behind */
    if (!app->server || (a->headless && !a->discard && cli_make_dirs(a->out_dir, err))) {
        fprintf(stderr, "lanray-server: %s\n", err->msg);
        return 1;
    }
    /* a path-traced view in a window converges once it stops, as Cycles'
     * viewport does, to 1024 samples a pixel (its still frames add up) */
    if (app->display && !a->still.given && app->scene->settings.integrator == INTEGRATOR_PATH)
        server_set_still(app->server, 1, AA_MAX, 0);
    /* ... and moves at 10 frames a second, fewer pixels while it moves (as
     * Cycles' viewport renders coarser while it is navigated) */
    if (app->display && !a->target_given && !(a->render_scale > 0) &&
        app->scene->settings.integrator == INTEGRATOR_PATH) {
        a->target_fps = 10;
        pace_init(&app->pace, a->target_fps);
    }
    /* frames written beside the loop, two queued (a frame over 64 MB is
     * written in it: two more copies would be too many) */
    const int bpp = (int)render_colour_bytes(&app->scene->settings);
    if (a->headless && !a->discard && (size_t)cfg->width * (size_t)cfg->height * (size_t)bpp <= ((size_t)64 << 20) &&
        !(app->writer = framewriter_create(cfg->width, cfg->height, bpp, 2, err)))
        fprintf(stderr, "lanray-server: frames written in the loop: %s\n", err->msg);
    if (a->scene_path && !(app->watch = watch_open(app->scene, err)))
        fprintf(stderr, "lanray-server: not following edits of %s: %s\n", a->scene_path, err->msg);
    /* the port line is what scripts wait for */
    char segtext[32];
    if (cfg->segment_lines)
        snprintf(segtext, sizeof segtext, "%u-line", cfg->segment_lines);
    else
        snprintf(segtext, sizeof segtext, "automatic");
    printf("lanray-server: listening on %s (%dx%d, %s segments)\n", server_address(app->server), cfg->width, cfg->height,
           segtext);
    if (a->announce == 1 || (a->announce == 0 && !net_is_loopback(cfg->listen_addr))) {
        /* without a daemon the farm goes on: clients take the address as given */
        app->mdns = mdns_announce(server_port(app->server), cfg->width, cfg->height, cfg->token != NULL, err);
        if (app->mdns)
            log_line(cfg->quiet, "lanray-server", "announced on the LAN as %s (protocol %u)", MDNS_TYPE, PROTO_VERSION);
        else
            fprintf(stderr, "lanray-server: not announced on the LAN: %s\n", err->msg);
    }
    fflush(stdout);
    return 0;
}

/* The window's title, twice a second: the frame rate and the clients. */
static void show_title(App *app)
{
    double now = timer_now();
    if (now - app->last_title <= 0.5)
        return;
    char title[160];
    uint32_t n = server_client_count(app->server);
    const double fps = framerate_get(&app->rate, now);
    char rate[PANEL_RATE];
    panel_rate(rate, app->frames_done > 0 && server_frame_converged(app->server), fps);
    /* the scene's name first: a user with several servers tells their windows apart */
    const char *name = app->name ? app->name : "built-in scene";
    if (app->edit_error[0])
        snprintf(title, sizeof title, "lanray - error: %.130s", app->edit_error);
    else if (n == 0) /* no rate: the last clients' falls as it waits */
        snprintf(title, sizeof title, "lanray - %.80s - waiting for clients", name);
    else
        snprintf(title, sizeof title, "lanray - %.80s - %s - %u client%s", name, rate, n, n == 1 ? "" : "s");
    display_title(app->display, title);
    window_panel(&app->win, fps, app->edit_error[0] ? app->edit_error : NULL);
    app->last_title = now;
}

/* What an edited scene asks of the frames (rs: its settings before the
 * command line's).  A new size: a window whose frames follow its size
 * takes it (the frames follow); headless, or at --fixed-size, the frames
 * stay (the frames written are one size).  Denoise,
 * which the server cannot take while it runs (the pixels' size follows
 * it).  Said, not dropped without a word. */
static void edit_frame_settings(App *app, const Args *a, const RenderSettings *rs)
{
    const int w = !a->width_given && rs->width ? rs->width : app->asked_w;
    const int h = !a->height_given && rs->height ? rs->height : app->asked_h;
    if (w != app->asked_w || h != app->asked_h) {
        app->asked_w = w, app->asked_h = h;
        if (app->display && app->win.follow) {
            display_set_size(app->display, w, h);
            log_line(a->cfg.quiet, "lanray-server", "%s asks for %dx%d frames: the window takes that size",
                     app->scene_path, w, h);
        } else {
            fprintf(stderr, "lanray-server: %s asks for %dx%d frames; they stay %dx%d until the server is started again\n",
                    app->scene_path, w, h, app->width, app->height);
        }
    }
    if (!a->denoise_given && rs->denoise != a->denoise)
        fprintf(stderr, "lanray-server: %s asks for denoise %s; the frames stay %s until the server is started again\n",
                app->scene_path, rs->denoise ? "on" : "off", a->denoise ? "denoised" : "raw");
}

/* --smooth for the scene of `path`: a model's alone (a scene file's models say it themselves). */
static int smooth_for(const Args *a, const char *path) { return a->smooth && path && model_load_knows(path); }

/* A scene that could not be read (an edit, a file dropped on the window):
 * the one shown stays, and the log and the title say why. */
static void keep_scene(App *app, const Err *err, const char *why)
{
    fprintf(stderr, "lanray-server: %s (%s)\n", err->msg, why);
    snprintf(app->edit_error, sizeof app->edit_error, "%s", err->msg);
    app->last_title = 0;
}

/* A scene read (next, rs its settings before the command line's) handed
 * to the server for the next frame, its files watched from now on. */
static void hand_over(App *app, const Args *a, Scene *next, const RenderSettings *rs)
{
    if (app->display)
        window_knobs_apply(&app->win, &next->settings);
    edit_frame_settings(app, a, rs);
    scene_destroy(app->pending);
    app->pending = next;
    server_set_scene(app->server, next);
    app->edit_error[0] = 0;
    Err err;
    Watch *w = watch_open(next, &err); /* its files from now on */
    if (w) {
        watch_close(app->watch);
        app->watch = w;
    }
}

/* The scene handed over, once the server took it: the old one is free. */
static void adopt_taken(App *app)
{
    if (app->pending && server_scene(app->server) == app->pending) {
        scene_destroy(app->scene);
        app->scene = app->pending;
        app->pending = NULL;
    }
}

/* Live edits: a scene file or one of its files changed (0.15 s ago, so
 * that an editor's writes are over): the scene is read again and handed to
 * the server for the next frame; an error keeps the last good scene on
 * screen and says why, in the log and the window's title. */
static void follow_edits(App *app, const Args *a)
{
    const double now = timer_now();
    if (watch_changed(app->watch))
        app->edit_t = now;
    if (app->edit_t == 0 || now - app->edit_t < 0.15)
        return;
    app->edit_t = 0;
    Scene *next;
    Err err;
    if (cli_open_scene(app->scene_path, &a->bvh, a->force_bvh, smooth_for(a, app->scene_path), &next, &err)) {
        keep_scene(app, &err, "the last good scene stays");
        return;
    }
    const RenderSettings asked = next->settings;
    if (apply_overrides(next, a, app->scene_path, &err)) {
        keep_scene(app, &err, "the last good scene stays");
        scene_destroy(next);
        return;
    }
    hand_over(app, a, next, &asked);
    log_line(a->cfg.quiet, "lanray-server", "%s read again", app->scene_path);
}

/* The window's still quality and frame-rate target for a dropped scene,
 * where the command line did not say them: as at the start, a
 * path-traced view converges to 1024 samples a pixel and moves at 10
 * frames a second, a Whitted view is not refined and has no target (a
 * path-traced scene dropped on a Whitted window stayed at one sample a
 * pixel, its noise never going). */
static void integrator_defaults(App *app, const Args *a, const Scene *s)
{
    const int path = s->settings.integrator == INTEGRATOR_PATH;
    if (!a->still.given)
        server_set_still(app->server, path, path ? AA_MAX : a->still.aa, path ? 0 : a->still.adaptive);
    if (!a->target_given && !(a->render_scale > 0)) {
        app->win.target_fps = path ? 10 : 0;
        pace_set_target(&app->pace, app->win.target_fps);
        server_set_scale(app->server, app->pace.scale);
    }
}

/* A file dropped on the window: a scene file or a model (previewed, as
 * given alone), read and shown in place of the scene, its camera and
 * home, its files followed from now on; one that cannot be read leaves the
 * scene shown, saying why. */
static void open_dropped(App *app, const Args *a, const char *path)
{
    Scene *next = NULL;
    Err err;
    char title[600]; /* a large model takes seconds to read and build: said meanwhile */
    snprintf(title, sizeof title, "lanray - opening %.500s ...", file_basename(path));
    display_title(app->display, title);
    char *kept = strdup(path);
    if (!kept || cli_open_scene(path, &a->bvh, a->force_bvh, smooth_for(a, path), &next, &err)) {
        if (!kept)
            err_set(&err, "%s: out of memory", path);
        keep_scene(app, &err, "the scene shown stays");
        free(kept);
        return;
    }
    const RenderSettings asked = next->settings;
    if (apply_overrides(next, a, path, &err)) {
        keep_scene(app, &err, "the scene shown stays");
        scene_destroy(next);
        free(kept);
        return;
    }
    free(app->dropped);
    app->dropped = kept;
    app->scene_path = kept;
    app->name = file_basename(kept);
    hand_over(app, a, next, &asked);
    window_new_scene(&app->win, next);
    integrator_defaults(app, a, next);
    app->last_title = 0; /* its name in the title now */
    log_line(a->cfg.quiet, "lanray-server", "%s opened", path);
}

/* Headless: one line a second at most, to see it is alive. */
static void show_status(App *app, double *since, uint32_t *frames)
{
    double now = timer_now();
    if (now - *since < 1)
        return;
    uint32_t n = server_client_count(app->server);
    if (app->frames_done != *frames || n == 0)
        fprintf(stderr, "lanray-server: %u frames, %.1f fps, %u client%s%s\n", app->frames_done,
                (app->frames_done - *frames) / (now - *since), n, n == 1 ? "" : "s", n ? "" : " (waiting for clients)");
    *since = now;
    *frames = app->frames_done;
}

/* Whether the window has nothing new to show: its last frame was a still
 * one, and no move, turn, edit or flight is on its way. */
static int idle(const App *app)
{
    return app->frames_done > 0 && server_frame_converged(app->server) && nothing_moves(app);
}

/* The event loop until the frames are done, the window closes or a signal
 * stops it: 0, or 1 when the server fails. */
static int serve(App *app, const Args *a)
{
    Err err = {{0}};
    if (app->display)
        window_init(&app->win, app->display, app->server, &app->pace, a->target_fps, app->scene, app->width,
                    app->height, !a->fixed_size && !a->verify_path);
    int wait_clients = a->wait_clients;
    uint32_t status_frames = 0;
    app->animate = a->rotate != 0;
    app->rotate = a->rotate;
    app->path_step = a->path_step;
    app->max_fps = a->max_fps;
    server_on_next(app->server, next_frame, app);
    server_on_lines(app->server, on_lines, app);
    double status_t = timer_now();
    /* --wait-clients: no frame starts before that many clients have joined */
    server_pause(app->server, wait_clients > 0);
    server_set_scale(app->server, app->pace.scale);
    while (!stop_flag) {
        if (wait_clients > 0 && server_client_count(app->server) >= (uint32_t)wait_clients) {
            server_pause(app->server, 0);
            wait_clients = 0;
        }
        /* --max-fps: the next frame waits for its time; a window whose
         * picture is still (converged, with --still-aa) waits for a change */
        if (wait_clients == 0)
            server_pause(app->server, (a->max_fps > 0 && timer_now() - app->last_frame_t < 1.0 / a->max_fps) ||
                                          (app->display && idle(app)));
        if (server_step(app->server, app->display ? 5 : 50, on_frame, app, &err)) {
            fprintf(stderr, "lanray-server: %s\n", err.msg);
            return 1;
        }
        adopt_taken(app);
        if (app->watch)
            follow_edits(app, a);
        if (app->display) {
            display_flush(app->display);
            if (window_poll(&app->win, &app->animate, &app->screenshot))
                break;
            if (app->win.dropped[0]) {
                open_dropped(app, a, app->win.dropped);
                app->win.dropped[0] = 0;
            }
            if (app->screenshot)
                save_screenshot(app);
            app->screenshot = 0;
            show_title(app);
        } else if (!a->cfg.quiet) {
            show_status(app, &status_t, &status_frames);
        }
        if (stats_flag) {
            stats_flag = 0;
            server_print_stats(app->server);
            fflush(stdout);
        }
    }
    return 0;
}

/* The statistics and the summary, and the exit status from how it ended. */
static int finish(App *app, const Args *a, int rc)
{
    Err err;
    count_write_failures(app, app->writer ? framewriter_flush(app->writer, &err) : 0, &err);
    server_print_stats(app->server);
    server_print_summary(app->server, a->machine_summary);
    if (app->path_t1 > app->path_t0 && app->path_final > 1)
        printf("path: frames 1 to %u in %.2f s, %.2f fps while moving\n", app->path_final, app->path_t1 - app->path_t0,
               (app->path_final - 1) / (app->path_t1 - app->path_t0));
    if (app->scaled_frames && app->pace.target > 0)
        printf("pace: target %.1f fps, mean render scale %.2f over %llu moving frames, the longest %.0f ms (frame %u), "
               "%u changes of scale (%u straight back)\n",
               1.0 / app->pace.target, (double)app->scale_sum / UPSCALE_ONE / (double)app->scaled_frames,
               (unsigned long long)app->scaled_frames, app->longest * 1e3, app->longest_frame, app->scale_changes,
               app->scale_returns);
    if (app->still_t > 0 && app->converged_t > 0)
        printf("path: first still frame %u, %.2f s after the last move\n", app->path_final + 1,
               app->still_t - app->path_t1);
    if (app->converged_t > 0)
        printf("path: converged frame %u, %.2f s after the last move\n", app->converged_frame,
               app->converged_t - app->path_t1);
    if (app->write_failures) {
        fprintf(stderr, "lanray-server: %llu frames could not be written\n", (unsigned long long)app->write_failures);
        rc = 1;
    }
    if (rc == 0 && a->frames && app->frames_done < (uint32_t)a->frames) {
        fprintf(stderr, "lanray-server: stopped after %u of %d frames\n", app->frames_done, a->frames);
        rc = 4;
    }
    if (app->verify) {
        printf("verify frames=%u wrong_frames=%llu wrong_pixels=%llu\n", app->frames_done,
               (unsigned long long)app->wrong_frames, (unsigned long long)app->wrong_pixels);
        if (app->wrong_frames && rc == 0)
            rc = 3;
    }
    return rc;
}

int main(int argc, char **argv)
{
    Args a;
    int rc = parse_args(&a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    App app = {0};
    Err err = {{0}};
    rc = open_scene(&app, &a, &err);
    if (rc == 0)
        rc = open_outputs(&app, &a, &err);
    if (rc == 0) {
        /* sigaction, not signal(): under _POSIX_C_SOURCE signal() resets a
         * handler after its first call, and a second SIGUSR1 killed the server */
        on_signal(SIGINT, on_stop, 1);
        on_signal(SIGTERM, on_stop, 1);
        on_signal(SIGUSR1, on_stats, 0);
        signal(SIGPIPE, SIG_IGN);
        rc = finish(&app, &a, serve(&app, &a));
    }
    app_close(&app);
    return rc;
}
