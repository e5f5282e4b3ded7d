/* world.h - what rays are traced against, built from a scene description.
 *
 * A Scene (scene.h) is the description: items as a file, the wire or code
 * gave them, checked by scene_check.  A World is built from one
 * (world_build) and holds what the inner loop reads, in the form it reads
 * it: the planes' unit normals and texture axes, the instances' rotations
 * and world boxes, the lights' axes, spot cones and lamps, the top-level
 * BVH, and the features the scene uses.  Spheres, scene triangles,
 * materials, textures and models are read from the description in place:
 * they need nothing derived.  A world never changes its description; the
 * description must outlive it and stay unchanged while it is used.
 *
 * Beside it, the frame's view: the camera and the quality settings, which a
 * frame may change without a new world (world_set_view checks them and
 * nothing else). */
#ifndef LANRAY_WORLD_H
#define LANRAY_WORLD_H

#include <stdatomic.h>

#include "bvh/bvh4.h"
#include "scene/environment.h"
#include "scene/scene.h"

enum {
    FEAT_TEXTURES = 1 << 0,
    FEAT_SMOOTH = 1 << 1,
    FEAT_SPOT = 1 << 2,
    FEAT_ATTENUATION = 1 << 3,
    FEAT_PLANES = 1 << 4,
    FEAT_SHADOWS = 1 << 5,
    FEAT_SPECULAR = 1 << 6,
    FEAT_COLOURS = 1 << 7, /* an instance shows its model's vertex colours */
    FEAT_REFLECT = 1 << 8, /* a material with mirror reflectance */
    FEAT_REFRACT = 1 << 9, /* a dielectric material */
    FEAT_EMIT = 1 << 10,   /* an emissive material */
    FEAT_AREA = 1 << 11,   /* a sphere or rectangle light */
    FEAT_ROUGH = 1 << 12,  /* a rough metal or frosted glass (rough_samples) */
    FEAT_LENS = 1 << 13,   /* a camera with an aperture (depth of field) */
    FEAT_CHECKER = 1 << 14, /* a material with a checker pattern */
    FEAT_NORMAL_MAP = 1 << 15, /* a model's material with a normal map */
    FEAT_COAT = 1 << 16,       /* a material with a clear coat */
    FEAT_NULL = 1 << 17,       /* a see-through blend (material_null): the path integrator's shadow rays pass it */
};

/* What one frame is rendered with beside the world. */
typedef struct {
    Camera camera;
    RenderSettings settings;
} View;

typedef struct {
    vec3 point;
    vec3 unit;   /* the unit normal */
    vec3 tu, tv; /* texture coordinates of p: ((p - point).tu, (p - point).tv) */
    uint32_t material;
} WorldPlane;

typedef struct {
    uint32_t model;
    mat3 rot;      /* model -> world rotation */
    vec3 translate;
    real scale;
    int32_t material; /* the scene material overriding the model's, or -1 */
    int identity;     /* no rotation, scale 1, no translation: rays need no transform */
    Model *placed;    /* a small model's copy in world space (model_place), traced
                       * with world rays instead of the model; NULL: the model */
} WorldInstance;

/* An instance's placement (its rotation made once) from its description. */
WorldInstance world_instance_derive(const Instance *in);

/* Model-space point p where instance in puts it in the world: turned,
 * scaled, moved (its directions: turned alone, m3_apply). */
static inline vec3 world_instance_point(const WorldInstance *in, vec3 p)
{
    return v3_add(v3_scale(m3_apply(&in->rot, p), in->scale), in->translate);
}

/* Transformed instances of models of at most this many triangles are
 * traced as placed copies (WorldInstance.placed, model_place): a copy's
 * memory is a few kilobytes, and a ray needs no move into model space
 * (models/example.scene's two cubes of 12: its frame at one sample, 1 x 1
 * light and rough-mirror samples, 1024x768, one thread, 0.277 -> 0.265 s).
 * Larger models keep one copy for all their instances. */
#define WORLD_PLACED_TRIS 64

/* A light as shading reads it: a spot's or a directional light's direction
 * and a rectangle's normal as a unit axis, a spot's angles as cosines. */
typedef struct {
    LightKind kind;
    vec3 pos;          /* point, spot; sphere: its centre; rectangle: a corner */
    vec3 axis;         /* spot: beam axis; directional: the way light travels; rectangle: its normal */
    vec3 color;
    real intensity;
    int attenuate;
    real radius;       /* sphere */
    vec3 edge1, edge2; /* rectangle */
    int samples;       /* sphere, rectangle: the side of the pattern of shadow rays */
    real cos_outer, cos_inner;       /* spot */
    uint32_t lamp_first, lamp_count; /* its lamp: World.lamps[lamp_first ..], which its shadow rays pass */
} WorldLight;

static inline int world_light_is_area(const WorldLight *l) { return l->kind == LIGHT_SPHERE || l->kind == LIGHT_RECT; }

/* The top-level BVH and the boxes it was built over, shared between worlds
 * whose boxes are the same (a new camera, new settings, a new material). */
typedef struct {
    Bvh bvh;      /* prims index spheres, then triangles, then instances */
    Bvh4 wide;    /* the same tree four-wide (bvh/bvh4.h); node_count 0: none */
    Aabb *boxes;
    uint32_t count;
    atomic_int refs;
} WorldTop;

/* What a world derives from its description item by item, shared by the
 * worlds that differ only in their view (world_with_view). */
typedef struct Emitter Emitter; /* scene/emitters.h */

#define WORLD_GLASS_LIST 8

typedef struct {
    WorldPlane *planes;
    WorldInstance *instances;
    uint32_t instance_count; /* and their placed models, freed with them */
    WorldLight *lights;
    uint32_t *lamps;
    Emitter *emitters;
    real *emit_cells;
    uint8_t *glassy;
    uint32_t glass_list[WORLD_GLASS_LIST];
    Environment *env;
    atomic_int refs;
} WorldParts;

typedef struct {
    const Scene *desc;
    View view;

    /* read in place from the description */
    const Material *materials;
    uint32_t material_count;
    Texture *const *textures;
    const Sphere *spheres;
    uint32_t sphere_count;
    const Tri *tris;
    const TriAttr *tri_attrs;
    uint32_t tri_count;
    Model *const *models;
    vec3 ambient, background;

    /* derived */
    WorldPlane *planes;
    uint32_t plane_count;
    WorldInstance *instances;
    uint32_t instance_count;
    WorldLight *lights;
    uint32_t light_count;
    /* lights the Whitted integrator alone takes, after the scene's
     * (lights[light_count ..]): an environment's sun, as a directional
     * light (the path integrator samples the environment itself) */
    uint32_t whitted_lights;
    uint32_t *lamps;  /* the lights' lamps: top-level primitive numbers, by light (WorldLight.lamp_first) */
    uint32_t lamp_total;
    Emitter *emitters; /* emissive geometry that lights the path integrator's scenes (scene/emitters.h) */
    uint32_t emitter_count;
    real emit_power;   /* their total power (area x mean emission) */
    real *emit_cells;  /* textured emitters' points by brightness (scene/emitters.h) */
    /* glass shadows: 1 for a top-level primitive that may be a dielectric
     * (a glass sphere or triangle, an instance with a glass material),
     * whose shadow rays trace_shadow follows through it; NULL in a scene
     * without dielectrics */
    const uint8_t *glassy;
    /* the top-level primitives glassy marks, where they are few (at most
     * WORLD_GLASS_LIST): a shadow ray's walk through glass tests them
     * alone, not the tree */
    const uint32_t *glass_list;
    uint32_t glass_count; /* UINT32_MAX: too many for the list */
    const Environment *env; /* light from everywhere, or NULL: the background colour */
    WorldParts *parts; /* owns planes, instances, lights, lamps, emitters and the environment */
    WorldTop *top;    /* NULL: nothing but planes */
    const Bvh *tree;  /* &top->bvh, or an empty tree */
    int lone_model;   /* the top level is one untransformed instance and nothing else (trace.c) */
    uint32_t features;      /* what the items use (FEAT_*), and what the view adds: */
    uint32_t item_features; /* the items' alone */
} World;

/* The side of area light l's pattern of points in w's view: its own
 * samples, or the view's settings light_samples where it sets one (a
 * still frame's refinement changes the view, not the description). */
static inline int world_light_side(const World *w, const WorldLight *l)
{
    return w->view.settings.light_samples ? w->view.settings.light_samples : l->samples;
}

/* Builds the world of desc (checked: scene_check), with desc's camera and
 * settings as its view.  previous (may be NULL), a world of an earlier
 * description, gives what did not change: its top-level BVH where the
 * boxes are the same.  The result is the same bits with or without it. */
World *world_build(const Scene *desc, const World *previous, Err *err);
void world_destroy(World *w);
/* Sets the view of the frames to come: checks the camera and the settings
 * (as scene_check does) and nothing else.  Not while a frame renders w. */
int world_set_view(World *w, const View *v, Err *err);
/* A world of w's description seen with view v: it shares w's derived
 * items and tree (w may be destroyed first, or render on meanwhile), and
 * costs the view's check and one allocation.  NULL with err set where v is
 * refused. */
World *world_with_view(const World *w, const View *v, Err *err);
/* How many top-level trees world_build has built in this process (a world
 * that reuses its previous one's builds none): for tests and benchmarks. */
uint64_t world_tree_builds(void);
/* The description's view: its camera and settings. */
View scene_view(const Scene *s);
/* Whether the world's top-level BVH is previous's (world_build reused it). */
int world_shares_top(const World *w, const World *previous);

static inline int world_has(const World *w, uint32_t feature) { return (w->features & feature) != 0; }

/* What the inner loop asks before taking an optional path.  A LANRAY_MINIMAL
 * build (make FEATURES=minimal) compiles every optional feature out, so that
 * `make bench` can show that a scene not using them pays nothing for them. */
#ifdef LANRAY_MINIMAL
#define world_uses(w, feature) ((void)(w), 0)
#else
#define world_uses(w, feature) world_has(w, feature)
#endif

#endif
