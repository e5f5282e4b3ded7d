/* server.c - see server.h.
 *
 * Per client: handshake (SERVER_HELLO -> HELLO -> WELCOME or ERROR), then the
 * assets it lacks (a new scene's sent ahead of its frames: ahead.c), then
 * for every frame an UPDATE with two segments, and a
 * COMPUTE after every DATA so that it always holds two.  With pipelined
 * frames (ServerConfig pipeline) two frames may be in flight: the next one
 * starts when the current one has no fresh work left, the current one's
 * state moves to `older`, and the scheduler's pair top-up hands out the
 * older frame's work first; frames are shown in order.  Anything a client
 * does wrong (garbage, a lying size, pixels for a segment it was not given,
 * a failed proof) ends that client's connection with a logged reason; the
 * others keep rendering and the scheduler hands its work to them.  A
 * frame's own course (started, refined, finished, shown) is frames.c's. */
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

#include "server_impl.h"

/* The per-segment overhead that sched_auto_lines sizes segments by is
 * measured (measure.h): for a client that was kept busy, the time between
 * two of its results minus the render time it reports, plus the CPU that
 * moving a segment's packets costs: the server's own, and as much again for
 * the client's network thread, the mirror image of it (one packet in, one
 * out; measured 33 us against the server's 22 us on a 2-core VM).  That CPU
 * is taken from rendering wherever all cores are busy, which is where the
 * segment size matters, and the gap does not show it: it lands in render
 * times. */

/* The first scene's assets. */
static int make_assets(Server *s, Err *err)
{
    Asset *a;
    uint32_t n;
    if (asset_make_scene(s->scene, &a, &n, err))
        return -1;
    return (s->assets = assetset_make(a, n)) ? 0 : err_set(err, "out of memory");
}

/* The denoise stage of s's frames (filter 0: the history alone, of
 * `temporal` frames), on --denoise-threads threads or one a core. */
DenoiseStage *server_stage_make(const Server *s, int width, int height, int filter, int temporal, Err *err)
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
        s->stage = server_stage_make(s, cfg->width, cfg->height, 1, cfg->temporal, &stage_err);
        s->filters = 1;
        s->stripped = malloc((size_t)cfg->width * cfg->height * s->cbpp);
        if (s->stage && !s->stripped)
            err_set(&stage_err, "out of memory for the raw view of %dx%d frames", cfg->width, cfg->height);
    }
    const int stage_ok = !scene->settings.denoise || (s->stage && s->stripped);
    if (!s->sched || !s->pixels || !s->shown || !s->codec || !stage_ok || make_assets(s, err)) {
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
    upload_free(&c->up);
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
    assetset_drop(s->assets);
    assetset_drop(s->next_assets);
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


/* The frames a history adds up of a view of settings rs
 * (render/temporal.h temporal_history: --temporal or --whitted-temporal)
 * where its stage is there (a path-traced view's, made with the server
 * where it denoises) or can be made (a Whitted view's, made at its first
 * moving frame), else 0. */
int server_temporal_frames(const Server *s, const RenderSettings *rs)
{
    if (rs->integrator == INTEGRATOR_PATH ? !s->stage : s->history_failed)
        return 0;
    return temporal_history(rs, s->cfg.temporal, s->cfg.whitted_temporal);
}

int server_denoises(const Server *s) { return s->filters; }
int server_denoise_shown(const Server *s) { return !s->raw_view; }
int server_temporal(const Server *s) { return server_temporal_frames(s, &s->view.settings); }
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
SchedStats server_stats_all(const Server *s)
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

const char *server_address(const Server *s) { return s->address; }
void server_set_camera(Server *s, const Camera *c)
{
    s->next_camera = *c;
    s->camera_pending = 1;
}

void server_turn_instances(Server *s, real degrees) { s->turn_pending += degrees; }

Camera server_camera(const Server *s) { return s->camera_pending ? s->next_camera : s->view.camera; }

Scene *server_scene(const Server *s) { return s->scene; }

int server_changes_pending(const Server *s)
{
    return s->camera_pending || s->turn_pending != R(0) || ahead_ready(s) || s->settings_pending ||
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

/* What was held for this frame: a new description, a camera for the view,
 * a turn for the description (which then is checked and sent again). */
void server_apply_pending(Server *s)
{
    if (ahead_ready(s))
        ahead_swap(s);
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
void server_drop(Server *s, Client *c, const char *reason) { drop(s, c, reason); }

void server_send_or_drop(Server *s, Client *c, const MsgOut *m)
{
    Err e;
    if (c->closing)
        return;
    if (conn_send_msg(&c->conn, m, CONN_MAX_QUEUE, &e))
        drop(s, c, e.msg);
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
        server_send_or_drop(s, c, &out);
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
void server_send_update(Server *s, Client *c)
{
    /* a client that holds this description got its assets before it */
    const int held = c->scene_held == s->scene_id;
    if (!held)
        ahead_send_now(s, c);
    if (c->closing)
        return;
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
    server_send_or_drop(s, c, &out);
    c->frame_sent = s->frame;
    c->scene_held = s->scene_id;
    send_computes_but(s, c, seg, from, n, 1); /* the older frame's, after the UPDATE that keeps it */
}

/* Bytes in and out over every connection so far, closed ones included. */
uint64_t server_bytes(const Server *s)
{
    uint64_t bytes = s->gone_bytes;
    for (uint32_t i = 0; i < s->nclients; i++)
        bytes += s->clients[i]->conn.bytes_in + s->clients[i]->conn.bytes_out;
    return bytes;
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
    server_send_or_drop(s, c, &out);
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
    server_send_or_drop(s, c, &out);
    log_line(s->cfg.quiet, "lanray-server", "client %d (%s) joined with %u thread%s", c->id, c->addr, c->threads,
             c->threads == 1 ? "" : "s");
    if (s->in_frame) {
        sched_set_clients(s->sched, server_client_count(s));
        c->older_ok = 0; /* it never had the older frame's view */
        server_send_update(s, c);
    }
    ahead_joined(s, c);
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
    case PKT_HAVE: ahead_on_have(s, c); break;
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
        (!s->next_fn || s->next_fn(s->next_ctx, s->frame + 1, 0)) && frames_start(s, err))
        return -1;
    /* a new scene's assets paced onto the connections (ahead.c) */
    const int uploading = ahead_pump(s);
    struct pollfd pfd[MAX_CLIENTS + 1];
    pfd[0] = (struct pollfd){s->listen_fd, POLLIN, 0};
    uint32_t n = s->nclients;
    int buffered = 0; /* packets read ahead and not handled yet (the per-round bound): no wait */
    for (uint32_t i = 0; i < n; i++) {
        pfd[i + 1] = (struct pollfd){s->clients[i]->conn.fd, (short)(POLLIN | (conn_pending(&s->clients[i]->conn) ? POLLOUT : 0)), 0};
        buffered |= conn_buffered(&s->clients[i]->conn);
    }
    /* a frame being filtered: back soon to show it */
    const int wait_ms = ((s->stage && denoise_stage_holds(s->stage)) || uploading) && timeout_ms > 1 ? 1 : timeout_ms;
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
    frames_finish(s, done, ctx);
    /* the next frame as soon as this one has no fresh work left */
    if (s->cfg.pipeline && s->in_frame && !s->older.id && !s->paused && !sched_has_fresh(s->sched) &&
        server_client_count(s) > 0 && frames_start_ahead(s, err) < 0)
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
    SchedStats st = server_stats_all(s);
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
