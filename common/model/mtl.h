/* mtl.h - Wavefront MTL material libraries: Kd, Ks, Ns and map_Kd per
 * newmtl, which Phong shading draws; Ka, Ke, Ni, d, Tr and illum, checked
 * and kept (MtlExtra); the other maps read past. */
#ifndef LANRAY_MTL_H
#define LANRAY_MTL_H

#include <stddef.h>

#include "base/err.h"
#include "geom/material.h"

#define MTL_NAME_MAX 128
#define MTL_PATH_MAX 1024

/* A material's diffuse texture (map_Kd): the file, relative to the
 * directory of its library and already joined to it (or, where it is not
 * there as written, the file file_find_near finds), and the options that
 * place it (-s scale and -o offset of u and v; -clamp on). */
typedef struct {
    char file[MTL_PATH_MAX]; /* empty: none */
    real s[2], o[2];
    int clamp;
    int found;               /* how file was found (FileFound, fileio.h) */
} MtlMap;

/* What a material says beyond the Phong terms: read, checked and kept, so
 * that a converter can say what it does not draw.  lanray's ambient term
 * takes Kd, not Ka (exporters write Ka as 0, as 1, or as Kd); reflection,
 * refraction, transparency and emission need rays lanray does not trace
 * yet, so such a material is drawn opaque with its Phong terms. */
typedef struct {
    vec3 ka, ke;   /* ambient and emitted colour (0 when not given) */
    real ni;       /* index of refraction, 0 when not given */
    real d;        /* opacity: d, or 1 - Tr; 1 when not given */
    int illum;     /* illumination model 0..10, -1 when not given */
    int line;      /* where its newmtl is, in library `file` */
    unsigned file;
} MtlExtra;

typedef struct {
    char (*names)[MTL_NAME_MAX];
    Material *mats;
    MtlMap *maps;
    MtlExtra *extra;
    unsigned count;
    char (*files)[MTL_PATH_MAX]; /* the libraries read, for messages */
    unsigned file_count;
} MtlLib;

/* Adds the materials of one library (in memory, NUL-terminated, modified in place). */
int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err);
int mtl_read(MtlLib *lib, const char *path, Err *err);
/* What a material asks for that lanray does not draw ("transparency (d
 * 0.4), glass (illum 7)"), into buf; 0 when nothing. */
int mtl_undrawn(const MtlExtra *x, char *buf, size_t size);
/* Index of a material by name, or -1. */
int mtl_find(const MtlLib *lib, const char *name);
void mtl_free(MtlLib *lib);

#endif
