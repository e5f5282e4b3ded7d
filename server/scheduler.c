/* scheduler.c - see scheduler.h. */
#include "scheduler.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    Segment seg;
    uint8_t done;
    uint32_t holders;
} Rec;

typedef struct {
    int client;
    uint32_t rec;
    uint64_t seq; /* assignment order: a client renders what it holds in this order */
} Assignment;

struct Sched {
    SchedConfig cfg;
    uint32_t frame, clients;
    uint32_t next_pixel, total, done_pixels;
    Rec *recs;
    uint32_t nrec, caprec;
    Assignment *asg;
    uint32_t nasg, capasg;
    uint64_t seq;
    SchedStats stats;
};

uint32_t sched_tail_static(uint32_t remaining, uint32_t seg, uint32_t clients, uint32_t min_pixels)
{
    (void)clients;
    (void)min_pixels;
    return seg < remaining ? seg : remaining;
}

uint32_t sched_tail_smart(uint32_t remaining, uint32_t seg, uint32_t clients, uint32_t min_pixels)
{
    (void)min_pixels;
    /* segments left at full size; the last clients/2 of them are halved */
    uint32_t left = (remaining + seg - 1) / seg;
    uint32_t size = left <= clients / 2 && seg > 1 ? seg / 2 : seg;
    return size < remaining ? size : remaining;
}

uint32_t sched_tail_adaptive(uint32_t remaining, uint32_t seg, uint32_t clients, uint32_t min_pixels)
{
    /* a fair share of what is left for every client, twice over (each holds two) */
    uint32_t share = remaining / (2 * (clients ? clients : 1));
    uint32_t size = share < seg ? share : seg;
    if (size < min_pixels)
        size = min_pixels;
    if (size == 0)
        size = 1;
    return size < remaining ? size : remaining;
}

const char *const sched_tail_names[] = {"static", "smart", "adaptive", NULL};
const SchedTailRule sched_tail_rules[] = {sched_tail_static, sched_tail_smart, sched_tail_adaptive};

SchedTailRule sched_tail_by_name(const char *name)
{
    for (int i = 0; sched_tail_names[i]; i++)
        if (strcmp(name, sched_tail_names[i]) == 0)
            return sched_tail_rules[i];
    return NULL;
}

Sched *sched_create(const SchedConfig *cfg)
{
    if (cfg->width < 1 || cfg->height < 1 || cfg->segment_lines < 1)
        return NULL;
    Sched *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->cfg = *cfg;
    if (!s->cfg.tail)
        s->cfg.tail = sched_tail_static;
    s->total = cfg->width * cfg->height;
    s->clients = 1;
    return s;
}

void sched_destroy(Sched *s)
{
    if (!s)
        return;
    free(s->recs);
    free(s->asg);
    free(s);
}

void sched_begin_frame(Sched *s, uint32_t frame)
{
    s->frame = frame;
    s->next_pixel = 0;
    s->done_pixels = 0;
    s->nrec = 0;
    s->nasg = 0;
}

void sched_set_clients(Sched *s, uint32_t clients) { s->clients = clients ? clients : 1; }

void sched_start_frame(Sched *s, uint32_t frame, uint32_t clients, int auto_size, double work_us, double overhead_us)
{
    if (auto_size)
        sched_set_segment_lines(s, sched_auto_lines(work_us, overhead_us, s->cfg.height, clients));
    sched_begin_frame(s, frame);
    sched_set_clients(s, clients);
}

void sched_set_segment_lines(Sched *s, uint32_t lines) { s->cfg.segment_lines = lines ? lines : 1; }

int sched_set_size(Sched *s, uint32_t width, uint32_t height)
{
    if (width < 1 || height < 1)
        return -1;
    s->cfg.width = width;
    s->cfg.height = height;
    s->total = width * height;
    return 0;
}

static int add_assignment(Sched *s, int client, uint32_t rec)
{
    if (s->nasg == s->capasg) {
        uint32_t cap = s->capasg ? 2 * s->capasg : 64;
        Assignment *p = realloc(s->asg, cap * sizeof *p);
        if (!p)
            return -1;
        s->asg = p;
        s->capasg = cap;
    }
    s->asg[s->nasg++] = (Assignment){client, rec, s->seq++};
    s->recs[rec].holders++;
    return 0;
}

static int holds(const Sched *s, int client, uint32_t rec)
{
    for (uint32_t i = 0; i < s->nasg; i++)
        if (s->asg[i].client == client && s->asg[i].rec == rec)
            return 1;
    return 0;
}

/* Every holder of rec still has an earlier-assigned segment of this frame to
 * render first (a segment nobody holds is not queued anywhere). */
static int queued(const Sched *s, uint32_t rec)
{
    int any = 0;
    for (uint32_t i = 0; i < s->nasg; i++) {
        const Assignment *a = &s->asg[i];
        if (a->rec != rec)
            continue;
        int behind = 0;
        for (uint32_t j = 0; j < s->nasg && !behind; j++)
            behind = s->asg[j].client == a->client && s->asg[j].seq < a->seq && !s->recs[s->asg[j].rec].done;
        if (!behind)
            return 0;
        any = 1;
    }
    return any;
}

/* A segment of pixels nobody was given yet, cut by the tail rule. */
static int assign_new(Sched *s, int client, Segment *out)
{
    if (s->next_pixel < s->total) {
        uint32_t remaining = s->total - s->next_pixel;
        uint32_t size = s->cfg.tail(remaining, s->cfg.segment_lines * s->cfg.width, s->clients, s->cfg.min_pixels);
        if (size < 1)
            size = 1;
        if (size > remaining)
            size = remaining;
        if (s->nrec == s->caprec) {
            uint32_t cap = s->caprec ? 2 * s->caprec : 256;
            Rec *p = realloc(s->recs, cap * sizeof *p);
            if (!p)
                return 0;
            s->recs = p;
            s->caprec = cap;
        }
        Rec *r = &s->recs[s->nrec];
        *r = (Rec){{s->next_pixel, size}, 0, 0};
        if (add_assignment(s, client, s->nrec))
            return 0;
        s->nrec++;
        s->next_pixel += size;
        s->stats.segments++;
        *out = r->seg;
        return 1;
    }
    return 0;
}

/* The newest segment whose holders all left (sched_release), which must be
 * given again before the frame can end: its record, or UINT32_MAX. */
static uint32_t orphan(const Sched *s)
{
    for (uint32_t i = s->nrec; i-- > 0;)
        if (!s->recs[i].done && s->recs[i].holders == 0)
            return i;
    return UINT32_MAX;
}

/* An orphaned segment again, the newest first, as assign_again chooses. */
static int assign_orphan(Sched *s, int client, Segment *out)
{
    const uint32_t i = orphan(s);
    if (i == UINT32_MAX || add_assignment(s, client, i))
        return 0;
    s->stats.reissued++;
    *out = s->recs[i].seg;
    return 1;
}

int sched_has_fresh(const Sched *s) { return s->next_pixel < s->total || orphan(s) != UINT32_MAX; }

int sched_assign_fresh(Sched *s, int client, Segment *out) { return assign_new(s, client, out) || assign_orphan(s, client, out); }

/* Nothing new: an outstanding segment again, the one with the fewest
 * holders; among those, one that waits in its holders' queues behind
 * another of their segments (it will be the last to come back), else
 * the newest. */
static int assign_again(Sched *s, int client, Segment *out)
{
    uint32_t best = UINT32_MAX;
    int best_queued = 0;
    for (uint32_t i = 0; i < s->nrec; i++) {
        const Rec *r = &s->recs[i];
        if (r->done || holds(s, client, i))
            continue;
        int q = queued(s, i);
        if (best == UINT32_MAX || r->holders < s->recs[best].holders ||
            (r->holders == s->recs[best].holders && q >= best_queued)) {
            best = i;
            best_queued = q;
        }
    }
    if (best == UINT32_MAX || add_assignment(s, client, best))
        return 0;
    s->stats.reissued++;
    *out = s->recs[best].seg;
    return 1;
}

int sched_assign(Sched *s, int client, Segment *out) { return assign_new(s, client, out) || assign_again(s, client, out); }

/* The assignment of seg to client in the current frame: its index, or -1. */
static int32_t find_assignment(const Sched *s, int client, Segment seg)
{
    for (uint32_t i = 0; i < s->nasg; i++) {
        const Assignment *a = &s->asg[i];
        const Rec *r = &s->recs[a->rec];
        if (a->client == client && r->seg.first == seg.first && r->seg.count == seg.count)
            return (int32_t)i;
    }
    return -1;
}

SchedResult sched_check(const Sched *s, int client, uint32_t frame, Segment seg)
{
    if (frame != s->frame)
        return SCHED_STALE;
    const int32_t i = find_assignment(s, client, seg);
    if (i < 0)
        return SCHED_UNKNOWN;
    return s->recs[s->asg[i].rec].done ? SCHED_DUPLICATE : SCHED_ACCEPT;
}

SchedResult sched_complete(Sched *s, int client, uint32_t frame, Segment seg)
{
    if (frame != s->frame)
        return SCHED_STALE;
    const int32_t i = find_assignment(s, client, seg);
    if (i < 0)
        return SCHED_UNKNOWN;
    Rec *r = &s->recs[s->asg[i].rec];
    r->holders--;
    s->asg[i] = s->asg[--s->nasg];
    if (r->done) {
        s->stats.duplicate_pixels += seg.count;
        return SCHED_DUPLICATE;
    }
    r->done = 1;
    s->done_pixels += seg.count;
    return SCHED_ACCEPT;
}

uint32_t sched_top_up(Sched *s, int client, Segment out[SCHED_IN_FLIGHT])
{
    Sched *from[SCHED_IN_FLIGHT];
    return sched_top_up_pair(s, NULL, client, out, from);
}

uint32_t sched_top_up_pair(Sched *older, Sched *newer, int client, Segment out[SCHED_IN_FLIGHT],
                           Sched *from[SCHED_IN_FLIGHT])
{
    uint32_t held = (older ? sched_held(older, client) : 0) + (newer ? sched_held(newer, client) : 0), n = 0;
    /* the older frame is shown first: its new pixels, then the newer
     * frame's, and only when neither has any left, outstanding segments
     * again (the older's first) */
    Sched *order[4] = {older, newer, older, newer};
    for (int k = 0; k < 4 && held + n < SCHED_IN_FLIGHT; k++) {
        Sched *s = order[k];
        while (s && held + n < SCHED_IN_FLIGHT && (k < 2 ? sched_assign_fresh(s, client, &out[n]) : assign_again(s, client, &out[n])))
            from[n++] = s;
    }
    return n;
}

void sched_release(Sched *s, int client)
{
    for (uint32_t i = 0; i < s->nasg;) {
        if (s->asg[i].client == client) {
            s->recs[s->asg[i].rec].holders--;
            s->asg[i] = s->asg[--s->nasg];
        } else {
            i++;
        }
    }
}

int sched_frame_done(const Sched *s) { return s->done_pixels == s->total; }

uint32_t sched_held(const Sched *s, int client)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nasg; i++)
        n += s->asg[i].client == client;
    return n;
}

uint32_t sched_frame(const Sched *s) { return s->frame; }
const SchedConfig *sched_config(const Sched *s) { return &s->cfg; }
SchedStats sched_stats(const Sched *s) { return s->stats; }

/* A segment of render time tau costs a fixed overhead o (packets,
 * scheduling, waking the client's thread pool) and, at the end of a frame,
 * leaves clients idle for about tau while the last segments finish.  Per
 * frame of work W on N clients that is o*W/(N*tau) + tau, smallest at
 * tau = sqrt(o*W/N).  The result is rounded to a power of two and kept to
 * at most half a frame per client; before anything is measured it is a
 * sixteenth of the frame per client. */
uint32_t sched_auto_lines(double work_us, double overhead_us, uint32_t height, uint32_t clients)
{
    if (clients < 1)
        clients = 1;
    uint32_t most = height / (2 * clients) > 0 ? height / (2 * clients) : 1;
    if (work_us <= 0) {
        uint32_t l = height / (16 * clients);
        return l < 1 ? 1 : (l > most ? most : l);
    }
    double tau = sqrt(overhead_us * work_us / clients);
    double line_us = work_us / height;
    double lines = tau / line_us;
    uint32_t p = 1;
    while (p * 2 <= most && (double)(p * 2) <= lines * 1.4142)
        p *= 2;
    return p;
}
