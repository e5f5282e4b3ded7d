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
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "app/cli.h"
#include "args.h"
#include "base/fileio.h"
#include "base/log.h"
#include "base/opt.h"
#include "base/srgb.h"
#include "base/timer.h"
#include "display.h"
#include "framewriter.h"
#include "image/image.h"
#include "livescene.h"
#include "net/mdns.h"
#include "net/msg.h"
#include "net/net.h"
#include "panel.h"
#include "render/pixel.h"
#include "render/render.h"
#include "scene/camera_path.h"
#include "scene/scene_parse.h"
#include "server.h"
#include "upscale.h"
#include "window.h"

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
    /* (a scene handed over counts once the server may take it: while its
     * assets travel to the clients, a still view stays still) */
    return !a->animate && !flying && !server_changes_pending(a->server);
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


/* Everything main opens, closed by app_close alone, whatever was reached. */
static void app_close(App *a)
{
    livescene_close(a);
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
    if (args_apply(scene, a, a->scene_path, err)) {
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
    char title[200];
    uint32_t n = server_client_count(app->server);
    const double fps = framerate_get(&app->rate, now);
    char rate[PANEL_RATE];
    panel_rate(rate, app->frames_done > 0 && server_frame_converged(app->server), fps);
    /* the scene's name first: a user with several servers tells their windows apart */
    const char *name = app->name ? app->name : "built-in scene";
    const char *opening = livescene_opening(app);
    if (opening) /* a large model takes seconds to read and build */
        snprintf(title, sizeof title, "lanray - %.80s - opening %.60s ...", name, opening);
    else if (app->edit_error[0])
        snprintf(title, sizeof title, "lanray - error: %.130s", app->edit_error);
    else if (n == 0) /* no rate: the last clients' falls as it waits */
        snprintf(title, sizeof title, "lanray - %.80s - waiting for clients", name);
    else
        snprintf(title, sizeof title, "lanray - %.80s - %s - %u client%s", name, rate, n, n == 1 ? "" : "s");
    display_title(app->display, title);
    window_panel(&app->win, fps, app->edit_error[0] ? app->edit_error : NULL);
    app->last_title = now;
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
    if (app->display) {
        window_init(&app->win, app->display, app->server, &app->pace, a->target_fps, app->scene, app->width,
                    app->height, !a->fixed_size && !a->verify_path);
        livescene_defaults(app, a, app->scene);
    }
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
        livescene_step(app, a);
        if (app->display) {
            display_flush(app->display);
            if (window_poll(&app->win, &app->animate, &app->screenshot))
                break;
            if (app->win.dropped[0]) {
                livescene_drop(app, a, app->win.dropped);
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
    int rc = args_parse(&a, argc, argv);
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
