/* optics.h - what a ray does at a smooth surface: mirror reflection,
 * refraction by Snell's law (with total internal reflection), and the share
 * reflected by a dielectric (Fresnel's equations, or Schlick's
 * approximation of them: a measured knob in `make tradeoff`).
 *
 * Directions are unit vectors; n is the unit normal on the side the ray
 * arrives from (dot(d, n) <= 0), and eta is n1 / n2, the index of the
 * medium the ray leaves over that of the medium it enters. */
#ifndef LANRAY_OPTICS_H
#define LANRAY_OPTICS_H

#include "base/vec.h"

typedef enum { FRESNEL_EXACT = 0, FRESNEL_SCHLICK = 1 } FresnelModel;

/* d mirrored about n. */
static inline vec3 optics_reflect(vec3 d, vec3 n) { return v3_reflect(d, n); }

/* The refracted direction into *t; 0 at total internal reflection (*t
 * untouched).  cos_i = -dot(d, n) >= 0. */
static inline int optics_refract(vec3 d, vec3 n, real eta, vec3 *t)
{
    real cos_i = -v3_dot(d, n);
    real k = R(1) - eta * eta * (R(1) - cos_i * cos_i);
    if (k < R(0))
        return 0;
    *t = v3_add(v3_scale(d, eta), v3_scale(n, eta * cos_i - sqrt(k)));
    return 1;
}

/* The share of unpolarised light a dielectric boundary reflects, for a ray
 * arriving at cos_i (0..1) with eta = n1 / n2: the mean of the s and p
 * reflectances; 1 past the critical angle. */
static inline real optics_fresnel_exact(real cos_i, real eta)
{
    real sin2_t = eta * eta * (R(1) - cos_i * cos_i);
    if (sin2_t >= R(1))
        return R(1);
    real cos_t = sqrt(R(1) - sin2_t);
    real rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    real rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return R(0.5) * (rs * rs + rp * rp);
}

/* Schlick's weight of the grazing reflectance at cosine c, (1 - c)^5:
 * the share by which a reflectance rises from its value head on to its
 * value at grazing (1 for a dielectric, white for a metal). */
static inline real optics_schlick_weight(real c)
{
    const real m = R(1) - real_clamp(c, R(0), R(1)), m2 = m * m;
    return m2 * m2 * m;
}

/* Schlick's approximation, R0 + (1 - R0)(1 - cos)^5 with R0 the reflectance
 * at normal incidence; cos is the angle in the rarer medium (the
 * transmitted one when the ray leaves the denser medium), and 1 past the
 * critical angle, as the exact form. */
static inline real optics_fresnel_schlick(real cos_i, real eta)
{
    if (eta == R(1)) /* no change of index: nothing reflected (the exact form's answer too) */
        return R(0);
    real r0 = (eta - R(1)) / (eta + R(1));
    r0 *= r0;
    real c = cos_i;
    if (eta > R(1)) {
        real sin2_t = eta * eta * (R(1) - cos_i * cos_i);
        if (sin2_t >= R(1))
            return R(1);
        c = sqrt(R(1) - sin2_t);
    }
    return r0 + (R(1) - r0) * optics_schlick_weight(c);
}

static inline real optics_fresnel(FresnelModel model, real cos_i, real eta)
{
    return model == FRESNEL_SCHLICK ? optics_fresnel_schlick(cos_i, eta) : optics_fresnel_exact(cos_i, eta);
}

#endif
