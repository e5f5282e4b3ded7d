/* datagen.c - a load generator for the server: clients that answer every
 * segment at once with valid pre-rendered DATA, as fast as the protocol
 * lets them, so that what is measured is the server's cost a packet.
 *
 *     datagen PORT SERVER_PID [--clients N] [--seconds S] [--warmup S] [--host H] [--whole] [--size WxH]
 *
 * N connections (8) to H:PORT (127.0.0.1) do the handshake (no token), then
 * answer each UPDATE's and COMPUTE's segments with DATA whose pixels are
 * a rendered segment of the default scene, coded as the WELCOME asks
 * (raw, LZ4 or zstd after the predictor: the server's --compress), coded
 * once per segment size before the clock starts.  With --whole the pixels
 * are the segment's own in the whole rendered frame of --size WxH
 * (1024x768: the server's frame size; each coded
 * the first time it is asked for), so that a frame's bytes are the default
 * scene's: a farm of clients faster than any link.  After S seconds (10,
 * after a warm-up of 1) it prints the DATA packets a second it sent, the
 * server's CPU time (/proc/SERVER_PID/stat, user + system) a packet and
 * the packets a second one server core would take at that cost.  Timing
 * only. */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/timer.h"
#include "net/conn.h"
#include "net/net.h"
#include "net/pixcodec.h"
#include "render/render.h"
#include "scene/scene_default.h"

#define MAX_CONNS 64
#define MAX_SIZES 8
#define MAX_SEGS 8192 /* --whole: the segments coded so far, by first pixel and count */

typedef struct {
    uint32_t count;
    uint8_t *data;
    size_t len;
    uint32_t used;
} CannedSize;

/* The rendered pixels, and their codings by segment size. */
typedef struct {
    uint8_t *frame; /* 1024 x 64 RGB8 of the default scene: pixels enough for any segment here */
    size_t frame_bytes;
    uint32_t coding;
    CannedSize sizes[MAX_SIZES];
    int nsizes;
    PixCodec *pc;
    int whole;               /* frame is the whole frame of width x height; segs holds each segment coded */
    int width, height;
    uint32_t seg_first[MAX_SEGS];
    CannedSize segs[MAX_SEGS];
} Canned;

static int canned_make(Canned *c, Err *err)
{
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Scene *s;
    RenderPool *pool = render_pool_create(c->whole ? 2 : 1, err);
    if (!pool || scene_default(&s, &opt, err))
        return -1;
    s->settings.aa = 1, s->settings.adaptive = 0;
    World *w = world_build(s, NULL, err);
    const int lines = c->whole ? c->height : 64, width = c->whole ? c->width : 1024;
    c->frame_bytes = (size_t)width * (size_t)lines * 3;
    c->frame = malloc(c->frame_bytes);
    /* lines 352..415 of a 1024x768 frame (the spheres and the floor), or all of it */
    int rc = !w || !c->frame ||
                     render_lines(pool, w, width, c->whole ? c->height : 768, c->whole ? 0 : 352, lines, c->frame, NULL, err)
                 ? -1
                 : 0;
    world_destroy(w);
    scene_destroy(s);
    render_pool_destroy(pool);
    c->pc = pixcodec_create();
    return rc || !c->pc ? -1 : 0;
}

/* --whole: segment seg of the frame, coded once. */
static int canned_seg(Canned *c, Segment seg, const uint8_t **data, size_t *len, uint32_t *coding)
{
    const size_t n = (size_t)seg.count * 3;
    if ((size_t)seg.first * 3 + n > c->frame_bytes)
        return -1;
    uint32_t h = (seg.first * 2654435761u ^ seg.count) % MAX_SEGS;
    for (uint32_t k = 0; k < MAX_SEGS; k++, h = (h + 1) % MAX_SEGS) {
        CannedSize *e = &c->segs[h];
        if (e->data && c->seg_first[h] == seg.first && e->count == seg.count) {
            *data = e->data, *len = e->len, *coding = e->used;
            return 0;
        }
        if (!e->data) {
            uint8_t *out = malloc(pixcodec_bound(n));
            Err err;
            int used = out ? pixcodec_encode(c->pc, c->coding, c->frame + (size_t)seg.first * 3, n, 3, out, &e->len, &err) : -1;
            if (used < 0)
                return free(out), -1;
            e->data = out, e->count = seg.count, e->used = (uint32_t)used;
            c->seg_first[h] = seg.first;
            *data = e->data, *len = e->len, *coding = e->used;
            return 0;
        }
    }
    return -1;
}

/* The DATA body's pixels for a segment of count pixels. */
static int canned_get(Canned *c, uint32_t count, const uint8_t **data, size_t *len, uint32_t *coding)
{
    for (int i = 0; i < c->nsizes; i++)
        if (c->sizes[i].count == count) {
            *data = c->sizes[i].data, *len = c->sizes[i].len, *coding = c->sizes[i].used;
            return 0;
        }
    const size_t n = (size_t)count * 3;
    if (c->nsizes == MAX_SIZES || n > c->frame_bytes)
        return -1;
    uint8_t *out = malloc(pixcodec_bound(n));
    size_t got;
    Err err;
    int used = out ? pixcodec_encode(c->pc, c->coding, c->frame, n, 3, out, &got, &err) : -1;
    if (used < 0)
        return free(out), -1;
    c->sizes[c->nsizes++] = (CannedSize){count, out, got, (uint32_t)used};
    return canned_get(c, count, data, len, coding);
}

static double cpu_of(int pid)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    const char *p = strrchr(buf, ')');
    unsigned long ut = 0, st = 0;
    /* after the command: state, then fields 4..13, utime and stime are 14 and 15 */
    if (!p || sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &ut, &st) != 2)
        return -1;
    return (double)(ut + st) / (double)sysconf(_SC_CLK_TCK);
}

static int handshake(Conn *c, Canned *cn, Err *err)
{
    for (int step = 0; step < 2; step++) {
        int got;
        struct pollfd p = {c->fd, POLLIN, 0};
        while ((got = conn_read(c, err)) == 0)
            if (poll(&p, 1, 5000) <= 0)
                return err_set(err, "handshake: no answer");
        if (got < 0)
            return -1;
        if (step == 0) {
            MsgHello h = {.magic = PROTO_MAGIC, .version = PROTO_VERSION, .bom = PROTO_BOM, .threads = 1,
                          .real_size = (uint32_t)sizeof(real), .codecs = PIX_CODEC_MASK};
            MsgOut out;
            msg_encode_hello(&h, &out);
            if (conn_send_msg(c, &out, CONN_MAX_QUEUE, err) || conn_flush(c, err) < 0)
                return -1;
        } else {
            MsgWelcome w;
            if (c->type != PKT_WELCOME || msg_decode_welcome(c->body, c->body_size, &w, err))
                return err_set(err, "handshake: no WELCOME");
            cn->coding = w.coding;
        }
    }
    return 0;
}

/* Answers a packet's segments with DATA; counts them. */
static int answer(Conn *c, Canned *cn, uint64_t *sent, Err *err)
{
    uint32_t frame = 0, nseg = 0;
    Segment seg[2];
    if (c->type == PKT_UPDATE) {
        MsgUpdate u;
        if (msg_decode_update(c->body, c->body_size, &u, err))
            return -1;
        frame = u.frame, nseg = u.nseg;
        memcpy(seg, u.seg, sizeof seg);
    } else if (c->type == PKT_COMPUTE) {
        MsgCompute m;
        if (msg_decode_compute(c->body, c->body_size, &m, err))
            return -1;
        frame = m.frame, nseg = 1, seg[0] = m.seg;
    } else if (c->type == PKT_ERROR) {
        return err_set(err, "the server sent an ERROR");
    }
    for (uint32_t i = 0; i < nseg; i++) {
        MsgData d = {.frame = frame, .seg = seg[i], .render_us = 1000, .bpp = 3};
        if (cn->whole ? canned_seg(cn, seg[i], &d.pixels, &d.len, &d.coding)
                      : canned_get(cn, seg[i].count, &d.pixels, &d.len, &d.coding))
            return err_set(err, "segment %u+%u: outside the canned pixels", seg[i].first, seg[i].count);
        MsgOut out;
        msg_encode_data(&d, &out);
        if (conn_send_msg(c, &out, CONN_MAX_QUEUE, err))
            return -1;
        (*sent)++;
    }
    return 0;
}

static int connect_all(Conn *conns, int nconn, const char *host, int port, Canned *cn, Err *err)
{
    for (int i = 0; i < nconn; i++) {
        int fd = net_dial(host, port, err);
        if (fd < 0)
            return -1;
        conn_init(&conns[i], fd);
        if (handshake(&conns[i], cn, err))
            return -1;
    }
    return 0;
}

/* What the command line says. */
typedef struct {
    int port, pid, nconn;
    double seconds, warmup;
    const char *host;
} Args;

static int parse_args(int argc, char **argv, Args *a, Canned *cn)
{
    if (argc < 3)
        return fprintf(stderr, "usage: datagen PORT SERVER_PID [--clients N] [--seconds S] [--warmup S] [--host H] "
                               "[--whole] [--size WxH]\n"), 2;
    *a = (Args){atoi(argv[1]), atoi(argv[2]), 8, 10, 1, "127.0.0.1"};
    cn->width = 1024, cn->height = 768;
    for (int i = 3; i < argc; i += 2) {
        if (!strcmp(argv[i], "--whole")) {
            cn->whole = 1;
            i--;
        } else if (i + 1 >= argc) {
            return fprintf(stderr, "datagen: %s needs a value\n", argv[i]), 2;
        } else if (!strcmp(argv[i], "--size")) {
            if (sscanf(argv[i + 1], "%dx%d", &cn->width, &cn->height) != 2 || cn->width < 1 || cn->height < 1 ||
                cn->width > 8192 || cn->height > 8192)
                return fprintf(stderr, "datagen: --size WxH, up to 8192x8192\n"), 2;
        } else if (!strcmp(argv[i], "--host")) {
            a->host = argv[i + 1];
        } else if (!strcmp(argv[i], "--clients")) {
            a->nconn = atoi(argv[i + 1]);
        } else if (!strcmp(argv[i], "--seconds")) {
            a->seconds = atof(argv[i + 1]);
        } else if (!strcmp(argv[i], "--warmup")) {
            a->warmup = atof(argv[i + 1]);
        }
    }
    if (a->nconn < 1 || a->nconn > MAX_CONNS)
        return fprintf(stderr, "datagen: 1..%d clients\n", MAX_CONNS), 2;
    return 0;
}

int main(int argc, char **argv)
{
    Args a;
    Canned cn = {0};
    int bad = parse_args(argc, argv, &a, &cn);
    if (bad)
        return bad;
    const int port = a.port, pid = a.pid, nconn = a.nconn;
    const double seconds = a.seconds, warmup = a.warmup;
    const char *host = a.host;
    Err err;
    if (canned_make(&cn, &err))
        return fprintf(stderr, "datagen: %s\n", err.msg), 1;
    Conn conns[MAX_CONNS];
    if (connect_all(conns, nconn, host, port, &cn, &err))
        return fprintf(stderr, "datagen: %s\n", err.msg), 1;
    uint64_t sent = 0, sent0 = 0;
    double t0 = timer_now(), start = 0, cpu0 = 0;
    for (;;) {
        const double now = timer_now();
        if (start == 0 && now - t0 >= warmup)
            start = now, sent0 = sent, cpu0 = cpu_of(pid);
        if (start > 0 && now - start >= seconds)
            break;
        struct pollfd p[MAX_CONNS];
        for (int i = 0; i < nconn; i++)
            p[i] = (struct pollfd){conns[i].fd, (short)(POLLIN | (conn_pending(&conns[i]) ? POLLOUT : 0)), 0};
        int buffered = 0;
        for (int i = 0; i < nconn; i++)
            buffered |= conn_buffered(&conns[i]);
        if (poll(p, (nfds_t)nconn, buffered ? 0 : 100) < 0)
            break;
        for (int i = 0; i < nconn; i++) {
            int got;
            if ((p[i].revents & (POLLIN | POLLHUP | POLLERR)) || conn_buffered(&conns[i]))
                while ((got = conn_read(&conns[i], &err)) == 1)
                    if (answer(&conns[i], &cn, &sent, &err))
                        return fprintf(stderr, "datagen: %s\n", err.msg), 1;
            if (conn_pending(&conns[i]) && conn_flush(&conns[i], &err) < 0)
                return fprintf(stderr, "datagen: %s\n", err.msg), 1;
        }
    }
    const double wall = timer_now() - start, cpu = cpu_of(pid) - cpu0;
    const double n = (double)(sent - sent0);
    printf("datagen: %s DATA, %d clients, %.1f s: %.0f packets/s sent; server CPU %.2f s, %.2f us a packet, "
           "%.0f packets/s on one server core\n",
           pixcodec_name(cn.coding), nconn, wall, n / wall, cpu, n > 0 ? 1e6 * cpu / n : 0, cpu > 0 ? n / cpu : 0);
    for (int i = 0; i < nconn; i++)
        conn_close(&conns[i]);
    return 0;
}
