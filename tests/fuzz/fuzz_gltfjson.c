/* fuzz_gltfjson.c - gltf_json.c's reading of a glTF's materials from its
 * JSON, on arbitrary bytes: the first byte's low bit says a .glb (its
 * header and chunks bounds-checked) or a .gltf's text.  Each material read
 * is then looked up by its own values: unless materials alike disagree,
 * that finds its own strength and specular (else abort: a finding).  The
 * same bytes' camera and lights (gltf_scene.c: the node hierarchy walked,
 * its matrices multiplied) must come out unit-length and finite where
 * they come out at all. */
#include <math.h>

#include "fuzz.h"
#include "model/gltf_json.h"
#include "model/gltf_scene.h"

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
    GltfScene g;
    if (gltf_scene_read(data + 1, size - 1, data[0] & 1, &g) == 0) {
        for (size_t i = 0; i < g.light_count; i++) {
            const double *d = g.lights[i].dir, *p = g.lights[i].pos;
            if (fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1) > 1e-6 || !isfinite(p[0] + p[1] + p[2]))
                abort();
        }
        if (g.has_camera && fabs(g.camera.fwd[0] * g.camera.fwd[0] + g.camera.fwd[1] * g.camera.fwd[1] +
                                 g.camera.fwd[2] * g.camera.fwd[2] - 1) > 1e-6)
            abort();
        gltf_scene_free(&g);
    }
    return 0;
}
