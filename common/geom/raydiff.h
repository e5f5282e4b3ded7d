/* raydiff.h - ray differentials: how a ray's origin and direction change
 * from one image sample to the next, across (x) and down (y) the image
 * (Igehy, "Tracing Ray Differentials", SIGGRAPH 1999).
 *
 * Carried to a hit, they give the sample's footprint on the surface, dP/dx
 * and dP/dy, from which a texture lookup knows how many texels one sample
 * spans (texture_sample.c).  A mirror or a refraction turns them with the
 * ray, using how the normal changes across the footprint (curved surfaces
 * widen or narrow it), so a texture seen in a mirror ball is filtered over
 * its footprint there too.  Only a scene with textures carries them.
 *
 * A ray that stands for a share of a spread of rays (one of a pixel's
 * lens rays, one of a rough mirror's) also carries a cone: its footprint
 * widened by |w0 + t spread| at distance t, the width of its share of the
 * spread (Amanatides' cones; Akenine-Moller et al., "Texture Level of
 * Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems ch. 20).
 * A texture is then filtered over what the spread blurs anyway: a floor out
 * of focus, or seen in a brushed metal, without the noise of sampling its
 * texels one ray at a time; the cone narrows as the rays a pixel takes
 * grow in number, so the picture converges to the same one. */
#ifndef LANRAY_RAYDIFF_H
#define LANRAY_RAYDIFF_H

#include "base/vec.h"

typedef struct {
    vec3 dox, doy; /* origin */
    vec3 ddx, ddy; /* direction (of the unit direction) */
    real w0, spread; /* the cone: extra width |w0 + t spread| at distance t */
} RayDiff;

/* The angle a ray's footprint spans far away (what it sees of an
 * environment): its direction's larger change to the next sample, widened
 * by its cone's spread. */
static inline real raydiff_width(const RayDiff *rd)
{
    const real a = v3_len(rd->ddx), b = v3_len(rd->ddy);
    return (a > b ? a : b) + fabs(rd->spread);
}

/* The footprint at the hit at distance t along unit direction d, on the
 * tangent plane of normal n: dP = dO + t dD + dt d, with dt keeping the
 * point on the plane (zero where d runs along the plane). */
static inline void raydiff_at(const RayDiff *rd, vec3 d, real t, vec3 n, vec3 *dpdx, vec3 *dpdy)
{
    vec3 px = v3_madd(rd->dox, rd->ddx, t), py = v3_madd(rd->doy, rd->ddy, t);
    real w = fabs(rd->w0 + t * rd->spread);
    if (w > R(0)) { /* the cone widens both sides of the footprint by its width */
        real lx = v3_len(px), ly = v3_len(py);
        px = lx > R(0) ? v3_scale(px, R(1) + w / lx) : px;
        py = ly > R(0) ? v3_scale(py, R(1) + w / ly) : py;
    }
    real dn = v3_dot(d, n);
    if (dn != R(0)) {
        px = v3_madd(px, d, -v3_dot(px, n) / dn);
        py = v3_madd(py, d, -v3_dot(py, n) / dn);
    }
    *dpdx = px;
    *dpdy = py;
}

/* The differentials of the ray mirrored about n at the footprint (dpdx,
 * dpdy), the normal changing by (dndx, dndy) across it:
 * r = d - 2 (d.n) n, dr = dd - 2 ((d.n) dn + d(d.n) n). */
static inline RayDiff raydiff_reflect(const RayDiff *rd, vec3 d, vec3 n, vec3 dndx, vec3 dndy, vec3 dpdx, vec3 dpdy)
{
    real dn = v3_dot(d, n);
    real ddnx = v3_dot(rd->ddx, n) + v3_dot(d, dndx), ddny = v3_dot(rd->ddy, n) + v3_dot(d, dndy);
    RayDiff out = {dpdx, dpdy, v3_sub(rd->ddx, v3_scale(v3_madd(v3_scale(dndx, dn), n, ddnx), R(2))),
                   v3_sub(rd->ddy, v3_scale(v3_madd(v3_scale(dndy, dn), n, ddny), R(2))), rd->w0, rd->spread};
    return out;
}

/* The same for the ray refracted with eta = n1 / n2 (n facing the
 * incoming ray): t = eta d + mu n, mu = eta c - k, c = -d.n,
 * k = sqrt(1 - eta^2 (1 - c^2)); dt = eta dd + mu dn + dmu n with
 * dmu = (eta - eta^2 c / k) dc.  At total internal reflection (k = 0) the
 * direction's change is left without the dmu term. */
static inline RayDiff raydiff_refract(const RayDiff *rd, vec3 d, vec3 n, real eta, vec3 dndx, vec3 dndy, vec3 dpdx,
                                      vec3 dpdy)
{
    real c = -v3_dot(d, n);
    real k2 = R(1) - eta * eta * (R(1) - c * c);
    real k = k2 > R(0) ? sqrt(k2) : R(0);
    real mu = eta * c - k;
    real dmu_dc = k > R(0) ? eta - eta * eta * c / k : R(0);
    real dcx = -(v3_dot(rd->ddx, n) + v3_dot(d, dndx)), dcy = -(v3_dot(rd->ddy, n) + v3_dot(d, dndy));
    RayDiff out = {dpdx, dpdy, v3_add(v3_add(v3_scale(rd->ddx, eta), v3_scale(dndx, mu)), v3_scale(n, dmu_dc * dcx)),
                   v3_add(v3_add(v3_scale(rd->ddy, eta), v3_scale(dndy, mu)), v3_scale(n, dmu_dc * dcy)), rd->w0,
                   rd->spread};
    return out;
}

/* The cone of a ray that continues from distance t of rd (a bounce): the
 * width it had there, spreading on as before. */
static inline void raydiff_carry(RayDiff *out, const RayDiff *rd, real t)
{
    out->w0 = rd->w0 + t * rd->spread;
    out->spread = rd->spread;
}

/* One of n rays spread over a lobe `angle` radians wide (a rough
 * mirror's), leaving at distance t of rd: the cone widens by its share
 * of the lobe, sqrt(pi / n) angle, diverging from the width it had. */
static inline void raydiff_lobe(RayDiff *out, const RayDiff *rd, real t, real angle, uint32_t n)
{
    out->w0 = fabs(rd->w0 + t * rd->spread);
    out->spread = fabs(rd->spread) + angle * R(1.7724538509055159) / sqrt((real)n);
}

#endif
