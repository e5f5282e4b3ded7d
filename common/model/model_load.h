/* model_load.h - a model from a file: an OBJ (parsed, its BVH built) or a
 * .tmd (read as stored, or rebuilt).  The scene parser and the model
 * preview (lanray-render model.obj) load models through it. */
#ifndef LANRAY_MODEL_LOAD_H
#define LANRAY_MODEL_LOAD_H

#include "model/model.h"

/* The file's name decides (model_format): .obj, .tmd, or an import.  opt builds an OBJ's tree; with
 * rebuild, a .tmd's tree is built again with it.  smooth: vertex normals
 * for an OBJ without them (refused for a .tmd). */
int model_load(const char *path, const BvhOptions *opt, int rebuild, int smooth, Model **out, Err *err);
/* Where the readers' warnings go (a texture that cannot be read, lines of
 * a kind skipped; obj.h), one line each: a program's main sets it once,
 * before it loads anything; without it (tests, fuzzers) they are only
 * counted.  A model rendered straight from its OBJ once lost its missing
 * texture without a word, where obj2tmd named it. */
void model_load_warnings(void (*warn)(void *ctx, const char *msg), void *ctx);
/* Whether model_load takes this file name. */
int model_load_knows(const char *path);
/* What a file's name says it is, the extension in any case: lanray's own
 * OBJ reader, a .tmd, a format Assimp reads (import.h), or none of them. */
typedef enum { MODEL_FORMAT_UNKNOWN, MODEL_FORMAT_OBJ, MODEL_FORMAT_TMD, MODEL_FORMAT_IMPORT } ModelFormat;
ModelFormat model_format(const char *path);

#endif
