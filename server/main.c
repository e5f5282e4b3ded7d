/* lanray-server - holds the scene, hands out segments to clients, shows or writes frames.
 *
 *   lanray-server [scene] [--port P] [--listen ADDR] [--token T | --insecure]
 *                 [--width W] [--height H] [--segment LINES|auto] [--tail static|smart|adaptive]
 *                 [--bvh sbt|mst|sah] [--aa N|adaptive[:N]] [--rotate DEG]
 *                 [--headless] [--frames N] [--out DIR] [--discard] [--warmup N]
 *                 [--stall-timeout S] [--handshake-timeout S] [--quiet]
 *
 * Without a scene it serves the built-in default scene.  With a display it
 * opens a window (keys in server/display.c); with --headless, or when there
 * is no display, it writes DIR/frame-NNNNN.png (--discard: throws frames away,
 * for benchmarks; --warmup N leaves the first N frames out of the summary).  SIGUSR1 prints per-client
 * statistics; they are printed at exit too. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "display.h"
#include "image.h"
#include "scene_default.h"
#include "scene_parse.h"
#include "server.h"
#include "timer.h"

static volatile sig_atomic_t stop_flag, stats_flag;
static void on_stop(int sig) { (void)sig; stop_flag = 1; }
static void on_stats(int sig) { (void)sig; stats_flag = 1; }

typedef struct {
    const char *out_dir; /* NULL: frames are discarded (benchmarks) */
    Display *display;
    Server *server;
    Scene *scene;
    int width, height;
    uint32_t frames_done, frames_wanted;
    double last_title, fps_t0;
    uint32_t fps_frames;
    int screenshot;
    const char *progname;
    /* --verify: every frame compared with a reference image */
    const char *verify_path;
    uint8_t *verify;
    uint64_t wrong_frames, wrong_pixels;
} App;

/* Pixels of a frame that differ from the reference (--verify): a farm test
 * (tests/cli/chaos.sh, tools/loadtest) checks every frame without writing it. */
static void verify_frame(App *a, uint32_t frame, const uint8_t *pixels)
{
    uint64_t wrong = 0, n = (uint64_t)a->width * a->height;
    for (uint64_t i = 0; i < n; i++)
        wrong += memcmp(pixels + 3 * i, a->verify + 3 * i, 3) != 0;
    if (wrong) {
        a->wrong_frames++;
        a->wrong_pixels += wrong;
        fprintf(stderr, "lanray-server: frame %u: %llu pixels differ from %s\n", frame, (unsigned long long)wrong,
                a->verify_path);
    }
}

static void on_frame(void *ctx, uint32_t frame, const uint8_t *pixels)
{
    App *a = ctx;
    Err err;
    a->frames_done++;
    a->fps_frames++;
    if (a->verify)
        verify_frame(a, frame, pixels);
    if (a->display) {
        display_show(a->display, pixels);
        if (a->screenshot) {
            char path[512];
            snprintf(path, sizeof path, "lanray-screenshot-%05u.png", frame);
            if (image_write(path, a->width, a->height, pixels, &err))
                fprintf(stderr, "lanray-server: %s\n", err.msg);
            else
                fprintf(stderr, "lanray-server: saved %s\n", path);
            a->screenshot = 0;
        }
    } else if (a->out_dir) {
        char path[4096];
        snprintf(path, sizeof path, "%s/frame-%05u.png", a->out_dir, a->frames_done);
        if (image_write(path, a->width, a->height, pixels, &err))
            fprintf(stderr, "lanray-server: %s\n", err.msg);
    }
    if (a->frames_wanted && a->frames_done >= a->frames_wanted)
        stop_flag = 1;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: lanray-server [scene] [--port P] [--listen ADDR] [--token T | --insecure]\n"
               "       [--width W] [--height H] [--segment LINES|auto] [--tail static|smart|adaptive]\n"
               "       [--bvh sbt|mst|sah] [--aa N|adaptive[:N]] [--rotate DEG]\n"
               "       [--headless] [--frames N] [--out DIR] [--discard] [--warmup N] [--stall-timeout S]\n"
               "       [--handshake-timeout S] [--verify REF.png] [--quiet]\n");
}

static int parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* Camera moves and animation from the window, applied before the next frame. */
static void apply_input(App *a, const DisplayInput *in, const Camera *home, int *animate)
{
    Camera *c = &a->scene->camera;
    int changed = 0;
    if (in->reset) {
        *c = *home;
        changed = 1;
    }
    if (in->forward || in->right || in->up) {
        vec3 r, u, f;
        camera_basis(c, &r, &u, &f);
        real step = R(0.1);
        c->pos = v3_add(c->pos, v3_scale(f, (real)in->forward * step));
        c->pos = v3_add(c->pos, v3_scale(r, (real)in->right * step));
        c->pos = v3_add(c->pos, v3_scale(v3(0, 1, 0), (real)in->up * step));
        changed = 1;
    }
    if (in->yaw || in->pitch) {
        c->yaw += (real)in->yaw;
        c->pitch = real_clamp(c->pitch + (real)in->pitch, -89, 89);
        changed = 1;
    }
    if (in->zoom) {
        c->zoom *= pow(R(1.1), (real)in->zoom);
        changed = 1;
    }
    if (in->toggle_animation)
        *animate = !*animate;
    if (in->screenshot)
        a->screenshot = 1;
    if (changed)
        server_scene_changed(a->server);
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *out_dir = "frames", *verify_path = NULL;
    ServerConfig cfg = {NULL, PROTO_DEFAULT_PORT, getenv("LANRAY_TOKEN"), 0, 1024, 768, 0, sched_tail_smart, 30, 10, 0, 0};
    if (cfg.token && !*cfg.token)
        cfg.token = NULL;
    BvhOptions bvh = bvh_options_default(BVH_SAH);
    int headless = 0, force_bvh = 0, aa = -1, adaptive = 0, discard = 0;
    long wait_clients = 0;
    long frames = 0;
    double rotate = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        int bad = 0;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(a, "--headless") == 0) {
            headless = 1;
            continue;
        } else if (strcmp(a, "--discard") == 0) {
            headless = discard = 1;
            continue;
        } else if (strcmp(a, "--insecure") == 0) {
            cfg.insecure = 1;
            continue;
        } else if (strcmp(a, "--quiet") == 0) {
            cfg.quiet = 1;
            continue;
        } else if (a[0] != '-') {
            scene_path = a;
            continue;
        } else if (!v) {
            fprintf(stderr, "lanray-server: option '%s' needs a value\n", a);
            return 2;
        } else if (strcmp(a, "--port") == 0) {
            bad = parse_int(v, 0, 65535, &n);
            cfg.port = (int)n;
        } else if (strcmp(a, "--listen") == 0) {
            cfg.listen_addr = v;
        } else if (strcmp(a, "--token") == 0) {
            cfg.token = v;
        } else if (strcmp(a, "--width") == 0) {
            bad = parse_int(v, 1, 16384, &n);
            cfg.width = (int)n;
        } else if (strcmp(a, "--height") == 0) {
            bad = parse_int(v, 1, 16384, &n);
            cfg.height = (int)n;
        } else if (strcmp(a, "--segment") == 0) {
            if (strcmp(v, "auto") == 0)
                n = 0;
            else
                bad = parse_int(v, 1, 16384, &n);
            cfg.segment_lines = (uint32_t)n;
        } else if (strcmp(a, "--tail") == 0) {
            cfg.tail = sched_tail_by_name(v);
            bad = cfg.tail == NULL;
        } else if (strcmp(a, "--bvh") == 0) {
            bad = bvh_kind_parse(v, &bvh.kind);
            force_bvh = 1;
        } else if (strcmp(a, "--aa") == 0) {
            adaptive = strncmp(v, "adaptive", 8) == 0;
            bad = adaptive ? (v[8] == ':' ? parse_int(v + 9, 1, AA_MAX, &n) : (n = 4, v[8] != 0)) : parse_int(v, 1, AA_MAX, &n);
            aa = (int)n;
        } else if (strcmp(a, "--frames") == 0) {
            bad = parse_int(v, 0, 100000000, &frames);
        } else if (strcmp(a, "--out") == 0) {
            out_dir = v;
        } else if (strcmp(a, "--verify") == 0) {
            verify_path = v;
        } else if (strcmp(a, "--rotate") == 0) {
            char *end;
            rotate = strtod(v, &end);
            bad = *end != 0;
        } else if (strcmp(a, "--wait-clients") == 0) {
            bad = parse_int(v, 0, 4096, &wait_clients);
        } else if (strcmp(a, "--warmup") == 0) {
            bad = parse_int(v, 0, 1000000, &n);
            cfg.warmup = (uint32_t)n;
        } else if (strcmp(a, "--handshake-timeout") == 0) {
            bad = parse_int(v, 1, 3600, &n);
            cfg.handshake_timeout = (double)n;
        } else if (strcmp(a, "--stall-timeout") == 0) {
            bad = parse_int(v, 1, 86400, &n);
            cfg.stall_timeout = (double)n;
        } else {
            fprintf(stderr, "lanray-server: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "lanray-server: bad value '%s' for %s\n", v, a);
            return 2;
        }
        i++;
    }
    Err err;
    Scene *scene;
    if (scene_path ? scene_load(scene_path, &bvh, force_bvh, &scene, &err) : scene_default(&scene, &bvh, &err)) {
        fprintf(stderr, "lanray-server: %s\n", err.msg);
        return 1;
    }
    if (aa > 0) {
        scene->settings.aa = aa;
        scene->settings.adaptive = adaptive;
    }
    App app;
    memset(&app, 0, sizeof app);
    app.out_dir = discard ? NULL : out_dir;
    app.scene = scene;
    app.width = cfg.width;
    app.height = cfg.height;
    app.frames_wanted = (uint32_t)frames;
    if (verify_path) {
        int vw, vh;
        if (image_read_png(verify_path, &vw, &vh, &app.verify, &err)) {
            fprintf(stderr, "lanray-server: %s\n", err.msg);
            scene_destroy(scene);
            return 1;
        }
        if (vw != cfg.width || vh != cfg.height) {
            fprintf(stderr, "lanray-server: %s is %dx%d, the frames are %dx%d\n", verify_path, vw, vh, cfg.width, cfg.height);
            free(app.verify);
            scene_destroy(scene);
            return 1;
        }
        app.verify_path = verify_path;
    }
    if (!headless && !display_available()) {
        fprintf(stderr, "lanray-server: no display; writing frames to %s/\n", out_dir);
        headless = 1;
    }
    if (!headless) {
        app.display = display_open(cfg.width, cfg.height, &err);
        if (!app.display) {
            fprintf(stderr, "lanray-server: cannot open a window (%s); writing frames to %s/\n", err.msg, out_dir);
            headless = 1;
        }
    }
    if (headless && !discard && mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "lanray-server: cannot create %s: %s\n", out_dir, strerror(errno));
        scene_destroy(scene);
        return 1;
    }
    app.server = server_create(&cfg, scene, &err);
    if (!app.server) {
        fprintf(stderr, "lanray-server: %s\n", err.msg);
        display_close(app.display);
        scene_destroy(scene);
        return 1;
    }
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGUSR1, on_stats);
    signal(SIGPIPE, SIG_IGN);
    /* the port line is what scripts wait for */
    char segtext[32];
    if (cfg.segment_lines)
        snprintf(segtext, sizeof segtext, "%u-line", cfg.segment_lines);
    else
        snprintf(segtext, sizeof segtext, "automatic");
    printf("lanray-server: listening on %s:%d (%dx%d, %s segments)\n", cfg.listen_addr ? cfg.listen_addr : "127.0.0.1",
           server_port(app.server), cfg.width, cfg.height, segtext);
    fflush(stdout);
    Camera home = scene->camera;
    int animate = rotate != 0, rc = 0;
    uint32_t seen = 0;
    app.fps_t0 = timer_now();
    /* --wait-clients: no frame starts before that many clients have joined */
    server_pause(app.server, wait_clients > 0);
    while (!stop_flag) {
        if (wait_clients > 0 && server_client_count(app.server) >= (uint32_t)wait_clients) {
            server_pause(app.server, 0);
            wait_clients = 0;
        }
        if (server_step(app.server, app.display ? 5 : 50, on_frame, &app, &err)) {
            fprintf(stderr, "lanray-server: %s\n", err.msg);
            rc = 1;
            break;
        }
        if (app.frames_done != seen) {
            seen = app.frames_done;
            if (animate) {
                for (uint32_t i = 0; i < scene->instance_count; i++)
                    scene->instances[i].rotate.y += (real)rotate;
                server_scene_changed(app.server);
            }
        }
        if (app.display) {
            DisplayInput in;
            display_poll(app.display, &in);
            if (in.quit)
                break;
            apply_input(&app, &in, &home, &animate);
            double now = timer_now();
            if (now - app.last_title > 0.5) {
                char title[160];
                uint32_t n = server_client_count(app.server);
                double fps = app.fps_frames / (now - app.fps_t0);
                snprintf(title, sizeof title, "lanray - %.1f fps - %u client%s%s", fps, n, n == 1 ? "" : "s",
                         n ? "" : " (waiting for clients)");
                display_title(app.display, title);
                app.last_title = now;
                app.fps_t0 = now;
                app.fps_frames = 0;
            }
        }
        if (stats_flag) {
            stats_flag = 0;
            server_print_stats(app.server);
            fflush(stdout);
        }
    }
    server_print_stats(app.server);
    server_print_summary(app.server);
    if (app.verify) {
        printf("verify frames=%u wrong_frames=%llu wrong_pixels=%llu\n", app.frames_done,
               (unsigned long long)app.wrong_frames, (unsigned long long)app.wrong_pixels);
        if (app.wrong_frames)
            rc = 3;
        free(app.verify);
    }
    server_destroy(app.server);
    display_close(app.display);
    scene_destroy(scene);
    return rc;
}
