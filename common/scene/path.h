/* path.h - the path integrator (settings integrator path): light that
 * bounces.  A camera ray's path goes on from every surface it meets:
 * diffuse surfaces take the explicit lights by next-event estimation (a
 * shadow ray to one point of each light a bounce) and scatter the path by
 * the cosine; mirrors and metals reflect it (bent by their roughness),
 * dielectrics reflect or refract it by Fresnel's reflectance; emissive
 * surfaces and the background add what they emit wherever a path meets
 * them.  Russian roulette ends paths after a few bounces.  Every number
 * comes from the ray's sample key, mixed with the bounce, so that a pixel
 * is the same whoever renders it. */
#ifndef LANRAY_PATH_H
#define LANRAY_PATH_H

#include "base/sample.h"
#include "scene/shade.h"

/* The light arriving along r (a camera ray of sample id); *key (may be
 * NULL) receives what it saw first, for adaptive anti-aliasing. */
vec3 path_radiance(const World *w, const Ray *r, SampleId id, RayStats *stats, uint64_t *key);

#endif
