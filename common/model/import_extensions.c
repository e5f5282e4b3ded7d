/* import_extensions.c - see import_extensions.h. */
#include "model/import_extensions.h"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "model/gltf_json.h"

/* What Assimp keeps of a material that the file's JSON is matched by. */
static void assimp_values(const struct aiMaterial *am, struct aiString *name, float emissive[3], float base[3])
{
    struct aiColor4D c = {0, 0, 0, 1};
    if (aiGetMaterialString(am, AI_MATKEY_NAME, name) != aiReturn_SUCCESS)
        name->length = 0, name->data[0] = 0;
    aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &c);
    emissive[0] = c.r, emissive[1] = c.g, emissive[2] = c.b;
    c = (struct aiColor4D){1, 1, 1, 1};
    aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c);
    base[0] = c.r, base[1] = c.g, base[2] = c.b;
}

/* Material m takes the file's g: its emission times g's strength (st
 * counts it), its coat times g's specular (at most 1). */
static void apply(const GltfMaterial *g, Material *m, ImportStats *st)
{
    if (material_emits(m) && g->strength != 1) {
        st->strengths++;
        m->ke = v3_scale(m->ke, (real)g->strength);
        if (!material_emits(m)) /* a strength of 0: no emission, nor its texture */
            m->emit_map = 0, m->emit_mapped = 0;
    }
    if (material_coats(m) && g->specular != 1) {
        st->speculars++;
        m->coat = real_min(R(1), m->coat * (real)g->specular);
        if (!material_coats(m))
            m->coat_roughness = 0;
    }
}

void import_gltf_extensions(const struct aiScene *sc, const char *path, const void *bytes, size_t len,
                            const char *hint, Mesh *out, ImportStats *st)
{
    const int glb = strcasecmp(hint, "glb") == 0;
    if (!glb && strcasecmp(hint, "gltf") != 0)
        return;
    uint8_t *own = path ? gltf_file_json(path, glb, &len) : NULL;
    GltfMaterials gm;
    gltf_materials_read(path ? own : bytes, path && !own ? 0 : len, glb, &gm);
    for (unsigned i = 0; gm.extra && i < sc->mNumMaterials && i < out->material_count; i++) {
        Material *m = &out->materials[i];
        if (!material_emits(m) && !material_coats(m))
            continue;
        struct aiString name;
        float e[3], b[3];
        assimp_values(sc->mMaterials[i], &name, e, b);
        int unknown = 0;
        const GltfMaterial *g = gltf_material_of(&gm, name.data, e, b, &unknown);
        st->strength_unknown += (unsigned long)(unknown && material_emits(m));
        st->specular_unknown += (unsigned long)(unknown && material_coats(m));
        if (g)
            apply(g, m, st);
    }
    gltf_materials_free(&gm);
    free(own);
}
