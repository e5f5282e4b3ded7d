/* mesh.h - a plain triangle list: what the OBJ reader and procedural shapes
 * produce and what a Model is built from.  Attributes are per corner, so no
 * index buffers; arrays that no triangle uses are dropped by mesh_trim. */
#ifndef LANRAY_MESH_H
#define LANRAY_MESH_H

#include <stdint.h>

#include "base/err.h"
#include "shading/material.h"
#include "model/texture.h"

typedef struct {
    uint32_t tri_count, cap;
    vec3 *pos;      /* 3 per triangle */
    vec3 *nrm;      /* 3 per triangle, or NULL */
    real *uv;       /* 6 per triangle, or NULL */
    uint32_t *mat;  /* 1 per triangle, or NULL */
    vec3 *col;      /* 3 per triangle (vertex colours), or NULL */
    Material *materials;
    uint32_t material_count;
    Texture **textures;    /* what materials' `texture` indexes (owned), or NULL */
    uint32_t texture_count;
} Mesh;

/* The optional per-triangle arrays, as flags. */
enum { MESH_NORMALS = 1, MESH_UVS = 2, MESH_MATERIALS = 4, MESH_COLOURS = 8 };

/* Starts an empty mesh; the attribute arrays exist only for the kinds asked for (MESH_*). */
int mesh_init(Mesh *m, unsigned attrs, Err *err);
void mesh_free(Mesh *m);
/* Room for `tris` triangles in all, allocated at once (on huge pages when
 * big: bigmem.h), for a caller that knows the count. */
int mesh_reserve(Mesh *m, uint32_t tris, Err *err);
/* Appends one triangle; nrm, uv, col may be NULL when the mesh has no such array. */
int mesh_add(Mesh *m, const vec3 pos[3], const vec3 *nrm, const real *uv, const vec3 *col, uint32_t mat, Err *err);
int mesh_add_material(Mesh *m, Material mat, Err *err);
/* Takes ownership of t; its index into textures in *id. */
int mesh_add_texture(Mesh *m, Texture *t, uint32_t *id, Err *err);
/* The MESH_* arrays the mesh has. */
unsigned mesh_attrs(const Mesh *m);
/* Twice the area is zero or not finite: a triangle that can never be hit. */
int mesh_tri_is_degenerate(const vec3 p[3]);

#endif
