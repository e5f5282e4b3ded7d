/* path.c - see path.h.
 *
 * Units follow the Whitted integrator's, so that the two agree where light
 * does not bounce: a light's contribution to a diffuse surface is kd x
 * cos x its radiance (shade.c), which is pi x the BRDF kd / pi x cos x
 * that radiance; a surface scatters by its lobes (shading/lobes.h: the
 * Lambertian kd / pi, the Phong highlight as a normalised glossy lobe,
 * the GGX lobes of rough metals and rough coats, a mirror; frosted glass
 * its facets, frosted_eval), and a bounce carries f x cos / the density
 * of its direction.
 * Emission (`emit`) is radiance, added wherever a path meets it, except
 * where a bounce from a smooth lobe meets a light's lamp (a visible lamp,
 * docs/scene.md: an emissive surface where a light is), whose light
 * next-event estimation took at that point: so nothing is counted twice.
 * An emissive surface without a light lights the scene both ways: a point
 * with a smooth lobe samples one of them (scene/emitters.h) and its bounce
 * may meet one, and the two estimates are weighed by the power heuristic
 * (settings emitter_sampling: or either alone).  Shadow rays stop at glass
 * (light through glass arrives by the paths that pass it: caustics). */
#include "scene/path.h"

#include <math.h>

#include "base/sample_lanes.h"
#include "model/texture.h"
#include "scene/dielectric.h"
#include "scene/emitters.h"
#include "shading/ggx.h"
#include "shading/lobes.h"
#include "shading/optics.h"


/* Bounce b's numbers for a ray: its sample's key mixed with the bounce
 * once, each dimension's seed mixed from that, and the ray's index among
 * its pixel's.  Where the sampler's lanes run side by side (AVX2) the
 * dimensions a bounce may draw are drawn at once (sample_draw_lanes:
 * the numbers each draw gives alone, to the bit; a bounce's four to six
 * draws of some 100 instructions each were a sixth of a path-traced
 * frame); elsewhere each alone, as asked. */
typedef struct {
    int lampless;                 /* the world has a light without a lamp (highlight_make) */
    int lanes;                    /* draw the dimensions below at once */
    uint32_t dims[SAMPLE_LANES]; /* the direction (2D), the lobe's pick, roulette, 4 (a
                                  * rough mirror's bend before its GGX lobe: unused, its
                                  * lane kept so that dimension k is lane k - 1), an
                                  * emitter's point (2D) and pick, then the environment's
                                  * direction (7) where there is one and the first area
                                  * lights' points (0x100 + light; other lights' alone) */
} DrawPlan;

/* The plan of a world's bounces: lanes wherever they run side by side,
 * even where a bounce draws only two or three numbers (a scene without
 * lights or emitters: the 100 spheres under a sky at 2 x 2 samples, 200 x
 * 112, 381.4M -> 375.5M instructions with the lanes,
 * though the two ways had cost alike when the plan was made); and whether
 * a light has no lamp (no ray can meet it), found once a packet, not at
 * every bounce. */
static void draw_plan(DrawPlan *pl, const World *w)
{
    pl->lanes = sample_lanes_wide();
    pl->lampless = 0;
    for (uint32_t li = 0; li < w->light_count; li++)
        pl->lampless |= w->lights[li].lamp_count == 0;
    for (uint32_t k = 0; k < 6; k++)
        pl->dims[k] = k + 1;
    pl->dims[6] = 0x100u, pl->dims[7] = 0x101u; /* unused without an environment or area lights */
    uint32_t k = 6;
    if (w->env) /* the environment's direction */
        pl->dims[k++] = 7;
    for (uint32_t li = 0; li < w->light_count && k < SAMPLE_LANES; li++)
        if (world_light_is_area(&w->lights[li]))
            pl->dims[k++] = 0x100u + li;
}

typedef struct {
    uint32_t key, index;
    int lanes;                                 /* the plan's */
    uint32_t light[2];                         /* the plan's dims[6] and dims[7] */
    uint32_t u[SAMPLE_LANES], v[SAMPLE_LANES]; /* the plan's dimensions, where it has lanes */
} Draws;

static inline int lane_of(const Draws *d, uint32_t dim)
{
    if (!d->lanes)
        return -1;
    if (dim >= 1 && dim <= 6)
        return (int)dim - 1;
    return dim == d->light[0] ? 6 : dim == d->light[1] ? 7 : -1;
}

static inline void draws_at(Draws *d, const DrawPlan *pl, const SampleId *id, uint32_t b)
{
    d->key = sample_mix(id->key, 0x50000000u + b);
    d->index = id->index;
    d->lanes = pl->lanes;
    d->light[0] = pl->dims[6], d->light[1] = pl->dims[7];
    if (d->lanes)
        sample_draw_lanes(d->key, d->index, pl->dims, d->u, d->v);
}

/* Two numbers of dimension `dim`: one point of a (0,2)-sequence over its
 * pixel's rays (stratified together), scrambled by the key. */
static inline __attribute__((always_inline)) void draw2(const Draws *d, uint32_t dim, real *u, real *v)
{
    const int k = lane_of(d, dim);
    if (k >= 0) {
        *u = sample_unit(d->u[k]);
        *v = sample_unit(d->v[k]);
        return;
    }
    sample_sobol2(d->index, sample_mix(d->key, dim), u, v);
}

/* One number of dimension `dim`: point `index` (shuffled) of an
 * Owen-scrambled van der Corput sequence over the pixel's rays, as
 * sample_sobol2's first dimension: each ray its own, stratified together
 * (a number of the key alone would be the same for every ray of the
 * pixel, and all of them would choose alike). */
static inline __attribute__((always_inline)) real draw1(const Draws *d, uint32_t dim)
{
    const int k = lane_of(d, dim);
    if (k >= 0)
        return sample_unit(d->u[k]);
    const SampleSobol q = sample_sobol_seq(sample_mix(d->key, dim));
    return sample_sobol_first(&q, d->index);
}

/* What of the light passes the shadow ray from origin along dir short of
 * tmax (passing light `towards`'s own lamp, where given): all of it or
 * none, except through see-through blends (material_null: unbent, so
 * the light's direction holds), times each one's transmitted colour; any
 * other dielectric stops it (its light comes by the paths). */
static vec3 passed(const World *w, const vec3 *origin, const vec3 *dir, real tmax, const WorldLight *towards,
                   RayStats *st)
{
    Ray r; /* written in place: ray_make's copy stalled on store forwarding (ray_set) */
    ray_init(&r, *origin, *dir, R(0), tmax);
    st->shadow++;
    int glass = 0;
    if (!world_has(w, FEAT_NULL) ? trace_occluded(w, &r, tmax, towards) : trace_shadow(w, &r, tmax, towards, &glass))
        return v3_splat(R(0));
    return glass ? shade_transmittance(w, &r, tmax, towards, 1, st) : v3_splat(R(1));
}

/* f x cos of frosted glass at sf (material_frosted) seen from wo (unit,
 * on the side of sf->ns) towards wi, on either side of it, and into *pdf
 * the density frosted_bounce gives wi: its facet h drawn from the visible
 * normals, reflected with Fresnel's share at h (all of it where the
 * refraction fails, as dielectric_split says), refracted otherwise; the
 * reflection's half vector h = wo + wi, the refraction's -(eta wo + wi)
 * (eta: the index on wo's side over wi's; Walter et al. 2007), whose
 * Jacobian |wi.h| / (eta wo.h + wi.h)^2.  Written so that a sample
 * weighs G2 / G1 (times the transmitted colour), as frosted_bounce's do:
 * no radiance scaling across the interface, as clear glass has none; and
 * times wt, the lobe's weight for the light between facets
 * (dielectric_frost_weight at wo); the reflection times keep (settings
 * caustics: 0 where it is dropped, its density kept). */
static vec3 frosted_eval(const World *w, const Surface *sf, vec3 wo, vec3 wi, real alpha, real wt, real keep,
                         real *pdf)
{
    *pdf = R(0);
    const vec3 n = sf->ns;
    const real co = v3_dot(n, wo), ci = v3_dot(n, wi), cg = v3_dot(sf->ng, wi);
    const int refl = ci > R(0);
    if (!(co > R(0)) || !(refl ? cg > R(0) : ci < R(0) && cg < R(0)))
        return v3_splat(R(0));
    const Material *m = sf->mat;
    const real eta = dielectric_eta(sf);
    vec3 h = v3_norm(refl ? v3_add(wo, wi) : v3_neg(v3_add(v3_scale(wo, eta), wi)));
    if (v3_dot(h, n) < R(0))
        h = v3_neg(h);
    const real oh = v3_dot(wo, h), ih = v3_dot(wi, h);
    if (!(oh > R(0)) || !(refl ? ih > R(0) : ih < R(0)))
        return v3_splat(R(0));
    real e; /* Fresnel's share at the facet, as frosted_bounce takes it */
    vec3 td;
    const real f = dielectric_split_at(w, sf, h, v3_neg(wo), &e, &td);
    const real a2 = alpha * alpha, d = ggx_d(v3_dot(n, h), a2), lo = ggx_lambda(co, a2), li = ggx_lambda(fabs(ci), a2);
    const real g1 = R(1) / (R(1) + lo), g2 = wt / (R(1) + lo + li);
    if (refl) {
        const real q = d / (R(4) * co);
        *pdf = f * g1 * q;
        return v3_splat(f * g2 * q * keep);
    }
    const real den = eta * oh + ih, q = oh * d / co * fabs(ih) / (den * den);
    *pdf = (R(1) - f) * g1 * q;
    return v3_scale(m->kt, (R(1) - f) * g2 * q);
}

/* f x cos of lobes lb at sf towards wi and its density: frosted glass's
 * (lb->frost) or the lobes'. */
static vec3 surface_eval(const World *w, const Surface *sf, const Lobes *lb, vec3 wi, real *pdf)
{
    return lb->frost > R(0) ? frosted_eval(w, sf, lb->wo, wi, lb->frost, lb->frost_wt, lb->frost_refl, pdf)
                            : lobes_eval(lb, wi, pdf);
}

/* Whether a light along dir can reach the point through its lobes: above
 * the shading normal, or through frosted glass from either side; and the
 * shadow ray's origin for it. */
static int light_side(const Surface *sf, const Lobes *lb, vec3 dir, vec3 origin, vec3 *from)
{
    if (v3_dot(dir, sf->ns) > R(0)) {
        *from = sf->smooth ? trace_leave_origin(sf, dir) : origin;
        return 1;
    }
    if (!(lb && lb->frost > R(0)))
        return 0;
    *from = trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err); /* through the glass */
    return 1;
}

/* Next-event estimation from a point with smooth lobes: one point of
 * every light, its shadow ray, pi x f x cos x the radiance that arrives.
 * lb (or NULL): lobes that take every light; hl (or NULL): a highlight
 * that takes only the lights without a lamp (highlight_make's).  The
 * shading normal decides which lights can reach the point, as in
 * Whitted's shading (shade.c): near the boundary between light and dark
 * on a smooth triangle, a light behind the flat facet but in front of the
 * curved surface its normals describe lights the point, and the shadow ray
 * (from the point lifted towards that surface as it grazes the facet:
 * trace_leave_origin) says whether anything is in the way.
 * (Deciding by the facet cut a low-poly ball's terminator into the
 * polygon of its triangles: tests/test_render.c, the shadow terminator.) */
static vec3 direct_light(const World *w, const Surface *sf, const Lobes *lb, const Lobes *hl, const Draws *dr,
                         vec3 origin, RayStats *st)
{
    vec3 sum = v3_splat(R(0));
    for (uint32_t li = 0; li < w->light_count; li++) {
        real u = R(0.5), v = R(0.5), dist, pdf;
        if (world_light_is_area(&w->lights[li])) /* others have one point */
            draw2(dr, 0x100u + li, &u, &v);
        vec3 dir, rad, from;
        if (!shade_light_point(w, li, &sf->p, u, v, &dir, &dist, &rad) || !light_side(sf, lb, dir, origin, &from))
            continue;
        vec3 fc = lb ? surface_eval(w, sf, lb, dir, &pdf) : v3_splat(R(0));
        if (hl && w->lights[li].lamp_count == 0)
            fc = v3_add(fc, lobes_eval(hl, dir, &pdf));
        if (!(v3_max_comp(fc) > R(0)))
            continue;
        if (world_has(w, FEAT_SHADOWS)) {
            rad = v3_mul(rad, passed(w, &from, &dir, isfinite(dist) ? dist * (R(1) - R(64) * REAL_EPS) : REAL_MAX,
                                     &w->lights[li], st));
            if (!(v3_max_comp(rad) > R(0)))
                continue;
        }
        sum = v3_add(sum, v3_scale(v3_mul(fc, rad), REAL_PI));
    }
    return sum;
}

/* The power heuristic's weight of a strategy of density a beside one of b. */
static real power_weight(real a, real b) { return a * a / (a * a + b * b); }

/* The weight of next-event estimation's draw of dir (density pdf_light)
 * beside the bounce that could have left that way (density pdf_bounce):
 * the power heuristic's under MIS, else all of it, as where no bounce
 * follows (the last) or none leaves that way (below the smooth normal;
 * frosted glass's bounce goes to either side). */
static real nee_weight(const World *w, const Surface *sf, const Lobes *lb, int last, vec3 dir, real pdf_light,
                       real pdf_bounce)
{
    const int bsdf_finds = w->view.settings.emitter_sampling == EMITTERS_MIS && !last &&
                           (lb->frost > R(0) || v3_dot(dir, sf->nv) > R(0));
    return bsdf_finds ? power_weight(pdf_light, pdf_bounce) : R(1);
}

/* Next-event estimation of emissive geometry from a point with smooth
 * lobes: one point of one emitter, f x cos x its radiance over its
 * density, weighed against the bounce that could have found it (at the
 * last bounce none follows, and no bounce leaves below the smooth normal
 * sf->nv, which a normal map's shading normal may dip under: the whole of
 * it).  The shading normal decides, as in direct_light. */
static vec3 direct_emitters(const World *w, const Surface *sf, const Lobes *lb, int last, const Draws *dr,
                            vec3 origin, RayStats *st)
{
    real u, v, pdf;
    draw2(dr, 5, &u, &v);
    EmitterSample es;
    vec3 from;
    if (!emitters_sample(w, sf->p, draw1(dr, 6), u, v, &es) || !light_side(sf, lb, es.dir, origin, &from))
        return v3_splat(R(0));
    const vec3 fc = surface_eval(w, sf, lb, es.dir, &pdf);
    if (!(v3_max_comp(fc) > R(0)))
        return v3_splat(R(0));
    /* short of the point by more than the rounding of its place, so the emitter does not shadow itself */
    vec3 through = v3_splat(R(1));
    if (w->view.settings.shadows) {
        through = passed(w, &from, &es.dir, es.dist * (R(1) - R(1024) * REAL_EPS), NULL, st);
        if (!(v3_max_comp(through) > R(0)))
            return v3_splat(R(0));
    }
    const real weight = nee_weight(w, sf, lb, last, es.dir, es.pdf, pdf);
    return v3_scale(v3_mul(v3_mul(fc, es.radiance), through), weight / es.pdf);
}

/* Next-event estimation of the environment from a point with smooth
 * lobes: one direction drawn by the image's light (environment.h), its
 * shadow ray out of the scene, f x cos x the light over its density,
 * weighed against the bounce that could have left that way, as
 * direct_emitters weighs an emitter's point. */
static vec3 direct_environment(const World *w, const Surface *sf, const Lobes *lb, int last, const Draws *dr,
                               vec3 origin, RayStats *st)
{
    real u, v, pdf_env, pdf;
    vec3 dir, light, from;
    draw2(dr, 7, &u, &v);
    if (!environment_sample(w->env, u, v, &dir, &light, &pdf_env) || !light_side(sf, lb, dir, origin, &from))
        return v3_splat(R(0));
    const vec3 fc = surface_eval(w, sf, lb, dir, &pdf);
    if (!(v3_max_comp(fc) > R(0)) || !(v3_max_comp(light) > R(0)))
        return v3_splat(R(0));
    vec3 through = v3_splat(R(1));
    if (w->view.settings.shadows) {
        through = passed(w, &from, &dir, REAL_MAX, NULL, st);
        if (!(v3_max_comp(through) > R(0)))
            return v3_splat(R(0));
    }
    const real weight = nee_weight(w, sf, lb, last, dir, pdf_env, pdf);
    return v3_scale(v3_mul(v3_mul(fc, light), through), weight / pdf_env);
}

/* The share of light that a bounce off a smooth lobe (density pdf_bounce)
 * brings from an emitter or the environment that next-event estimation
 * draws with density pl there: all of it where it could not have drawn
 * it, else the bounce's weight (none where next-event estimation alone
 * finds such light; all where the bounces alone do). */
static real bounce_weight(const World *w, real pdf_bounce, real pl)
{
    const EmitterSampling es = w->view.settings.emitter_sampling;
    if (es == EMITTERS_BSDF || !(pl > R(0)))
        return R(1);
    return es == EMITTERS_NEE ? R(0) : power_weight(pdf_bounce, pl);
}

/* The share of emission that a path meeting h after a bounce from p off
 * a smooth lobe (density pdf_bounce) adds: all of it where next-event
 * estimation could not have found it, else the weight of the bounce. */
static real bounce_share(const World *w, vec3 p, real pdf_bounce, const Ray *r, const Hit *h, int through)
{
    if (w->view.settings.emitter_sampling == EMITTERS_BSDF) /* (the density not needed) */
        return R(1);
    Ray rp;
    Hit hp;
    if (through) { /* the ray from p itself, as next-event estimation's: its distance from there */
        const vec3 q = ray_at(r, h->t);
        rp = *r, hp = *h;
        rp.org = p;
        hp.t = v3_dot(v3_sub(q, p), r->dir);
        r = &rp, h = &hp;
    }
    return bounce_weight(w, pdf_bounce, emitters_pdf(w, p, r, h));
}

/* The surface's diffuse colour here: its material's (or its checker's
 * square), a model's vertex colour, times its texture (read at one point:
 * no ray footprint here). */
static vec3 diffuse_at(const World *w, const Surface *sf)
{
    vec3 kd = world_has(w, FEAT_COLOURS) && sf->has_colour ? sf->colour : sf->mat->kd;
    if (world_has(w, FEAT_CHECKER) && material_checkered(sf->mat))
        kd = material_checker(sf->mat, kd, sf->p, sf->u, sf->v, sf->has_uv);
    if (world_has(w, FEAT_TEXTURES) && sf->tex && sf->has_uv)
        kd = v3_mul(kd, trace_surface_texel(w, sf, NULL));
    return kd;
}

/* Glass: the path reflected (its weight times fr, the share of Fresnel's
 * reflection the material keeps) or refracted (times the transmitted
 * colour), chosen by Fresnel's reflectance f (td: the refracted
 * direction, dielectric_split's).  0 where the path ends. */
static int glass_bounce(const Surface *sf, vec3 d, real f, vec3 td, real fr, real pick, vec3 *beta, Ray *next)
{
    if (pick < f) {
        vec3 r = trace_reflected(d, sf);
        if (fr < R(1))
            *beta = v3_scale(*beta, fr);
        ray_init(next, trace_offset_origin(sf->p, sf->ng, sf->err), r, R(0), REAL_MAX);
        return v3_dot(r, sf->ng) > R(0);
    }
    *beta = v3_mul(*beta, sf->mat->kt);
    ray_init(next, trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err), v3_norm(td), R(0), REAL_MAX);
    return 1;
}

/* Frosted glass (material_frosted): a facet of its GGX lobe that the ray
 * sees, drawn from (u, v) (ggx_visible_normal), reflects or refracts it
 * as clear glass would (Fresnel's reflectance at the facet deciding), and
 * the path keeps G2 / G1 of its weight (the facets that shadow where it
 * goes: Walter et al.'s microfacet BSDF, sampled as Heitz's visible
 * normals make it, whose weight is that alone).  What would leave on the
 * wrong side of the surface (a facet's reflection into it, or its
 * refraction out of it) ends the path.  fr as glass_bounce's; wt the
 * lobe's weight for the light between facets (dielectric_frost_weight). */
static int frosted_bounce(const World *w, const Surface *sf, vec3 d, real fr, real wt, real pick, real u, real v,
                          vec3 *beta, Ray *next)
{
    const real alpha = ggx_alpha(sf->mat->roughness);
    const vec3 m = ggx_visible_normal(sf->ns, v3_neg(d), alpha, u, v);
    real eta;
    vec3 td;
    const real f = dielectric_split_at(w, sf, m, d, &eta, &td);
    vec3 wi;
    if (pick < f) {
        wi = v3_reflect(d, m);
        if (!(v3_dot(wi, sf->ng) > R(0)))
            return 0;
        *beta = v3_scale(*beta, fr * wt * ggx_keep(sf->ns, v3_neg(d), wi, alpha));
        ray_init(next, trace_offset_origin(sf->p, sf->ng, sf->err), wi, R(0), REAL_MAX);
        return 1;
    }
    wi = v3_norm(td); /* dielectric_split took it for a reflection where it would not go below the facet */
    *beta = v3_scale(v3_mul(*beta, sf->mat->kt), wt * ggx_keep(sf->ns, v3_neg(d), wi, alpha));
    ray_init(next, trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err), wi, R(0), REAL_MAX);
    return 1;
}

/* A dielectric that is glass alone: reflected or refracted by Fresnel's
 * reflectance (so the weight stays, times fr on the reflection;
 * refraction takes the transmitted colour).  0 where the path ends. */
static int dielectric_bounce(const World *w, const Surface *sf, vec3 d, real fr, real pick, vec3 *beta, Ray *next)
{
    real eta;
    vec3 td;
    const real f = dielectric_split(w, sf, d, &eta, &td);
    return glass_bounce(sf, d, f, td, fr, pick, beta, next);
}

/* A mirror (a smooth metal; a smooth coat): the mirror direction,
 * weighted by its colour kr.  0 where the path ends (mirrored into the
 * surface).  A rough metal's lobe is a smooth one (lobes.h). */
static int mirror_bounce(const Surface *sf, vec3 kr, vec3 d, vec3 *beta, Ray *next)
{
    const vec3 r = trace_reflected(d, sf);
    if (!(v3_dot(r, sf->ng) > R(0)))
        return 0;
    *beta = v3_mul(*beta, kr);
    ray_init(next, trace_offset_origin(sf->p, sf->ng, sf->err), r, R(0), REAL_MAX);
    return 1;
}

/* A path under way: what it has gathered and the ray it goes on by. */
typedef struct {
    vec3 L, beta;
    Ray ray;       /* the next ray to trace */
    SampleId id;
    uint64_t *key; /* the camera ray's first sight (adaptive anti-aliasing), or NULL */
    int b;         /* the bounce whose hit comes next: 0 for the camera ray */
    int after_smooth; /* the path left a point by a smooth lobe, which took the lights (next-event estimation) */
    vec3 from;        /* that point */
    real pdf_bounce;  /* and the density of the bounce's direction */
    real min_pdf;     /* the least density of the path's bounces off smooth lobes (surface_blur) */
    int diffuse_before; /* its last bounce was the diffuse lobe's (settings caustics: surface_drop) */
    real fresnel_keep;  /* what glass's Fresnel reflection keeps at this surface: 1, or 0 (surface_drop) */
    int through;      /* the ray left a see-through blend it passed straight, not that point */
    const DrawPlan *plan;
    Guide *guide;     /* the denoiser's guide, while the path has not met its first rough surface; else NULL */
    vec3 tint;        /* ... the smooth mirrors' and clear glass's colours on the way to it */
    real dist;        /* ... and the path's length so far */
} Path;

static void path_start(Path *p, const DrawPlan *plan, const Ray *r, SampleId id, uint64_t *key, Guide *guide)
{
    p->plan = plan;
    /* field by field: a compound literal cleared the whole and copied it */
    p->L = v3_splat(R(0)), p->beta = v3_splat(R(1)), p->from = v3_splat(R(0));
    p->ray = *r, p->id = id, p->key = key;
    p->b = 0, p->after_smooth = 0, p->pdf_bounce = R(0), p->through = 0, p->min_pdf = REAL_MAX;
    p->diffuse_before = 0, p->fresnel_keep = R(1);
    p->guide = guide;
    if (guide) {
        p->tint = v3_splat(R(1)), p->dist = R(0);
        *guide = guide_none(p->tint);
    }
}

/* A metal rougher than this is a surface of its own to the guide; a
 * smoother one's reflection is followed as a mirror's (what it reflects
 * stays sharp: the brass ball of models/example.scene, roughness 0.15, lost
 * its reflection to the filter as a surface) */
#define GUIDE_GLOSSY R(0.3)

/* Whether glass at this hit is curved (a sphere, a smooth triangle), a
 * lens: there the guide stops at the glass's own surface.  Through a lens
 * neighbouring pixels see far-apart surfaces and the light that crosses it
 * is the noisiest of the frame (the lights reach it by paths alone); the
 * guides of what each saw through it differed, the filter's edges kept it
 * out, and a glass ball stayed speckled in a smooth frame (the default
 * scene at 2 x 2 samples denoised: RMSE 16.6 about the ball against 16 x
 * 16 samples; 12.8 stopping there, what it shows blurred a little).  Through
 * flat glass (a pane) the guide goes on, so what it shows stays sharp. */
static int guide_lens(const Hit *h, const Surface *sf)
{
    return h->kind == HIT_SPHERE || sf->smooth;
}

/* The guide at a hit of a path that has met no rough surface yet (kd: the
 * surface's diffuse and Phong specular colours there, so that a white
 * highlight on red is not divided by red's little green): the surface's
 * colour, normal and distance; a mirror or clear glass (delta: the path's
 * next ray is its only one, or nearly) gives its own where the path ends
 * on it, else its colour tints what is seen through it, which sets the
 * guide.  An emitter ends the guide as the background does (surface 0). */
static void guide_at(Path *p, const Surface *sf, const Hit *h, vec3 kd, int delta)
{
    const Material *m = sf->mat;
    Guide *g = p->guide;
    const int first = p->dist == R(0); /* the camera ray's own hit, not one seen through a mirror or glass */
    p->dist += h->t;
    if (material_emits(m)) {
        *g = guide_none(p->tint);
        p->guide = NULL;
        return;
    }
    const real mu = v3_dot(sf->ns, v3_neg(p->ray.dir));
    const vec3 kr = material_reflects(m) ? material_mirror_at(m, mu) : v3_splat(R(0)),
               kt = material_dielectric(m) ? m->kt : v3_splat(R(0));
    g->albedo = v3_mul(p->tint, v3_min(v3_add(v3_add(kd, kr), kt), v3_splat(R(1))));
    g->normal = mu < R(0) ? v3_neg(sf->ns) : sf->ns;
    g->depth = p->dist;
    g->surface = 1;
    g->instance = first && h->kind == HIT_INSTANCE ? h->index + 1 : 0;
    if (delta) /* what the next ray meets sets it, seen through this colour */
        p->tint = v3_mul(p->tint, material_dielectric(m) ? v3_splat(R(1)) : kr);
    else
        p->guide = NULL;
}

/* The Phong highlight (ks) of a surface that reflects rays itself (a
 * mirror, a metal; a dielectric's has none here, path_step), into *hl: it stands here for the reflection of
 * the lights no ray can meet (points, spots, directions, area lights
 * without a lamp), as it does for every light under Whitted's integrator.
 * What a ray can meet (lamps, emitters, the background) the surface's
 * reflected ray brings: a whole glossy lobe beside it counted that twice
 * (an imported metal, whose highlight is its mirror's colour, reflected
 * twice its colour of a white sky).  0 where there is none (or the
 * world, as plan pl says, has no such light). */
static int highlight_make(const DrawPlan *pl, const Surface *sf, vec3 ks, vec3 d, Lobes *hl)
{
    const vec3 zero = v3_splat(R(0));
    const LobeColours c = {.kd = zero, .ks = ks, .shininess = sf->mat->shininess, .kr = zero, .km = zero};
    return v3_max_comp(ks) > R(0) && pl->lampless && lobes_make(hl, &c, &sf->ns, &d);
}

/* Light c (times the path's weight) added to the sample's; where it came
 * after the path's first bounce (indirect: a light met by the path's
 * third ray or later, or sampled from its second surface or later), held
 * to settings clamp_indirect, the sum of its channels, as Cycles' Clamp
 * Indirect holds it: fewer fireflies, a little less light. */
static inline void path_gather(const World *w, Path *p, vec3 c, int indirect)
{
    const real limit = w->view.settings.clamp_indirect;
    if (indirect && limit > R(0)) {
        const real sum = fabs(c.x) + fabs(c.y) + fabs(c.z);
        if (sum > limit)
            c = v3_scale(c, limit / sum);
    }
    p->L = v3_add(p->L, c);
}

/* A surface of smooth lobes (diffuse, the Phong highlight, a rough coat's
 * and a rough metal's GGX lobes) and delta ones (a mirror share; a
 * dielectric's glass: Fresnel's reflection, less the mirror's share, and
 * the transmission, or frosted glass's facets, by the paths alone here): next-event estimation for the
 * smooth ones, then one lobe chosen by weight for the path's next ray.
 * 0 where the path ends. */
static int surface_bounce(const World *w, Path *p, const Surface *sf, vec3 kd, vec3 ks, const Draws *dr, int last,
                          RayStats *st)
{
    const Material *m = sf->mat;
    const vec3 d = p->ray.dir;
    const real mu = v3_dot(sf->ns, v3_neg(d));
    /* kcm: a smooth coat's mirror */
    vec3 kr = material_reflects(m) ? material_mirror_at(m, mu) : v3_splat(R(0)), kcm = v3_splat(R(0));
    real kc = R(0), coat_alpha = R(0), under = R(1); /* under: what the coat lets through */
    if (world_has(w, FEAT_COAT) && material_coats(m) && w->view.settings.shading == SHADE_PHONG) {
        /* a clear coat: its Fresnel share a GGX lobe, the rest of the surface what it lets through */
        kc = dielectric_coat_share(w, sf, v3_neg(d));
        coat_alpha = ggx_alpha(m->coat_roughness);
        under = R(1) - kc;
        kd = v3_scale(kd, under), ks = v3_scale(ks, under), kr = v3_scale(kr, under);
        if (material_coat_smooth(m)) /* a mirror share (material.h) */
            kcm = v3_splat(kc), kc = R(0);
    }
    real f = R(0), fr = R(1), eta, u, v;
    vec3 td = v3_splat(R(0)), kg = v3_splat(R(0));
    if (material_dielectric(m)) {
        f = dielectric_split(w, sf, d, &eta, &td);
        fr = real_max(R(0), R(1) - v3_max_comp(kr)) * p->fresnel_keep;
        kg = v3_add(v3_splat(f * fr), v3_scale(m->kt, R(1) - f));
    }
    /* a rough metal reflects by its GGX lobe (ggx.h), a smooth one, lit
     * by every light and emitter as the other smooth lobes are: it shows
     * the lights itself, so it keeps no Phong highlight; a smooth mirror
     * keeps its highlight for the lights no ray meets */
    const int rough = material_rough(m), own = material_reflects(m) && !rough;
    LobeColours lc = {.kd = kd, .ks = material_reflects(m) ? v3_splat(R(0)) : ks, .shininess = m->shininess,
                      .kr = v3_add(v3_add(kr, kcm), kg), .kc = kc, .coat_alpha = coat_alpha, .km = v3_splat(R(0))};
    if (rough) { /* weighed for the light its facets pass between them (ggx_metal) */
        lc.km = v3_scale(ggx_metal_of(m, mu, &lc.kme), under); /* an edged one's colour by each facet (lobes.h) */
        lc.kme = v3_scale(lc.kme, under);
        lc.alpha = ggx_alpha(m->roughness), lc.kr = v3_add(kcm, kg), kr = v3_splat(R(0));
    }
    Lobes lb, hl;
    const int highlight = own && highlight_make(p->plan, sf, ks, d, &hl);
    if (!lobes_make(&lb, &lc, &sf->ns, &d))
        return 0;
    lb.nv = sf->nv, lb.bumped = sf->bumped; /* a normal map's diffuse shadowing (lobes.h) */
    /* the shadow rays' origin, made once: a flat surface's bounce leaves from it too */
    const int emitters = w->emitter_count > 0 && w->view.settings.emitter_sampling != EMITTERS_BSDF;
    const int envs = w->env && w->view.settings.emitter_sampling != EMITTERS_BSDF;
    const int smooth = lobes_smooth(&lb) && (w->light_count > 0 || emitters || envs);
    const int nee = smooth || highlight;
    /* the light rays' origin off a flat surface, made once (a smooth
     * triangle's each by its direction: trace_leave_origin) */
    const vec3 from_p = nee || !sf->smooth ? trace_offset_origin(sf->p, sf->ng, sf->err) : v3_splat(R(0));
    if (nee) { /* next-event estimation: what the smooth lobes take from the lights */
        path_gather(w, p, v3_mul(p->beta, direct_light(w, sf, smooth ? &lb : NULL, highlight ? &hl : NULL, dr,
                                                         from_p, st)), p->b >= 1);
        if (smooth && emitters)
            path_gather(w, p, v3_mul(p->beta, direct_emitters(w, sf, &lb, last, dr, from_p, st)), p->b >= 1);
        if (smooth && envs)
            path_gather(w, p, v3_mul(p->beta, direct_environment(w, sf, &lb, last, dr, from_p, st)), p->b >= 1);
    }
    if (last)
        return 0;
    draw2(dr, 1, &u, &v);
    const real pick = draw1(dr, 2), wm = v3_max_comp(kr), wg = v3_max_comp(kg);
    if (pick < lb.pm && !(wg > R(0))) { /* the mirror, chosen with probability pm */
        p->beta = v3_scale(p->beta, R(1) / lb.pm);
        return mirror_bounce(sf, v3_add(kr, kcm), d, &p->beta, &p->ray);
    }
    if (pick < lb.pm) { /* the mirror or the glass, each by its share of pm (a dielectric has no coat) */
        const real s = pick / lb.pm * (wm + wg);
        const int mirror = s < wm;
        p->beta = v3_scale(p->beta, (wm + wg) / (lb.pm * (mirror ? wm : wg)));
        if (mirror)
            return mirror_bounce(sf, kr, d, &p->beta, &p->ray);
        return material_frosted(m) ? frosted_bounce(w, sf, d, fr, dielectric_frost_weight(sf, v3_neg(d)),
                                                    (s - wm) / wg, u, v, &p->beta, &p->ray)
                                   : glass_bounce(sf, d, f, td, fr, (s - wm) / wg, &p->beta, &p->ray);
    }
    /* a smooth lobe's direction, weighed by both smooth lobes */
    real pdf;
    const real sub = (pick - lb.pm) / (R(1) - lb.pm);
    const vec3 nd = lobes_sample_smooth(&lb, sub, u, v);
    p->diffuse_before = lobes_picks_diffuse(&lb, sub);
    const vec3 fc = lobes_eval(&lb, nd, &pdf);
    const int go = pdf > R(0) && v3_dot(nd, sf->nv) > R(0); /* leaves the smooth surface (sf->nv) */
    p->beta = v3_mul(p->beta, v3_scale(fc, go ? R(1) / pdf : R(0)));
    p->after_smooth = 1;
    p->from = sf->p;
    p->pdf_bounce = pdf;
    p->min_pdf = real_min(p->min_pdf, pdf * (R(1) - lb.pm)); /* the density of all its choices, as Cycles' */
    /* lifted as the shadow rays are, by how nearly it grazes the facet */
    ray_init(&p->ray, sf->smooth ? trace_leave_origin(sf, nd) : from_p, nd, R(0), REAL_MAX);
    return go;
}

/* Frosted glass alone: the lights and emitters through its facets, from
 * either side (next-event estimation: frosted_eval), then the path on by
 * one facet (frosted_bounce), weighed against the emitters it may meet
 * (multiple importance sampling), as a smooth lobe's.  0 where the path
 * ends. */
static int frosted_step(const World *w, Path *p, const Surface *sf, const Draws *dr, int last, RayStats *st)
{
    const vec3 d = p->ray.dir;
    const real alpha = ggx_alpha(sf->mat->roughness);
    const vec3 wo = v3_neg(d);
    /* the weight for the light between facets, once for the lights, the emitters and the bounce */
    const Lobes lb = {.n = sf->ns, .wo = wo, .frost = alpha, .frost_wt = dielectric_frost_weight(sf, wo),
                      .frost_refl = p->fresnel_keep};
    const int emitters = w->emitter_count > 0 && w->view.settings.emitter_sampling != EMITTERS_BSDF;
    const int envs = w->env && w->view.settings.emitter_sampling != EMITTERS_BSDF;
    if (w->light_count > 0 || emitters || envs) {
        const vec3 from_p = trace_offset_origin(sf->p, sf->ng, sf->err);
        path_gather(w, p, v3_mul(p->beta, direct_light(w, sf, &lb, NULL, dr, from_p, st)), p->b >= 1);
        if (emitters)
            path_gather(w, p, v3_mul(p->beta, direct_emitters(w, sf, &lb, last, dr, from_p, st)), p->b >= 1);
        if (envs)
            path_gather(w, p, v3_mul(p->beta, direct_environment(w, sf, &lb, last, dr, from_p, st)), p->b >= 1);
    }
    if (last)
        return 0;
    real u, v, pdf;
    draw2(dr, 1, &u, &v);
    if (!frosted_bounce(w, sf, d, p->fresnel_keep, lb.frost_wt, draw1(dr, 2), u, v, &p->beta, &p->ray))
        return 0;
    frosted_eval(w, sf, wo, p->ray.dir, alpha, lb.frost_wt, R(1), &pdf);
    p->after_smooth = pdf > R(0);
    p->from = sf->p;
    p->pdf_bounce = pdf;
    p->min_pdf = real_min(p->min_pdf, pdf);
    return 1;
}

/* Filter Glossy (settings filter_glossy F: Cycles' blur_glossy, as Cycles
 * 3.4 applies it).  After bounces whose least density q (Path.min_pdf,
 * solid angle) is under F, every GGX lobe of sf is at least
 * sqrt(1 - q / F) / 2 wide (alpha; roughness its square root), and a
 * mirror, clear glass or a smooth coat becomes one that wide: the sun
 * that a diffuse bounce meets through a mirror ball only by chance, a
 * firefly, becomes a glossy highlight that next-event estimation finds.
 * Biased: caustics blur, the more the less likely the path that led
 * there.  The camera's surface, and any after mirrors and glass alone
 * (density unbounded), are never blurred, nor a see-through blend (ior 1:
 * it bends nothing, as Cycles' Transparent BSDF, which is not blurred). */
static void surface_blur(const World *w, const Path *p, Surface *sf)
{
    const real f = w->view.settings.filter_glossy;
    if (!(f > R(0) && p->min_pdf < f))
        return;
    const real rough = sqrt(sqrt(R(1) - p->min_pdf / f) * R(0.5)); /* ggx_alpha's square root */
    const Material *m = sf->mat;
    const int lobe = (material_reflects(m) || material_dielectric(m)) && !material_null(m) && m->roughness < rough,
              coat = material_coats(m) && m->coat_roughness < rough;
    if (!(lobe || coat))
        return;
    Material *l = trace_surface_local(sf);
    if (lobe)
        l->roughness = rough;
    if (coat)
        l->coat_roughness = rough;
}

/* Caustics dropped (settings caustics: Cycles' Reflective and Refractive
 * Caustics, as Cycles 3.4 drops a closure where the ray came from a
 * diffuse bounce): at a surface the path reached by its diffuse lobe,
 * without reflective caustics its mirror, metal, coat and Phong highlight
 * are gone and glass keeps no Fresnel reflection (p->fresnel_keep 0),
 * without refractive ones glass lets nothing through (a see-through
 * blend, which bends nothing, still does: Cycles' Transparent BSDF is no
 * caustic either); what is gone takes neither light nor a path on.  The
 * sun that a floor meets in a mirror ball or through a glass ball,
 * fireflies, is then not there at all: less light, no noise from it. */
static void surface_drop(const World *w, Path *p, Surface *sf)
{
    const Caustics c = w->view.settings.caustics;
    const int reflect = c == CAUSTICS_BOTH || c == CAUSTICS_REFLECTIVE,
              refract = c == CAUSTICS_BOTH || c == CAUSTICS_REFRACTIVE;
    p->fresnel_keep = R(1);
    if (!p->diffuse_before || (reflect && refract))
        return;
    p->fresnel_keep = reflect ? R(1) : R(0);
    Material *l = trace_surface_local(sf);
    if (!reflect)
        l->kr = l->kre = l->ks = v3_splat(R(0)), l->coat = R(0);
    if (!refract && !material_null(l))
        l->kt = v3_splat(R(0));
}

/* One bounce of path p: the hit h of its ray (found: whether there is
 * one) lit and scattered.  1 where the path goes on by p->ray. */
static int path_step(const World *w, Path *p, int found, const Hit *h, RayStats *st)
{
    const int b = p->b;
    if (b == 0)
        st->primary++;
    else
        st->secondary++;
    if (!found) {
        vec3 seen = w->background;
        if (w->env) { /* weighed against the environment's next-event estimation after a smooth bounce */
            real pl;
            seen = environment_seen(w->env, p->ray.dir, &pl);
            if (p->after_smooth)
                seen = v3_scale(seen, bounce_weight(w, p->pdf_bounce, pl));
        }
        path_gather(w, p, v3_mul(p->beta, seen), b >= 2);
        if (b == 0 && p->key)
            *p->key = UINT64_MAX;
        if (p->guide) /* the background seen, through what tinted it */
            *p->guide = guide_none(p->tint);
        return 0;
    }
    const int depth = w->view.settings.depth;
    Surface sf;
    trace_surface(w, &p->ray, h, &sf);
    trace_surface_bump(&sf, NULL); /* samples accumulate: the maps at a point each */
    trace_surface_metal(w, &sf, NULL);
    trace_surface_blend(&sf);
    surface_blur(w, p, &sf);
    surface_drop(w, p, &sf);
    const int was_diffuse = p->diffuse_before;
    p->diffuse_before = 0; /* until surface_bounce takes the diffuse lobe again */
    const Material *m = sf.mat;
    if (b == 0 && p->key)
        *p->key = (uint64_t)sf.object << 16;
    if (sf.inside && material_dielectric(m) && v3_max_comp(m->absorb) > R(0)) /* crossed its inside */
        p->beta = v3_mul(p->beta, dielectric_absorbed(w, m, h));
    /* emission, but not a lamp's whose light was sampled at the point before */
    if (material_emits(m) && !(p->after_smooth && trace_any_lamp(w, h)))
        path_gather(w, p,
                    v3_scale(v3_mul(p->beta, trace_emission(w, &sf, NULL)),
                             p->after_smooth ? bounce_share(w, p->from, p->pdf_bounce, &p->ray, h, p->through) : R(1)),
                    b >= 2);
    const int last = b >= depth; /* the light that reaches this point still counts: depth 0 is direct light */
    Draws dr;
    draws_at(&dr, p->plan, &p->id, (uint32_t)b);
    int go;
    /* the bounce before, kept where the path passes a see-through blend
     * straight (next-event estimation saw through it: passed) */
    const int was_smooth = p->after_smooth;
    const vec3 was_from = p->from, was_dir = p->ray.dir;
    p->after_smooth = 0, p->through = 0;
    /* a dielectric's highlight is its Fresnel reflection, traced here (its
     * Phong `specular` stands in for it under the Whitted integrator, which
     * cannot reflect a point light; here a highlight of the point lights, as
     * a metal keeps (highlight_make), made a caustic of each on the floor
     * around the example's bottle, a speckle of fireflies at 64 samples) */
    const int glass = material_dielectric(m);
    const vec3 kd = diffuse_at(w, &sf),
               ks = w->view.settings.shading == SHADE_PHONG && !glass ? m->ks : v3_splat(R(0));
    if (p->guide) { /* delta: clear flat glass, or a mirror of nothing else, smooth or nearly */
        const int bare = !(v3_max_comp(kd) > R(0));
        guide_at(p, &sf, h, v3_add(kd, ks),
                 bare && (glass ? !material_reflects(m) && !material_frosted(m) && !guide_lens(h, &sf)
                                : material_reflects(m) && m->roughness < GUIDE_GLOSSY && !material_coats(m)));
    }
    if (glass && !(v3_max_comp(kd) > R(0) || material_reflects(m)) && material_frosted(m)) {
        go = frosted_step(w, p, &sf, &dr, last, st);
    } else if (glass && !(v3_max_comp(kd) > R(0) || material_reflects(m))) {
        if (last)
            return 0;
        go = dielectric_bounce(w, &sf, p->ray.dir, p->fresnel_keep, draw1(&dr, 2), &p->beta, &p->ray);
    } else {
        go = surface_bounce(w, p, &sf, kd, ks, &dr, last, st);
    }
    if (!go)
        return 0;
    const int straight = material_null(m) && v3_dot(p->ray.dir, was_dir) > R(1) - R(1e-6);
    if (was_smooth && !p->after_smooth && straight)
        p->after_smooth = 1, p->from = was_from, p->through = 1; /* pdf_bounce is still that bounce's */
    if (straight) /* the diffuse bounce before it still counts past a veil (Cycles' transparent bounces) */
        p->diffuse_before = was_diffuse;
    if (b + 1 >= w->view.settings.roulette) { /* Russian roulette: survivors weighed up by as much */
        const real keep = real_min(R(1), v3_max_comp(p->beta));
        if (!(draw1(&dr, 3) < keep))
            return 0;
        p->beta = v3_scale(p->beta, R(1) / keep);
    }
    p->b = b + 1;
    return 1;
}

void path_radiance_packet(const World *w, const Ray *rays, int n, const SampleId *ids, vec3 *out, RayStats *st,
                          uint64_t *keys, Guide *guides)
{
    Path p[TRACE_PACKET];
    Hit h[TRACE_PACKET];
    DrawPlan plan;
    draw_plan(&plan, w);
    /* the camera rays together (a packet where they keep together) */
    trace_closest_packet(w, rays, n, h);
    int live[TRACE_PACKET], m = 0;
    for (int i = 0; i < n; i++) {
        const SampleId id = ids ? ids[i] : (SampleId){.key = 0, .index = 0, .count = 1};
        path_start(&p[i], &plan, &rays[i], id, keys ? &keys[i] : NULL, guides ? &guides[i] : NULL);
        if (path_step(w, &p[i], h[i].kind != HIT_NONE, &h[i], st))
            live[m++] = i;
    }
    /* then the bounces of every live path at once: one call
     * (trace_closest_each) walks their rays two at a time, and in a world
     * of one model hands them all to the model's pairs' walk (as
     * tools/bench/rayclass times diffuse bounces).  Measured against the
     * pairs of paths this loop kept before (a path that ended gave its
     * place to the next): lanray-render --integrator path --aa 4, 320x240,
     * one thread, the bunny and the default scene: within noise (0.49-0.52
     * s and 1.14-1.23 s either way), the same pixels. */
    while (m > 0) {
        Ray r[TRACE_PACKET];
        for (int k = 0; k < m; k++)
            r[k] = p[live[k]].ray;
        trace_closest_each(w, r, m, h);
        int still = 0;
        for (int k = 0; k < m; k++)
            if (path_step(w, &p[live[k]], h[k].kind != HIT_NONE, &h[k], st))
                live[still++] = live[k];
        m = still;
    }
    for (int i = 0; i < n; i++)
        out[i] = p[i].L;
}
