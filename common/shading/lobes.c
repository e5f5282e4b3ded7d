/* lobes.c - see lobes.h. */
#include "shading/lobes.h"

#include "base/sample.h"

int lobes_make(Lobes *lb, vec3 kd, vec3 ks, real shininess, vec3 kr, real kc, real coat_exp, vec3 n, vec3 d)
{
    const real wd = v3_max_comp(kd), wg = v3_max_comp(ks), wm = v3_max_comp(kr), wc = real_max(kc, R(0)),
               sum = wd + wg + wm + wc;
    if (!(sum > R(0)))
        return 0;
    *lb = (Lobes){.kd = kd, .ks = ks, .kr = kr, .shininess = shininess, .kc = wc, .coat_exp = coat_exp,
                  .pd = wd / sum, .pg = wg / sum, .pc = wc / sum, .pm = wm / sum, .n = n, .r = v3_reflect(d, n)};
    return 1;
}

/* A glossy lobe's cos^s a (0 past 90 degrees from the mirror direction). */
static real glossy_power(const Lobes *lb, vec3 wi, real s)
{
    const real ca = v3_dot(wi, lb->r);
    return ca > R(0) ? pow(ca, s) : R(0);
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
    if (lb->pc > R(0)) {
        const real s = lb->coat_exp, g = glossy_power(lb, wi, s);
        f = v3_add(f, v3_splat(lb->kc * (s + R(2)) / (R(2) * REAL_PI) * g));
        p += lb->pc * (s + R(1)) / (R(2) * REAL_PI) * g;
    }
    *pdf = p;
    return v3_scale(f, c);
}

/* The unit vector of coordinates (x, y, z) in a frame whose third axis is
 * unit `axis`: the frame of Duff et al. ("Building an orthonormal basis,
 * revisited", JCGT 2017), one division where v3_frame's normalised cross
 * product took a square root and a division on every bounce (9% of a
 * path-traced frame). */
static vec3 in_frame(vec3 axis, real x, real y, real z)
{
    const real sign = copysign(R(1), axis.z), a = R(-1) / (sign + axis.z), b = axis.x * axis.y * a;
    const vec3 t = v3(R(1) + sign * axis.x * axis.x * a, sign * b, -sign * axis.x);
    const vec3 u = v3(b, sign + axis.y * axis.y * a, -axis.y);
    return v3_norm(v3_add(v3_add(v3_scale(t, x), v3_scale(u, y)), v3_scale(axis, z)));
}

vec3 lobes_sample_smooth(const Lobes *lb, real pick, real u, real v)
{
    const real smooth = lb->pd + lb->pg + lb->pc;
    if (pick * smooth < lb->pd) { /* the cosine about the normal (Malley: a disc's point lifted) */
        real x, y;
        sample_disc(u, v, &x, &y);
        /* a point on the disc's rim would give a direction along the surface: kept just above it */
        return in_frame(lb->n, x, y, sqrt(real_max(R(1e-6), R(1) - x * x - y * y)));
    }
    /* cos^s about the mirror direction: cos a = u^(1 / (s + 1)), s the coat's past the highlight's share */
    const real s = pick * smooth < lb->pd + lb->pg ? lb->shininess : lb->coat_exp;
    const real z = pow(u, R(1) / (s + R(1))), rho = sqrt(real_max(R(0), R(1) - z * z));
    const real phi = R(2) * REAL_PI * v;
    return in_frame(lb->r, rho * cos(phi), rho * sin(phi), z);
}
