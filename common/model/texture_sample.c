/* texture_sample.c - reading a texture over a ray's footprint.
 *
 * The footprint (how far u and v move from one sample to the next, across
 * and down the image: texture.h) measured in texels gives the level of
 * detail lambda = log2(rho), rho the longer of its two sides: where one
 * sample spans rho texels, level lambda has about one texel per sample,
 * and sampling it does not alias (Williams, "Pyramidal Parametrics", 1983).
 * Trilinear filtering blends the bilinear lookups of the two levels around
 * lambda.  On a surface seen edge-on the footprint is long and thin, and
 * rho (its long side) blurs across the short one; anisotropic filtering
 * takes N = long / short (at most ANISO_MAX) trilinear probes spread along
 * the long side, at the level of long / N, as GPUs do.
 *
 * Magnified (lambda <= 0), a texture's texels blend bilinearly, or, for a
 * `closest` texture (pixel art, a checkerboard of one texel a square),
 * stay squares: the bilinear weight is sharpened to the box of the sample's
 * footprint, a ramp one footprint wide at each texel edge instead of one
 * texel wide (with a footprint of a texel it is bilinear again, so the two
 * meet where magnification ends).
 *
 * lambda is computed without libm (frexp is exact, the fraction linear):
 * the same bits on every machine, as the pixels of a farm must be. */
#include <math.h>

#include "base/srgb.h"
#include "model/texture.h"

#define ANISO_MAX 16

/* Wraps a coordinate into [0,1); NaN and inf map to 0. */
static inline real wrap01(real u)
{
    if (!isfinite(u))
        return R(0);
    u -= floor(u);
    return u >= R(1) ? R(0) : u;
}

/* Clamps a coordinate into [0,1]; NaN maps to 0. */
static inline real clamp01(real u) { return u > R(0) ? (u < R(1) ? u : R(1)) : R(0); }

/* Folds a coordinate into [0,1] as mirrored tiles do: [1, 2] runs back
 * from 1 to 0, [2, 3] forward again; NaN and inf map to 0.  Exact: the
 * halving, the floor and the subtraction of an even whole number. */
static inline real mirror01(real u)
{
    if (!isfinite(u))
        return R(0);
    u -= R(2) * floor(u * R(0.5)); /* [0, 2] */
    return u > R(1) ? R(2) - u : u;
}

/* A coordinate along one axis into [0, 1] by that axis's wrap mode. */
static inline real wrap_axis(uint8_t wrap, real u)
{
    return wrap == TEXTURE_CLAMP ? clamp01(u) : wrap == TEXTURE_MIRROR ? mirror01(u) : wrap01(u);
}

/* A texel index along a side of n, from -1 to n (a coordinate in [0, 1]
 * less half a texel, and the texel after it): wrapped, or held at the
 * edge, where the mirrored tile beyond starts with the edge's texel too.
 * No division: it showed in the profile of a textured floor. */
static inline uint32_t address(uint8_t wrap, int64_t i, uint32_t n)
{
    if (wrap != TEXTURE_REPEAT)
        return i < 0 ? 0 : i >= (int64_t)n ? n - 1 : (uint32_t)i;
    return i < 0 ? n - 1 : i >= (int64_t)n ? 0 : (uint32_t)i;
}

/* The weight of the second of two texels at fraction a between their
 * centres, for a box footprint of s texels: a itself for s >= 1
 * (bilinear), a ramp of width s about their shared edge below. */
static inline real sharpen(real a, real s)
{
    if (s >= R(1))
        return a;
    real w = (a - R(0.5)) / s + R(0.5);
    return w < R(0) ? R(0) : w > R(1) ? R(1) : w;
}

/* A code as a number: a colour's in linear light (sRGB decoded, `data`
 * 0); a normal map's (data 1), 0 -> -1 and 255 -> 1 (128 a little above 0,
 * as glTF's and every exporter's maps have it); a fraction's (data 2: a
 * metal-roughness texture's), c / 255. */
static inline real code_value(uint8_t c, const int data)
{
    return data == 1 ? (real)c * (R(2) / R(255)) - R(1) : data == 2 ? (real)c / R(255) : (real)srgb_decode8[c];
}

/* Texel (x, y) of level L, a colour or data (code_value). */
static inline vec3 texel_by(const TextureLevel *L, uint32_t x, uint32_t y, const int data)
{
    const uint8_t *p = &L->rgb[3 * ((size_t)y * L->w + x)];
    return v3(code_value(p[0], data), code_value(p[1], data), code_value(p[2], data));
}

/* Texel (x, y) of level L in linear light. */
static inline vec3 texel(const TextureLevel *L, uint32_t x, uint32_t y) { return texel_by(L, x, y, 0); }

/* Bilinear in level L of t, colours or data (texel_by); (u, v) wrapped or
 * clamped already, v = 0 at the top; sx, sy: a closest texture's footprint
 * in this level's texels. */
static inline vec3 bilinear_by(const Texture *t, const TextureLevel *L, real u, real v, real sx, real sy,
                               const int data)
{
    real fx = u * (real)L->w - R(0.5), fy = v * (real)L->h - R(0.5);
    real x0f = floor(fx), y0f = floor(fy);
    real ax = fx - x0f, ay = fy - y0f;
    if (t->closest) {
        ax = sharpen(ax, sx);
        ay = sharpen(ay, sy);
    }
    int64_t x0 = (int64_t)x0f, y0 = (int64_t)y0f;
    uint32_t xa = address(t->wrap[0], x0, L->w), xb = address(t->wrap[0], x0 + 1, L->w);
    uint32_t ya = address(t->wrap[1], y0, L->h), yb = address(t->wrap[1], y0 + 1, L->h);
    vec3 top = v3_lerp(texel_by(L, xa, ya, data), texel_by(L, xb, ya, data), ax);
    vec3 bot = v3_lerp(texel_by(L, xa, yb, data), texel_by(L, xb, yb, data), ax);
    return v3_lerp(top, bot, ay);
}

static inline vec3 bilinear(const Texture *t, uint32_t l, real u, real v, real sx, real sy)
{
    return bilinear_by(t, &t->level[l], u, v, sx, sy, 0);
}

/* A coordinate pair as the levels index them: each axis by its wrap
 * mode, v from the top. */
static inline void place(const Texture *t, real *u, real *v)
{
    *u = wrap_axis(t->wrap[0], *u);
    *v = R(1) - wrap_axis(t->wrap[1], *v);
}

/* log2(x) for x > 0: exact at powers of two, linear between (at most 0.09
 * low); -inf for 0, and huge for inf or NaN. */
static real lod_log2(real x)
{
    if (!(x > R(0)))
        return -REAL_INF;
    if (!isfinite(x))
        return R(1e9);
    int e;
    real m = frexp(x, &e); /* x = m 2^e, m in [0.5, 1) */
    return (real)(e - 1) + (R(2) * m - R(1));
}

/* One trilinear lookup at level of detail lambda; (sx, sy): the
 * footprint's extent along u and v in texels of level 0 (closest). */
static inline vec3 trilinear(const Texture *t, real u, real v, real lambda, real sx, real sy)
{
    place(t, &u, &v);
    if (!(lambda > R(0)))
        return bilinear(t, 0, u, v, sx, sy);
    const real last = (real)(t->levels - 1);
    if (lambda >= last)
        return bilinear(t, t->levels - 1, u, v, 1, 1);
    uint32_t l = (uint32_t)lambda;
    real f = lambda - (real)l;
    return v3_lerp(bilinear(t, l, u, v, 1, 1), bilinear(t, l + 1, u, v, 1, 1), f);
}

/* The image's texel nearest to (u, v), after the wrap modes (level 0). */
static inline void nearest_xy(const Texture *t, real u, real v, uint32_t *x, uint32_t *y)
{
    place(t, &u, &v);
    const uint32_t nx = (uint32_t)(u * (real)t->w), ny = (uint32_t)(v * (real)t->h);
    *x = nx < t->w ? nx : t->w - 1, *y = ny < t->h ? ny : t->h - 1;
}

static vec3 nearest(const Texture *t, real u, real v)
{
    uint32_t x, y;
    nearest_xy(t, u, v, &x, &y);
    return texel(&t->level[0], x, y);
}

vec3 texture_sample(const Texture *t, real u, real v, const TexFootprint *fp, TextureFilter filter)
{
    if (!isfinite(u) || !isfinite(v))
        u = v = R(0);
    if (filter == FILTER_NEAREST)
        return nearest(t, u, v);
    if (!fp) {
        if (t->closest) /* no footprint: a square's texel */
            return nearest(t, u, v);
        place(t, &u, &v);
        return bilinear(t, 0, u, v, 1, 1);
    }
    /* the footprint's two sides, in texels of level 0 */
    const real W = (real)t->w, H = (real)t->h;
    real ax = fp->dudx * W, ay = fp->dvdx * H, bx = fp->dudy * W, by = fp->dvdy * H;
    real la = sqrt(ax * ax + ay * ay), lb = sqrt(bx * bx + by * by);
    real sx = fabs(ax) + fabs(bx), sy = fabs(ay) + fabs(by);
    if (filter == FILTER_BILINEAR) {
        place(t, &u, &v);
        return bilinear(t, 0, u, v, sx, sy);
    }
    real major = real_max(la, lb), minor = real_min(la, lb);
    if (filter == FILTER_TRILINEAR || !(major > R(0)) || !isfinite(major))
        return trilinear(t, u, v, lod_log2(major), sx, sy);
    /* anisotropic: probes along the long side, each at the level of long / n */
    real ratio = minor > R(0) ? major / minor : (real)ANISO_MAX;
    int n = ratio >= (real)ANISO_MAX ? ANISO_MAX : (int)ceil(ratio);
    if (n <= 1)
        return trilinear(t, u, v, lod_log2(major), sx, sy);
    real du = la >= lb ? fp->dudx : fp->dudy, dv = la >= lb ? fp->dvdx : fp->dvdy;
    real lambda = lod_log2(major / (real)n);
    /* each probe's footprint: the long side cut in n, the short one whole */
    real psx = (la >= lb ? fabs(ax) : fabs(bx)) / (real)n + (la >= lb ? fabs(bx) : fabs(ax));
    real psy = (la >= lb ? fabs(ay) : fabs(by)) / (real)n + (la >= lb ? fabs(by) : fabs(ay));
    vec3 sum = v3_splat(0);
    for (int i = 0; i < n; i++) {
        real k = ((real)i + R(0.5)) / (real)n - R(0.5);
        sum = v3_add(sum, trilinear(t, u + du * k, v + dv * k, lambda, psx, psy));
    }
    return v3_scale(sum, R(1) / (real)n);
}

real texture_coverage(const Texture *t, real u, real v)
{
    if (!isfinite(u) || !isfinite(v))
        u = v = R(0);
    uint32_t x, y;
    nearest_xy(t, u, v, &x, &y);
    const size_t i = (size_t)y * t->w + x;
    if (t->alpha)
        return (real)t->alpha[i] / R(255);
    const uint8_t *p = &t->level[0].rgb[3 * i];
    return (real)(p[0] + p[1] + p[2]) / R(765);
}

/* A data texture's texel values at (u, v) in the image itself, codes read
 * as `data` (code_value): the nearest texel of a `closest` texture, else
 * bilinear; *placed the coordinates as the levels index them (NULL for a
 * closest texture, which reads no level below). */
static vec3 data_at(const Texture *t, real *u, real *v, const int data, int *placed)
{
    if (!isfinite(*u) || !isfinite(*v))
        *u = *v = R(0);
    *placed = 0;
    if (t->closest) {
        uint32_t x, y;
        nearest_xy(t, *u, *v, &x, &y);
        return texel_by(&t->level[0], x, y, data);
    }
    place(t, u, v);
    *placed = 1;
    return bilinear_by(t, &t->level[0], *u, *v, 1, 1, data);
}

/* A data texture's values over the footprint fp (NULL: at the point),
 * codes read as `data`: trilinearly in the data levels where t has them
 * (texture_make_data_levels), else at the point. */
static vec3 data_over(const Texture *t, real u, real v, const TexFootprint *fp, const int data)
{
    int placed;
    const vec3 here = data_at(t, &u, &v, data, &placed);
    if (!placed || !fp || !t->data_texels)
        return here;
    /* the footprint's longer side in texels of the image, as trilinear takes it */
    const real W = (real)t->w, H = (real)t->h;
    const real ax = fp->dudx * W, ay = fp->dvdx * H, bx = fp->dudy * W, by = fp->dvdy * H;
    const real lambda = lod_log2(real_max(sqrt(ax * ax + ay * ay), sqrt(bx * bx + by * by)));
    if (!(lambda > R(0)))
        return here;
    const real last = (real)(t->levels - 1);
    if (lambda >= last)
        return bilinear_by(t, &t->data_level[t->levels - 1], u, v, 1, 1, data);
    const uint32_t l = (uint32_t)lambda;
    return v3_lerp(bilinear_by(t, &t->data_level[l], u, v, 1, 1, data), bilinear_by(t, &t->data_level[l + 1], u, v, 1, 1, data),
                   lambda - (real)l);
}

vec3 texture_normal(const Texture *t, real u, real v, const TexFootprint *fp) { return data_over(t, u, v, fp, 1); }

vec3 texture_fractions(const Texture *t, real u, real v, const TexFootprint *fp) { return data_over(t, u, v, fp, 2); }
