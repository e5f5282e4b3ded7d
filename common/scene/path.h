/* path.h - the path integrator (settings integrator path): light that
 * bounces.  A camera ray's path goes on from every surface it meets:
 * diffuse surfaces take the explicit lights by next-event estimation (a
 * shadow ray to one point of each light a bounce) and scatter the path by
 * the cosine; mirrors reflect it, rough metals and rough clear coats
 * scatter it by their GGX lobes (lit by next-event estimation as diffuse
 * surfaces are), dielectrics reflect or refract it by Fresnel's
 * reflectance; emissive
 * surfaces and the background add what they emit wherever a path meets
 * them.  Russian roulette ends paths after a few bounces.  Every number
 * comes from the ray's sample key, mixed with the bounce, so that a pixel
 * is the same whoever renders it. */
#ifndef LANRAY_PATH_H
#define LANRAY_PATH_H

#include "base/sample.h"
#include "scene/shade.h"

/* The light arriving along each of n <= TRACE_PACKET camera rays (ids:
 * their samples, or NULL) in out[i]; keys[i] (keys may be NULL) receives
 * what ray i saw first, for adaptive anti-aliasing.  Each path is what it
 * is alone: the camera rays go as a packet, the bounces of the live
 * paths in one call (trace_closest_each).  guides (may be NULL): each
 * path's guide for the denoiser (scene/shade.h). */
void path_radiance_packet(const World *w, const Ray *rays, int n, const SampleId *ids, vec3 *out, RayStats *stats,
                          uint64_t *keys, Guide *guides);

#endif
