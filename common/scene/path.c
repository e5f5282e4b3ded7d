/* path.c - see path.h.
 *
 * Units follow the Whitted integrator's, so that the two agree where light
 * does not bounce: a light's contribution to a diffuse surface is kd x
 * cos x its radiance (shade.c), and a bounce off it carries kd x what the
 * scattered path brings (the cosine-weighted direction's weight: kd / pi
 * x cos over the density cos / pi).  Emission (`emit`) is radiance, added
 * wherever a path meets it, except where a diffuse bounce's path meets a
 * light's lamp (a visible lamp, docs/scene.md: an emissive surface where a
 * light is), whose light next-event estimation took at that bounce: so
 * nothing is counted twice.  An emissive surface without a light lights
 * the scene through the paths that meet it.  This first cut leaves out the
 * Phong highlights (a diffuse surface is Lambertian here), shadow rays
 * through glass (a dielectric stops them; light through glass arrives by
 * the paths that pass it: caustics of emissive surfaces and the sky), and
 * sampling emissive surfaces as lights (multiple importance sampling). */
#include "scene/path.h"

#include <math.h>

#include "model/texture.h"
#include "shading/optics.h"

/* Settings depth bounds a path's bounces (0: direct light only); past
 * this many, Russian roulette may end it (surviving paths weighted up by
 * as much). */
#define PATH_ROULETTE_AFTER 3

/* Two numbers of bounce b's dimension `dim` for a ray: one point of a
 * (0,2)-sequence over its pixel's rays (stratified together), scrambled by
 * the key. */
static void draw2(const SampleId *id, uint32_t b, uint32_t dim, real *u, real *v)
{
    sample_sobol2(id->index, sample_mix(sample_mix(id->key, 0x50000000u + b), dim), u, v);
}

/* One number of bounce b's dimension `dim`: point `index` (shuffled) of
 * an Owen-scrambled van der Corput sequence over the pixel's rays, as
 * sample_sobol2's first dimension: each ray its own, stratified together
 * (a number of the key alone would be the same for every ray of the
 * pixel, and all of them would choose alike). */
static real draw1(const SampleId *id, uint32_t b, uint32_t dim)
{
    const uint32_t seed = sample_mix(sample_mix(id->key, 0x50000000u + b), dim);
    return sample_sobol_first(sample_sobol_index(id->index, seed), seed);
}

/* A direction about n by the cosine, from (u, v) in the unit square. */
static vec3 cosine_dir(vec3 n, real u, real v)
{
    real x, y;
    sample_disc(u, v, &x, &y);
    /* a point on the disc's rim would give a direction along the surface: kept just above it */
    real z = sqrt(real_max(R(1e-6), R(1) - x * x - y * y));
    vec3 a = v3_norm(v3_cross(fabs(n.x) > R(0.5) ? v3(0, 1, 0) : v3(1, 0, 0), n)), b = v3_cross(n, a);
    return v3_norm(v3_add(v3_add(v3_scale(a, x), v3_scale(b, y)), v3_scale(n, z)));
}

/* Next-event estimation from a diffuse point: one point of every light,
 * its shadow ray, kd x cos x the radiance that arrives. */
static vec3 direct_light(const World *w, const Surface *sf, vec3 kd, const SampleId *id, uint32_t b, RayStats *st)
{
    vec3 sum = v3_splat(R(0));
    const vec3 origin = trace_offset_origin(sf->ps, sf->ng, sf->ps_err);
    for (uint32_t li = 0; li < w->light_count; li++) {
        real u, v, dist;
        draw2(id, b, 0x100u + li, &u, &v);
        vec3 dir, rad;
        if (!shade_light_point(w, li, sf->p, u, v, &dir, &dist, &rad))
            continue;
        const real c = v3_dot(dir, sf->ns);
        if (!(c > R(0)) || !(v3_dot(dir, sf->ng) > R(0)))
            continue;
        if (world_has(w, FEAT_SHADOWS)) {
            const real tmax = isfinite(dist) ? dist * (R(1) - R(64) * REAL_EPS) : REAL_MAX;
            Ray sr = ray_make(origin, dir, R(0), tmax);
            st->shadow++;
            if (trace_occluded(w, &sr, tmax, &w->lights[li]))
                continue;
        }
        sum = v3_add(sum, v3_scale(v3_mul(kd, rad), c));
    }
    return sum;
}

/* The surface's diffuse colour here: its material's, a model's vertex
 * colour, times its texture (read at one point: no ray footprint here). */
static vec3 diffuse_at(const World *w, const Surface *sf)
{
    vec3 kd = world_has(w, FEAT_COLOURS) && sf->has_colour ? sf->colour : sf->mat->kd;
    if (world_has(w, FEAT_TEXTURES) && sf->tex && sf->has_uv)
        kd = v3_mul(kd, texture_sample(sf->tex, sf->u, sf->v, NULL, w->view.settings.filter));
    return kd;
}

/* A dielectric: the path reflected or refracted, chosen by Fresnel's
 * reflectance (so the weight stays; refraction takes the transmitted
 * colour).  0 where the path ends. */
static int dielectric_bounce(const World *w, const Surface *sf, vec3 d, real pick, vec3 *beta, Ray *next)
{
    const Material *m = sf->mat;
    const real eta = sf->inside ? m->ior : R(1) / m->ior, cos_i = real_max(R(0), -v3_dot(d, sf->ns));
    real f = optics_fresnel(w->view.settings.fresnel, cos_i, eta);
    vec3 td = v3_splat(R(0));
    if (f >= R(1) || !optics_refract(d, sf->ns, eta, &td) || !(v3_dot(td, sf->ng) < R(0)))
        f = R(1);
    if (pick < f) {
        vec3 r = optics_reflect(d, sf->ns);
        *next = ray_make(trace_offset_origin(sf->p, sf->ng, sf->err), r, R(0), REAL_MAX);
        return v3_dot(r, sf->ng) > R(0);
    }
    *beta = v3_mul(*beta, m->kt);
    *next = ray_make(trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err), v3_norm(td), R(0), REAL_MAX);
    return 1;
}

/* A mirror or metal: the mirror direction, bent by the roughness (a point
 * of a ball of that radius, from u, v and s: the Whitted integrator's rough
 * mirror, one ray), weighted by its colour.  0 where the path ends (bent
 * into the surface). */
static int mirror_bounce(const Surface *sf, vec3 d, real u, real v, real s, vec3 *beta, Ray *next)
{
    const Material *m = sf->mat;
    vec3 r = optics_reflect(d, sf->ns);
    if (m->roughness > R(0)) {
        const real z = R(1) - R(2) * u, rho = sqrt(real_max(R(0), R(1) - z * z)), phi = R(6.283185307179586) * v;
        const real len = cbrt(s) * m->roughness;
        r = v3_norm(v3_add(r, v3_scale(v3(rho * cos(phi), rho * sin(phi), z), len)));
    }
    if (!(v3_dot(r, sf->ng) > R(0)))
        return 0;
    *beta = v3_mul(*beta, m->kr);
    *next = ray_make(trace_offset_origin(sf->p, sf->ng, sf->err), r, R(0), REAL_MAX);
    return 1;
}

/* Whether h is on a light's lamp (its light was sampled from a diffuse point). */
static int on_lamp(const World *w, const Hit *h)
{
    for (uint32_t li = 0; li < w->light_count; li++)
        if (trace_lamp_part(w, &w->lights[li], h))
            return 1;
    return 0;
}

vec3 path_radiance(const World *w, const Ray *r, SampleId id, RayStats *st, uint64_t *key)
{
    int after_diffuse = 0; /* the path left a diffuse point, which took the lights (next-event estimation) */
    vec3 L = v3_splat(R(0)), beta = v3_splat(R(1));
    Ray ray = *r;
    const int depth = w->view.settings.depth;
    for (int b = 0;; b++) {
        Hit h;
        if (b == 0)
            st->primary++;
        else
            st->secondary++;
        if (!trace_closest(w, &ray, &h)) {
            L = v3_add(L, v3_mul(beta, w->background));
            if (b == 0 && key)
                *key = UINT64_MAX;
            break;
        }
        Surface sf;
        trace_surface(w, &ray, &h, &sf);
        const Material *m = sf.mat;
        if (b == 0 && key)
            *key = (uint64_t)sf.object << 16;
        if (sf.inside && material_dielectric(m) && v3_max_comp(m->absorb) > R(0)) /* crossed its inside */
            beta = v3_mul(beta, v3(exp(-m->absorb.x * h.t), exp(-m->absorb.y * h.t), exp(-m->absorb.z * h.t)));
        if (material_emits(m) && !(after_diffuse && on_lamp(w, &h)))
            L = v3_add(L, v3_mul(beta, m->ke));
        const int last = b >= depth; /* the light that reaches this point still counts: depth 0 is direct light */
        const vec3 d = ray.dir;
        real u, v;
        draw2(&id, (uint32_t)b, 1, &u, &v);
        const real pick = draw1(&id, (uint32_t)b, 2);
        int go;
        after_diffuse = 0;
        if (material_dielectric(m)) {
            if (last)
                break;
            go = dielectric_bounce(w, &sf, d, pick, &beta, &ray);
        } else {
            const vec3 kd = diffuse_at(w, &sf);
            const real pd = v3_max_comp(kd), pm = material_reflects(m) ? v3_max_comp(m->kr) : R(0);
            if (!(pd + pm > R(0)))
                break;
            if (pick * (pd + pm) < pm) { /* the mirror lobe, chosen with probability pm / (pd + pm) */
                if (last)
                    break;
                beta = v3_scale(beta, (pd + pm) / pm);
                go = mirror_bounce(&sf, d, u, v, draw1(&id, (uint32_t)b, 4), &beta, &ray);
            } else {
                beta = v3_scale(beta, (pd + pm) / pd);
                L = v3_add(L, v3_mul(beta, direct_light(w, &sf, kd, &id, (uint32_t)b, st)));
                if (last)
                    break;
                vec3 nd = cosine_dir(sf.ns, u, v);
                go = v3_dot(nd, sf.ng) > R(0);
                beta = v3_mul(beta, kd);
                after_diffuse = 1;
                ray = ray_make(trace_offset_origin(sf.p, sf.ng, sf.err), nd, R(0), REAL_MAX);
            }
        }
        if (!go)
            break;
        if (b + 1 >= PATH_ROULETTE_AFTER) {
            const real keep = real_min(R(1), v3_max_comp(beta));
            if (!(draw1(&id, (uint32_t)b, 3) < keep))
                break;
            beta = v3_scale(beta, R(1) / keep);
        }
    }
    return L;
}
