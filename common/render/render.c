/* render.c - the per-pixel sampling (regular N x N grid, or adaptive: one
 * sample, then N x N where a 4-neighbour saw another key or a contrasting
 * colour), run over chunks of pixels on a thread pool (pool.h). */
#include "render/render.h"

#include "base/sample.h"
#include "base/sample_lanes.h"

#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "geom/camera.h"
#include "base/pool.h"
#include "base/srgb.h"

/* Pixels per work item: enough items for every thread to keep busy to the
 * end of a span (CHUNK_PER_THREAD of them each), as few as that allows:
 * each item is an atomic step of a counter the threads share, and its
 * pixels' bytes share cache lines with the next item's.  At 32 pixels an
 * item, a 1024x768 frame on two threads took 24576 steps, and scaled 1.7
 * times from one thread where Embree's harness (a line an item) scaled 2. */
#define CHUNK_MIN 32
#define CHUNK_MAX 1024
#define CHUNK_PER_THREAD 16

typedef void (*JobFn)(void *ctx, uint32_t chunk, RayStats *stats);

typedef struct {
    RayStats s;
    char pad[64 - sizeof(RayStats)]; /* one cache line per thread: no false sharing */
} PaddedStats;

/* The threads (pool.h), each thread's ray counts, and who watches them. */
struct RenderPool {
    Pool *pool;
    PaddedStats *stats;
    RenderProgress *progress;
};

RenderPool *render_pool_create(int threads, Err *err)
{
    if (threads < 1 || threads > RENDER_MAX_THREADS) {
        err_set(err, "render: %d threads out of range 1..%d", threads, RENDER_MAX_THREADS);
        return NULL;
    }
    RenderPool *p = calloc(1, sizeof *p);
    if (!p || !(p->stats = aligned_alloc(64, (size_t)threads * sizeof *p->stats))) {
        free(p);
        err_set(err, "render: out of memory");
        return NULL;
    }
    if (!(p->pool = pool_create(threads, err))) {
        free(p->stats);
        free(p);
        return NULL;
    }
    return p;
}

void render_pool_destroy(RenderPool *p)
{
    if (!p)
        return;
    pool_destroy(p->pool);
    free(p->stats);
    free(p);
}

int render_pool_threads(const RenderPool *p) { return pool_threads(p->pool); }
Pool *render_pool_pool(RenderPool *p) { return p->pool; }
void render_pool_watch(RenderPool *p, RenderProgress *progress) { p->progress = progress; }

typedef struct {
    JobFn fn;
    void *ctx;
    PaddedStats *stats;
} Counted;

static void counted_job(void *ctx, uint32_t chunk, int thread)
{
    Counted *c = ctx;
    c->fn(c->ctx, chunk, &c->stats[thread].s);
}

/* Runs fn over chunks [0, chunks) on the pool; returns the summed stats. */
static RayStats pool_run_counted(RenderPool *p, JobFn fn, void *ctx, uint32_t chunks)
{
    int n = pool_threads(p->pool);
    memset(p->stats, 0, (size_t)n * sizeof *p->stats);
    Counted c = {fn, ctx, p->stats};
    pool_run(p->pool, counted_job, &c, chunks);
    RayStats total = {0, 0, 0};
    for (int i = 0; i < n; i++)
        ray_stats_add(&total, p->stats[i].s);
    return total;
}

typedef struct {
    const World *w;
    CameraFrame cam;
    int width;
    uint64_t first, count; /* the span, in pixels */
    uint8_t *pixels;
    const atomic_int *cancel;
    RenderProgress *progress;
    int linear; /* write linear codes instead of sRGB (--linear) */
    int diffs;  /* the scene has textures or checkers: camera rays carry differentials (raydiff.h) */
    int bpp;    /* bytes a pixel: its colour, then its guide where guided */
    int cbpp;   /* bytes of its colour: 3 codes, or 4 of RGBE (settings hdr) */
    int guided; /* settings denoise or guides: each pixel's guide after its colour (render/denoise.h) */
    uint32_t chunk; /* pixels per work item (chunk_size) */
    /* the grid's pairs of whole lines (job_tiles): from line tile_line on,
     * each pair cut into blocks of tile_cols columns */
    uint64_t tile_line;
    uint32_t tile_cols, tile_blocks;
    real gain;  /* 2^exposure, for the codes */
    Tonemap tonemap; /* ... and their view transform */
    /* path, N x N of N = 2^prog_m (progressive.h; 0: not in batches):
     * each pixel's samples [s0, s1) in their progressive order, written as
     * their sums (sums: settings batch) or as the pixel they make */
    int prog_m, sums;
    uint32_t s0, s1;
    int grid_n; /* the grid's N x N positions a pixel: settings aa, or 32 for a jittered frame's one sample */
    /* adaptive mode: keys and centre colours, as written, of whole lines key_first .. key_first + key_lines - 1 */
    int key_first, key_lines;
    int probe;         /* adaptive light sampling: the centre samples probe each area light (SampleId.probe) */
    uint64_t key_mask;  /* the bits of a key that refines() compares with the 4 neighbours' */
    uint64_t area_mask; /* the area lights' bits of a key (compared with the 8 neighbours') */
    int colour_test;   /* refines() compares colours too */
    int contrast;      /* ... differing by more than this many codes in a channel (settings contrast) */
    uint64_t *keys;
    uint8_t *colors; /* 3 codes per pixel: the key lines' centre samples, compared for contrast */
    uint8_t *centre; /* their pixels (bpp per pixel); colors itself when bpp is 3 */
} Frame;

static int cancelled(const Frame *f) { return f->cancel && atomic_load_explicit(f->cancel, memory_order_relaxed); }

/* n <= TRACE_PACKET sample positions: where they are in the image, which
 * of their pixel's `per_pixel` positions each is (pos, NULL: the first),
 * and the step to the next position (their footprint: 1 for one sample a
 * pixel, 1/N for N x N). */
typedef struct {
    const real *xs, *ys;
    const uint32_t *pos;
    const uint32_t *keys; /* each position's pixel's key (pixel_key), or NULL: made from xs, ys */
    uint32_t per_pixel;
    real step;
    int n;
    int probe; /* adaptive light sampling's first pass: one point of each area light (SampleId.probe) */
} Samples;

/* The key of the pixel that holds image position (x, y). */
static uint32_t pixel_key(real x, real y)
{
    return sample_mix(sample_hash((uint32_t)(int64_t)floor(x)), (uint32_t)(int64_t)floor(y));
}

/* The samples (base/sample.h) of the camera rays at the positions, where
 * the scene draws random numbers (area lights, rough mirrors, a lens, the
 * path integrator's bounces), else NULL.  Per effect, each position its
 * own key; one budget, the pixel's key and the position's number among
 * the pixel's. */
static const SampleId *sample_ids(const Frame *f, const Samples *sm, SampleId *ids)
{
    if (!world_uses(f->w, FEAT_AREA | FEAT_ROUGH | FEAT_LENS) && f->w->view.settings.integrator != INTEGRATOR_PATH)
        return NULL;
    for (int i = 0; i < sm->n; i++) {
        ids[i] = f->w->view.settings.sampling == SAMPLING_PRODUCT
                     ? (SampleId){.key = sample_seed(sm->xs[i], sm->ys[i]), .index = 0, .count = 1}
                     : (SampleId){.key = sm->keys ? sm->keys[i] : pixel_key(sm->xs[i], sm->ys[i]),
                                  .index = sm->pos ? sm->pos[i] : 0,
                                  .count = sm->per_pixel};
        if (sm->probe) {
            ids[i].probe = 1;
            ids[i].px = (uint16_t)(int64_t)floor(sm->xs[i]);
            ids[i].py = (uint16_t)(int64_t)floor(sm->ys[i]);
        }
    }
    return ids;
}

/* The differentials of the camera rays through the positions, to the
 * positions a step on; NULL where the scene has no textures.  The
 * pinhole's by its formula (also for a lens: the footprint in the plane of
 * focus), an orthographic camera's origin moves, a fisheye's by finite
 * differences (towards the centre where a step leaves its circle). */
static const RayDiff *camera_diffs(const Frame *f, const real *xs, const real *ys, int n, real step, RayDiff *out)
{
    if (!f->diffs)
        return NULL;
    const CameraFrame *c = &f->cam;
    for (int i = 0; i < n; i++) {
        RayDiff *d = &out[i];
        d->dox = d->doy = d->ddx = d->ddy = v3_splat(0);
        d->w0 = d->spread = R(0);
        if (c->kind == CAMERA_ORTHO) {
            d->dox = v3_scale(c->u, step);
            d->doy = v3_scale(c->v, step);
        } else if (c->kind == CAMERA_FISHEYE) {
            vec3 o, d0, d1;
            if (!camera_ray(c, xs[i], ys[i], &o, &d0))
                continue;
            for (int a = 0; a < 2; a++) {
                real sx = a == 0 ? step : 0, sy = a == 0 ? 0 : step;
                real sign = (a == 0 ? xs[i] > c->cx : ys[i] > c->cy) ? R(-1) : R(1);
                if (camera_ray(c, xs[i] + sign * sx, ys[i] + sign * sy, &o, &d1))
                    *(a == 0 ? &d->ddx : &d->ddy) = v3_scale(v3_sub(d1, d0), sign);
            }
        } else {
            vec3 a = camera_dir(c, xs[i], ys[i]);
            real len = v3_len(a);
            if (!(len > R(0)))
                continue;
            vec3 u = v3_scale(a, R(1) / len);
            d->ddx = v3_scale(v3_madd(c->u, u, -v3_dot(u, c->u)), step / len);
            d->ddy = v3_scale(v3_madd(c->v, u, -v3_dot(u, c->v)), step / len);
        }
    }
    return out;
}

/* g plus h: a pixel's guides summed sample by sample */
static inline void guide_add(Guide *g, const Guide *h)
{
    g->albedo = v3_add(g->albedo, h->albedo);
    g->lum2 += h->lum2;
    g->instance = h->instance > g->instance ? h->instance : g->instance;
    if (h->surface) {
        g->normal = v3_add(g->normal, h->normal);
        g->depth += h->depth;
        g->surface += h->surface;
    }
}

/* A camera with an aperture: rays from stratified points of the lens for
 * each sample position, in packets, averaged; a position's key (adaptive
 * sampling) is its first lens ray's.  Per effect, lens_samples^2 rays a
 * position; one budget, the position's share of the lens_samples^2 its
 * pixel takes (at least one), points of one sequence for the pixel, each
 * ray a ray of the pixel's count. */
static void sample_packet_lens(const Frame *f, const Samples *sm, vec3 *out, RayStats *st, uint64_t *keys,
                               Guide *guides)
{
    const int product = f->w->view.settings.sampling == SAMPLING_PRODUCT;
    const uint32_t k = (uint32_t)settings_lens_samples(&f->w->view.settings),
                   per = product ? k * k : sample_share(k * k, sm->per_pixel);
    /* a lens ray's share of the aperture (a square of the same area) */
    const real cone_w = R(1.7724538509055159) * f->cam.lens_radius / sqrt((real)(product ? per : per * sm->per_pixel));
    SampleId id[TRACE_PACKET], rs[TRACE_PACKET];
    sample_ids(f, sm, id);
    RayDiff pos_diff[TRACE_PACKET], diff[TRACE_PACKET];
    const RayDiff *pd = camera_diffs(f, sm->xs, sm->ys, sm->n, sm->step, pos_diff);
    Ray rays[TRACE_PACKET];
    vec3 col[TRACE_PACKET];
    uint64_t key[TRACE_PACKET];
    int which[TRACE_PACKET], first[TRACE_PACKET], m = 0;
    const int n = sm->n;
    Guide rg[TRACE_PACKET];
    for (int i = 0; i < n; i++) {
        out[i] = v3_splat(0);
        if (guides)
            guides[i] = guide_none(v3_splat(R(0)));
    }
    for (int i = 0; i < n; i++) {
        const uint32_t lens_key = sample_mix(id[i].key, 0x4c454e53u); /* "LENS" */
        vec3 focal = v3_splat(0); /* where the position's lens rays meet */
        if (pd) {
            vec3 dc = v3_norm(camera_dir(&f->cam, sm->xs[i], sm->ys[i]));
            focal = v3_madd(f->cam.org, dc, f->cam.focus / v3_dot(dc, f->cam.forward));
        }
        for (uint32_t j = 0; j < per; j++) {
            real lu, lv;
            vec3 org, dir;
            if (product) {
                sample_stratum(lens_key, j, k, &lu, &lv);
                rs[m] = id[i];
                rs[m].key = sample_mix(id[i].key, j), rs[m].index = 0, rs[m].count = 1;
            } else {
                rs[m] = id[i];
                rs[m].index = id[i].index * per + j, rs[m].count = id[i].count * per;
                sample_sobol2(rs[m].index, lens_key, &lu, &lv);
            }
            camera_lens_ray(&f->cam, sm->xs[i], sm->ys[i], lu, lv, &org, &dir);
            ray_set(&rays[m], org, dir, v3(R(1) / dir.x, R(1) / dir.y, R(1) / dir.z), R(0), REAL_INF);
            if (pd) {
                /* the cone of the ray's share of the lens: as wide as that
                 * share's square there, closing to a point at the focus */
                diff[m] = pd[i];
                real dist = v3_len(v3_sub(focal, org));
                diff[m].w0 = cone_w;
                diff[m].spread = dist > R(0) ? -cone_w / dist : R(0);
            }
            first[m] = j == 0;
            which[m++] = i;
            if (m == TRACE_PACKET || (i == n - 1 && j == per - 1)) {
                shade_packet_guided(f->w, rays, m, col, st, keys ? key : NULL, rs, pd ? diff : NULL,
                                    guides ? rg : NULL);
                for (int q = 0; q < m; q++) {
                    out[which[q]] = v3_add(out[which[q]], col[q]);
                    if (guides)
                        guide_add(&guides[which[q]], &rg[q]);
                    if (keys && first[q])
                        keys[which[q]] = key[q];
                }
                m = 0;
            }
        }
    }
    for (int i = 0; i < n; i++) {
        out[i] = v3_scale(out[i], R(1) / (real)per);
        if (guides) { /* a position's guide the mean of its lens rays', a surface where all met one */
            Guide *g = &guides[i];
            const int all = g->surface == (int)per;
            g->albedo = v3_scale(g->albedo, R(1) / (real)per);
            g->depth = all ? g->depth / (real)per : R(0);
            g->normal = all ? g->normal : v3_splat(R(0));
            g->surface = all;
        }
    }
}

/* The same for an orthographic or fisheye camera: each ray by camera_ray,
 * the ones it has (a fisheye sees nothing outside its circle) traced as one
 * packet, the others the background. */
static void sample_packet_other(const Frame *f, const Samples *sm, vec3 *out, RayStats *st, uint64_t *keys,
                                Guide *guides)
{
    Guide rg[TRACE_PACKET];
    Ray rays[TRACE_PACKET];
    vec3 col[TRACE_PACKET];
    uint64_t key[TRACE_PACKET];
    SampleId id[TRACE_PACKET], rs[TRACE_PACKET];
    const SampleId *ids = sample_ids(f, sm, id);
    RayDiff pos_diff[TRACE_PACKET], diff[TRACE_PACKET];
    const RayDiff *pd = camera_diffs(f, sm->xs, sm->ys, sm->n, sm->step, pos_diff);
    int which[TRACE_PACKET], m = 0;
    for (int i = 0; i < sm->n; i++) {
        vec3 org, dir;
        if (camera_ray(&f->cam, sm->xs[i], sm->ys[i], &org, &dir)) {
            ray_init(&rays[m], org, dir, R(0), REAL_INF);
            rs[m] = ids ? ids[i] : (SampleId){.key = 0, .index = 0, .count = 1};
            if (pd)
                diff[m] = pd[i];
            which[m++] = i;
        } else {
            out[i] = f->w->background;
            if (keys)
                keys[i] = UINT64_MAX;
            if (guides)
                guides[i] = guide_none(v3_splat(R(1)));
        }
    }
    if (m == 0)
        return;
    shade_packet_guided(f->w, rays, m, col, st, keys ? key : NULL, rs, pd ? diff : NULL, guides ? rg : NULL);
    for (int k = 0; k < m; k++) {
        out[which[k]] = col[k];
        if (guides)
            guides[which[k]] = rg[k];
        if (keys)
            keys[which[k]] = key[k];
    }
}

/* The colours of the sample positions, traced as one packet (shade_packet:
 * each colour is what the ray gives alone); where guides is not NULL,
 * each position's guide. */
static void sample_packet(const Frame *f, const Samples *sm, vec3 *out, RayStats *st, uint64_t *keys,
                          Guide *guides)
{
    if (f->cam.kind != CAMERA_PINHOLE) {
        sample_packet_other(f, sm, out, st, keys, guides);
        return;
    }
    if (world_uses(f->w, FEAT_LENS)) {
        sample_packet_lens(f, sm, out, st, keys, guides);
        return;
    }
    /* ray_make(org, v3_norm(camera_dir(x, y))) for all eight lanes at once,
     * operation for operation, in arrays the compiler turns into vector
     * code: the square roots and divisions of one ray would otherwise wait
     * on each other */
    const int n = sm->n;
    real dx[TRACE_PACKET], dy[TRACE_PACKET], dz[TRACE_PACKET], ix[TRACE_PACKET], iy[TRACE_PACKET], iz[TRACE_PACKET];
    real len[TRACE_PACKET]; /* zero: a degenerate camera, done as ray_make does it */
    const CameraFrame *c = &f->cam;
    real px[TRACE_PACKET], py[TRACE_PACKET];
    for (int i = 0; i < TRACE_PACKET; i++)
        px[i] = sm->xs[i < n ? i : 0], py[i] = sm->ys[i < n ? i : 0];
    const real ux = c->u.x, uy = c->u.y, uz = c->u.z, vx = c->v.x, vy = c->v.y, vz = c->v.z;
    const real kx = c->k.x, ky = c->k.y, kz = c->k.z;
    for (int i = 0; i < TRACE_PACKET; i++) {
        real ax = ux * px[i] + vx * py[i] + kx, ay = uy * px[i] + vy * py[i] + ky, az = uz * px[i] + vz * py[i] + kz;
        real l = sqrt(ax * ax + ay * ay + az * az);
        real inv = R(1) / l;
        len[i] = l;
        dx[i] = ax * inv, dy[i] = ay * inv, dz[i] = az * inv;
        ix[i] = R(1) / dx[i], iy[i] = R(1) / dy[i], iz[i] = R(1) / dz[i];
    }
    Ray rays[TRACE_PACKET];
    for (int i = 0; i < n; i++) {
        if (len[i] > R(0))
            ray_set(&rays[i], c->org, v3(dx[i], dy[i], dz[i]), v3(ix[i], iy[i], iz[i]), R(0), REAL_INF);
        else
            ray_init(&rays[i], c->org, v3_norm(camera_dir(c, px[i], py[i])), R(0), REAL_INF);
    }
    SampleId id[TRACE_PACKET];
    RayDiff diff[TRACE_PACKET];
    shade_packet_guided(f->w, rays, n, out, st, keys, sample_ids(f, sm, id), camera_diffs(f, px, py, n, sm->step, diff),
                        guides);
}

/* One sample a pixel at each of n positions (their pixels' centres). */
static Samples centres(const real *xs, const real *ys, int n)
{
    Samples sm = {.xs = xs, .ys = ys, .per_pixel = 1, .step = R(1), .n = n};
    return sm;
}

/* Pixel centres i0.. of a run of `width`-wide lines starting at line offset
 * `g0`: how many (at most TRACE_PACKET) lie on the first one's line, with
 * their positions.  Packets follow lines, so a segment of one line, or of
 * part of one, still gets them. */
static int line_packet(uint64_t g0, uint64_t left, int width, real *xs, real *ys)
{
    int px = (int)(g0 % (uint64_t)width), py = (int)(g0 / (uint64_t)width);
    int n = width - px < TRACE_PACKET ? width - px : TRACE_PACKET;
    if ((uint64_t)n > left)
        n = (int)left;
    for (int k = 0; k < n; k++) {
        xs[k] = (real)(px + k) + R(0.5);
        ys[k] = (real)py + R(0.5);
    }
    return n;
}

/* A finished pixel: its colour (pixel.h); where guided, then its guide,
 * of g (the sum of its n samples' guides). */
static inline __attribute__((always_inline)) void put_pixel(const Frame *f, uint8_t *dst, vec3 c, const Guide *g,
                                                            int n)
{
    pixel_put_colour(dst, c, f->cbpp == 4, f->gain, f->tonemap, f->linear);
    if (f->guided)
        denoise_guide_pack(g, n, c, dst + f->cbpp);
}

/* Pixels' n x n sub-samples, gathered across pixels into full packets: a
 * 2 x 2 pixel alone filled half a packet and a 3 x 3 one a packet and a
 * ray, and a packet costs its set-up whatever it holds.  Each pixel sums
 * its colours in the order of its samples, and each colour is what its ray
 * gives alone, so a pixel is the same whatever packets it shared.  At most
 * TRACE_PACKET pixels wait (the samples of a packet, the newest pixel's
 * among them), so that a slot comes round free. */
#define GRID_SLOTS (TRACE_PACKET + 1)

typedef struct {
    const Frame *f;
    RayStats *st;
    int n;
    real inv; /* 1 / n */
    real xs[TRACE_PACKET], ys[TRACE_PACKET];
    uint32_t pos[TRACE_PACKET];
    uint32_t key[TRACE_PACKET]; /* the samples' pixels' keys, made once a pixel (some 45 instructions) */
    int slot[TRACE_PACKET], m;
    vec3 sum[GRID_SLOTS];
    Guide gsum[GRID_SLOTS]; /* where guided */
    /* in batches (f->prog_m): each slot's sums of its batch so far and of
     * the batches before; which samples end a batch */
    real part[GRID_SLOTS][PROG_MAX], total[GRID_SLOTS][PROG_MAX];
    uint8_t last[TRACE_PACKET];
    uint8_t *dst[GRID_SLOTS];
    int left[GRID_SLOTS], next;
} GridBatch;

static GridBatch grid_start(const Frame *f, RayStats *st, int n)
{
    return (GridBatch){.f = f, .st = st, .n = n, .inv = R(1) / (real)n};
}

/* The gathered samples' colours c (and guides gd) added to their pixels'
 * sums, in batches (progressive.h); the pixels they finish written. */
static void grid_flush_batches(GridBatch *g, const vec3 *c, Guide *gd)
{
    const Frame *f = g->f;
    const uint32_t reals = progressive_reals(&f->w->view.settings);
    for (int q = 0; q < g->m; q++) {
        const int s = g->slot[q];
        if (gd) {
            const real l = guide_luminance(c[q]);
            gd[q].lum2 = l * l;
        }
        progressive_add_sample(g->part[s], c[q], gd ? &gd[q] : NULL);
        if (g->last[q]) {
            progressive_fold(g->total[s], g->part[s], reals);
            memset(g->part[s], 0, sizeof g->part[s]);
        }
        if (--g->left[s] == 0) {
            if (f->sums) {
                memcpy(g->dst[s], g->total[s], reals * sizeof(real));
            } else {
                progressive_encode(&f->w->view.settings, f->gain, g->total[s], f->s1 - f->s0, g->dst[s]);
                /* a moving frame's one sample (settings jitter): its instance, which
                 * sums do not carry (a still frame's first batch, a server's sums, has none) */
                if (gd && f->w->view.settings.jitter)
                    denoise_guide_put_instance(g->dst[s] + f->cbpp, gd[q].surface ? gd[q].instance : 0);
            }
        }
    }
    g->m = 0;
}

/* Traces the gathered samples; writes the pixels they finish. */
static void grid_flush(GridBatch *g)
{
    if (g->m == 0)
        return;
    vec3 c[TRACE_PACKET];
    Guide gd[TRACE_PACKET];
    const int guided = g->f->guided;
    Samples sm = {.xs = g->xs, .ys = g->ys, .pos = g->pos, .keys = g->key, .per_pixel = (uint32_t)(g->n * g->n),
                  .step = g->inv, .n = g->m};
    sample_packet(g->f, &sm, c, g->st, NULL, guided ? gd : NULL);
    if (g->f->prog_m) {
        grid_flush_batches(g, c, guided ? gd : NULL);
        return;
    }
    for (int q = 0; q < g->m; q++) {
        const int s = g->slot[q];
        g->sum[s] = v3_add(g->sum[s], c[q]);
        if (guided) { /* the sample's light, for the spread of its pixel's samples */
            const real l = guide_luminance(c[q]);
            gd[q].lum2 = l * l;
            guide_add(&g->gsum[s], &gd[q]);
        }
        if (--g->left[s] == 0)
            put_pixel(g->f, g->dst[s], v3_scale(g->sum[s], g->inv * g->inv), &g->gsum[s], g->n * g->n);
    }
    g->m = 0;
}

/* Pixel (px, py), written to dst once its n x n samples are traced. */
static void grid_add(GridBatch *g, int px, int py, uint8_t *dst)
{
    const int s = g->next, n = g->n;
    g->next = (s + 1) % GRID_SLOTS;
    g->sum[s] = v3_splat(0);
    g->gsum[s] = guide_none(v3_splat(R(0)));
    g->dst[s] = dst;
    g->left[s] = n * n;
    const uint32_t key = pixel_key((real)px, (real)py); /* each sample's floor is the pixel (n <= 32) */
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            const int k = g->m++;
            g->xs[k] = (real)px + ((real)i + R(0.5)) * g->inv;
            g->ys[k] = (real)py + ((real)j + R(0.5)) * g->inv;
            g->pos[k] = (uint32_t)(j * n + i);
            g->key[k] = key;
            g->slot[k] = s;
            if (g->m == TRACE_PACKET)
                grid_flush(g);
        }
}

/* Pixel (px, py) in batches: its samples [s0, s1) in their progressive
 * order (sample_grid_cell), each its own number in the pixel's sequence;
 * their cells made GRID_CELLS at a time (sample_grid_cells: eight lanes
 * side by side, where a cell alone took some 140 instructions, 3% of the
 * 100 spheres' path-traced frame at 2 x 2). */
#define GRID_CELLS 64
_Static_assert(GRID_CELLS % SAMPLE_LANES == 0, "sample_grid_cells writes whole lanes");
static void grid_add_batches(GridBatch *g, int px, int py, uint8_t *dst)
{
    const Frame *f = g->f;
    const int s = g->next;
    g->next = (s + 1) % GRID_SLOTS;
    memset(g->part[s], 0, sizeof g->part[s]);
    memset(g->total[s], 0, sizeof g->total[s]);
    g->dst[s] = dst;
    g->left[s] = (int)(f->s1 - f->s0);
    const uint32_t key = pixel_key((real)px, (real)py);
    const SampleSobol q = sample_grid_seq(key);
    uint32_t ci[GRID_CELLS], cj[GRID_CELLS];
    for (uint32_t n = f->s0; n < f->s1; n++) {
        const uint32_t c = (n - f->s0) % GRID_CELLS;
        if (c == 0)
            sample_grid_cells(&q, n, f->s1 - n < GRID_CELLS ? f->s1 - n : GRID_CELLS, f->prog_m, ci, cj);
        const int k = g->m++;
        g->xs[k] = (real)px + ((real)ci[c] + R(0.5)) * g->inv;
        g->ys[k] = (real)py + ((real)cj[c] + R(0.5)) * g->inv;
        g->pos[k] = n;
        g->key[k] = key;
        g->slot[k] = s;
        g->last[k] = (uint8_t)(progressive_last(n) || n + 1 == f->s1);
        if (g->m == TRACE_PACKET)
            grid_flush(g);
    }
}

/* A chunk done: its finished pixels and the rays it took (since `before`). */
static void count_progress(const Frame *f, uint64_t pixels, const RayStats *st, uint64_t before)
{
    if (!f->progress)
        return;
    atomic_fetch_add_explicit(&f->progress->pixels, pixels, memory_order_relaxed);
    atomic_fetch_add_explicit(&f->progress->rays, ray_stats_total(st) - before, memory_order_relaxed);
}

/* [i0, i1): the chunk's pixels as offsets into a run of `total` */
static void chunk_range(const Frame *f, uint32_t chunk, uint64_t total, uint64_t *i0, uint64_t *i1)
{
    *i0 = (uint64_t)chunk * f->chunk;
    *i1 = *i0 + f->chunk < total ? *i0 + f->chunk : total;
}

/* chunk of the span, regular grid */
static void job_grid(void *ctx, uint32_t chunk, RayStats *st)
{
    Frame *f = ctx;
    if (cancelled(f))
        return;
    uint64_t i0, i1;
    chunk_range(f, chunk, f->count, &i0, &i1);
    int n = f->grid_n;
    uint64_t before = ray_stats_total(st);
    GridBatch grid = grid_start(f, st, n);
    for (uint64_t i = i0; i < i1;) {
        uint64_t g = f->first + i;
        if (n == 1) {
            real xs[TRACE_PACKET], ys[TRACE_PACKET];
            vec3 c[TRACE_PACKET];
            Guide gd[TRACE_PACKET];
            int k = line_packet(g, i1 - i, f->width, xs, ys);
            Samples sm = centres(xs, ys, k);
            sample_packet(f, &sm, c, st, NULL, f->guided ? gd : NULL);
            for (int q = 0; q < k; q++)
                put_pixel(f, &f->pixels[f->bpp * (i + (uint64_t)q)], c[q], &gd[q], 1);
            i += (uint64_t)k;
            continue;
        }
        int px = (int)(g % (uint64_t)f->width), py = (int)(g / (uint64_t)f->width);
        if (f->prog_m)
            grid_add_batches(&grid, px, py, &f->pixels[f->bpp * i]);
        else
            grid_add(&grid, px, py, &f->pixels[f->bpp * i]);
        i++;
    }
    grid_flush(&grid);
    count_progress(f, i1 - i0, st, before);
}

/* A chunk of the grid's pairs of whole lines, one sample a pixel: a block
 * of columns of two lines, in packets of 4 x 2 pixels.  A packet's rays
 * then spread over half the width of a line's eight, and on the 1M-triangle
 * sphere a frame took 8-13% less time (the bunny and the elephant 0-4%);
 * each pixel is what its ray gives alone, whatever packet it is in. */
#define TILE_W (TRACE_PACKET / 2)

static void job_tiles(void *ctx, uint32_t chunk, RayStats *st)
{
    Frame *f = ctx;
    if (cancelled(f))
        return;
    const uint64_t w = (uint64_t)f->width, y = f->tile_line + 2 * (uint64_t)(chunk / f->tile_blocks);
    const int c0 = (int)(chunk % f->tile_blocks * f->tile_cols);
    const int c1 = f->width - c0 > (int)f->tile_cols ? c0 + (int)f->tile_cols : f->width;
    uint64_t before = ray_stats_total(st);
    for (int x = c0; x < c1; x += TILE_W) {
        const int k = c1 - x < TILE_W ? c1 - x : TILE_W; /* columns in this packet */
        real xs[TRACE_PACKET], ys[TRACE_PACKET];
        vec3 c[TRACE_PACKET];
        Guide gd[TRACE_PACKET];
        for (int q = 0; q < 2 * k; q++) {
            xs[q] = (real)(x + q % k) + R(0.5);
            ys[q] = (real)(y + (uint64_t)(q / k)) + R(0.5);
        }
        Samples sm = centres(xs, ys, 2 * k);
        sample_packet(f, &sm, c, st, NULL, f->guided ? gd : NULL);
        for (int q = 0; q < 2 * k; q++)
            put_pixel(f, &f->pixels[f->bpp * ((y + (uint64_t)(q / k)) * w + (uint64_t)(x + q % k) - f->first)], c[q],
                      &gd[q], 1);
    }
    count_progress(f, 2 * (uint64_t)(c1 - c0), st, before);
}

/* adaptive pass 1: one centre sample per pixel of the key lines, keeping its key */
static void job_keys(void *ctx, uint32_t chunk, RayStats *st)
{
    Frame *f = ctx;
    if (cancelled(f))
        return;
    uint64_t i0, i1;
    chunk_range(f, chunk, (uint64_t)f->width * (uint64_t)f->key_lines, &i0, &i1);
    uint64_t before = ray_stats_total(st);
    for (uint64_t i = i0; i < i1;) {
        real xs[TRACE_PACKET], ys[TRACE_PACKET];
        vec3 c[TRACE_PACKET];
        Guide gd[TRACE_PACKET];
        int k = line_packet(i, i1 - i, f->width, xs, ys);
        for (int q = 0; q < k; q++)
            ys[q] += (real)f->key_first;
        Samples sm = centres(xs, ys, k);
        sm.probe = f->probe;
        sample_packet(f, &sm, c, st, &f->keys[i], f->guided ? gd : NULL);
        /* kept as written: the contrast test compares what a viewer sees, and
         * a pixel without an edge is this sample */
        for (int q = 0; q < k; q++) {
            pixel_put_codes(&f->colors[3 * (i + (uint64_t)q)], c[q], f->gain, f->tonemap, f->linear);
            if (f->centre != f->colors)
                put_pixel(f, &f->centre[f->bpp * (i + (uint64_t)q)], c[q], &gd[q], 1);
        }
        i += (uint64_t)k;
    }
    count_progress(f, 0, st, before);
}

/* Adaptive sampling also refines where two neighbouring centre samples, as
 * written, differ by more than `contrast` codes in a channel (settings
 * contrast, default 15): the edges a key does not see, a texture's, a
 * highlight's, a spot light's soft edge.  Measured at 512x384 against the
 * 16x16 double reference (docs/tradeoff.md, sRGB output): the textured
 * scene's RMSE falls from 0.81 (no colour test) to 0.37 (4x4 everywhere:
 * 0.31) for twice the time, the default scene's from 1.01 to 0.89 (0.85);
 * 30 codes bought half of that in the textured scene, 8 little more for
 * 40% more time. */
static int contrasts(const uint8_t *a, const uint8_t *b, int contrast)
{
    for (int k = 0; k < 3; k++)
        if (a[k] - b[k] > contrast || b[k] - a[k] > contrast)
            return 1;
    return 0;
}

/* Whether the pixel at key (px, py) of the key lines is refined: a
 * 4-neighbour differs in key or colour.  With adaptive light sampling, also
 * where any of the 8 neighbours differs in an area light's bit of the keys:
 * a 3 x 3 block of pixels probes all 9 strata of a 3 x 3 light, and a
 * penumbra shows as bits that differ within it; at one sample a pixel only
 * those bits count (a surface's edge or a colour gains nothing from every
 * point of the lights). */
static int refines(const Frame *f, const uint64_t *key, const uint8_t *col, int px, int py)
{
    const ptrdiff_t w = f->width, row = 3 * w;
    const int left = px > 0, right = px + 1 < f->width, up = py > f->key_first,
              down = py < f->key_first + f->key_lines - 1;
    uint64_t mask = f->area_mask;
#define DIFFERS(o) ((key[o] & mask) != (key[0] & mask))
    if (f->probe && ((up && ((left && DIFFERS(-w - 1)) || (right && DIFFERS(-w + 1)))) ||
                     (down && ((left && DIFFERS(w - 1)) || (right && DIFFERS(w + 1))))))
        return 1;
    mask = f->key_mask;
    if ((left && DIFFERS(-1)) || (right && DIFFERS(1)) || (up && DIFFERS(-w)) || (down && DIFFERS(w)))
        return 1;
#undef DIFFERS
    if (!f->colour_test)
        return 0;
    const int c = f->contrast;
    return (left && contrasts(col - 3, col, c)) || (right && contrasts(col + 3, col, c)) ||
           (up && contrasts(col - row, col, c)) || (down && contrasts(col + row, col, c));
}

/* adaptive pass 2: supersample where refines() says; at one sample a pixel
 * (adaptive light sampling alone) the refined pixels' centres go in
 * packets, every point of every area light */
static void job_refine(void *ctx, uint32_t chunk, RayStats *st)
{
    Frame *f = ctx;
    if (cancelled(f))
        return;
    uint64_t i0, i1;
    chunk_range(f, chunk, f->count, &i0, &i1);
    const int n = f->w->view.settings.aa;
    uint64_t before = ray_stats_total(st);
    real xs[TRACE_PACKET], ys[TRACE_PACKET];
    uint64_t at_px[TRACE_PACKET];
    int m = 0;
    GridBatch grid = grid_start(f, st, n);
    for (uint64_t i = i0; i < i1; i++) {
        uint64_t g = f->first + i;
        int px = (int)(g % (uint64_t)f->width), py = (int)(g / (uint64_t)f->width);
        size_t at = (size_t)(py - f->key_first) * (size_t)f->width + (size_t)px;
        if (!refines(f, &f->keys[at], &f->colors[3 * at], px, py))
            memcpy(&f->pixels[f->bpp * i], &f->centre[f->bpp * at], (size_t)f->bpp);
        else if (n > 1)
            grid_add(&grid, px, py, &f->pixels[f->bpp * i]);
        else {
            xs[m] = (real)px + R(0.5), ys[m] = (real)py + R(0.5);
            at_px[m++] = i;
        }
        if (m == TRACE_PACKET || (m > 0 && i + 1 == i1)) {
            vec3 c[TRACE_PACKET];
            Guide gd[TRACE_PACKET];
            Samples sm = centres(xs, ys, m);
            sample_packet(f, &sm, c, st, NULL, f->guided ? gd : NULL);
            for (int q = 0; q < m; q++)
                put_pixel(f, &f->pixels[f->bpp * at_px[q]], c[q], &gd[q], 1);
            m = 0;
        }
    }
    grid_flush(&grid);
    count_progress(f, i1 - i0, st, before);
}

int render_probes_lights(const World *w)
{
    const RenderSettings *rs = &w->view.settings;
    if (rs->light_sampling != LIGHTS_ADAPTIVE || !world_uses(w, FEAT_AREA) || !world_has(w, FEAT_SHADOWS) ||
        (rs->aa > 1 && !rs->adaptive))
        return 0;
    for (uint32_t i = 0; i < w->light_count; i++)
        if (world_light_is_area(&w->lights[i]) && world_light_side(w, &w->lights[i]) > 1)
            return 1;
    return 0;
}

static uint32_t chunks_of(const Frame *f, uint64_t n) { return (uint32_t)((n + f->chunk - 1) / f->chunk); }

/* CHUNK_MIN..CHUNK_MAX pixels, a multiple of the packet width, so that
 * each thread gets about CHUNK_PER_THREAD items of n pixels */
static uint32_t chunk_size(uint64_t n, int threads)
{
    uint64_t c = n / ((uint64_t)threads * CHUNK_PER_THREAD) / TRACE_PACKET * TRACE_PACKET;
    return (uint32_t)(c < CHUNK_MIN ? CHUNK_MIN : c > CHUNK_MAX ? CHUNK_MAX : c);
}

/* Pixels [first, first + count) of f's span, by lines (job_grid). */
static RayStats grid_lines(RenderPool *p, const Frame *f, uint64_t first, uint64_t count)
{
    if (count == 0)
        return (RayStats){0, 0, 0};
    Frame l = *f;
    l.first = first;
    l.count = count;
    l.pixels = f->pixels + (size_t)f->bpp * (first - f->first);
    return pool_run_counted(p, job_grid, &l, chunks_of(&l, count));
}

/* The regular grid.  With one sample a pixel, the span's whole lines go
 * two by two (job_tiles), and what is left of a line at either end, and an
 * odd last whole line, by lines; a segment of one line, or of part of one,
 * goes by lines alone. */
static RayStats render_grid(RenderPool *p, Frame *f)
{
    const uint64_t w = (uint64_t)f->width, end = f->first + f->count;
    const uint64_t r0 = (f->first + w - 1) / w, r1 = end / w; /* whole lines [r0, r1) */
    if (f->grid_n != 1 || r1 < r0 + 2)
        return pool_run_counted(p, job_grid, f, chunks_of(f, f->count));
    const uint64_t rb = r0 + (r1 - r0) / 2 * 2; /* the pairs end */
    RayStats st = grid_lines(p, f, f->first, r0 * w - f->first);
    Frame t = *f;
    t.tile_line = r0;
    t.tile_cols = f->chunk / 2 / TILE_W * TILE_W; /* about a chunk's pixels: CHUNK_MIN / 2 or more */
    t.tile_blocks = (uint32_t)((w + t.tile_cols - 1) / t.tile_cols);
    ray_stats_add(&st, pool_run_counted(p, job_tiles, &t, (uint32_t)((rb - r0) / 2 * t.tile_blocks)));
    ray_stats_add(&st, grid_lines(p, f, rb * w, end - rb * w));
    return st;
}

int render_span(RenderPool *p, const World *w, int width, int height, uint64_t first, uint64_t count, uint8_t *pixels,
                RayStats *stats, const atomic_int *cancel, Err *err)
{
    if (width < 1 || height < 1 || width > RENDER_MAX_SIDE || height > RENDER_MAX_SIDE)
        return err_set(err, "render: frame %dx%d out of range 1..%d", width, height, RENDER_MAX_SIDE);
    uint64_t total = (uint64_t)width * (uint64_t)height;
    if (first > total || count > total - first)
        return err_set(err, "render: pixels %llu..%llu outside a frame of %llu", (unsigned long long)first,
                       (unsigned long long)(first + count), (unsigned long long)total);
    if (stats)
        *stats = (RayStats){0, 0, 0};
    if (count == 0)
        return 0;
    if (count / CHUNK_MIN >= UINT32_MAX)
        return err_set(err, "render: span of %llu pixels too large", (unsigned long long)count);
    Frame f;
    memset(&f, 0, sizeof f);
    f.w = w;
    f.cam = camera_frame(&w->view.camera, width, height);
    f.width = width;
    f.first = first;
    f.count = count;
    f.pixels = pixels;
    f.cancel = cancel;
    f.progress = p->progress;
    f.linear = w->view.settings.linear;
    /* footprints where a texture or a checker is read, or an environment
     * that the Whitted integrator reads over them (environment_levels.c) */
    f.diffs = world_uses(w, FEAT_TEXTURES | FEAT_CHECKER) ||
              (w->env && w->view.settings.integrator == INTEGRATOR_WHITTED && w->view.settings.filter >= FILTER_TRILINEAR);
    f.bpp = (int)render_pixel_bytes(&w->view.settings);
    f.cbpp = (int)render_colour_bytes(&w->view.settings);
    f.guided = render_guided(&w->view.settings);
    f.gain = pixel_gain(&w->view.settings);
    f.tonemap = w->view.settings.tonemap;
    f.chunk = chunk_size(count, pool_threads(p->pool));
    f.grid_n = w->view.settings.aa;
    const RenderSettings *rs = &w->view.settings;
    const int batches = progressive_batches(rs);
    if (batches) {
        const int b = rs->batch, upto = progressive_upto(rs);
        if (b > batches || upto > batches)
            return err_set(err, "render: batch %d of %d", b ? b : upto, batches);
        f.prog_m = __builtin_ctz((unsigned)rs->aa);
        f.sums = b > 0;
        f.s0 = b ? progressive_start(b) : 0;
        f.s1 = b ? progressive_end(b) : progressive_end(upto);
    } else if (rs->batch || rs->batches) {
        return err_set(err, "render: batches of a frame whose samples do not go in batches (path, N x N, N a power of two)");
    } else if (rs->jitter) {
        /* a moving frame's one sample: the pixel's sample jitter - 1 of
         * its 32 x 32 in their progressive order, its key and place in the
         * pixel's sequence those of that sample of a still of 32 x 32 */
        if (rs->integrator != INTEGRATOR_PATH || rs->aa != 1 || rs->adaptive)
            return err_set(err, "render: jitter %d of a frame that is not path-traced at one sample a pixel", rs->jitter);
        f.grid_n = 1 << PROG_JITTER_M;
        f.prog_m = PROG_JITTER_M;
        f.s0 = (uint32_t)(rs->jitter - 1) % (1u << 2 * PROG_JITTER_M);
        f.s1 = f.s0 + 1;
    }
    f.probe = !rs->jitter && render_probes_lights(w);
    /* at one sample a pixel, adaptive light sampling refines only for the
     * area lights (the lights' bits of the keys: shade.c) */
    f.area_mask = 0;
    for (uint32_t i = 0; i < w->light_count && i < 16; i++)
        if (world_light_is_area(&w->lights[i]))
            f.area_mask |= 1u << i;
    f.key_mask = f.probe && w->view.settings.aa == 1 ? f.area_mask : UINT64_MAX;
    f.colour_test = w->view.settings.aa > 1 && w->view.settings.contrast < 255;
    f.contrast = w->view.settings.contrast;
    RayStats st;
    if (!f.probe && (!w->view.settings.adaptive || w->view.settings.aa == 1)) {
        st = render_grid(p, &f);
    } else {
        /* keys for the span's lines and the lines just above and below */
        int l0 = (int)(first / (uint64_t)width), l1 = (int)((first + count - 1) / (uint64_t)width);
        f.key_first = l0 > 0 ? l0 - 1 : 0;
        f.key_lines = (l1 + 1 < height ? l1 + 1 : l1) - f.key_first + 1;
        f.keys = malloc((size_t)width * (size_t)f.key_lines * sizeof *f.keys);
        f.colors = malloc((size_t)width * (size_t)f.key_lines * 3);
        f.centre = f.bpp == 3 ? f.colors : malloc((size_t)width * (size_t)f.key_lines * (size_t)f.bpp);
        if (!f.keys || !f.colors || !f.centre) {
            if (f.centre != f.colors)
                free(f.centre);
            free(f.keys);
            free(f.colors);
            return err_set(err, "render: out of memory for adaptive sampling of %llu pixels", (unsigned long long)count);
        }
        st = pool_run_counted(p, job_keys, &f, chunks_of(&f, (uint64_t)width * (uint64_t)f.key_lines));
        ray_stats_add(&st, pool_run_counted(p, job_refine, &f, chunks_of(&f, count)));
        if (f.centre != f.colors)
            free(f.centre);
        free(f.keys);
        free(f.colors);
    }
    if (stats)
        *stats = st;
    return cancelled(&f) ? RENDER_CANCELLED : 0;
}

int render_lines(RenderPool *p, const World *w, int width, int height, int first_line, int count, uint8_t *pixels,
                 RayStats *stats, Err *err)
{
    if (first_line < 0 || count < 0 || count > height - first_line)
        return err_set(err, "render: lines %d..%d outside a frame of %d lines", first_line, first_line + count, height);
    return render_span(p, w, width, height, (uint64_t)first_line * (uint64_t)(width > 0 ? width : 0),
                       (uint64_t)count * (uint64_t)(width > 0 ? width : 0), pixels, stats, NULL, err);
}
