/* shade.c - local illumination.
 *
 *   colour = ambient*kd + sum over lights reaching the point of
 *            radiance * (kd * max(0, N.L) + ks * max(0, R.V)^shininess)
 *
 * kd is multiplied by the texture where the material has one; the specular
 * term is skipped in diffuse-only mode and for materials without ks.  One
 * shadow ray per light stops at the first occluder (any-hit). */
#include "shade.h"

/* Light arriving at p: unit direction towards the light, distance, radiance. */
static int light_at(const Scene *s, const Light *l, vec3 p, vec3 *dir, real *dist, vec3 *radiance)
{
    real scale = l->intensity;
    if (l->kind == LIGHT_DIRECTIONAL) {
        *dir = v3_neg(l->axis);
        *dist = REAL_INF;
    } else {
        vec3 d = v3_sub(l->pos, p);
        real d2 = v3_dot(d, d);
        if (!(d2 > R(0)))
            return 0;
        *dist = sqrt(d2);
        *dir = v3_scale(d, R(1) / *dist);
        if (scene_uses(s, FEAT_ATTENUATION) && l->attenuate)
            scale /= d2;
        if (scene_uses(s, FEAT_SPOT) && l->kind == LIGHT_SPOT) {
            real c = -v3_dot(*dir, l->axis);
            if (c <= l->cos_outer)
                return 0;
            if (c < l->cos_inner) { /* soft edge: smoothstep across the rim */
                real t = (c - l->cos_outer) / (l->cos_inner - l->cos_outer);
                scale *= t * t * (R(3) - R(2) * t);
            }
        }
    }
    if (!(scale > R(0)))
        return 0;
    *radiance = v3_scale(l->color, scale);
    return 1;
}

vec3 shade_ray(const Scene *s, const Ray *r, RayStats *stats, uint64_t *key)
{
    Hit hit;
    stats->primary++;
    if (!trace_closest(s, r, &hit)) {
        if (key)
            *key = UINT64_MAX;
        return s->background;
    }
    Surface sf;
    trace_surface(s, r, &hit, &sf);
    const Material *m = sf.mat;
    vec3 kd = m->kd;
    if (scene_uses(s, FEAT_TEXTURES) && m->texture >= 0 && sf.has_uv)
        kd = v3_mul(kd, texture_sample(s->textures[m->texture], sf.u, sf.v, s->settings.filter));
    vec3 col = v3_mul(s->ambient, kd);
    vec3 view = v3_neg(v3_norm(r->dir));
    int phong = s->settings.shading == SHADE_PHONG && v3_max_comp(m->ks) > R(0);
    int shadows = scene_has(s, FEAT_SHADOWS);
    vec3 origin = sf.p;
    if (shadows) /* every light ray leaves on the viewer's side, a smooth triangle's from its
                  * point lifted onto the curved surface (trace_terminator_point) */
        origin = trace_offset_origin(sf.ps, sf.ng, sf.ps_err);
    uint32_t lit = 0;
    for (uint32_t i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        vec3 L, rad;
        real dist;
        if (!light_at(s, l, sf.p, &L, &dist, &rad))
            continue;
        /* The shading normal decides.  On a flat surface it is the geometric
         * one, so a light behind the surface is skipped.  On a smooth
         * triangle near the boundary between light and dark, a light may be
         * behind the flat facet but in front of the curved surface its
         * normals describe: it lights the point, and the shadow ray from the
         * lifted point says whether anything is in the way.  (Skipping lights
         * behind the facet cut triangle-shaped dark patches into coarse
         * smooth meshes: tests/test_render.c, the shadow terminator.) */
        real ndotl = v3_dot(sf.ns, L);
        if (ndotl <= R(0))
            continue;
        if (shadows) {
            /* stop just short of the light so that it does not shadow itself */
            Ray sr = ray_make(origin, L, R(0), isfinite(dist) ? dist * (R(1) - R(64) * REAL_EPS) : REAL_MAX);
            stats->shadow++;
            if (trace_occluded(s, &sr, sr.tmax))
                continue;
        }
        lit |= i < 16 ? 1u << i : 0;
        col = v3_add(col, v3_scale(v3_mul(kd, rad), ndotl));
        if (phong) {
            real rv = v3_dot(v3_reflect(v3_neg(L), sf.ns), view);
            if (rv > R(0))
                col = v3_add(col, v3_scale(v3_mul(m->ks, rad), pow(rv, m->shininess)));
        }
    }
    if (key)
        *key = (uint64_t)sf.object << 16 | lit;
    return col;
}
