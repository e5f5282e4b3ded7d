/* client.c - see client.h.
 *
 * Three threads: the network thread (the caller's) owns the socket, decodes
 * UPDATEs and queues segments; the assets' thread (assetload.c) decodes
 * the models and textures sent, a HAVE sent for each as it is done; the
 * render thread renders the segments one at a time
 * with render_span and hands finished pixels back through a pipe that wakes
 * the network thread.  An UPDATE for a newer frame drops the queued segments
 * of frames older than the one it says to keep, and cancels the one being
 * rendered if it is one of them: normally every older frame, but a server
 * that starts a frame before the one before it is finished (pipelined
 * frames) keeps that one, and its segments are rendered first. */
#include "client.h"

#include <errno.h>
#include <math.h>
#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "assetload.h"
#include "net/auth.h"
#include "net/conn.h"
#include "render/render.h"
#include "base/log.h"
#include "net/net.h"
#include "net/pixcodec.h"
#include "base/timer.h"
#include "net/wire.h"

#define MAX_JOBS 64

/* A description the server sent (its number: MsgUpdate.scene_id), shared
 * by the frames that use it. */
typedef struct {
    Scene *scene;
    uint32_t id;
    atomic_int refs; /* the network thread takes, either thread drops */
} Desc;

/* A frame: its description and the world seen with the frame's view.  The
 * render thread's jobs hold references, so a new frame never changes what
 * an old segment renders.  (The counts change under Worker.mu.) */
typedef struct {
    Desc *desc;
    World *world;
    uint32_t frame;
    int width, height;
    int refs;
} SceneRef;

typedef struct {
    uint32_t frame;
    Segment seg;
    SceneRef *ref;
    uint8_t *pixels; /* set when done: as coded */
    size_t len;      /* their bytes */
    uint32_t coding; /* PIX_RAW or the session's coding */
    uint32_t render_us;
    uint32_t bpp; /* the pixels' size, set when done (ref is gone by then) */
} Job;

typedef struct {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    Job queue[MAX_JOBS];
    int nqueue;
    Job done[MAX_JOBS * 2];
    int ndone;
    uint32_t keep_from, running_frame; /* the oldest frame wanted (UPDATE keep), the one being rendered */
    int running, quit;
    atomic_int cancel;
    int wake[2];
    RenderPool *pool;
    PixCodec *codec;  /* the render thread's: it codes each segment it finished */
    uint32_t coding;  /* what the server asked for (WELCOME), set before any job */
    uint64_t segments, pixels;
    uint64_t scenes; /* descriptions decoded (the network thread's) */
    AssetLoad *load; /* the assets sent, decoded on a thread of their own (it wakes the network thread too) */
} Worker;

static void desc_drop(Desc *d)
{
    if (d && atomic_fetch_sub(&d->refs, 1) == 1) {
        scene_destroy(d->scene);
        free(d);
    }
}

static void ref_drop(SceneRef *r)
{
    if (r && --r->refs == 0) {
        world_destroy(r->world);
        desc_drop(r->desc);
        free(r);
    }
}

static uint32_t ref_bpp(const SceneRef *r) { return render_pixel_bytes(&r->world->view.settings); }

/* The description an UPDATE brings, or the one it names that the client
 * holds (cur's), with one more reference. */
static Desc *update_desc(const MsgUpdate *u, const AssetCache *cache, const SceneRef *cur, Err *err)
{
    if (u->scene_len == 0) {
        if (!cur || cur->desc->id != u->scene_id) {
            err_set(err, "UPDATE for scene %u without it (this client holds %u)", u->scene_id, cur ? cur->desc->id : 0);
            return NULL;
        }
        atomic_fetch_add(&cur->desc->refs, 1);
        return cur->desc;
    }
    Desc *d = calloc(1, sizeof *d);
    if (!d) {
        err_set(err, "out of memory");
        return NULL;
    }
    if (wire_decode_scene(u->scene, u->scene_len, cache, &d->scene, err)) {
        free(d);
        return NULL;
    }
    d->id = u->scene_id;
    atomic_init(&d->refs, 1);
    return d;
}

/* The frame of an UPDATE: its description (new, or the one held) and its
 * world: a new description's built with the previous frame's world (its
 * tree where the boxes are the same), the held one's shared with the new
 * view (no check, no build). */
static SceneRef *update_ref(const MsgUpdate *u, const AssetCache *cache, const SceneRef *cur, Err *err)
{
    View view;
    if (wire_decode_view(u->view, u->view_len, &view, err))
        return NULL;
    Desc *d = update_desc(u, cache, cur, err);
    if (!d)
        return NULL;
    World *world = NULL;
    if (d == (cur ? cur->desc : NULL)) {
        world = world_with_view(cur->world, &view, err);
    } else if ((world = world_build(d->scene, cur ? cur->world : NULL, err)) && world_set_view(world, &view, err)) {
        world_destroy(world);
        world = NULL;
    }
    SceneRef *ref = world ? calloc(1, sizeof *ref) : NULL;
    if (!ref) {
        if (world)
            err_set(err, "out of memory");
        world_destroy(world);
        desc_drop(d);
        return NULL;
    }
    *ref = (SceneRef){d, world, u->frame, (int)u->width, (int)u->height, 1};
    return ref;
}

/* The render time a DATA reports is the segment's render, plus, when the
 * thread went straight on from its previous segment, the time between the
 * two that it spent waiting for a core rather than running (wall time less
 * its own CPU time).  The server takes "gap between two results less render
 * time" as the per-segment overhead; when clients share cores, the handing
 * back of a result wakes the network thread, the render thread loses its
 * turn, and its wait (a slice of other clients' rendering, not lost time)
 * would otherwise read as milliseconds of overhead. */
static void *render_thread(void *arg)
{
    Worker *w = arg;
    double last_end = 0, last_end_cpu = 0;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        int straight = last_end > 0 && w->nqueue > 0;
        while (!w->quit && w->nqueue == 0)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->quit)
            break;
        Job j = w->queue[0];
        memmove(w->queue, w->queue + 1, (size_t)--w->nqueue * sizeof *w->queue);
        if (j.frame < w->keep_from) {
            ref_drop(j.ref);
            continue;
        }
        w->running = 1;
        w->running_frame = j.frame;
        atomic_store(&w->cancel, 0);
        pthread_mutex_unlock(&w->mu);
        uint8_t *px = malloc((size_t)j.seg.count * ref_bpp(j.ref));
        Err err;
        double t0 = timer_now(), waited = 0;
        if (straight)
            waited = fmax((t0 - last_end) - (timer_thread_cpu() - last_end_cpu), 0.0);
        int rc = px ? render_span(w->pool, j.ref->world, j.ref->width, j.ref->height, j.seg.first, j.seg.count, px,
                                  NULL, &w->cancel, &err)
                    : -1;
        last_end = timer_now();
        last_end_cpu = timer_thread_cpu();
        double us = (last_end - t0 + waited) * 1e6;
        /* coded here, beside the network thread: the server asked for it */
        size_t len = (size_t)j.seg.count * ref_bpp(j.ref);
        uint32_t coding = PIX_RAW;
        if (rc == 0 && w->coding != PIX_RAW) {
            uint8_t *coded = malloc(pixcodec_bound(len));
            size_t got;
            int used = coded ? pixcodec_encode(w->codec, w->coding, px, len, ref_bpp(j.ref), coded, &got, &err) : -1;
            if (used > PIX_RAW) {
                free(px);
                px = coded, len = got, coding = (uint32_t)used;
            } else {
                free(coded); /* no gain, or no memory: sent raw */
            }
        }
        pthread_mutex_lock(&w->mu);
        w->running = 0;
        if (rc == 0 && j.frame >= w->keep_from && w->ndone < MAX_JOBS * 2) {
            j.pixels = px;
            j.len = len;
            j.coding = coding;
            j.bpp = ref_bpp(j.ref);
            j.render_us = us < 4e9 ? (uint32_t)us : UINT32_MAX;
            w->done[w->ndone++] = j;
            w->segments++;
            w->pixels += j.seg.count;
            char b = 1;
            if (write(w->wake[1], &b, 1) < 0) { /* the pipe is full: the network thread is awake anyway */
            }
        } else {
            free(px);
        }
        ref_drop(j.ref);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* Waits for one packet (handshake only), up to `seconds`. */
static int read_packet(Conn *c, double seconds, Err *err)
{
    double end = timer_now() + seconds;
    for (;;) {
        int r = conn_read(c, err);
        if (r != 0)
            return r;
        double left = end - timer_now();
        if (left <= 0)
            return err_set(err, "server did not answer in time");
        struct pollfd p = {c->fd, POLLIN, 0};
        poll(&p, 1, (int)(left * 1000) + 1);
    }
}

/* How a session ended: after the handshake, refused by the server, or
 * before the handshake got through (no connection, no answer). */
enum { SESSION_ENDED = 0, SESSION_REFUSED = -1, SESSION_FAILED = -2 };

/* Waits for one handshake packet of the given type: 1 when it came, else
 * SESSION_REFUSED (the server sent an ERROR) or SESSION_ENDED. */
static int expect(Conn *c, uint32_t type, Err *err)
{
    if (read_packet(c, 10, err) < 0)
        return SESSION_FAILED;
    if (c->type == PKT_ERROR) {
        char text[PROTO_MAX_ERROR_TEXT + 1];
        if (msg_decode_error(c->body, c->body_size, text, err))
            return SESSION_FAILED;
        err_set(err, "server refused the connection: %s", text);
        return SESSION_REFUSED;
    }
    if (c->type != type) {
        err_set(err, "server sent %s instead of %s", msg_type_name(c->type), msg_type_name(type));
        return SESSION_FAILED;
    }
    return 1;
}

static int handshake(const ClientConfig *cfg, Conn *c, uint32_t *coding, Err *err)
{
    int got = expect(c, PKT_SERVER_HELLO, err);
    if (got != 1)
        return got;
    MsgServerHello sh;
    if (msg_decode_server_hello(c->body, c->body_size, &sh, err))
        return SESSION_FAILED;
    if (sh.magic != PROTO_MAGIC) {
        err_set(err, "not a lanray server (bad magic)");
        return SESSION_REFUSED;
    }
    if (sh.bom != PROTO_BOM) {
        err_set(err, "server has the other byte order");
        return SESSION_REFUSED;
    }
    if (sh.version != PROTO_VERSION) {
        err_set(err, "server speaks protocol version %u, this client %u", sh.version, PROTO_VERSION);
        return SESSION_REFUSED;
    }
    if ((sh.flags & HELLO_TOKEN_REQUIRED) && !cfg->token)
        log_line(cfg->quiet, "lanray-client", "server requires a token; none given (--token or LANRAY_TOKEN)");
    MsgHello h = {.magic = PROTO_MAGIC, .version = PROTO_VERSION, .bom = PROTO_BOM, .threads = (uint32_t)cfg->threads,
                  .real_size = (uint32_t)sizeof(real), .codecs = PIX_CODEC_MASK};
    auth_random(h.nonce, PROTO_NONCE);
    auth_proof(cfg->token ? cfg->token : "", sh.nonce, h.nonce, h.proof);
    MsgOut out;
    msg_encode_hello(&h, &out);
    if (conn_send_msg(c, &out, CONN_MAX_QUEUE, err) || conn_flush(c, err) < 0)
        return SESSION_FAILED;
    got = expect(c, PKT_WELCOME, err);
    if (got != 1)
        return got;
    MsgWelcome wm;
    if (msg_decode_welcome(c->body, c->body_size, &wm, err))
        return SESSION_FAILED;
    if (!pixcodec_known(wm.coding)) {
        err_set(err, "server asked for pixel coding %#x, which this client does not have", wm.coding);
        return SESSION_REFUSED;
    }
    *coding = wm.coding;
    return 1;
}

static void queue_job(Worker *w, uint32_t frame, Segment seg, SceneRef *ref)
{
    if (w->nqueue == MAX_JOBS)
        return; /* the server never gives more than a few: a misbehaving server */
    ref->refs++;
    w->queue[w->nqueue++] = (Job){.frame = frame, .seg = seg, .ref = ref};
    pthread_cond_signal(&w->cv);
}

/* A segment the server asks for must lie in the frame, and its pixels must
 * fit in a DATA packet (the server would refuse a bigger one). */
static int segment_ok(Segment seg, const SceneRef *ref, const char *packet, Err *err)
{
    uint64_t width = (uint64_t)ref->width, height = (uint64_t)ref->height;
    if ((uint64_t)seg.first + seg.count > width * height)
        return err_set(err, "%s segment %u+%u outside the %llux%llu frame", packet, seg.first, seg.count,
                       (unsigned long long)width, (unsigned long long)height);
    if (msg_min_size(PKT_DATA) + ref_bpp(ref) * (uint64_t)seg.count > msg_max_size(PKT_DATA))
        return err_set(err, "%s segment of %u pixels is larger than a DATA packet can carry", packet, seg.count);
    return 0;
}

static void send_have(void *ctx, const uint8_t *hash)
{
    Conn *c = ctx;
    MsgHave h;
    memcpy(h.hash, hash, PROTO_HASH);
    MsgOut out;
    msg_encode_have(&h, &out);
    Err e;
    conn_send_msg(c, &out, CONN_MAX_QUEUE, &e); /* a connection that fails says so at its next send or read */
}

/* The assets decoded so far into the cache, a HAVE for each. */
static int assets_taken(Worker *w, Conn *c, AssetCache *cache, Err *err)
{
    return assetload_take(w->load, cache, send_have, c, err);
}

/* Handles one packet from the server; returns -1 to end the session.  cur
 * is the newest frame, prev the one before it where the server keeps it
 * (NULL otherwise). */
static int on_packet(const ClientConfig *cfg, Worker *w, Conn *c, AssetCache *cache, SceneRef **cur, SceneRef **prev,
                     Err *err)
{
    switch (c->type) {
    case PKT_ASSET: {
        MsgAsset a;
        return msg_decode_asset(c->body, c->body_size, &a, err) || assetload_slice(w->load, &a, err) ? -1 : 0;
    }
    case PKT_UPDATE: {
        MsgUpdate u;
        if (msg_decode_update(c->body, c->body_size, &u, err))
            return -1;
        uint32_t frame = u.frame, width = u.width, height = u.height, nseg = u.nseg, keep = u.keep;
        if (width < 1 || height < 1 || width > RENDER_MAX_SIDE || height > RENDER_MAX_SIDE)
            return err_set(err, "malformed UPDATE");
        if (keep > frame || (*cur && frame <= (*cur)->frame))
            return err_set(err, "UPDATE for frame %u keeping frames from %u (after frame %u)", frame, keep,
                           *cur ? (*cur)->frame : 0);
        /* a new description names assets sent before it: all of them in
         * the cache first (most were taken in while the frames before
         * rendered: server/ahead.c) */
        if (u.scene_len > 0) {
            assetload_wait(w->load);
            if (assets_taken(w, c, cache, err))
                return -1;
        }
        SceneRef *ref = update_ref(&u, cache, *cur, err);
        if (!ref)
            return -1;
        w->scenes += u.scene_len > 0;
        pthread_mutex_lock(&w->mu);
        w->keep_from = keep;
        int kept = 0;
        for (int i = 0; i < w->nqueue; i++)
            if (w->queue[i].frame >= keep)
                w->queue[kept++] = w->queue[i];
            else
                ref_drop(w->queue[i].ref);
        w->nqueue = kept;
        if (w->running && w->running_frame < keep)
            atomic_store(&w->cancel, 1);
        ref_drop(*prev);
        *prev = NULL;
        if (*cur && (*cur)->frame >= keep)
            *prev = *cur; /* still wanted: its COMPUTEs may come yet */
        else
            ref_drop(*cur);
        *cur = ref;
        for (uint32_t i = 0; i < nseg; i++) {
            Segment seg = u.seg[i];
            if (segment_ok(seg, ref, "UPDATE", err)) {
                pthread_mutex_unlock(&w->mu);
                return -1;
            }
            queue_job(w, frame, seg, ref);
        }
        pthread_mutex_unlock(&w->mu);
        return 0;
    }
    case PKT_COMPUTE: {
        MsgCompute m;
        if (msg_decode_compute(c->body, c->body_size, &m, err))
            return -1;
        Segment seg = m.seg;
        pthread_mutex_lock(&w->mu);
        SceneRef *ref = *cur && m.frame == (*cur)->frame ? *cur : *prev && m.frame == (*prev)->frame ? *prev : NULL;
        if (ref) {
            if (segment_ok(seg, ref, "COMPUTE", err)) {
                pthread_mutex_unlock(&w->mu);
                return -1;
            }
            queue_job(w, m.frame, seg, ref);
        }
        pthread_mutex_unlock(&w->mu);
        return 0;
    }
    case PKT_ERROR: {
        char text[PROTO_MAX_ERROR_TEXT + 1];
        if (msg_decode_error(c->body, c->body_size, text, err))
            return -1;
        return err_set(err, "server closed the connection: %s", text);
    }
    case PKT_BYE: return err_set(err, "server said goodbye");
    default: return err_set(err, "unexpected %s packet from the server", msg_type_name(c->type));
    }
    (void)cfg;
}

/* One connection, from the handshake to its end; fd < 0: dial the server. */
static int session(const ClientConfig *cfg, int fd, Worker *w, AssetCache *cache, volatile sig_atomic_t *stop, Err *err)
{
    if (fd < 0)
        fd = net_dial(cfg->host, cfg->port, err);
    if (fd < 0)
        return SESSION_FAILED;
    Conn c;
    conn_init(&c, fd);
    uint32_t coding = PIX_RAW;
    int hs = handshake(cfg, &c, &coding, err);
    if (hs <= 0) {
        conn_close(&c);
        return hs;
    }
    pthread_mutex_lock(&w->mu);
    w->coding = coding; /* no job is running between sessions */
    pthread_mutex_unlock(&w->mu);
    /* an IPv6 address in brackets, as it is typed: [::1]:7878 */
    const int v6 = strchr(cfg->host, ':') != NULL;
    log_line(cfg->quiet, "lanray-client", "connected to %s%s%s:%d with %d threads", v6 ? "[" : "", cfg->host,
             v6 ? "]" : "", cfg->port, cfg->threads);
    SceneRef *cur = NULL, *prev = NULL;
    int rc = SESSION_ENDED;
    for (;;) {
        if (*stop) {
            err_set(err, "stopped");
            MsgOut bye;
            msg_encode_bye(&bye);
            conn_send_msg(&c, &bye, CONN_MAX_QUEUE, err);
            conn_flush(&c, err);
            break;
        }
        struct pollfd p[2] = {{c.fd, (short)(POLLIN | (conn_pending(&c) ? POLLOUT : 0)), 0}, {w->wake[0], POLLIN, 0}};
        const int buffered = conn_buffered(&c); /* read ahead (the handshake's too): no wait */
        if (poll(p, 2, buffered ? 0 : 200) < 0 && errno != EINTR) {
            err_set(err, "poll failed: %s", strerror(errno));
            break;
        }
        if (buffered)
            p[0].revents |= POLLIN;
        if (p[1].revents & POLLIN) {
            char buf[256];
            while (read(w->wake[0], buf, sizeof buf) > 0) {
            }
            pthread_mutex_lock(&w->mu);
            Job done[MAX_JOBS * 2];
            int n = w->ndone;
            memcpy(done, w->done, (size_t)n * sizeof *done);
            w->ndone = 0;
            pthread_mutex_unlock(&w->mu);
            int bad = 0;
            for (int i = 0; i < n; i++) {
                MsgOut out;
                msg_encode_data(&(MsgData){.frame = done[i].frame, .seg = done[i].seg, .render_us = done[i].render_us,
                                           .coding = done[i].coding, .pixels = done[i].pixels, .len = done[i].len,
                                           .bpp = done[i].bpp},
                                &out);
                if (!bad && conn_send_msg(&c, &out, CONN_MAX_QUEUE, err))
                    bad = 1;
                free(done[i].pixels);
            }
            if (bad || assets_taken(w, &c, cache, err))
                break;
        }
        if (p[0].revents & (POLLIN | POLLHUP | POLLERR)) {
            int got, bad = 0;
            while ((got = conn_read(&c, err)) == 1)
                if (on_packet(cfg, w, &c, cache, &cur, &prev, err)) {
                    bad = 1;
                    break;
                }
            if (bad || got < 0)
                break;
        }
        if (conn_pending(&c) && conn_flush(&c, err) < 0)
            break;
    }
    /* forget this server's work; keep the assets it sent that decoded */
    assetload_settle(w->load, cache);
    pthread_mutex_lock(&w->mu);
    w->keep_from = UINT32_MAX; /* nothing of this session's frames */
    for (int i = 0; i < w->nqueue; i++)
        ref_drop(w->queue[i].ref);
    w->nqueue = 0;
    atomic_store(&w->cancel, 1);
    for (int i = 0; i < w->ndone; i++)
        free(w->done[i].pixels);
    w->ndone = 0;
    ref_drop(cur);
    ref_drop(prev);
    pthread_mutex_unlock(&w->mu);
    conn_close(&c);
    return rc;
}

static int worker_start(Worker *w, int threads, AssetCache **cache, pthread_t *th, Err *err)
{
    memset(w, 0, sizeof *w);
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    if (pipe(w->wake) || net_setup(w->wake[0]) || net_setup(w->wake[1]))
        return err_set(err, "cannot create a pipe: %s", strerror(errno));
    w->pool = render_pool_create(threads, err);
    w->codec = pixcodec_create();
    *cache = asset_cache_create();
    Err e = {{0}};
    if (w->pool && w->codec && *cache)
        w->load = assetload_create(w->wake[1], &e);
    if (!w->pool || !w->codec || !*cache || !w->load || pthread_create(th, NULL, render_thread, w)) {
        assetload_destroy(w->load);
        render_pool_destroy(w->pool);
        pixcodec_destroy(w->codec);
        asset_cache_destroy(*cache);
        close(w->wake[0]);
        close(w->wake[1]);
        if (!w->pool)
            return -1;
        if (w->codec && *cache && !w->load) {
            *err = e;
            return -1;
        }
        return err_set(err, w->codec && *cache ? "cannot start the render thread" : "out of memory");
    }
    return 0;
}

static void worker_stop(Worker *w, AssetCache *cache, pthread_t th, ClientStats *stats, uint32_t sessions)
{
    pthread_mutex_lock(&w->mu);
    w->quit = 1;
    atomic_store(&w->cancel, 1);
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
    pthread_join(th, NULL);
    assetload_destroy(w->load);
    if (stats)
        *stats = (ClientStats){w->segments, w->pixels, sessions, w->scenes, world_tree_builds()};
    render_pool_destroy(w->pool);
    pixcodec_destroy(w->codec);
    asset_cache_destroy(cache);
    close(w->wake[0]);
    close(w->wake[1]);
    pthread_mutex_destroy(&w->mu);
    pthread_cond_destroy(&w->cv);
}

int client_run(const ClientConfig *cfg, volatile sig_atomic_t *stop, ClientStats *stats, Err *err)
{
    Worker w;
    AssetCache *cache;
    pthread_t th;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (worker_start(&w, cfg->threads, &cache, &th, err))
        return -1;
    int rc = 0;
    uint32_t sessions = 0;
    double backoff = 0.1;
    while (!*stop) {
        double start = timer_now();
        Err e = {{0}};
        int r = session(cfg, -1, &w, cache, stop, &e);
        sessions += r == SESSION_ENDED;
        if (r == SESSION_REFUSED || (r == SESSION_FAILED && !cfg->reconnect && !*stop)) {
            err_set(err, "%s", e.msg);
            rc = -1;
            break;
        }
        if (*stop || !cfg->reconnect)
            break;
        if (r == SESSION_ENDED || timer_now() - start > 2)
            backoff = 0.1; /* the session worked (past the handshake): start over gently */
        log_line(cfg->quiet, "lanray-client", "%s; reconnecting in %.1f s", e.msg, backoff);
        struct timespec ts = {(time_t)backoff, (long)((backoff - (double)(time_t)backoff) * 1e9)};
        nanosleep(&ts, NULL);
        backoff = backoff * 2 < 5 ? backoff * 2 : 5;
    }
    worker_stop(&w, cache, th, stats, sessions);
    return rc;
}

int client_run_fd(const ClientConfig *cfg, int fd, volatile sig_atomic_t *stop, ClientStats *stats, Err *err)
{
    Worker w;
    AssetCache *cache;
    pthread_t th;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (worker_start(&w, cfg->threads, &cache, &th, err)) {
        close(fd);
        return -1;
    }
    int r = session(cfg, fd, &w, cache, stop, err);
    worker_stop(&w, cache, th, stats, r == SESSION_ENDED);
    return r == SESSION_ENDED ? 0 : -1;
}
