/* aabb.h - axis-aligned bounding boxes for the BVH builders. */
#ifndef LANRAY_AABB_H
#define LANRAY_AABB_H

#include "base/vec.h"

typedef struct {
    vec3 min, max;
} Aabb;

static inline Aabb aabb_empty(void)
{
    Aabb b = {v3_splat(REAL_INF), v3_splat(-REAL_INF)};
    return b;
}
static inline Aabb aabb_point(vec3 p) { Aabb b = {p, p}; return b; }
static inline void aabb_grow(Aabb *b, vec3 p) { b->min = v3_min(b->min, p); b->max = v3_max(b->max, p); }
static inline Aabb aabb_union(Aabb a, Aabb b)
{
    Aabb r = {v3_min(a.min, b.min), v3_max(a.max, b.max)};
    return r;
}
static inline int aabb_is_empty(Aabb b) { return !(b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z); }
static inline vec3 aabb_centre(Aabb b) { return v3_scale(v3_add(b.min, b.max), R(0.5)); }
static inline vec3 aabb_extent(Aabb b) { return v3_sub(b.max, b.min); }
/* Half the surface area: the SAH only ever compares areas, so the factor 2 is dropped. */
static inline real aabb_half_area(Aabb b)
{
    if (aabb_is_empty(b))
        return R(0);
    vec3 e = aabb_extent(b);
    return e.x * e.y + e.y * e.z + e.z * e.x;
}
static inline int aabb_contains(Aabb outer, Aabb inner)
{
    return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
           outer.max.x >= inner.max.x && outer.max.y >= inner.max.y && outer.max.z >= inner.max.z;
}

#endif
