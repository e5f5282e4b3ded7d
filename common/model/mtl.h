/* mtl.h - Wavefront MTL material libraries: Kd, Ks, Ns and map_Kd per
 * newmtl, which Phong shading draws; map_d, a cutout's mask; norm (and
 * bump or map_Bump where it is one), a normal map; map_Ke, the emission's
 * texture; Ka, Ke, Ni, d, Tr and
 * illum, checked and kept (MtlExtra); the other maps read past. */
#ifndef LANRAY_MTL_H
#define LANRAY_MTL_H

#include <stddef.h>

#include "base/err.h"
#include "shading/material.h"

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
    real bm;                 /* -bm: a bump or normal map's strength (1 when not given) */
} MtlMap;

/* Where a material's normal map came from: `norm` (the PBR extension's
 * normal map), or `bump` / `map_Bump`, which exporters use for normal maps
 * (Blender) and for grey height maps (Sponza) alike: read as a normal map
 * unless its image is grey. */
typedef enum { MTL_NORMALS_NONE = 0, MTL_NORMALS_BUMP = 1, MTL_NORMALS_NORM = 2 } MtlNormals;

/* What a material says beyond the Phong terms: read, checked and kept, and
 * mapped onto lanray's reflection, refraction and emission by mtl_optics.
 * lanray's ambient term takes Kd, not Ka (exporters write Ka as 0, as 1, or
 * as Kd). */
typedef struct {
    vec3 ka, ke;   /* ambient and emitted colour (0 when not given) */
    real ni;       /* index of refraction, 0 when not given */
    real d;        /* opacity: d, or 1 - Tr; 1 when not given */
    int illum;     /* illumination model 0..10, -1 when not given */
    int line;      /* where its newmtl is, in library `file` */
    unsigned file;
    int ke_given;  /* a Ke line was read (map_Ke without one glows by its texture alone) */
} MtlExtra;

typedef struct {
    char (*names)[MTL_NAME_MAX];
    Material *mats;
    MtlMap *maps;
    MtlMap *dmaps; /* map_d: where its opacity (alpha, or grey level) is under 0.5, a hole */
    MtlMap *nmaps; /* norm, bump, map_Bump: a normal map (nkinds says which) */
    MtlMap *emaps; /* map_Ke: the emission's texture, multiplying Ke */
    unsigned char *nkinds; /* MtlNormals */
    MtlExtra *extra;
    unsigned count;
    char (*files)[MTL_PATH_MAX]; /* the libraries read, for messages */
    unsigned file_count;
} MtlLib;

/* Adds the materials of one library (in memory, NUL-terminated, modified in place). */
int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err);
int mtl_read(MtlLib *lib, const char *path, Err *err);
/* Maps what a material says beyond the Phong terms onto m: illum 3, 5 and
 * 8 (reflection) make a mirror reflecting Ks; illum 4, 6, 7 and 9 (glass) a
 * dielectric of index Ni (1.5 when not given) whose diffuse colour keeps
 * the share d (opacity; none when d is not given) and which transmits the
 * rest; a dissolve d < 1 otherwise is a blend with what is behind (index
 * 1: unbent), diffuse and specular times d; Ke is emission.  Ka is not
 * used (the ambient term takes the diffuse colour).  1 when it mapped
 * anything. */
int mtl_optics(const MtlExtra *x, Material *m);
/* Index of a material by name, or -1. */
int mtl_find(const MtlLib *lib, const char *name);
void mtl_free(MtlLib *lib);

#endif
