/* denoise_kernel.h - the denoiser's passes over taps (render/denoise.c):
 * their constants, planes and pass record, and the two that weigh 24 taps
 * a pixel (the variance's window and the a-trous pass), written over eight
 * pixels of a row at once, which the compiler makes vector code.  Each
 * file that includes it defines DENOISE_KERNEL(name) to its own names:
 * denoise.c for the baseline (SSE2), denoise_avx2.c under AVX2's target
 * (eight lanes a register; never FMA, so that every path gives the same
 * bits: tests/cli/denoise.sh renders on each). */
#ifndef LANRAY_DENOISE_KERNEL_H
#define LANRAY_DENOISE_KERNEL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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
#define ALBEDO_FLOOR 0.05f /* the light is divided by the albedo, but never by less than this */
#define VAR_RADIUS 2       /* the variance's window: 5 x 5 */
#define FIREFLY 4.0f       /* light this many deviations above the neighbours' mean is cut to it */

/* exp(-x) for x >= 0, within about 2e-7 relative: 2^-(x log2 e) as a
 * power of two times a polynomial of the fraction; without a branch (past
 * 2^-125 it stays there), so that a loop of it is vector code, and the
 * same bits on every CPU, where a library's exp may take another path on
 * another one */
static inline float exp_neg(float x)
{
    /* t = min(x log2 e, 125) by the bits (of a float at or above 0, in the
     * order of the floats): a float's comparison here kept AVX2's compile
     * from vector code, and a NaN becomes 125 */
    union {
        float f;
        uint32_t u;
    } t = {.f = x * 1.44269504f};
    t.u = t.u < 0x42fa0000u ? t.u : 0x42fa0000u; /* 125.0f */
    const int i = (int)t.f;
    const float f = (float)i - t.f; /* in (-1, 0] */
    /* 2^f by its Taylor series in f ln 2 (degree 6) */
    const float u = f * 0.693147181f;
    const float p5 = 0.0416666667f + u * (0.00833333333f + u * 0.00138888889f);
    const float p = 1.0f + u * (1.0f + u * (0.5f + u * (0.166666667f + u * p5)));
    const union {
        uint32_t u;
        float f;
    } sc = {.u = (uint32_t)(127 - i) << 23};
    return p * sc.f;
}

/* Planes of floats, a value a pixel each (structure of arrays: a row of
 * eight pixels' taps is eight neighbouring floats, vector code), each
 * with a margin of PAD pixels of zeros round the frame (no surface: a tap
 * there weighs 0), so that every tap of every pixel is in the planes and
 * no pass tests the frame's edges. */
#define PAD 32 /* the farthest tap: 2 x 16 */
enum { P_R, P_G, P_B, /* the light / albedo */
       P_R2, P_G2, P_B2, /* ... the other of the passes' pair */
       P_VAR, P_VAR2, P_VBLUR, P_LUM, P_LBLUR, P_NX, P_NY, P_NZ, P_AR, P_AG, P_AB, P_Z, P_DZ, P_SURF, P_NOISE, PLANES };

/* One frame's pass: what each row function reads. */
typedef struct {
    float *const *P;       /* the denoiser's planes */
    const uint8_t *px;
    uint8_t *out;
    uint32_t w, cb, bpp;
    size_t stride;         /* floats a row of the planes: w + 2 PAD */
    int linear;
    int step;              /* the a-trous pass's tap spacing */
    const float *in[3];    /* the light a pass reads */
    float *out_c[3];       /* ... and writes */
    const float *var_in;
    float *var_out;
} Pass;

static inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
static inline float absf(float x) { return fabsf(x); }

/* The passes, by their names in the file that includes this (_sse, _avx2). */
void denoise_moments_sse(void *ctx, uint64_t lo, uint64_t hi, int thread);
void denoise_atrous_sse(void *ctx, uint64_t lo, uint64_t hi, int thread);
void denoise_moments_avx2(void *ctx, uint64_t lo, uint64_t hi, int thread);
void denoise_atrous_avx2(void *ctx, uint64_t lo, uint64_t hi, int thread);

/* LANES pixels of a row at once, for a pass over taps: what each pixel
 * keeps of itself, then its sums over the taps. */
#define LANES 8
typedef struct {
    float nx[LANES], ny[LANES], nz[LANES], ar[LANES], ag[LANES], ab[LANES], z[LANES], lum[LANES];
    float inv_l[LANES], inv_z[5][LANES]; /* by the tap's reach, 1..4 steps */
    float sw[LANES], sv[LANES], sr[LANES], sg[LANES], sb[LANES];
} Lanes;

/* The weight of a tap: its kernel weight kw times how alike the pixel
 * (lane l of L) and the tap q are (surf: whether q met a surface, 0 or
 * 1; in the planes' margin, 0) */
static inline __attribute__((always_inline)) float tap_weight(const Lanes *L, int l, float *const *P, size_t q,
                                                              float kw, int reach, float surf)
{
    float c = L->nx[l] * P[P_NX][q] + L->ny[l] * P[P_NY][q] + L->nz[l] * P[P_NZ][q];
    c = (c + fabsf(c)) * 0.5f; /* c, or 0 below 0 (exactly), without a branch */
    /* normals: the cosine's 128th power, 7 squarings (as a loop, AVX2's
     * compile made no vector code of the taps) */
    c *= c, c *= c, c *= c, c *= c, c *= c, c *= c, c *= c;
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

/* Pixel (x, y)'s place in the planes. */
static inline size_t plane_at(const Pass *ps, int x, int y)
{
    return (size_t)(y + PAD) * ps->stride + (size_t)(x + PAD);
}

/* The block of n <= LANES pixels from plane place i0 into the lanes (a
 * lane past n takes the first pixel's): their normals, distances, and the
 * inverse of the distance difference that weighs 1/e at each reach of
 * taps `step` apart */
static inline __attribute__((always_inline)) void lanes_start(Lanes *L, float *const *P, size_t i0, int n, int step)
{
    for (int l = 0; l < LANES; l++) {
        const size_t i = i0 + (size_t)(l < n ? l : 0);
        L->nx[l] = P[P_NX][i], L->ny[l] = P[P_NY][i], L->nz[l] = P[P_NZ][i], L->z[l] = P[P_Z][i];
        for (int r = 1; r <= 4; r++)
            L->inv_z[r][l] = 1.0f / (SIGMA_Z * P[P_DZ][i] * (float)(step * r) + 1e-3f * L->z[l] + 1e-30f);
    }
}

/* rows [lo, hi): one a-trous pass, taps ps->step apart, eight pixels at once */
void DENOISE_KERNEL(denoise_atrous)(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->P;
    const int w = (int)ps->w, s = ps->step;
    const ptrdiff_t S = (ptrdiff_t)ps->stride;
    static const float kern[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
    const float wc = kern[2] * kern[2];
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x0 = 0; x0 < w; x0 += LANES) {
            const int n = w - x0 < LANES ? w - x0 : LANES;
            const size_t i0 = plane_at(ps, x0, y);
            Lanes L;
            lanes_start(&L, P, i0, n, s);
            for (int l = 0; l < LANES; l++) {
                const size_t i = i0 + (size_t)(l < n ? l : 0);
                L.ar[l] = P[P_AR][i], L.ag[l] = P[P_AG][i], L.ab[l] = P[P_AB][i], L.lum[l] = P[P_LBLUR][i];
                const int by_light = s >= LUM_FROM || P[P_NOISE][i] >= 0;
                L.inv_l[l] = by_light ? 1.0f / (SIGMA_L * sqrtf(P[P_VBLUR][i]) + 1e-6f) : 0.0f;
                L.sw[l] = wc, L.sv[l] = wc * wc * ps->var_in[i];
                L.sr[l] = wc * ps->in[0][i], L.sg[l] = wc * ps->in[1][i], L.sb[l] = wc * ps->in[2][i];
            }
            for (int j = -2; j <= 2; j++)
                for (int k = -2; k <= 2; k++) {
                    if (j == 0 && k == 0)
                        continue;
                    const float kw = kern[j + 2] * kern[k + 2];
                    const int reach = (j < 0 ? -j : j) + (k < 0 ? -k : k);
                    const size_t q0 = (size_t)((ptrdiff_t)i0 + (ptrdiff_t)j * s * S + (ptrdiff_t)k * s);
                    for (int l = 0; l < LANES; l++) {
                        const size_t q = q0 + (size_t)l;
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

/* A tap of the variance's window: weighed by whether it faces as the
 * pixel (lane l) does and how far its distance lies from the pixel's */
static inline __attribute__((always_inline)) void moment_add(Lanes *L, int l, float *const *P, size_t q, int reach,
                                                             float surf)
{
    const float c = L->nx[l] * P[P_NX][q] + L->ny[l] * P[P_NY][q] + L->nz[l] * P[P_NZ][q];
    const float ez = absf(P[P_Z][q] - L->z[l]) * L->inv_z[reach][l];
    const float wt = surf * (c > 0.9f ? 1.0f : 0.0f) * exp_neg(ez), lq = P[P_LUM][q];
    L->sw[l] += wt, L->sr[l] += wt * lq, L->sg[l] += wt * lq * lq;
}

/* Pixel i's variance from its window's sums (sw, m1 and m2 the weighed
 * count, light and squares of the others), and a firefly cut */
static inline void moment_finish(const Pass *ps, float *const *P, size_t i, float sw, float m1, float m2)
{
    for (int k = 0; k < 3; k++)
        ps->out_c[k][i] = ps->in[k][i];
    ps->var_out[i] = 0;
    if (!(P[P_SURF][i] > 0))
        return;
    if (!(sw > 0)) { /* alone: its own samples' spread, where it has several */
        const float own = P[P_NOISE][i] * P[P_LUM][i];
        ps->var_out[i] = P[P_NOISE][i] >= 0 ? own * own : 0;
        return;
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
     * several: where they agree, what differs from its neighbours is the
     * picture, not noise, and stays), else with its own (cut) light among
     * the others' */
    const float a1 = (m1 * sw + l) / (sw + 1), a2 = (m2 * sw + l * l) / (sw + 1), own = P[P_NOISE][i] * l;
    ps->var_out[i] = P[P_NOISE][i] >= 0 ? own * own : a2 - a1 * a1 > 0 ? a2 - a1 * a1 : 0;
}

/* rows [lo, hi): the mean and variance of the light among the 5 x 5 pixels
 * about each that face and lie as it does (weighed by how alike); a pixel
 * far brighter than the others there (a firefly: a path that found a
 * light by a rare bounce, which no filter of this width spreads out) is
 * cut to FIREFLY deviations above their mean, into out_c; the variance
 * into var_out.  Eight pixels at once. */
void DENOISE_KERNEL(denoise_moments)(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->P;
    const int w = (int)ps->w, R = VAR_RADIUS;
    const ptrdiff_t S = (ptrdiff_t)ps->stride;
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x0 = 0; x0 < w; x0 += LANES) {
            const int n = w - x0 < LANES ? w - x0 : LANES;
            const size_t i0 = plane_at(ps, x0, y);
            Lanes L;
            lanes_start(&L, P, i0, n, 1);
            for (int l = 0; l < LANES; l++)
                L.sw[l] = 0, L.sr[l] = 0, L.sg[l] = 0;
            for (int j = -R; j <= R; j++)
                for (int k = -R; k <= R; k++) {
                    if (j == 0 && k == 0)
                        continue;
                    const int reach = (j < 0 ? -j : j) + (k < 0 ? -k : k);
                    const size_t q0 = (size_t)((ptrdiff_t)i0 + (ptrdiff_t)j * S + (ptrdiff_t)k);
                    for (int l = 0; l < LANES; l++)
                        moment_add(&L, l, P, q0 + (size_t)l, reach, P[P_SURF][q0 + (size_t)l]);
                }
            for (int l = 0; l < n; l++)
                moment_finish(ps, P, i0 + (size_t)l, L.sw[l], L.sr[l], L.sg[l]);
        }
}

#endif
