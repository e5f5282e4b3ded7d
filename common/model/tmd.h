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
/* Version 6 is written: materials by the material's field table (field.h),
 * as on the wire.  Versions 1 to 5 are read (5: the file's length and a
 * CRC-32 of all of it in the header, textures as their image files' bytes;
 * 4: reflecting, refracting or emitting materials, 3: vertex colours, 2:
 * textures as float texels, 1: the rest). */
#define TMD_VERSION 6u
#define TMD_VERSION_FIELDS 6u
#define TMD_VERSION_FORMS 5u
#define TMD_VERSION_OPTICS 4u
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
#define TMD_HAS_OPTICS 64u   /* versions 4 and 5: each material's reflection, refraction and emission */
#define TMD_MAX_FILE_BYTES ((size_t)1 << 31)
#define TMD_LENGTH_AT 48u   /* version 5: u32 the file's length */
#define TMD_CHECKSUM_AT 52u /* version 5: u32 CRC-32 of the file, this field read as 0 */

int tmd_write(const char *path, const Model *m, Err *err);
int tmd_read(const char *path, Model **out, Err *err);
/* In-memory forms, for tests and fuzzing; `name` labels error messages. */
/* wide: float64 numbers (TMD_WIDE), the model's own values in a double build. */
int tmd_encode(const Model *m, int wide, void **data, size_t *len, Err *err);
int tmd_decode(const void *data, size_t len, const char *name, Model **out, Err *err);
/* The checksum a version-5 file carries at TMD_CHECKSUM_AT (len >= 64). */
uint32_t tmd_checksum(const void *data, size_t len);

#endif
