/* scene.h - a scene's description: its items as they were given.
 *
 * A Scene is filled through the scene_add_* calls (by the scene-file parser,
 * the built-in default scene or the wire decoder) and checked once by
 * scene_check (every item by its field table, scene/scene_fields.h, and the
 * references between items).  It holds plain values only: what rendering
 * derives from them (plane axes, instance transforms, light cones, lamps,
 * the top-level BVH, the features used) is a World's (scene/world.h), built
 * from a checked description. */
#ifndef LANRAY_SCENE_H
#define LANRAY_SCENE_H

#include <stdint.h>

#include "geom/camera.h"
#include "shading/optics.h"
#include "model/model.h"
#include "model/texture.h"

#define SCENE_MAX_ITEMS (1u << 24)
#define SCENE_MAX_LIGHTS 65536u
#define AA_MAX 32 /* 1024 samples a pixel: a path-traced still */
#define SCENE_MAX_SIDE 65536 /* settings width/height */
#define SCENE_MAX_DEPTH 64   /* settings depth: reflections and refractions deep */
#define SCENE_MAX_SAMPLES 16 /* settings rough_samples, lens_samples: a side of the pattern */

typedef struct {
    vec3 centre;
    real radius;
    uint32_t material;
} Sphere;

/* Scene items keep the values they were given (a file, the wire); what
 * a world derives from them is the world's (world.h), so that building a
 * world twice, or once on each side of the wire, gives the same bits: a
 * direction normalised again can move by an ulp. */
typedef struct {
    vec3 point, normal; /* as given: normal need not be unit length */
    uint32_t material;
    real uv_scale;      /* planar texture mapping: world units per repeat (> 0) */
    real uv_rotate;     /* and its turn about the normal, degrees */
} Plane;

/* Shading attributes of a scene-level triangle (positions live in Scene.tris). */
typedef struct {
    vec3 n[3];
    real uv[6];
    uint32_t material;
    uint8_t smooth, textured;
} TriAttr;

typedef struct {
    uint32_t model;
    vec3 translate, rotate; /* rotate: degrees about x, y, z */
    real scale;             /* uniform, > 0 */
    int32_t material;       /* scene material overriding the model's, or -1 */
} Instance;

/* Area lights (a sphere, a rectangle) send `samples` x `samples` shadow
 * rays to stratified points of their surface, which makes soft shadows.
 *
 * A light is not seen; an emissive primitive placed where it is shows it
 * (a lamp).  Such a primitive encloses the light's points, so its shadow
 * rays would all end on it: world_build pairs every light with its lamp
 * (the emissive spheres around its centre, or around which its sphere lies;
 * for a rectangle, the emissive scene triangles in its plane that overlap
 * it), and the light's shadow rays pass them. */
typedef enum { LIGHT_POINT = 0, LIGHT_SPOT = 1, LIGHT_DIRECTIONAL = 2, LIGHT_SPHERE = 3, LIGHT_RECT = 4 } LightKind;

#define LIGHT_MAX_SAMPLES 64 /* a side of the pattern: 4096 shadow rays */

typedef struct {
    LightKind kind;
    vec3 pos;          /* point, spot */
    vec3 dir;          /* spot: beam axis; directional: direction light travels; as given */
    vec3 color;
    real intensity;
    int attenuate;     /* point, spot: divide by distance squared */
    real angle, soft;  /* spot: full beam angle and soft edge width, degrees */
    real radius;       /* sphere: pos is its centre */
    vec3 edge1, edge2; /* rectangle: pos is a corner, the edges span it */
    int samples;       /* sphere, rectangle: the side of the pattern of shadow rays */
} Light;

typedef enum { SHADE_PHONG = 0, SHADE_DIFFUSE = 1 } ShadeModel;

/* How the sampled effects (area lights, a lens, rough mirrors) share a
 * pixel's samples: one budget (each of the pixel's rays takes its share of
 * each effect's points, from stratified sequences: costs add), or per
 * effect (every ray takes all of each effect's points: costs multiply). */
typedef enum { SAMPLING_BUDGET = 0, SAMPLING_PRODUCT = 1 } Sampling;

/* Area lights' shadow rays: every pixel all of a light's points (full), or
 * one point a pixel first and all of them only where a pixel's 3 x 3
 * neighbourhood disagrees on surface, lights or colour (adaptive: render.c). */
typedef enum { LIGHTS_FULL = 0, LIGHTS_ADAPTIVE = 1 } LightSampling;

/* How light is carried: Whitted's (lights, shadows, mirrors and glass;
 * emission seen, lighting nothing), or a path tracer's (scene/path.h:
 * light that bounces, emission that lights). */
typedef enum { INTEGRATOR_WHITTED = 0, INTEGRATOR_PATH = 1 } Integrator;

/* How the path integrator finds emissive geometry (scene/emitters.h): by
 * next-event estimation and by the paths that meet it, weighed by
 * multiple importance sampling; or by either alone (the same picture,
 * with other noise: for tests and make tradeoff). */
typedef enum { EMITTERS_MIS = 0, EMITTERS_NEE = 1, EMITTERS_BSDF = 2 } EmitterSampling;

/* What a mirror's or a dielectric's ray that the depth limit cuts returns
 * in place of what it would see: nothing (black), the background, the
 * ambient light, or the light at the surface where it is cut (what a white
 * diffuse surface there would show: the ambient plus the lights that reach
 * it). */
typedef enum { LIMIT_BLACK = 0, LIMIT_BACKGROUND = 1, LIMIT_AMBIENT = 2, LIMIT_LOCAL = 3, LIMIT_COUNT } DepthLimit;

/* How light past white comes to the 8-bit codes (render/tonemap.h): cut
 * at white, or a view transform's curve that rolls it off. */
typedef enum { TONEMAP_NONE = 0, TONEMAP_ACES = 1, TONEMAP_NEUTRAL = 2 } Tonemap;

/* Which caustics the path integrator keeps (Cycles' Reflective and
 * Refractive Caustics): a surface met right after a diffuse bounce
 * reflects (mirrors, metals, coats, highlights, glass's Fresnel
 * reflection) and refracts (glass's transmission) only as this says. */
typedef enum { CAUSTICS_BOTH = 0, CAUSTICS_REFLECTIVE = 1, CAUSTICS_REFRACTIVE = 2, CAUSTICS_NONE = 3 } Caustics;

/* Quality knobs: the scene file sets defaults, the command line may override. */
typedef struct {
    int aa;            /* samples per pixel side: aa*aa per pixel (1..AA_MAX) */
    int adaptive;      /* 1: one sample, aa*aa only where neighbours differ (surface, lights or colour) */
    ShadeModel shading;
    int shadows;
    TextureFilter filter;
    int linear;        /* pixels are written as linear codes (--linear), not sRGB */
    /* secondary rays (reflection, refraction); only a scene with such
     * materials carries these on the wire */
    int depth;         /* bounces after the camera ray (0..SCENE_MAX_DEPTH) */
    DepthLimit depth_limit; /* what a ray the depth limit cuts returns */
    real cutoff;       /* a ray whose weight (the largest channel of what it
                        * still adds to the pixel) is below this is not traced */
    FresnelModel fresnel;
    int glass_shadows; /* 1: shadow rays pass dielectrics, tinted by their
                        * transmitted colour; 0: dielectrics cast opaque shadows */
    int rough_samples; /* a rough mirror reflects rough_samples^2 rays (per pixel, or per ray with product); 0: the default */
    int lens_samples;  /* a camera with an aperture sends lens_samples^2 rays per pixel (budget) or pixel sample
                        * (product); 0: the default */
    int light_samples; /* every sphere and rect light takes light_samples^2 points in place of its own samples^2
                        * (a still frame's refinement: lanray-server --still-light-samples); 0: each its own */
    Sampling sampling;
    LightSampling light_sampling;
    Integrator integrator;
    EmitterSampling emitter_sampling;
    int roulette;      /* path: bounces before Russian roulette may end a path */
    real clamp_indirect; /* path: each light a sample gathers after its first bounce held to this sum of
                          * red, green and blue (Cycles' Clamp Indirect); 0: never */
    real filter_glossy;  /* path: glossy lobes, mirrors and glass blurred after bounces of density under
                          * this (Cycles' Filter Glossy, path.c surface_blur); 0: never */
    Caustics caustics;   /* path: what a surface reached by a diffuse bounce reflects and refracts */
    int contrast;      /* adaptive: a pixel is refined where a neighbour's centre sample differs by more than this
                        * many codes in a channel (255: never by colour alone) */
    real exposure;     /* stops: the 8-bit codes encode light times 2^exposure */
    Tonemap tonemap;   /* ... through this view transform's curve */
    int denoise;       /* path: each pixel also carries what its camera rays saw first (a guide), and the frame
                        * is filtered by it (render/denoise.h) */
    int hdr;           /* pixels are RGBE, 4 bytes (a .hdr from lanray-render, lanray-server --hdr); not in scene files */
    /* path, N x N, N a power of two (render/progressive.h): batch b of the
     * samples, each pixel's sums in place of its colour (a farm's still
     * frame, which its server adds up); 0: the whole picture.  On the wire
     * only. */
    int batch;
    /* path, one sample a pixel on a regular grid: sample jitter - 1 (mod
     * 1024) of the pixel's 32 x 32 in their progressive order, in place of
     * its centre (a farm's moving frame, which its server adds to the
     * frames before, reprojected: render/temporal.h); 0: the centre.  On
     * the wire only. */
    int jitter;
    /* Whitted, a moving frame: each pixel carries the guide of what its
     * camera rays met first (render/denoise.h), for the server's history
     * that adds the moving frames up (render/temporal.h); not filtered.
     * On the wire only. */
    int guides;
    /* the picture of the first `batches` batches alone (lanray-render
     * --still-frame); 0: all.  Not on the wire, not in scene files. */
    int batches;
    /* what the scene file asked for, for the programs' defaults; not on the
     * wire (an UPDATE carries the frame's size, the samples are above) */
    int width, height;  /* 0: not given */
    int sampling_given; /* the file set aa or adaptive */
} RenderSettings;

/* Light from everywhere (scene/environment.h): an image around the scene. */
typedef struct {
    int32_t texture; /* the panorama, or -1: none (the background colour) */
    real strength;   /* its light times this */
    real rotate;     /* turned by these degrees about +y */
} SceneEnvironment;

typedef struct {
    Camera camera;
    vec3 ambient, background;
    SceneEnvironment environment;
    RenderSettings settings;

    Material *materials;   uint32_t material_count, material_cap;
    Texture **textures;    uint32_t texture_count, texture_cap;
    Sphere *spheres;       uint32_t sphere_count, sphere_cap;
    Plane *planes;         uint32_t plane_count, plane_cap;
    Tri *tris;             uint32_t tri_count, tri_cap;
    TriAttr *tri_attrs;    uint32_t tri_attr_cap;
    Model **models;        uint32_t model_count, model_cap;
    Instance *instances;   uint32_t instance_count, instance_cap;
    Light *lights;         uint32_t light_count, light_cap;

    int borrowed_assets;   /* models and textures belong to someone else (a client's asset cache) */
    int preview_lamps;     /* a model's preview (scene_preview): its lights are the preview's own lamps,
                            * not the file's; not on the wire */
    int checked;           /* scene_check passed since the last change */
    /* the files it was read from (the scene file, its models' and textures'
     * files), for a server that follows edits; not on the wire */
    char **sources;        uint32_t source_count, source_cap;
} Scene;

Scene *scene_create(void);
void scene_destroy(Scene *s);

int scene_add_material(Scene *s, Material m, uint32_t *id, Err *err);
/* Takes ownership of t, also on failure (unless borrowed_assets). */
int scene_add_texture(Scene *s, Texture *t, uint32_t *id, Err *err);
int scene_add_sphere(Scene *s, Sphere sp, Err *err);
int scene_add_plane(Scene *s, Plane p, Err *err);
/* n (3 normals) and uv (6 numbers) may be NULL. */
int scene_add_triangle(Scene *s, const vec3 p[3], const vec3 *n, const real *uv, uint32_t material, Err *err);
/* Takes ownership of m, also on failure (unless borrowed_assets). */
int scene_add_model(Scene *s, Model *m, uint32_t *id, Err *err);
int scene_add_instance(Scene *s, Instance in, Err *err);
int scene_add_light(Scene *s, Light l, Err *err);
/* Records a file the scene was read from (a copy of path). */
int scene_add_source(Scene *s, const char *path, Err *err);

Plane plane_make(vec3 point, vec3 normal, uint32_t material);
Light light_point(vec3 pos, vec3 color, real intensity, int attenuate);
Light light_spot(vec3 pos, vec3 dir, real angle, real soft, vec3 color, real intensity, int attenuate);
Light light_directional(vec3 dir, vec3 color, real intensity);
Light light_sphere(vec3 centre, real radius, int samples, vec3 color, real intensity, int attenuate);
Light light_rect(vec3 corner, vec3 edge1, vec3 edge2, int samples, vec3 color, real intensity, int attenuate);
static inline int light_is_area(const Light *l) { return l->kind == LIGHT_SPHERE || l->kind == LIGHT_RECT; }
static inline int light_has_direction(const Light *l) { return l->kind == LIGHT_SPOT || l->kind == LIGHT_DIRECTIONAL; }
Instance instance_make(uint32_t model, vec3 translate, vec3 rotate, real scale);
/* Copies n instances from src into *buf, grown where it holds fewer
 * (*cap: how many it holds): n, or 0 where memory ran out (*buf kept). */
uint32_t instances_copy(Instance **buf, uint32_t *cap, const Instance *src, uint32_t n);
RenderSettings render_settings_default(void);
/* The rough mirrors' and the lens's samples a side: the scene's, else the
 * default of its sampling.  One budget: 6 x 6 rough rays and 3 x 3 lens rays
 * a pixel, where the lens scene of make tradeoff reached the error of the
 * per-effect defaults (4 x 4 each per ray) at a fifth of their time; per
 * effect, those 4 x 4 (docs/tradeoff.md). */
static inline int settings_rough_samples(const RenderSettings *rs)
{
    return rs->rough_samples ? rs->rough_samples : rs->sampling == SAMPLING_PRODUCT ? 4 : 6;
}
static inline int settings_lens_samples(const RenderSettings *rs)
{
    return rs->lens_samples ? rs->lens_samples : rs->sampling == SAMPLING_PRODUCT ? 4 : 3;
}

/* A sphere holding the scene's bounded items (spheres, triangles, model
 * instances; not planes, not lights), for a camera to frame it and to pace
 * its moves by: 0, or -1 where there is none. */
int scene_bounds(const Scene *s, vec3 *centre, real *radius);

/* The one check of a scene however it was made: every item by its table,
 * the references between items. */
int scene_check(Scene *s, Err *err);
/* The part of it a frame's camera and settings take. */
int scene_check_view(const Camera *c, const RenderSettings *rs, Err *err);
/* Rebuilds every model's BVH with another builder (then build a new world). */
int scene_rebuild_models(Scene *s, const BvhOptions *opt, Err *err);
uint64_t scene_triangle_count(const Scene *s);

#endif
