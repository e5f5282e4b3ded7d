/* import_emissive.h - glTF's KHR_materials_emissive_strength, which
 * Assimp 5.2.5 does not read, applied to an imported mesh's materials
 * (gltf_json.h finds each material's strength in the file's own JSON). */
#ifndef LANRAY_IMPORT_EMISSIVE_H
#define LANRAY_IMPORT_EMISSIVE_H

#include <stddef.h>

#include "model/import.h"

struct aiScene;

/* Each emitting material of out (made from scene sc, material i from sc's
 * material i) takes its emission times its strength: from the glTF at
 * path, or (path NULL) in bytes[0..len); `hint` names the format ("gltf",
 * "glb", in any case: a file's extension without its dot; any other:
 * nothing to do).  Materials that cannot be told apart
 * are counted in st->strength_unknown. */
void import_emissive_strengths(const struct aiScene *sc, const char *path, const void *bytes, size_t len,
                               const char *hint, Mesh *out, ImportStats *st);

#endif
