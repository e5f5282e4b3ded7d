/* gltf_scene.h - what a glTF says besides its meshes: its camera and its
 * lights (KHR_lights_punctual), placed by its nodes, read from the file's
 * own JSON (json-c): what Blender's exporter writes of a scene, so that
 * `lanray-render scene.glb` shows it as it was made.
 *
 * The nodes of the file's scene (`scene`, else the first) are walked from
 * their roots, each placed by its parent's matrix times its own (`matrix`,
 * or translation x rotation x scale), as the meshes Assimp flattens are
 * (aiProcess_PreTransformVertices), in the file's frame (+y up, as
 * lanray's).  A camera and a light look down their node's -z, a camera's
 * up its +y (glTF 2.0, 3.10 and the extension).  At most GLTF_MAX_VISITS
 * nodes are visited (a file whose nodes share children could make the walk
 * exponential) and GLTF_MAX_DEPTH deep. */
#ifndef LANRAY_GLTF_SCENE_H
#define LANRAY_GLTF_SCENE_H

#include <stddef.h>
#include <stdint.h>

#define GLTF_MAX_VISITS 65536
#define GLTF_MAX_DEPTH 64
#define GLTF_MAX_LIGHTS 4096

typedef enum { GLTF_POINT = 0, GLTF_SPOT = 1, GLTF_DIRECTIONAL = 2 } GltfLightKind;

typedef struct {
    GltfLightKind kind;
    double pos[3], dir[3]; /* dir: the way the light travels, unit length */
    double color[3];
    double intensity;      /* candela (point, spot) or lux (directional) */
    double inner, outer;   /* spot: the cone's half angles, radians */
} GltfLight;

typedef struct {
    int ortho;             /* orthographic: xmag is half the view's width */
    double pos[3], fwd[3], up[3]; /* fwd, up: unit length */
    double yfov;           /* perspective: the vertical field of view, radians */
    double xmag;
    double aspect;         /* width over height; 0 where the file gives none */
} GltfCamera;

typedef struct {
    GltfLight *lights;
    size_t light_count;
    int has_camera;        /* the first node with a camera, in the walk's order */
    GltfCamera camera;
} GltfScene;

/* The camera and lights of the glTF whose bytes are bytes[0..len): a
 * .gltf's JSON text, or with glb a .glb's (its JSON chunk, bounds-checked).
 * What is missing or malformed is left out (a light of an unknown type, a
 * node's index out of range, a number past a double's range); 0, or -1
 * out of memory. */
int gltf_scene_read(const uint8_t *bytes, size_t len, int glb, GltfScene *out);
void gltf_scene_free(GltfScene *s);

#endif
