/* obj.h - Wavefront OBJ reader producing a Mesh.
 *
 * Supports v, vt, vn, f in all four index forms (v, v/t, v//n, v/t/n) with
 * negative (relative) indices, polygons (fan-triangulated), o/g, mtllib and
 * usemtl.  Keeps only attributes the faces use; zero-area faces are dropped
 * and counted. */
#ifndef LANRAY_OBJ_H
#define LANRAY_OBJ_H

#include <stddef.h>

#include "mesh.h"

typedef struct {
    int smooth; /* compute area-weighted vertex normals where the file has none */
} ObjOptions;

typedef struct {
    unsigned long vertices, faces, triangles, degenerate, groups;
} ObjStats;

/* Parses OBJ text (NUL-terminated, modified in place).  `name` labels errors;
 * `dir` is where mtllib files are looked up (NULL: mtllib is an error). */
int obj_parse(char *text, size_t len, const char *name, const char *dir, const ObjOptions *opt, Mesh *out,
              ObjStats *stats, Err *err);
int obj_read(const char *path, const ObjOptions *opt, Mesh *out, ObjStats *stats, Err *err);

#endif
