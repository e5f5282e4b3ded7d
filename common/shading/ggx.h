/* ggx.h - the GGX (Trowbridge-Reitz) microfacet lobe of a rough metal, for
 * the path integrator: Walter et al.'s distribution D of width alpha, the
 * height-correlated Smith shadowing G2 (Heitz, "Understanding the
 * masking-shadowing function", 2014), directions drawn from the normals
 * the viewer sees (Heitz, "Sampling the GGX distribution of visible
 * normals", JCGT 2018), so that a sample weighs G2 / G1 of its colour.
 * It is the lobe Cycles' Glossy BSDF and Principled metals reflect by and
 * a glTF's roughness means: a long-tailed blur, where the Phong lobe of
 * material_phong_exponent has none.  Isotropic: only cosines to the
 * normal enter, except in the sampling's frame. */
#ifndef LANRAY_GGX_H
#define LANRAY_GGX_H

#include <math.h>

#include "base/dmath.h"
#include "base/vec.h"
#include "shading/material.h"
#include "shading/optics.h"

/* alpha = roughness^2 (glTF's and Cycles' mapping), kept above 1e-3: a
 * narrower D's peak, 1 / (pi alpha^2), depends on n.h past what a float
 * cosine resolves (roughness 0.03: a blur of a thousandth of a radian) */
static inline real ggx_alpha(real roughness) { return real_max(roughness * roughness, R(1e-3)); }

/* Smith's Lambda of a direction at cosine c to the normal. */
static inline real ggx_lambda(real c, real a2)
{
    const real c2 = c * c, t2 = real_max(R(0), R(1) - c2) / c2;
    return (sqrt(R(1) + a2 * t2) - R(1)) * R(0.5);
}

/* The distribution D of facet normal h at cosine ch to the normal. */
static inline real ggx_d(real ch, real a2)
{
    const real k = ch * ch * (a2 - R(1)) + R(1);
    return a2 / (REAL_PI * k * k);
}

/* f x cos(n, wi) of a white GGX reflector at n seen from wo (unit, towards
 * the viewer), towards wi, and into *pdf the density ggx_sample gives wi
 * (solid angle); 0 where either lies below the surface. */
static inline real ggx_eval(vec3 n, vec3 wo, vec3 wi, real alpha, real *pdf)
{
    *pdf = R(0);
    const real co = v3_dot(n, wo), ci = v3_dot(n, wi);
    if (!(co > R(0) && ci > R(0)))
        return R(0);
    const vec3 h = v3_norm(v3_add(wo, wi));
    const real a2 = alpha * alpha, d = ggx_d(v3_dot(n, h), a2);
    const real lo = ggx_lambda(co, a2), li = ggx_lambda(ci, a2);
    const real q = d / (R(4) * co);
    *pdf = q / (R(1) + lo);     /* G1(wo) D(h) (wo.h) / co / (4 wo.h) */
    return q / (R(1) + lo + li); /* D G2 / (4 co ci) x ci */
}

/* A facet normal from (u, v) in the unit square: one of those the lobe
 * at n shows to wo, drawn by their visible area. */
static inline vec3 ggx_visible_normal(vec3 n, vec3 wo, real alpha, real u, real v)
{
    vec3 t, b;
    v3_frame_fast(n, &t, &b);
    /* wo in the frame, stretched to the unit-roughness configuration */
    const vec3 vh = v3_norm(v3(alpha * v3_dot(wo, t), alpha * v3_dot(wo, b), v3_dot(wo, n)));
    const real l2 = vh.x * vh.x + vh.y * vh.y;
    const vec3 t1 = l2 > R(0) ? v3_scale(v3(-vh.y, vh.x, R(0)), R(1) / sqrt(l2)) : v3(R(1), R(0), R(0));
    const vec3 t2 = v3_cross(vh, t1);
    const real r = sqrt(u), phi = R(2) * REAL_PI * v, s = R(0.5) * (R(1) + vh.z);
    real sp, cp;
    dmath_sincosr(phi, &sp, &cp);
    const real p1 = r * cp, p2r = r * sp;
    const real p2 = (R(1) - s) * sqrt(real_max(R(0), R(1) - p1 * p1)) + s * p2r;
    const real p3 = sqrt(real_max(R(0), R(1) - p1 * p1 - p2 * p2));
    const vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)), v3_scale(vh, p3));
    /* back to the lobe's roughness, then to world space */
    return v3_norm(v3_add(v3_add(v3_scale(t, alpha * nh.x), v3_scale(b, alpha * nh.y)),
                          v3_scale(n, real_max(R(1e-6), nh.z))));
}

/* A direction from (u, v) in the unit square: wo mirrored about a visible
 * facet (ggx_visible_normal; it may fall below the surface: ggx_eval
 * gives it 0). */
static inline vec3 ggx_sample(vec3 n, vec3 wo, real alpha, real u, real v)
{
    const vec3 m = ggx_visible_normal(n, wo, alpha, u, v);
    return v3_sub(v3_scale(m, R(2) * v3_dot(wo, m)), wo);
}

/* The directional albedo E of a white GGX reflector of `roughness` seen at
 * cosine mu (tools/ggx-tables writes the table: rows of roughness, columns
 * of sqrt(mu), bilinear between them): what its lobe reflects of the light
 * from a direction after one facet.  The rest, 1 - E (two thirds head on
 * at roughness 1), meets a second facet first, which the lobe leaves out. */
#define GGX_TABLE_N 32
extern const float ggx_albedo_table[GGX_TABLE_N][GGX_TABLE_N];

/* The tables' lookups.  t in [0, 1] over an axis of n points (below 0,
 * and a NaN, read 0; above 1 reads 1): the cell *i (0..n-2) it falls in,
 * and the fraction of the cell, returned. */
static inline real ggx_cell(real t, int n, int *i)
{
    const real x = (t > R(0) ? real_min(t, R(1)) : R(0)) * (real)(n - 1);
    *i = x < (real)(n - 2) ? (int)x : n - 2;
    return x - (real)*i;
}

/* Rows a and b (one cell of the next axis apart) at column cell i:
 * linear along each row by fx, then between them by fy. */
static inline real ggx_bilinear(const float *a, const float *b, int i, real fx, real fy)
{
    const real lo = (real)a[i] + ((real)a[i + 1] - (real)a[i]) * fx, hi = (real)b[i] + ((real)b[i + 1] - (real)b[i]) * fx;
    return lo + (hi - lo) * fy;
}

static inline real ggx_albedo(real mu, real roughness)
{
    int i, j;
    const real fx = ggx_cell(sqrt(mu > R(0) ? real_min(mu, R(1)) : R(0)), GGX_TABLE_N, &i);
    const real fy = ggx_cell(roughness, GGX_TABLE_N, &j);
    return ggx_bilinear(ggx_albedo_table[j], ggx_albedo_table[j + 1], i, fx, fy);
}

/* E's cosine-weighted mean over the hemisphere, row by row of roughness
 * (tools/ggx-tables), linear between them. */
extern const float ggx_albedo_avg[GGX_TABLE_N];

static inline real ggx_albedo_mean(real roughness)
{
    int j;
    const real fy = ggx_cell(roughness, GGX_TABLE_N, &j);
    return (real)ggx_albedo_avg[j] + ((real)ggx_albedo_avg[j + 1] - (real)ggx_albedo_avg[j]) * fy;
}

/* The colour a rough metal of colour kr lends its single-scattering lobe
 * seen at cosine mu, so that the light its facets pass between them comes
 * back: kr + c (1 - E) / E, so that it reflects kr E + c (1 - E) of the
 * light from everywhere (Turquin 2019: the lobe's shape stays, only its
 * weight grows, most where E is least).  c, the colour of the light
 * between facets, takes fa at each facet it meets and leaves after each
 * by E_avg's share (Kulla and Conty 2017): fa^2 E_avg / (1 - fa (1 -
 * E_avg)), 1 for a white metal, which then loses nothing.  fa is the
 * metal's mean reflectance over the hemisphere (Kulla and Conty's F_avg):
 * kr itself (ggx_metal), or, for a metal whose colour rises from kr head
 * on towards a grazing one (material_mirror_at, the lobe adding the rise
 * at each facet: ggx_schlick_gain), material_mirror_mean.  Cycles 4's
 * weighing; Cycles 3.4's "Multiscatter GGX", which walks the light from
 * facet to facet, is within 0.5% up to roughness 0.6, 5-10% brighter at 1
 * on coloured metals (docs/renderer.md). */
static inline vec3 ggx_metal_edged(vec3 kr, vec3 fa, real mu, real roughness)
{
    const real e = ggx_albedo(mu, roughness), ea = ggx_albedo_mean(roughness), k = (R(1) - e) / e;
    vec3 out;
    for (int i = 0; i < 3; i++) {
        const real f = fa.e[i];
        out.e[i] = kr.e[i] + f * f * ea / (R(1) - f * (R(1) - ea)) * k;
    }
    return out;
}

static inline vec3 ggx_metal(vec3 kr, real mu, real roughness) { return ggx_metal_edged(kr, kr, mu, roughness); }

/* Rough metal m's lobe seen at cosine mu, as both integrators weigh it:
 * the colour its single-scattering lobe takes (ggx_metal_edged with the
 * metal's mean reflectance; for a metal without a rim, ggx_metal's), and
 * into *kme what it gains towards grazing facets (reflect_edge - reflect,
 * times ggx_schlick_gain in each direction; 0 without a rim). */
static inline vec3 ggx_metal_of(const Material *m, real mu, vec3 *kme)
{
    *kme = material_edged(m) ? v3_sub(m->kre, m->kr) : v3_splat(R(0));
    return ggx_metal_edged(m->kr, material_mirror_mean(m), mu, m->roughness);
}

/* Schlick's (1 - c)^5 at the facet that mirrors wo into wi: c the cosine
 * between wo and their half vector (what an edged metal's lobe adds of
 * kre - kr in that direction). */
static inline real ggx_schlick_gain(vec3 wo, vec3 wi)
{
    const vec3 h = v3_add(wo, wi);
    const real l = v3_len(h);
    return optics_schlick_weight(l > R(0) ? v3_dot(wo, h) / l : R(0));
}

/* The same for frosted glass (path.c's frosted_bounce: a visible facet
 * reflects or refracts by Fresnel's exact share at it, G2 / G1 kept, a
 * reflection into the surface lost), seen at cosine mu with eta = n1 / n2
 * (the index the ray leaves over the one it enters): rows of roughness
 * and columns of sqrt(mu) as ggx_albedo's, planes of eta from 1/3 to 3
 * (3^(k/8 - 1)), trilinear; eta outside that range reads its end.  What
 * a path keeps at one surface: the rest, lost between facets, is most
 * from inside at high roughness (0.42 of the light kept head on at
 * roughness 1, index 1.5). */
#define GGX_GLASS_N 16
#define GGX_GLASS_ETAS 17
extern const float ggx_glass_table[GGX_GLASS_ETAS][GGX_GLASS_N][GGX_GLASS_N];

static inline real ggx_glass_albedo(real mu, real roughness, real eta)
{
    int i, j, k;
    const real fx = ggx_cell(sqrt(mu > R(0) ? real_min(mu, R(1)) : R(0)), GGX_GLASS_N, &i);
    const real fy = ggx_cell(roughness, GGX_GLASS_N, &j);
    /* log3(eta) in [-1, 1] over the planes; a NaN or eta <= 0 reads the first */
    const real le = eta > R(0) ? log(eta) * (R(1) / R(1.0986122886681098)) : R(-1);
    const real fz = ggx_cell((real_clamp(le, R(-1), R(1)) + R(1)) * R(0.5), GGX_GLASS_ETAS, &k);
    const real e0 = ggx_bilinear(ggx_glass_table[k][j], ggx_glass_table[k][j + 1], i, fx, fy);
    const real e1 = ggx_bilinear(ggx_glass_table[k + 1][j], ggx_glass_table[k + 1][j + 1], i, fx, fy);
    return e0 + (e1 - e0) * fz;
}

/* What frosted glass's single-scattering lobe is weighed by, at cosine mu
 * and eta as ggx_glass_albedo, so that it gives back the light its facets
 * pass between them: 1 / E (Turquin 2019, as Cycles 4 weighs its rough
 * glass): in a white furnace a clear frosted ball vanishes; reflection and
 * refraction keep their single-scattering shares. */
static inline real ggx_glass_weight(real mu, real roughness, real eta)
{
    return R(1) / real_max(ggx_glass_albedo(mu, roughness, eta), R(0.05));
}

/* What a path that left wo by a visible facet towards wi keeps, G2 / G1
 * (wo): the facets that shadow wi, reflected or refracted (wi on either
 * side of n: its cosine taken whole). */
static inline real ggx_keep(vec3 n, vec3 wo, vec3 wi, real alpha)
{
    const real a2 = alpha * alpha, lo = ggx_lambda(fabs(v3_dot(n, wo)), a2);
    return (R(1) + lo) / (R(1) + lo + ggx_lambda(fabs(v3_dot(n, wi)), a2));
}

#endif
