/* environment.h - light from everywhere: an image around the scene (an
 * equirectangular panorama, a Radiance .hdr's light) that rays which leave
 * the scene see, and that lights it.
 *
 * The image wraps the sphere of directions as Blender's Environment
 * Texture does (so that tools/bench/scene2cycles hands Cycles the same
 * world): u = atan2(z, x) / 2 pi + 1/2 plus the turn, the image's centre
 * along +x, its left and right edges along -x and a quarter in along -z
 * (where a camera of yaw 0 looks); v its elevation, the top row straight
 * up.  The path integrator
 * samples it by importance: a direction drawn in proportion to each
 * texel's weight (its light less the image's mean light, at least a
 * twentieth of its light: what stands out, the sun, drawn, and the even rest left
 * mostly to the paths) times the solid angle it spans (sin of its polar
 * angle), blended between texel centres as the light is (bilinear: a cell between
 * four centres picked by a row of cells from the rows' sums and a cell
 * from the row's, then a point in it; environment_pdf is that density),
 * weighed against the paths that meet it by multiple importance sampling.  The Whitted
 * integrator lights a diffuse surface by the image's irradiance at its
 * normal from nine spherical harmonics (Ramamoorthi and Hanrahan, "An
 * efficient representation for irradiance environment maps", 2001): no
 * shadow, as its ambient light has none, and no noise; and a sun in the
 * image (a small patch far brighter than the rest, environment_sun) as a
 * directional light of its own, with its shadows and highlights, the
 * harmonics made without it.
 *
 * Everything is made from the texels in a fixed order in double, so that
 * every client of a farm derives the same numbers. */
#ifndef LANRAY_ENVIRONMENT_H
#define LANRAY_ENVIRONMENT_H

#include "base/err.h"
#include "base/srgb.h"
#include "base/vec.h"
#include "model/texture.h"

/* Levels of the image's mip-map: 1 (the image) + 15 down to 1 x 1 from 16384 wide. */
#define ENV_MAX_LEVELS 16

typedef struct {
    uint32_t w, h;
    const float *hdr;      /* the texture's light (Texture.hdr), or NULL: */
    const uint8_t *codes;  /* its sRGB codes (level 0), both borrowed: no copy a client */
    real gain;             /* the strength, held so that no texel's light passes ENV_MAX_LIGHT */
    real turn;             /* the turn about +y as a fraction of a circle */
    float *rows;           /* h + 2: the cell rows' cumulative shares, 0 to 1 (environment.c) */
    float *cols;           /* (h + 1) x (w + 1): each cell row's cells' cumulative shares, 0 to 1 */
    float *weight;         /* w x h: each texel's weight in the draws, its light times its row's
                            * polar sine (its solid angle's share) */
    double total;          /* the cells' weights summed: 0 where the image is black */
    double scale;          /* w x h / total: a blend of weights to a density over the unit square */
    double sh[9][3];       /* the irradiance's spherical harmonics, each band's convolution applied
                            * (without the sun's texels where it has one) */
    int has_sun;
    vec3 sun_dir;          /* towards the sun: its texels' directions weighed by their light */
    vec3 sun_light;        /* its irradiance head on over pi: a directional light's colour */
    uint8_t *sun_mask;     /* a bit a texel, set for the sun's (NULL without a sun) */
    real sun_fill[3];      /* the mean light of the texels round the sun, which stands in for it
                            * (before the gain, as the texels are stored) */
    uint32_t levels;       /* 1 + the box-filtered levels below the image (environment_levels.c) */
    uint32_t lw[ENV_MAX_LEVELS], lh[ENV_MAX_LEVELS];
    float *level[ENV_MAX_LEVELS]; /* level l >= 1: lw x lh texels, 3 floats each, before the gain */
    float *sunless[ENV_MAX_LEVELS]; /* the same of the image without its sun (its texels filled,
                                     * as environment_radiance_sunless reads it); only with a sun */
} Environment;

/* Channel k of texel i (row-major) as stored: before the gain. */
static inline real environment_texel(const Environment *e, size_t i, int k)
{
    return e->hdr ? (real)e->hdr[3 * i + (size_t)k] : (real)srgb_decode8[e->codes[3 * i + (size_t)k]];
}

/* Whether texel i (row-major) is the sun's (Environment.sun_mask). */
static inline int environment_sun_texel(const Environment *e, size_t i)
{
    return e->sun_mask && (e->sun_mask[i / 8] >> (i % 8) & 1);
}

/* The environment of texture t (its .hdr light where it has one, else its
 * sRGB colours), times strength, turned by rotate degrees about +y; it
 * reads t's texels, which must outlive it (a world's, its description's
 * texture).  NULL with err set when out of memory. */
Environment *environment_create(const Texture *t, real strength, real rotate, Err *err);
void environment_destroy(Environment *e);

/* The light arriving from direction d (any length; bilinear in the image). */
vec3 environment_radiance(const Environment *e, vec3 d);
/* Image coordinates of direction d: u across, t down, each in [0, 1]. */
void environment_uv(const Environment *e, vec3 d, real *u, real *t);
/* The light at image point (u, t) (environment_uv's): bilinear between
 * texel centres, across the seam in u, held at the poles in t; sunless:
 * the sun's texels filled (environment_radiance_sunless). */
vec3 environment_light_at(const Environment *e, real u, real t, int sunless);

/* The four texels (row-major indices) round image point (u, t) of a w x h
 * image and their bilinear weights: between texel centres, across the
 * seam in u, held at the poles in t.  (For the image and its levels.) */
static inline void environment_corners(uint32_t w, uint32_t h, real u, real t, size_t at[4], real wq[4])
{
    const real fx = u * (real)w - R(0.5), fy = t * (real)h - R(0.5);
    /* floor by truncation, a step down below zero (libm's floor is a call on the baseline x86-64) */
    int64_t x0 = (int64_t)fx, y0 = (int64_t)fy; /* u in [0, 1): x0 from -1 to w - 1 */
    x0 -= (real)x0 > fx, y0 -= (real)y0 > fy;
    const real ax = fx - (real)x0, ay = fy - (real)y0;
    const uint32_t xa = x0 < 0 ? w - 1 : (uint32_t)x0, xb = xa + 1 < w ? xa + 1 : 0;
    const uint32_t ya = y0 < 0 ? 0 : (uint32_t)y0, yb = y0 + 1 >= (int64_t)h ? h - 1 : (uint32_t)(y0 + 1);
    at[0] = (size_t)ya * w + xa, at[1] = (size_t)ya * w + xb, at[2] = (size_t)yb * w + xa, at[3] = (size_t)yb * w + xb;
    wq[0] = (R(1) - ax) * (R(1) - ay), wq[1] = ax * (R(1) - ay), wq[2] = (R(1) - ax) * ay, wq[3] = ax * ay;
}

/* environment_levels.c: the image's mip-map, each level the one above
 * box-filtered to half its size, down to 1 x 1, made when the environment
 * is (in one order, in double: every client the same floats); 0, or -1
 * out of memory. */
int environment_make_levels(Environment *e, Err *err);
/* The light arriving from direction d seen over a footprint `width`
 * radians wide (a sample's, from its ray differentials): bilinear in the
 * image where the footprint spans at most a texel (environment_radiance's
 * very numbers), else trilinear between the two levels whose texels span
 * it, so that a mirror ball or a wide lens that shrinks the panorama
 * shows its mean and does not alias. */
vec3 environment_radiance_over(const Environment *e, vec3 d, real width);
/* The same of the image without its sun (environment_radiance_sunless):
 * what a rough metal's or frosted glass's ray sees over its cone. */
vec3 environment_radiance_sunless_over(const Environment *e, vec3 d, real width);
/* A direction drawn by importance from two numbers in [0, 1): its light
 * and its density over solid angle; 0 where the image is black. */
int environment_sample(const Environment *e, real u1, real u2, vec3 *dir, vec3 *light, real *pdf);
/* The density environment_sample draws direction d with (0 for a black image). */
real environment_pdf(const Environment *e, vec3 d);
/* Both at once, for a path that leaves the scene along d: the light
 * arriving from d, and the density into *pdf (one look-up of d). */
vec3 environment_seen(const Environment *e, vec3 d, real *pdf);
/* The light from d as the Whitted integrator's mirrors and glass see it:
 * its sun's texels (where it has one: a light of its own, whose highlight
 * stands for its reflection, as for every light) filled with the sky
 * round the sun.  Without this a rough metal's rays that met the sun were
 * sparkles, and an imported metal's highlight showed the sun twice. */
vec3 environment_radiance_sunless(const Environment *e, vec3 d);
/* What a white diffuse surface of normal n (unit) shows of it, unshadowed:
 * its irradiance / pi (less the sun's, where it has one). */
vec3 environment_diffuse(const Environment *e, vec3 n);

/* The image's sun, if it has one: its brightest texel at least
 * ENV_SUN_CONTRAST times the image's mean light, and with it every texel
 * within ENV_SUN_DEGREES of it that holds at least ENV_SUN_SHARE of its
 * light.  Found when the environment is made (Environment.has_sun). */
#define ENV_SUN_CONTRAST 50.0
#define ENV_SUN_DEGREES 12.0
#define ENV_SUN_SHARE 0.02

#endif
