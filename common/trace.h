/* trace.h - rays against a whole prepared scene: closest hit, any hit, and
 * the surface (point, normals, texture coordinates, material) at a hit. */
#ifndef LANRAY_TRACE_H
#define LANRAY_TRACE_H

#include "scene.h"

typedef enum { HIT_NONE = 0, HIT_SPHERE, HIT_PLANE, HIT_TRIANGLE, HIT_INSTANCE } HitKind;

typedef struct {
    real t, b1, b2;   /* distance; barycentrics of vertices 1 and 2 for triangles */
    HitKind kind;
    uint32_t index;   /* sphere, plane, scene triangle or instance */
    uint32_t sub;     /* triangle inside the instance's model */
} Hit;

typedef struct {
    vec3 p;           /* hit point */
    vec3 ng;          /* geometric normal, unit, facing the incoming ray */
    vec3 ns;          /* shading normal, unit, same side as ng */
    real u, v;        /* texture coordinates (when has_uv) */
    int has_uv;
    const Material *mat;
    uint32_t object;  /* identifies the surface for adaptive anti-aliasing */
} Surface;

int trace_closest(const Scene *s, const Ray *r, Hit *hit);
int trace_occluded(const Scene *s, const Ray *r, real tmax);
void trace_surface(const Scene *s, const Ray *r, const Hit *hit, Surface *out);

/* Moves p off the surface along n by an amount that scales with |p|
 * (Wächter & Binder, "A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6): a fixed number of ulps far
 * from the origin, a small absolute step near it.  n points to the side the
 * new ray leaves on. */
vec3 trace_offset_origin(vec3 p, vec3 n);

#endif
