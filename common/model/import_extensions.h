/* import_extensions.h - the glTF extensions Assimp 5.2.5 does not read,
 * applied to an imported mesh's materials (gltf_json.h finds each
 * material's values in the file's own JSON): KHR_materials_emissive_strength
 * (the emission times its strength) and KHR_materials_specular (the clear
 * coat of a non-metal's dielectric base times its specular). */
#ifndef LANRAY_IMPORT_EXTENSIONS_H
#define LANRAY_IMPORT_EXTENSIONS_H

#include <stddef.h>

#include "model/import.h"

struct aiScene;

/* Each material of out (made from scene sc, material i from sc's material
 * i) takes its extensions' values: from the glTF at path, or (path NULL)
 * in bytes[0..len); `hint` names the format ("gltf", "glb", in any case: a
 * file's extension without its dot; any other: nothing to do).  Emitting
 * materials that cannot be told apart are counted in st->strength_unknown. */
void import_gltf_extensions(const struct aiScene *sc, const char *path, const void *bytes, size_t len,
                            const char *hint, Mesh *out, ImportStats *st);

#endif
