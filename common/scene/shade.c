/* shade.c - local illumination.
 *
 *   colour = ambient*kd + sum over lights reaching the point of
 *            radiance * (kd * max(0, N.L) + ks * max(0, R.V)^shininess)
 *
 * kd is a model's interpolated vertex colour where it has them (and the
 * instance keeps the model's material), and is multiplied by the texture
 * where the material has one; the specular
 * term is skipped in diffuse-only mode and for materials without ks.  One
 * shadow ray per light stops at the first occluder (any-hit); with glass
 * shadows, a blocked one is followed through dielectrics instead, tinted
 * by their transmitted colour (no refraction: no caustics).
 *
 * Beyond the local terms (shade_beyond): an emissive material adds its
 * radiance; a mirror adds kr times what its reflected ray sees; a
 * dielectric splits into the reflected ray (weight F, by Fresnel's
 * equations or Schlick's approximation) and the refracted one (weight
 * (1 - F) kt), total internal reflection sending everything back; light
 * that crossed a dielectric's inside is absorbed by exp(-absorb t)
 * (Beer-Lambert).  Secondary rays recurse up to settings.depth bounces and
 * are not traced where their weight, the most they can add to the pixel,
 * is below settings.cutoff.  A rough mirror spreads its reflection over
 * rough_samples^2 rays about the mirror direction, and an area light (a
 * sphere, a rectangle) is samples^2 shadow rays to stratified points of it:
 * soft shadows.  Their random numbers come from the ray's key (the pixel
 * sample's, base/sample.h), mixed with the bounce and what they are drawn
 * for: any client renders any pixel the same. */
#include "scene/shade.h"

#include "scene/path.h"

#include "base/sample.h"
#include "geom/raydiff.h"

/* The axes of the disc a sphere light shows a shading point, kept for
 * the light's next point (a profile of adaptive light sampling, which
 * takes every point without its shadow ray, had a sixth of the time in
 * making them again). */
typedef struct {
    vec3 a, b;
    uint32_t of; /* 1 + the light they are of; 0: none yet */
} DiscAxes;

/* The point (u, v) of the unit square on area light li, l, as seen from p:
 * a rectangle's point, or a sphere's on the disc it shows p. */
static vec3 area_point(const WorldLight *l, uint32_t li, vec3 p, real u, real v, DiscAxes *ax)
{
    if (l->kind == LIGHT_RECT)
        return v3_add(l->pos, v3_add(v3_scale(l->edge1, u), v3_scale(l->edge2, v)));
    /* a sphere: its disc facing p (what p sees of it), by the concentric map */
    if (ax->of != li + 1) {
        vec3 w = v3_norm(v3_sub(p, l->pos));
        v3_frame(w, &ax->a, &ax->b);
        ax->of = li + 1;
    }
    real x, y;
    sample_disc(u, v, &x, &y);
    return v3_add(l->pos, v3_scale(v3_add(v3_scale(ax->a, x), v3_scale(ax->b, y)), l->radius));
}

/* area_sample's j for stratum s of an adaptive light sampling probe: PROBE_POINT + s */
#define PROBE_POINT 0x80000000u

/* Area light li's point j for a ray (id: its sample, mixed with the
 * bounce) into (u, v), and the point's share of the light; 0 where the ray
 * takes fewer points.  Per effect (settings sampling product): j of the
 * light's samples^2 stratified points, each ray its own.  One budget (the
 * default): j of the ray's share of the samples^2 points its pixel takes
 * (base/sample.h). */
static inline int area_sample(const World *w, const WorldLight *l, uint32_t li, const SampleId *id, uint32_t j, real *u,
                              real *v, real *share)
{
    const uint32_t k = (uint32_t)(l->samples * l->samples), key = sample_mix(id->key, 0x4c000000u + li);
    if (j >= PROBE_POINT) { /* adaptive light sampling's probe: a stratum of the light */
        sample_stratum(key, j - PROBE_POINT, (uint32_t)l->samples, u, v);
        *share = R(1);
        return 1;
    }
    if (w->view.settings.sampling == SAMPLING_PRODUCT) {
        sample_stratum(key, j, (uint32_t)l->samples, u, v);
        *share = R(1) / (real)k;
        return 1;
    }
    const uint32_t m = sample_share(k, id->count);
    if (j >= m)
        return 0;
    sample_sobol2(id->index * m + j, key, u, v);
    *share = R(1) / (real)m;
    return 1;
}

/* Light arriving at p from light l at pos (its position; an area light's
 * point), `scale` times its intensity so far: unit direction towards the
 * light, its distance (infinite for directional lights) and the radiance
 * arriving (colour x intensity, attenuated, a spot's cone, a rectangle's
 * cosine); 0 where none arrives. */
static inline __attribute__((always_inline)) int light_towards(const World *w, const WorldLight *l, vec3 pos, vec3 p,
                                                              real scale, vec3 *dir, real *dist, vec3 *radiance,
                                                              const int optional)
{
    if (l->kind == LIGHT_DIRECTIONAL) {
        *dir = v3_neg(l->axis);
        *dist = REAL_INF;
    } else {
        vec3 d = v3_sub(pos, p);
        real d2 = v3_dot(d, d);
        if (!(d2 > R(0)))
            return 0;
        *dist = sqrt(d2);
        *dir = v3_scale(d, R(1) / *dist);
        if (optional && world_uses(w, FEAT_ATTENUATION) && l->attenuate)
            scale /= d2;
        if (optional && world_uses(w, FEAT_SPOT) && l->kind == LIGHT_SPOT) {
            real c = -v3_dot(*dir, l->axis);
            if (c <= l->cos_outer)
                return 0;
            if (c < l->cos_inner) { /* soft edge: smoothstep across the rim */
                real t = (c - l->cos_outer) / (l->cos_inner - l->cos_outer);
                scale *= t * t * (R(3) - R(2) * t);
            }
        }
        if (optional && world_uses(w, FEAT_AREA) && l->kind == LIGHT_RECT)
            scale *= fabs(v3_dot(*dir, l->axis));
    }
    if (!(scale > R(0)))
        return 0;
    *radiance = v3_scale(l->color, scale);
    return 1;
}

/* Light arriving at p from light l, number li (for an area light, from
 * its point j for the ray's sample id), as light_towards says. */
static inline __attribute__((always_inline)) int light_at(const World *w, const WorldLight *l, vec3 p, const SampleId *id,
                                                         DiscAxes *ax, uint32_t li, uint32_t j, vec3 *dir, real *dist,
                                                         vec3 *radiance, const int optional)
{
    real scale = l->intensity;
    vec3 pos = l->pos;
    if (l->kind != LIGHT_DIRECTIONAL && optional && world_uses(w, FEAT_AREA) && world_light_is_area(l)) {
        real u, v, share;
        if (!area_sample(w, l, li, id, j, &u, &v, &share))
            return 0;
        pos = area_point(l, li, p, u, v, ax);
        scale *= share;
    }
    return light_towards(w, l, pos, p, scale, dir, dist, radiance, optional);
}

int shade_light_point(const World *w, uint32_t li, vec3 p, real u, real v, vec3 *dir, real *dist, vec3 *radiance)
{
    const WorldLight *l = &w->lights[li];
    DiscAxes ax = {.of = 0};
    vec3 pos = world_light_is_area(l) ? area_point(l, li, p, u, v, &ax) : l->pos;
    return light_towards(w, l, pos, p, l->intensity, dir, dist, radiance, 1);
}

/* What one camera ray's shading carries from light to light. */
typedef struct {
    Surface sf;
    vec3 kd, col, view, origin;
    int phong;
    uint32_t lit;
    SampleId id; /* the ray's sample, its key mixed with its bounce */
    DiscAxes disc;
    /* a scene with textures: the ray's differentials, its footprint on the
     * surface and how the shading normal changes across it (raydiff.h) */
    const RayDiff *rd;
    real t; /* the hit's distance, where the ray's cone goes on from */
    vec3 dpdx, dpdy, dndx, dndy;
    vec3 irr; /* settings depth_limit local: the ambient and the light that reaches the point */
} Shading;

/* Light l's contribution to ray sh, already known to reach it. */
static void add_light(Shading *sh, vec3 L, vec3 rad, real ndotl, uint32_t i)
{
    sh->lit |= i < 16 ? 1u << i : 0;
    sh->col = v3_add(sh->col, v3_scale(v3_mul(sh->kd, rad), ndotl));
    if (sh->phong) {
        real rv = v3_dot(v3_reflect(v3_neg(L), sh->sf.ns), sh->view);
        if (rv > R(0))
            sh->col = v3_add(sh->col, v3_scale(v3_mul(sh->sf.mat->ks, rad), pow(rv, sh->sf.mat->shininess)));
    }
}

static inline __attribute__((always_inline)) void shade_start(const World *w, const Ray *r, const Hit *hit,
                                                              Shading *sh, const RayDiff *rd, const int optional)
{
    trace_surface(w, r, hit, &sh->sf);
    const Material *m = sh->sf.mat;
    sh->kd = optional && world_uses(w, FEAT_COLOURS) && sh->sf.has_colour ? sh->sf.colour : m->kd;
    const int textured = optional && world_uses(w, FEAT_TEXTURES) && sh->sf.tex && sh->sf.has_uv;
    /* the footprint where a texture reads it or a mirror's or glass's rays carry it on */
    sh->rd = optional && (textured || material_reflects(m) || material_dielectric(m)) ? rd : NULL;
    sh->t = hit->t;
    TexFootprint fp;
    if (sh->rd) {
        raydiff_at(rd, r->dir, hit->t, sh->sf.ng, &sh->dpdx, &sh->dpdy);
        trace_surface_change(w, hit, &sh->sf, sh->dpdx, sh->dpdy, &fp, &sh->dndx, &sh->dndy);
    }
    if (optional && world_uses(w, FEAT_CHECKER) && material_checkered(m))
        sh->kd = material_checker(m, sh->kd, sh->sf.p, sh->sf.u, sh->sf.v, sh->sf.has_uv);
    if (textured)
        sh->kd = v3_mul(sh->kd, texture_sample(sh->sf.tex, sh->sf.u, sh->sf.v, sh->rd ? &fp : NULL, w->view.settings.filter));
    sh->col = v3_mul(w->ambient, sh->kd);
    sh->view = v3_neg(v3_norm(r->dir));
    sh->phong = w->view.settings.shading == SHADE_PHONG && v3_max_comp(m->ks) > R(0);
    sh->origin = sh->sf.p;
    if (world_has(w, FEAT_SHADOWS)) /* every light ray leaves on the viewer's side, a smooth triangle's from its
                                     * point lifted onto the curved surface (trace_terminator_point) */
        sh->origin = trace_offset_origin(sh->sf.ps, sh->sf.ng, sh->sf.ps_err);
    sh->lit = 0;
    sh->disc.of = 0;
    sh->id = (SampleId){.key = 0, .index = 0, .count = 1};
    if (optional)
        sh->irr = w->ambient;
}

/* Shadow rays through dielectrics: at most this many surfaces crossed. */
#define GLASS_MAX_CROSSINGS 32

static vec3 beer_lambert(vec3 absorb, real t)
{
    return v3(exp(-absorb.x * t), exp(-absorb.y * t), exp(-absorb.z * t));
}

/* What of a light's radiance passes along shadow ray sr (blocked by the
 * any-hit test): the product of the transmitted colours (and absorption)
 * of the dielectrics it crosses before tmax, 0 at anything opaque. */
static vec3 transmittance(const World *w, const Ray *sr, real tmax, const WorldLight *l, RayStats *stats)
{
    vec3 T = v3_splat(R(1));
    Ray r = *sr;
    real left = tmax;
    for (int i = 0; i < GLASS_MAX_CROSSINGS; i++) {
        Hit h;
        r.tmax = left;
        if (!trace_closest(w, &r, &h))
            return T;
        Surface sf;
        trace_surface(w, &r, &h, &sf);
        const int lamp = trace_lamp_part(w, l, &h); /* the light's own lamp: passed, untinted */
        if (!lamp && !material_dielectric(sf.mat))
            break;
        if (!lamp)
            T = v3_mul(T, sf.mat->kt);
        if (!lamp && sf.inside && v3_max_comp(sf.mat->absorb) > R(0))
            T = v3_mul(T, beer_lambert(sf.mat->absorb, h.t));
        if (!(v3_max_comp(T) > R(0)))
            break;
        /* on through the surface: from just past it, the rest of the way */
        left = left == REAL_MAX ? left : left - h.t;
        stats->shadow++;
        ray_set(&r, trace_offset_origin(sf.p, v3_neg(sf.ng), sf.err), r.dir, r.inv, R(0), left);
    }
    return v3_splat(R(0));
}

static void shade_rays(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                       const SampleId *ids, const RayDiff *diffs, int depth, vec3 weight);

/* The colour seen along a secondary ray from org in unit direction d
 * (id: its sample; rd: its differentials, or NULL). */
static vec3 shade_secondary(const World *w, vec3 org, vec3 d, SampleId id, const RayDiff *rd, int depth, vec3 weight,
                            RayStats *stats)
{
    Ray r = ray_make(org, d, R(0), REAL_INF);
    vec3 c;
    stats->secondary++;
    shade_rays(w, &r, 1, &c, stats, NULL, &id, rd, depth, weight);
    return c;
}

/* A mirrored or refracted ray's sample: the same ray of its pixel, its key
 * mixed with which it is (1 reflected, 2 refracted). */
static SampleId follow(const SampleId *id, uint32_t which)
{
    /* no probe after a bounce: a reflected penumbra takes all its points */
    SampleId c = {.key = sample_mix(id->key, which), .index = id->index, .count = id->count};
    return c;
}

/* The differentials of the mirrored ray, where the ray has them. */
static const RayDiff *reflected_diff(const Shading *sh, vec3 d, RayDiff *out)
{
    if (!sh->rd)
        return NULL;
    *out = raydiff_reflect(sh->rd, d, sh->sf.ns, sh->dndx, sh->dndy, sh->dpdx, sh->dpdy);
    raydiff_carry(out, sh->rd, sh->t);
    return out;
}

/* A rough mirror: rays about the mirror direction r, each bent by a
 * stratified point of a sphere of radius `roughness` (a ray bent into the
 * surface is mirrored back out of it), each carrying its share.  Per
 * effect: rough_samples^2 rays; one budget: the ray's share of the
 * rough_samples^2 its pixel takes, each a ray of the pixel's count at the
 * next bounce (base/sample.h). */
static vec3 rough_reflection(const World *w, const Shading *sh, vec3 front, vec3 r, int depth, vec3 weight,
                             RayStats *stats)
{
    const Surface *sf = &sh->sf;
    const Material *m = sf->mat;
    const int product = w->view.settings.sampling == SAMPLING_PRODUCT;
    uint32_t k = (uint32_t)settings_rough_samples(&w->view.settings), n = product ? k * k : sample_share(k * k, sh->id.count);
    real share = R(1) / (real)n;
    vec3 wt = v3_scale(v3_mul(weight, m->kr), share), sum = v3_splat(0);
    uint32_t key = sample_mix(sh->id.key, 0x52000000u);
    RayDiff rd; /* the mirror's, its cone widened by each ray's share of the lobe */
    const RayDiff *rdp = reflected_diff(sh, v3_neg(sh->view), &rd);
    if (rdp)
        raydiff_lobe(&rd, sh->rd, sh->t, m->roughness, product ? n : sh->id.count * n);
    /* the rays leave one point into one lobe: traced as packets, each
     * colour what the ray gives alone, summed in order */
    Ray rays[TRACE_PACKET];
    SampleId child[TRACE_PACKET];
    RayDiff diff[TRACE_PACKET];
    vec3 col[TRACE_PACKET];
    uint32_t q = 0;
    for (uint32_t j = 0; j < n; j++) {
        real u, v;
        if (product) {
            sample_stratum(key, j, k, &u, &v);
            child[q] = (SampleId){.key = sample_mix(key, j), .index = 0, .count = 1};
        } else {
            child[q] = (SampleId){.key = key, .index = sh->id.index * n + j, .count = sh->id.count * n};
            sample_sobol2(child[q].index, key, &u, &v);
        }
        vec3 d = v3_norm(v3_madd(r, sample_sphere(u, v), m->roughness));
        real below = v3_dot(d, sf->ng);
        if (below <= R(0))
            d = v3_norm(v3_madd(d, sf->ng, R(-2) * below));
        rays[q] = ray_make(front, d, R(0), REAL_INF);
        if (rdp)
            diff[q] = *rdp;
        if (++q == TRACE_PACKET || j == n - 1) {
            stats->secondary += q;
            shade_rays(w, rays, (int)q, col, stats, NULL, child, rdp ? diff : NULL, depth + 1, wt);
            for (uint32_t i = 0; i < q; i++)
                sum = v3_add(sum, col[i]);
            q = 0;
        }
    }
    return v3_mul(m->kr, v3_scale(sum, share));
}

/* A secondary ray is traced when what it can add to the pixel is at least the cutoff. */
static int worth_tracing(const World *w, vec3 weight)
{
    real wt = v3_max_comp(weight);
    return wt > R(0) && wt >= w->view.settings.cutoff;
}

/* The mirror direction of unit d at the surface: about the shading normal,
 * or about the geometric one where a smooth normal would send it into the
 * surface. */
static vec3 reflected(vec3 d, const Surface *sf)
{
    vec3 r = optics_reflect(d, sf->ns);
    return v3_dot(r, sf->ng) > R(0) ? r : optics_reflect(d, sf->ng);
}

/* Emission, reflection, refraction and absorption at sh's hit (at
 * distance t along r), for a ray at bounce `depth` carrying `weight`. */
static vec3 shade_beyond(const World *w, real t, const Shading *sh, int depth, vec3 weight, RayStats *stats)
{
    const Surface *sf = &sh->sf;
    const Material *m = sf->mat;
    vec3 col = sh->col;
    if (world_uses(w, FEAT_EMIT))
        col = v3_add(col, m->ke);
    const int reflects = world_uses(w, FEAT_REFLECT) && material_reflects(m);
    const int refracts = world_uses(w, FEAT_REFRACT) && material_dielectric(m);
    if (depth >= w->view.settings.depth && (reflects || refracts) && w->view.settings.depth_limit != LIMIT_BLACK) {
        /* cut by the depth limit: what the untraced rays would carry, an
         * estimate of what they see times their weight */
        const DepthLimit lim = w->view.settings.depth_limit;
        vec3 seen = lim == LIMIT_BACKGROUND ? w->background : lim == LIMIT_AMBIENT ? w->ambient : sh->irr;
        if (reflects) {
            col = v3_add(col, v3_mul(m->kr, seen));
        } else {
            vec3 d = v3_neg(sh->view), td;
            real eta = sf->inside ? m->ior : R(1) / m->ior;
            real f = optics_fresnel(w->view.settings.fresnel, real_max(R(0), -v3_dot(d, sf->ns)), eta);
            if (f >= R(1) || !optics_refract(d, sf->ns, eta, &td) || !(v3_dot(td, sf->ng) < R(0)))
                f = R(1);
            col = v3_add(col, v3_mul(seen, v3_add(v3_splat(f), v3_scale(m->kt, R(1) - f))));
        }
    } else if (depth < w->view.settings.depth && (reflects || refracts)) {
        vec3 d = v3_neg(sh->view);
        /* a reflected ray leaves on the side the ray came from, a refracted one on the other */
        vec3 front = trace_offset_origin(sf->p, sf->ng, sf->err);
        RayDiff rrd, trd;
        const RayDiff *rdp = reflected_diff(sh, d, &rrd);
        if (reflects) {
            vec3 wt = v3_mul(weight, m->kr);
            if (!worth_tracing(w, wt))
                ;
            else if (world_uses(w, FEAT_ROUGH) && m->roughness > R(0))
                col = v3_add(col, rough_reflection(w, sh, front, reflected(d, sf), depth, weight, stats));
            else
                col = v3_add(col, v3_mul(m->kr, shade_secondary(w, front, reflected(d, sf), follow(&sh->id, 1), rdp,
                                                                depth + 1, wt, stats)));
        } else {
            real eta = sf->inside ? m->ior : R(1) / m->ior;
            real cos_i = real_max(R(0), -v3_dot(d, sf->ns));
            real f = optics_fresnel(w->view.settings.fresnel, cos_i, eta);
            vec3 td = v3_splat(0);
            /* past the critical angle, or bent back through the facet by a
             * smooth normal: everything is reflected */
            if (f >= R(1) || !optics_refract(d, sf->ns, eta, &td) || !(v3_dot(td, sf->ng) < R(0)))
                f = R(1);
            vec3 wr = v3_scale(weight, f);
            if (worth_tracing(w, wr))
                col = v3_add(col, v3_scale(shade_secondary(w, front, reflected(d, sf), follow(&sh->id, 1), rdp,
                                                           depth + 1, wr, stats),
                                           f));
            vec3 kt = v3_scale(m->kt, R(1) - f);
            vec3 wt = v3_mul(weight, kt);
            if (f < R(1) && worth_tracing(w, wt)) {
                vec3 back = trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err);
                const RayDiff *tdp = NULL;
                if (sh->rd) {
                    trd = raydiff_refract(sh->rd, d, sf->ns, eta, sh->dndx, sh->dndy, sh->dpdx, sh->dpdy);
                    raydiff_carry(&trd, sh->rd, sh->t);
                    tdp = &trd;
                }
                col = v3_add(col, v3_mul(kt, shade_secondary(w, back, v3_norm(td), follow(&sh->id, 2), tdp, depth + 1,
                                                             wt, stats)));
            }
        }
    }
    /* the ray crossed this dielectric's inside to get here */
    if (world_uses(w, FEAT_REFRACT) && sf->inside && material_dielectric(m) && v3_max_comp(m->absorb) > R(0))
        col = v3_mul(col, beer_lambert(m->absorb, t));
    return col;
}

/* The shadow ray from h's hit towards a light dist away along unit L,
 * stopping just short of the light so that it does not shadow itself:
 * its tmax. */
static inline real shadow_ray(const Shading *h, vec3 L, real dist, Ray *sr)
{
    const real tmax = isfinite(dist) ? dist * (R(1) - R(64) * REAL_EPS) : REAL_MAX;
    ray_set(sr, h->origin, L, v3(R(1) / L.x, R(1) / L.y, R(1) / L.z), R(0), tmax);
    return tmax;
}

/* Adaptive light sampling's probes of area light li: from the hit of each
 * live ray that probes (the first pass's camera rays), shadow rays to the
 * strata s = i, i + 9, i + 18, ... of the light's k x k, i being its
 * pixel's place in its 3 x 3 block: every block of 3 x 3 pixels probes
 * every stratum once (interleaved sampling), a pixel one stratum of a
 * light of 3 x 3 or less, two of 4 x 4, at most eight of 8 x 8.  Bit k of
 * *probed: live ray k's probes agreed, and bit k of *clear, that the light
 * reaches it; that ray then takes all its points of the light without
 * shadow rays, the same light as with them where they would all pass, or
 * none.  A ray whose probes disagree, or one of whose probe points lies
 * behind its surface, or is tinted by glass, takes its points with their
 * shadow rays. */
static void probe_pass(const World *w, Shading *sh, const int *live, int nl, uint32_t li, uint32_t *probed,
                       uint32_t *clear, RayStats *stats)
{
    const WorldLight *l = &w->lights[li];
    const uint32_t k = (uint32_t)(l->samples * l->samples);
    const int glass = world_uses(w, FEAT_REFRACT) && w->view.settings.glass_shadows;
    uint32_t asked = 0, seen_clear = 0, seen_blocked = 0, unsure = 0;
    for (uint32_t round = 0; round * 9 < k; round++) {
        Ray sr[TRACE_PACKET];
        real tmax[TRACE_PACKET];
        int who[TRACE_PACKET], m = 0;
        for (int q = 0; q < nl; q++) {
            Shading *h = &sh[live[q]];
            const uint32_t s = h->id.px % 3 + 3 * (h->id.py % 3) + 9 * round;
            if (!h->id.probe || s >= k || (unsure >> q & 1))
                continue;
            asked |= 1u << q;
            vec3 L, rad;
            real dist;
            if (!light_at(w, l, h->sf.p, &h->id, &h->disc, li, PROBE_POINT + s, &L, &dist, &rad, 1) ||
                !(v3_dot(h->sf.ns, L) > R(0))) {
                unsure |= 1u << q;
                continue;
            }
            tmax[m] = shadow_ray(h, L, dist, &sr[m]);
            who[m++] = q;
        }
        if (m == 0)
            continue;
        stats->shadow += (uint64_t)m;
        uint32_t blocked =
            m == 1 ? (uint32_t)trace_occluded(w, &sr[0], tmax[0], l) : trace_occluded_packet(w, sr, m, tmax, l);
        for (int q = 0; q < m; q++) {
            const uint32_t bit = 1u << who[q];
            if (!(blocked >> q & 1))
                seen_clear |= bit;
            else if (glass && v3_max_comp(transmittance(w, &sr[q], tmax[q], l, stats)) > R(0))
                unsure |= bit; /* through glass: tinted, not a yes or no */
            else
                seen_blocked |= bit;
        }
    }
    *probed = asked & ~unsure & ~(seen_clear & seen_blocked);
    *clear = *probed & seen_clear;
}

/* Light li (for an area light, its point j) at the live rays' hits: the
 * shadow rays as one packet, and what reaches each hit added to it; the
 * rays whose probe decided (probe_pass) take the light as it said. */
static inline __attribute__((always_inline)) void light_pass(const World *w, Shading *sh, const int *live, int nl,
                                                             uint32_t li, uint32_t j, uint32_t probed, uint32_t clear,
                                                             RayStats *stats, const int optional)
{
    const int shadows = world_has(w, FEAT_SHADOWS);
    const int glass_shadows = optional && world_uses(w, FEAT_REFRACT) && w->view.settings.glass_shadows;
    /* the light at the point, for a ray the depth limit cuts there */
    const int track = optional && world_uses(w, FEAT_REFLECT | FEAT_REFRACT) && w->view.settings.depth_limit == LIMIT_LOCAL;
    const WorldLight *l = &w->lights[li];
    Ray sr[TRACE_PACKET];
    real tmax[TRACE_PACKET];
    vec3 L[TRACE_PACKET], rad[TRACE_PACKET];
    real ndotl[TRACE_PACKET];
    int who[TRACE_PACKET], m = 0;
    for (int k = 0; k < nl; k++) {
        Shading *h = &sh[live[k]];
        real dist;
        if (!light_at(w, l, h->sf.p, &h->id, &h->disc, li, j, &L[m], &dist, &rad[m], optional))
            continue;
        /* The shading normal decides.  On a flat surface it is the
         * geometric one, so a light behind the surface is skipped.  On a
         * smooth triangle near the boundary between light and dark, a
         * light may be behind the flat facet but in front of the curved
         * surface its normals describe: it lights the point, and the
         * shadow ray from the lifted point says whether anything is in
         * the way.  (Skipping lights behind the facet cut triangle-shaped
         * dark patches into coarse smooth meshes: tests/test_render.c,
         * the shadow terminator.) */
        ndotl[m] = v3_dot(h->sf.ns, L[m]);
        if (ndotl[m] <= R(0))
            continue;
        if (!shadows || (probed >> k & 1)) {
            if (shadows && !(clear >> k & 1))
                continue;
            add_light(h, L[m], rad[m], ndotl[m], li);
            if (track)
                h->irr = v3_madd(h->irr, rad[m], ndotl[m]);
            continue;
        }
        tmax[m] = shadow_ray(h, L[m], dist, &sr[m]);
        who[m++] = live[k];
    }
    if (m == 0)
        return;
    stats->shadow += (uint64_t)m;
    uint32_t blocked =
        m == 1 ? (uint32_t)trace_occluded(w, &sr[0], tmax[0], l) : trace_occluded_packet(w, sr, m, tmax, l);
    for (int k = 0; k < m; k++) {
        vec3 got = rad[k];
        if (blocked >> k & 1) {
            got = glass_shadows ? v3_mul(rad[k], transmittance(w, &sr[k], tmax[k], l, stats)) : v3_splat(0);
            if (!(v3_max_comp(got) > R(0)))
                continue;
        }
        add_light(&sh[who[k]], L[k], got, ndotl[k], li);
        if (track)
            sh[who[k]].irr = v3_madd(sh[who[k]].irr, got, ndotl[k]);
    }
}

void shade_packet(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                  const SampleId *ids, const RayDiff *diffs)
{
    if (w->view.settings.integrator == INTEGRATOR_PATH) {
        for (int i = 0; i < n; i++)
            out[i] = path_radiance(w, &rays[i], ids ? ids[i] : (SampleId){.key = 0, .index = 0, .count = 1}, stats,
                                   keys ? &keys[i] : NULL);
        return;
    }
    shade_rays(w, rays, n, out, stats, keys, ids, diffs, 0, v3_splat(R(1)));
}

/* shade_rays' body; `optional` (a constant in each copy) lets in the paths
 * of the features a scene may use beyond point lights, shadows and Phong. */
static inline __attribute__((always_inline)) void shade_rays_at(const World *w, const Ray *rays, int n, vec3 *out,
                                                                RayStats *stats, uint64_t *keys, const SampleId *ids,
                                                                const RayDiff *diffs, int depth, vec3 weight,
                                                                const int optional)
{
    Hit hits[TRACE_PACKET];
    Shading sh[TRACE_PACKET];
    int live[TRACE_PACKET], nl = 0;
    if (n == 1)
        trace_closest(w, &rays[0], &hits[0]);
    else
        trace_closest_packet(w, rays, n, hits);
    if (depth == 0)
        stats->primary += (uint64_t)n;
    /* the hit triangles' vertices, for every ray at once: on a big model
     * each is a cache miss, and waiting for them one by one showed */
    for (int i = 0; i < n; i++)
        if (hits[i].kind == HIT_INSTANCE)
            __builtin_prefetch(&w->models[w->instances[hits[i].index].model]->tris[hits[i].sub]);
    for (int i = 0; i < n; i++) {
        if (hits[i].kind == HIT_NONE) {
            out[i] = w->background;
            if (keys)
                keys[i] = UINT64_MAX;
            continue;
        }
        shade_start(w, &rays[i], &hits[i], &sh[i], diffs ? &diffs[i] : NULL, optional);
        live[nl++] = i;
    }
    /* a random key only where something draws from it (hashing every ray's
     * showed in the instruction count of scenes without) */
    if (optional && world_uses(w, FEAT_AREA | FEAT_ROUGH))
        for (int k = 0; k < nl; k++) {
            const SampleId id = ids ? ids[live[k]] : (SampleId){.key = 0, .index = 0, .count = 1};
            sh[live[k]].id = id;
            sh[live[k]].id.key = sample_mix(id.key, (uint32_t)depth);
        }
    for (uint32_t li = 0; li < w->light_count; li++) {
        const WorldLight *l = &w->lights[li];
        uint32_t points = 1, probed = 0, clear = 0;
        if (optional && world_uses(w, FEAT_AREA) && world_light_is_area(l)) {
            if (w->view.settings.light_sampling == LIGHTS_ADAPTIVE && depth == 0 && l->samples > 1)
                probe_pass(w, sh, live, nl, li, &probed, &clear, stats);
            /* per effect, every ray all of the light's points; one budget,
             * each ray its share (the most of the packet's rays) */
            const uint32_t k = (uint32_t)(l->samples * l->samples);
            const int product = w->view.settings.sampling == SAMPLING_PRODUCT;
            points = 0;
            for (int q = 0; q < nl && points < k; q++) {
                const SampleId *id = &sh[live[q]].id;
                uint32_t m = product ? k : sample_share(k, id->count);
                points = m > points ? m : points;
            }
        }
        for (uint32_t j = 0; j < points; j++)
            light_pass(w, sh, live, nl, li, j, probed, clear, stats, optional);
    }
    const int beyond = optional && world_uses(w, FEAT_REFLECT | FEAT_REFRACT | FEAT_EMIT);
    for (int k = 0; k < nl; k++) {
        int i = live[k];
        out[i] = beyond ? shade_beyond(w, hits[i].t, &sh[i], depth, weight, stats) : sh[i].col;
        if (keys)
            keys[i] = (uint64_t)sh[i].sf.object << 16 | sh[i].lit;
    }
}

/* The features whose paths the shading asks about; a scene using none of
 * them (point lights, shadows, Phong or diffuse: make bench's scenes)
 * takes a copy without those paths.  In the one body, their tests and the
 * bigger function's registers cost a flat hit 50 instructions more than a
 * build with the features compiled out. */
#define SHADE_OPTIONAL (FEAT_TEXTURES | FEAT_COLOURS | FEAT_SPOT | FEAT_ATTENUATION | FEAT_REFLECT | FEAT_REFRACT | \
                        FEAT_EMIT | FEAT_AREA | FEAT_ROUGH | FEAT_CHECKER)

static void shade_rays(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                       const SampleId *ids, const RayDiff *diffs, int depth, vec3 weight)
{
    if (world_uses(w, SHADE_OPTIONAL))
        shade_rays_at(w, rays, n, out, stats, keys, ids, diffs, depth, weight, 1);
    else
        shade_rays_at(w, rays, n, out, stats, keys, ids, NULL, depth, weight, 0);
}

vec3 shade_ray(const World *w, const Ray *r, RayStats *stats, uint64_t *key)
{
    vec3 c;
    shade_rays(w, r, 1, &c, stats, key, NULL, NULL, 0, v3_splat(R(1)));
    return c;
}
