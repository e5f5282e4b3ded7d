/* server.c - see server.h.
 *
 * Per client: handshake (SERVER_HELLO -> HELLO -> WELCOME or ERROR), then the
 * assets it lacks, then for every frame an UPDATE with two segments, and a
 * COMPUTE after every DATA so that it always holds two.  With pipelined
 * frames (ServerConfig pipeline) two frames may be in flight: the next one
 * starts when the current one has no fresh work left, the current one's
 * state moves to `older`, and the scheduler's pair top-up hands out the
 * older frame's work first; frames are shown in order.  Anything a client
 * does wrong (garbage, a lying size, pixels for a segment it was not given,
 * a failed proof) ends that client's connection with a logged reason; the
 * others keep rendering and the scheduler hands its work to them. */
#include "server.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "net/auth.h"
#include "net/conn.h"
#include "net/pixcodec.h"
#include "base/array.h"
#include "base/log.h"
#include "net/net.h"
#include "base/timer.h"
#include "net/wire.h"
#include "render/render.h"

#include "measure.h"
#include "upscale.h"
#include "denoisestage.h"

#define MAX_CLIENTS 1024

typedef enum { CLIENT_HANDSHAKE, CLIENT_ACTIVE } ClientState;

typedef struct {
    int id;
    Conn conn;
    ClientState state;
    char addr[64];
    uint8_t nonce[PROTO_NONCE];
    uint32_t threads;
    uint32_t coding; /* what its WELCOME asked for: its DATA is raw or coded so */
    double since, last_result;
    uint32_t frame_sent; /* last frame it got an UPDATE for (0: none) */
    uint32_t scene_held; /* the description it was sent last (Server.scene_id; 0: none) */
    uint8_t (*sent)[PROTO_HASH]; /* the assets it was sent, by hash (a new scene keeps what it shares) */
    uint32_t nsent, sent_cap;
    uint64_t segments, pixels, duplicates;
    uint64_t frame_pixels, last_frame_pixels; /* this frame's, and the last finished one's (the panel) */
    uint64_t busy_us;
    MeasureClient mc;       /* its results' timing, for the segment overhead */
    int older_ok;           /* it holds the older frame's view (it had that frame's UPDATE) */
    int closing;
} Client;

/* The older of two frames in flight (pipelined frames): the current
 * frame's state, moved here when the next frame started before it was
 * finished. */
typedef struct {
    uint32_t id; /* 0: one frame in flight */
    Sched *sched;
    uint8_t *pixels;
    uint32_t fw, fh;
    int scale, still, converged;
    double t0;
    RenderSettings rs; /* its view's settings (a batch: its pixels are sums) */
    uint32_t bpp;      /* its pixels' bytes */
    uint32_t cap;      /* the bytes a pixel its buffer was made for */
    Camera cam;        /* its camera, and its description's and settings' numbers */
    uint64_t epoch;
    int placed;        /* its instances' placements: Server.placed[placed] */
} Older;

/* A frame's instances as its description placed them, for its history
 * (render/temporal.h follows a turning model's pixels by their moves). */
typedef struct {
    Instance *inst;
    uint32_t count, cap;
} Placed;

struct Server {
    ServerConfig cfg;
    Scene *scene;
    int listen_fd, port;
    char address[80]; /* as net_listen shows it */
    Client *clients[MAX_CLIENTS];
    uint32_t nclients;
    int next_id;
    Sched *sched;
    uint32_t frame;   /* current frame id; 0 before the first */
    int in_frame, paused, dirty;
    View view;          /* the frame's camera and settings, apart from the description */
    uint32_t scene_id;  /* the description's number, one up each time it changes */
    /* ... one up each time it changes but by the animation's turns: the
     * histories' epoch (a turning model leaves the rest of the picture
     * where it was, and its history with it) */
    uint32_t edit_id;
    Scene *next_scene;  /* server_set_scene: the description of the frames to come */
    Camera last_camera; /* the camera of the frame before, and its description's number: */
    uint32_t last_scene_id;
    int still;          /* the current frame's are the same (refinement) */
    int still_step;     /* and how many frames they have been: 1 the first still one, 0 a moving one */
    int sharp_first;    /* the frame before the first still one was at a render scale (refine_step) */
    int converged;      /* the current frame has the still quality (or is still, without refinement) */
    int next_scale;     /* server_set_scale: the moving frames' render scale (quarter steps: upscale.h) */
    int scale;          /* the current frame's, and its size: */
    uint32_t fw, fh;
    uint8_t *shown;     /* a scaled frame scaled up to the full size, for the callback */
    uint16_t *upscale_scratch; /* upscale_smooth's, made at the first scaled frame */
    double *upscale_rgbe;      /* upscale_smooth_rgbe's, likewise */
    /* changes held for the next frame (server_set_camera, server_turn_instances) */
    Camera next_camera;
    int camera_pending;
    real turn_pending;
    RenderSettings next_settings; /* server_set_settings */
    int settings_pending;
    int still_pending; /* server_set_still: a new still quality */
    int next_width, next_height; /* server_set_size (0: none held) */
    uint32_t settings_id, last_settings_id; /* one up at each change of the view's settings */
    double frame_t0, last_frame_s; /* the current frame's start, the last finished frame's time */
    uint8_t *pixels; /* the frame, bpp bytes a pixel: RGB8, or RGBE (hdr), then with denoise its guide */
    uint32_t bpp;
    /* the current frame's settings and bytes a pixel (a path-traced still's
     * batch: its sums, render/progressive.h); the bytes a pixel the frames'
     * buffers (pixels, spare_pixels) are made for */
    RenderSettings frame_rs;
    uint32_t frame_bpp, frame_cap;
    Camera frame_cam;    /* the current frame's camera, and its description's and settings' numbers */
    uint64_t frame_epoch;
    /* the placements of the frames in flight (two at most): the current
     * frame's placed[frame_placed], the older's the other */
    Placed placed[2];
    int frame_placed;
    /* the batches of a path-traced still so far: their sums, the pixels
     * they make (bpp), and the last batch added */
    real *acc_sums;
    uint8_t *acc_px;
    int acc_batch;
    Pool *acc_pool; /* ... added on these threads (NULL: the loop's alone) */
    uint32_t cbpp;   /* bytes of a pixel's colour, as shown */
    /* settings denoise (fixed for the server's life, as bpp): each finished
     * frame is filtered on the stage's thread, and shown once filtered; or
     * a Whitted view's moving frames added up there (settings guides), the
     * stage without its filter, made at the first (history_stage) */
    DenoiseStage *stage;
    int filters;        /* the stage filters (settings denoise) */
    int history_failed; /* a Whitted view's history could not be made: none */
    int raw_view;     /* denoised frames shown raw (server_set_denoise_shown) */
    uint8_t *stripped; /* ... a frame's colours without their guides */
    Asset *assets;    /* models then textures of the scene */
    uint32_t nassets;
    Sink scene_blob;  /* the serialised description (number scene_id) */
    Sink blob;        /* the current frame's view, and behind it scene_blob once a client lacks it */
    uint32_t view_len;
    int blob_has_scene;
    /* finished clients' statistics, for the summary */
    uint64_t gone_segments, gone_pixels, gone_bytes;
    uint32_t gone_clients; /* clients that left, or were dropped */
    int auto_segment;
    Measure m; /* for the summary line and the automatic segment size */
    PixCodec *codec; /* decodes coded DATA (the loop's one thread) */
    /* pipelined frames */
    SchedConfig sched_cfg; /* what a frame's scheduler is made with */
    Older older;
    Sched *spare_sched;    /* a frame's scheduler and pixels between frames */
    uint8_t *spare_pixels;
    FrameNextFn next_fn;
    void *next_ctx;
    FrameLinesFn lines_fn; /* server_on_lines, and a batch's pixels shown before it is whole */
    void *lines_ctx;
    uint8_t *peek_px;
    int shown_still, shown_scale, shown_converged, shown_samples; /* the frame shown last */
    uint32_t frames_dropped;      /* older frames nobody left could finish */
    uint32_t frames_ahead;        /* frames started before the one before was finished */
    uint32_t frames_given_way;    /* still frames dropped for a change (a move, a setting, an edit) */
};

/* The per-segment overhead that sched_auto_lines sizes segments by is
 * measured (measure.h): for a client that was kept busy, the time between
 * two of its results minus the render time it reports, plus the CPU that
 * moving a segment's packets costs: the server's own, and as much again for
 * the client's network thread, the mirror image of it (one packet in, one
 * out; measured 33 us against the server's 22 us on a 2-core VM).  That CPU
 * is taken from rendering wherever all cores are busy, which is where the
 * segment size matters, and the gap does not show it: it lands in render
 * times. */

static int build_assets(Server *s, Err *err)
{
    for (uint32_t i = 0; i < s->nassets; i++)
        asset_free(&s->assets[i]);
    free(s->assets);
    s->nassets = s->scene->model_count + s->scene->texture_count;
    s->assets = calloc(s->nassets + 1, sizeof *s->assets);
    if (!s->assets)
        return err_set(err, "out of memory");
    for (uint32_t i = 0; i < s->scene->model_count; i++)
        if (asset_make_model(s->scene->models[i], &s->assets[i], err))
            return -1;
    for (uint32_t i = 0; i < s->scene->texture_count; i++)
        if (asset_make_texture(s->scene->textures[i], &s->assets[s->scene->model_count + i], err))
            return -1;
    return 0;
}

/* The denoise stage of s's frames (filter 0: the history alone, of
 * `temporal` frames), on --denoise-threads threads or one a core. */
static DenoiseStage *stage_make(const Server *s, int width, int height, int filter, int temporal, Err *err)
{
    const long cores = sysconf(_SC_NPROCESSORS_ONLN);
    const int threads = s->cfg.denoise_threads > 0 ? s->cfg.denoise_threads : cores > 0 ? (int)cores : 1;
    return denoise_stage_create((uint32_t)width, (uint32_t)height, s->cbpp,
                                threads < POOL_MAX_THREADS ? threads : POOL_MAX_THREADS, filter, temporal, err);
}

Server *server_create(const ServerConfig *cfg, Scene *scene, Err *err)
{
    const char *addr = cfg->listen_addr ? cfg->listen_addr : "127.0.0.1";
    if (!net_is_loopback(addr) && !cfg->token && !cfg->insecure) {
        err_set(err, "listening on %s (not loopback) needs --token (or LANRAY_TOKEN) or an explicit --insecure", addr);
        return NULL;
    }
    Server *s = calloc(1, sizeof *s);
    if (!s) {
        err_set(err, "out of memory");
        return NULL;
    }
    s->cfg = *cfg;
    s->cfg.listen_addr = addr;
    s->scene = scene;
    s->view = scene_view(scene);
    s->listen_fd = -1;
    s->next_id = 1;
    s->auto_segment = cfg->segment_lines == 0;
    s->m.warmup = cfg->warmup;
    SchedConfig sc = {(uint32_t)cfg->width, (uint32_t)cfg->height, cfg->segment_lines ? cfg->segment_lines : 1, cfg->tail,
                      (uint32_t)(cfg->width / 4 > 0 ? cfg->width / 4 : 1)};
    s->sched = sched_create(&sc);
    s->sched_cfg = sc;
    s->bpp = render_pixel_bytes(&scene->settings);
    s->cbpp = render_colour_bytes(&scene->settings);
    s->pixels = calloc((size_t)cfg->width * cfg->height, s->bpp);
    s->frame_bpp = s->frame_cap = s->bpp;
    s->shown = calloc((size_t)cfg->width * cfg->height, s->cbpp);
    s->scale = s->next_scale = s->shown_scale = UPSCALE_ONE;
    s->fw = (uint32_t)cfg->width, s->fh = (uint32_t)cfg->height;
    s->codec = pixcodec_create();
    Err stage_err = {{0}};
    if (scene->settings.denoise) {
        s->stage = stage_make(s, cfg->width, cfg->height, 1, cfg->temporal, &stage_err);
        s->filters = 1;
        s->stripped = malloc((size_t)cfg->width * cfg->height * s->cbpp);
        if (s->stage && !s->stripped)
            err_set(&stage_err, "out of memory for the raw view of %dx%d frames", cfg->width, cfg->height);
    }
    const int stage_ok = !scene->settings.denoise || (s->stage && s->stripped);
    if (!s->sched || !s->pixels || !s->shown || !s->codec || !stage_ok || build_assets(s, err)) {
        if (!stage_ok)
            *err = stage_err;
        else if (!s->sched || !s->pixels || !s->shown || !s->codec)
            err_set(err, "out of memory or invalid frame size");
        server_destroy(s);
        return NULL;
    }
    NetListener l;
    if (net_listen(addr, cfg->port, &l, err)) {
        server_destroy(s);
        return NULL;
    }
    s->listen_fd = l.fd;
    s->port = l.port;
    snprintf(s->address, sizeof s->address, "%s", l.shown);
    s->dirty = 1;
    return s;
}

static void client_free(Server *s, Client *c)
{
    s->gone_segments += c->segments;
    s->gone_clients++;
    s->gone_pixels += c->pixels;
    s->gone_bytes += c->conn.bytes_in + c->conn.bytes_out;
    conn_close(&c->conn);
    free(c->sent);
    free(c);
}

void server_destroy(Server *s)
{
    if (!s)
        return;
    for (uint32_t i = 0; i < s->nclients; i++) {
        Err e;
        MsgOut bye;
        msg_encode_bye(&bye);
        conn_send_msg(&s->clients[i]->conn, &bye, CONN_MAX_QUEUE, &e);
        conn_flush(&s->clients[i]->conn, &e);
        client_free(s, s->clients[i]);
    }
    if (s->listen_fd >= 0)
        close(s->listen_fd);
    for (uint32_t i = 0; i < s->nassets; i++)
        asset_free(&s->assets[i]);
    free(s->assets);
    sink_free(&s->blob);
    sink_free(&s->scene_blob);
    sched_destroy(s->sched);
    sched_destroy(s->older.sched);
    sched_destroy(s->spare_sched);
    pixcodec_destroy(s->codec);
    free(s->pixels);
    free(s->placed[0].inst);
    free(s->placed[1].inst);
    free(s->older.pixels);
    free(s->spare_pixels);
    free(s->acc_sums);
    free(s->acc_px);
    free(s->peek_px);
    pool_destroy(s->acc_pool);
    free(s->shown);
    denoise_stage_destroy(s->stage);
    free(s->stripped);
    free(s->upscale_scratch);
    free(s->upscale_rgbe);
    free(s);
}

int server_port(const Server *s) { return s->port; }
int server_frame_still(const Server *s) { return s->shown_still; }
int server_frame_scale(const Server *s) { return s->shown_scale; }
int server_frame_converged(const Server *s) { return s->shown_converged; }
int server_frame_samples(const Server *s) { return s->shown_samples; }

/* The coarsest render scale (quarter steps: 1.5) whose Whitted moving frames
 * are added up: at 1.5 the demo's flight came 4% closer (SSIM 0.979 ->
 * 0.980), at 2 as close as without, at 3 and 4 further. */
#define HISTORY_SCALE 6

/* The frames a history adds up of a view of settings rs
 * (render/temporal.h temporal_history: --temporal or --whitted-temporal)
 * where its stage is there (a path-traced view's, made with the server
 * where it denoises) or can be made (a Whitted view's, made at its first
 * moving frame), else 0. */
static int temporal_frames(const Server *s, const RenderSettings *rs)
{
    if (rs->integrator == INTEGRATOR_PATH ? !s->stage : s->history_failed)
        return 0;
    return temporal_history(rs, s->cfg.temporal, s->cfg.whitted_temporal);
}

int server_denoises(const Server *s) { return s->filters; }
int server_denoise_shown(const Server *s) { return !s->raw_view; }
int server_temporal(const Server *s) { return temporal_frames(s, &s->view.settings); }
void server_set_denoise_shown(Server *s, int shown)
{
    s->raw_view = s->filters && !shown;
    const RenderSettings rs = server_settings(s); /* the view again (with a change still pending), shown the new way */
    server_set_settings(s, &rs);
}
int server_newest_converged(const Server *s) { return s->converged; }

void server_on_next(Server *s, FrameNextFn next, void *ctx)
{
    s->next_fn = next;
    s->next_ctx = ctx;
}

void server_on_lines(Server *s, FrameLinesFn lines, void *ctx)
{
    s->lines_fn = lines;
    s->lines_ctx = ctx;
}

/* The scheduler statistics of every frame so far (the frames' schedulers
 * take turns where frames are pipelined). */
static SchedStats stats_all(const Server *s)
{
    SchedStats t = sched_stats(s->sched);
    const Sched *more[2] = {s->older.sched, s->spare_sched};
    for (int i = 0; i < 2; i++)
        if (more[i])
            t = sched_stats_sum(t, sched_stats(more[i]));
    return t;
}

void server_set_scale(Server *s, int scale)
{
    s->next_scale = scale < UPSCALE_ONE ? UPSCALE_ONE : scale > UPSCALE_MAX ? UPSCALE_MAX : scale;
}

/* A frame rendered at `scale`, brought up to the full size (upscale.h):
 * smooth (RGB8 or RGBE), or in blocks where asked or where the scratch
 * cannot be had. */
static const uint8_t *scaled_up(Server *s, const uint8_t *pixels, int scale)
{
    if (scale == UPSCALE_ONE)
        return pixels;
    const uint32_t w = (uint32_t)s->cfg.width, h = (uint32_t)s->cfg.height, k = (uint32_t)scale;
    const int smooth = s->cfg.upscale == UPSCALE_SMOOTH, rgbe = s->cbpp == 4;
    /* the finest scale's (1.5) scratch is the most either needs */
    if (smooth && !rgbe && !s->upscale_scratch)
        s->upscale_scratch = malloc(upscale_scratch(w, h, UPSCALE_ONE + 1) * sizeof *s->upscale_scratch);
    if (smooth && rgbe && !s->upscale_rgbe)
        s->upscale_rgbe = malloc(upscale_scratch_rgbe(w, h, UPSCALE_ONE + 1) * sizeof *s->upscale_rgbe);
    if (smooth && !rgbe && s->upscale_scratch)
        upscale_smooth(pixels, s->shown, w, h, k, s->upscale_scratch);
    else if (smooth && rgbe && s->upscale_rgbe)
        upscale_smooth_rgbe(pixels, s->shown, w, h, k, s->upscale_rgbe);
    else
        upscale_blocks(pixels, s->shown, w, h, s->cbpp, k);
    return s->shown;
}
const char *server_address(const Server *s) { return s->address; }
void server_set_camera(Server *s, const Camera *c)
{
    s->next_camera = *c;
    s->camera_pending = 1;
}

void server_turn_instances(Server *s, real degrees) { s->turn_pending += degrees; }

Camera server_camera(const Server *s) { return s->camera_pending ? s->next_camera : s->view.camera; }

void server_set_scene(Server *s, Scene *next) { s->next_scene = next; }
Scene *server_scene(const Server *s) { return s->scene; }

int server_changes_pending(const Server *s)
{
    return s->camera_pending || s->turn_pending != R(0) || s->next_scene != NULL || s->settings_pending ||
           s->still_pending || s->next_width;
}

void server_set_size(Server *s, int width, int height)
{
    width = width < 1 ? 1 : width > SERVER_MAX_SIDE ? SERVER_MAX_SIDE : width;
    height = height < 1 ? 1 : height > SERVER_MAX_SIDE ? SERVER_MAX_SIDE : height;
    const int same = width == s->cfg.width && height == s->cfg.height;
    s->next_width = same ? 0 : width;
    s->next_height = same ? 0 : height;
}

void server_size(const Server *s, int *width, int *height)
{
    *width = s->cfg.width;
    *height = s->cfg.height;
}

void server_set_settings(Server *s, const RenderSettings *rs)
{
    s->next_settings = *rs;
    s->settings_pending = 1;
}

RenderSettings server_settings(const Server *s) { return s->settings_pending ? s->next_settings : s->view.settings; }

void server_set_still(Server *s, int refine, int aa, int adaptive)
{
    s->cfg.refine = refine, s->cfg.still_aa = aa, s->cfg.still_adaptive = adaptive;
    s->still_pending = 1; /* a change: a converged view starts again, and a still frame on its way gives way */
}

void server_still(const Server *s, int *refine, int *aa, int *adaptive)
{
    *refine = s->cfg.refine, *aa = s->cfg.still_aa, *adaptive = s->cfg.still_adaptive;
}

int server_still_lights(const Server *s) { return s->cfg.still_lights; }

uint32_t server_clients_info(const Server *s, ServerClientInfo *out, uint32_t max)
{
    uint64_t total = 0;
    for (uint32_t i = 0; i < s->nclients; i++)
        total += s->clients[i]->last_frame_pixels;
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nclients && n < max; i++) {
        const Client *c = s->clients[i];
        if (c->state != CLIENT_ACTIVE || c->closing)
            continue;
        out[n] = (ServerClientInfo){.id = c->id, .threads = c->threads};
        snprintf(out[n].addr, sizeof out[n].addr, "%s", c->addr);
        out[n].share = total ? (double)c->last_frame_pixels / (double)total : 0;
        /* lines of the full frame's width a second, over the last frame */
        out[n].lines_per_s = s->last_frame_s > 0 ? (double)c->last_frame_pixels / s->fw / s->last_frame_s : 0;
        n++;
    }
    return n;
}

double server_last_frame_time(const Server *s) { return s->last_frame_s; }

void server_set_moving_lights(Server *s, int lights) { s->cfg.moving_lights = lights; }
int server_moving_light_samples(const Server *s) { return s->cfg.moving_light_samples; }
int server_moving_lights(const Server *s)
{
    return s->cfg.moving_lights >= 0 ? s->cfg.moving_lights : (int)server_settings(s).light_sampling;
}

void server_set_upscale(Server *s, int upscale) { s->cfg.upscale = upscale; }
int server_upscale(const Server *s) { return s->cfg.upscale; }

/* A new description (a reload): its assets, its camera where it moved the
 * file's, its settings. */
static int swap_scene(Server *s, Err *err)
{
    const Camera before = s->scene->camera;
    s->scene = s->next_scene;
    s->next_scene = NULL;
    if (build_assets(s, err))
        return -1;
    if (!camera_same(&before, &s->scene->camera))
        s->view.camera = s->scene->camera;
    s->view.settings = s->scene->settings;
    s->dirty = 1;
    s->edit_id++;
    return 0;
}

/* What was held for this frame: a new description, a camera for the view,
 * a turn for the description (which then is checked and sent again). */
static int apply_pending(Server *s, Err *err)
{
    if (s->next_scene && swap_scene(s, err))
        return -1;
    if (s->camera_pending) {
        s->view.camera = s->next_camera;
        s->camera_pending = 0;
    }
    if (s->settings_pending) {
        s->view.settings = s->next_settings;
        s->settings_pending = 0;
        s->settings_id++;
    }
    if (s->still_pending) { /* the next frame is not the last one refined */
        s->still_pending = 0;
        s->settings_id++;
    }
    if (s->turn_pending != R(0)) {
        for (uint32_t i = 0; i < s->scene->instance_count; i++)
            s->scene->instances[i].rotate.y += s->turn_pending;
        s->turn_pending = 0;
        s->dirty = 1;
    }
    return 0;
}
void server_pause(Server *s, int paused) { s->paused = paused; }

uint32_t server_client_count(const Server *s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nclients; i++)
        n += s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing;
    return n;
}

/* Why a connection ends: whether the client is told (an ERROR with the
 * reason) or already knows. */
typedef enum { DROP_TELL, DROP_GOODBYE } DropKind;

/* Ends a client's connection, logged with the reason. */
static void drop_as(Server *s, Client *c, DropKind kind, const char *reason)
{
    if (c->closing)
        return;
    log_line(s->cfg.quiet, "lanray-server", "client %d (%s) disconnected: %s", c->id, c->addr, reason);
    if (kind == DROP_TELL) {
        Err e;
        MsgOut m;
        msg_encode_error(&(MsgError){reason, strlen(reason)}, &m);
        conn_send_msg(&c->conn, &m, CONN_MAX_QUEUE, &e);
        conn_flush(&c->conn, &e);
    }
    c->closing = 1;
    sched_release(s->sched, c->id);
    if (s->older.id)
        sched_release(s->older.sched, c->id);
}

static void drop(Server *s, Client *c, const char *reason) { drop_as(s, c, DROP_TELL, reason); }

static void send_or_drop(Server *s, Client *c, const MsgOut *m)
{
    Err e;
    if (c->closing)
        return;
    if (conn_send_msg(&c->conn, m, CONN_MAX_QUEUE, &e))
        drop(s, c, e.msg);
}

/* Whether the client was sent the asset of that hash. */
static int client_has(const Client *c, const uint8_t *hash)
{
    for (uint32_t i = 0; i < c->nsent; i++)
        if (memcmp(c->sent[i], hash, PROTO_HASH) == 0)
            return 1;
    return 0;
}

/* The older frame's scheduler where the client can render that frame. */
static Sched *older_for(const Server *s, const Client *c) { return s->older.id && c->older_ok ? s->older.sched : NULL; }

/* The segments the client holds, of both frames in flight. */
static uint32_t held_by(const Server *s, const Client *c)
{
    const Sched *o = older_for(s, c);
    return sched_held(s->sched, c->id) + (o ? sched_held(o, c->id) : 0);
}

/* The segments the scheduler tops the client up with (over both frames
 * where two are in flight), a COMPUTE each; with `skip` those of the
 * newest frame are left out (the UPDATE carries them). */
static void send_computes_but(Server *s, Client *c, Segment *seg, Sched **from, uint32_t n, int skip)
{
    for (uint32_t k = 0; k < n && !c->closing; k++) {
        if (skip && from[k] == s->sched)
            continue;
        MsgCompute m = {from[k] == s->sched ? s->frame : s->older.id, seg[k]};
        MsgOut out;
        msg_encode_compute(&m, &out);
        send_or_drop(s, c, &out);
    }
}

static void send_computes(Server *s, Client *c)
{
    Segment seg[SCHED_IN_FLIGHT];
    Sched *from[SCHED_IN_FLIGHT];
    uint32_t n = sched_top_up_pair(older_for(s, c), s->sched, c->id, seg, from);
    send_computes_but(s, c, seg, from, n, 0);
}

/* The assets it lacks, then the scene and two segments. */
static void send_update(Server *s, Client *c)
{
    /* a client that holds this description got its assets before it */
    const int held = c->scene_held == s->scene_id;
    for (uint32_t i = 0; i < s->nassets && !held; i++)
        if (!client_has(c, s->assets[i].hash)) {
            MsgAsset a = {s->assets[i].kind, {0}, s->assets[i].data, s->assets[i].len};
            memcpy(a.hash, s->assets[i].hash, PROTO_HASH);
            MsgOut out;
            msg_encode_asset(&a, &out);
            send_or_drop(s, c, &out);
            if (!c->closing && array_reserve((void **)&c->sent, &c->sent_cap, c->nsent + 1, sizeof *c->sent, 1u << 20))
                drop(s, c, "out of memory for the assets it holds");
            else if (!c->closing)
                memcpy(c->sent[c->nsent++], s->assets[i].hash, PROTO_HASH);
            measure_asset_sent(&s->m, PROTO_HEADER + out.head_len + out.tail_len);
        }
    if (!held && !s->blob_has_scene) { /* the description behind the view: copied in a frame that needs it */
        sink_put(&s->blob, s->scene_blob.data, s->scene_blob.len);
        if (s->blob.failed) {
            s->blob.failed = 0;
            s->blob.len = s->view_len;
            drop(s, c, "out of memory for the scene's UPDATE");
            return;
        }
        s->blob_has_scene = 1;
    }
    MsgUpdate u = {.frame = s->frame, .width = s->fw, .height = s->fh, .keep = older_for(s, c) ? s->older.id : s->frame,
                   .scene_id = s->scene_id, .view_len = s->view_len, .view = s->blob.data,
                   .scene_len = held ? 0 : s->blob.len - s->view_len};
    _Static_assert(sizeof u.seg / sizeof u.seg[0] >= SCHED_IN_FLIGHT, "an UPDATE carries a client's first segments");
    Segment seg[SCHED_IN_FLIGHT];
    Sched *from[SCHED_IN_FLIGHT];
    const uint32_t n = sched_top_up_pair(older_for(s, c), s->sched, c->id, seg, from);
    for (uint32_t k = 0; k < n; k++)
        if (from[k] == s->sched)
            u.seg[u.nseg++] = seg[k];
    MsgOut out;
    msg_encode_update(&u, &out);
    send_or_drop(s, c, &out);
    c->frame_sent = s->frame;
    c->scene_held = s->scene_id;
    send_computes_but(s, c, seg, from, n, 1); /* the older frame's, after the UPDATE that keeps it */
}

/* Bytes in and out over every connection so far, closed ones included. */
static uint64_t server_bytes(const Server *s)
{
    uint64_t bytes = s->gone_bytes;
    for (uint32_t i = 0; i < s->nclients; i++)
        bytes += s->clients[i]->conn.bytes_in + s->clients[i]->conn.bytes_out;
    return bytes;
}

/* The side of the largest pattern of points of the scene's area lights in
 * a view of settings rs (0: no area light). */
static int largest_light_side(const Scene *scene, const RenderSettings *rs)
{
    int side = 0;
    for (uint32_t i = 0; i < scene->light_count; i++)
        if (light_is_area(&scene->lights[i])) {
            const int own = rs->light_samples ? rs->light_samples : scene->lights[i].samples;
            side = own > side ? own : side;
        }
    return side;
}

/* Progressive refinement: the samples of still frame k (1 the first).  A
 * path-traced view sharpens while it is looked at: where the still
 * quality is N x N of N a power of two (`batches`, 2 log2 N + 1 of them,
 * where the server has room for their sums), each still frame renders the
 * next batch of the N x N samples alone, doubling what the picture has,
 * and the server adds them up (the converged frame costs what rendering it
 * alone does); otherwise each doubles the samples a side, 2, 4, 8 ... up
 * to the still quality, rendered whole (4/3 of the converged frame's
 * cost).  The Whitted integrator's takes the still quality at once (after
 * moving frames at a render scale, one frame of the view's own samples
 * first, sharp_first), and then, with still_lights, multiplies its area
 * lights' points a side by four each frame from the largest light's own up
 * to still_lights (its soft shadows'
 * grain: a round lamp of 3 x 3 points leaves penumbrae of ten grey levels
 * and noise; docs/realtime.md).  Whether frame k has the still quality
 * (the converged picture, which is lanray-render's with --aa still_aa and,
 * with still_lights, --light-samples still_lights). */
static int refine_step(const ServerConfig *c, const Scene *scene, int k, RenderSettings *rs, int batches,
                       int sharp_first)
{
    if (batches > 0) { /* the batches of N x N, added up (render/progressive.h) */
        rs->aa = c->still_aa;
        rs->adaptive = 0;
        rs->batch = k <= batches ? k : 0;
        return k >= batches;
    }
    /* after moving frames at a render scale, a Whitted view's first still
     * frame is the view's own samples, whole: a sharp picture in a third
     * of the still quality's time (the demo's 1024x768, 2 cores: 0.4 s
     * against 1.1 s), where the window would have shown the last moving
     * frame's blur until then */
    if (sharp_first && rs->integrator == INTEGRATOR_WHITTED &&
        (rs->aa != c->still_aa || rs->adaptive != c->still_adaptive)) {
        if (k == 1)
            return 0;
        k--;
    }
    const int side = k < 8 ? 2 << (k - 1) : AA_MAX;
    if (rs->integrator == INTEGRATOR_PATH && side < c->still_aa) {
        rs->aa = side;
        rs->adaptive = 0;
        return 0;
    }
    rs->aa = c->still_aa;
    rs->adaptive = c->still_adaptive;
    const int own = largest_light_side(scene, rs);
    if (rs->integrator == INTEGRATOR_PATH || c->still_lights == 0 || own == 0) /* no points to add */
        return 1;
    if (k == 1)
        return 0;
    /* own x 4^(k - 1), stopped at still_lights (k may grow without end):
     * sixteen times the points a frame, so that the frames before the
     * converged one cost a fifteenth of it, not a third as doubling a side
     * did (the demo's lamp, 3 x 3 to 12 x 12 at once: converged a fifth
     * sooner), while in a window the last frame shows as it comes */
    int lights = own;
    for (int j = 1; j < k && lights < c->still_lights; j++)
        lights *= 4;
    rs->light_samples = lights < c->still_lights ? lights : c->still_lights;
    return rs->light_samples == c->still_lights;
}

/* Whether a frame of settings rs samples adaptively (anti-aliasing, or
 * area lights probed first), so that each segment samples its neighbour
 * lines' centres too. */
static int adaptive_frame(const RenderSettings *rs)
{
    return (rs->adaptive && rs->aa > 1) || rs->light_sampling == LIGHTS_ADAPTIVE;
}

/* The current frame's buffer (free: its frame has not started) made for
 * need bytes a pixel; 0 where there is no memory for it. */
static int frame_room(Server *s, uint32_t need)
{
    if (s->frame_cap >= need)
        return 1;
    uint8_t *p = realloc(s->pixels, (size_t)s->cfg.width * s->cfg.height * need);
    if (!p)
        return 0;
    s->pixels = p;
    s->frame_cap = need;
    free(s->spare_pixels); /* made smaller: made again when wanted */
    s->spare_pixels = NULL;
    return 1;
}

/* The batches a still frame of the view's settings at the still quality
 * would take (render/progressive.h), with the frames' buffers grown to
 * hold their sums and the sums' own made; 0 where its samples do not go
 * in batches, the frame is too large, or there is no memory for them
 * (each still frame is then rendered whole). */
static int still_batches(Server *s)
{
    RenderSettings rs = s->view.settings;
    rs.aa = s->cfg.still_aa, rs.adaptive = s->cfg.still_adaptive, rs.batch = 1;
    const int batches = progressive_batches(&rs);
    const size_t n = (size_t)s->cfg.width * s->cfg.height;
    const uint32_t need = render_pixel_bytes(&rs);
    /* a frame whose sums would not fit one DATA packet is rendered whole
     * (12 bytes a pixel, 48 denoised: 4K UHD fits, and denoised 1920x1080) */
    if (!batches || (uint64_t)n * need > PROTO_MAX_PIXELS)
        return 0;
    if (!s->acc_sums) {
        s->acc_sums = calloc(n, progressive_reals(&rs) * sizeof(real));
        s->acc_px = malloc(n * s->bpp);
        if (!s->acc_sums || !s->acc_px) {
            free(s->acc_sums), free(s->acc_px);
            s->acc_sums = NULL, s->acc_px = NULL;
            return 0;
        }
        /* a 1024x768 frame's batch took the loop 17 ms alone (39 with
         * guides): its pixels are added on up to 8 threads (without them, on
         * the loop's) */
        const long cores = sysconf(_SC_NPROCESSORS_ONLN);
        if (!s->acc_pool) /* kept through a change of size */
            s->acc_pool = cores > 1 ? pool_create(cores < 8 ? (int)cores : 8, NULL) : NULL;
    }
    return frame_room(s, need) ? batches : 0;
}

/* A Whitted view's history (server_temporal): the stage that adds its
 * moving frames up, without a filter, made at the first of them (a
 * server that never moves has none: about 150 bytes a pixel), and the room
 * for its guided pixels; 0 where there is no memory for them (logged
 * once: the frames then go without). */
static int history_stage(Server *s)
{
    if (s->stage)
        return frame_room(s, s->cbpp + DENOISE_GUIDE_BYTES);
    Err err = {{0}};
    s->stage = stage_make(s, s->cfg.width, s->cfg.height, 0, s->cfg.whitted_temporal, &err);
    if (s->stage && !frame_room(s, s->cbpp + DENOISE_GUIDE_BYTES))
        err_set(&err, "out of memory for %dx%d guided pixels", s->cfg.width, s->cfg.height);
    if (s->stage && !err.msg[0])
        return 1;
    log_line(s->cfg.quiet, "lanray-server", "moving frames without their history: %s", err.msg);
    denoise_stage_destroy(s->stage);
    s->stage = NULL;
    s->history_failed = 1;
    return 0;
}

/* server_set_size, taken where no frame is in flight nor in the stage
 * (server_step waits for that): the frames' buffers made again at the new
 * size (those made when wanted, freed), the stage's filter and history
 * too; the view starts again (the next frame is not a still one).  Where
 * there is no memory for them the size stays, said in the log. */
static void apply_size(Server *s)
{
    const int w = s->next_width, h = s->next_height;
    s->next_width = s->next_height = 0;
    const size_t n = (size_t)w * h;
    uint8_t *px = malloc(n * s->frame_cap), *shown = malloc(n * s->cbpp);
    uint8_t *stripped = s->stripped ? malloc(n * s->cbpp) : NULL;
    Err err = {{0}};
    DenoiseStage *stage = s->filters ? stage_make(s, w, h, 1, s->cfg.temporal, &err) : NULL;
    if (!px || !shown || (s->stripped && !stripped) || (s->filters && !stage)) {
        free(px), free(shown), free(stripped);
        denoise_stage_destroy(stage);
        log_line(s->cfg.quiet, "lanray-server", "%dx%d frames: %s; they stay %dx%d", w, h,
                 err.msg[0] ? err.msg : "out of memory", s->cfg.width, s->cfg.height);
        return;
    }
    free(s->pixels), free(s->shown), free(s->stripped);
    s->pixels = px, s->shown = shown, s->stripped = stripped;
    denoise_stage_destroy(s->stage); /* a Whitted view's history: made again at its next moving frame */
    s->stage = stage;
    uint8_t **made_later[] = {&s->spare_pixels, &s->peek_px, &s->acc_px};
    for (size_t i = 0; i < sizeof made_later / sizeof *made_later; i++)
        free(*made_later[i]), *made_later[i] = NULL;
    free(s->acc_sums), s->acc_sums = NULL, s->acc_batch = 0;
    free(s->upscale_scratch), s->upscale_scratch = NULL;
    free(s->upscale_rgbe), s->upscale_rgbe = NULL;
    sched_destroy(s->spare_sched), s->spare_sched = NULL;
    s->cfg.width = w, s->cfg.height = h;
    s->sched_cfg.width = (uint32_t)w, s->sched_cfg.height = (uint32_t)h;
    s->sched_cfg.min_pixels = (uint32_t)(w / 4 > 0 ? w / 4 : 1);
    s->settings_id++;
}

static int start_frame(Server *s, Err *err)
{
    if (s->next_width)
        apply_size(s);
    if (apply_pending(s, err))
        return -1;
    if (s->dirty) { /* a new description: checked, encoded once, numbered */
        s->scene_blob.len = 0;
        if (scene_check(s->scene, err) ||
            wire_encode_scene(s->scene, s->assets, s->assets + s->scene->model_count, &s->scene_blob, err))
            return -1;
        s->scene_id++;
        s->dirty = 0;
    }
    /* still: nothing moved since the frame before, which the view then refines */
    s->still = s->frame > 0 && s->scene_id == s->last_scene_id && s->settings_id == s->last_settings_id &&
               camera_same(&s->view.camera, &s->last_camera);
    s->last_camera = s->view.camera;
    s->last_scene_id = s->scene_id;
    s->last_settings_id = s->settings_id;
    s->frame_t0 = timer_now();
    s->still_step = s->still ? s->still_step + 1 : 0;
    if (s->still_step == 1)
        s->sharp_first = s->scale > UPSCALE_ONE; /* the frame before's scale */
    View v = s->view;
    const int batches = s->still && s->cfg.refine ? still_batches(s) : 0;
    s->converged = s->still && (!s->cfg.refine ||
                                refine_step(&s->cfg, s->scene, s->still_step, &v.settings, batches, s->sharp_first));
    if (!s->still && s->cfg.moving_lights >= 0)
        v.settings.light_sampling = (LightSampling)s->cfg.moving_lights;
    if (!s->still && s->cfg.moving_light_samples > 0)
        v.settings.light_samples = s->cfg.moving_light_samples;
    /* a path-traced moving frame whose history adds it up: another of its
     * pixels' samples each (the frame to come is s->frame + 1); a Whitted
     * one near the full size carries its guides there (at render scales 2
     * to 4 its history blurred more than it smoothed: the demo's flight
     * 1-2% further from the full-quality frames, and slower) */
    if (!s->still && temporal_frames(s, &v.settings)) {
        if (v.settings.integrator == INTEGRATOR_PATH)
            v.settings.jitter = progressive_jitter(&v.settings, s->frame + 1);
        else if (s->next_scale <= HISTORY_SCALE)
            v.settings.guides = history_stage(s);
    }
    s->frame_cam = v.camera;
    s->frame_epoch = (uint64_t)s->edit_id << 32 | s->settings_id;
    s->frame_placed = s->older.id ? 1 - s->older.placed : 0;
    Placed *p = &s->placed[s->frame_placed]; /* none where memory ran out: the history follows no instance */
    p->count = instances_copy(&p->inst, &p->cap, s->scene->instances, s->scene->instance_count);
    s->frame_rs = v.settings;
    s->frame_bpp = render_pixel_bytes(&v.settings);
    /* a moving frame at the render scale, a still one whole */
    const uint32_t last_lines = s->fh;
    s->scale = s->still ? UPSCALE_ONE : s->next_scale;
    s->fw = upscale_side((uint32_t)s->cfg.width, (uint32_t)s->scale);
    s->fh = upscale_side((uint32_t)s->cfg.height, (uint32_t)s->scale);
    sched_set_size(s->sched, s->fw, s->fh);
    s->blob.len = 0;
    if (wire_encode_view(&v, &s->blob, err))
        return -1;
    s->view_len = (uint32_t)s->blob.len;
    s->blob_has_scene = 0;
    s->frame++;
    s->in_frame = 1;
    uint32_t n = server_client_count(s);
    double work;
    const SchedStats st = stats_all(s);
    double o = measure_frame_start(&s->m, timer_now(), n, server_bytes(s), st.duplicate_pixels, st.segments,
                                   s->auto_segment, &work);
    /* a segment of an adaptive frame renders the centre samples of the
     * lines just above and below it again (render.c, the key lines): up to
     * two lines of the last frame's work more a segment, which the measured
     * gaps do not show (they land in render times) */
    if (adaptive_frame(&v.settings) && last_lines > 0)
        o += 2.0 * work / last_lines;
    sched_start_frame(s->sched, s->frame, n, s->auto_segment, work, o);
    for (uint32_t i = 0; i < s->nclients; i++)
        if (s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing)
            send_update(s, s->clients[i]);
    return 0;
}

/* The next frame, started while the current one still has segments out:
 * the current one's state moves to `older` (its scheduler and pixels stay
 * live until it is shown), the new one takes the spare ones.  0 where it
 * does not start (no memory for a second frame, or the application holds
 * it back), 1 where it did, -1 on an error. */
static int start_ahead(Server *s, Err *err)
{
    if (s->next_width) /* a new size: after the frames in flight */
        return 0;
    if (!s->spare_sched && !(s->spare_sched = sched_create(&s->sched_cfg)))
        return 0;
    if (!s->spare_pixels && !(s->spare_pixels = calloc((size_t)s->cfg.width * s->cfg.height, s->frame_cap)))
        return 0;
    if (s->next_fn && !s->next_fn(s->next_ctx, s->frame + 1, 1))
        return 0;
    s->older = (Older){s->frame,    s->sched,    s->pixels,    s->fw,        s->fh,        s->scale,
                       s->still,    s->converged, s->frame_t0, s->frame_rs, s->frame_bpp, s->frame_cap,
                       s->frame_cam, s->frame_epoch, s->frame_placed};
    sched_set_segment_lines(s->spare_sched, sched_config(s->sched)->segment_lines);
    s->sched = s->spare_sched;
    s->pixels = s->spare_pixels;
    s->spare_sched = NULL;
    s->spare_pixels = NULL;
    for (uint32_t i = 0; i < s->nclients; i++)
        s->clients[i]->older_ok = s->clients[i]->frame_sent == s->older.id;
    s->frames_ahead++;
    return start_frame(s, err) ? -1 : 1;
}

int server_adopt(Server *s, int fd, const char *addr)
{
    if (s->nclients >= MAX_CLIENTS) {
        close(fd);
        log_line(s->cfg.quiet, "lanray-server", "refused a connection from %s: too many clients", addr);
        return -1;
    }
    Client *c = calloc(1, sizeof *c);
    if (!c) {
        free(c);
        close(fd);
        log_line(s->cfg.quiet, "lanray-server", "refused a connection from %s: out of memory", addr);
        return -1;
    }
    conn_init(&c->conn, fd);
    c->id = s->next_id++;
    c->state = CLIENT_HANDSHAKE;
    c->since = timer_now();
    snprintf(c->addr, sizeof c->addr, "%s", addr);
    auth_random(c->nonce, sizeof c->nonce);
    MsgServerHello h = {PROTO_MAGIC, PROTO_VERSION, PROTO_BOM, s->cfg.token ? HELLO_TOKEN_REQUIRED : 0, {0}};
    memcpy(h.nonce, c->nonce, PROTO_NONCE);
    s->clients[s->nclients++] = c;
    MsgOut out;
    msg_encode_server_hello(&h, &out);
    send_or_drop(s, c, &out);
    return 0;
}

static void accept_clients(Server *s)
{
    for (;;) {
        char addr[64];
        int fd = net_accept(s->listen_fd, addr, sizeof addr);
        if (fd < 0)
            return;
        server_adopt(s, fd, addr);
    }
}

static void on_hello(Server *s, Client *c)
{
    MsgHello h;
    Err e;
    if (msg_decode_hello(c->conn.body, c->conn.body_size, &h, &e)) {
        drop(s, c, e.msg);
        return;
    }
    char why[256];
    if (h.magic != PROTO_MAGIC) {
        drop(s, c, "handshake: not a lanray client (bad magic)");
        return;
    }
    if (h.bom != PROTO_BOM) {
        drop(s, c, "handshake: byte order differs from the server's");
        return;
    }
    if (h.version != PROTO_VERSION) {
        snprintf(why, sizeof why, "handshake: protocol version %u, the server speaks version %u", h.version,
                 PROTO_VERSION);
        drop(s, c, why);
        return;
    }
    if (h.real_size != sizeof(real)) {
        snprintf(why, sizeof why, "handshake: client computes with %u-byte reals, the server with %zu (build both with the same PRECISION)",
                 h.real_size, sizeof(real));
        drop(s, c, why);
        return;
    }
    if (h.threads < 1 || h.threads > 4096) {
        drop(s, c, "handshake: implausible thread count");
        return;
    }
    if (s->cfg.token && !auth_proof_ok(s->cfg.token, c->nonce, h.nonce, h.proof)) {
        drop(s, c, "handshake: authentication failed (wrong or missing token)");
        return;
    }
    c->threads = h.threads;
    c->state = CLIENT_ACTIVE;
    c->last_result = timer_now();
    const uint32_t codec = s->cfg.coding & ~(uint32_t)PIX_PREDICT;
    c->coding = codec < 32 && (h.codecs >> codec & 1) ? s->cfg.coding : PIX_RAW;
    MsgOut out;
    msg_encode_welcome(&(MsgWelcome){.id = (uint32_t)c->id, .coding = c->coding}, &out);
    send_or_drop(s, c, &out);
    log_line(s->cfg.quiet, "lanray-server", "client %d (%s) joined with %u thread%s", c->id, c->addr, c->threads,
             c->threads == 1 ? "" : "s");
    if (s->in_frame) {
        sched_set_clients(s->sched, server_client_count(s));
        c->older_ok = 0; /* it never had the older frame's view */
        send_update(s, c);
    }
}

/* A segment of frame `old ? older : current` just written at px, to the
 * application as it comes (server_on_lines) where the frame is the next to
 * be shown, a still one, whole, and shown as its pixels say: not through
 * the stage (a filter, a history), nor after a frame the stage holds.  A
 * path-traced still's batch shows with the batches before it (peeked: its
 * sums are added when it is finished, in order, as lanray-render adds
 * them), unless it is one the finished frame would not show (a batch after
 * a lost one). */
static void show_lines(Server *s, int old, Segment seg, const uint8_t *px)
{
    const int still = old ? s->older.still : s->still, scale = old ? s->older.scale : s->scale;
    const RenderSettings *rs = old ? &s->older.rs : &s->frame_rs;
    const uint32_t frame = old ? s->older.id : s->frame, bpp = old ? s->older.bpp : s->frame_bpp;
    if (!s->lines_fn || (!old && s->older.id) || !still || scale != UPSCALE_ONE || render_guided(rs) ||
        (s->stage && denoise_stage_holds(s->stage)))
        return;
    if (rs->batch) {
        if ((rs->batch != 1 && rs->batch != s->acc_batch + 1) || !s->acc_sums)
            return;
        if (!s->peek_px && !(s->peek_px = malloc((size_t)s->cfg.width * s->cfg.height * s->cbpp)))
            return; /* shown when whole */
        const uint32_t reals = progressive_reals(rs);
        progressive_frame_peek(rs, rs->batch == 1 ? NULL : s->acc_sums + (size_t)seg.first * reals, px, seg.count,
                               s->peek_px);
        px = s->peek_px;
    } else if (bpp != s->cbpp) {
        return;
    }
    s->lines_fn(s->lines_ctx, frame, seg.first, seg.count, px);
}

static void on_data(Server *s, Client *c)
{
    MsgData d;
    Err e;
    /* its pixels' size is its frame's: the older of two in flight, the
     * current one, or one no longer held (not read) */
    uint32_t id = 0, bpp = 0;
    if (c->conn.body_size >= sizeof id)
        memcpy(&id, c->conn.body, sizeof id);
    if (id && id == s->older.id)
        bpp = s->older.bpp;
    else if (id == s->frame)
        bpp = s->frame_bpp;
    if (msg_decode_data(c->conn.body, c->conn.body_size, bpp, &d, &e)) {
        drop(s, c, e.msg);
        return;
    }
    Segment seg = d.seg;
    const uint32_t frame = d.frame, render_us = d.render_us;
    char why[PROTO_MAX_ERROR_TEXT];
    if (d.coding != PIX_RAW && d.coding != c->coding) {
        snprintf(why, sizeof why, "DATA packet coded %#x; it was asked for %#x or raw", d.coding, c->coding);
        drop(s, c, why);
        return;
    }
    double now = timer_now();
    c->last_result = now;
    /* the older of two frames in flight, or the current one */
    const int old = s->older.id && frame == s->older.id;
    Sched *sc = old ? s->older.sched : s->sched;
    uint8_t *const frame_px = old ? s->older.pixels : s->pixels;
    measure_data(&s->m, &c->mc, now, frame, old ? frame : s->frame, render_us, held_by(s, c));
    SchedResult r = sched_check(sc, c->id, frame, seg);
    if (r == SCHED_UNKNOWN) {
        snprintf(why, sizeof why, "pixels for segment %u+%u of frame %u, which it was not given", seg.first, seg.count, frame);
        drop(s, c, why);
        return;
    }
    /* straight into the frame, only where they are taken: a packet that
     * does not decode to exactly its segment drops its client, and its
     * segment goes to another, which writes it whole */
    if (r == SCHED_ACCEPT) {
        uint8_t *dst = frame_px + (size_t)seg.first * bpp;
        if (d.coding == PIX_RAW)
            memcpy(dst, d.pixels, (size_t)seg.count * bpp);
        else if (pixcodec_decode(s->codec, d.coding, d.pixels, d.len, dst, (size_t)seg.count * bpp, bpp, &e)) {
            snprintf(why, sizeof why, "DATA packet for segment %u+%u of frame %u: %.200s", seg.first, seg.count, frame,
                     e.msg);
            drop(s, c, why);
            return;
        }
        show_lines(s, old, seg, dst);
    }
    r = sched_complete(sc, c->id, frame, seg);
    measure_result(&s->m, render_us, r != SCHED_STALE, r == SCHED_ACCEPT);
    if (r != SCHED_STALE) /* time spent rendering counts whether or not this copy won */
        c->busy_us += render_us;
    if (r == SCHED_ACCEPT) {
        c->segments++;
        c->pixels += seg.count;
        c->frame_pixels += seg.count;
    } else if (r == SCHED_DUPLICATE) {
        c->duplicates += seg.count;
    }
    if (r != SCHED_STALE && s->in_frame) /* the others are topped up in housekeeping */
        send_computes(s, c);
}

static void on_packet(Server *s, Client *c)
{
    uint32_t t = c->conn.type;
    if (c->state == CLIENT_HANDSHAKE) {
        if (t == PKT_HELLO)
            on_hello(s, c);
        else {
            char why[96];
            snprintf(why, sizeof why, "handshake: expected HELLO, got %s", msg_type_name(t));
            drop(s, c, why);
        }
        return;
    }
    switch (t) {
    case PKT_DATA: on_data(s, c); break;
    case PKT_BYE: drop_as(s, c, DROP_GOODBYE, "said goodbye"); break;
    case PKT_ERROR: {
        char text[PROTO_MAX_ERROR_TEXT + 1];
        Err e;
        if (msg_decode_error(c->conn.body, c->conn.body_size, text, &e)) {
            drop(s, c, e.msg);
            break;
        }
        char why[PROTO_MAX_ERROR_TEXT + 32];
        snprintf(why, sizeof why, "client reported: %s", text);
        drop(s, c, why);
        break;
    }
    default: {
        char why[96];
        snprintf(why, sizeof why, "unexpected %s packet from a client", msg_type_name(t));
        drop(s, c, why);
    }
    }
}

static void housekeeping(Server *s)
{
    double now = timer_now();
    for (uint32_t i = 0; i < s->nclients; i++) {
        Client *c = s->clients[i];
        if (c->closing)
            continue;
        if (c->state == CLIENT_HANDSHAKE && now - c->since > s->cfg.handshake_timeout)
            drop(s, c, "handshake not completed in time");
        else if (c->state == CLIENT_ACTIVE && held_by(s, c) && now - c->last_result > s->cfg.stall_timeout)
            drop(s, c, "stalled: no result in time");
    }
    /* every client topped up (the scheduler's policy): segments released by
     * a client that left, or still outstanding at the end of a frame, go to
     * the idle ones */
    for (uint32_t i = 0; s->in_frame && i < s->nclients; i++) {
        Client *c = s->clients[i];
        if (c->state == CLIENT_ACTIVE && !c->closing && c->frame_sent == s->frame)
            send_computes(s, c);
    }
    /* remove closed clients */
    for (uint32_t i = 0; i < s->nclients;) {
        if (s->clients[i]->closing) {
            client_free(s, s->clients[i]);
            s->clients[i] = s->clients[--s->nclients];
        } else {
            i++;
        }
    }
}

/* A range of a batch frame's pixels added to the sums before it and
 * encoded (progressive_frame_add), for pool_for. */
typedef struct {
    const RenderSettings *rs;
    real *acc;
    const uint8_t *sums;
    uint8_t *out;
    uint32_t bpp;
} BatchAdd;

static void batch_add_range(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const BatchAdd *b = ctx;
    const uint32_t reals = progressive_reals(b->rs);
    progressive_frame_add(b->rs, b->acc + lo * reals, b->sums + lo * reals * sizeof(real), (size_t)(hi - lo),
                          b->out + lo * b->bpp);
}

/* The samples a pixel of a frame of settings rs shows: a batch's, all
 * those so far (render/progressive.h); a whole frame's, N x N (adaptive:
 * at most). */
static int frame_samples(const RenderSettings *rs)
{
    return rs->batch ? (int)progressive_end(rs->batch) : rs->aa * rs->aa;
}

/* What a frame's showing needs, and its history's adding up. */
static StageFrame stage_frame(const Server *s, uint32_t id, int scale, int still, int converged, double t0,
                              const RenderSettings *rs, const Camera *cam, uint64_t epoch, int placed)
{
    const int temporal = rs->integrator == INTEGRATOR_PATH ? temporal_frames(s, rs) > 0 : rs->guides;
    const Placed *p = &s->placed[placed];
    return (StageFrame){id, scale, still, converged, t0, frame_samples(rs), temporal, *cam, epoch, p->inst, p->count};
}

/* A finished frame to the application: the panel's and the pace's
 * figures first, then the callback. */
static void show_frame(Server *s, const StageFrame *f, const uint8_t *pixels, FrameDoneFn done, void *ctx)
{
    const double now = timer_now();
    measure_frame_end(&s->m, now);
    measure_latency(&s->m, now - f->t0);
    s->last_frame_s = now - f->t0;
    for (uint32_t i = 0; i < s->nclients; i++) {
        s->clients[i]->last_frame_pixels = s->clients[i]->frame_pixels;
        s->clients[i]->frame_pixels = 0;
    }
    s->shown_still = f->still;
    s->shown_converged = f->converged;
    s->shown_scale = f->scale;
    s->shown_samples = f->samples;
    if (done)
        done(ctx, f->id, scaled_up(s, pixels, f->scale));
}

/* The frame the denoise stage filtered, shown (wait: once it is); 1 where
 * one was. */
static int show_filtered(Server *s, int wait, FrameDoneFn done, void *ctx)
{
    const uint8_t *colours;
    StageFrame f;
    if (!s->stage || !denoise_stage_take(s->stage, wait, &colours, &f))
        return 0;
    show_frame(s, &f, colours, done, ctx);
    return 1;
}

/* A finished frame: shown, or with settings denoise handed to the stage to
 * be filtered at its render scale (then brought up) and shown once it is,
 * or with settings guides to be added to its history (the frame before
 * first: frames are shown in order). */
static void frame_finished(Server *s, const StageFrame *f, const uint8_t *pixels, const RenderSettings *rs,
                           FrameDoneFn done, void *ctx)
{
    if (rs->batch) { /* a batch of a still's samples: added to the ones before, their picture shown */
        if (rs->batch != 1 && rs->batch != s->acc_batch + 1) {
            /* the batch before was lost (a frame dropped when the clients
             * that had it left): the still frames start again from batch 1 */
            log_line(s->cfg.quiet, "lanray-server", "frame %u: batch %d of the still's samples after batch %d: not shown",
                     f->id, rs->batch, s->acc_batch);
            s->still_step = 0;
            s->converged = 0;
            return;
        }
        const size_t n = (size_t)s->cfg.width * s->cfg.height;
        if (rs->batch == 1)
            memset(s->acc_sums, 0, n * progressive_reals(rs) * sizeof(real));
        s->acc_batch = rs->batch;
        BatchAdd b = {rs, s->acc_sums, pixels, s->acc_px, s->bpp};
        pool_for(s->acc_pool, n, 8192, batch_add_range, &b);
        pixels = s->acc_px;
    }
    if (s->stage && denoise_stage_holds(s->stage)) /* the frame before first */
        show_filtered(s, 1, done, ctx);
    if (!s->stage || !render_guided(rs)) { /* no guides: nothing for the stage */
        show_frame(s, f, pixels, done, ctx);
        return;
    }
    const uint32_t fw = upscale_side((uint32_t)s->cfg.width, (uint32_t)f->scale),
                   fh = upscale_side((uint32_t)s->cfg.height, (uint32_t)f->scale);
    if (s->raw_view) { /* the colours alone, unfiltered */
        for (size_t i = 0; i < (size_t)fw * fh; i++)
            memcpy(s->stripped + i * s->cbpp, pixels + i * s->bpp, s->cbpp);
        show_frame(s, f, s->stripped, done, ctx);
        return;
    }
    denoise_stage_put(s->stage, pixels, fw, fh, s->view.settings.linear, f);
}

/* Frames shown in order: the older of two in flight first.  An older frame
 * with work left that no client still connected can render (all that held
 * its view left) is dropped, not waited for. */
static void finish_frames(Server *s, FrameDoneFn done, void *ctx)
{
    show_filtered(s, 0, done, ctx);
    if (s->older.id) {
        Older *o = &s->older;
        int stranded = !sched_frame_done(o->sched) && sched_has_fresh(o->sched);
        for (uint32_t i = 0; stranded && i < s->nclients; i++)
            stranded = !(s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing && s->clients[i]->older_ok);
        if (!sched_frame_done(o->sched) && !stranded)
            return;
        if (stranded) {
            s->frames_dropped++;
            log_line(s->cfg.quiet, "lanray-server", "frame %u dropped: the clients that had its view left", o->id);
        } else {
            const StageFrame f =
                stage_frame(s, o->id, o->scale, o->still, o->converged, o->t0, &o->rs, &o->cam, o->epoch, o->placed);
            frame_finished(s, &f, o->pixels, &o->rs, done, ctx);
        }
        s->spare_sched = o->sched;
        if (o->cap == s->frame_cap) { /* else made before the buffers grew */
            s->spare_pixels = o->pixels;
        } else {
            free(o->pixels);
            s->spare_pixels = NULL;
        }
        *o = (Older){0};
    }
    if (s->in_frame && sched_frame_done(s->sched)) {
        s->in_frame = 0;
        const StageFrame f = stage_frame(s, s->frame, s->scale, s->still, s->converged, s->frame_t0, &s->frame_rs,
                                         &s->frame_cam, s->frame_epoch, s->frame_placed);
        frame_finished(s, &f, s->pixels, &s->frame_rs, done, ctx);
    }
}

int server_step(Server *s, int timeout_ms, FrameDoneFn done, void *ctx, Err *err)
{
    /* a still frame gives way to a change (a move, a setting, an edit): a
     * refining one may take many seconds (--still-light-samples) and would
     * show a view the user has left; dropped, the results of its segments
     * come back stale, and the next frame starts now */
    if (s->in_frame && s->still && !s->older.id && server_changes_pending(s)) {
        s->in_frame = 0;
        s->frames_given_way++;
        log_line(s->cfg.quiet, "lanray-server", "frame %u gave way to a change", s->frame);
    }
    /* a new size waits for the frame in the stage (shown at the old one) */
    const int size_waits = s->next_width && s->stage && denoise_stage_holds(s->stage);
    if (!s->in_frame && !s->paused && !size_waits && server_client_count(s) > 0 &&
        (!s->next_fn || s->next_fn(s->next_ctx, s->frame + 1, 0)) && start_frame(s, err))
        return -1;
    struct pollfd pfd[MAX_CLIENTS + 1];
    pfd[0] = (struct pollfd){s->listen_fd, POLLIN, 0};
    uint32_t n = s->nclients;
    int buffered = 0; /* packets read ahead and not handled yet (the per-round bound): no wait */
    for (uint32_t i = 0; i < n; i++) {
        pfd[i + 1] = (struct pollfd){s->clients[i]->conn.fd, (short)(POLLIN | (conn_pending(&s->clients[i]->conn) ? POLLOUT : 0)), 0};
        buffered |= conn_buffered(&s->clients[i]->conn);
    }
    /* a frame being filtered: back soon to show it */
    const int wait_ms = s->stage && denoise_stage_holds(s->stage) && timeout_ms > 1 ? 1 : timeout_ms;
    int r = poll(pfd, n + 1, buffered ? 0 : wait_ms);
    if (r < 0 && errno != EINTR)
        return err_set(err, "poll failed: %s", strerror(errno));
    if (buffered) {
        for (uint32_t i = 0; i < n; i++)
            if (conn_buffered(&s->clients[i]->conn))
                pfd[i + 1].revents |= POLLIN;
        r = r > 0 ? r + 1 : 1;
    }
    if (r > 0 && (pfd[0].revents & POLLIN))
        accept_clients(s);
    /* the CPU of reading, handling and answering packets (not of waiting in
     * poll, nor of starting frames): per DATA packet, for the automatic size */
    double cpu0 = timer_thread_cpu();
    for (uint32_t i = 0; r > 0 && i < n; i++) {
        Client *c = s->clients[i];
        if (c->closing || !pfd[i + 1].revents)
            continue;
        Err e;
        if (pfd[i + 1].revents & (POLLIN | POLLHUP | POLLERR)) {
            /* a bounded number of packets per client per round: fairness */
            for (int k = 0; k < 64 && !c->closing; k++) {
                int got = conn_read(&c->conn, &e);
                if (got < 0) {
                    drop(s, c, e.msg);
                    break;
                }
                if (got == 0)
                    break;
                on_packet(s, c);
            }
        }
        if (!c->closing && conn_pending(&c->conn) && conn_flush(&c->conn, &e) < 0)
            drop(s, c, e.msg);
    }
    housekeeping(s);
    measure_cpu(&s->m, timer_thread_cpu() - cpu0);
    finish_frames(s, done, ctx);
    /* the next frame as soon as this one has no fresh work left */
    if (s->cfg.pipeline && s->in_frame && !s->older.id && !s->paused && !sched_has_fresh(s->sched) &&
        server_client_count(s) > 0 && start_ahead(s, err) < 0)
        return -1;
    return 0;
}

uint32_t server_segment_lines(const Server *s) { return sched_config(s->sched)->segment_lines; }

void server_print_summary(const Server *s, int machine)
{
    const Measure *m = &s->m;
    uint64_t bytes = server_bytes(s);
    uint32_t frames = m->frames_done > s->cfg.warmup ? m->frames_done - s->cfg.warmup : 0;
    double wall = frames ? m->last_frame_end - m->first_frame_start : 0;
    double busy = (double)m->total_busy_us * 1e-6;
    uint32_t n = m->clients_seen_max;
    SchedStats st = stats_all(s);
    double fr = frames ? frames : 1;
    double dup = (double)(st.duplicate_pixels - m->dup_base) / s->cfg.width / fr;
    double per_frame = (double)(bytes - m->measured_bytes_base - m->asset_bytes) / fr;
    double segs = (double)(st.segments - m->seg_base) / fr;
    /* the most clients at once; where some left, how many stayed to the end */
    char who[96] = "";
    if (s->gone_clients)
        snprintf(who, sizeof who, ", %u at the end, %u gone", s->nclients, s->gone_clients);
    printf("%u frames%s in %.3f s: %.2f fps with %s%u client%s%s (busy %.0f%% of their time)\n", frames,
           s->cfg.warmup ? " after the warm-up" : "", wall, wall > 0 ? frames / wall : 0.0, s->gone_clients ? "up to " : "",
           n, n == 1 ? "" : "s", who, wall > 0 && n ? 100 * busy / (n * wall) : 0.0);
    printf("a frame: %.1f segments of %u lines, %.1f lines rendered twice, %.2f MB on the network\n", segs,
           server_segment_lines(s), dup, per_frame / 1e6);
    if (s->frames_ahead || s->frames_dropped)
        printf("pipelined: %u frames started before the one before was finished%s\n", s->frames_ahead,
               s->frames_dropped ? "; some dropped (their clients left)" : "");
    if (m->latency_frames)
        printf("a frame shown %.1f ms after it started, on average\n", 1e3 * m->latency_sum / m->latency_frames);
    if (!machine)
        return;
    printf("summary frames=%u wall_s=%.4f fps=%.3f clients=%u busy_s=%.4f efficiency=%.4f idle_s=%.4f "
           "dup_lines_per_frame=%.2f bytes_per_frame=%.0f segments_per_frame=%.1f segment_lines=%u overhead_us=%.0f packet_cpu_us=%.1f "
           "turnaround_us=%.0f ahead=%u dropped=%u latency_ms=%.1f\n",
           frames, wall, wall > 0 ? frames / wall : 0.0, n, busy, wall > 0 && n ? busy / (n * wall) : 0.0, n * wall - busy,
           dup, per_frame, segs, server_segment_lines(s), m->overhead_us,
           m->measured_packets ? m->measured_cpu * 1e6 / (double)m->measured_packets : 0.0,
           m->turn_samples ? m->turn_sum_us / (double)m->turn_samples : 0.0, s->frames_ahead, s->frames_dropped,
           m->latency_frames ? 1e3 * m->latency_sum / m->latency_frames : 0.0);
}

void server_print_stats(const Server *s)
{
    printf("frames started %u; %u client%s connected\n", s->frame, s->nclients, s->nclients == 1 ? "" : "s");
    if (s->nclients)
        printf("  %-6s %-24s %7s %9s %9s %9s %11s %11s\n", "client", "address", "threads", "segments", "lines/s",
               "dup px", "bytes in", "bytes out");
    for (uint32_t i = 0; i < s->nclients; i++) {
        const Client *c = s->clients[i];
        double t = timer_now() - c->since;
        printf("  %-6d %-24s %7u %9llu %9.1f %9llu %11llu %11llu\n", c->id, c->addr, c->threads,
               (unsigned long long)c->segments, t > 0 ? (double)c->pixels / s->cfg.width / t : 0.0,
               (unsigned long long)c->duplicates, (unsigned long long)c->conn.bytes_in,
               (unsigned long long)c->conn.bytes_out);
    }
    if (s->gone_segments || s->gone_bytes)
        printf("  clients gone: %llu segments, %llu pixels, %llu bytes\n", (unsigned long long)s->gone_segments,
               (unsigned long long)s->gone_pixels, (unsigned long long)s->gone_bytes);
}
