/* schedsim - discrete-event simulation of a lanray render farm, driving the
 * real scheduler (server/scheduler.c) with simulated clients.
 *
 *   schedsim --profile lines.csv [--width W] [--clients N] [--threads T]
 *            [--cores C] [--speeds a,b,...] [--segment LINES|auto] [--tail RULE]
 *            [--latency-us L] [--bandwidth-mbit B] [--client-mbit B2 [--client-burst-kb K]]
 *            [--overhead-us O] [--overhead-cpu Q] [--bg-cpu-us G] [--slice-us S]
 *            [--turnaround-us R] [--server-us P] [--frames F] [--cost-scale K]
 *            [--pixel-bytes X] [--pipeline on|off]
 *   schedsim --probe-slice C     (measures S on this machine's C cores; --help lists every option)
 *
 * The cost of a pixel comes from a real frame's profile (`lanray-render
 * --profile`: microseconds per line on one thread); a client with T threads
 * has K * (its pixels' cost) / (T * speed) + Q * O / speed of CPU work for a
 * segment, and the rest of the per-segment overhead, (1 - Q) * O, is waiting
 * (thread wake-ups).  When the clients together have more threads than there
 * are cores C (the benchmark machine's clients share its cores), the busy
 * ones share the cores equally (processor sharing: a client's rate changes
 * whenever another starts or stops), and a client that was idle waits for a
 * core before it starts: one time slice S for every C threads already
 * running or waiting, as the OS scheduler makes a woken thread queue.
 * Moving a segment's packets costs G of CPU in the server and the client's
 * network thread; on shared cores that work runs first, a core for each
 * client whose network thread has some (the threads are the clients').  The
 * server is one thread: it handles DATA packets one at a time, P each (its
 * measured CPU per packet), so at high packet rates results queue for it.
 * Packets take the latency L plus their size over the server's link of B
 * Mbit/s, one FIFO queue each way (DATA into the server, UPDATE/COMPUTE out
 * of it), and with --client-mbit through a link of that rate per client as
 * well, a token bucket of K kilobytes as tc's tbf (a link idle for a while
 * passes the next K kB at once).  The server behaves as the real one: an
 * UPDATE with two segments per client at the start of a frame, a COMPUTE
 * after every DATA, idle clients topped up (outstanding segments handed out
 * again), the next frame as soon as the last pixels arrive, its UPDATE at a
 * client no sooner than the measured turnaround R after that (the server
 * encoding and sending the scene, the client decoding it: about 0.3 ms); a
 * client cancels the render it is in when an UPDATE for a newer frame
 * arrives, as the real one does.  With --pipeline on the server starts the
 * next frame as soon as the current one has no fresh work left (the real
 * server's --pipeline, through the same scheduler calls: sched_has_fresh,
 * sched_top_up_pair), the UPDATE keeps the older frame, and frames are
 * counted as they are shown, in order.  A DATA packet carries X bytes a
 * pixel (--pixel-bytes: 3 raw, about 0.6 after zstd: docs/scaling.md).
 * Prints FPS, efficiency (busy / (clients x
 * wall)), duplicated lines and bytes per frame. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "base/opt.h"
#include "scheduler.h"
#include "base/timer.h"

#define MAXC 4096
#define UPDATE_BYTES 900.0 /* header, two segments and the serialised benchmark scene */

typedef enum { EV_ARRIVE_CLIENT, EV_DONE, EV_ARRIVE_SERVER, EV_WAKE, EV_LAGGED, EV_BG_IDLE } EvKind;

typedef struct {
    double t;
    EvKind kind;
    int client;
    uint32_t frame;
    Segment seg;
    double busy_us;
    uint32_t gen; /* EV_DONE: the client's render generation it ends; EV_ARRIVE_SERVER: 1 once handled */
    uint32_t keep; /* EV_ARRIVE_CLIENT of an UPDATE: the oldest frame the client keeps (0: a COMPUTE) */
    uint64_t seq; /* push order: events at the same time pop first-in first-out */
} Event;

typedef struct {
    Event *e;
    int n, cap;
    uint64_t pushed;
} Heap;

/* Ties in time keep push order, so that two segments sent in one packet
 * arrive (and are queued) in the order they were sent. */
static int ev_before(const Event *a, const Event *b) { return a->t < b->t || (a->t == b->t && a->seq < b->seq); }

static void heap_push(Heap *h, Event ev)
{
    if (h->n == h->cap) {
        h->cap = h->cap ? 2 * h->cap : 1024;
        h->e = realloc(h->e, (size_t)h->cap * sizeof *h->e);
        if (!h->e)
            abort();
    }
    ev.seq = h->pushed++;
    int i = h->n++;
    while (i > 0 && ev_before(&ev, &h->e[(i - 1) / 2])) {
        h->e[i] = h->e[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->e[i] = ev;
}

static Event heap_pop(Heap *h)
{
    Event top = h->e[0], last = h->e[--h->n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && ev_before(&h->e[c + 1], &h->e[c]))
            c++;
        if (!ev_before(&h->e[c], &last))
            break;
        h->e[i] = h->e[c];
        i = c;
    }
    h->e[i] = last;
    return top;
}

/* A link: FIFO, and shaped as tc's tbf shapes a client's, tokens (bytes)
 * filling at its rate up to the burst size, a packet leaving once there are
 * enough (burst 0, the server's: a plain FIFO at the rate). */
typedef struct {
    double free_at; /* the last packet's departure */
    double tokens;  /* as of `at` */
    double at;
} Link;

typedef struct {
    Link up, down;    /* its own link, when client_mbit > 0 */
    double bg_left, bg_since; /* CPU work of its packets waiting (bg_cpu_us each), as of bg_since */
    double bg_rate;   /* its network thread's share of a core, <= 1 */
    uint32_t bg_gen;
    double speed;     /* speed factor (--speeds) */
    int group;        /* the cores it shares: its own, or all of them (group 0) */
    double left;      /* work left in the current segment, microseconds at full rate */
    double rate;      /* its current share of its group, <= 1 */
    double since;     /* when left and rate were last brought up to date */
    double started;   /* when the current segment started (render time is wall time) */
    Segment seg;      /* the current segment */
    uint32_t seg_frame;
    Segment queue[64];
    uint32_t qframe[64];
    int nq;
    int busy;
    int waking;         /* idle, given work, waiting for a core (EV_WAKE) */
    int lagging;        /* its segment taken, in the waiting part of the overhead (EV_LAGGED) */
    uint32_t gen;       /* bumped when a render is cancelled: its EV_DONE is void */
    uint32_t keep_from; /* the oldest frame it renders (its last UPDATE's keep) */
} Client;

typedef struct {
    int width, height, clients, threads, frames;
    double cores, latency_us, mbit, overhead_us, cost_scale;
    double group_cores; /* cores in each group of clients sharing them */
    double overhead_cpu; /* the part of the per-segment overhead that is CPU work */
    double slice_us;    /* the OS scheduler's time slice: what a woken client waits per round of others */
    double client_mbit; /* > 0: every client also has its own link of this rate (namespaces behind veth pairs) */
    double client_burst; /* bytes: the token bucket of each client's link */
    double bg_cpu_us;   /* CPU per segment outside the render threads (server, network threads) */
    double turnaround_us; /* from a frame's last pixels to a client starting the next frame */
    double server_us;   /* the server thread's time per DATA packet (and the COMPUTE it sends) */
    double pixel_bytes; /* a pixel's bytes in a DATA packet (3 raw; fewer coded) */
    int pipeline;       /* the next frame starts when the current one has no fresh work left */
    int shared;         /* the clients share one group of cores, with the server */
    uint32_t segment; /* 0: auto, as the server */
    SchedTailRule tail;
    double *line_us;  /* per line, one thread */
    double *prefix;   /* cumulative cost per pixel, for segment costs */
    double speeds[MAXC];
    int nspeeds;
} Sim;

static double seg_cost(const Sim *s, Segment g) { return s->prefix[g.first + g.count] - s->prefix[g.first]; }

/* time a packet of `bytes` leaves a link of `mbit` Mbit/s (bytes per
 * microsecond: mbit / 8) with a token bucket of `burst` bytes */
static double link_send(double now, Link *l, double bytes, double mbit, double burst)
{
    double rate = mbit / 8.0; /* bytes per microsecond */
    double start = now > l->free_at ? now : l->free_at;
    double tokens = fmin(burst, l->tokens + (start - l->at) * rate);
    double done = tokens >= bytes ? start : start + (bytes - tokens) / rate;
    l->tokens = tokens >= bytes ? tokens - bytes : 0;
    l->at = l->free_at = done;
    return done;
}

/* A packet to or from client c: through the server's link, then (with
 * per-client links) through the client's own. */
static double send_via(const Sim *s, double now, Link *server, Link *client, double bytes)
{
    double t = link_send(now, server, bytes, s->mbit, 0);
    if (s->client_mbit > 0)
        t = link_send(t, client, bytes, s->client_mbit, s->client_burst);
    return t + s->latency_us;
}

/* Threads in group g that want a core: the busy clients' and the waking ones'. */
static double group_demand(const Sim *s, const Client *cl, int g)
{
    int n = 0;
    for (int i = 0; i < s->clients; i++)
        n += cl[i].group == g && (cl[i].busy || cl[i].waking);
    return (double)n * s->threads;
}

/* Clients whose network thread has packet work waiting (bg_add). */
static int bg_pending(const Sim *s, const Client *cl)
{
    int n = 0;
    for (int i = 0; i < s->clients; i++)
        n += cl[i].bg_left > 0;
    return n;
}

/* The busy clients of core group g share its cores equally: brings each one's
 * work left up to `now`, gives it the new rate and schedules its EV_DONE
 * again (the one scheduled before is voided through the generation). */
static void group_share(const Sim *s, Client *cl, int g, double now, Heap *h)
{
    int busy = 0;
    for (int i = 0; i < s->clients; i++)
        busy += cl[i].group == g && cl[i].busy;
    /* background work (packets) runs first, on shared cores: a core for
     * each client with some */
    double cap = s->shared ? fmax(s->group_cores - bg_pending(s, cl), 0.0) : s->group_cores;
    double want = (double)busy * s->threads, rate = want > cap ? cap / want : 1.0;
    for (int i = 0; i < s->clients; i++) {
        Client *c = &cl[i];
        if (c->group != g || !c->busy)
            continue;
        c->left = fmax(c->left - (now - c->since) * c->rate, 0.0);
        c->since = now;
        if (c->rate == rate)
            continue;
        c->rate = rate;
        c->gen++;
        heap_push(h, (Event){now + c->left / rate, EV_DONE, i, c->seg_frame, c->seg, 0, c->gen, 0, 0});
    }
}

/* A segment's packets cost bg_cpu_us of CPU in the server and the client's
 * network thread.  Those threads sleep between packets, so the OS runs them
 * as soon as they wake: on shared cores each client's takes a core from the
 * render threads until its work is done, and when more have work than there
 * are cores they share them (one core for all of them, as a first version
 * had it, fitted a 16-CPU machine's runs a little worse: 89, 101 and 81 of
 * 112 within 15% against 91, 101 and 82).  On clients' own machines they
 * cost nothing here. */
static void bg_share(const Sim *s, Client *cl, double now, Heap *h)
{
    int pending = bg_pending(s, cl);
    double rate = pending > s->group_cores ? s->group_cores / pending : 1.0;
    for (int i = 0; i < s->clients; i++) {
        Client *c = &cl[i];
        if (c->bg_left <= 0)
            continue;
        c->bg_left = fmax(c->bg_left - (now - c->bg_since) * c->bg_rate, 1e-9);
        c->bg_since = now;
        if (c->bg_rate == rate)
            continue;
        c->bg_rate = rate;
        heap_push(h, (Event){now + c->bg_left / rate, EV_BG_IDLE, i, 0, {0, 0}, 0, ++c->bg_gen, 0, 0});
    }
    group_share(s, cl, 0, now, h);
}

static void bg_add(const Sim *s, Client *cl, int ci, double now, Heap *h)
{
    if (s->bg_cpu_us <= 0 || !s->shared)
        return;
    Client *c = &cl[ci];
    if (c->bg_left > 0) { /* more for a thread already at work: same share */
        c->bg_left = fmax(c->bg_left - (now - c->bg_since) * c->bg_rate, 0.0) + s->bg_cpu_us;
        c->bg_since = now;
        heap_push(h, (Event){now + c->bg_left / c->bg_rate, EV_BG_IDLE, ci, 0, {0, 0}, 0, ++c->bg_gen, 0, 0});
        return;
    }
    c->bg_left = s->bg_cpu_us;
    c->bg_since = now;
    c->bg_rate = 0; /* bg_share gives it its share and schedules its end */
    bg_share(s, cl, now, h);
}

/* The simulation under way: what run's event handlers share. */
typedef struct {
    Sim *s;
    Client *cl;
    Sched *sc;          /* the newest frame's scheduler (its number: newest) */
    Sched *older;       /* pipelined: the frame before it, still in flight (NULL: none) */
    Sched *spare;
    uint32_t newest, older_id;
    int in_frame;       /* the newest frame is not shown yet */
    Heap h;
    Link down, up; /* the server's link, each way */
    double now, bytes, busy, work, server_free;
} Run;

/* The frame of a segment the pair top-up gave (from[k]). */
static uint32_t frame_of(const Run *r, const Sched *from) { return from == r->sc ? r->newest : r->older_id; }

/* A DATA packet's bytes: header and fields, and the pixels as coded. */
static double data_bytes(const Sim *s, Segment g) { return 28.0 + s->pixel_bytes * g.count; }

/* A frame begins: the scheduler sizes and starts it, and every client gets
 * the UPDATE with its first segments (and, pipelined, COMPUTEs of the
 * older frame where it has any fresh work: none, as it starts now). */
static void frame_begin(Run *r, int frame)
{
    Sim *s = r->s;
    r->newest = (uint32_t)frame + 1;
    r->in_frame = 1;
    /* the server's rule, with the simulated per-segment overhead and CPU
     * outside the render threads standing for what the server measures
     * (the gap between results, and its own CPU per packet twice over) */
    sched_start_frame(r->sc, (uint32_t)frame + 1, (uint32_t)s->clients, s->segment == 0, r->work,
                      s->overhead_us + s->bg_cpu_us);
    r->work = 0;
    const uint32_t keep = r->older ? r->older_id : r->newest;
    for (int i = 0; i < s->clients; i++) {
        double t = fmax(send_via(s, r->now, &r->down, &r->cl[i].down, UPDATE_BYTES), r->now + s->turnaround_us);
        r->bytes += UPDATE_BYTES;
        Segment g[SCHED_IN_FLIGHT];
        Sched *from[SCHED_IN_FLIGHT];
        uint32_t n = sched_top_up_pair(r->older, r->sc, i, g, from);
        /* the UPDATE (keep) reaches the client even where it brings no segment */
        heap_push(&r->h, (Event){t, EV_ARRIVE_CLIENT, i, r->newest, {0, 0}, 0, 0, keep, 0});
        for (uint32_t k = 0; k < n; k++)
            heap_push(&r->h, (Event){t, EV_ARRIVE_CLIENT, i, frame_of(r, from[k]), g[k], 0, 0, 0, 0});
    }
}

/* A segment reaches its client: queued, unless a newer frame has come.
 * Each handler returns 0 where the event changes nothing more (idle
 * clients are not looked at), 1 where it goes on. */
static int on_arrive_client(Run *r, const Event *ev)
{
    Client *c = &r->cl[ev->client];
    if (ev->keep > c->keep_from) { /* newer UPDATE: drop work older than it keeps, cancel such a render */
        c->keep_from = ev->keep;
        int kept = 0;
        for (int i = 0; i < c->nq; i++)
            if (c->qframe[i] >= ev->keep) {
                c->queue[kept] = c->queue[i];
                c->qframe[kept++] = c->qframe[i];
            }
        c->nq = kept;
        if ((c->busy || c->lagging) && c->seg_frame < ev->keep) {
            c->busy = c->lagging = 0;
            c->gen++;
            group_share(r->s, r->cl, c->group, r->now, &r->h);
        }
    }
    if (ev->seg.count == 0) /* the UPDATE itself */
        return 1;
    if (ev->frame < c->keep_from || c->nq == 64)
        return 0;
    c->queue[c->nq] = ev->seg;
    c->qframe[c->nq++] = ev->frame;
    return 1;
}

/* A client finishes a segment: its DATA goes to the server. */
static int on_done(Run *r, Event ev)
{
    Client *c = &r->cl[ev.client];
    if (ev.gen != c->gen)
        return 0; /* cancelled, or rescheduled at another rate */
    c->busy = 0;
    c->rate = 0;
    ev.busy_us = r->now - c->started;
    group_share(r->s, r->cl, c->group, r->now, &r->h);
    if (ev.frame >= c->keep_from) {
        double t = send_via(r->s, r->now, &r->up, &c->up, data_bytes(r->s, ev.seg));
        heap_push(&r->h, (Event){t, EV_ARRIVE_SERVER, ev.client, ev.frame, ev.seg, ev.busy_us, 0, 0, 0});
    }
    return 1;
}

/* A DATA packet at the server: its one thread takes packets in turn; the
 * result goes to the scheduler, and every client is topped up. */
static int on_arrive_server(Run *r, Event ev)
{
    Sim *s = r->s;
    if (s->server_us > 0 && !ev.gen) {
        r->server_free = fmax(r->now, r->server_free) + s->server_us;
        ev.t = r->server_free;
        ev.gen = 1;
        heap_push(&r->h, ev);
        return 0;
    }
    r->bytes += data_bytes(s, ev.seg);
    bg_add(s, r->cl, ev.client, r->now, &r->h);
    SchedResult res = sched_complete(r->older && ev.frame == r->older_id ? r->older : r->sc, ev.client, ev.frame, ev.seg);
    if (res != SCHED_STALE) {
        r->busy += ev.busy_us;
        if (res == SCHED_ACCEPT)
            r->work += ev.busy_us; /* the server sums the render times clients report */
    }
    if (res == SCHED_STALE || (!r->older && sched_frame_done(r->sc)))
        return 1; /* the frame is over: the next one's UPDATE tops the clients up */
    /* every client topped up after a result, a COMPUTE a segment */
    for (int i = 0; i < s->clients; i++) {
        Segment g[SCHED_IN_FLIGHT];
        Sched *from[SCHED_IN_FLIGHT];
        uint32_t n = sched_top_up_pair(r->older, r->sc, i, g, from);
        for (uint32_t k = 0; k < n; k++) {
            double t = send_via(s, r->now, &r->down, &r->cl[i].down, 20);
            r->bytes += 20;
            heap_push(&r->h, (Event){t, EV_ARRIVE_CLIENT, i, frame_of(r, from[k]), g[k], 0, 0, 0, 0});
        }
    }
    return 1;
}

/* Idle clients start their next queued segment; one that was idle (not
 * going straight on from its own last segment) first waits for a core when
 * its group is oversubscribed. */
static void start_idle(Run *r, const Event *ev)
{
    Sim *s = r->s;
    for (int i = 0; i < s->clients; i++) {
        Client *d = &r->cl[i];
        if (d->busy || d->waking || d->lagging || d->nq == 0)
            continue;
        int woke = ev->kind == EV_WAKE && ev->client == i;
        if (!woke && !(ev->kind == EV_DONE && ev->client == i) && s->slice_us > 0) {
            double delay = s->slice_us * floor(group_demand(s, r->cl, d->group) / s->group_cores);
            if (delay > 0) {
                d->waking = 1;
                heap_push(&r->h, (Event){r->now + delay, EV_WAKE, i, 0, {0, 0}, 0, 0, 0, 0});
                continue;
            }
        }
        Segment g = d->queue[0];
        uint32_t f = d->qframe[0];
        memmove(d->queue, d->queue + 1, (size_t)--d->nq * sizeof *d->queue);
        memmove(d->qframe, d->qframe + 1, (size_t)d->nq * sizeof *d->qframe);
        /* the CPU part of the per-segment overhead stretches with the
         * core share; the waiting part comes first and takes no core */
        d->left = (seg_cost(s, g) / (s->threads * d->speed) + s->overhead_cpu * s->overhead_us / d->speed);
        d->seg = g;
        d->seg_frame = f;
        d->started = d->since = r->now;
        d->rate = 0;
        double lag = (1 - s->overhead_cpu) * s->overhead_us;
        if (lag > 0) {
            d->lagging = 1;
            heap_push(&r->h, (Event){r->now + lag, EV_LAGGED, i, 0, {0, 0}, 0, d->gen, 0, 0});
            continue;
        }
        d->busy = 1;
        group_share(s, r->cl, d->group, r->now, &r->h);
    }
}

/* One event of a frame. */
static void on_event(Run *r, const Event *ev)
{
    Client *c = &r->cl[ev->client];
    int go_on = 1;
    switch (ev->kind) {
    case EV_ARRIVE_CLIENT: go_on = on_arrive_client(r, ev); break;
    case EV_DONE: go_on = on_done(r, *ev); break;
    case EV_ARRIVE_SERVER: go_on = on_arrive_server(r, *ev); break;
    case EV_BG_IDLE:
        if (ev->gen == c->bg_gen) {
            c->bg_left = 0; /* its background work is done: the core is the render threads' again */
            c->bg_rate = 0;
            bg_share(r->s, r->cl, r->now, &r->h);
        }
        break;
    case EV_WAKE: c->waking = 0; break;
    case EV_LAGGED:
        if (ev->gen == c->gen && c->lagging) {
            c->lagging = 0; /* waited: now the CPU work */
            c->busy = 1;
            group_share(r->s, r->cl, c->group, r->now, &r->h);
        }
        break;
    }
    if (go_on)
        start_idle(r, ev);
}

static void run(Sim *s)
{
    Run r = {.s = s, .cl = calloc((size_t)s->clients, sizeof *r.cl)};
    /* --cores: the clients (and the server) share that many cores; without
     * it every client has its own machine */
    s->shared = s->cores < 1e6;
    int groups = s->shared ? 1 : s->clients;
    s->group_cores = s->cores / groups;
    for (int i = 0; i < s->clients; i++) {
        r.cl[i].speed = s->nspeeds ? s->speeds[i % s->nspeeds] : 1.0;
        r.cl[i].up.tokens = r.cl[i].down.tokens = s->client_burst; /* tbf starts full */
        r.cl[i].group = i % groups;
    }
    SchedConfig cfg = {.width = (uint32_t)s->width, .height = (uint32_t)s->height,
                       .segment_lines = s->segment ? s->segment : 1, .tail = s->tail,
                       .min_pixels = (uint32_t)(s->width / 4 > 0 ? s->width / 4 : 1)};
    r.sc = sched_create(&cfg);
    r.spare = sched_create(&cfg);
    sched_set_clients(r.sc, (uint32_t)s->clients);
    sched_set_clients(r.spare, (uint32_t)s->clients);
    int measured = 0, started = 0, shown = 0;
    const int total = s->frames + 1; /* frame 0 is warm-up, as in the benchmark */
    double t_first = 0;
    frame_begin(&r, started++);
    while (shown < total && r.h.n) {
        Event ev = heap_pop(&r.h);
        r.now = ev.t;
        on_event(&r, &ev);
        /* frames shown in order, the older of two first; the clock starts
         * when the warm-up frame is shown */
        for (;;) {
            if (r.older && sched_frame_done(r.older)) {
                r.spare = r.older;
                r.older = NULL;
            } else if (!r.older && r.in_frame && sched_frame_done(r.sc)) {
                r.in_frame = 0;
            } else {
                break;
            }
            if (++shown == 1) {
                t_first = r.now;
                r.bytes = r.busy = 0;
            } else {
                measured++;
            }
        }
        if (!r.in_frame && started < total) {
            frame_begin(&r, started++);
        } else if (s->pipeline && r.in_frame && !r.older && !sched_has_fresh(r.sc) && started < total) {
            r.older = r.sc;
            r.older_id = r.newest;
            r.sc = r.spare;
            r.spare = NULL;
            sched_set_segment_lines(r.sc, sched_config(r.older)->segment_lines);
            frame_begin(&r, started++);
        }
    }
    double wall = r.now - t_first;
    SchedStats st = sched_stats(r.sc);
    const Sched *more[2] = {r.older, r.spare};
    for (int i = 0; i < 2; i++)
        if (more[i])
            st = sched_stats_sum(st, sched_stats(more[i]));
    printf("predicted fps=%.3f efficiency=%.4f dup_lines_per_frame=%.2f bytes_per_frame=%.0f segment_lines=%u\n",
           measured / (wall * 1e-6), r.busy / (s->clients * wall), (double)st.duplicate_pixels / s->width / (s->frames + 1),
           r.bytes / measured, sched_config(r.sc)->segment_lines);
    sched_destroy(r.sc);
    sched_destroy(r.older);
    sched_destroy(r.spare);
    free(r.h.e);
    free(r.cl);
}

/* --probe-slice: how long a runnable thread waits for a core on this
 * machine.  cores + 1 threads spin for a second reading the clock; a gap in
 * one thread's readings is time it was not running.  The median gap is what
 * a client woken on oversubscribed cores waits per round (one time slice). */
typedef struct {
    double gaps[4096];
    int n;
} Probe;

static void *probe_spin(void *arg)
{
    Probe *p = arg;
    double start = timer_now() * 1e6, last = start;
    while (last - start < 1e6) {
        double t = timer_now() * 1e6;
        if (t - last > 200 && p->n < 4096)
            p->gaps[p->n++] = t - last;
        last = t;
    }
    return NULL;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int probe_slice(int cores)
{
    int n = cores + 1;
    Probe *p = calloc((size_t)n, sizeof *p);
    pthread_t *th = calloc((size_t)n, sizeof *th);
    if (!p || !th)
        return 1;
    for (int i = 0; i < n; i++)
        pthread_create(&th[i], NULL, probe_spin, &p[i]);
    double *all = NULL;
    int total = 0;
    for (int i = 0; i < n; i++) {
        pthread_join(th[i], NULL);
        double *grown = realloc(all, (size_t)(total + p[i].n + 1) * sizeof *all);
        if (!grown)
            abort();
        all = grown;
        memcpy(all + total, p[i].gaps, (size_t)p[i].n * sizeof *all);
        total += p[i].n;
    }
    qsort(all, (size_t)total, sizeof *all, cmp_double);
    printf("slice_us=%.0f gaps=%d\n", total ? all[total / 2] : 0.0, total);
    free(all);
    free(p);
    free(th);
    return 0;
}

static int parse_speeds(const char *v, void *dst, Err *err)
{
    (void)err;
    Sim *s = dst;
    s->nspeeds = 0;
    const char *p = v;
    while (*p) {
        char *end;
        double d = strtod(p, &end);
        if (end == p || !(d > 0) || s->nspeeds >= MAXC)
            return -1;
        s->speeds[s->nspeeds++] = d;
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',')
            return -1;
    }
    return s->nspeeds ? 0 : -1;
}


/* What the command line says beyond the simulation's own numbers. */
static const char *const pipeline_words[] = {"off", "on", NULL};

typedef struct {
    const char *profile;
    int tail, probe, pipeline;
    double burst_kb;
} Args;

/* Parses the command line into s and a: OPT_GO, or the exit status. */
static int parse_args(Sim *s, Args *a, int argc, char **argv)
{
    *s = (Sim){.width = 1024, .clients = 1, .threads = 1, .frames = 3, .cores = 1e9, .latency_us = 50, .mbit = 10000,
               .overhead_us = 100, .segment = 16, .cost_scale = 1, .overhead_cpu = 1, .pixel_bytes = 3};
    *a = (Args){.tail = 1};
    const Opt opts[] = {
        {.name = "--profile", .kind = OPT_STRING, .dst = &a->profile, .arg = "FILE",
         .help = "per-line cost, 'line,microseconds' (lanray-render --profile); required"},
        {.name = "--width", .kind = OPT_INT, .dst = &s->width, .arg = "W", .lo = 1, .hi = 65536, .help = "frame width"},
        {.name = "--clients", .kind = OPT_INT, .dst = &s->clients, .arg = "N", .lo = 1, .hi = MAXC, .help = "clients"},
        {.name = "--threads", .kind = OPT_INT, .dst = &s->threads, .arg = "T", .lo = 1, .hi = 1024, .help = "threads per client"},
        {.name = "--cores", .kind = OPT_REAL, .dst = &s->cores, .arg = "C", .help = "cores the clients share", .def = "unlimited"},
        {.name = "--speeds", .kind = OPT_CUSTOM, .dst = s, .arg = "a,b,...", .parse = parse_speeds,
         .range = "positive numbers separated by commas", .help = "speed factor of each client", .def = "all 1"},
        {.name = "--segment", .kind = OPT_CUSTOM, .dst = &s->segment, .arg = "LINES|auto", .parse = cli_parse_segment,
         .range = CLI_SEGMENT_RANGE, .help = "lines per segment", .def = "16"},
        {.name = "--tail", .kind = OPT_CHOICE, .dst = &a->tail, .choices = sched_tail_names, .help = "tail rule"},
        {.name = "--frames", .kind = OPT_INT, .dst = &s->frames, .arg = "F", .lo = 1, .hi = 100000, .help = "frames to simulate"},
        {.name = "--latency-us", .kind = OPT_REAL, .dst = &s->latency_us, .arg = "L", .help = "one-way packet latency"},
        {.name = "--bandwidth-mbit", .kind = OPT_REAL, .dst = &s->mbit, .arg = "B", .help = "the server's link"},
        {.name = "--client-mbit", .kind = OPT_REAL, .dst = &s->client_mbit, .arg = "B2", .help = "each client's own link, 0 = none"},
        {.name = "--client-burst-kb", .kind = OPT_REAL, .dst = &a->burst_kb, .arg = "K", .help = "token bucket of a client's link"},
        {.name = "--overhead-us", .kind = OPT_REAL, .dst = &s->overhead_us, .arg = "O", .help = "per-segment overhead"},
        {.name = "--overhead-cpu", .kind = OPT_REAL, .dst = &s->overhead_cpu, .arg = "Q", .rlo = 0, .rhi = 1,
         .help = "part of the overhead that is CPU work"},
        {.name = "--bg-cpu-us", .kind = OPT_REAL, .dst = &s->bg_cpu_us, .arg = "G", .help = "CPU per segment outside the render threads"},
        {.name = "--slice-us", .kind = OPT_REAL, .dst = &s->slice_us, .arg = "S", .help = "the OS scheduler's time slice"},
        {.name = "--turnaround-us", .kind = OPT_REAL, .dst = &s->turnaround_us, .arg = "R", .help = "frame end to next UPDATE"},
        {.name = "--server-us", .kind = OPT_REAL, .dst = &s->server_us, .arg = "P", .help = "server CPU per DATA packet"},
        {.name = "--pixel-bytes", .kind = OPT_REAL, .dst = &s->pixel_bytes, .arg = "X", .rlo = 0, .rhi = 16,
         .help = "bytes a pixel in a DATA packet (3 raw; about 0.6 with --compress zstd)", .def = "3"},
        {.name = "--pipeline", .kind = OPT_CHOICE, .dst = &a->pipeline, .choices = pipeline_words,
         .help = "the next frame starts when the current one has no fresh work left (lanray-server --pipeline)",
         .def = "off"},
        {.name = "--cost-scale", .kind = OPT_REAL, .dst = &s->cost_scale, .arg = "K", .help = "multiplies the profile's costs"},
        {.name = "--probe-slice", .kind = OPT_INT, .dst = &a->probe, .arg = "C", .lo = 1, .hi = 4096,
         .help = "instead: measure the time slice S on C cores of this machine", .def = "off"},
        {0},
    };
    OptSpec spec = {.prog = "schedsim", .synopsis = "--profile lines.csv [options]",
                    .about = "Discrete-event simulation of a render farm driving the real scheduler (server/scheduler.c); see the\n"
                    "comment at the top of tools/schedsim.c and docs/scaling.md for the model.",
                    .opts = opts,
                    .exits = "  0  simulated\n  1  the profile could not be read\n  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    if (go == OPT_GO && !a->probe && !a->profile) {
        fprintf(stderr, "schedsim: needs --profile FILE (usage: %s %s)\n", spec.prog, spec.synopsis);
        return 2;
    }
    s->tail = sched_tail_rules[a->tail];
    s->pipeline = a->pipeline;
    s->client_burst = a->burst_kb * 1024;
    return go;
}

/* The per-line costs, and their running sum per pixel: 0, or 1. */
static int read_profile(Sim *s, const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "schedsim: cannot open %s\n", path);
        return 1;
    }
    int cap = 0, line;
    double us;
    while (fscanf(f, "%d,%lf", &line, &us) == 2) {
        if (s->height == cap) {
            cap = cap ? 2 * cap : 1024;
            s->line_us = realloc(s->line_us, (size_t)cap * sizeof *s->line_us);
        }
        s->line_us[s->height++] = us;
    }
    fclose(f);
    if (s->height < 1) {
        fprintf(stderr, "schedsim: %s has no lines\n", path);
        return 1;
    }
    s->prefix = malloc(((size_t)s->width * s->height + 1) * sizeof *s->prefix);
    s->prefix[0] = 0;
    for (size_t p = 0; p < (size_t)s->width * s->height; p++)
        s->prefix[p + 1] = s->prefix[p] + s->cost_scale * s->line_us[p / s->width] / s->width;
    return 0;
}

int main(int argc, char **argv)
{
    static Sim s; /* its speeds table is large */
    Args a;
    int rc = parse_args(&s, &a, argc, argv);
    if (rc != OPT_GO)
        return rc;
    if (a.probe)
        return probe_slice(a.probe);
    rc = read_profile(&s, a.profile);
    if (rc == 0)
        run(&s);
    free(s.line_us);
    free(s.prefix);
    return rc;
}
