/* ray.h - rays with the per-ray constants that traversal and intersection reuse.
 *
 * The inverse direction (slab test) and the shear constants of the watertight
 * triangle test (Woop, Benthin & Wald 2013) are computed once per ray, not
 * once per box or triangle. */
#ifndef LANRAY_RAY_H
#define LANRAY_RAY_H

#include "base/vec.h"

typedef struct {
    vec3 org, dir, inv;
    real tmin, tmax;
    int kx, ky, kz;  /* axis permutation: kz is the dominant direction axis */
    int near[3], far[3]; /* per axis: index of the entry/exit plane in a BVH node's reals */
    real sx, sy, sz; /* shear that maps the ray onto +z */
} Ray;

/* Fills *out: a ray whose inverse direction the caller computed (1/dir.x,
 * ... exactly; ray_make and the camera's packets, which divide eight at a
 * time).  Written in place: a Ray assembled on the stack and copied out
 * stalls on store forwarding, a tenth of a frame in the packet loops. */
static inline void ray_set(Ray *out, vec3 org, vec3 dir, vec3 inv, real tmin, real tmax)
{
    out->org = org;
    out->dir = dir;
    out->inv = inv;
    out->tmin = tmin;
    out->tmax = tmax;
    for (int a = 0; a < 3; a++) { /* a node is bmin[3], first, bmax[3], count: bmax starts at real 4 */
        out->near[a] = inv.e[a] >= R(0) ? a : a + 4;
        out->far[a] = inv.e[a] >= R(0) ? a + 4 : a;
    }
    int kz = v3_max_axis(v3_abs(dir));
    int kx = kz + 1 == 3 ? 0 : kz + 1;
    int ky = kx + 1 == 3 ? 0 : kx + 1;
    if (dir.e[kz] < R(0)) { /* keep the winding so that U, V, W keep their signs */
        int t = kx;
        kx = ky;
        ky = t;
    }
    out->kx = kx;
    out->ky = ky;
    out->kz = kz;
    /* reuse the reciprocal: the test stays watertight however S is rounded,
     * as long as every triangle sees the same S for this ray */
    out->sz = inv.e[kz];
    out->sx = dir.e[kx] * out->sz;
    out->sy = dir.e[ky] * out->sz;
}

/* Fills *out from an origin and a direction: where the ray is to be kept
 * (an array, a struct), in place of ray_make's copy (ray_set says why). */
static inline void ray_init(Ray *out, vec3 org, vec3 dir, real tmin, real tmax)
{
    /* 1/0 gives +-inf, which the slab test handles: a ray parallel to a slab
     * is either inside it for all t or never. */
    ray_set(out, org, dir, v3(R(1) / dir.x, R(1) / dir.y, R(1) / dir.z), tmin, tmax);
}

static inline Ray ray_make(vec3 org, vec3 dir, real tmin, real tmax)
{
    Ray r;
    ray_init(&r, org, dir, tmin, tmax);
    return r;
}

static inline vec3 ray_at(const Ray *r, real t) { return v3_madd(r->org, r->dir, t); }

#endif
