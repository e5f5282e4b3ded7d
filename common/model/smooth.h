/* smooth.h - vertex normals by smoothing group: what a modeller shows for
 * an OBJ without normals whose faces say `s 1`, `s 2`, ...
 *
 * A corner of a triangle in group g (g != 0) gets the area-weighted mean of
 * the face normals of the triangles of group g around its vertex: faces of
 * one group meet smoothly, faces of two groups at a crease.  Group 0 (`s
 * off`, or no `s` at all) stays flat, unless `group0` asks for it to be
 * smoothed like any other group (obj2tmd --smooth).  Each normal is the sum
 * in the order of the triangles, so the same model gives the same bits. */
#ifndef LANRAY_SMOOTH_H
#define LANRAY_SMOOTH_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "base/vec.h"
#include "model/mesh.h"

/* The triangles, as a reader keeps them: triangle i's three vertex indices
 * at p[i * stride] and its group at group[i * stride] (stride in 32-bit
 * words: both may sit in one array of structs). */
typedef struct {
    const vec3 *v;
    uint32_t nv;
    const int32_t *p;
    const uint32_t *group;
    size_t stride;
    uint32_t ntri;
    int group0;
} SmoothInput;

/* The smooth normals (unnormalised sums) in *normals, and for each corner
 * (3 per triangle) the index of its normal in *corner, or SMOOTH_FLAT for
 * a corner of a flat triangle.  Both arrays are the caller's to free. */
#define SMOOTH_FLAT UINT32_MAX
int smooth_normals(const SmoothInput *in, uint32_t **corner, vec3 **normals, Err *err);

/* Whether triangle i is smoothed (its group, or group 0 with group0). */
static inline int smooth_tri(const SmoothInput *in, uint32_t i)
{
    return in->group[(size_t)i * in->stride] != 0 || in->group0;
}

/* A triangle soup's vertex normals (a Mesh without normals: STL, PLY,
 * OFF, ...): corners at the same position, bit for bit, share a vertex,
 * and each corner's normal is the area-weighted sum of the face normals
 * around its vertex that lie within crease_deg of its own face's, in the
 * triangles' order (an edge sharper than that stays sharp; a vertex of
 * more than SMOOTH_CREASE_MAX corners smooths them all, the crease
 * unchecked, so that no file costs the square of its size).  m gets a
 * normals array. */
#define SMOOTH_CREASE_MAX 1024
int mesh_smooth(Mesh *m, real crease_deg, Err *err);

#endif
