/* fuzz_gltfjson.c - gltf_json.c's reading of a glTF's materials from its
 * JSON, on arbitrary bytes: the first byte's low bit says a .glb (its
 * header and chunks bounds-checked) or a .gltf's text.  Each material read
 * is then looked up by its own values: unless materials alike disagree,
 * that finds its own strength and specular (else abort: a finding). */
#include "fuzz.h"
#include "model/gltf_json.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    GltfMaterials gm;
    gltf_materials_read(data + 1, size - 1, data[0] & 1, &gm);
    for (size_t i = 0; i < gm.n; i++) {
        int unknown = 0;
        const GltfMaterial *m = gltf_material_of(&gm, gm.m[i].name, gm.m[i].emissive, gm.m[i].base, &unknown);
        if (!unknown && (!m || m->strength != gm.m[i].strength || m->specular != gm.m[i].specular))
            abort();
        if (!(gm.m[i].specular >= 0 && gm.m[i].specular <= 1e6f))
            abort();
    }
    gltf_materials_free(&gm);
    return 0;
}
