/* gltf_json.h - what lanray reads from a glTF's own JSON where Assimp
 * 5.2.5 does not: each material's KHR_materials_emissive_strength (the
 * factor by which Blender's exporter, and others, carry an emission
 * brighter than 1; without it a glowing panel lights a path-traced scene
 * that many times too dimly) and KHR_materials_specular (how strong the
 * dielectric base's specular reflection is: Blender's exporter writes it
 * where a Principled BSDF's Specular is not 0.5, 0 for a matte one).
 *
 * Assimp numbers its materials in the order it meets them, not the
 * file's, so a material is found by what Assimp keeps of it: its name, its
 * emissive factor and its base colour factor.  Materials alike in all
 * three whose extensions' values differ cannot be told apart
 * (gltf_material_of says so). */
#ifndef LANRAY_GLTF_JSON_H
#define LANRAY_GLTF_JSON_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    char *name;      /* "" where the file gives none */
    float emissive[3], base[3];
    float strength;  /* 1 without the extension */
    float specular;  /* specularFactor x the largest of specularColorFactor: 1 without the extension */
} GltfMaterial;

typedef struct {
    GltfMaterial *m;
    size_t n;
    size_t extra; /* materials whose strength or specular is not 1 */
} GltfMaterials;

/* The materials of the glTF whose bytes are bytes[0..len): a .gltf's JSON
 * text, or with glb a .glb (its first chunk, the JSON, bounds-checked).
 * Bytes that are not such a file, or JSON that does not parse, give no
 * materials (Assimp, which read the file, says what is wrong with it). */
void gltf_materials_read(const uint8_t *bytes, size_t len, int glb, GltfMaterials *out);

/* The file's material that Assimp shows with this name, emissive factor
 * and base colour; NULL where none matches, or where several match whose
 * strengths or speculars differ (then *ambiguous set). */
const GltfMaterial *gltf_material_of(const GltfMaterials *gm, const char *name, const float emissive[3],
                                     const float base[3], int *ambiguous);

void gltf_materials_free(GltfMaterials *gm);

/* A .glb's header and JSON chunk (not its buffers), or a .gltf's whole
 * text, from the file at path: malloc'd, *len its size; NULL where it
 * cannot be read.  What gltf_materials_read and gltf_scene_read take. */
uint8_t *gltf_file_json(const char *path, int glb, size_t *len);

/* The JSON of a glTF's bytes (as gltf_materials_read takes them), parsed
 * by json-c (json_object_put it); NULL where there is none. */
struct json_object;
struct json_object *gltf_json_parse(const uint8_t *bytes, size_t len, int glb);
/* Object o's member key, or NULL (o NULL or not an object too). */
struct json_object *gltf_member(struct json_object *o, const char *key);
/* A finite number v into *out: 1, else 0. */
int gltf_number(struct json_object *v, double *out);

#endif
