/* denoise.c - the guided a-trous filter of denoise.h. */
#include "render/denoise.h"

#include <stdlib.h>
#include <string.h>

#include "base/srgb.h"

/* the filter's constants, as SVGF's paper gives them but for sigma_z,
 * which here compares distances with the pixel's own distance gradient,
 * and the albedo's, which keeps the light of unlike surfaces apart */
#define PASSES 5
#define SIGMA_L 4.0f       /* the light: differences of 4 standard deviations weigh 1/e */
/* a pixel of one sample: the light's difference weighs from the pass of
 * this step on.  Its noise is skewed (most paths find little, a few much),
 * and a weight by the light's difference keeps the few out of the many's
 * mean: on the Cornell box at one sample, the surfaces' light 6% low, 3%
 * from the second pass on (its taps' light means of 25) */
#define LUM_FROM 2
#define SIGMA_Z 1.0f       /* distances: a gradient's worth of difference a pixel apart weighs 1/e */
#define SIGMA_A 0.25f      /* albedos: a sum of channel differences of 0.25 weighs 1/e */
#define NORMAL_POWER 128   /* normals: the cosine's 128th power (7 squarings) */
#define ALBEDO_FLOOR 0.05f /* the light is divided by the albedo, but never by less than this */
#define VAR_RADIUS 2       /* the variance's window: 5 x 5 */
#define FIREFLY 4.0f       /* a pixel's light above its neighbours' mean by this many of their deviations is cut to it */

/* The noise byte's scale: a float's sign, exponent and top 4 mantissa bits
 * (its bits >> 19: sixteenths of an octave, piecewise linear), from 2^-12 */
#define NOISE_BASE ((127u - 12u) << 4)

/* The standard error of a pixel's mean luminance (n samples, their
 * squares summing to lum2, their mean luminance mean) over that mean, as
 * the noise byte: 0 for one sample (unknown), 1 for none or below 2^-12 */
static uint8_t noise_code(real mean, real lum2, int n)
{
    if (n < 2)
        return 0;
    const real var = (lum2 / (real)n - mean * mean) / (real)(n - 1); /* of the mean */
    const float rel = mean > R(0) && var > R(0) ? (float)(sqrt(var) / mean) : 0.0f;
    uint32_t bits;
    memcpy(&bits, &rel, sizeof bits);
    const uint32_t v = bits >> 19;
    return (uint8_t)(v <= NOISE_BASE ? 1 : v - NOISE_BASE + 1 > 255 ? 255 : v - NOISE_BASE + 1);
}

void denoise_guide_pack(const Guide *sum, int n, vec3 mean, uint8_t out[DENOISE_GUIDE_BYTES])
{
    const real inv = R(1) / (real)(n > 0 ? n : 1);
    for (int k = 0; k < 3; k++)
        out[k] = linear_encode8(sum->albedo.e[k] * inv);
    out[8] = noise_code(R(0.2126) * mean.x + R(0.7152) * mean.y + R(0.0722) * mean.z, sum->lum2, n);
    if (sum->surface < n) { /* a sample saw the background or an emitter: the pixel passes as it is (its
                             * light, far from its surface's, spread into its neighbours and lost) */
        memset(out + 3, 0, 5);
        out[3] = out[4] = 128;
        return;
    }
    /* the mean normal onto the octahedron |x| + |y| + |z| = 1, the lower
     * half folded out over the corners */
    const vec3 m = sum->normal;
    const real l1 = fabs(m.x) + fabs(m.y) + fabs(m.z);
    real x = l1 > R(0) ? m.x / l1 : R(0), y = l1 > R(0) ? m.y / l1 : R(0);
    if (l1 > R(0) && m.z < R(0)) {
        const real fx = (R(1) - fabs(y)) * (x < R(0) ? R(-1) : R(1));
        const real fy = (R(1) - fabs(x)) * (y < R(0) ? R(-1) : R(1));
        x = fx, y = fy;
    }
    out[3] = (uint8_t)(int)((x + R(1)) * R(127.5) + R(0.5));
    out[4] = (uint8_t)(int)((y + R(1)) * R(127.5) + R(0.5));
    const float depth = (float)(sum->depth / (real)sum->surface);
    uint32_t bits;
    memcpy(&bits, &depth, sizeof bits);
    bits = depth > 0.0f ? bits >> 8 : 0; /* below 0x7f8000: 24 bits */
    bits = bits ? bits : 1;              /* 0 says no surface */
    out[5] = (uint8_t)bits, out[6] = (uint8_t)(bits >> 8), out[7] = (uint8_t)(bits >> 16);
}

void denoise_guide_unpack(const uint8_t in[DENOISE_GUIDE_BYTES], float albedo[3], float normal[3], float *depth,
                          float *noise)
{
    for (int k = 0; k < 3; k++)
        albedo[k] = (float)in[k] / 255.0f;
    float x = (float)in[3] / 127.5f - 1.0f, y = (float)in[4] / 127.5f - 1.0f;
    const float nz = 1.0f - (x < 0 ? -x : x) - (y < 0 ? -y : y);
    if (nz < 0.0f) {
        const float fx = (1.0f - (y < 0 ? -y : y)) * (x < 0 ? -1.0f : 1.0f);
        const float fy = (1.0f - (x < 0 ? -x : x)) * (y < 0 ? -1.0f : 1.0f);
        x = fx, y = fy;
    }
    const float l = sqrtf(x * x + y * y + nz * nz);
    normal[0] = x / l, normal[1] = y / l, normal[2] = nz / l;
    const uint32_t bits = ((uint32_t)in[5] | (uint32_t)in[6] << 8 | (uint32_t)in[7] << 16) << 8;
    float z;
    memcpy(&z, &bits, sizeof z);
    *depth = z > 0.0f && z <= 1e30f ? z : 0.0f; /* a client's bytes: no infinity, NaN or sign gets in */
    /* the noise: the middle of its sixteenth of an octave (code 1: none) */
    const uint32_t nb = ((NOISE_BASE + (uint32_t)in[8] - 1u) << 19) | (1u << 18);
    memcpy(noise, &nb, sizeof *noise);
    *noise = in[8] == 0 ? -1.0f : in[8] == 1 ? 0.0f : *noise;
}

/* exp(-x) for x >= 0, within about 2e-7 relative: 2^-(x log2 e) as a
 * power of two times a polynomial of the fraction; without a branch (past
 * 2^-125 it stays there), so that a loop of it is vector code, and the
 * same bits on every CPU, where a library's exp may take another path on
 * another one */
static inline float exp_neg(float x)
{
    float t = x * 1.44269504f;
    t = t < 125.0f ? t : 125.0f;
    const int i = (int)t;
    const float f = (float)i - t; /* in (-1, 0] */
    /* 2^f by its Taylor series in f ln 2 (degree 6) */
    const float u = f * 0.693147181f;
    const float p = 1.0f + u * (1.0f + u * (0.5f + u * (0.166666667f + u * (0.0416666667f +
                                                                             u * (0.00833333333f + u * 0.00138888889f)))));
    const uint32_t bits = (uint32_t)(127 - i) << 23;
    float sc;
    memcpy(&sc, &bits, sizeof sc);
    return p * sc;
}

/* Planes of floats, a value a pixel each (structure of arrays: a row of
 * eight pixels' taps is eight neighbouring floats, vector code). */
enum { P_R, P_G, P_B, /* the light / albedo */
       P_R2, P_G2, P_B2, /* ... the other of the passes' pair */
       P_VAR, P_VAR2, P_VBLUR, P_LUM, P_LBLUR, P_NX, P_NY, P_NZ, P_AR, P_AG, P_AB, P_Z, P_DZ, P_SURF, P_NOISE, PLANES };

struct Denoiser {
    Pool *pool;
    size_t cap; /* pixels the planes hold */
    float *mem;
    float *p[PLANES];
};

Denoiser *denoiser_create(Pool *pool, size_t pixels)
{
    Denoiser *d = calloc(1, sizeof *d);
    const size_t n = pixels > 0 ? pixels : 1;
    float *mem = d && n < SIZE_MAX / PLANES / sizeof *mem ? malloc(n * PLANES * sizeof *mem) : NULL;
    if (!mem) {
        free(d);
        return NULL;
    }
    d->pool = pool, d->mem = mem, d->cap = n;
    for (int k = 0; k < PLANES; k++)
        d->p[k] = mem + (size_t)k * n;
    return d;
}

void denoiser_destroy(Denoiser *d)
{
    if (!d)
        return;
    free(d->mem);
    free(d);
}

/* One frame's pass: what each row function reads. */
typedef struct {
    Denoiser *d;
    const uint8_t *px;
    uint8_t *out;
    uint32_t w, h, cb, bpp;
    int linear;
    int step;              /* the a-trous pass's tap spacing */
    const float *in[3];    /* the light a pass reads */
    float *out_c[3];       /* ... and writes */
    const float *var_in;
    float *var_out;
} Pass;

static inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
static inline float absf(float x) { return x < 0 ? -x : x; }
static inline float divisor(float a) { return a > ALBEDO_FLOOR ? a : ALBEDO_FLOOR; }

/* rows [lo, hi): the pixels' light and guides read, the light divided by the albedo */
static void pass_read(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    for (uint64_t i = lo * ps->w; i < hi * ps->w; i++) {
        const uint8_t *p = ps->px + i * ps->bpp;
        float c[3], n[3], a[3], z, noise;
        if (ps->cb == 4) {
            double v[3];
            rgbe_decode(p, v);
            for (int k = 0; k < 3; k++)
                c[k] = (float)v[k];
        } else {
            for (int k = 0; k < 3; k++)
                c[k] = ps->linear ? (float)p[k] / 255.0f : srgb_decode8[p[k]];
        }
        denoise_guide_unpack(p + ps->cb, a, n, &z, &noise);
        P[P_SURF][i] = z > 0.0f ? 1.0f : 0.0f;
        P[P_NOISE][i] = noise;
        P[P_Z][i] = z;
        for (int k = 0; k < 3; k++) {
            P[P_AR + k][i] = a[k];
            P[P_NX + k][i] = n[k];
            P[P_R + k][i] = c[k] / divisor(a[k]);
        }
        P[P_LUM][i] = luminance(P[P_R][i], P[P_G][i], P[P_B][i]);
    }
}

/* rows [lo, hi): each pixel's distance gradient (the smaller step to a
 * neighbour that met a surface, along the axis where it is larger: a
 * surface's slope, not an edge's jump) */
static void pass_gradient(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    const uint64_t w = ps->w, h = ps->h;
    for (uint64_t i = lo * w; i < hi * w; i++) {
        const uint64_t x = i % w, y = i / w;
        /* the neighbours left, right, up, down, where they are in the frame */
        const int has[4] = {x > 0, x + 1 < w, y > 0, y + 1 < h};
        const uint64_t at[4] = {i - 1, i + 1, i - w, i + w};
        float g[2] = {-1, -1}; /* -1: no neighbour on that axis */
        for (int k = 0; k < 4 && P[P_SURF][i] > 0; k++) {
            if (!has[k] || !(P[P_SURF][at[k]] > 0))
                continue;
            const float diff = absf(P[P_Z][at[k]] - P[P_Z][i]);
            g[k / 2] = g[k / 2] < 0 || diff < g[k / 2] ? diff : g[k / 2];
        }
        P[P_DZ][i] = g[0] > g[1] ? (g[0] > 0 ? g[0] : 0) : (g[1] > 0 ? g[1] : 0);
    }
}

/* rows [lo, hi): the mean and variance of the light among the 5 x 5 pixels
 * about each that face and lie as it does (weighed by how alike); a pixel
 * far brighter than the others there (a firefly: a path that found a
 * light by a rare bounce, which no filter of this width spreads out) is
 * cut to FIREFLY deviations above their mean, into out_c; the variance
 * into var_out */
static void pass_moments(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    const int w = (int)ps->w, h = (int)ps->h;
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x = 0; x < w; x++) {
            const size_t i = (size_t)y * (size_t)w + (size_t)x;
            for (int k = 0; k < 3; k++)
                ps->out_c[k][i] = ps->in[k][i];
            ps->var_out[i] = 0;
            if (!(P[P_SURF][i] > 0))
                continue;
            const float zp = P[P_Z][i], nx = P[P_NX][i], ny = P[P_NY][i], nz = P[P_NZ][i];
            float sw = 0, m1 = 0, m2 = 0; /* the others' */
            for (int j = -VAR_RADIUS; j <= VAR_RADIUS; j++)
                for (int k = -VAR_RADIUS; k <= VAR_RADIUS; k++) {
                    const int qx = x + k, qy = y + j;
                    if ((j == 0 && k == 0) || qx < 0 || qy < 0 || qx >= w || qy >= h)
                        continue;
                    const size_t q = (size_t)qy * (size_t)w + (size_t)qx;
                    if (!(P[P_SURF][q] > 0))
                        continue;
                    const float c = nx * P[P_NX][q] + ny * P[P_NY][q] + nz * P[P_NZ][q];
                    const float reach = (float)(j < 0 ? -j : j) + (float)(k < 0 ? -k : k);
                    const float ez = absf(P[P_Z][q] - zp) / (SIGMA_Z * P[P_DZ][i] * reach + 1e-3f * zp);
                    const float wt = c > 0.9f ? exp_neg(ez) : 0.0f;
                    const float l = P[P_LUM][q];
                    sw += wt, m1 += wt * l, m2 += wt * l * l;
                }
            if (!(sw > 0)) { /* alone: its own samples' spread, where it has several */
                const float own = P[P_NOISE][i] * P[P_LUM][i];
                ps->var_out[i] = P[P_NOISE][i] >= 0 ? own * own : 0;
                continue;
            }
            m1 /= sw, m2 /= sw;
            const float var = m2 - m1 * m1 > 0 ? m2 - m1 * m1 : 0, lp = P[P_LUM][i];
            const float top = m1 + FIREFLY * sqrtf(var);
            float l = lp;
            if (lp > top && lp > 0) { /* a firefly */
                const float cut = top / lp;
                for (int k = 0; k < 3; k++)
                    ps->out_c[k][i] *= cut;
                l = top;
            }
            /* the variance of its light: as its own samples spread (a pixel of
             * several: where they agree, what differs from its neighbours is
             * the picture, not noise, and stays), else with its own (cut)
             * light among the others' */
            const float a1 = (m1 * sw + l) / (sw + 1), a2 = (m2 * sw + l * l) / (sw + 1), own = P[P_NOISE][i] * l;
            ps->var_out[i] = P[P_NOISE][i] >= 0 ? own * own : a2 - a1 * a1 > 0 ? a2 - a1 * a1 : 0;
        }
}

/* rows [lo, hi): the luminance of the light the next pass reads */
static void pass_lum(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    for (uint64_t i = lo * ps->w; i < hi * ps->w; i++)
        ps->d->p[P_LUM][i] = luminance(ps->in[0][i], ps->in[1][i], ps->in[2][i]);
}

/* rows [lo, hi): the variance blurred by a 3 x 3 Gaussian (the luminance
 * weight's spread, steadier than one pixel's) */
static void pass_blur(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    const int w = (int)ps->w, h = (int)ps->h;
    static const float k3[3] = {0.25f, 0.5f, 0.25f};
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x = 0; x < w; x++) {
            const size_t i = (size_t)y * (size_t)w + (size_t)x;
            float s = 0, sw = 0, sl = 0;
            for (int j = -1; j <= 1; j++)
                for (int k = -1; k <= 1; k++) {
                    const int qx = x + k, qy = y + j;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h)
                        continue;
                    const size_t q = (size_t)qy * (size_t)w + (size_t)qx;
                    const float wt = k3[j + 1] * k3[k + 1] * P[P_SURF][q];
                    s += wt * ps->var_in[q], sw += wt, sl += wt * P[P_LUM][q];
                }
            P[P_VBLUR][i] = sw > 0 ? s / sw : 0;
            P[P_LBLUR][i] = sw > 0 ? sl / sw : P[P_LUM][i];
        }
}

/* An a-trous pass over LANES pixels of a row at once: what each pixel
 * keeps of itself, then its sums over the taps. */
#define LANES 8
typedef struct {
    float nx[LANES], ny[LANES], nz[LANES], ar[LANES], ag[LANES], ab[LANES], z[LANES], lum[LANES];
    float inv_l[LANES], inv_z[5][LANES]; /* by the tap's reach, 1..4 steps */
    float sw[LANES], sv[LANES], sr[LANES], sg[LANES], sb[LANES];
} Lanes;

/* The weight of a tap: its kernel weight kw times how alike the pixel
 * (lane l of L) and the tap q are (surf: whether q met a surface, 0 or
 * 1; out of the frame also 0), one expression for the vector and the
 * border code, so that both give the same bits */
static inline __attribute__((always_inline)) float tap_weight(const Lanes *L, int l, float *const *P, size_t q,
                                                              float kw, int reach, float surf)
{
    float c = L->nx[l] * P[P_NX][q] + L->ny[l] * P[P_NY][q] + L->nz[l] * P[P_NZ][q];
    c = c > 0.0f ? c : 0.0f;
    for (int e = 0; e < 7; e++) /* c^NORMAL_POWER */
        c *= c;
    const float ez = absf(P[P_Z][q] - L->z[l]) * L->inv_z[reach][l];
    const float el = absf(P[P_LUM][q] - L->lum[l]) * L->inv_l[l];
    const float ea = (absf(P[P_AR][q] - L->ar[l]) + absf(P[P_AG][q] - L->ag[l]) + absf(P[P_AB][q] - L->ab[l])) *
                     (1.0f / SIGMA_A);
    return kw * surf * c * exp_neg(ez + el + ea);
}

static inline __attribute__((always_inline)) void tap_add(Lanes *L, int l, const Pass *ps, size_t q, float wt)
{
    L->sw[l] += wt, L->sv[l] += wt * wt * ps->var_in[q];
    L->sr[l] += wt * ps->in[0][q], L->sg[l] += wt * ps->in[1][q], L->sb[l] += wt * ps->in[2][q];
}

/* rows [lo, hi): one a-trous pass, taps ps->step apart; eight pixels at
 * once where all their taps lie in the frame, else pixel by pixel */
static void pass_atrous(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    const int w = (int)ps->w, h = (int)ps->h, s = ps->step;
    static const float kern[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
    const float wc = kern[2] * kern[2];
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x0 = 0; x0 < w; x0 += LANES) {
            const int n = w - x0 < LANES ? w - x0 : LANES;
            const size_t i0 = (size_t)y * (size_t)w + (size_t)x0;
            Lanes L;
            for (int l = 0; l < LANES; l++) {
                const size_t i = i0 + (size_t)(l < n ? l : 0);
                L.nx[l] = P[P_NX][i], L.ny[l] = P[P_NY][i], L.nz[l] = P[P_NZ][i];
                L.ar[l] = P[P_AR][i], L.ag[l] = P[P_AG][i], L.ab[l] = P[P_AB][i];
                L.z[l] = P[P_Z][i], L.lum[l] = P[P_LBLUR][i];
                const int by_light = s >= LUM_FROM || P[P_NOISE][i] >= 0;
                L.inv_l[l] = by_light ? 1.0f / (SIGMA_L * sqrtf(P[P_VBLUR][i]) + 1e-6f) : 0.0f;
                for (int r = 1; r <= 4; r++)
                    L.inv_z[r][l] = 1.0f / (SIGMA_Z * P[P_DZ][i] * (float)(s * r) + 1e-3f * L.z[l] + 1e-30f);
                L.sw[l] = wc, L.sv[l] = wc * wc * ps->var_in[i];
                L.sr[l] = wc * ps->in[0][i], L.sg[l] = wc * ps->in[1][i], L.sb[l] = wc * ps->in[2][i];
            }
            const int inside = n == LANES && x0 - 2 * s >= 0 && x0 + LANES - 1 + 2 * s < w && y - 2 * s >= 0 &&
                               y + 2 * s < h;
            for (int j = -2; j <= 2; j++)
                for (int k = -2; k <= 2; k++) {
                    if (j == 0 && k == 0)
                        continue;
                    const float kw = kern[j + 2] * kern[k + 2];
                    const int reach = (j < 0 ? -j : j) + (k < 0 ? -k : k);
                    if (inside) {
                        const size_t q0 = (size_t)((ptrdiff_t)i0 + (ptrdiff_t)j * s * w + (ptrdiff_t)k * s);
                        for (int l = 0; l < LANES; l++) {
                            const size_t q = q0 + (size_t)l;
                            tap_add(&L, l, ps, q, tap_weight(&L, l, P, q, kw, reach, P[P_SURF][q]));
                        }
                        continue;
                    }
                    for (int l = 0; l < n; l++) {
                        const int qx = x0 + l + k * s, qy = y + j * s;
                        if (qx < 0 || qy < 0 || qx >= w || qy >= h)
                            continue;
                        const size_t q = (size_t)qy * (size_t)w + (size_t)qx;
                        tap_add(&L, l, ps, q, tap_weight(&L, l, P, q, kw, reach, P[P_SURF][q]));
                    }
                }
            for (int l = 0; l < n; l++) {
                const size_t i = i0 + (size_t)l;
                const int surface = P[P_SURF][i] > 0;
                ps->out_c[0][i] = surface ? L.sr[l] / L.sw[l] : ps->in[0][i];
                ps->out_c[1][i] = surface ? L.sg[l] / L.sw[l] : ps->in[1][i];
                ps->out_c[2][i] = surface ? L.sb[l] / L.sw[l] : ps->in[2][i];
                ps->var_out[i] = surface ? L.sv[l] / (L.sw[l] * L.sw[l]) : ps->var_in[i];
            }
        }
}

/* rows [lo, hi): the filtered light times the albedo again, coded; a pixel
 * that met no surface keeps its own bytes */
static void pass_write(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->d->p;
    for (uint64_t i = lo * ps->w; i < hi * ps->w; i++) {
        uint8_t *o = ps->out + i * ps->cb;
        if (!(P[P_SURF][i] > 0)) {
            memcpy(o, ps->px + i * ps->bpp, ps->cb);
            continue;
        }
        real c[3];
        for (int k = 0; k < 3; k++)
            c[k] = (real)(ps->in[k][i] * divisor(P[P_AR + k][i]));
        if (ps->cb == 4)
            rgbe_encode(c[0], c[1], c[2], o);
        else
            for (int k = 0; k < 3; k++)
                o[k] = ps->linear ? linear_encode8(c[k]) : srgb_encode8(c[k]);
    }
}

static void set_light(Pass *ps, float *const *P, int from, int to)
{
    for (int k = 0; k < 3; k++)
        ps->in[k] = P[from + k], ps->out_c[k] = P[to + k];
}

int denoise_frame(Denoiser *d, const uint8_t *px, uint32_t w, uint32_t h, uint32_t colour_bytes, int linear,
                  uint8_t *out, Err *err)
{
    const size_t n = (size_t)w * (size_t)h;
    if (n == 0)
        return 0;
    if (n > d->cap)
        return err_set(err, "denoise: a frame of %ux%u is larger than the %zu pixels made for", w, h, d->cap);
    Pass ps = {.d = d, .px = px, .out = out, .w = w, .h = h, .cb = colour_bytes,
               .bpp = colour_bytes + DENOISE_GUIDE_BYTES, .linear = linear};
    float *const *P = d->p;
    const uint64_t grain = 4; /* rows a call */
    pool_for(d->pool, h, grain, pass_read, &ps);
    pool_for(d->pool, h, grain, pass_gradient, &ps);
    set_light(&ps, P, P_R, P_R2);
    ps.var_out = P[P_VAR];
    pool_for(d->pool, h, grain, pass_moments, &ps);
    int cur = P_R2, var = P_VAR; /* where the light and its variance are */
    for (int k = 0; k < PASSES; k++) {
        const int next = cur == P_R ? P_R2 : P_R, next_var = var == P_VAR ? P_VAR2 : P_VAR;
        set_light(&ps, P, cur, next);
        ps.var_in = P[var], ps.var_out = P[next_var];
        pool_for(d->pool, h, grain, pass_lum, &ps);
        pool_for(d->pool, h, grain, pass_blur, &ps);
        ps.step = 1 << k;
        pool_for(d->pool, h, grain, pass_atrous, &ps);
        cur = next, var = next_var;
    }
    set_light(&ps, P, cur, cur);
    pool_for(d->pool, h, grain, pass_write, &ps);
    return 0;
}
