/* mtl.h - Wavefront MTL material libraries: Kd, Ks, Ns and map_Kd per newmtl
 * (Ka, Ni, d, Tr, illum and the other maps are checked and read past). */
#ifndef LANRAY_MTL_H
#define LANRAY_MTL_H

#include <stddef.h>

#include "err.h"
#include "material.h"

#define MTL_NAME_MAX 128
#define MTL_PATH_MAX 1024

/* A material's diffuse texture (map_Kd): the file, relative to the
 * directory of its library and already joined to it, and the options that
 * place it (-s scale and -o offset of u and v; -clamp on). */
typedef struct {
    char file[MTL_PATH_MAX]; /* empty: none */
    real s[2], o[2];
    int clamp;
} MtlMap;

typedef struct {
    char (*names)[MTL_NAME_MAX];
    Material *mats;
    MtlMap *maps;
    unsigned count;
} MtlLib;

/* Adds the materials of one library (in memory, NUL-terminated, modified in place). */
int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err);
int mtl_read(MtlLib *lib, const char *path, Err *err);
/* Index of a material by name, or -1. */
int mtl_find(const MtlLib *lib, const char *name);
void mtl_free(MtlLib *lib);

#endif
