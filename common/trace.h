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
    real err;         /* bound on the rounding error of each coordinate of p */
} Surface;

int trace_closest(const Scene *s, const Ray *r, Hit *hit);
/* The point at barycentrics (b1, b2) of triangle v0 v1 v2, as trace_surface
 * computes a scene triangle's hit point, and the bound on the rounding error
 * of each of its coordinates (for trace_offset_origin). */
vec3 trace_triangle_point(vec3 v0, vec3 v1, vec3 v2, real b1, real b2, real *err);
int trace_occluded(const Scene *s, const Ray *r, real tmax);
void trace_surface(const Scene *s, const Ray *r, const Hit *hit, Surface *out);

/* Moves p off the surface along n (the side the new ray leaves on) by just
 * more than the rounding error of p, so that the new ray cannot hit the
 * surface it starts on, whatever the scale or position of the scene.  Like
 * Wächter & Binder ("A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6) the offset grows with the
 * magnitude of the numbers involved rather than being a fixed epsilon; its
 * size is the error bound `err` of the primitive's hit point (PBRT 3.9), and
 * each coordinate is then rounded away from the surface (nextafter) so the
 * addition cannot land back on it. */
vec3 trace_offset_origin(vec3 p, vec3 n, real err);

#endif
