/* intersect.h - ray/primitive intersection: the innermost hot path.
 *
 * Each routine returns 1 and writes t (and surface coordinates) when the ray
 * hits inside (r->tmin, tmax), else 0.  All are static inline so that the BVH
 * traversal loops compile to straight-line code. */
#ifndef LANRAY_INTERSECT_H
#define LANRAY_INTERSECT_H

#include "geom/aabb.h"
#include "geom/ray.h"

/* A triangle's vertices, kept apart from its shading attributes so that the
 * traversal touches only these 9 numbers. */
typedef struct {
    real v[3][3];
} Tri;

static inline vec3 tri_vertex(const Tri *t, int i) { return v3(t->v[i][0], t->v[i][1], t->v[i][2]); }

/* The box of a triangle's corners (what every tree over triangles is built on). */
static inline Aabb tri_box(const Tri *t)
{
    Aabb b = aabb_point(tri_vertex(t, 0));
    aabb_grow(&b, tri_vertex(t, 1));
    aabb_grow(&b, tri_vertex(t, 2));
    return b;
}

/* Watertight ray/triangle test (Woop, Benthin & Wald, JCGT 2013).  The ray is
 * sheared onto +z, so the three edge functions are evaluated in the same 2D
 * frame for every triangle sharing an edge: a ray through a shared edge or
 * vertex hits at least one of the triangles, never none.  Edge functions that
 * come out exactly zero are recomputed in double, as the paper prescribes.
 * tri_solve gives the hit beyond r->tmin with no far limit; on a hit, *b1
 * and *b2 are the barycentric weights of vertices 1 and 2.  The wide
 * kernels (wide_kernel.h) repeat these operations lane by lane. */
static inline __attribute__((always_inline)) int tri_solve(const Ray *r, const Tri *tri, real *t_out, real *b1, real *b2)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const real ax = tri->v[0][kx] - r->org.e[kx], ay = tri->v[0][ky] - r->org.e[ky], az = tri->v[0][kz] - r->org.e[kz];
    const real bx = tri->v[1][kx] - r->org.e[kx], by = tri->v[1][ky] - r->org.e[ky], bz = tri->v[1][kz] - r->org.e[kz];
    const real cx = tri->v[2][kx] - r->org.e[kx], cy = tri->v[2][ky] - r->org.e[ky], cz = tri->v[2][kz] - r->org.e[kz];
    const real Ax = ax - r->sx * az, Ay = ay - r->sy * az;
    const real Bx = bx - r->sx * bz, By = by - r->sy * bz;
    const real Cx = cx - r->sx * cz, Cy = cy - r->sy * cz;
    real U = Cx * By - Cy * Bx;
    real V = Ax * Cy - Ay * Cx;
    real W = Bx * Ay - By * Ax;
#ifndef LANRAY_DOUBLE
    if (__builtin_expect(U == R(0) || V == R(0) || W == R(0), 0)) {
        U = (real)((double)Cx * (double)By - (double)Cy * (double)Bx);
        V = (real)((double)Ax * (double)Cy - (double)Ay * (double)Cx);
        W = (real)((double)Bx * (double)Ay - (double)By * (double)Ax);
    }
#endif
    if ((U < R(0) || V < R(0) || W < R(0)) && (U > R(0) || V > R(0) || W > R(0)))
        return 0;
    const real det = U + V + W;
    if (det == R(0))
        return 0;
    const real T = U * (r->sz * az) + V * (r->sz * bz) + W * (r->sz * cz);
    /* compare the distance itself, not T against tmax*det: the two round
     * differently, and the closest of two near-coincident hits would then
     * depend on the order the triangles are visited */
    const real inv = R(1) / det;
    const real t = T * inv;
    if (!(t > r->tmin))
        return 0;
    *t_out = t;
    *b1 = V * inv;
    *b2 = W * inv;
    return 1;
}

/* The hit with r->tmin < t < tmax, if any. */
static inline __attribute__((always_inline)) int tri_intersect(const Ray *r, const Tri *tri, real tmax, real *t_out, real *b1, real *b2)
{
    return tri_solve(r, tri, t_out, b1, b2) && *t_out < tmax;
}

/* Sphere test in the numerically careful form of Haines et al., "Precision
 * Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7): the
 * discriminant is computed from the distance of the centre to the ray, which
 * does not cancel catastrophically for distant or small spheres. */
static inline __attribute__((always_inline)) int sphere_intersect(const Ray *r, vec3 centre, real radius, real tmax, real *t_out)
{
    const vec3 f = v3_sub(r->org, centre);
    const real a = v3_dot(r->dir, r->dir);
    const real b = -v3_dot(f, r->dir);
    const vec3 l = v3_madd(f, r->dir, b / a); /* centre-to-closest-point vector */
    const real disc = radius * radius - v3_dot(l, l);
    if (disc < R(0))
        return 0;
    const real q = b + copysign(sqrt(a * disc), b);
    /* roots q/a and c/q with c = |f|^2 - r^2: no subtraction of near-equal terms */
    real t0 = q / a;
    real t1 = q != R(0) ? (v3_dot(f, f) - radius * radius) / q : t0;
    if (t0 > t1) {
        real tmp = t0;
        t0 = t1;
        t1 = tmp;
    }
    if (t0 > r->tmin && t0 < tmax) {
        *t_out = t0;
        return 1;
    }
    if (t1 > r->tmin && t1 < tmax) {
        *t_out = t1;
        return 1;
    }
    return 0;
}

/* Infinite plane through `point` with normal `n`.  Rays parallel to the plane
 * (denominator zero, or too small to give a finite t) miss. */
static inline int plane_intersect(const Ray *r, vec3 point, vec3 n, real tmax, real *t_out)
{
    const real denom = v3_dot(r->dir, n);
    if (denom == R(0))
        return 0;
    const real t = v3_dot(v3_sub(point, r->org), n) / denom;
    if (!(t > r->tmin && t < tmax)) /* also rejects NaN and inf */
        return 0;
    *t_out = t;
    return 1;
}

#endif
