/* obj.h - Wavefront OBJ reader producing a Mesh.
 *
 * Supports v (with or without w and r g b vertex colours), vt, vn, f in all four index forms (v, v/t, v//n, v/t/n) with
 * negative (relative) indices, polygons (fan-triangulated), o/g, mtllib and
 * usemtl, and s (smoothing groups: smooth normals where the file has
 * none, smooth.h).  Keeps only attributes the faces use; zero-area faces are dropped
 * and counted.  Vertex colours become the mesh's per-vertex diffuse colour
 * when no face uses a material (vertices without one get the default
 * material's); colours below 0 are an error.
 *
 * Lenient where exporters are sloppy, strict where the data is wrong.  With
 * a warning naming file and line (and a count in ObjStats): a usemtl of an
 * undefined material or without a name (the default material), a missing
 * material library (default materials), a library or texture that is
 * not where the file says but is found by its file name (file_find_near:
 * models moved from the machine that wrote them), a material asking for
 * transparency, glass, reflection or emission (drawn opaque with its Phong
 * terms; the warning names the MTL file and line), vertex colours where faces use
 * materials (ignored: the materials win) or given as whole numbers up to 255
 * (read as 0..255), and
 * the elements a triangle renderer cannot use (lines, points, free-form
 * curves and surfaces, merging groups, level of detail,
 * display attributes, unknown keywords: skipped, counted by kind; one
 * warning per kind).  Also read: UTF-8 and UTF-16 files with a byte-order
 * mark, CRLF, tabs, '\' line continuations, '\' in paths, names with spaces.
 * Errors, with file and line: an index of 0 or out of range, a face of
 * fewer than 3 corners, a number that is not one.  `strict` makes every
 * warning an error. */
#ifndef LANRAY_OBJ_H
#define LANRAY_OBJ_H

#include <stddef.h>

#include "model/mesh.h"

typedef struct {
    int smooth; /* smooth the faces outside any smoothing group (smooth.h) where the file has no normals */
    int strict; /* every warning is an error */
    /* where warnings go, one line each ("file:line: what"), or NULL */
    void (*warn)(void *ctx, const char *msg);
    void *warn_ctx;
} ObjOptions;

/* What a reader skips, by kind (obj_skip_name). */
typedef enum {
    OBJ_SKIP_LINE,      /* l */
    OBJ_SKIP_POINT,     /* p */
    OBJ_SKIP_FREEFORM,  /* vp, cstype, deg, curv, surf, ... */
    OBJ_SKIP_MERGING,   /* mg */
    OBJ_SKIP_LOD,       /* lod */
    OBJ_SKIP_DISPLAY,   /* usemap, maplib, shadow_obj, trace_obj, ... */
    OBJ_SKIP_UNKNOWN,   /* anything else */
    OBJ_SKIP_KINDS
} ObjSkip;
const char *obj_skip_name(ObjSkip k);

typedef struct {
    unsigned long vertices, faces, triangles, degenerate, groups;
    unsigned long smoothing;         /* s statements */
    unsigned long smoothed;          /* triangles given smooth normals (their smoothing group, or --smooth) */
    unsigned long warnings;
    unsigned long skipped[OBJ_SKIP_KINDS];
    unsigned long coloured;          /* vertices with colours */
    int colours;                     /* the mesh keeps them (a model without materials) */
    int colours_ignored;             /* they were dropped: the model has materials */
    unsigned long undefined_mtl;     /* usemtl of a material no library defines, or of none */
    unsigned long missing_mtllib;    /* material libraries that could not be read */
    unsigned long missing_textures;  /* map_Kd and map_d files that could not be read */
    unsigned long found_elsewhere;   /* libraries and textures found by file name, not where written */
    unsigned long optics_mtl;        /* used materials with reflection, glass, transparency or emission */
    unsigned long emit_strengths;    /* glTF materials whose emission took KHR_materials_emissive_strength */
    unsigned long speculars;         /* glTF materials whose clear coat took KHR_materials_specular */
} ObjStats;

/* One warning under these options, for every reader that takes them (the
 * importer too): with `strict` an error in err ("... (an error with
 * --strict)"), returning -1; else counted in *count and handed to the
 * callback. */
int obj_warning(const ObjOptions *opt, unsigned long *count, Err *err, const char *msg);

/* Parses OBJ text (NUL-terminated, modified in place).  `name` labels errors;
 * `dir` is where mtllib files are looked up (NULL: mtllib is an error). */
int obj_parse(char *text, size_t len, const char *name, const char *dir, const ObjOptions *opt, Mesh *out,
              ObjStats *stats, Err *err);
int obj_read(const char *path, const ObjOptions *opt, Mesh *out, ObjStats *stats, Err *err);

#endif
