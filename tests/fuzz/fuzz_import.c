/* fuzz_import.c - the Assimp path (import.c) on arbitrary bytes: the first
 * byte picks the format (PLY, STL, glTF binary, OFF, COLLADA, glTF text),
 * the rest is the file; a glTF's embedded images are decoded as textures,
 * and its JSON read again for its emission strengths (gltf_json.c). */
#include "fuzz.h"
#include "model/import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const hints[] = {"ply", "stl", "glb", "off", "dae", "gltf"};
    if (size < 1)
        return 0;
    Mesh m;
    Err err;
    if (import_read_memory(data + 1, size - 1, hints[data[0] % 6], "fuzz", NULL, &m, NULL, &err) == 0)
        mesh_free(&m);
    return 0;
}
