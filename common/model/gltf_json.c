/* gltf_json.c - see gltf_json.h.  The JSON is parsed by json-c. */
#include "model/gltf_json.h"

#include <float.h>
#include <json-c/json.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A GLB's JSON chunk (glTF 2.0, 4.4: a 12-byte header, then chunks of a
 * u32 length and a u32 type, the JSON's first), in place; NULL where the
 * bytes do not hold one. */
static const uint8_t *glb_json(const uint8_t *b, size_t len, size_t *json_len)
{
    uint32_t head[5];
    if (len < sizeof head)
        return NULL;
    memcpy(head, b, sizeof head);
    if (memcmp(b, "glTF", 4) != 0 || head[1] != 2 || head[4] != 0x4E4F534Au /* "JSON" */)
        return NULL;
    if (head[3] > len - sizeof head)
        return NULL;
    *json_len = head[3];
    return b + sizeof head;
}

/* A .glb's header and JSON chunk, or a .gltf's whole text, from the file
 * at path into a buffer of the caller's (*len its size); NULL where it
 * cannot be read (Assimp, which read it, would have said why). */
uint8_t *gltf_file_json(const char *path, int glb, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    uint8_t head[20];
    size_t want = (size_t)size;
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0)
        want = 0;
    else if (glb) {
        uint32_t chunk;
        if (fread(head, 1, sizeof head, f) != sizeof head || fseek(f, 0, SEEK_SET) != 0)
            want = 0;
        memcpy(&chunk, head + 12, sizeof chunk);
        if (want && (uint64_t)chunk <= (uint64_t)size - sizeof head)
            want = sizeof head + chunk; /* gltf_materials_read checks the rest */
    }
    uint8_t *b = want ? malloc(want) : NULL;
    if (b && fread(b, 1, want, f) != want) {
        free(b);
        b = NULL;
    }
    fclose(f);
    *len = want;
    return b;
}

json_object *gltf_json_parse(const uint8_t *bytes, size_t len, int glb)
{
    size_t n = len;
    const uint8_t *text = glb ? glb_json(bytes, len, &n) : bytes;
    if (!text || n == 0 || n > INT_MAX)
        return NULL;
    json_tokener *tok = json_tokener_new();
    if (!tok)
        return NULL;
    json_object *root = json_tokener_parse_ex(tok, (const char *)text, (int)n);
    if (json_tokener_get_error(tok) != json_tokener_success) {
        json_object_put(root);
        root = NULL;
    }
    json_tokener_free(tok);
    return root;
}

json_object *gltf_member(json_object *o, const char *key)
{
    json_object *v = NULL;
    return o && json_object_is_type(o, json_type_object) && json_object_object_get_ex(o, key, &v) ? v : NULL;
}

int gltf_number(json_object *v, double *out)
{
    if (!v || !(json_object_is_type(v, json_type_double) || json_object_is_type(v, json_type_int)))
        return 0;
    *out = json_object_get_double(v);
    return isfinite(*out);
}


/* n numbers of array a into out, where a is an array of at least n
 * numbers that a float holds; else out keeps its defaults (a number past
 * a float's range became infinity, and a material no longer matched its
 * own values: fuzz_gltfjson) */
static void numbers(json_object *a, int n, float *out)
{
    if (!a || !json_object_is_type(a, json_type_array) || json_object_array_length(a) < (size_t)n)
        return;
    float v[4];
    for (int k = 0; k < n; k++) {
        double d;
        if (!gltf_number(json_object_array_get_idx(a, (size_t)k), &d) || fabs(d) > (double)FLT_MAX)
            return;
        v[k] = (float)d;
    }
    memcpy(out, v, (size_t)n * sizeof *v);
}

/* One material's values, glTF's defaults where it gives none. */
static int material_read(json_object *o, GltfMaterial *m)
{
    *m = (GltfMaterial){.emissive = {0, 0, 0}, .base = {1, 1, 1}, .strength = 1, .specular = 1};
    json_object *name = gltf_member(o, "name");
    m->name = strdup(name && json_object_is_type(name, json_type_string) ? json_object_get_string(name) : "");
    if (!m->name)
        return -1;
    numbers(gltf_member(o, "emissiveFactor"), 3, m->emissive);
    numbers(gltf_member(gltf_member(o, "pbrMetallicRoughness"), "baseColorFactor"), 3, m->base);
    double s;
    if (gltf_number(gltf_member(gltf_member(gltf_member(o, "extensions"), "KHR_materials_emissive_strength"), "emissiveStrength"), &s) &&
        s >= 0 && s <= 1e30)
        m->strength = (float)s;
    json_object *spec = gltf_member(gltf_member(o, "extensions"), "KHR_materials_specular");
    if (spec) { /* glTF's defaults: factor 1, colour factor 1 1 1 */
        double f = 1;
        float c[3] = {1, 1, 1};
        if (!gltf_number(gltf_member(spec, "specularFactor"), &f) || f < 0 || f > 1)
            f = 1;
        numbers(gltf_member(spec, "specularColorFactor"), 3, c);
        const float cmax = fmaxf(c[0], fmaxf(c[1], c[2]));
        m->specular = (float)f * (isfinite(cmax) && cmax >= 0 && cmax <= 1e6f ? cmax : 1);
    }
    return 0;
}

void gltf_materials_read(const uint8_t *bytes, size_t len, int glb, GltfMaterials *out)
{
    memset(out, 0, sizeof *out);
    json_object *root = gltf_json_parse(bytes, len, glb);
    json_object *mats = gltf_member(root, "materials");
    size_t count = mats && json_object_is_type(mats, json_type_array) ? json_object_array_length(mats) : 0;
    out->m = count ? calloc(count, sizeof *out->m) : NULL;
    for (size_t i = 0; out->m && i < count; i++) {
        if (material_read(json_object_array_get_idx(mats, i), &out->m[out->n]))
            break;
        out->extra += out->m[out->n].strength != 1 || out->m[out->n].specular != 1;
        out->n++;
    }
    json_object_put(root);
}

/* Whether two of Assimp's floats and the file's are one number (each read
 * the decimal its own way: the last bits may differ) */
static int same(float a, float b)
{
    return fabsf(a - b) <= 1e-6f * fmaxf(1, fmaxf(fabsf(a), fabsf(b)));
}

const GltfMaterial *gltf_material_of(const GltfMaterials *gm, const char *name, const float emissive[3],
                                     const float base[3], int *ambiguous)
{
    const GltfMaterial *found = NULL;
    for (size_t i = 0; i < gm->n; i++) {
        const GltfMaterial *m = &gm->m[i];
        int alike = strcmp(m->name, name) == 0;
        for (int k = 0; alike && k < 3; k++)
            alike = same(m->emissive[k], emissive[k]) && same(m->base[k], base[k]);
        if (!alike)
            continue;
        if (found && (m->strength != found->strength || m->specular != found->specular)) {
            *ambiguous = 1;
            return NULL;
        }
        found = m;
    }
    return found;
}

void gltf_materials_free(GltfMaterials *gm)
{
    for (size_t i = 0; i < gm->n; i++)
        free(gm->m[i].name);
    free(gm->m);
    memset(gm, 0, sizeof *gm);
}
