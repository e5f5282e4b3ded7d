/* vec.h - three-component vectors for points, directions and colours.
 * Everything is static inline: this is the innermost layer of the hot path. */
#ifndef LANRAY_VEC_H
#define LANRAY_VEC_H

#include "base/real.h"

typedef union {
    struct { real x, y, z; };
    real e[3];
} vec3;

static inline vec3 v3(real x, real y, real z) { vec3 v = {{x, y, z}}; return v; }
static inline vec3 v3_splat(real s) { return v3(s, s, s); }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, real s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
/* a + b*s: the common "point along a ray" form */
static inline vec3 v3_madd(vec3 a, vec3 b, real s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline real v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline real v3_len(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline vec3 v3_norm(vec3 a)
{
    real l = v3_len(a);
    return l > R(0) ? v3_scale(a, R(1) / l) : a;
}
static inline vec3 v3_min(vec3 a, vec3 b) { return v3(real_min(a.x, b.x), real_min(a.y, b.y), real_min(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(real_max(a.x, b.x), real_max(a.y, b.y), real_max(a.z, b.z)); }
static inline vec3 v3_abs(vec3 a) { return v3(fabs(a.x), fabs(a.y), fabs(a.z)); }
static inline real v3_max_comp(vec3 a) { return real_max(a.x, real_max(a.y, a.z)); }
/* v3_norm of a vector of any size (a face normal, the cross product of
 * edges: the square of coordinates past 1e9 overflows a float, of ones
 * under 1e-19 underflows): scaled by its largest component first where its
 * length is out of that range; v3_norm's very bits within it. */
static inline vec3 v3_norm_any(vec3 a)
{
    const real l = v3_len(a);
    if (l > R(1e-18) && l < R(1e18))
        return v3_scale(a, R(1) / l);
    const real m = v3_max_comp(v3_abs(a));
    if (!(m > R(0)) || !isfinite(m))
        return a;
    return v3_norm(v3_scale(a, R(1) / m));
}
static inline real v3_min_comp(vec3 a) { return real_min(a.x, real_min(a.y, a.z)); }
static inline int v3_is_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
/* The same vector, component by component (exactly; a NaN is no vector's same). */
static inline int v3_same(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
static inline vec3 v3_lerp(vec3 a, vec3 b, real t) { return v3_madd(a, v3_sub(b, a), t); }
/* mirror d about n (n unit length) */
static inline vec3 v3_reflect(vec3 d, vec3 n) { return v3_sub(d, v3_scale(n, R(2) * v3_dot(d, n))); }
static inline int v3_max_axis(vec3 a)
{
    return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
}

/* Two unit axes across unit vector n, so that (a, b, n) is a
 * right-handed frame: for directions and discs about n. */
static inline void v3_frame(vec3 n, vec3 *a, vec3 *b)
{
    *a = v3_norm(v3_cross(fabs(n.x) > R(0.5) ? v3(0, 1, 0) : v3(1, 0, 0), n));
    *b = v3_cross(n, *a);
}

/* The same without a square root (Duff et al., "Building an orthonormal
 * basis, revisited", JCGT 2017: one division): for the path integrator's
 * bounces, where v3_frame's took 9% of a path-traced frame.  Other axes
 * than v3_frame's. */
static inline void v3_frame_fast(vec3 n, vec3 *a, vec3 *b)
{
    const real sign = copysign(R(1), n.z), k = R(-1) / (sign + n.z), c = n.x * n.y * k;
    *a = v3(R(1) + sign * n.x * n.x * k, sign * c, -sign * n.x);
    *b = v3(c, sign + n.y * n.y * k, -n.y);
}

/* A 3x3 matrix, row-major: used for instance rotations. */
typedef struct { vec3 r[3]; } mat3;

static inline vec3 m3_apply(const mat3 *m, vec3 v) { return v3(v3_dot(m->r[0], v), v3_dot(m->r[1], v), v3_dot(m->r[2], v)); }
static inline vec3 m3_apply_t(const mat3 *m, vec3 v)
{
    return v3_add(v3_add(v3_scale(m->r[0], v.x), v3_scale(m->r[1], v.y)), v3_scale(m->r[2], v.z));
}

/* Rotation by Euler angles in degrees, applied about X, then Y, then Z. */
mat3 m3_rotation_xyz(vec3 degrees);

#endif
