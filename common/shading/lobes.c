/* lobes.c - see lobes.h. */
#include "shading/lobes.h"

#include "base/dmath.h"
#include "base/sample.h"
#include "shading/ggx.h"

int lobes_make(Lobes *lb, const LobeColours *c, const vec3 *np, const vec3 *dp)
{
    const vec3 n = *np, d = *dp;
    const int edged = c->kme.x != R(0) || c->kme.y != R(0) || c->kme.z != R(0);
    /* an edged metal's lobe weighs as its colour seen along the normal's mirror direction */
    const vec3 km = edged ? v3_add(c->km, v3_scale(c->kme, optics_schlick_weight(-v3_dot(n, d)))) : c->km;
    const real wd = v3_max_comp(c->kd), wg = v3_max_comp(c->ks), wm = v3_max_comp(c->kr), wc = real_max(c->kc, R(0)),
               wr = v3_max_comp(km), sum = wd + wg + wm + wc + wr;
    if (!(sum > R(0)))
        return 0;
    /* field by field: a compound literal cleared the whole struct first
     * (a string store, its start-up in every bounce) and wrote it again */
    lb->kd = c->kd, lb->ks = c->ks, lb->kr = c->kr, lb->shininess = c->shininess;
    lb->kc = wc, lb->coat_alpha = c->coat_alpha, lb->km = c->km, lb->alpha = c->alpha, lb->kme = c->kme;
    lb->edged = edged;
    lb->pd = wd / sum, lb->pg = wg / sum, lb->pc = wc / sum, lb->pr = wr / sum, lb->pm = wm / sum;
    lb->n = n, lb->wo = v3_neg(d), lb->r = v3_reflect(d, n);
    lb->nv = v3_splat(R(0)), lb->bumped = 0;
    lb->frost = lb->frost_wt = lb->frost_refl = R(0);
    return 1;
}

/* A glossy lobe's cos^s a (0 past 90 degrees from the mirror direction). */
static real glossy_power(const Lobes *lb, vec3 wi, real s)
{
    const real ca = v3_dot(wi, lb->r);
    return ca > R(0) ? dmath_powr(ca, s) : R(0);
}

vec3 lobes_eval(const Lobes *lb, vec3 wi, real *pdf)
{
    const real c = v3_dot(wi, lb->n);
    *pdf = R(0);
    if (!(c > R(0)))
        return v3_splat(R(0));
    vec3 f = v3_scale(lb->kd, (lb->bumped ? lobes_bump_shadowing(lb->nv, lb->n, wi) : R(1)) / REAL_PI);
    real p = lb->pd * c / REAL_PI;
    if (lb->pg > R(0)) {
        const real s = lb->shininess, g = glossy_power(lb, wi, s);
        f = v3_add(f, v3_scale(lb->ks, (s + R(2)) / (R(2) * REAL_PI) * g));
        p += lb->pg * (s + R(1)) / (R(2) * REAL_PI) * g;
    }
    f = v3_scale(f, c);
    /* the microfacet lobes, already times the cosine */
    if (lb->pc > R(0)) {
        real q;
        f = v3_add(f, v3_splat(lb->kc * ggx_eval(lb->n, lb->wo, wi, lb->coat_alpha, &q)));
        p += lb->pc * q;
    }
    if (lb->pr > R(0)) {
        real q;
        const real g = ggx_eval(lb->n, lb->wo, wi, lb->alpha, &q);
        f = v3_add(f, v3_scale(lb->km, g));
        if (lb->edged) /* the facet that mirrors wo into wi grazes it by Schlick's weight */
            f = v3_add(f, v3_scale(lb->kme, g * ggx_schlick_gain(lb->wo, wi)));
        p += lb->pr * q;
    }
    *pdf = p;
    return f;
}

/* The unit vector of coordinates (x, y, z) in a frame whose third axis is
 * unit `axis` (v3_frame_fast's). */
static vec3 in_frame(vec3 axis, real x, real y, real z)
{
    vec3 t, u;
    v3_frame_fast(axis, &t, &u);
    return v3_norm(v3_add(v3_add(v3_scale(t, x), v3_scale(u, y)), v3_scale(axis, z)));
}

vec3 lobes_sample_smooth(const Lobes *lb, real pick, real u, real v)
{
    const real smooth = lb->pd + lb->pg + lb->pc + lb->pr, at = pick * smooth;
    if (lobes_picks_diffuse(lb, pick)) { /* the cosine about the normal (Malley: a disc's point lifted) */
        real x, y;
        sample_disc(u, v, &x, &y);
        /* a point on the disc's rim would give a direction along the surface: kept just above it */
        return in_frame(lb->n, x, y, sqrt(real_max(R(1e-6), R(1) - x * x - y * y)));
    }
    if (at < lb->pd + lb->pg || !(lb->pc + lb->pr > R(0))) {
        /* the highlight's cos^s about the mirror direction: cos a = u^(1 / (s + 1)) */
        const real s = lb->shininess, z = dmath_powr(u, R(1) / (s + R(1))), rho = sqrt(real_max(R(0), R(1) - z * z));
        const real phi = R(2) * REAL_PI * v;
        real sp, cp;
        dmath_sincosr(phi, &sp, &cp);
        return in_frame(lb->r, rho * cp, rho * sp, z);
    }
    /* a visible normal of the coat's or the metal's facets (shading/ggx.h) */
    const int coat = lb->pr > R(0) ? at < lb->pd + lb->pg + lb->pc : 1;
    return ggx_sample(lb->n, lb->wo, coat ? lb->coat_alpha : lb->alpha, u, v);
}
