/* test_lobes.c - the path integrator's sampling against its own densities:
 * the lobes' density integrates to their share and their samples follow
 * it (shading/lobes.h); an emitter's samples cover the solid angle it
 * fills, and emitters_pdf gives a bounce's direction the density the
 * emitter's sample had (scene/emitters.h).  Where a sampler and its
 * density disagreed, next-event estimation and multiple importance
 * sampling would weigh light wrongly while each picture looked plausible. */
#include "helpers.h"
#include "worlds.h"

#include <math.h>

#include "scene/emitters.h"
#include "shading/ggx.h"
#include "shading/optics.h"
#include "shading/lobes.h"
#include "shading/material.h"

#define TWO_PI 6.283185307179586

/* A uniform direction on the unit sphere. */
static vec3 sphere_dir(Rng *r)
{
    const double z = 1 - 2 * (double)rng_real(r, 0, 1), phi = TWO_PI * (double)rng_real(r, 0, 1);
    const double rho = sqrt(fmax(0, 1 - z * z));
    return v3((real)(rho * cos(phi)), (real)(rho * sin(phi)), (real)z);
}

static void smooth_lobes_density_integrates_to_their_share(void **state)
{
    (void)state;
    /* at normal incidence the glossy lobe lies wholly above the surface */
    const vec3 n = v3_norm(v3(0.3f, 1, -0.2f));
    Lobes lb;
    /* and a clear coat's lobe and a rough metal's */
    const LobeColours c = {v3(0.5f, 0.4f, 0.3f), v3(0.3f, 0.3f, 0.3f), 20, v3(0.2f, 0.2f, 0.2f), 0.25f, 0.3f,
                           v3(0.3f, 0.2f, 0.1f), 0.6f, v3(0.4f, 0.5f, 0.6f)}; /* an edged metal */
    const vec3 d = v3_neg(n);
    assert_true(lobes_make(&lb, &c, &n, &d));
    Rng rng = {11};
    const int N = 400000;
    double sum = 0;
    for (int i = 0; i < N; i++) {
        real pdf;
        lobes_eval(&lb, sphere_dir(&rng), &pdf);
        sum += (double)pdf;
    }
    /* less what the microfacet lobes' samples send below the surface
     * (mirrored about a facet tilted far enough), counted from the sampler */
    double below[2] = {0, 0};
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 2; k++) {
            const vec3 wi = ggx_sample(n, lb.wo, k ? lb.alpha : lb.coat_alpha, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1));
            below[k] += v3_dot(wi, n) <= 0;
        }
    const double integral = sum / N * 2 * TWO_PI;
    const double share = (double)(lb.pd + lb.pg) + (double)lb.pc * (1 - below[0] / N) + (double)lb.pr * (1 - below[1] / N);
    if (fabs(integral - share) > 0.01 * share)
        fail_msg("the smooth lobes' density integrates to %.4f over the sphere, their share above it is %.4f", integral,
                 share);
    assert_true(below[1] > 0.01 * N); /* the test tells a lobe that loses light */
    assert_true(lb.pc > 0 && lb.pr > 0);
    assert_true(fabs((double)(lb.pd + lb.pg + lb.pc + lb.pr + lb.pm) - 1) < 1e-6);
}

static void samples_follow_the_density(void **state)
{
    (void)state;
    /* E[share / pdf] over the samples is the solid angle where the density
     * is not 0: the hemisphere, where the diffuse lobe reaches */
    Rng rng = {5};
    for (int t = 0; t < 4; t++) {
        const vec3 n = v3_norm(rng_dir(&rng));
        vec3 d = v3_norm(rng_dir(&rng));
        if (v3_dot(d, n) > 0)
            d = v3_neg(d);
        Lobes lb;
        const LobeColours c = {v3(0.6f, 0.5f, 0.4f), v3(0.4f, 0.4f, 0.4f), t == 0 ? 1 : 30 * t, v3(0, 0, 0),
                               t == 3 ? 0 : 0.3f, (real)(0.05 + 0.2 * t), t == 1 ? v3(0.5f, 0.4f, 0.3f) : v3(0, 0, 0),
                               0.4f, t == 1 ? v3(0.3f, 0.3f, 0.3f) : v3(0, 0, 0)};
        assert_true(lobes_make(&lb, &c, &n, &d));
        const int N = 200000;
        double sum = 0;
        for (int i = 0; i < N; i++) {
            const vec3 wi = lobes_sample_smooth(&lb, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), rng_real(&rng, 0, 1));
            real pdf;
            lobes_eval(&lb, wi, &pdf);
            if (pdf > 0)
                sum += (double)(lb.pd + lb.pg + lb.pc + lb.pr) / (double)pdf;
        }
        const double got = sum / N;
        if (fabs(got - TWO_PI) > 0.02 * TWO_PI)
            fail_msg("shininess %d: E[share / pdf] over the samples is %.4f, the hemisphere's solid angle %.4f", 30 * t,
                     got, TWO_PI);
    }
}

static void a_white_lambertian_weighs_one(void **state)
{
    (void)state;
    Lobes lb;
    const vec3 n = v3(0, 0, 1);
    const LobeColours c = {.kd = v3(1, 1, 1), .shininess = 1};
    const vec3 d = v3_norm(v3(0.2f, 0.1f, -1));
    assert_true(lobes_make(&lb, &c, &n, &d));
    Rng rng = {3};
    for (int i = 0; i < 10000; i++) {
        const vec3 wi = lobes_sample_smooth(&lb, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), rng_real(&rng, 0, 1));
        real pdf;
        const vec3 fc = lobes_eval(&lb, wi, &pdf);
        assert_true(pdf > 0);
        for (int k = 0; k < 3; k++)
            if (fabs((double)(fc.e[k] / pdf) - 1) > 1e-4)
                fail_msg("a white Lambertian bounce weighs %.6f, not 1", (double)(fc.e[k] / pdf));
    }
}

/* A white GGX metal (shading/ggx.h) seen from wo at angle `deg` to its
 * normal, with roughness `rough`: what it reflects of light from
 * everywhere (its albedo) estimated twice, from its own samples weighed by
 * their density and from uniform directions; where the sampler and the
 * density disagreed, the two would part. */
static void lobe_albedo(const LobeColours *c, double deg, double *by_samples, double *by_uniform, double *max_weight)
{
    const vec3 n = v3_norm(v3(0.2f, 1, 0.3f));
    vec3 t = v3_norm(v3_cross(n, v3(1, 0, 0)));
    const double th = deg * TWO_PI / 360;
    const vec3 wo = v3_norm(v3_add(v3_scale(n, (real)cos(th)), v3_scale(t, (real)sin(th))));
    Lobes lb;
    const vec3 d = v3_neg(wo);
    assert_true(lobes_make(&lb, c, &n, &d));
    assert_true(lb.pr == 1);
    Rng rng = {17};
    const int N = 400000;
    double a = 0, b = 0, mw = 0;
    for (int i = 0; i < N; i++) {
        real pdf;
        const vec3 wi = lobes_sample_smooth(&lb, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), rng_real(&rng, 0, 1));
        const vec3 fc = lobes_eval(&lb, wi, &pdf);
        if (pdf > 0) {
            a += (double)(fc.x / pdf);
            mw = fmax(mw, (double)(fc.x / pdf));
        }
        b += (double)lobes_eval(&lb, sphere_dir(&rng), &pdf).x * 2 * TWO_PI;
    }
    *by_samples = a / N, *by_uniform = b / N, *max_weight = mw;
}

static void metal_albedo(real rough, double deg, double *by_samples, double *by_uniform, double *max_weight)
{
    const LobeColours c = {.km = v3(1, 1, 1), .alpha = ggx_alpha(rough)};
    lobe_albedo(&c, deg, by_samples, by_uniform, max_weight);
}

/* A metal whose colour kr rises towards white at grazing angles
 * (material.h's reflect_edge; glTF's metals): nearly smooth, it reflects
 * Schlick's kr + (1 - kr)(1 - cos)^5 of the light from everywhere at each
 * viewing angle (its facets nearly the normal; the plain lobe kr at every
 * angle, which fails this past 60 degrees); rough, its samples and its
 * density agree as the plain lobe's do, and it reflects more than the
 * plain lobe of kr and no more than a white metal.  Schlick's weight's
 * cosine-weighted mean is 1 / 21 (material_mirror_mean). */
static void an_edged_metal_rises_to_white_at_grazing(void **state)
{
    (void)state;
    const real kr = 0.2f;
    Material m = material_default();
    m.kr = v3_splat(kr), m.kre = v3(1, 1, 1);
    const double deg[] = {0, 60, 80, 87};
    for (int k = 0; k < 4; k++) {
        const real mu = (real)cos(deg[k] * TWO_PI / 360);
        double s, u, mw;
        LobeColours c = {.km = ggx_metal_edged(m.kr, material_mirror_mean(&m), mu, 0.05f),
                         .kme = v3_sub(m.kre, m.kr), .alpha = ggx_alpha(0.05f)};
        lobe_albedo(&c, deg[k], &s, &u, &mw);
        const double want = (double)material_mirror_at(&m, mu).x;
        if (fabs(s - want) > 0.01 * want)
            fail_msg("a smooth edged metal of 0.2 at %.0f degrees reflects %.4f, Schlick's %.4f", deg[k], s, want);
        const real rough = 0.6f;
        c = (LobeColours){.km = ggx_metal_edged(m.kr, material_mirror_mean(&m), mu, rough), .kme = v3_sub(m.kre, m.kr),
                          .alpha = ggx_alpha(rough)};
        lobe_albedo(&c, deg[k], &s, &u, &mw);
        if (fabs(s - u) > 0.015 * u)
            fail_msg("an edged metal of roughness 0.6 at %.0f degrees: albedo %.4f by its samples, %.4f by uniform "
                     "directions", deg[k], s, u);
        double plain, white, ignore;
        metal_albedo(rough, deg[k], &white, &ignore, &mw);
        plain = white * (double)ggx_metal(m.kr, mu, rough).x;
        white *= (double)ggx_metal(v3(1, 1, 1), mu, rough).x;
        if (!(s > plain && s <= white))
            fail_msg("an edged metal of roughness 0.6 at %.0f degrees reflects %.4f: not between the plain lobe's "
                     "%.4f and white's %.4f", deg[k], s, plain, white);
    }
    double mean = 0;
    for (int i = 0; i < 100000; i++) { /* the midpoint rule over c^2, uniform for weight 2c */
        const double c = sqrt((i + 0.5) / 100000);
        mean += (double)optics_schlick_weight((real)c) / 100000;
    }
    assert_float_equal(material_mirror_mean(&m).x, 0.2 + 0.8 * mean, 1e-5);
    assert_float_equal(mean, 1.0 / 21, 1e-5);
}

static void ggx_samples_follow_their_density(void **state)
{
    (void)state;
    const real rough[] = {0.45f, 0.7f, 0.95f, 0.7f};
    const double deg[] = {0, 45, 70, 85};
    for (int k = 0; k < 4; k++) {
        double s, u, mw;
        metal_albedo(rough[k], deg[k], &s, &u, &mw);
        if (fabs(s - u) > 0.015 * u)
            fail_msg("roughness %.2f at %.0f degrees: albedo %.4f by the lobe's samples, %.4f by uniform directions",
                     (double)rough[k], deg[k], s, u);
        /* a sample weighs G2 / G1 of the colour: at most 1 */
        if (mw > 1 + 1e-4)
            fail_msg("roughness %.2f at %.0f degrees: a sample weighs %.5f of a white metal's colour", (double)rough[k],
                     deg[k], mw);
    }
}

/* A near-smooth metal reflects almost all of the light head on (what the
 * single-scattering lobe loses, light that meets a second facet, grows
 * with roughness and at grazing angles: Kulla and Conty's plots). */
static void a_smooth_ggx_metal_reflects_nearly_all(void **state)
{
    (void)state;
    double s, u, mw;
    metal_albedo(0.2f, 0, &s, &u, &mw);
    if (!(s > 0.99 && s <= 1.0001))
        fail_msg("a white GGX metal of roughness 0.2 reflects %.4f of the light from everywhere head on", s);
    /* a rough one loses some: Kulla and Conty's figure, about half at
     * alpha 0.9 seen 70 degrees off its normal */
    metal_albedo(0.95f, 70, &s, &u, &mw);
    if (!(s > 0.45 && s < 0.7))
        fail_msg("a white GGX metal of roughness 0.95 reflects %.4f of the light at 70 degrees", s);
}

/* The table of the lobe's albedo (tools/ggx-tables, ggx_albedo) against
 * the albedo of the C lobe's own samples, at rows, columns and between
 * them, head on to grazing; a white rough metal weighed by ggx_metal
 * reflects all the light from everywhere (without it, down to 0.31 head
 * on at roughness 1), a grey one what one facet gives and part of the
 * rest (its light between facets takes its colour at least twice: kr^2 of
 * what one facet loses at most; some of it: 0.05 of it at least for
 * kr 0.5, where Kulla and Conty's colour gives 0.14-0.25). */
static void ggx_albedo_table_is_the_lobes(void **state)
{
    (void)state;
    const real rough[] = {0.12f, 0.5f, 0.77f, 1};
    const double deg[] = {0, 40, 75, 87};
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) {
            double s, u, mw;
            metal_albedo(rough[r], deg[k], &s, &u, &mw);
            const real mu = (real)cos(deg[k] * TWO_PI / 360), e = ggx_albedo(mu, rough[r]);
            if (fabs((double)e - s) > 0.006)
                fail_msg("roughness %.2f at %.0f degrees: the table's albedo %.4f, the lobe's samples' %.4f",
                         (double)rough[r], deg[k], (double)e, s);
            const double white = s * (double)ggx_metal(v3(1, 1, 1), mu, rough[r]).x;
            if (fabs(white - 1) > 0.01)
                fail_msg("roughness %.2f at %.0f degrees: a white metal weighed by ggx_metal reflects %.4f",
                         (double)rough[r], deg[k], white);
            /* a coloured one gets back less: its light between facets
             * takes its colour at least twice (kr^2 of it at most) */
            const double grey = (double)ggx_metal(v3(0.5f, 0.5f, 0.5f), mu, rough[r]).x, lost = (1 - e) / e;
            if (!(grey >= 0.5 + 0.05 * lost && grey <= 0.5 + 0.25 * lost + 1e-6))
                fail_msg("roughness %.2f at %.0f degrees: a metal of 0.5 weighed by ggx_metal as %.4f, not between "
                         "%.4f and %.4f", (double)rough[r], deg[k], grey, 0.5 + 0.05 * lost, 0.5 + 0.25 * lost);
        }
    /* the table's ends and what lies past them */
    assert_true(ggx_albedo(1, 0) > R(0.999) && ggx_albedo(1, 0) <= 1);
    assert_true(ggx_albedo(2, -1) == ggx_albedo(1, 0));
    assert_true(ggx_albedo(NAN, NAN) == ggx_albedo(0, 0));
    assert_true(ggx_albedo(1, 1) < R(0.35) && ggx_albedo(1, 5) == ggx_albedo(1, 1));
    assert_true(ggx_albedo_mean(0) > R(0.999) && ggx_albedo_mean(1) < R(0.45) && ggx_albedo_mean(NAN) == ggx_albedo_mean(0));
}

/* The table of frosted glass's albedo (tools/ggx-tables, ggx_glass_albedo)
 * against the same mean taken here from the C lobe's visible facets and
 * optics.h (a facet reflects by Fresnel's exact share or refracts; a
 * refraction that fails or would go back out reflects; a reflection into
 * the surface is lost; each keeps G2 / G1), from outside and inside, at
 * and between the table's rows and planes; and its weight gives a clear
 * frosted surface all its light back. */
static void ggx_glass_table_is_the_lobes(void **state)
{
    (void)state;
    const vec3 n = v3(0, 0, 1);
    const real rough[] = {0.2f, 0.55f, 0.9f};
    const real cosines[] = {1, 0.6f, 0.3f};
    const real etas[] = {1 / 1.5f, 1.5f, 1 / 2.2f, 2.2f};
    const int K = 128;
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++)
            for (int e = 0; e < 4; e++) {
                const real mu = cosines[c], eta = etas[e], alpha = ggx_alpha(rough[a]);
                const vec3 wo = v3(sqrt(1 - mu * mu), 0, mu);
                double sum = 0;
                for (int i = 0; i < K; i++)
                    for (int j = 0; j < K; j++) {
                        const vec3 m = ggx_visible_normal(n, wo, alpha, (real)((i + 0.5) / K), (real)((j + 0.5) / K));
                        const vec3 d = v3_neg(wo);
                        real f = optics_fresnel_exact(real_max(0, v3_dot(wo, m)), eta);
                        vec3 t = v3(0, 0, 0);
                        if (f >= 1 || !optics_refract(d, m, eta, &t) || !(t.z < 0))
                            f = 1;
                        const vec3 r = v3_reflect(d, m);
                        if (r.z > 0)
                            sum += (double)(f * ggx_keep(n, wo, r, alpha));
                        if (f < 1)
                            sum += (double)((1 - f) * ggx_keep(n, wo, v3_norm(t), alpha));
                    }
                const double mean = sum / (K * K), table = (double)ggx_glass_albedo(mu, rough[a], eta);
                if (fabs(table - mean) > 0.012)
                    fail_msg("frosted glass of roughness %.2f, eta %.3f, cosine %.1f: the table keeps %.4f, the lobe %.4f",
                             (double)rough[a], (double)eta, (double)mu, table, mean);
                if (fabs(mean * (double)ggx_glass_weight(mu, rough[a], eta) - 1) > 0.015)
                    fail_msg("frosted glass of roughness %.2f, eta %.3f, cosine %.1f: weighed, it keeps %.4f",
                             (double)rough[a], (double)eta, (double)mu, mean * (double)ggx_glass_weight(mu, rough[a], eta));
            }
    /* past the table's ends: its last planes; a NaN reads the first */
    assert_true(ggx_glass_albedo(1, 1, 16) == ggx_glass_albedo(1, 1, 3));
    assert_true(ggx_glass_albedo(0.5f, 0.5f, 0.01f) == ggx_glass_albedo(0.5f, 0.5f, 1e-6f));
    assert_true(isfinite(ggx_glass_weight(NAN, NAN, NAN)) && ggx_glass_weight(NAN, NAN, NAN) >= 1);
}

/* The lobe at the extremes: the narrowest (roughness 0: alpha's floor)
 * and the widest, seen head on and at grazing cosines down to 1e-7, with
 * (u, v) at the unit square's corners: every sample a finite unit
 * vector, every value and density finite and not negative, no sample
 * weighing more than its colour. */
static void ggx_holds_at_the_extremes(void **state)
{
    (void)state;
    const vec3 n = v3_norm(v3(0.3f, -0.8f, 0.5f));
    vec3 t, b;
    v3_frame_fast(n, &t, &b);
    const real rough[] = {0, 0.001f, 0.03f, 0.5f, 1};
    const real cosines[] = {1, 0.5f, 1e-2f, 1e-4f, 1e-7f};
    const real corners[] = {0, 1e-7f, 0.5f, 1 - 1e-7f};
    for (int r = 0; r < 5; r++)
        for (int c = 0; c < 5; c++) {
            const real co = cosines[c], si = sqrt(1 - co * co);
            const vec3 wo = v3_norm(v3_add(v3_scale(n, co), v3_scale(t, si)));
            const real alpha = ggx_alpha(rough[r]);
            for (int i = 0; i < 4; i++)
                for (int j = 0; j < 4; j++) {
                    const vec3 wi = ggx_sample(n, wo, alpha, corners[i], corners[j]);
                    const double len = (double)v3_len(wi);
                    if (!(fabs(len - 1) < 1e-4))
                        fail_msg("roughness %g, cosine %g, (u, v) = (%g, %g): a sample of length %g", (double)rough[r],
                                 (double)co, (double)corners[i], (double)corners[j], len);
                    real pdf;
                    const real f = ggx_eval(n, wo, wi, alpha, &pdf);
                    if (!(isfinite(f) && isfinite(pdf) && f >= 0 && pdf >= 0 && (f == 0 || pdf > 0)))
                        fail_msg("roughness %g, cosine %g: f %g, density %g", (double)rough[r], (double)co, (double)f,
                                 (double)pdf);
                    if (f > 0 && (double)(f / pdf) > 1 + 1e-3)
                        fail_msg("roughness %g, cosine %g: a sample weighs %g", (double)rough[r], (double)co,
                                 (double)(f / pdf));
                }
        }
}

/* The solid angle of triangle abc seen from the origin (Van Oosterom and
 * Strackee). */
static double triangle_solid_angle(vec3 a, vec3 b, vec3 c)
{
    const double la = (double)v3_len(a), lb = (double)v3_len(b), lc = (double)v3_len(c);
    const double num = fabs((double)v3_dot(a, v3_cross(b, c)));
    const double den = la * lb * lc + (double)v3_dot(a, b) * lc + (double)v3_dot(a, c) * lb + (double)v3_dot(b, c) * la;
    return 2 * atan2(num, den);
}

static void emitters_cover_their_solid_angle(void **state)
{
    (void)state;
    Scene *s = scene_create();
    uint32_t dark, glow, dim;
    Material m = material_default();
    assert_int_equal(scene_add_material(s, m, &dark, NULL), 0);
    m.kd = v3(0, 0, 0);
    m.ke = v3(4, 4, 4);
    assert_int_equal(scene_add_material(s, m, &glow, NULL), 0);
    m.ke = v3(1, 2, 3);
    assert_int_equal(scene_add_material(s, m, &dim, NULL), 0);
    const vec3 centre = v3(2, 3, -1);
    const real radius = 0.5f;
    assert_int_equal(scene_add_sphere(s, (Sphere){centre, radius, glow}, NULL), 0);
    const vec3 tri[3] = {v3(-2, 2, 1), v3(-1, 2.5f, 2), v3(-2.5f, 3, 2)};
    assert_int_equal(scene_add_triangle(s, tri, NULL, NULL, dim, NULL), 0);
    assert_int_equal(scene_add_sphere(s, (Sphere){v3(0, -100, 0), 99, dark}, NULL), 0); /* not an emitter */
    s->settings.integrator = INTEGRATOR_PATH;
    const World *w = world_now(s);
    assert_int_equal(w->emitter_count, 2);
    const vec3 p = v3(0, 0.5f, 0.5f); /* off the triangle's plane (through (0, 0.5, 0)) */
    /* E[1 / pdf] = the solid angle both fill (they do not overlap seen from p) */
    const double d = (double)v3_len(v3_sub(centre, p)), cone = TWO_PI * (1 - sqrt(1 - (double)(radius * radius) / (d * d)));
    const double want = cone + triangle_solid_angle(v3_sub(tri[0], p), v3_sub(tri[1], p), v3_sub(tri[2], p));
    Rng rng = {17};
    const int N = 200000;
    double sum = 0;
    int checked = 0, missed = 0;
    for (int i = 0; i < N; i++) {
        EmitterSample es;
        if (!emitters_sample(w, p, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), &es))
            continue;
        sum += 1 / (double)es.pdf;
        if (i % 97 == 0) { /* the bounce that met the same point has the same density */
            Ray r = ray_make(p, es.dir, 0, REAL_MAX);
            Hit h;
            if (!trace_closest(w, &r, &h)) { /* a grazing ray past a silhouette, by rounding */
                missed++;
                continue;
            }
            const double back = (double)emitters_pdf(w, p, &r, &h);
            if (fabs(back - (double)es.pdf) > 2e-3 * (double)es.pdf)
                fail_msg("emitters_pdf gives %.6g where the sample had %.6g", back, (double)es.pdf);
            checked++;
        }
    }
    const double got = sum / N;
    if (fabs(got - want) > 0.01 * want)
        fail_msg("the emitters' samples cover %.5f sr, they fill %.5f", got, want);
    assert_true(checked > 1000);
    if (missed * 200 > checked)
        fail_msg("%d of %d rays towards an emitter's sampled point missed it", missed, checked + missed);
    /* a direction that meets no emitter has density 0 */
    Ray away = ray_make(p, v3(0, -1, 0), 0, REAL_MAX);
    Hit h;
    assert_true(trace_closest(w, &away, &h));
    assert_true(emitters_pdf(w, p, &away, &h) == 0);
    world_now_free();
    scene_destroy(s);
}

/* An emitting model whose left half gives no light, as a cutout (a hole
 * there) or by its emission texture (black there, white on the right):
 * every sample that brings light lies on the right half, and the samples'
 * light over their density covers the right half's solid angle (the
 * integral of the radiance, 1 there).  The texture draws the samples to
 * its bright half (emitters.c): each triangle's points by 8 x 8 cells of
 * its area, each as likely as its mean (1/64 for black), so that 90% of
 * the samples bring light, where half did when the points were uniform;
 * made of two quads that meet at the middle (split), the dark quad's
 * triangles are also picked by their share, 1/64 of the bright ones':
 * 98%.  The light they bring stays the bright half's. */
static void half_emitter_lights_from_its_bright_half(int glow, int split)
{
    Mesh mesh;
    Err err;
    assert_int_equal(mesh_init(&mesh, MESH_UVS | MESH_MATERIALS, &err), 0);
    const uint8_t grey[6] = {0, 0, 0, 255, 255, 255}; /* 2 x 1: black (a hole, or dark), white */
    Texture *t = texture_from_rgb8(2, 1, grey);
    t->closest = 1; /* read at one point: the nearest texel, no blend across the middle */
    uint32_t tex;
    assert_int_equal(mesh_add_texture(&mesh, t, &tex, &err), 0);
    Material m = material_default();
    m.kd = v3(0, 0, 0), m.ke = v3(1, 1, 1);
    if (glow)
        m.emit_map = (int32_t)tex, m.emit_mapped = 1;
    else
        m.mask = (int32_t)tex, m.cutoff = R(0.5);
    assert_int_equal(mesh_add_material(&mesh, m, &err), 0);
    /* the quad x 0..2, y 0..1 at z = 0, u = x / 2 (split: as the quads x 0..1 and 1..2) */
    for (int q = 0; q < (split ? 2 : 1); q++) {
        const real x0 = split ? (real)q : 0, x1 = split ? (real)(q + 1) : 2;
        const vec3 a[3] = {v3(x0, 0, 0), v3(x1, 0, 0), v3(x1, 1, 0)}, b[3] = {v3(x0, 0, 0), v3(x1, 1, 0), v3(x0, 1, 0)};
        const real u0 = x0 / 2, u1 = x1 / 2;
        const real ua[6] = {u0, 0, u1, 0, u1, 1}, ub[6] = {u0, 0, u1, 1, u0, 1};
        assert_int_equal(mesh_add(&mesh, a, NULL, ua, NULL, 0, &err), 0);
        assert_int_equal(mesh_add(&mesh, b, NULL, ub, NULL, 0, &err), 0);
    }
    Scene *s = worlds_scene_of_mesh(&mesh, v3(0, 0, 0));
    s->settings.integrator = INTEGRATOR_PATH;
    const World *w = world_now(s);
    assert_int_equal(w->emitter_count, split ? 4 : 2);
    const vec3 p = v3(1, 0.5f, 1);
    Rng rng = {5};
    const int N = 200000;
    double sum = 0;
    int lit = 0, checked = 0;
    for (int i = 0; i < N; i++) {
        EmitterSample es;
        if (!emitters_sample(w, p, rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), rng_real(&rng, 0, 1), &es))
            continue;
        const vec3 q = v3_add(p, v3_scale(es.dir, es.dist));
        if (q.x < R(0.999) && es.radiance.x > R(0))
            fail_msg("light %g from (%g, %g), on the dark half", (double)es.radiance.x, (double)q.x, (double)q.y);
        sum += (double)es.radiance.x / (double)es.pdf;
        lit += es.radiance.x > R(0);
        /* a bounce that meets the same point has the same density (off the
         * middle, where a ray may meet the triangle beside the sampled one) */
        if (i % 61 == 0 && fabs((double)q.x - 1) > 1e-3) {
            Ray r = ray_make(p, es.dir, 0, REAL_MAX);
            Hit h;
            if (trace_closest(w, &r, &h)) {
                const double back = (double)emitters_pdf(w, p, &r, &h);
                if (fabs(back - (double)es.pdf) > 2e-3 * (double)es.pdf)
                    fail_msg("emitters_pdf gives %.6g where the sample had %.6g", back, (double)es.pdf);
                checked++;
            }
        }
    }
    assert_true(checked > 1000);
    if (glow && lit < N * (split ? 97 : 85) / 100)
        fail_msg("%d of %d samples of the emission texture bring light (split %d): the dark half is drawn as often",
                 lit, N, split);
    /* the bright half, x 1..2, y 0..1 at distance 1: its solid angle by two triangles */
    const vec3 c0 = v3(0, -0.5f, -1), c1 = v3(1, -0.5f, -1), c2 = v3(1, 0.5f, -1), c3 = v3(0, 0.5f, -1);
    const double want = triangle_solid_angle(c0, c1, c2) + triangle_solid_angle(c0, c2, c3);
    if (fabs(sum / N - want) > 0.01 * want)
        fail_msg("the %s's samples bring %.5f, its bright half %.5f", glow ? "emission texture" : "cutout", sum / N,
                 want);
    world_now_free();
    scene_destroy(s);
}

static void a_cutout_emits_only_where_it_is(void **state)
{
    (void)state;
    half_emitter_lights_from_its_bright_half(0, 0);
}

static void an_emission_texture_lights_by_its_texels(void **state)
{
    (void)state;
    half_emitter_lights_from_its_bright_half(1, 0);
}

static void bright_texels_are_picked_first(void **state)
{
    (void)state;
    half_emitter_lights_from_its_bright_half(1, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(smooth_lobes_density_integrates_to_their_share),
        cmocka_unit_test(samples_follow_the_density),
        cmocka_unit_test(a_white_lambertian_weighs_one),
        cmocka_unit_test(ggx_samples_follow_their_density),
        cmocka_unit_test(a_smooth_ggx_metal_reflects_nearly_all),
        cmocka_unit_test(ggx_holds_at_the_extremes),
        cmocka_unit_test(ggx_albedo_table_is_the_lobes),
        cmocka_unit_test(an_edged_metal_rises_to_white_at_grazing),
        cmocka_unit_test(ggx_glass_table_is_the_lobes),
        cmocka_unit_test(emitters_cover_their_solid_angle),
        cmocka_unit_test(a_cutout_emits_only_where_it_is),
        cmocka_unit_test(an_emission_texture_lights_by_its_texels),
        cmocka_unit_test(bright_texels_are_picked_first),
    };
    return cmocka_run_group_tests_name("lobes", tests, NULL, NULL);
}
