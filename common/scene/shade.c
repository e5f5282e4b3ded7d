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
 * is below settings.cutoff.  A rough metal spreads its reflection over
 * rough_samples^2 rays drawn from its GGX lobe (frosted glass its
 * reflection and refraction), and an area light (a
 * sphere, a rectangle) is samples^2 shadow rays to stratified points of it:
 * soft shadows.  Their random numbers come from the ray's key (the pixel
 * sample's, base/sample.h), mixed with the bounce and what they are drawn
 * for: any client renders any pixel the same. */
#include "scene/shade.h"

#include "base/dmath.h"
#include "scene/dielectric.h"
#include "scene/path.h"
#include "shading/ggx.h"
#include "shading/lobes.h"

#include "base/sample.h"
#include "base/sample_lanes.h"
#include "geom/raydiff.h"

/* What a ray's points of one area light share, kept for the light's next
 * point: the axes of the disc a sphere light shows the shading point (a
 * profile of adaptive light sampling, which takes every point without its
 * shadow ray, had a sixth of the time in making them again), and the
 * ray's key for the light and its sequence (the hashes of each point
 * took a tenth of the default scene's frame). */
typedef struct {
    vec3 a, b;
    uint32_t of;     /* 1 + the light the axes are of; 0: none yet */
    uint32_t key_of; /* 1 + the light key and seq are of; 0: none yet */
    uint32_t key;
    SampleSobol seq;
} DiscAxes;

/* The point (u, v) of the unit square on area light li, l, as seen from p:
 * a rectangle's point, or a sphere's on the disc it shows p. */
static inline __attribute__((always_inline)) vec3 area_point(const WorldLight *l, uint32_t li, vec3 p, real u, real v, DiscAxes *ax)
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
 * (base/sample.h).  2 where (u, v) is the point *index of ax->seq, left to
 * the caller (sample_sobol_point, or eight rays' at once: light_uvs). */
static inline int area_plan(const World *w, const WorldLight *l, uint32_t li, const SampleId *id, DiscAxes *ax,
                            uint32_t j, real *u, real *v, real *share, uint32_t *index)
{
    const uint32_t side = (uint32_t)world_light_side(w, l), k = side * side;
    /* a pixel's one point of the light (one ray a pixel, one point a ray):
     * a sequence of one point is any uniform point, two hashes of the key
     * where the scrambled Sobol point cost five times as much (a twentieth
     * of models/example.scene's frame at one sample a pixel) */
    const int single = id->count == 1 && k == 1;
    if (ax->key_of != li + 1) {
        ax->key = sample_mix(id->key, 0x4c000000u + li);
        if (!single)
            ax->seq = sample_sobol_seq(ax->key);
        ax->key_of = li + 1;
    }
    const uint32_t key = ax->key;
    if (j >= PROBE_POINT) { /* adaptive light sampling's probe: a stratum of the light */
        sample_stratum(key, j - PROBE_POINT, side, u, v);
        *share = R(1);
        return 1;
    }
    if (single || w->view.settings.sampling == SAMPLING_PRODUCT) {
        sample_stratum(key, j, side, u, v);
        *share = R(1) / (real)k;
        return 1;
    }
    const uint32_t m = sample_share(k, id->count);
    if (j >= m)
        return 0;
    *index = id->index * m + j;
    *share = R(1) / (real)m;
    return 2;
}

static inline int area_sample(const World *w, const WorldLight *l, uint32_t li, const SampleId *id, DiscAxes *ax,
                              uint32_t j, real *u, real *v, real *share)
{
    uint32_t index;
    const int got = area_plan(w, l, li, id, ax, j, u, v, share, &index);
    if (got == 2)
        sample_sobol_point(&ax->seq, index, u, v);
    return got != 0;
}

/* What of `scale` times a light's intensity arrives along unit dir from
 * a point d2 away (squared) of light l (not a directional one):
 * attenuated, a spot's cone, a rectangle's cosine; 0 or less where none. */
static inline __attribute__((always_inline)) real light_falloff(const World *w, const WorldLight *l, vec3 dir, real d2,
                                                               real scale, const int optional)
{
    if (optional && world_uses(w, FEAT_ATTENUATION) && l->attenuate)
        scale /= d2;
    if (optional && world_uses(w, FEAT_SPOT) && l->kind == LIGHT_SPOT) {
        real c = -v3_dot(dir, l->axis);
        if (c <= l->cos_outer)
            return R(0);
        if (c < l->cos_inner) { /* soft edge: smoothstep across the rim */
            real t = (c - l->cos_outer) / (l->cos_inner - l->cos_outer);
            scale *= t * t * (R(3) - R(2) * t);
        }
    }
    if (optional && world_uses(w, FEAT_AREA) && l->kind == LIGHT_RECT)
        scale *= fabs(v3_dot(dir, l->axis));
    return scale;
}

/* Light arriving at p from light l at pos (its position; an area light's
 * point), `scale` times its intensity so far: unit direction towards the
 * light, its distance (infinite for directional lights) and the radiance
 * arriving (colour x intensity, light_falloff); 0 where none arrives. */
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
        scale = light_falloff(w, l, *dir, d2, scale, optional);
    }
    if (!(scale > R(0)))
        return 0;
    *radiance = v3_scale(l->color, scale);
    return 1;
}

/* Where light l, number li, is for p (not a directional light): its
 * position, or for an area light its point j for the ray's sample id, and
 * the share of its intensity there; 0 where the ray takes no point j. */
static inline __attribute__((always_inline)) int light_pos(const World *w, const WorldLight *l, vec3 p, const SampleId *id,
                                                          DiscAxes *ax, uint32_t li, uint32_t j, vec3 *pos, real *scale,
                                                          const int optional)
{
    *scale = l->intensity;
    *pos = l->pos;
    if (optional && world_uses(w, FEAT_AREA) && world_light_is_area(l)) {
        real u, v, share;
        if (!area_sample(w, l, li, id, ax, j, &u, &v, &share))
            return 0;
        *pos = area_point(l, li, p, u, v, ax);
        *scale *= share;
    }
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
    if (l->kind != LIGHT_DIRECTIONAL && !light_pos(w, l, p, id, ax, li, j, &pos, &scale, optional))
        return 0;
    return light_towards(w, l, pos, p, scale, dir, dist, radiance, optional);
}

int shade_light_point(const World *w, uint32_t li, const vec3 *pp, real u, real v, vec3 *dir, real *dist,
                      vec3 *radiance)
{
    const vec3 p = *pp;
    const WorldLight *l = &w->lights[li];
    DiscAxes ax = {.of = 0, .key_of = 0};
    vec3 pos = world_light_is_area(l) ? area_point(l, li, p, u, v, &ax) : l->pos;
    return light_towards(w, l, pos, p, l->intensity, dir, dist, radiance, 1);
}

/* What one camera ray's shading carries from light to light. */
typedef struct {
    Surface sf;
    vec3 kd, col, view, origin, origin_ps; /* where light rays leave: off p, and a smooth triangle's off ps */
    vec3 ke; /* what the surface emits here (trace_emission) */
    int phong;
    /* a rough mirror's GGX width, colour and rim (rough_reflection's), and
     * whether its lobe is the lights' highlight (a rough metal without a
     * Phong highlight: the path integrator's) */
    int rough_metal;
    real metal_alpha;
    vec3 metal_kr, metal_kme;
    real coat;     /* a clear coat's share of the light here (dielectric_coat_share), 0 without one */
    real coat_alpha; /* and its GGX width */
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

/* Light l's contribution to ray sh, already known to reach it (`optional`
 * as shade_rays_at's: a coat's highlight only where the world has coats). */
static inline __attribute__((always_inline)) void add_light(Shading *sh, vec3 L, vec3 rad, real ndotl, uint32_t i,
                                                            const int optional)
{
    sh->lit |= i < 16 ? 1u << i : 0;
    const real shadowing = optional && sh->sf.bumped ? lobes_bump_shadowing(sh->sf.nv, sh->sf.ns, L) : R(1);
    sh->col = v3_add(sh->col, v3_scale(v3_mul(sh->kd, rad), ndotl * shadowing));
    if (sh->phong) {
        real rv = v3_dot(v3_reflect(v3_neg(L), sh->sf.ns), sh->view);
        if (rv > R(0)) /* under a coat, what it lets through */
            sh->col = v3_add(sh->col, v3_scale(v3_mul(sh->sf.mat->ks, rad),
                                               dmath_powr(rv, sh->sf.mat->shininess) * (optional ? R(1) - sh->coat : R(1))));
    }
    if (optional && sh->rough_metal) { /* a rough metal's: its GGX lobe, as its rays' (rough_reflection) */
        real pdf;
        const real f = ggx_eval(sh->sf.ns, sh->view, L, sh->metal_alpha, &pdf) * REAL_PI * (R(1) - sh->coat);
        vec3 k = sh->metal_kr;
        if (material_edged(sh->sf.mat))
            k = v3_add(k, v3_scale(sh->metal_kme, ggx_schlick_gain(sh->view, L)));
        sh->col = v3_add(sh->col, v3_scale(v3_mul(k, rad), f));
    }
    if (optional && sh->coat > R(0)) { /* the coat's highlight: the path integrator's GGX lobe (lobes.h) */
        real pdf;
        const real f = ggx_eval(sh->sf.ns, sh->view, L, sh->coat_alpha, &pdf);
        sh->col = v3_add(sh->col, v3_scale(rad, sh->coat * REAL_PI * f));
    }
}

static inline __attribute__((always_inline)) void shade_start(const World *w, const Ray *r, const Hit *hit,
                                                              Shading *sh, const RayDiff *rd, const int optional)
{
    trace_surface(w, r, hit, &sh->sf);
    const Material *m = sh->sf.mat; /* a mapped metal's as the file gives it, until its texel is read */
    const int textured = optional && world_uses(w, FEAT_TEXTURES) && sh->sf.tex && sh->sf.has_uv;
    /* the footprint where a texture reads it or a mirror's or glass's rays carry it on (a
     * mapped metal reflects: its factor's share, kr, is the texels' most) */
    const int checker = optional && world_uses(w, FEAT_CHECKER) && material_checkered(m);
    sh->rd = optional && (textured || sh->sf.etex || sh->sf.nmap || sh->sf.aotex || material_reflects(m) ||
                          material_dielectric(m) || material_coats(m) || checker)
                 ? rd
                 : NULL;
    sh->t = hit->t;
    TexFootprint fp;
    if (sh->rd) {
        raydiff_at(rd, r->dir, hit->t, sh->sf.ng, &sh->dpdx, &sh->dpdy);
        trace_surface_change(w, hit, &sh->sf, sh->dpdx, sh->dpdy, &fp, &sh->dndx, &sh->dndy);
    }
    if (optional) { /* the data maps over the footprint: the far-off ones' means, not one texel */
        trace_surface_bump(&sh->sf, sh->rd ? &fp : NULL);
        trace_surface_metal(w, &sh->sf, sh->rd ? &fp : NULL);
        trace_surface_blend(&sh->sf);
        m = sh->sf.mat;
    }
    sh->kd = optional && world_uses(w, FEAT_COLOURS) && sh->sf.has_colour ? sh->sf.colour : m->kd;
    if (checker && sh->rd && w->view.settings.filter != FILTER_NEAREST) /* over the sample's footprint */
        sh->kd = material_checker_box(m, sh->kd, sh->sf.p, sh->sf.u, sh->sf.v, sh->sf.has_uv,
                                      m->checker_uv ? v3(fabs(fp.dudx) + fabs(fp.dudy), fabs(fp.dvdx) + fabs(fp.dvdy), 0)
                                                    : v3_add(v3_abs(sh->dpdx), v3_abs(sh->dpdy)));
    else if (checker)
        sh->kd = material_checker(m, sh->kd, sh->sf.p, sh->sf.u, sh->sf.v, sh->sf.has_uv);
    if (textured)
        sh->kd = v3_mul(sh->kd, trace_surface_texel(w, &sh->sf, sh->rd ? &fp : NULL));
    sh->view = v3_neg(v3_norm(r->dir));
    sh->coat = R(0);
    if (optional && world_uses(w, FEAT_COAT) && material_coats(m) && w->view.settings.shading == SHADE_PHONG) {
        sh->coat = dielectric_coat_share(w, &sh->sf, sh->view);
        sh->coat_alpha = ggx_alpha(m->coat_roughness);
        sh->kd = v3_scale(sh->kd, R(1) - sh->coat); /* what the coat lets through */
    }
    if (world_uses(w, FEAT_EMIT))
        sh->ke = optional && sh->sf.etex ? trace_emission(w, &sh->sf, sh->rd ? &fp : NULL) : m->ke;
    /* the light from everywhere: the ambient, and an environment's at the normal */
    const vec3 amb = w->env ? v3_add(w->ambient, environment_diffuse(w->env, sh->sf.ns)) : w->ambient;
    sh->col = v3_mul(amb, sh->kd);
    /* a rough coat reflects the light from everywhere that the ambient
     * light stands for (its reflected rays are the path integrator's); a
     * smooth one's ray brings what it sees.  Without it a coated white
     * surface lost its coat's share of the ambient light: dark rims, where
     * Fresnel's share nears 1 */
    if (optional && sh->coat > R(0) && !material_coat_smooth(m))
        sh->col = v3_add(sh->col, v3_scale(amb, sh->coat));
    if (optional && sh->sf.aotex) /* an occlusion texture: crevices take less of the ambient light */
        sh->col = v3_scale(sh->col, trace_occlusion(&sh->sf, sh->rd ? &fp : NULL));
    sh->phong = w->view.settings.shading == SHADE_PHONG && v3_max_comp(m->ks) > R(0);
    /* a rough mirror's lobe, for its rays (rough_reflection) and, on a
     * metal without a Phong highlight of its own (`specular`: a scene's
     * that asks for one, an imported metal's keep it), for the lights */
    sh->rough_metal = 0;
    if (optional && world_uses(w, FEAT_ROUGH) && material_rough(m)) {
        sh->metal_alpha = ggx_alpha(m->roughness);
        sh->metal_kr = ggx_metal_of(m, v3_dot(sh->sf.ns, sh->view), &sh->metal_kme);
        sh->rough_metal = w->view.settings.shading == SHADE_PHONG && !material_dielectric(m) && !sh->phong;
    }
    sh->origin = sh->origin_ps = sh->sf.p;
    if (world_has(w, FEAT_SHADOWS)) { /* every light ray leaves on the viewer's side, a smooth triangle's towards
                                       * its point lifted onto the curved surface as the light grazes its facet
                                       * (trace_lift_share) */
        sh->origin = trace_offset_origin(sh->sf.p, sh->sf.ng, sh->sf.err);
        sh->origin_ps = sh->sf.smooth ? trace_offset_origin(sh->sf.ps, sh->sf.ng, sh->sf.ps_err) : sh->origin;
    }
    sh->lit = 0;
    sh->disc.of = 0;
    sh->disc.key_of = 0;
    sh->id = (SampleId){.key = 0, .index = 0, .count = 1};
    if (optional)
        sh->irr = amb;
}

/* Shadow rays through dielectrics: at most this many surfaces crossed. */
#define GLASS_MAX_CROSSINGS 32

vec3 shade_transmittance(const World *w, const Ray *sr, real tmax, const WorldLight *l, int nulls_only,
                         RayStats *stats)
{
    vec3 T = v3_splat(R(1));
    Ray r = *sr;
    real left = tmax;
    for (int i = 0; i < GLASS_MAX_CROSSINGS; i++) {
        Hit h;
        r.tmax = left;
        if (!trace_closest_glass(w, &r, &h))
            return T;
        Surface sf;
        trace_surface(w, &r, &h, &sf);
        trace_surface_blend(&sf); /* a blend's see-through share by its texel */
        const int lamp = l && trace_lamp_part(w, l, &h); /* the light's own lamp: passed, untinted */
        if (!lamp && (!material_dielectric(sf.mat) || (nulls_only && !material_null(sf.mat))))
            break;
        if (!lamp)
            T = v3_mul(T, sf.mat->kt);
        if (!lamp && sf.inside && v3_max_comp(sf.mat->absorb) > R(0))
            T = v3_mul(T, dielectric_absorbed(w, sf.mat, &h));
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
                       const SampleId *ids, const RayDiff *diffs, int depth, const vec3 *weights, int sunless,
                       Guide *guides);

/* A mirrored or refracted ray that a packet's hit sends: the ray `parent`
 * adds factor times what it sees.  The rays a packet sends are traced
 * together as packets of their own (a mirror's reflected rays from
 * neighbouring pixels stay coherent), their shadow rays too; each ray's
 * colour is what it finds alone, added to its parent in the order one
 * ray at a time added them. */
typedef struct {
    Ray ray;
    SampleId id;
    RayDiff rd;   /* its differentials, where has_rd */
    vec3 weight;  /* the most it can add to the pixel */
    vec3 factor;
    int parent, has_rd;
} Spawn;

/* At most a reflected and a refracted ray for each ray of a packet. */
#define SPAWN_MAX (2 * TRACE_PACKET)

static void spawn_push(Spawn *sp, int *ns, int parent, vec3 org, vec3 d, SampleId id, const RayDiff *rd, vec3 weight,
                       vec3 factor)
{
    Spawn *s = &sp[(*ns)++];
    ray_init(&s->ray, org, d, R(0), REAL_INF);
    s->id = id;
    s->has_rd = rd != NULL;
    if (rd)
        s->rd = *rd;
    s->weight = weight;
    s->factor = factor;
    s->parent = parent;
}

/* The ns spawned rays, TRACE_PACKET at a time at bounce depth + 1, what
 * each sees times its factor added to its parent's out. */
static void spawn_trace(const World *w, const Spawn *sp, int ns, vec3 *out, RayStats *stats, int depth)
{
    for (int first = 0; first < ns; first += TRACE_PACKET) {
        const int q = ns - first < TRACE_PACKET ? ns - first : TRACE_PACKET;
        Ray rays[TRACE_PACKET];
        SampleId ids[TRACE_PACKET];
        RayDiff diffs[TRACE_PACKET];
        vec3 wt[TRACE_PACKET], col[TRACE_PACKET];
        int all_rd = 1; /* one packet's rays all have differentials or none (their parents' came alike) */
        for (int k = 0; k < q; k++) {
            const Spawn *s = &sp[first + k];
            rays[k] = s->ray, ids[k] = s->id, wt[k] = s->weight;
            if (s->has_rd)
                diffs[k] = s->rd;
            all_rd &= s->has_rd;
        }
        stats->secondary += (uint64_t)q;
        shade_rays(w, rays, q, col, stats, NULL, ids, all_rd ? diffs : NULL, depth + 1, wt, 0, NULL);
        for (int k = 0; k < q; k++) {
            const Spawn *s = &sp[first + k];
            out[s->parent] = v3_add(out[s->parent], v3_mul(s->factor, col[k]));
        }
    }
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

/* How many rays a sampled surface effect (a rough mirror, frosted glass)
 * of rough_samples k a side traces from ray sh: per effect (*product) all
 * k x k, one budget sh's share of them. */
static uint32_t effect_rays(const World *w, const Shading *sh, uint32_t *k, int *product)
{
    *product = w->view.settings.sampling == SAMPLING_PRODUCT;
    *k = (uint32_t)settings_rough_samples(&w->view.settings);
    return *product ? *k * *k : sample_share(*k * *k, sh->id.count);
}

/* Ray j of those n: its point (u, v) of the unit square, stratum j of
 * k x k (product), or point sh->id.index x n + j of the pixel's sequence
 * for key (one budget); and its sample, a ray of the pixel's count at the
 * next bounce. */
static SampleId effect_sample(const Shading *sh, uint32_t key, uint32_t j, uint32_t k, uint32_t n, int product,
                              real *u, real *v)
{
    if (product) {
        sample_stratum(key, j, k, u, v);
        return (SampleId){.key = sample_mix(key, j), .index = 0, .count = 1};
    }
    const SampleId id = {.key = key, .index = sh->id.index * n + j, .count = sh->id.count * n};
    sample_sobol2(id.index, key, u, v);
    return id;
}

/* A rough mirror: rays drawn from its GGX lobe (shading/ggx.h: the
 * visible normals of a microfacet surface of its roughness, as the path
 * integrator's metal and Cycles' Glossy BSDF reflect), stratified, each
 * carrying its share times what the lobe keeps of it (G2 / G1: a ray
 * shadowed by the facets, or mirrored into the surface, keeps less or
 * nothing).  Per effect: rough_samples^2 rays; one budget: the ray's share
 * of the rough_samples^2 its pixel takes, each a ray of the pixel's count
 * at the next bounce (base/sample.h). */
static vec3 rough_reflection(const World *w, const Shading *sh, vec3 front, int depth, vec3 weight, RayStats *stats)
{
    const Surface *sf = &sh->sf;
    const Material *m = sf->mat;
    uint32_t k;
    int product;
    const uint32_t n = effect_rays(w, sh, &k, &product);
    real share = R(1) / (real)n;
    /* weighed for the light its facets pass between them (ggx_metal); an
     * edged metal's colour rises by kme x Schlick's weight at each ray's
     * facet (sume gathers what the rays bring times that weight) */
    const int edged = material_edged(m);
    const vec3 kr = sh->metal_kr, kme = sh->metal_kme; /* (shade_start's) */
    vec3 wt = v3_scale(v3_mul(weight, kr), share), sum = v3_splat(0), sume = v3_splat(0);
    uint32_t key = sample_mix(sh->id.key, 0x52000000u);
    RayDiff rd; /* the mirror's, its cone widened by each ray's share of the lobe */
    const RayDiff *rdp = reflected_diff(sh, v3_neg(sh->view), &rd);
    const real alpha = sh->metal_alpha;
    if (rdp) /* the reflected lobe is some 2 alpha wide */
        raydiff_lobe(&rd, sh->rd, sh->t, real_min(R(2) * alpha, R(1)), product ? n : sh->id.count * n);
    /* the rays leave one point into one lobe: traced as packets, each
     * colour what the ray gives alone, summed in order */
    Ray rays[TRACE_PACKET];
    SampleId child[TRACE_PACKET];
    RayDiff diff[TRACE_PACKET];
    vec3 col[TRACE_PACKET], wts[TRACE_PACKET];
    real keep[TRACE_PACKET], gain[TRACE_PACKET];
    uint32_t q = 0;
    for (uint32_t j = 0; j < n; j++) {
        real u, v;
        child[q] = effect_sample(sh, key, j, k, n, product, &u, &v);
        const vec3 d = ggx_sample(sf->ns, sh->view, alpha, u, v);
        real pdf;
        const real f = ggx_eval(sf->ns, sh->view, d, alpha, &pdf);
        if (f > R(0) && v3_dot(d, sf->ng) > R(0)) { /* else the ray brings nothing: not traced */
            keep[q] = f / pdf;
            wts[q] = v3_scale(wt, keep[q]);
            if (edged) {
                gain[q] = ggx_schlick_gain(sh->view, d);
                wts[q] = v3_add(wts[q], v3_scale(v3_mul(weight, kme), share * keep[q] * gain[q]));
            }
            ray_init(&rays[q], front, d, R(0), REAL_INF);
            if (rdp)
                diff[q] = *rdp;
            q++;
        }
        if (q == TRACE_PACKET || (j == n - 1 && q > 0)) {
            stats->secondary += q;
            shade_rays(w, rays, (int)q, col, stats, NULL, child, rdp ? diff : NULL, depth + 1, wts, 1, NULL);
            for (uint32_t i = 0; i < q; i++) {
                sum = v3_add(sum, v3_scale(col[i], keep[i]));
                if (edged)
                    sume = v3_add(sume, v3_scale(col[i], keep[i] * gain[i]));
            }
            q = 0;
        }
    }
    const vec3 out = v3_mul(kr, v3_scale(sum, share));
    return edged ? v3_add(out, v3_mul(kme, v3_scale(sume, share))) : out;
}

/* Frosted glass (material_frosted): rough_samples^2 facets drawn from
 * those its GGX lobe shows the ray (stratified, as rough_reflection's),
 * each reflecting (times fr, the share of Fresnel's reflection the
 * material keeps) or refracting (times the transmitted colour) by
 * Fresnel's share at it, chosen by a number of the facet's sample, and
 * keeping G2 / G1 of that: the path integrator's frosted glass.  One ray
 * a facet: tracing both, each ray of a ray's tree doubled at every glass
 * surface (a ball at depth 8, no cutoff: minutes for a 64x48 frame).  A
 * ray whose facet sends it to the wrong side of the surface brings
 * nothing.  The rays go on without differentials (what they see is
 * blurred). */
static vec3 frosted_glass(const World *w, const Shading *sh, real fr, int depth, vec3 weight, RayStats *stats)
{
    const Surface *sf = &sh->sf;
    const Material *m = sf->mat;
    uint32_t k;
    int product;
    const uint32_t n = effect_rays(w, sh, &k, &product);
    /* each facet's share, weighed for the light its facets pass between them */
    const real share = dielectric_frost_weight(sf, sh->view) / (real)n;
    const real alpha = ggx_alpha(m->roughness);
    const uint32_t key = sample_mix(sh->id.key, 0x46000000u);
    const vec3 d = v3_neg(sh->view), front = trace_offset_origin(sf->p, sf->ng, sf->err),
               back = trace_offset_origin(sf->p, v3_neg(sf->ng), sf->err);
    Ray rays[TRACE_PACKET];
    SampleId child[TRACE_PACKET];
    vec3 col[TRACE_PACKET], wts[TRACE_PACKET], kept[TRACE_PACKET], sum = v3_splat(R(0));
    uint32_t q = 0;
    for (uint32_t j = 0; j < n; j++) {
        real u, v;
        const SampleId id = effect_sample(sh, key, j, k, n, product, &u, &v);
        const vec3 facet = ggx_visible_normal(sf->ns, sh->view, alpha, u, v);
        real eta;
        vec3 td;
        const real f = dielectric_split_at(w, sf, facet, d, &eta, &td);
        if (sample_unit(sample_mix(id.key ^ id.index, 0x46u)) < f) { /* the facet's reflection */
            const vec3 r = v3_reflect(d, facet);
            if (fr > R(0) && v3_dot(r, sf->ng) > R(0)) {
                kept[q] = v3_splat(fr * ggx_keep(sf->ns, sh->view, r, alpha));
                ray_init(&rays[q], front, r, R(0), REAL_INF);
                child[q++] = follow(&id, 1);
            }
        } else { /* or its refraction */
            const vec3 t = v3_norm(td);
            kept[q] = v3_scale(m->kt, ggx_keep(sf->ns, sh->view, t, alpha));
            ray_init(&rays[q], back, t, R(0), REAL_INF);
            child[q++] = follow(&id, 2);
        }
        if (q == TRACE_PACKET || (j == n - 1 && q > 0)) {
            for (uint32_t i = 0; i < q; i++)
                wts[i] = v3_scale(v3_mul(weight, kept[i]), share);
            stats->secondary += q;
            shade_rays(w, rays, (int)q, col, stats, NULL, child, NULL, depth + 1, wts, 1, NULL);
            for (uint32_t i = 0; i < q; i++)
                sum = v3_add(sum, v3_mul(col[i], kept[i]));
            q = 0;
        }
    }
    return v3_scale(sum, share);
}

/* A secondary ray is traced when what it can add to the pixel is at least the cutoff. */
static int worth_tracing(const World *w, vec3 weight)
{
    real wt = v3_max_comp(weight);
    return wt > R(0) && wt >= w->view.settings.cutoff;
}

/* Emission, reflection and refraction at sh's hit, for ray `i` of its
 * packet at bounce `depth` carrying `weight`: the colour without what its
 * mirrored and refracted rays see, those rays pushed to sp (spawn_trace
 * adds what they see). */
static vec3 shade_beyond(const World *w, int i, const Shading *sh, int depth, vec3 weight, RayStats *stats, Spawn *sp,
                         int *ns)
{
    const Surface *sf = &sh->sf;
    const Material *m = sf->mat;
    vec3 col = sh->col;
    if (world_uses(w, FEAT_EMIT))
        col = v3_add(col, sh->ke);
    const int reflects = world_uses(w, FEAT_REFLECT) && material_reflects(m);
    const int refracts = world_uses(w, FEAT_REFRACT) && material_dielectric(m);
    /* a smooth coat's share is a mirror's (a rough one's reflection this
     * integrator leaves out: its highlight stands for it) */
    const real coat = world_uses(w, FEAT_COAT) && material_coat_smooth(m) ? sh->coat : R(0);
    const int mirrors = reflects || coat > R(0);
    /* a dielectric's Fresnel reflection keeps 1 - max(reflect) of its
     * strength: a mirror share (a glTF metal's over glass) takes the rest */
    /* the mirror's colour at this angle (an edged metal's rises towards its rim) */
    const vec3 kr = reflects ? material_mirror_at(m, v3_dot(sf->ns, sh->view)) : m->kr;
    const real fr = reflects ? real_max(R(0), R(1) - v3_max_comp(kr)) : R(1);
    if (depth >= w->view.settings.depth && (mirrors || refracts) && w->view.settings.depth_limit != LIMIT_BLACK) {
        /* cut by the depth limit: what the untraced rays would carry, an
         * estimate of what they see times their weight */
        const DepthLimit lim = w->view.settings.depth_limit;
        vec3 seen = lim == LIMIT_BACKGROUND ? w->background : lim == LIMIT_AMBIENT ? w->ambient : sh->irr;
        if (lim == LIMIT_BACKGROUND && w->env) { /* what the environment shows the reflected ray */
            const vec3 r = trace_reflected(v3_neg(sh->view), sf);
            seen = material_rough(m) ? environment_radiance_sunless(w->env, r) : environment_radiance(w->env, r);
        }
        if (reflects)
            col = v3_add(col, v3_scale(v3_mul(kr, seen), R(1) - sh->coat));
        if (coat > R(0))
            col = v3_add(col, v3_scale(seen, coat));
        if (refracts) {
            vec3 td;
            real eta;
            const real f = dielectric_split(w, sf, v3_neg(sh->view), &eta, &td);
            col = v3_add(col, v3_mul(seen, v3_add(v3_splat(f * fr), v3_scale(m->kt, R(1) - f))));
        }
    } else if (depth < w->view.settings.depth && (mirrors || refracts)) {
        vec3 d = v3_neg(sh->view);
        /* a reflected ray leaves on the side the ray came from, a refracted one on the other */
        vec3 front = trace_offset_origin(sf->p, sf->ng, sf->err);
        RayDiff rrd, trd;
        const RayDiff *rdp = reflected_diff(sh, d, &rrd);
        const int rough = reflects && world_uses(w, FEAT_ROUGH) && m->roughness > R(0);
        const real under = R(1) - sh->coat; /* what a coat lets through to the mirror */
        if (rough && worth_tracing(w, v3_mul(weight, v3_scale(kr, under))))
            col = v3_add(col, v3_scale(rough_reflection(w, sh, front, depth, weight, stats), under));
        real eta, f = R(0);
        vec3 td;
        const int frosted = refracts && material_frosted(m);
        if (frosted && worth_tracing(w, v3_mul(weight, v3_max(m->kt, v3_splat(fr)))))
            col = v3_add(col, frosted_glass(w, sh, fr, depth, weight, stats));
        if (refracts && !frosted)
            f = dielectric_split(w, sf, d, &eta, &td);
        /* one sharp reflected ray: the mirror's and the glass's shares */
        vec3 kref = reflects && !rough ? v3_scale(kr, under) : v3_splat(R(0));
        if (coat > R(0))
            kref = v3_add(kref, v3_splat(coat));
        if (refracts && !frosted)
            kref = v3_add(kref, v3_splat(f * fr));
        vec3 wr = v3_mul(weight, kref);
        if (worth_tracing(w, wr))
            spawn_push(sp, ns, i, front, trace_reflected(d, sf), follow(&sh->id, 1), rdp, wr, kref);
        if (refracts && !frosted) {
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
                spawn_push(sp, ns, i, back, v3_norm(td), follow(&sh->id, 2), tdp, wt, kt);
            }
        }
    }
    return col;
}

/* The shadow ray from h's hit towards a light dist away along unit L
 * (inv: its inverse, 1/L.x ...), stopping just short of the light so that
 * it does not shadow itself: its tmax. */
/* A smooth triangle's shadow-ray origin towards L (trace_lift_share):
 * apart, so that the flat surfaces' shadow rays stay inline. */
static __attribute__((noinline)) vec3 smooth_origin(const Shading *h, vec3 L)
{
    const real a = trace_lift_share(&h->sf, L);
    return a >= R(1) ? h->origin_ps : a > R(0) ? trace_lifted_origin(&h->sf, a) : h->origin;
}

static inline __attribute__((always_inline)) real shadow_ray_inv(const Shading *h, vec3 L, vec3 inv, real dist,
                                                                 Ray *sr)
{
    const real tmax = isfinite(dist) ? dist * (R(1) - R(64) * REAL_EPS) : REAL_MAX;
    ray_set(sr, h->sf.smooth ? smooth_origin(h, L) : h->origin, L, inv, R(0), tmax);
    return tmax;
}

static inline real shadow_ray(const Shading *h, vec3 L, real dist, Ray *sr)
{
    return shadow_ray_inv(h, L, v3(R(1) / L.x, R(1) / L.y, R(1) / L.z), dist, sr);
}

/* light_dirs' end: from the offsets (dx, dy, dz) of the lanes of `ok` to
 * their light's points, and the intensity there, light_towards' arithmetic
 * operation for operation, in arrays the compiler turns into vector code. */
static inline __attribute__((always_inline)) uint32_t light_dirs_towards(const World *w, const WorldLight *l, uint32_t ok,
                                                                        const real *dx, const real *dy, const real *dz,
                                                                        const real *sc, vec3 *L, real *dist, vec3 *inv,
                                                                        vec3 *rad, const int optional)
{
    real d2[TRACE_PACKET], ds[TRACE_PACKET], lx[TRACE_PACKET], ly[TRACE_PACKET], lz[TRACE_PACKET];
    real ix[TRACE_PACKET], iy[TRACE_PACKET], iz[TRACE_PACKET];
    for (int k = 0; k < TRACE_PACKET; k++) {
        d2[k] = dx[k] * dx[k] + dy[k] * dy[k] + dz[k] * dz[k];
        ds[k] = sqrt(d2[k]);
        const real r = R(1) / ds[k];
        lx[k] = dx[k] * r, ly[k] = dy[k] * r, lz[k] = dz[k] * r;
        ix[k] = R(1) / lx[k], iy[k] = R(1) / ly[k], iz[k] = R(1) / lz[k];
    }
    for (uint32_t m = ok; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        real scale = R(0);
        if (d2[k] > R(0)) {
            L[k] = v3(lx[k], ly[k], lz[k]);
            scale = light_falloff(w, l, L[k], d2[k], sc[k], optional);
        }
        if (!(scale > R(0))) {
            ok &= ~(1u << k);
            continue;
        }
        dist[k] = ds[k];
        inv[k] = v3(ix[k], iy[k], iz[k]);
        rad[k] = v3_scale(l->color, scale);
    }
    return ok;
}

_Static_assert(SAMPLE_LANES == TRACE_PACKET, "a packet's rays are the sampler's lanes");

/* Area light li's point j (area_sample) for the hits of the live rays:
 * the mask of lanes with one, (u, v) and the intensity there (sc), each
 * hit's position (p); lanes past nl something finite.  The lanes whose
 * point is a scrambled Sobol point get it eight at once
 * (sample_sobol_lanes: the chains of hashes side by side). */
static inline __attribute__((always_inline)) uint32_t light_uvs(const World *w, Shading *sh, const int *live, int nl,
                                                               uint32_t li, uint32_t j, real *u, real *v, real *sc,
                                                               real p[3][TRACE_PACKET])
{
    const WorldLight *l = &w->lights[li];
    SampleLanes sl;
    uint32_t ok = 0, sobol = 0;
    for (int k = 0; k < TRACE_PACKET; k++) {
        p[0][k] = p[1][k] = p[2][k] = R(0), u[k] = v[k] = R(0.5), sc[k] = R(0);
        sl.index[k] = sl.seq_index[k] = sl.seq_first[k] = sl.seq_second[k] = 0;
        if (k >= nl)
            continue;
        Shading *h = &sh[live[k]];
        real share;
        p[0][k] = h->sf.p.x, p[1][k] = h->sf.p.y, p[2][k] = h->sf.p.z;
        const int got = area_plan(w, l, li, &h->id, &h->disc, j, &u[k], &v[k], &share, &sl.index[k]);
        if (!got)
            continue;
        if (got == 2) {
            sl.seq_index[k] = h->disc.seq.index, sl.seq_first[k] = h->disc.seq.first;
            sl.seq_second[k] = h->disc.seq.second;
            sobol |= 1u << k;
        }
        ok |= 1u << k;
        sc[k] = l->intensity * share;
    }
    if (sobol) {
        sample_sobol_lanes(&sl);
        for (uint32_t m = sobol; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            u[k] = sample_unit(sl.u[k]), v[k] = sample_unit(sl.v[k]);
        }
    }
    return ok;
}

/* A rectangle light's points corner + u edge1 + v edge2 (area_point),
 * less the hits' positions p, lane by lane, into d. */
static inline __attribute__((always_inline)) void rect_offsets(const WorldLight *l, const real *u, const real *v,
                                                              real p[3][TRACE_PACKET], real d[3][TRACE_PACKET])
{
    for (int e = 0; e < 3; e++)
        for (int k = 0; k < TRACE_PACKET; k++)
            d[e][k] = l->pos.e[e] + (l->edge1.e[e] * u[k] + l->edge2.e[e] * v[k]) - p[e][k];
}

/* The disc axes (area_point's: v3_frame of the unit vector from the
 * sphere light's centre to the hit) of the hits p of the lanes of ok into
 * (ax, bx), lane by lane: those a ray keeps for light li read back, the
 * others made here and kept, as area_point keeps them, for the ray's next
 * point of the light. */
static inline __attribute__((always_inline)) void sphere_axes(const WorldLight *l, uint32_t li, Shading *sh,
                                                             const int *live, uint32_t ok, real p[3][TRACE_PACKET],
                                                             real ax[3][TRACE_PACKET], real bx[3][TRACE_PACKET])
{
    const real *px = p[0], *py = p[1], *pz = p[2];
    uint32_t fresh = 0; /* lanes whose disc axes are made here */
    for (int k = 0; k < TRACE_PACKET; k++) {
        for (int e = 0; e < 3; e++)
            ax[e][k] = bx[e][k] = R(0);
        if (!(ok >> k & 1))
            continue;
        const DiscAxes *d = &sh[live[k]].disc;
        if (d->of == li + 1)
            for (int e = 0; e < 3; e++)
                ax[e][k] = d->a.e[e], bx[e][k] = d->b.e[e];
        else
            fresh |= 1u << k;
    }
    if (!fresh)
        return;
    const real cx = l->pos.x, cy = l->pos.y, cz = l->pos.z;
    real fa[3][TRACE_PACKET], fb[3][TRACE_PACKET];
    for (int k = 0; k < TRACE_PACKET; k++) {
        /* w = v3_norm(p - centre) */
        real wx = px[k] - cx, wy = py[k] - cy, wz = pz[k] - cz;
        const real wl = sqrt(wx * wx + wy * wy + wz * wz), wi = R(1) / wl;
        const int wok = wl > R(0);
        wx = wok ? wx * wi : wx, wy = wok ? wy * wi : wy, wz = wok ? wz * wi : wz;
        /* v3_frame: a = v3_norm(cross(|w.x| > 0.5 ? (0, 1, 0) : (1, 0, 0), w)), b = cross(w, a) */
        const int side = fabs(wx) > R(0.5);
        const real ex = side ? R(0) : R(1), ey = side ? R(1) : R(0), ez = R(0);
        real qx = ey * wz - ez * wy, qy = ez * wx - ex * wz, qz = ex * wy - ey * wx;
        const real ql = sqrt(qx * qx + qy * qy + qz * qz), qi = R(1) / ql;
        const int qok = ql > R(0);
        qx = qok ? qx * qi : qx, qy = qok ? qy * qi : qy, qz = qok ? qz * qi : qz;
        fa[0][k] = qx, fa[1][k] = qy, fa[2][k] = qz;
        fb[0][k] = wy * qz - wz * qy, fb[1][k] = wz * qx - wx * qz, fb[2][k] = wx * qy - wy * qx;
    }
    for (uint32_t m = fresh; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        DiscAxes *d = &sh[live[k]].disc;
        for (int e = 0; e < 3; e++)
            ax[e][k] = d->a.e[e] = fa[e][k], bx[e][k] = d->b.e[e] = fb[e][k];
        d->of = li + 1;
    }
}

/* A sphere light's points (u, v) of the discs of axes (ax, bx) it shows
 * the hits p, less the hits' positions, into (dx, dy, dz): light_pos's
 * point (area_point: the concentric map, sample_disc) operation for
 * operation, lane by lane in arrays, where one ray's square roots and
 * divisions waited on each other (the round lamp's points were a tenth of
 * models/example.scene's frame). */
static inline __attribute__((always_inline)) void sphere_points(const WorldLight *l, real ax[3][TRACE_PACKET],
                                                               real bx[3][TRACE_PACKET], const real *u, const real *v,
                                                               real p[3][TRACE_PACKET], real *dx, real *dy, real *dz)
{
    const real cx = l->pos.x, cy = l->pos.y, cz = l->pos.z, radius = l->radius;
    for (int k = 0; k < TRACE_PACKET; k++) {
        /* sample_disc(u, v) */
        const real a = R(2) * u[k] - R(1), b = R(2) * v[k] - R(1);
        const int centre = (a == R(0)) & (b == R(0)), wide = a * a > b * b;
        const real r = wide ? a : b, q = wide ? b : a;
        real sn, cs;
        sample_sincos_quarter((REAL_PI / R(4)) * (q / r), &sn, &cs);
        const real x = centre ? R(0) : r * (wide ? cs : sn), y = centre ? R(0) : r * (wide ? sn : cs);
        /* the point: centre + (a x + b y) radius, less p */
        dx[k] = cx + (ax[0][k] * x + bx[0][k] * y) * radius - p[0][k];
        dy[k] = cy + (ax[1][k] * x + bx[1][k] * y) * radius - p[1][k];
        dz[k] = cz + (ax[2][k] * x + bx[2][k] * y) * radius - p[2][k];
    }
}

/* A sphere light's points of the disc it shows each hit of the lanes of
 * ok, less the hits' positions p, into (dx, dy, dz): sphere_axes, then
 * sphere_points. */
static inline __attribute__((always_inline)) void sphere_offsets(const WorldLight *l, uint32_t li, Shading *sh,
                                                                const int *live, uint32_t ok, const real *u,
                                                                const real *v, real p[3][TRACE_PACKET], real *dx,
                                                                real *dy, real *dz)
{
    real ax[3][TRACE_PACKET], bx[3][TRACE_PACKET];
    sphere_axes(l, li, sh, live, ok, p, ax, bx);
    sphere_points(l, ax, bx, u, v, p, dx, dy, dz);
}

/* The directions, distances, inverses and radiance (light_dirs_towards)
 * from hits p of the lanes of ok to area light li's points (u, v) there
 * (sphere_offsets, rect_offsets), sc the light's intensity a lane. */
static inline __attribute__((always_inline)) uint32_t area_dirs(const World *w, uint32_t li, Shading *sh,
                                                               const int *live, uint32_t ok, const real *u,
                                                               const real *v, const real *sc, real p[3][TRACE_PACKET],
                                                               vec3 *L, real *dist, vec3 *inv, vec3 *rad)
{
    const WorldLight *l = &w->lights[li];
    real d[3][TRACE_PACKET];
    if (l->kind == LIGHT_SPHERE)
        sphere_offsets(l, li, sh, live, ok, u, v, p, d[0], d[1], d[2]);
    else
        rect_offsets(l, u, v, p, d);
    return light_dirs_towards(w, l, ok, d[0], d[1], d[2], sc, L, dist, inv, rad, 1);
}

/* What an area light's points share at a packet's hits, made once for
 * all of the light's points (light_pass's j) where each point made it
 * again: each lane's hit position, its disc axes (a sphere light), its
 * share of the points (one budget: the m points of its pixel's sequence
 * from base on) and that sequence's scrambles, and the light a point
 * brings.  Lanes past the live rays take no point (m 0).  Measured
 * (callgrind, one thread): the demo's last view at 12 x 12 points, 128 x
 * 96, 3128M -> 2845M instructions; a moving frame's 2 x 2, 256 x 192,
 * 482M -> 462M; models/example.scene at one sample 512M -> 474M. */
typedef struct {
    real p[3][TRACE_PACKET], ax[3][TRACE_PACKET], bx[3][TRACE_PACKET], sc[TRACE_PACKET];
    uint32_t m[TRACE_PACKET], base[TRACE_PACKET];
    uint32_t seq_index[TRACE_PACKET], seq_first[TRACE_PACKET], seq_second[TRACE_PACKET];
} AreaLanes;

/* AreaLanes of area light li at the live rays' hits, from area_plan at the
 * light's first point and sphere_axes (the rays' keys and axes kept as
 * they keep them); 0 where a ray's points are not its share of a scrambled
 * Sobol sequence (per effect, or a pixel's one point of a light of one:
 * those go point by point, light_uvs). */
static inline __attribute__((always_inline)) int area_lanes(const World *w, Shading *sh, const int *live, int nl,
                                                           uint32_t li, AreaLanes *al)
{
    const WorldLight *l = &w->lights[li];
    const uint32_t side = (uint32_t)world_light_side(w, l), k = side * side;
    uint32_t ok = 0;
    for (int q = 0; q < TRACE_PACKET; q++) {
        for (int e = 0; e < 3; e++)
            al->p[e][q] = R(0);
        al->sc[q] = R(0);
        al->m[q] = al->base[q] = al->seq_index[q] = al->seq_first[q] = al->seq_second[q] = 0;
        if (q >= nl)
            continue;
        Shading *h = &sh[live[q]];
        real u, v, share;
        if (area_plan(w, l, li, &h->id, &h->disc, 0, &u, &v, &share, &al->base[q]) != 2)
            return 0;
        al->p[0][q] = h->sf.p.x, al->p[1][q] = h->sf.p.y, al->p[2][q] = h->sf.p.z;
        al->m[q] = sample_share(k, h->id.count);
        const SampleSobol *seq = &h->disc.seq;
        al->seq_index[q] = seq->index, al->seq_first[q] = seq->first, al->seq_second[q] = seq->second;
        al->sc[q] = l->intensity * share;
        ok |= 1u << q;
    }
    if (l->kind == LIGHT_SPHERE)
        sphere_axes(l, li, sh, live, ok, al->p, al->ax, al->bx);
    return 1;
}

/* area_dirs of point j of each lane of al (light_uvs' and area_dirs' arithmetic). */
static inline __attribute__((always_inline)) uint32_t lanes_dirs(const World *w, uint32_t li, AreaLanes *al,
                                                                uint32_t j, vec3 *L, real *dist, vec3 *inv, vec3 *rad)
{
    const WorldLight *l = &w->lights[li];
    SampleLanes sl;
    real u[TRACE_PACKET], v[TRACE_PACKET], d[3][TRACE_PACKET];
    uint32_t ok = 0;
    for (int k = 0; k < TRACE_PACKET; k++) {
        sl.index[k] = al->base[k] + j;
        sl.seq_index[k] = al->seq_index[k], sl.seq_first[k] = al->seq_first[k], sl.seq_second[k] = al->seq_second[k];
        ok |= (uint32_t)(j < al->m[k]) << k;
    }
    if (!ok)
        return 0;
    sample_sobol_lanes(&sl);
    for (int k = 0; k < TRACE_PACKET; k++)
        u[k] = sample_unit(sl.u[k]), v[k] = sample_unit(sl.v[k]);
    if (l->kind == LIGHT_SPHERE)
        sphere_points(l, al->ax, al->bx, u, v, al->p, d[0], d[1], d[2]);
    else
        rect_offsets(l, u, v, al->p, d);
    return light_dirs_towards(w, l, ok, d[0], d[1], d[2], al->sc, L, dist, inv, rad, 1);
}

/* What a packet's shading takes for an area light's points (area_dirs),
 * for n points given: the twin of shade_light_point's scalar code, for
 * tests to hold the two to each other. */
uint32_t shade_light_points(const World *w, uint32_t li, int n, const vec3 *at, const real *u, const real *v,
                            vec3 *dir, real *dist, vec3 *radiance)
{
    const WorldLight *l = &w->lights[li];
    if (!world_light_is_area(l))
        return 0;
    Shading sh[TRACE_PACKET];
    int live[TRACE_PACKET];
    real uu[TRACE_PACKET], vv[TRACE_PACKET], sc[TRACE_PACKET], p[3][TRACE_PACKET];
    vec3 inv[TRACE_PACKET];
    const uint32_t ok = n >= TRACE_PACKET ? (1u << TRACE_PACKET) - 1 : (1u << n) - 1;
    for (int k = 0; k < TRACE_PACKET; k++) {
        const int in = k < n;
        sh[k].disc = (DiscAxes){.of = 0, .key_of = 0};
        live[k] = k;
        uu[k] = in ? u[k] : R(0.5), vv[k] = in ? v[k] : R(0.5), sc[k] = in ? l->intensity : R(0);
        for (int e = 0; e < 3; e++)
            p[e][k] = in ? at[k].e[e] : R(0);
    }
    return area_dirs(w, li, sh, live, ok, uu, vv, sc, p, dir, dist, inv, radiance);
}

/* light_at for light li (its point j) at the hits of the live rays, and
 * each direction's inverse for its shadow ray: bit k of the result where
 * light arrives at live ray k.  The square roots and divisions of all the
 * rays lane by lane, in arrays the compiler turns into vector code (one
 * ray's waited on each other: a fifth of the default scene's frame). */
static inline __attribute__((always_inline)) uint32_t light_dirs(const World *w, Shading *sh, const int *live, int nl,
                                                                uint32_t li, uint32_t j, AreaLanes *al, vec3 *L,
                                                                real *dist, vec3 *inv, vec3 *rad, const int optional)
{
    const WorldLight *l = &w->lights[li];
    uint32_t ok = 0;
    if (l->kind == LIGHT_DIRECTIONAL) {
        for (int k = 0; k < nl; k++) {
            Shading *h = &sh[live[k]];
            if (light_at(w, l, h->sf.p, &h->id, &h->disc, li, j, &L[k], &dist[k], &rad[k], optional)) {
                inv[k] = v3(R(1) / L[k].x, R(1) / L[k].y, R(1) / L[k].z);
                ok |= 1u << k;
            }
        }
        return ok;
    }
    real dx[TRACE_PACKET], dy[TRACE_PACKET], dz[TRACE_PACKET], sc[TRACE_PACKET];
    if (optional && world_uses(w, FEAT_AREA) && world_light_is_area(l)) { /* lane by lane */
        if (al)
            return lanes_dirs(w, li, al, j, L, dist, inv, rad);
        real u[TRACE_PACKET], v[TRACE_PACKET], p[3][TRACE_PACKET];
        const uint32_t got = light_uvs(w, sh, live, nl, li, j, u, v, sc, p);
        return area_dirs(w, li, sh, live, got, u, v, sc, p, L, dist, inv, rad);
    }
    for (int k = 0; k < TRACE_PACKET; k++) {
        vec3 pos = v3_splat(R(1)), p = v3_splat(R(0)); /* a lane past nl: something finite */
        sc[k] = R(0);
        if (k < nl) {
            Shading *h = &sh[live[k]];
            p = h->sf.p;
            if (light_pos(w, l, p, &h->id, &h->disc, li, j, &pos, &sc[k], optional))
                ok |= 1u << k;
        }
        dx[k] = pos.x - p.x, dy[k] = pos.y - p.y, dz[k] = pos.z - p.z;
    }
    return light_dirs_towards(w, l, ok, dx, dy, dz, sc, L, dist, inv, rad, optional);
}

/* The m shadow rays sr towards light l: the mask of those blocked; with
 * glass shadows, blocked by something opaque, and in *through those that
 * cross glass (their light is what transmittance says). */
static inline uint32_t shadow_packet(const World *w, const Ray *sr, int m, const real *tmax, const WorldLight *l,
                                     int glass, uint32_t *through)
{
    if (!glass)
        return m == 1 ? (uint32_t)trace_occluded(w, &sr[0], tmax[0], l) : trace_occluded_packet(w, sr, m, tmax, l);
    if (m > 1)
        return trace_shadow_packet(w, sr, m, tmax, l, through);
    int g;
    uint32_t blocked = (uint32_t)trace_shadow(w, &sr[0], tmax[0], l, &g);
    *through = (uint32_t)g;
    return blocked;
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
    const uint32_t side = (uint32_t)world_light_side(w, l), k = side * side;
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
        uint32_t through = 0, blocked = shadow_packet(w, sr, m, tmax, l, glass, &through);
        for (int q = 0; q < m; q++) {
            const uint32_t bit = 1u << who[q];
            if (blocked >> q & 1)
                seen_blocked |= bit;
            else if (!(through >> q & 1))
                seen_clear |= bit;
            else if (v3_max_comp(shade_transmittance(w, &sr[q], tmax[q], l, 0, stats)) > R(0))
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
                                                             uint32_t li, uint32_t j, AreaLanes *al, uint32_t probed,
                                                             uint32_t clear, RayStats *stats, const int optional)
{
    const int shadows = world_has(w, FEAT_SHADOWS);
    const int glass_shadows = optional && world_uses(w, FEAT_REFRACT) && w->view.settings.glass_shadows;
    /* the light at the point, for a ray the depth limit cuts there */
    const int track = optional && world_uses(w, FEAT_REFLECT | FEAT_REFRACT) && w->view.settings.depth_limit == LIMIT_LOCAL;
    const WorldLight *l = &w->lights[li];
    Ray sr[TRACE_PACKET];
    real tmax[TRACE_PACKET], dist[TRACE_PACKET];
    vec3 Lk[TRACE_PACKET], radk[TRACE_PACKET], inv[TRACE_PACKET];
    vec3 L[TRACE_PACKET], rad[TRACE_PACKET];
    real ndotl[TRACE_PACKET];
    int who[TRACE_PACKET], m = 0;
    for (uint32_t lit = light_dirs(w, sh, live, nl, li, j, al, Lk, dist, inv, radk, optional); lit; lit &= lit - 1) {
        const int k = __builtin_ctz(lit);
        Shading *h = &sh[live[k]];
        L[m] = Lk[k], rad[m] = radk[k];
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
            add_light(h, L[m], rad[m], ndotl[m], li, optional);
            if (track)
                h->irr = v3_madd(h->irr, rad[m], ndotl[m]);
            continue;
        }
        tmax[m] = shadow_ray_inv(h, L[m], inv[k], dist[k], &sr[m]);
        who[m++] = live[k];
    }
    if (m == 0)
        return;
    stats->shadow += (uint64_t)m;
    uint32_t through = 0, blocked = shadow_packet(w, sr, m, tmax, l, glass_shadows, &through);
    for (int k = 0; k < m; k++) {
        vec3 got = rad[k];
        if (blocked >> k & 1)
            continue;
        if (through >> k & 1) {
            got = v3_mul(rad[k], shade_transmittance(w, &sr[k], tmax[k], l, 0, stats));
            if (!(v3_max_comp(got) > R(0)))
                continue;
        }
        add_light(&sh[who[k]], L[k], got, ndotl[k], li, optional);
        if (track)
            sh[who[k]].irr = v3_madd(sh[who[k]].irr, got, ndotl[k]);
    }
}

/* The guide of a Whitted camera ray that met a surface (settings guides:
 * for the server's history, render/temporal.h): the surface's shading
 * normal towards the ray and its distance.  A mirror's and glass's too:
 * what they show moves otherwise than they do, but the history holds its
 * light within the frame's (TemporalFrame clip), and treating them as no
 * surface let their neighbours take their light (an open edge's) and
 * streak the floor by the glass ball.  What the history does not read
 * costs no bytes on the wire once coded: no colour (white), and the
 * distance rounded to 16 bits of its float (0.4%; the history's test of
 * a surface is 5%): a 1024 x 768 frame of the demo's flight coded 1.37 MB
 * -> 0.88 MB (0.46 MB without guides), the pictures within 0.008 RMSE. */
static Guide first_guide(const Ray *r, const Hit *hit, const Shading *h)
{
    const real mu = v3_dot(h->sf.ns, v3_neg(r->dir));
    float d = (float)hit->t;
    uint32_t bits;
    memcpy(&bits, &d, sizeof bits);
    bits = bits < 0x7f7f0000u ? (bits + 0x8000u) & 0xffff0000u : bits;
    memcpy(&d, &bits, sizeof d);
    return (Guide){.albedo = v3_splat(R(1)),
                   .normal = mu < R(0) ? v3_neg(h->sf.ns) : h->sf.ns,
                   .depth = (real)d,
                   .surface = 1,
                   .lum2 = R(0),
                   .instance = hit->kind == HIT_INSTANCE ? hit->index + 1 : 0};
}

void shade_packet(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                  const SampleId *ids, const RayDiff *diffs)
{
    shade_packet_guided(w, rays, n, out, stats, keys, ids, diffs, NULL);
}

void shade_packet_guided(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                         const SampleId *ids, const RayDiff *diffs, Guide *guides)
{
    if (w->view.settings.integrator == INTEGRATOR_PATH) {
        path_radiance_packet(w, rays, n, ids, out, stats, keys, guides);
        return;
    }
    /* Whitted's frames have a guide where the server's history asks
     * (settings guides); with settings denoise alone they pass as they are */
    const int guided = guides && w->view.settings.guides;
    for (int i = 0; guides && !guided && i < n; i++)
        guides[i] = guide_none(v3_splat(R(1)));
    vec3 ones[TRACE_PACKET];
    for (int i = 0; i < n; i++)
        ones[i] = v3_splat(R(1));
    shade_rays(w, rays, n, out, stats, keys, ids, diffs, 0, ones, 0, guided ? guides : NULL);
}

/* shade_rays' body; `optional` (a constant in each copy) lets in the paths
 * of the features a scene may use beyond point lights, shadows and Phong. */
static inline __attribute__((always_inline)) void shade_rays_at(const World *w, const Ray *rays, int n, vec3 *out,
                                                                RayStats *stats, uint64_t *keys, const SampleId *ids,
                                                                const RayDiff *diffs, int depth, const vec3 *weights,
                                                                int sunless, Guide *guides, const int optional)
{
    Hit hits[TRACE_PACKET];
    Shading sh[TRACE_PACKET];
    int live[TRACE_PACKET], nl = 0;
    if (n == 1)
        trace_closest(w, &rays[0], &hits[0]);
    else if (depth == 0)
        trace_closest_packet(w, rays, n, hits);
    else
        trace_closest_bounced(w, rays, n, hits);
    if (depth == 0)
        stats->primary += (uint64_t)n;
    /* the hit triangles' vertices, for every ray at once: on a big model
     * each is a cache miss, and waiting for them one by one showed */
    for (int i = 0; i < n; i++)
        if (hits[i].kind == HIT_INSTANCE)
            __builtin_prefetch(&w->models[w->instances[hits[i].index].model]->tris[hits[i].sub]);
    for (int i = 0; i < n; i++) {
        if (hits[i].kind == HIT_NONE) {
            /* (a rough metal's and frosted glass's rays see the sky without
             * its sun, a light of its own here whose lobe shows it) */
            /* over the ray's footprint where it has one and the filter reads mip-maps (0: at a point) */
            const real width = diffs && w->view.settings.filter >= FILTER_TRILINEAR ? raydiff_width(&diffs[i]) : R(0);
            out[i] = !w->env   ? w->background
                     : sunless ? environment_radiance_sunless_over(w->env, rays[i].dir, width)
                               : environment_radiance_over(w->env, rays[i].dir, width);
            if (keys)
                keys[i] = UINT64_MAX;
            continue;
        }
        shade_start(w, &rays[i], &hits[i], &sh[i], diffs ? &diffs[i] : NULL, optional);
        live[nl++] = i;
    }
    if (guides) /* settings guides: what the camera rays met first */
        for (int i = 0; i < n; i++)
            guides[i] = hits[i].kind == HIT_NONE ? guide_none(v3_splat(R(1))) : first_guide(&rays[i], &hits[i], &sh[i]);
    /* a random key only where something draws from it (hashing every ray's
     * showed in the instruction count of scenes without) */
    if (optional && world_uses(w, FEAT_AREA | FEAT_ROUGH))
        for (int k = 0; k < nl; k++) {
            const SampleId id = ids ? ids[live[k]] : (SampleId){.key = 0, .index = 0, .count = 1};
            sh[live[k]].id = id;
            sh[live[k]].id.key = sample_mix(id.key, (uint32_t)depth);
        }
    for (uint32_t li = 0; li < w->light_count + w->whitted_lights; li++) {
        const WorldLight *l = &w->lights[li];
        uint32_t points = 1, probed = 0, clear = 0;
        AreaLanes lanes, *al = NULL;
        if (optional && world_uses(w, FEAT_AREA) && world_light_is_area(l)) {
            if (w->view.settings.light_sampling == LIGHTS_ADAPTIVE && depth == 0 && world_light_side(w, l) > 1)
                probe_pass(w, sh, live, nl, li, &probed, &clear, stats);
            /* per effect, every ray all of the light's points; one budget,
             * each ray its share (the most of the packet's rays) */
            const uint32_t side = (uint32_t)world_light_side(w, l), k = side * side;
            const int product = w->view.settings.sampling == SAMPLING_PRODUCT;
            points = 0;
            for (int q = 0; q < nl && points < k; q++) {
                const SampleId *id = &sh[live[q]].id;
                uint32_t m = product ? k : sample_share(k, id->count);
                points = m > points ? m : points;
            }
        }
        if (optional && points > 1 && area_lanes(w, sh, live, nl, li, &lanes))
            al = &lanes;
        for (uint32_t j = 0; j < points; j++)
            light_pass(w, sh, live, nl, li, j, al, probed, clear, stats, optional);
    }
    const int beyond = optional && world_uses(w, FEAT_REFLECT | FEAT_REFRACT | FEAT_EMIT | FEAT_COAT);
    Spawn sp[SPAWN_MAX];
    int ns = 0;
    for (int k = 0; k < nl; k++) {
        int i = live[k];
        out[i] = beyond ? shade_beyond(w, i, &sh[i], depth, weights[i], stats, sp, &ns) : sh[i].col;
        if (keys)
            keys[i] = (uint64_t)sh[i].sf.object << 16 | sh[i].lit;
    }
    if (ns)
        spawn_trace(w, sp, ns, out, stats, depth);
    /* a ray that crossed a dielectric's inside to get here: absorbed on the way */
    if (optional && world_uses(w, FEAT_REFRACT))
        for (int k = 0; k < nl; k++) {
            const Surface *sf = &sh[live[k]].sf;
            if (sf->inside && material_dielectric(sf->mat) && v3_max_comp(sf->mat->absorb) > R(0))
                out[live[k]] = v3_mul(out[live[k]], dielectric_absorbed(w, sf->mat, &hits[live[k]]));
        }
}

/* The features whose paths the shading asks about; a scene using none of
 * them (point lights, shadows, Phong or diffuse: make bench's scenes)
 * takes a copy without those paths.  In the one body, their tests and the
 * bigger function's registers cost a flat hit 50 instructions more than a
 * build with the features compiled out. */
#define SHADE_OPTIONAL (FEAT_TEXTURES | FEAT_COLOURS | FEAT_SPOT | FEAT_ATTENUATION | FEAT_REFLECT | FEAT_REFRACT | \
                        FEAT_EMIT | FEAT_AREA | FEAT_ROUGH | FEAT_CHECKER | FEAT_COAT)

static void shade_rays(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                       const SampleId *ids, const RayDiff *diffs, int depth, const vec3 *weights, int sunless,
                       Guide *guides)
{
    if (world_uses(w, SHADE_OPTIONAL))
        shade_rays_at(w, rays, n, out, stats, keys, ids, diffs, depth, weights, sunless, guides, 1);
    else
        shade_rays_at(w, rays, n, out, stats, keys, ids, NULL, depth, weights, sunless, guides, 0);
}

vec3 shade_ray(const World *w, const Ray *r, RayStats *stats, uint64_t *key)
{
    vec3 c;
    const vec3 one = v3_splat(R(1));
    shade_rays(w, r, 1, &c, stats, key, NULL, NULL, 0, &one, 0, NULL);
    return c;
}
