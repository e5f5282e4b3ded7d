/* mtl.h - Wavefront MTL material libraries (Kd, Ks, Ns per newmtl). */
#ifndef LANRAY_MTL_H
#define LANRAY_MTL_H

#include <stddef.h>

#include "err.h"
#include "material.h"

#define MTL_NAME_MAX 128

typedef struct {
    char (*names)[MTL_NAME_MAX];
    Material *mats;
    unsigned count;
} MtlLib;

/* Adds the materials of one library (in memory, NUL-terminated, modified in place). */
int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err);
int mtl_read(MtlLib *lib, const char *path, Err *err);
/* Index of a material by name, or -1. */
int mtl_find(const MtlLib *lib, const char *name);
void mtl_free(MtlLib *lib);

#endif
