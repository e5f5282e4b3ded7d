/* shade.h - colour of a camera ray: Phong or diffuse-only shading with
 * point, spot and directional lights and hard shadows, and the reflected
 * and refracted rays of mirrors and dielectrics. */
#ifndef LANRAY_SHADE_H
#define LANRAY_SHADE_H

#include <stdint.h>

#include "base/sample.h"
#include "geom/raydiff.h"
#include "scene/trace.h"

typedef struct {
    uint64_t primary, shadow;
    uint64_t secondary; /* reflected and refracted rays (and their shadow rays count as shadow) */
} RayStats;

static inline uint64_t ray_stats_total(const RayStats *s) { return s->primary + s->shadow + s->secondary; }
static inline void ray_stats_add(RayStats *to, RayStats st)
{
    to->primary += st.primary;
    to->shadow += st.shadow;
    to->secondary += st.secondary;
}

/* What a camera ray's path saw first, for the denoiser (render/denoise.h):
 * the first surface that is not a smooth mirror or clear flat glass
 * (through which the path is followed, their colours in its albedo; curved
 * glass is a surface: scene/path.c guide_lens), its colour
 * (albedo: the diffuse colour, a metal's, glass's), its shading normal
 * towards the ray and the distance along the path; surface 0 where the
 * path left the scene or met an emitter first (the background's light, a
 * lamp's: no noise to take out), albedo then the tint on the way.  Summed
 * over a pixel's samples: surface counts the samples that met one, and
 * the normals and depths are theirs alone. */
typedef struct {
    vec3 albedo, normal;
    real depth;
    int surface;
    real lum2; /* the square of the sample's luminance, summed (render.c sets it: the noise's measure) */
    /* the model instance (its index + 1) whose surface the camera ray met
     * first and the guide shows, so that a history follows the instance's
     * own motion (render/temporal.h); 0: none, or seen through a mirror or
     * glass.  Of samples summed, the largest. */
    uint32_t instance;
} Guide;

/* The guide of a sample that met no surface (the background, an emitter),
 * seen through a tint of albedo; with albedo 0, the empty sum. */
static inline Guide guide_none(vec3 albedo)
{
    return (Guide){.albedo = albedo, .normal = v3_splat(R(0)), .depth = R(0), .surface = 0, .lum2 = R(0)};
}

/* Rec. 709 luminance of linear light: what a guide's noise is measured in. */
static inline real guide_luminance(vec3 c) { return R(0.2126) * c.x + R(0.7152) * c.y + R(0.0722) * c.z; }

/* What of a light's radiance passes along shadow ray sr, which
 * trace_shadow let pass (nothing opaque in its way but in an instance
 * that is partly glass, so the walk looks at glass alone): the product of
 * the transmitted colours (and absorption) of the dielectrics it crosses
 * before tmax, passing light l's own lamp (l may be NULL); 0 at anything
 * opaque, and with nulls_only at any dielectric that bends light (the
 * path integrator's: only see-through blends, material_null, pass). */
vec3 shade_transmittance(const World *w, const Ray *sr, real tmax, const WorldLight *l, int nulls_only,
                         RayStats *stats);

/* Traces r and returns its colour.  *key (may be NULL) receives an identifier
 * of what the ray saw, for adaptive anti-aliasing: the surface and which of
 * the first 16 lights reached it. */
vec3 shade_ray(const World *w, const Ray *r, RayStats *stats, uint64_t *key);
/* n <= TRACE_PACKET rays at once, camera rays and shadow rays traced as
 * packets: out[i] (and keys[i], when keys is not NULL) is what shade_ray
 * gives for rays[i], to the bit.  ids[i] is ray i's sample (base/sample.h:
 * its pixel's key, and which of its pixel's rays it is), from which area
 * lights and rough mirrors draw; NULL: all key 0, ray 0 of 1, which a scene
 * without them may pass.
 * diffs[i] are ray i's differentials, from which textures are filtered
 * over the sample's footprint (also after mirrors and glass); NULL: each
 * texture is read at one point of its image. */
void shade_packet(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                  const SampleId *ids, const RayDiff *diffs);
/* The same, with each ray's guide in guides[i]: the path integrator's;
 * Whitted's where settings guides asks (a moving frame's, for the
 * server's history: the first surface, none at a mirror, glass or an
 * emitter), else surface 0 (with settings denoise alone its pixels pass
 * the denoiser as they are). */
void shade_packet_guided(const World *w, const Ray *rays, int n, vec3 *out, RayStats *stats, uint64_t *keys,
                         const SampleId *ids, const RayDiff *diffs, Guide *guides);

/* The path integrator's next-event estimation (scene/path.c): light li's
 * radiance arriving at *p from the point (u, v) of the unit square on it
 * (an area light's; other lights have one point), the whole light's
 * (no share of a pixel's budget), with its unit direction and distance; 0
 * where none arrives.  (p by pointer: lobes_make says why.) */
int shade_light_point(const World *w, uint32_t li, const vec3 *p, real u, real v, vec3 *dir, real *dist,
                      vec3 *radiance);
/* The same for the points of area light li at (u[k], v[k]) seen from n <=
 * TRACE_PACKET points at[k], by the lane-by-lane code a packet's shading
 * uses (each point as shade_light_point gives it: tests hold them to it);
 * the mask of the points light reaches. */
uint32_t shade_light_points(const World *w, uint32_t li, int n, const vec3 *at, const real *u, const real *v,
                            vec3 *dir, real *dist, vec3 *radiance);

#endif
