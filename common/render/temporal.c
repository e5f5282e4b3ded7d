/* temporal.c - the reprojected history of temporal.h. */
#include "render/temporal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/srgb.h"
#include "render/denoise.h"
#include "render/pixel.h"
#include "scene/world.h"

/* A pixel as the history holds it: its light (linear, as its codes say),
 * the mean square of its luminance, the frames (samples) it weighs, and
 * its surface's distance (0: none) and normal, to find it again. */
typedef struct {
    float c[3], m2, len, depth, n[3];
    float alb[3], an[3]; /* the albedo and the normal its guide shows, added up as the light */
} Hist;

/* A frame of the history: its pixels and the camera they were seen by. */
typedef struct {
    Hist *px;
    CameraFrame cam;
} HistFrame;

/* An instance's move from the frame before to this one: where it placed
 * its model then and now. */
typedef struct {
    int moved;
    WorldInstance then, now;
} Move;

struct Temporal {
    Pool *pool;
    Instance *placed; /* the instances as the frame before placed them */
    Move *moves;      /* ... and each one's move since */
    uint32_t placed_count, placed_cap, moves_cap;
    float *light; /* the frame's own light, 3 floats a pixel, for its neighbours' clip */
    uint32_t max_w, max_h;
    int frames;
    HistFrame f[2];
    int prev, base; /* the last frame's, and under still frames the last moving frame's (-1: none) */
    int in_still;   /* the last frame was a still one */
    uint64_t epoch;
};

/* A surface seen again: distances within this share, normals whose cosine is above this. */
#define SAME_DEPTH 0.05f
#define SAME_NORMAL 0.9f
/* The frames a pixel's temporal noise needs before the denoiser reads it. */
#define NOISE_FRAMES 4.0f

uint64_t temporal_bytes(uint32_t max_w, uint32_t max_h)
{
    return (uint64_t)max_w * max_h * (2 * sizeof(Hist) + 3 * sizeof(float));
}

Temporal *temporal_create(Pool *pool, uint32_t max_w, uint32_t max_h, int frames)
{
    if (frames < 1 || frames > TEMPORAL_MAX_FRAMES || max_w < 1 || max_h < 1 || max_w > 1u << 16 || max_h > 1u << 16)
        return NULL;
    Temporal *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    *t = (Temporal){.pool = pool, .max_w = max_w, .max_h = max_h, .frames = frames, .prev = -1, .base = -1};
    for (int k = 0; k < 2; k++)
        if (!(t->f[k].px = malloc((size_t)max_w * max_h * sizeof(Hist)))) {
            temporal_destroy(t);
            return NULL;
        }
    if (!(t->light = malloc((size_t)max_w * max_h * 3 * sizeof(float)))) {
        temporal_destroy(t);
        return NULL;
    }
    return t;
}

void temporal_destroy(Temporal *t)
{
    if (!t)
        return;
    for (int k = 0; k < 2; k++)
        free(t->f[k].px);
    free(t->light);
    free(t->placed);
    free(t->moves);
    free(t);
}

static inline float luminance(const float c[3]) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

/* What a pixel of the frame before must have seen to count: a surface at
 * distance d (within SAME_DEPTH) facing n; at an edge (the pixel's 3 x 3
 * saw surfaces at distances lo to hi further apart than that, or facing
 * other ways), any surface between those distances (unless the point was
 * hidden then: history_at), so that the edge's pixels add up what their
 * samples meet on either side (its anti-aliasing) where the test of one
 * surface would start them again at every frame that meets the other. */
typedef struct {
    float d, lo, hi, n[3];
    int edge;
    int open; /* its 3 x 3 also saw the background or an emitter (no distance): those count too */
} Seen;

/* Pixel (x, y) of frame src where it saw what `seen` asks, else NULL. */
static const Hist *seen_there(const HistFrame *src, int x, int y, const Seen *seen)
{
    if (x < 0 || y < 0 || x >= src->cam.width || y >= src->cam.height)
        return NULL;
    const Hist *q = &src->px[(size_t)y * (size_t)src->cam.width + (size_t)x];
    if (!(q->len > 0.0f) || (!(q->depth > 0.0f) && !seen->open))
        return NULL;
    if (q->depth > 0.0f &&
        (seen->edge ? q->depth < seen->lo || q->depth > seen->hi
                    : fabsf(q->depth - seen->d) > SAME_DEPTH * (q->depth > seen->d ? q->depth : seen->d) ||
                          q->n[0] * seen->n[0] + q->n[1] * seen->n[1] + q->n[2] * seen->n[2] < SAME_NORMAL))
        return NULL;
    return q;
}

/* Pixel (x, y) of frame src added to acc by weight wt where it saw what
 * `seen` asks: the weight it added. */
static float tap(const HistFrame *src, int x, int y, const Seen *seen, float wt, Hist *acc)
{
    const Hist *q = wt > 0.0f ? seen_there(src, x, y, seen) : NULL;
    if (!q)
        return 0.0f;
    for (int k = 0; k < 3; k++) {
        acc->c[k] += wt * q->c[k];
        acc->alb[k] += wt * q->alb[k];
        acc->an[k] += wt * q->an[k];
    }
    acc->m2 += wt * q->m2;
    acc->len += wt * q->len;
    return wt;
}

/* Catmull-Rom's weights of the four taps about t in [0, 1). */
static void cubic_weights(float t, float w[4])
{
    w[0] = t * (-0.5f + t * (1.0f - 0.5f * t));
    w[1] = 1.0f + t * t * (-2.5f + 1.5f * t);
    w[2] = t * (0.5f + t * (2.0f - 1.5f * t));
    w[3] = t * t * (-0.5f + 0.5f * t);
}

/* acc's light (the four taps' bilinear sum, their weights summing to 1)
 * made the 4 x 4 taps' cubic where all of them saw what `seen` asks,
 * within the four's lights channel by channel. */
static void cubic_light(const HistFrame *src, int x0, int y0, float ax, float ay, const Seen *seen, Hist *acc)
{
    float wx[4], wy[4], c[3] = {0, 0, 0}, lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {0, 0, 0};
    cubic_weights(ax, wx);
    cubic_weights(ay, wy);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            const Hist *q = seen_there(src, x0 - 1 + i, y0 - 1 + j, seen);
            if (!q)
                return;
            const float w = wx[i] * wy[j];
            for (int k = 0; k < 3; k++) {
                c[k] += w * q->c[k];
                if ((i == 1 || i == 2) && (j == 1 || j == 2)) {
                    lo[k] = q->c[k] < lo[k] ? q->c[k] : lo[k];
                    hi[k] = q->c[k] > hi[k] ? q->c[k] : hi[k];
                }
            }
        }
    const float wsum = (wx[0] + wx[1] + wx[2] + wx[3]) * (wy[0] + wy[1] + wy[2] + wy[3]);
    for (int k = 0; k < 3; k++) {
        const float v = c[k] / wsum;
        acc->c[k] = v < lo[k] ? lo[k] : v > hi[k] ? hi[k] : v;
    }
}

/* What the history held of the surface point p (seen from the frame
 * before's camera at `seen`'s distances) in frame src: its pixels about
 * p's position weighed bilinearly where they saw it; 0 where none did. */
static int history_at(const HistFrame *src, vec3 p, Seen *seen, Hist *out)
{
    real x, y, dist;
    if (!camera_project(&src->cam, p, &x, &y, &dist))
        return 0;
    const int w = src->cam.width, h = src->cam.height;
    const real fx = x - R(0.5), fy = y - R(0.5);
    if (!(fx > R(-1)) || !(fy > R(-1)) || !(fx < (real)w) || !(fy < (real)h))
        return 0;
    /* the distances as the frame before's camera sees them: moved by what p's moved */
    const float d = (float)dist, shift = d - seen->d;
    seen->d = d, seen->lo = (seen->lo + shift) * (1.0f - SAME_DEPTH), seen->hi = (seen->hi + shift) * (1.0f + SAME_DEPTH);
    const int xn = (int)floor(x), yn = (int)floor(y);
    if (seen->edge && xn >= 0 && yn >= 0 && xn < w && yn < h) {
        /* the frame before saw a nearer surface there: p was hidden (a
         * surface coming out from behind an edge), not one side of it */
        const float dn = src->px[(size_t)yn * (size_t)w + (size_t)xn].depth;
        if (dn > 0.0f && dn < d * (1.0f - 2.0f * SAME_DEPTH))
            return 0;
    }
    const int x0 = (int)floor(fx), y0 = (int)floor(fy);
    const float ax = (float)(fx - (real)x0), ay = (float)(fy - (real)y0);
    float wsum = 0.0f;
    Hist acc;
    memset(&acc, 0, sizeof acc);
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++)
            wsum += tap(src, x0 + i, y0 + j, seen, (i ? ax : 1.0f - ax) * (j ? ay : 1.0f - ay), &acc);
    /* all sixteen about it saw it (inside a surface): its light by
     * Catmull-Rom's cubic, sharper than the four's bilinear mean (which,
     * taken again every frame, softened a texture), kept within the four's
     * lights (the cubic overshoots at a step) */
    if (wsum > 0.999f)
        cubic_light(src, x0, y0, ax, ay, seen, &acc);
    /* none of the four saw it: the 3 x 3 about the nearest that did, alike */
    for (int j = -1; j <= 1 && !(wsum > 1e-3f); j++)
        for (int i = -1; i <= 1; i++)
            wsum += tap(src, xn + i, yn + j, seen, 1.0f, &acc);
    if (!(wsum > 1e-3f))
        return 0;
    const float inv = 1.0f / wsum;
    for (int k = 0; k < 3; k++) {
        out->c[k] = acc.c[k] * inv;
        out->alb[k] = acc.alb[k] * inv;
        out->an[k] = acc.an[k] * inv;
    }
    out->m2 = acc.m2 * inv;
    out->len = acc.len * inv;
    return 1;
}

/* One frame's pass: the frame, the history it reads (NULL: none) and the one it writes. */
typedef struct {
    uint8_t *px;
    uint32_t w, h, cb, bpp;
    int linear;
    const TemporalFrame *f;
    float *light;
    const HistFrame *src;
    HistFrame *dst;
    float frames;
    float detail; /* the history's pixels over the frame's, at most 1 */
    const Move *moves; /* the instances' since the history's frame */
    uint32_t move_count;
} Pass;

/* The mean square of a pixel's luminance from its mean and its guide's
 * noise (the standard error of the mean over it, of `samples` samples). */
static float mean_square(float lum, float noise, float samples)
{
    const float se = noise > 0.0f ? noise * lum : 0.0f;
    return lum * lum + se * se * samples;
}

/* Rows [lo, hi): the pixels' guides read into the history written: their
 * surfaces (distance, normal) for their neighbours' edges, and until
 * pass_pixel reads them their albedo (alb) and noise (m2). */
static void pass_guides(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    for (size_t i = (size_t)lo * ps->w; i < (size_t)hi * ps->w; i++) {
        Hist *o = &ps->dst->px[i];
        denoise_guide_unpack(ps->px + i * ps->bpp + ps->cb, o->alb, o->n, &o->depth, &o->m2);
        if (ps->f->clip)
            pixel_read_colour(ps->px + i * ps->bpp, ps->cb, ps->linear, ps->light + 3 * i);
    }
}

/* The surface pixel (x, y) saw, and whether its 3 x 3 is an edge.  A
 * pixel that saw no surface (the background, an emitter: no distance)
 * beside ones that did is an open edge, taken at the farthest of their
 * distances (a lamp in a ceiling moves with the ceiling, the sky beside a
 * silhouette with it); d 0: none around either (it shows as it is). */
static Seen seen_at(const Pass *ps, uint32_t x, uint32_t y)
{
    const Hist *o = &ps->dst->px[(size_t)y * ps->w + x];
    Seen s = {o->depth, FLT_MAX, 0.0f, {o->n[0], o->n[1], o->n[2]}, 0, 0};
    const int own = o->depth > 0.0f;
    for (uint32_t j = y > 0 ? y - 1 : 0; j <= y + 1 && j < ps->h; j++)
        for (uint32_t i = x > 0 ? x - 1 : 0; i <= x + 1 && i < ps->w; i++) {
            const Hist *q = &ps->dst->px[(size_t)j * ps->w + i];
            if (!(q->depth > 0.0f)) {
                s.open = 1;
                continue;
            }
            s.lo = q->depth < s.lo ? q->depth : s.lo, s.hi = q->depth > s.hi ? q->depth : s.hi;
            s.edge |= own && q->n[0] * s.n[0] + q->n[1] * s.n[1] + q->n[2] * s.n[2] < SAME_NORMAL;
        }
    if (!(s.hi > 0.0f)) /* no surface in the 3 x 3 */
        return (Seen){0};
    s.edge |= s.open || s.hi > s.lo * (1.0f + 2.0f * SAME_DEPTH);
    if (!own)
        s.d = s.hi;
    return s;
}

/* Light c held within the frame's own light about pixel (x, y), channel
 * by channel (its 3 x 3's least and most): what the history kept that the
 * frame no longer shows (a highlight or a reflection that moved with the
 * view) goes, where one frame's noise (a penumbra's) leaves the range
 * wide. */
static void clip_light(const Pass *ps, uint32_t x, uint32_t y, float c[3])
{
    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (uint32_t j = y > 0 ? y - 1 : 0; j <= y + 1 && j < ps->h; j++)
        for (uint32_t i = x > 0 ? x - 1 : 0; i <= x + 1 && i < ps->w; i++) {
            const float *q = ps->light + 3 * ((size_t)j * ps->w + i);
            for (int k = 0; k < 3; k++) {
                lo[k] = q[k] < lo[k] ? q[k] : lo[k];
                hi[k] = q[k] > hi[k] ? q[k] : hi[k];
            }
        }
    for (int k = 0; k < 3; k++)
        c[k] = c[k] < lo[k] ? lo[k] : c[k] > hi[k] ? hi[k] : c[k];
}

/* Where a point (direction) of the instance that moved by m was in the frame before. */
static vec3 moved_back(const Move *m, vec3 p)
{
    const vec3 local = v3_scale(m3_apply_t(&m->now.rot, v3_sub(p, m->now.translate)), R(1) / m->now.scale);
    return world_instance_point(&m->then, local);
}
static vec3 turned_back(const Move *m, vec3 d) { return m3_apply(&m->then.rot, m3_apply_t(&m->now.rot, d)); }

/* The move of the instance pixel p's guide names since the frame before, or NULL. */
static const Move *pixel_move(const Pass *ps, const uint8_t *p)
{
    const uint32_t inst = denoise_guide_instance(p + ps->cb);
    return inst > 0 && inst <= ps->move_count && ps->moves[inst - 1].moved ? &ps->moves[inst - 1] : NULL;
}

static void pass_pixel(const Pass *ps, uint32_t x, uint32_t y)
{
    const size_t i = (size_t)y * ps->w + x;
    uint8_t *p = ps->px + i * ps->bpp;
    Hist *o = &ps->dst->px[i];
    float c[3];
    const float albedo[3] = {o->alb[0], o->alb[1], o->alb[2]}, n[3] = {o->n[0], o->n[1], o->n[2]}, noise = o->m2;
    pixel_read_colour(p, ps->cb, ps->linear, c);
    const float s = (float)ps->f->samples, lum = luminance(c);
    Hist h;
    int found = 0;
    vec3 org, dir;
    Seen seen = ps->src ? seen_at(ps, x, y) : (Seen){0};
    if (seen.d > 0.0f && camera_ray(&ps->dst->cam, (real)x + R(0.5), (real)y + R(0.5), &org, &dir)) {
        vec3 at = v3_madd(org, dir, (real)seen.d);
        const Move *m = pixel_move(ps, p);
        if (m) { /* a moving model's point, and its normal, where they were */
            at = moved_back(m, at);
            const vec3 n0 = turned_back(m, v3((real)seen.n[0], (real)seen.n[1], (real)seen.n[2]));
            seen.n[0] = (float)n0.x, seen.n[1] = (float)n0.y, seen.n[2] = (float)n0.z;
        }
        found = history_at(ps->src, at, &seen, &h);
    }
    /* a history of fewer pixels (a coarser render scale) has less of this
     * pixel's detail: it counts as fewer frames to a moving frame, which
     * brings that detail; a still frame (whole, after a scaled flight)
     * takes it by its samples alone, so that stopping shows the smooth
     * history until the still frame's own samples are as many */
    if (found && !ps->f->still)
        h.len *= ps->detail;
    if (found && ps->f->clip)
        clip_light(ps, x, y, h.c);
    if (!found || (ps->f->still && s >= h.len)) { /* the frame's own bytes */
        memcpy(o->c, c, sizeof c);
        memcpy(o->alb, albedo, sizeof albedo);
        memcpy(o->an, n, sizeof n);
        o->m2 = mean_square(lum, noise, s);
        o->len = s < ps->frames ? s : ps->frames;
        return;
    }
    /* a moving frame's s samples weigh s/len, len the samples so far (at
     * most `frames`: one a frame at one sample a pixel); a still frame's
     * by their share of all */
    const float len = h.len + s < ps->frames ? h.len + s : ps->frames;
    const float a = ps->f->still ? s / (h.len + s) : s < len ? s / len : 1.0f;
    for (int k = 0; k < 3; k++) {
        o->c[k] = h.c[k] + (c[k] - h.c[k]) * a;
        o->alb[k] = h.alb[k] + (albedo[k] - h.alb[k]) * a;
        o->an[k] = h.an[k] + (n[k] - h.an[k]) * a;
    }
    o->m2 = h.m2 + (mean_square(lum, noise, s) - h.m2) * a;
    o->len = len;
    /* the codes' light is already past the exposure and the view transform */
    pixel_put_colour(p, v3((real)o->c[0], (real)o->c[1], (real)o->c[2]), ps->cb == 4, R(1), TONEMAP_NONE, ps->linear);
    for (int k = 0; k < 3; k++)
        p[ps->cb + k] = linear_encode8((real)o->alb[k]);
    denoise_normal_pack(v3((real)o->an[0], (real)o->an[1], (real)o->an[2]), p + ps->cb + 3);
    const float mean = luminance(o->c), var = o->m2 - mean * mean;
    p[ps->cb + 8] =
        len >= NOISE_FRAMES ? denoise_noise_code(mean > 0.0f && var > 0.0f ? sqrtf(var / len) / mean : 0.0f) : 0;
}

static void pass_rows(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    for (uint64_t y = lo; y < hi; y++)
        for (uint32_t x = 0; x < ps->w; x++)
            pass_pixel(ps, x, (uint32_t)y);
}

/* Each instance's move from the frame before's placement (t->placed) to
 * frame f's (instances that were not there then: none), and f's kept for
 * the next: how many moves there are (0 where memory for them ran out:
 * the history then follows no instance). */
static uint32_t place_instances(Temporal *t, const TemporalFrame *f)
{
    const uint32_t n = f->instance_count;
    if (n > t->moves_cap) {
        Move *m = realloc(t->moves, n * sizeof *m);
        if (!m) {
            t->placed_count = 0;
            return 0;
        }
        t->moves = m, t->moves_cap = n;
    }
    for (uint32_t k = 0; k < n; k++) {
        const Instance *a = k < t->placed_count ? &t->placed[k] : NULL, *b = &f->instances[k];
        Move *m = &t->moves[k];
        m->moved = a && (!v3_same(a->translate, b->translate) || !v3_same(a->rotate, b->rotate) || a->scale != b->scale);
        if (m->moved)
            m->then = world_instance_derive(a), m->now = world_instance_derive(b);
    }
    t->placed_count = instances_copy(&t->placed, &t->placed_cap, f->instances, n);
    return n;
}

int temporal_add(Temporal *t, uint8_t *px, uint32_t w, uint32_t h, uint32_t colour_bytes, int linear,
                 const TemporalFrame *f)
{
    if (w < 1 || h < 1 || w > t->max_w || h > t->max_h)
        return -1;
    if (f->epoch != t->epoch)
        t->prev = t->base = -1, t->in_still = 0, t->placed_count = 0;
    t->epoch = f->epoch;
    const uint32_t moves = place_instances(t, f);
    /* a still frame reads the last moving frame's history (its own samples
     * add up apart); a moving frame the last frame's, whichever it was */
    if (!f->still)
        t->in_still = 0;
    else if (!t->in_still)
        t->in_still = 1, t->base = t->prev;
    /* two frames serve: the one read, and the other written (under still
     * frames the last moving frame's is read by each, the other rewritten) */
    const int src = f->still ? t->base : t->prev, dst = src == 0 ? 1 : 0;
    t->f[dst].cam = camera_frame(&f->camera, (int)w, (int)h);
    Pass ps = {px, w, h, colour_bytes, colour_bytes + DENOISE_GUIDE_BYTES, linear, f, t->light,
               src >= 0 ? &t->f[src] : NULL, &t->f[dst], (float)t->frames, 1.0f, t->moves, moves};
    if (src >= 0 && (double)t->f[src].cam.width * t->f[src].cam.height < (double)w * h)
        ps.detail = (float)((double)t->f[src].cam.width * t->f[src].cam.height / ((double)w * h));
    pool_for(t->pool, h, 8, pass_guides, &ps);
    pool_for(t->pool, h, 8, pass_rows, &ps);
    t->prev = dst;
    return 0;
}
