/* tmd.h - the .tmd model file: a serialised Model (BVH + triangles + attributes).
 *
 * Layout (docs/tmd.md): a 64-byte header with magic, version, byte-order mark,
 * flags and counts, then the sections in a fixed order, all numbers 32-bit in
 * the writer's byte order.  Geometry is float32 in files; a double-precision
 * build sends models to its clients with flag TMD_WIDE (float64), so that a
 * client renders the very numbers lanray-render does. */
#ifndef LANRAY_TMD_H
#define LANRAY_TMD_H

#include <stddef.h>

#include "model/model.h"

#define TMD_MAGIC "LRAYTMD"
/* The version written is the lowest that holds the model, so that older
 * readers take every file they can: 4 with reflecting, refracting or
 * emitting materials, 3 with vertex colours, 2 with textures, 1 otherwise. */
#define TMD_VERSION 4u
#define TMD_VERSION_COLOURS 3u
#define TMD_VERSION_TEXTURES 2u
#define TMD_VERSION_PLAIN 1u
#define TMD_BOM 0x01020304u
#define TMD_HEADER_BYTES 64u
#define TMD_HAS_NORMALS 1u
#define TMD_HAS_UVS 2u
#define TMD_HAS_MATERIALS 4u
#define TMD_WIDE 8u /* numbers are float64 */
#define TMD_HAS_TEXTURES 16u /* version 2: materials name textures carried at the end of the file */
#define TMD_HAS_COLOURS 32u  /* version 3: vertex colours, after the material ids */
#define TMD_HAS_OPTICS 64u   /* version 4: each material's reflection, refraction and emission */
#define TMD_MAX_FILE_BYTES ((size_t)1 << 31)

int tmd_write(const char *path, const Model *m, Err *err);
int tmd_read(const char *path, Model **out, Err *err);
/* In-memory forms, for tests and fuzzing; `name` labels error messages. */
/* wide: float64 numbers (TMD_WIDE), the model's own values in a double build. */
int tmd_encode(const Model *m, int wide, void **data, size_t *len, Err *err);
int tmd_decode(const void *data, size_t len, const char *name, Model **out, Err *err);

#endif
