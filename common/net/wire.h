/* wire.h - the scene on the wire.
 *
 * A scene is serialised once per frame (docs/protocol.md): header with magic,
 * version and byte-order mark, then only what the scene has.  Models and
 * textures are not inside: the scene names them by the SHA-256 of their
 * ASSET payload, which a client receives once per connection and caches, so
 * an UPDATE for a scene with millions of triangles stays small. */
#ifndef LANRAY_WIRE_H
#define LANRAY_WIRE_H

#include "net/asset.h"
#include "base/cursor.h"
#include "net/msg.h"
#include "scene/world.h"

#define WIRE_MAGIC 0x4353524cu /* "LRSC" */
#define WIRE_VERSION 26u /* 2: the output encoding (linear or sRGB), a plane's texture mapping;
                         * 3: the extras word, reflection, refraction and emission;
                         * 4: texture filters trilinear and anisotropic, the sampling
                         * (extras 16), what a ray cut at the depth limit returns;
                         * 5: every item by its field table, with group bits in place of
                         * the extras word; 6: settings light_sampling; 7: settings integrator;
                         * 8: settings emitter_sampling, roulette; material checker;
                         * 9: settings contrast; 10: settings light_samples;
                         * 11: material mask, cutoff (a model's cutouts, in its asset);
                         * 12: material normal_map, normal_scale (a model's, in its asset);
                         * 13: material emit_map, emit_mapped (likewise);
                         * 14: material metal_map, metal_mapped (likewise);
                         * 15: material ao_map, ao_strength (likewise); material coat,
                         *     coat_roughness (group 11, unnumbered);
                         * 16: material reflect_edge (group 12);
                         * 17: material mask_blend (group 13: a model's, in its asset);
                         * 18: the environment after the background (its group: texture,
                         *     strength, rotate);
                         * 19: settings denoise (group 3, the output's);
                         * 20: settings batch (group 2, the sampling's: on the wire only);
                         * 21: settings jitter (group 2, on the wire only);
                         * 22: settings guides (group 3, on the wire only);
                         * 23: settings clamp_indirect (group 2);
                         * 24: settings tonemap (group 3, the output's);
                         * 25: settings filter_glossy (group 2);
                         * 26: settings caustics (group 2) */

/* Serialises s, checked (scene_check); model_assets[i] / texture_assets[i] are the assets of
 * s->models[i] / s->textures[i]. */
int wire_encode_scene(const Scene *s, const Asset *model_assets, const Asset *texture_assets, Sink *out, Err *err);

/* Decodes a scene whose models and textures are in the cache; the scene
 * borrows them and comes back checked (scene_check). */
int wire_decode_scene(const void *data, size_t len, const AssetCache *cache, Scene **out, Err *err);

/* A frame's view on the wire: the camera and the settings by their tables,
 * as the scene's header has them (a few hundred bytes at most). */
int wire_encode_view(const View *v, Sink *out, Err *err);
/* Decodes and checks a view (scene_check_view); the bytes must be exactly it. */
int wire_decode_view(const void *data, size_t len, View *out, Err *err);

#endif
