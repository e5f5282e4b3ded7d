/* denoise.c - the guided a-trous filter of denoise.h. */
#include "render/denoise.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "base/simd.h"
#include "base/srgb.h"
#include "render/pixel.h"
#define DENOISE_KERNEL(name) name##_sse
#include "render/denoise_kernel.h"

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
    return denoise_noise_code(mean > R(0) && var > R(0) ? (float)(sqrt(var) / mean) : 0.0f);
}

uint8_t denoise_noise_code(float rel)
{
    uint32_t bits;
    memcpy(&bits, &rel, sizeof bits);
    const uint32_t v = bits >> 19;
    return (uint8_t)(v <= NOISE_BASE ? 1 : v - NOISE_BASE + 1 > 255 ? 255 : v - NOISE_BASE + 1);
}

void denoise_normal_pack(vec3 m, uint8_t out[2])
{
    /* onto the octahedron |x| + |y| + |z| = 1, the lower half folded out
     * over the corners */
    const real l1 = fabs(m.x) + fabs(m.y) + fabs(m.z);
    real x = l1 > R(0) ? m.x / l1 : R(0), y = l1 > R(0) ? m.y / l1 : R(0);
    if (l1 > R(0) && m.z < R(0)) {
        const real fx = (R(1) - fabs(y)) * (x < R(0) ? R(-1) : R(1));
        const real fy = (R(1) - fabs(x)) * (y < R(0) ? R(-1) : R(1));
        x = fx, y = fy;
    }
    out[0] = (uint8_t)(int)((x + R(1)) * R(127.5) + R(0.5));
    out[1] = (uint8_t)(int)((y + R(1)) * R(127.5) + R(0.5));
}

void denoise_guide_pack(const Guide *sum, int n, vec3 mean, uint8_t out[DENOISE_GUIDE_BYTES])
{
    const real inv = R(1) / (real)(n > 0 ? n : 1);
    for (int k = 0; k < 3; k++)
        out[k] = linear_encode8(sum->albedo.e[k] * inv);
    out[8] = noise_code(guide_luminance(mean), sum->lum2, n);
    denoise_guide_put_instance(out, sum->surface >= n ? sum->instance : 0);
    if (sum->surface < n) { /* a sample saw the background or an emitter: the pixel passes as it is (its
                             * light, far from its surface's, spread into its neighbours and lost) */
        memset(out + 3, 0, 5);
        out[3] = out[4] = 128;
        return;
    }
    denoise_normal_pack(sum->normal, out + 3);
    const real d = sum->depth / (real)sum->surface; /* a client's batch sums may say anything: kept in float's range */
    const float depth = d > R(0) ? (d < (real)FLT_MAX ? (float)d : FLT_MAX) : 0.0f;
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
    const float nz = 1.0f - absf(x) - absf(y);
    if (nz < 0.0f) {
        const float fx = (1.0f - absf(y)) * (x < 0 ? -1.0f : 1.0f);
        const float fy = (1.0f - absf(x)) * (y < 0 ? -1.0f : 1.0f);
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

struct Denoiser {
    Pool *pool;
    uint32_t max_w, max_h; /* the largest frame it takes */
    uint32_t w, h;         /* the last frame's size (its planes' margins are zeros) */
    float *mem;
    float *p[PLANES];
};

uint64_t denoiser_bytes(uint32_t max_w, uint32_t max_h)
{
    return ((uint64_t)max_w + 2 * PAD) * ((uint64_t)max_h + 2 * PAD) * PLANES * sizeof(float);
}

Denoiser *denoiser_create(Pool *pool, uint32_t max_w, uint32_t max_h)
{
    Denoiser *d = calloc(1, sizeof *d);
    const size_t n = ((size_t)max_w + 2 * PAD) * ((size_t)max_h + 2 * PAD);
    float *mem = d && max_w <= 1u << 20 && max_h <= 1u << 20 && n < SIZE_MAX / PLANES / sizeof *mem
                     ? malloc(n * PLANES * sizeof *mem)
                     : NULL;
    if (!mem) {
        free(d);
        return NULL;
    }
    d->pool = pool, d->mem = mem, d->max_w = max_w, d->max_h = max_h;
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

static inline float divisor(float a) { return a > ALBEDO_FLOOR ? a : ALBEDO_FLOOR; }

/* rows [lo, hi): the pixels' light and guides read, the light divided by the albedo */
static void pass_read(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->P;
    for (uint64_t b = lo * ps->w; b < hi * ps->w; b++) {
        const uint8_t *p = ps->px + b * ps->bpp;
        const size_t i = plane_at(ps, (int)(b % ps->w), (int)(b / ps->w));
        float c[3], n[3], a[3], z, noise;
        pixel_read_colour(p, ps->cb, ps->linear, c);
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
    float *const *P = ps->P;
    for (uint64_t b = lo * ps->w; b < hi * ps->w; b++) {
        const size_t i = plane_at(ps, (int)(b % ps->w), (int)(b / ps->w));
        /* the neighbours left, right, up, down (in the margin: no surface) */
        const size_t at[4] = {i - 1, i + 1, i - ps->stride, i + ps->stride};
        float g[2] = {-1, -1}; /* -1: no neighbour on that axis */
        for (int k = 0; k < 4 && P[P_SURF][i] > 0; k++) {
            if (!(P[P_SURF][at[k]] > 0))
                continue;
            const float diff = absf(P[P_Z][at[k]] - P[P_Z][i]);
            g[k / 2] = g[k / 2] < 0 || diff < g[k / 2] ? diff : g[k / 2];
        }
        P[P_DZ][i] = g[0] > g[1] ? (g[0] > 0 ? g[0] : 0) : (g[1] > 0 ? g[1] : 0);
    }
}

/* rows [lo, hi): the luminance of the light the next pass reads */
static void pass_lum(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    for (uint64_t y = lo; y < hi; y++)
        for (size_t i = plane_at(ps, 0, (int)y), e = i + ps->w; i < e; i++)
            ps->P[P_LUM][i] = luminance(ps->in[0][i], ps->in[1][i], ps->in[2][i]);
}

/* rows [lo, hi): the variance blurred by a 3 x 3 Gaussian (the luminance
 * weight's spread, steadier than one pixel's) */
static void pass_blur(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->P;
    static const float k3[3] = {0.25f, 0.5f, 0.25f};
    for (int y = (int)lo; y < (int)hi; y++)
        for (int x = 0; x < (int)ps->w; x++) {
            const size_t i = plane_at(ps, x, y);
            float s = 0, sw = 0, sl = 0;
            for (int j = -1; j <= 1; j++)
                for (int k = -1; k <= 1; k++) {
                    const size_t q = (size_t)((ptrdiff_t)i + j * (ptrdiff_t)ps->stride + k);
                    const float wt = k3[j + 1] * k3[k + 1] * P[P_SURF][q];
                    s += wt * ps->var_in[q], sw += wt, sl += wt * P[P_LUM][q];
                }
            P[P_VBLUR][i] = sw > 0 ? s / sw : 0;
            P[P_LBLUR][i] = sw > 0 ? sl / sw : P[P_LUM][i];
        }
}

/* rows [lo, hi): the filtered light times the albedo again, coded; a pixel
 * that met no surface keeps its own bytes */
static void pass_write(void *ctx, uint64_t lo, uint64_t hi, int thread)
{
    (void)thread;
    const Pass *ps = ctx;
    float *const *P = ps->P;
    for (uint64_t b = lo * ps->w; b < hi * ps->w; b++) {
        uint8_t *o = ps->out + b * ps->cb;
        const size_t i = plane_at(ps, (int)(b % ps->w), (int)(b / ps->w));
        if (!(P[P_SURF][i] > 0)) {
            memcpy(o, ps->px + b * ps->bpp, ps->cb);
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
    if (w == 0 || h == 0)
        return 0;
    if (w > d->max_w || h > d->max_h)
        return err_set(err, "denoise: a frame of %ux%u is larger than the %ux%u made for", w, h, d->max_w, d->max_h);
    if (w != d->w || h != d->h) { /* another layout: its margins zeros */
        const size_t n = ((size_t)d->max_w + 2 * PAD) * ((size_t)d->max_h + 2 * PAD);
        memset(d->mem, 0, n * PLANES * sizeof *d->mem);
        d->w = w, d->h = h;
    }
    const int avx2 = simd_path() >= SIMD_AVX2;
    PoolRangeFn moments = avx2 ? denoise_moments_avx2 : denoise_moments_sse,
                atrous = avx2 ? denoise_atrous_avx2 : denoise_atrous_sse;
    Pass ps = {.P = d->p, .px = px, .out = out, .w = w, .cb = colour_bytes,
               .bpp = colour_bytes + DENOISE_GUIDE_BYTES, .stride = (size_t)w + 2 * PAD, .linear = linear};
    float *const *P = d->p;
    const uint64_t grain = 4; /* rows a call */
    pool_for(d->pool, h, grain, pass_read, &ps);
    pool_for(d->pool, h, grain, pass_gradient, &ps);
    set_light(&ps, P, P_R, P_R2);
    ps.var_out = P[P_VAR];
    pool_for(d->pool, h, grain, moments, &ps);
    int cur = P_R2, var = P_VAR; /* where the light and its variance are */
    for (int k = 0; k < PASSES; k++) {
        const int next = cur == P_R ? P_R2 : P_R, next_var = var == P_VAR ? P_VAR2 : P_VAR;
        set_light(&ps, P, cur, next);
        ps.var_in = P[var], ps.var_out = P[next_var];
        pool_for(d->pool, h, grain, pass_lum, &ps);
        pool_for(d->pool, h, grain, pass_blur, &ps);
        ps.step = 1 << k;
        pool_for(d->pool, h, grain, atrous, &ps);
        cur = next, var = next_var;
    }
    set_light(&ps, P, cur, cur);
    pool_for(d->pool, h, grain, pass_write, &ps);
    return 0;
}
