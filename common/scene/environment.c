/* environment.c - see environment.h. */
#include "scene/environment.h"

#include "base/dmath.h"

#include <math.h>
#include <stdlib.h>

#include "base/srgb.h"
#include "base/trig.h"

#define PI 3.14159265358979323846
/* the least share of its light a texel's weight in the draws keeps (env_tables) */
#define ENV_DRAW_FLOOR 0.05
/* the most light a texel may hold: a float's range over the texels' sums and a bilinear blend */
#define ENV_MAX_LIGHT 1e30

void environment_uv(const Environment *e, vec3 d, real *u, real *t)
{
    real a = trig_atan2(d.z, d.x) / (R(2) * REAL_PI) + R(0.5) + e->turn;
    a -= floor(a);
    *u = a < R(1) ? a : R(0);
    const real el = trig_atan2(d.y, sqrt(d.x * d.x + d.z * d.z)); /* -pi/2 .. pi/2 */
    *t = real_clamp(R(0.5) - el / REAL_PI, R(0), R(1));
    if (!(*t >= R(0))) /* a direction of NaNs reads the top row */
        *t = R(0);
}

/* The light of texel i, times the gain. */
static inline void texel(const Environment *e, size_t i, real c[3])
{
    for (int k = 0; k < 3; k++)
        c[k] = environment_texel(e, i, k) * e->gain;
}

/* The weight a texel's light gives its solid angle: its channels' mean. */
static double texel_weight(const real *c) { return ((double)c[0] + (double)c[1] + (double)c[2]) / 3.0; }

/* The nine real spherical harmonics at unit direction (x, y, z). */
static void sh_basis(double x, double y, double z, double b[9])
{
    b[0] = 0.282095;
    b[1] = 0.488603 * y, b[2] = 0.488603 * z, b[3] = 0.488603 * x;
    b[4] = 1.092548 * x * y, b[5] = 1.092548 * y * z, b[6] = 0.315392 * (3.0 * z * z - 1.0);
    b[7] = 1.092548 * x * z, b[8] = 0.546274 * (x * x - y * y);
}

/* The solid angles of the rows' texels, scaled to 4 pi in all (the
 * midpoint rule's sum of sines is 2 only as h grows): a constant image's
 * first band of harmonics exact at any size, the others' sums off by some
 * 0.6 / h^2 of it (0.2% at 16 rows: tests/test_environment.c). */
static double texel_solid_angle(const Environment *e, uint32_t y, double rings)
{
    return (2.0 * PI / e->w) * (PI / e->h) * dmath_sin((y + 0.5) / e->h * PI) * (2.0 / rings);
}

/* The texels' centres as directions, made once: each column's azimuth's
 * cosine and sine (the turn applied), each row's polar sine and cosine. */
typedef struct {
    double *cphi, *sphi; /* w each */
    double rings;        /* texel_solid_angle's */
} Grid;

static vec3 grid_dir(const Grid *g, uint32_t x, double sn, double cs)
{
    return v3((real)(sn * g->cphi[x]), (real)cs, (real)(sn * g->sphi[x]));
}

/* Whether a texel of light c in direction dir is the sun's (environment.h:
 * near its brightest texel, of light peak in direction at, and bright;
 * near: a cosine to at of at least cos_sun, cos(ENV_SUN_DEGREES), made
 * once by the caller). */
static int sun_texel(const real *c, vec3 dir, double peak, vec3 at, double cos_sun)
{
    return texel_weight(c) >= ENV_SUN_SHARE * peak && (double)v3_dot(dir, at) >= cos_sun;
}

/* The sun (environment.h): its texels' light and direction, summed; 0
 * where the image has none.  Into *mean the texels' mean weight over the
 * sphere (their light's, by solid angle). */
static int env_find_sun(Environment *e, const Grid *g, double *mean)
{
    const uint32_t w = e->w, h = e->h;
    double power = 0.0, peak = 0.0;
    uint32_t px = 0, py = 0;
    for (uint32_t y = 0; y < h; y++) {
        const double dw = texel_solid_angle(e, y, g->rings);
        for (uint32_t x = 0; x < w; x++) {
            real c[3];
            texel(e, (size_t)y * w + x, c);
            const double l = texel_weight(c);
            power += l * dw;
            if (l > peak)
                peak = l, px = x, py = y;
        }
    }
    *mean = power / (4.0 * PI); /* the solid angles sum to 4 pi (texel_solid_angle) */
    if (!(peak > ENV_SUN_CONTRAST * power / (4.0 * PI)) ||
        !(e->sun_mask = calloc(((size_t)w * h + 7) / 8, 1))) /* (out of memory: no sun of its own) */
        return 0;
    double psn, pcs;
    dmath_sincos((py + 0.5) / h * PI, &psn, &pcs);
    const vec3 at = grid_dir(g, px, psn, pcs);
    double d[3] = {0, 0, 0}, s[3] = {0, 0, 0}, fill[4] = {0, 0, 0, 0};
    const double cos_sun = dmath_cos(ENV_SUN_DEGREES * PI / 180.0), ring = dmath_cos(2.0 * ENV_SUN_DEGREES * PI / 180.0);
    for (uint32_t y = 0; y < h; y++) {
        const double dw = texel_solid_angle(e, y, g->rings);
        double sn, cs;
        dmath_sincos((y + 0.5) / h * PI, &sn, &cs);
        for (uint32_t x = 0; x < w; x++) {
            real c[3];
            const size_t i = (size_t)y * w + x;
            texel(e, i, c);
            const vec3 dir = grid_dir(g, x, sn, cs);
            if (!sun_texel(c, dir, peak, at, cos_sun)) { /* the sky round it: what stands in for it */
                if ((double)v3_dot(dir, at) >= ring)
                    for (int k = 0; k < 4; k++)
                        fill[k] += (k < 3 ? (double)c[k] : 1.0) * dw;
                continue;
            }
            e->sun_mask[i / 8] |= (uint8_t)(1u << (i % 8));
            for (int k = 0; k < 3; k++) {
                d[k] += texel_weight(c) * dw * (double)dir.e[k];
                s[k] += (double)c[k] * dw / PI;
            }
        }
    }
    for (int k = 0; k < 3; k++)
        e->sun_fill[k] = fill[3] > 0.0 && e->gain > R(0) ? (real)(fill[k] / fill[3] / (double)e->gain) : R(0);
    const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(n > 0.0)) {
        free(e->sun_mask);
        e->sun_mask = NULL;
        return 0;
    }
    e->sun_dir = v3((real)(d[0] / n), (real)(d[1] / n), (real)(d[2] / n));
    e->sun_light = v3((real)s[0], (real)s[1], (real)s[2]);
    e->has_sun = 1;
    return 1;
}

/* The sampling tables and the harmonics (without the sun's texels where
 * there is one), from the light (in row order).  The density drawn is the
 * bilinear blend (environment_corners) of each texel's weight times its
 * row's sine, so that it follows the light the draws read (bilinear too)
 * within every cell between four texel centres: a piecewise constant
 * density beside bilinear light drew the sky next to a sun at the sky's
 * density and read half the sun there, fireflies on every diffuse
 * surface in sunlight.  A texel's weight is its light less the mean
 * light, and at least a twentieth of its light (ENV_DRAW_FLOOR): what the
 * image has everywhere the paths find as well as the draws (a diffuse
 * bounce leaves by the cosine, which suits an even sky), and the draws go
 * to what stands out, the sun (Karlik et al., "MIS Compensation", 2019);
 * the floor keeps every lit texel drawable, so that light over density
 * stays within twenty times its mean where next-event estimation is taken
 * alone (settings emitter_sampling nee).  The floor trades the two: the
 * balls under the sky at one sample a pixel, 192 x 144, RMSE against 32 x
 * 32 samples 31.4 at a tenth, 28.6 at a twentieth, 26.6 at a fiftieth
 * (the caustics scene 32.0, 28.8, 26.7); next-event estimation alone at
 * 4 x 4, 34.0, 39.8, 42.4.  Cell row y lies between texel rows y - 1 and y,
 * the first and last half rows held at the poles; cell x between texel
 * columns x and x + 1, the last across the seam.  `top`, `bottom`: w
 * doubles; `acc`: w + 1; `row_sums`: h + 1. */
static void env_tables(Environment *e, const Grid *g, double *top, double *bottom, double *acc, double *row_sums)
{
    const uint32_t w = e->w, h = e->h;
    const double band[9] = {PI, 2.0 * PI / 3.0, 2.0 * PI / 3.0, 2.0 * PI / 3.0, PI / 4.0,
                            PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0};
    double sh[9][3] = {{0}}, rows = 0.0, mean;
    env_find_sun(e, g, &mean);
    e->rows[0] = 0.0f;
    for (uint32_t y = 0; y <= h; y++) {
        if (y < h) { /* texel row y's weights into bottom, and its harmonics */
            const double dw = texel_solid_angle(e, y, g->rings);
            double sn, cs;
            dmath_sincos((y + 0.5) / h * PI, &sn, &cs);
            for (uint32_t x = 0; x < w; x++) {
                real c[3];
                texel(e, (size_t)y * w + x, c);
                bottom[x] = fmax(texel_weight(c) - mean, ENV_DRAW_FLOOR * texel_weight(c)) * sn;
                e->weight[(size_t)y * w + x] = (float)bottom[x];
                if (environment_sun_texel(e, (size_t)y * w + x))
                    continue; /* the sun's: its own light for the Whitted integrator */
                const vec3 d = grid_dir(g, x, sn, cs);
                double b[9];
                sh_basis(d.x, d.y, d.z, b);
                for (int k = 0; k < 9; k++)
                    for (int ch = 0; ch < 3; ch++)
                        sh[k][ch] += (double)c[ch] * b[k] * dw;
            }
        }
        /* cell row y: its corners' sums, cell by cell */
        const double *up = y == 0 ? bottom : top, *down = y == h ? top : bottom;
        acc[0] = 0.0;
        for (uint32_t x = 0; x < w; x++) {
            const uint32_t xn = x + 1 < w ? x + 1 : 0;
            acc[x + 1] = acc[x] + up[x] + up[xn] + down[x] + down[xn];
        }
        const double sum = acc[w];
        float *col = &e->cols[(size_t)y * (w + 1)];
        for (uint32_t x = 0; x <= w; x++) /* the row's shares, 0 to 1 (a black row: even) */
            col[x] = x == w ? 1.0f : (float)(sum > 0.0 ? acc[x] / sum : (double)x / w);
        rows += sum / 4.0 * (y == 0 || y == h ? 0.5 : 1.0); /* the cells' mean weight times their height */
        row_sums[y] = rows;
        double *swap = top;
        top = bottom, bottom = swap; /* texel row y is the next cell row's top */
    }
    e->total = rows;
    e->scale = rows > 0.0 ? (double)w * h / rows : 0.0;
    for (uint32_t y = 1; y <= h + 1; y++)
        e->rows[y] = y == h + 1 ? 1.0f : (float)(e->total > 0.0 ? row_sums[y - 1] / e->total : (double)y / (h + 1));
    for (int k = 0; k < 9; k++)
        for (int ch = 0; ch < 3; ch++)
            e->sh[k][ch] = sh[k][ch] * band[k];
}

/* The gain that keeps every texel's light under ENV_MAX_LIGHT: the
 * strength, or less (a sun's light times a strength past a float's range
 * summed into the tables). */
static real env_gain(const Texture *t, real strength)
{
    double most = 0.0;
    for (size_t i = 0, n = (size_t)t->w * t->h * 3; t->hdr && i < n; i++)
        most = fmax(most, (double)t->hdr[i]);
    return most * (double)strength > ENV_MAX_LIGHT ? (real)(ENV_MAX_LIGHT / most) : strength;
}

Environment *environment_create(const Texture *t, real strength, real rotate, Err *err)
{
    Environment *e = calloc(1, sizeof *e);
    double *acc = malloc((t->w + 1) * sizeof *acc), *cphi = malloc(t->w * sizeof *cphi),
           *sphi = malloc(t->w * sizeof *sphi), *row_sums = malloc((t->h + 1) * sizeof *row_sums),
           *weights = malloc(2 * (size_t)t->w * sizeof *weights);
    if (!e || !acc || !cphi || !sphi || !row_sums || !weights ||
        !(e->rows = malloc((t->h + 2) * sizeof *e->rows)) ||
        !(e->weight = malloc((size_t)t->w * t->h * sizeof *e->weight)) ||
        !(e->cols = malloc((size_t)(t->h + 1) * (t->w + 1) * sizeof *e->cols))) {
        free(acc), free(cphi), free(sphi), free(row_sums), free(weights);
        environment_destroy(e);
        err_set(err, "scene: out of memory for the environment's %ux%u texels", t->w, t->h);
        return NULL;
    }
    e->w = t->w, e->h = t->h;
    e->hdr = t->hdr, e->codes = t->level[0].rgb;
    e->gain = env_gain(t, strength);
    e->turn = rotate / R(360);
    e->turn -= floor(e->turn);
    Grid g = {.cphi = cphi, .sphi = sphi, .rings = 0.0};
    for (uint32_t x = 0; x < e->w; x++) {
        const double phi = ((x + 0.5) / e->w - (double)e->turn - 0.5) * 2.0 * PI;
        dmath_sincos(phi, &sphi[x], &cphi[x]);
    }
    for (uint32_t y = 0; y < e->h; y++)
        g.rings += dmath_sin((y + 0.5) / e->h * PI) * (PI / e->h);
    env_tables(e, &g, weights, weights + e->w, acc, row_sums);
    free(acc), free(cphi), free(sphi), free(row_sums), free(weights);
    if (environment_make_levels(e, err)) {
        environment_destroy(e);
        return NULL;
    }
    return e;
}

void environment_destroy(Environment *e)
{
    if (!e)
        return;
    free(e->rows);
    free(e->weight);
    free(e->cols);
    free(e->sun_mask);
    for (uint32_t l = 1; l < e->levels; l++)
        free(e->level[l]), free(e->sunless[l]);
    free(e);
}

vec3 environment_light_at(const Environment *e, real u, real t, int sunless)
{
    size_t at[4];
    real wq[4];
    environment_corners(e->w, e->h, u, t, at, wq);
    /* the four texels' blend, times the gain once (the blend is linear) */
    real c[3] = {R(0), R(0), R(0)};
    if (e->hdr && !(sunless && e->sun_mask)) { /* a .hdr's light, as drawn and where paths leave */
        const float *p0 = e->hdr + 3 * at[0], *p1 = e->hdr + 3 * at[1], *p2 = e->hdr + 3 * at[2],
                    *p3 = e->hdr + 3 * at[3];
        for (int k = 0; k < 3; k++)
            c[k] = wq[0] * (real)p0[k] + wq[1] * (real)p1[k] + wq[2] * (real)p2[k] + wq[3] * (real)p3[k];
        return v3(c[0] * e->gain, c[1] * e->gain, c[2] * e->gain);
    }
    for (int q = 0; q < 4; q++) {
        const real *fill = sunless && environment_sun_texel(e, at[q]) ? e->sun_fill : NULL;
        for (int k = 0; k < 3; k++) {
            c[k] += wq[q] * (fill ? fill[k] : environment_texel(e, at[q], k));
        }
    }
    return v3(c[0] * e->gain, c[1] * e->gain, c[2] * e->gain);
}

vec3 environment_radiance(const Environment *e, vec3 d)
{
    real u, t;
    environment_uv(e, d, &u, &t);
    return environment_light_at(e, u, t, 0);
}

vec3 environment_radiance_sunless(const Environment *e, vec3 d)
{
    real u, t;
    environment_uv(e, d, &u, &t);
    return environment_light_at(e, u, t, 1);
}

/* The first i of the n + 1 ascending cdf values with cdf[i] <= x < cdf[i + 1]
 * (skipping empty intervals). */
static uint32_t find(const float *cdf, uint32_t n, double x)
{
    uint32_t lo = 0, hi = n; /* cdf[lo] <= x < cdf[hi] */
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if ((double)cdf[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The density environment_sample draws image point (u, t) with, over the
 * unit square: the bilinear blend of the four texels' weights round it
 * (env_tables), as environment_light_at blends their light. */
static double point_density(const Environment *e, real u, real t)
{
    size_t at[4];
    real wq[4];
    environment_corners(e->w, e->h, u, t, at, wq);
    const float *g = e->weight;
    double d = 0.0;
    for (int q = 0; q < 4; q++)
        d += (double)wq[q] * (double)g[at[q]];
    return d * e->scale;
}

/* min(x, 1) and max(0, min(x, 1)) as fmin and fmax give them (NaN: 1 and
 * 0), inline: fmin and fmax are libm calls unless finite maths is
 * assumed, five a draw */
static inline double at_most_one(double x) { return x < 1.0 ? x : 1.0; }
static inline double within_01(double x) { return x > 0.0 ? at_most_one(x) : 0.0; }

/* x in [0, 1] drawn from u in [0, 1) by a density linear from p at 0 to q
 * at 1 (p, q >= 0): the inverse of its quadratic distribution, in the form
 * that loses no digits as p and q near each other. */
static double sample_linear(double u, double p, double q)
{
    const double below = p + sqrt(p * p + u * (q * q - p * p));
    return p == q || !(below > 0.0) ? u : at_most_one(u * (p + q) / below);
}

int environment_sample(const Environment *e, real u1, real u2, vec3 *dir, vec3 *light, real *pdf)
{
    if (!(e->total > 0.0))
        return 0;
    const uint32_t w = e->w, h = e->h;
    /* a cell by the tables, then a point in it by its bilinear weights */
    const uint32_t y = find(e->rows, h + 1, (double)u1);
    const double ry = (double)e->rows[y + 1] - (double)e->rows[y];
    const double fy = within_01(ry > 0.0 ? ((double)u1 - (double)e->rows[y]) / ry : 0.5);
    const float *col = &e->cols[(size_t)y * (w + 1)];
    const uint32_t x = find(col, w, (double)u2);
    const double rx = (double)col[x + 1] - (double)col[x];
    const double fx = within_01(rx > 0.0 ? ((double)u2 - (double)col[x]) / rx : 0.5);
    const uint32_t ya = y == 0 ? 0 : y - 1, yb = y == h ? h - 1 : y, xb = x + 1 < w ? x + 1 : 0;
    const float *g = e->weight;
    const double a = g[(size_t)ya * w + x], b = g[(size_t)ya * w + xb], c = g[(size_t)yb * w + x],
                 d = g[(size_t)yb * w + xb];
    /* down the cell: even in the half rows held at the poles */
    const double ay = y == 0 ? 0.5 + 0.5 * fy : y == h ? 0.5 * fy : sample_linear(fy, a + b, c + d);
    const double ax = sample_linear(fx, (1.0 - ay) * a + ay * c, (1.0 - ay) * b + ay * d);
    const double t = at_most_one(((double)y - 0.5 + ay) / h);
    double u = (x + 0.5 + ax) / w;
    u -= u >= 1.0 ? 1.0 : 0.0;
    /* the direction of (u, t) in the precision of the rays, its sine kept */
    const real theta = (real)(t * PI), phi = (real)((u - (double)e->turn - 0.5) * 2.0 * PI);
    real sn, cs, sp, cp;
    trig_sincos(theta, &sn, &cs);
    trig_sincos(phi, &sp, &cp);
    const double density = ((1.0 - ay) * ((1.0 - ax) * a + ax * b) + ay * ((1.0 - ax) * c + ax * d)) * e->scale;
    if (!(sn > R(0)) || !(density > 0.0))
        return 0;
    *dir = v3(sn * cp, cs, sn * sp);
    *pdf = (real)(density / (2.0 * PI * PI * (double)sn));
    *light = environment_light_at(e, (real)u, (real)t, 0); /* where it was drawn: no way back from the direction */
    return 1;
}

/* The density environment_sample draws d with, d at image point (u, t). */
static real dir_density(const Environment *e, vec3 d, real u, real t)
{
    /* the polar angle's sine: the direction's length across +y */
    const double across = sqrt((double)d.x * (double)d.x + (double)d.z * (double)d.z),
                 sn = across / sqrt(across * across + (double)d.y * (double)d.y);
    if (!(e->total > 0.0 && sn > 0.0))
        return R(0);
    return (real)(point_density(e, u, t) / (2.0 * PI * PI * sn));
}

vec3 environment_seen(const Environment *e, vec3 d, real *pdf)
{
    real u, t;
    environment_uv(e, d, &u, &t);
    *pdf = dir_density(e, d, u, t);
    return environment_light_at(e, u, t, 0);
}

real environment_pdf(const Environment *e, vec3 d)
{
    real u, t;
    environment_uv(e, d, &u, &t);
    return dir_density(e, d, u, t);
}

vec3 environment_diffuse(const Environment *e, vec3 n)
{
    double b[9];
    sh_basis(n.x, n.y, n.z, b);
    vec3 c;
    for (int ch = 0; ch < 3; ch++) {
        double s = 0.0;
        for (int k = 0; k < 9; k++)
            s += e->sh[k][ch] * b[k];
        c.e[ch] = (real)fmax(s / PI, 0.0); /* a sun's ringing dips below zero */
    }
    return c;
}
