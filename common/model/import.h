/* import.h - models in the formats other tools write (PLY, STL, glTF 2.0,
 * and whatever else Assimp reads), through Assimp's C API, into a Mesh.
 *
 * OBJ keeps its own reader (obj.h): faster, and its errors name the line.
 * Every node's transform is applied (a glTF scene's hierarchy becomes one
 * triangle list); polygons are triangulated; points and lines are skipped
 * and counted.  Normals and texture coordinates come along where the file
 * has them, except STL's facet normals (STL has no other kind: such a model
 * is flat, and its geometric normals are the ones lanray computes), and
 * each material's diffuse and specular colour and shininess, and its
 * diffuse (glTF: base colour) texture, embedded in the file or beside it
 * (import_texture.h: a texture that cannot be read is a warning).  Vertex
 * colours (the first set) are kept where the file has no materials, as the
 * OBJ reader keeps them; otherwise they are dropped and counted.
 *
 * Assimp runs in a child process (fork): it crashes on some malformed
 * files, and a crash there becomes an error naming the file. */
#ifndef LANRAY_IMPORT_H
#define LANRAY_IMPORT_H

#include <stddef.h>

#include "model/mesh.h"
#include "model/obj.h"

typedef struct {
    unsigned long meshes, triangles, degenerate, points, lines, vertices;
    unsigned long coloured; /* vertices with a colour */
    int colours_ignored; /* the file had vertex colours and materials: the materials win (a warning) */
    unsigned long textures;         /* textures the materials use, read */
    unsigned long missing_textures; /* textures that could not be read (a warning each) */
    unsigned long warnings;
    unsigned long optics; /* materials with a metal's reflection, glass, see-through or emission */
    unsigned long smoothed; /* triangles given smooth normals (ObjOptions.smooth, a file without normals) */
    unsigned long strengths;        /* glTF materials whose emission took KHR_materials_emissive_strength */
    unsigned long strength_unknown; /* emitting glTF materials alike but for their strengths (a warning) */
    unsigned long speculars;        /* glTF materials whose coat took KHR_materials_specular */
    unsigned long specular_unknown; /* coated glTF materials alike but for their speculars (a warning) */
} ImportStats;

/* With ObjOptions.smooth, a file without normals gets them by mesh_smooth
 * (smooth.h): faces that meet at less than this smoothly, sharper edges
 * kept (a tessellated cylinder's facets meet at 11 degrees, a box's at 90). */
#define IMPORT_CREASE_DEG R(45)

/* Whether the name's extension is one the importer takes (not .obj or .tmd). */
int import_knows(const char *path);
/* Warnings go through opt as the OBJ reader's do (obj_warning: with
 * `strict` they are errors); opt may be NULL. */
int import_read(const char *path, const ObjOptions *opt, Mesh *out, ImportStats *stats, Err *err);
/* The same from bytes in memory; `hint` is the format's extension without
 * the dot ("ply", "stl", "glb", ...); `name` labels errors. */
int import_read_memory(const void *data, size_t len, const char *hint, const char *name, const ObjOptions *opt,
                       Mesh *out, ImportStats *stats, Err *err);

#endif
