/* lobes.h - a surface's scattering for the path integrator: a Lambertian
 * lobe (kd / pi), a glossy lobe for the Phong highlight (the normalised
 * modified Phong of Lafortune and Willems: ks (s + 2) / (2 pi) cos^s a,
 * a the angle between the direction and the mirror direction, s the
 * shininess), the GGX microfacet lobes (shading/ggx.h) of a rough clear
 * coat (grey: its Fresnel share kc, its width coat_alpha) and of a rough
 * metal (km, of width alpha), and a mirror (kr, a delta).  One of them is sampled in proportion to its largest channel;
 * the smooth ones are evaluated together, so that next-event estimation and multiple importance
 * sampling see the whole of them (lobes_eval: f x cos and the density of
 * lobes_sample's choice, solid angle).  Radiometric units: a light given
 * as lanray's Whitted radiance (kd x cos x radiance on a diffuse surface)
 * is pi x lobes_eval's value times it. */
#ifndef LANRAY_LOBES_H
#define LANRAY_LOBES_H

#include "base/vec.h"

typedef struct {
    vec3 kd, ks, kr;
    real shininess;
    real kc, coat_alpha; /* a clear coat's GGX lobe: grey kc (its share here), width coat_alpha */
    vec3 km;           /* a rough metal's GGX lobe: its colour, and its width alpha */
    real alpha;
    vec3 kme;          /* and what its colour gains towards grazing facets (ggx_schlick_gain) */
    int edged;         /* kme is not 0 */
    real pd, pg, pc, pr, pm; /* the probability of sampling each lobe; they sum to 1 */
    vec3 n;          /* unit shading normal, on the side the ray came from */
    vec3 wo;         /* towards where the ray came from */
    vec3 r;          /* the mirror direction of the incoming ray about n */
    vec3 nv;         /* with bumped: the smooth normal a normal map tilted n from */
    int bumped;
    real frost;      /* > 0: frosted glass of this GGX width, both sides of n (the path
                      * integrator's frosted_eval; the other lobes none) */
    real frost_wt;   /* and its weight for the light between its facets (dielectric_frost_weight) */
    real frost_refl; /* and what its reflection keeps: 1, or 0 without reflective caustics (path.c) */
} Lobes;

/* How much of the light from wi a normal-mapped surface's diffuse lobe
 * takes (Chiang, Li and Burley, "Taming the Shadow Terminator", 2019, as
 * Cycles applies it): the map tilts the shading normal n towards a light
 * that the smooth surface nv meets at a grazing angle, where the surface's
 * own relief would shadow it; the share falls smoothly to 0 as the light
 * nears nv's horizon instead of lighting the tilted normal fully up to a
 * hard shadow edge (a low-poly model's facets cutting scallops into its
 * lit side).  1 where n and nv agree. */
static inline real lobes_bump_shadowing(vec3 nv, vec3 n, vec3 wi)
{
    const real d = v3_dot(n, wi) * v3_dot(nv, n);
    if (!(d > R(0)))
        return R(0);
    const real g = v3_dot(nv, wi) / d;
    if (g >= R(1))
        return R(1);
    if (!(g > R(0)))
        return R(0);
    return g + g * g - g * g * g;
}

/* What a surface scatters by: colours (0 where it has no such lobe), the
 * highlight's exponent, a clear coat's lobe (grey kc, of GGX width
 * coat_alpha: ggx_alpha; kc 0: none) and a rough metal's (km, of GGX width
 * alpha, rising by kme towards its facets' grazing angles). */
typedef struct {
    vec3 kd, ks;
    real shininess;
    vec3 kr;
    real kc, coat_alpha;
    vec3 km;
    real alpha;
    vec3 kme; /* an edged metal's rise: its colour km + kme x (1 - cos)^5 at a facet (0: none) */
} LobeColours;

/* The lobes of a surface of colours c at unit shading normal *n seen along
 * unit direction *d; 0 where it scatters nothing.  (By pointer: a vec3
 * passed by value comes in two registers, x and y in one, z in the other,
 * and GCC rejoined y and z through the stack, a load that spans two
 * stores and waits for both: two thirds of this function's samples in a
 * path-traced Cornell box.) */
int lobes_make(Lobes *lb, const LobeColours *c, const vec3 *n, const vec3 *d);

/* Whether it has a smooth (not delta) lobe: what next-event estimation
 * serves. */
static inline int lobes_smooth(const Lobes *lb) { return lb->pd + lb->pg + lb->pc + lb->pr > R(0); }

/* f(wi) x cos(n, wi) of the smooth lobes, and into *pdf the density with
 * which lobes_sample_smooth (after the mirror's pick) gives wi: pd x the
 * cosine's + pg x the highlight's + pc x the coat's + pr x the metal's.
 * 0 below the surface. */
vec3 lobes_eval(const Lobes *lb, vec3 wi, real *pdf);

/* Whether lobes_sample_smooth's `pick` chooses the diffuse lobe. */
static inline int lobes_picks_diffuse(const Lobes *lb, real pick)
{
    return pick * (lb->pd + lb->pg + lb->pc + lb->pr) < lb->pd;
}

/* A direction of the smooth lobes: `pick` in [0, 1) chooses diffuse,
 * glossy, coat or metal by their shares, (u, v) in the unit square places
 * it. */
vec3 lobes_sample_smooth(const Lobes *lb, real pick, real u, real v);

#endif
