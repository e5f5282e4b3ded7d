/* environment_levels.c - the environment's mip-map and its light over a
 * footprint (environment.h).
 *
 * A mirror ball, glass or a fisheye lens shrinks the panorama: one sample
 * a pixel then reads one texel of the many its footprint covers, and the
 * reflection sparkles and crawls as the view moves.  Each level halves the
 * one above (a texel the mean of the two by two above it; an odd row or
 * column's last texel the mean of what it covers), and a sample reads the
 * level whose texels span its footprint, as textures do (texture.h).  The
 * footprint's width counts in texels across (its arc over the row's
 * circumference, which shrinks towards the poles) and down, the larger of
 * the two: blurred along a row near the poles rather than aliased.  An
 * image with a sun has a second mip-map without it (its texels filled as
 * environment_radiance_sunless fills them), which rough metals' and
 * frosted glass's rays read over their cones. */
#include "scene/environment.h"

#include "base/dmath.h"

#include <math.h>
#include <stdlib.h>

/* Channel k of the image's texel (x, y), before the gain; `dark`: its
 * sun's texels filled with the sky round it (environment_radiance_sunless). */
static double image_texel(const Environment *e, int dark, uint32_t x, uint32_t y, int k)
{
    const size_t i = (size_t)y * e->w + x;
    return (double)(dark && environment_sun_texel(e, i) ? e->sun_fill[k] : environment_texel(e, i, k));
}

/* Level l (>= 1) of the image, or of the image without its sun: the level
 * above halved (a texel the mean of the two by two above it; an odd row's
 * or column's last texel the mean of what it covers), or NULL. */
static float *halve(const Environment *e, int dark, uint32_t l)
{
    const uint32_t pw = e->lw[l - 1], ph = e->lh[l - 1], w = e->lw[l], h = e->lh[l];
    const float *above = l > 1 ? (dark ? e->sunless : e->level)[l - 1] : NULL;
    float *out = malloc((size_t)w * h * 3 * sizeof *out);
    if (!out)
        return NULL;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const uint32_t x1 = 2 * x + 1 < pw ? 2 * x + 1 : 2 * x, y1 = 2 * y + 1 < ph ? 2 * y + 1 : 2 * y;
            const double n = (double)((x1 - 2 * x + 1) * (y1 - 2 * y + 1));
            for (int k = 0; k < 3; k++) {
                double s = 0.0;
                for (uint32_t sy = 2 * y; sy <= y1; sy++)
                    for (uint32_t sx = 2 * x; sx <= x1; sx++)
                        s += above ? (double)above[3 * ((size_t)sy * pw + sx) + (size_t)k] : image_texel(e, dark, sx, sy, k);
                out[3 * ((size_t)y * w + x) + (size_t)k] = (float)(s / n);
            }
        }
    return out;
}

int environment_make_levels(Environment *e, Err *err)
{
    e->levels = 1, e->lw[0] = e->w, e->lh[0] = e->h;
    while (e->levels < ENV_MAX_LEVELS && (e->lw[e->levels - 1] > 1 || e->lh[e->levels - 1] > 1)) {
        const uint32_t l = e->levels;
        e->lw[l] = (e->lw[l - 1] + 1) / 2, e->lh[l] = (e->lh[l - 1] + 1) / 2;
        e->level[l] = halve(e, 0, l);
        e->sunless[l] = e->sun_mask && e->level[l] ? halve(e, 1, l) : NULL;
        e->levels++; /* (what was made is freed with the environment) */
        if (!e->level[l] || (e->sun_mask && !e->sunless[l]))
            return err_set(err, "scene: out of memory for the environment's mip-map (%ux%u)", e->lw[l], e->lh[l]);
    }
    return 0;
}

/* Level l (>= 1) of the image (or of it without its sun: dark) at image
 * point (u, t), bilinear (environment_corners), times the gain. */
static vec3 level_at(const Environment *e, int dark, uint32_t l, real u, real t)
{
    size_t at[4];
    real wq[4];
    environment_corners(e->lw[l], e->lh[l], u, t, at, wq);
    const float *m = dark ? e->sunless[l] : e->level[l];
    const float *p[4] = {&m[3 * at[0]], &m[3 * at[1]], &m[3 * at[2]], &m[3 * at[3]]};
    real c[3];
    for (int k = 0; k < 3; k++)
        c[k] = (wq[0] * (real)p[0][k] + wq[1] * (real)p[1][k] + wq[2] * (real)p[2][k] + wq[3] * (real)p[3][k]) * e->gain;
    return v3(c[0], c[1], c[2]);
}

/* environment_radiance_over, of the image or (dark) of it without its sun. */
static vec3 radiance_over(const Environment *e, vec3 d, real width, int dark)
{
    dark = dark && e->sun_mask;
    real u, t;
    environment_uv(e, d, &u, &t);
    if (!(width > R(0)) || e->levels < 2)
        return environment_light_at(e, u, t, dark);
    /* texels the footprint spans: across, its arc over the row's circle
     * (the cosine of the elevation, kept off 0), and down */
    const real c = real_max(dmath_sinr(t * REAL_PI), R(1) / (real)e->w);
    const real across = width * (real)e->w / (R(2) * REAL_PI * c), down = width * (real)e->h / REAL_PI;
    const real lod = dmath_log2r(real_max(across, down));
    if (!(lod > R(0))) /* magnified: the image itself, as without a footprint */
        return environment_light_at(e, u, t, dark);
    const real top = (real)(e->levels - 1);
    const real at = lod < top ? lod : top;
    const uint32_t l = (uint32_t)at;
    const real f = at - (real)l;
    const vec3 a = l > 0 ? level_at(e, dark, l, u, t) : environment_light_at(e, u, t, dark);
    if (f == R(0) || l + 1 >= e->levels)
        return a;
    return v3_lerp(a, level_at(e, dark, l + 1, u, t), f);
}

vec3 environment_radiance_over(const Environment *e, vec3 d, real width) { return radiance_over(e, d, width, 0); }

vec3 environment_radiance_sunless_over(const Environment *e, vec3 d, real width)
{
    return radiance_over(e, d, width, 1);
}
