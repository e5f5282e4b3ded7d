/* progressive.c - sums of a pixel's samples in batches, and the pixel they
 * make (progressive.h). */
#include "render/progressive.h"

#include <math.h>
#include <string.h>

#include "render/pixel.h"

int progressive_batches(const RenderSettings *rs)
{
    const int n = rs->aa;
    if (rs->integrator != INTEGRATOR_PATH || rs->adaptive || n < 2 || (n & (n - 1)) != 0)
        return 0;
    return 2 * __builtin_ctz((unsigned)n) + 1;
}

void progressive_add_sample(real *sums, vec3 c, const Guide *g)
{
    for (int k = 0; k < 3; k++)
        sums[k] += c.e[k];
    if (!g)
        return;
    real *s = sums + PROG_COLOUR;
    for (int k = 0; k < 3; k++)
        s[k] += g->albedo.e[k];
    s[3] += g->lum2;
    if (g->surface) { /* as render.c's guide_add: the normals and distances of samples that met a surface */
        for (int k = 0; k < 3; k++)
            s[4 + k] += g->normal.e[k];
        s[7] += g->depth;
        s[8] += (real)g->surface;
    }
}

void progressive_fold(real *total, const real *batch, uint32_t n)
{
    for (uint32_t k = 0; k < n; k++)
        total[k] += batch[k];
}

void progressive_encode(const RenderSettings *rs, real gain, const real *sums, uint32_t samples, uint8_t *dst)
{
    const real inv = R(1) / (real)samples; /* a power of 2: exact */
    const vec3 mean = v3(sums[0] * inv, sums[1] * inv, sums[2] * inv);
    pixel_put_colour(dst, mean, rs->hdr, gain, rs->tonemap, rs->linear);
    if (!render_guided(rs))
        return;
    /* a client's sums, on a server: whatever their bits, numbers the
     * guide's packing takes (finite, the surface count a count) */
    real s[PROG_GUIDE];
    for (uint32_t k = 0; k < PROG_GUIDE; k++)
        s[k] = isfinite(sums[PROG_COLOUR + k]) ? sums[PROG_COLOUR + k] : R(0);
    const int surface = s[8] >= R(1) ? (s[8] < (real)samples ? (int)s[8] : (int)samples) : 0;
    const Guide g = {.albedo = v3(s[0], s[1], s[2]), .lum2 = s[3], .normal = v3(s[4], s[5], s[6]), .depth = s[7],
                     .surface = surface};
    denoise_guide_pack(&g, (int)samples, mean, dst + render_colour_bytes(rs));
}

/* progressive_frame_add's pixels from acc (NULL: zeros), the sums kept
 * in `kept` where not NULL. */
static void frame_fold(const RenderSettings *rs, const real *acc, real *kept, const uint8_t *sums, size_t n,
                       uint8_t *out)
{
    const uint32_t reals = progressive_reals(rs), bpp = render_shown_bytes(rs);
    const uint32_t samples = progressive_end(rs->batch);
    const real gain = pixel_gain(rs);
    for (size_t i = 0; i < n; i++) {
        real b[PROG_MAX], total[PROG_MAX] = {0};
        memcpy(b, sums + i * reals * sizeof(real), reals * sizeof(real));
        if (acc)
            memcpy(total, acc + i * reals, reals * sizeof(real));
        progressive_fold(total, b, reals);
        if (kept)
            memcpy(kept + i * reals, total, reals * sizeof(real));
        progressive_encode(rs, gain, total, samples, out + i * bpp);
    }
}

void progressive_frame_add(const RenderSettings *rs, real *acc, const uint8_t *sums, size_t n, uint8_t *out)
{
    frame_fold(rs, acc, acc, sums, n, out);
}

void progressive_frame_peek(const RenderSettings *rs, const real *acc, const uint8_t *sums, size_t n, uint8_t *out)
{
    frame_fold(rs, acc, NULL, sums, n, out);
}
