/* scene_fields.c - the scene's field tables (see scene_fields.h).  Each
 * table's order is the wire's; the groups hold what only some items use
 * (a lens, a textured plane, a smooth triangle), so that they pay for it
 * alone. */
#include "scene/scene_fields.h"

#include "base/dmath.h"

#include <stdio.h>
#include <string.h>

static const char *const camera_kinds[] = {"pinhole", "ortho", "fisheye", NULL};

#define CAM(f) offsetof(CameraSpec, f)
enum { CAMERA_GROUP_PROJECTION = 1, CAMERA_GROUP_LENS = 2 };
static const Field camera_fields[] = {
    {.key = "position", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = CAM(cam.pos), .lo = -FIELD_INF,
     .hi = FIELD_INF, .doc = "where the camera is"},
    {.key = "lookat", .type = FIELD_VEC, .flags = FIELD_FILE, .off = CAM(lookat), .lo = -FIELD_INF, .hi = FIELD_INF,
     .shown_default = "none", .doc = "the point it looks at (or `yaw` and `pitch`)"},
    {.key = "yaw", .type = FIELD_REAL, .off = CAM(cam.yaw), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "degrees about the vertical: 0 looks along -z, 90 along -x"},
    {.key = "pitch", .type = FIELD_REAL, .off = CAM(cam.pitch), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "degrees up"},
    {.key = "roll", .type = FIELD_REAL, .off = CAM(cam.roll), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "degrees about the view direction"},
    {.key = "zoom", .type = FIELD_REAL, .flags = FIELD_LO_OPEN, .off = CAM(cam.zoom), .hi = FIELD_INF,
     .def = 1.7320508075688772, .shown_default = "1.732 (fov 60)",
     .doc = "a pinhole's focal length over half the image width"},
    {.key = "fov", .type = FIELD_REAL, .flags = FIELD_FILE | FIELD_LO_OPEN | FIELD_HI_OPEN, .off = CAM(fov), .hi = 180,
     .shown_default = "60", .doc = "a pinhole's field of view across the width, degrees"},
    {.key = "ortho", .type = FIELD_REAL, .group = CAMERA_GROUP_PROJECTION, .flags = FIELD_LO_OPEN | FIELD_ZERO_OK,
     .off = CAM(cam.size), .hi = FIELD_INF, .shown_default = "none",
     .doc = "an orthographic camera: the view's width in world units"},
    {.key = "fisheye", .type = FIELD_REAL, .group = CAMERA_GROUP_PROJECTION, .flags = FIELD_LO_OPEN | FIELD_ZERO_OK,
     .off = CAM(cam.fov), .hi = 360, .shown_default = "none",
     .doc = "an equidistant fisheye: its field of view across the width, degrees"},
    {.key = "kind", .type = FIELD_CHOICE, .group = CAMERA_GROUP_PROJECTION, .flags = FIELD_WIRE, .off = CAM(cam.kind),
     .words = camera_kinds, .doc = "the projection"},
    {.key = "aperture", .type = FIELD_REAL, .group = CAMERA_GROUP_LENS, .off = CAM(cam.aperture), .hi = FIELD_INF,
     .doc = "a pinhole's lens diameter: depth of field (0: none); needs `focus`"},
    {.key = "focus", .type = FIELD_REAL, .group = CAMERA_GROUP_LENS, .flags = FIELD_LO_OPEN | FIELD_ZERO_OK,
     .off = CAM(cam.focus), .hi = FIELD_INF, .shown_default = "none",
     .doc = "the distance in focus, along the view direction; needs `aperture`"},
};

#define ONE_PROJECTION "camera takes one of 'zoom', 'fov' (a pinhole), 'ortho' and 'fisheye'"
static const FieldRule camera_rules[] = {
    {RULE_EXCLUDES, "zoom", "fov", "camera takes either 'zoom' or 'fov', not both", NULL},
    {RULE_EXCLUDES, "zoom", "ortho", ONE_PROJECTION, NULL},
    {RULE_EXCLUDES, "zoom", "fisheye", ONE_PROJECTION, NULL},
    {RULE_EXCLUDES, "fov", "ortho", ONE_PROJECTION, NULL},
    {RULE_EXCLUDES, "fov", "fisheye", ONE_PROJECTION, NULL},
    {RULE_EXCLUDES, "ortho", "fisheye", ONE_PROJECTION, NULL},
    {RULE_TOGETHER, "aperture", "focus", "camera takes 'aperture' and 'focus' together (a thin lens)", NULL},
    {RULE_EXCLUDES, "aperture", "ortho", "'aperture' is a pinhole camera's lens, not an orthographic or fisheye camera's", NULL},
    {RULE_EXCLUDES, "aperture", "fisheye", "'aperture' is a pinhole camera's lens, not an orthographic or fisheye camera's", NULL},
    {RULE_EXCLUDES, "lookat", "yaw", "camera takes either 'lookat' or 'yaw'/'pitch', not both", NULL},
    {RULE_EXCLUDES, "lookat", "pitch", "camera takes either 'lookat' or 'yaw'/'pitch', not both", NULL},
    {0, NULL, NULL, NULL, NULL},
};

const FieldKind camera_kind = {.name = "camera", .size = sizeof(CameraSpec), .fields = camera_fields,
                               .count = sizeof camera_fields / sizeof *camera_fields, .rules = camera_rules,
                               .group_count = 2};

static const char *const shading_words[] = {"phong", "diffuse", NULL};
static const char *const onoff_words[] = {"off", "on", NULL};
static const char *const fresnel_words[] = {"exact", "schlick", NULL};
static const char *const glass_words[] = {"opaque", "tinted", NULL};
static const char *const sampling_words[] = {"budget", "product", NULL};
static const char *const light_sampling_words[] = {"full", "adaptive", NULL};
static const char *const integrator_words[] = {"whitted", "path", NULL};
static const char *const emitter_words[] = {"mis", "nee", "bsdf", NULL};
static const char *const limit_words[] = {"black", "background", "ambient", "local", NULL};
static const char *const tonemap_words[] = {"none", "aces", "neutral", NULL};
static const char *const caustics_words[] = {"both", "reflective", "refractive", "none", NULL};

#define SET(f) offsetof(SettingsSpec, f)
enum { SETTINGS_GROUP_SECONDARY = 1, SETTINGS_GROUP_SAMPLING = 2, SETTINGS_GROUP_OUTPUT = 3 };
static const Field settings_fields[] = {
    {.key = "aa", .type = FIELD_WHOLE, .off = SET(rs.aa), .lo = 1, .hi = AA_MAX, .def = 1,
     .doc = "anti-aliasing: N x N samples a pixel"},
    {.key = "adaptive", .type = FIELD_WHOLE, .flags = FIELD_FILE, .off = SET(adaptive), .lo = 1, .hi = AA_MAX, .def = 1,
     .shown_default = "none", .doc = "one sample a pixel, N x N where a neighbour differs (surface, lights or colour)"},
    {.key = "adaptive", .type = FIELD_FLAG, .flags = FIELD_WIRE, .off = SET(rs.adaptive), .doc = "aa is adaptive"},
    {.key = "shading", .type = FIELD_CHOICE, .off = SET(rs.shading), .words = shading_words,
     .doc = "Phong, or diffuse only"},
    {.key = "shadows", .type = FIELD_CHOICE, .off = SET(rs.shadows), .words = onoff_words, .def = 1,
     .doc = "shadow rays"},
    {.key = "filter", .type = FIELD_CHOICE, .off = SET(rs.filter), .words = texture_filter_names, .def = FILTER_ANISOTROPIC,
     .doc = "texture filtering: one texel, four, mip-maps by the ray's footprint, or mip-maps along it (a "
            "procedural checker: at a point with nearest, else over the footprint; an environment: its "
            "mip-map by the footprint with the last two)"},
    {.key = "linear", .type = FIELD_FLAG, .flags = FIELD_WIRE, .off = SET(rs.linear), .doc = "linear output codes"},
    {.key = "hdr", .type = FIELD_FLAG, .flags = FIELD_WIRE, .off = SET(rs.hdr), .doc = "RGBE pixels (4 bytes)"},
    {.key = "width", .type = FIELD_WHOLE, .flags = FIELD_FILE, .off = SET(rs.width), .lo = 1, .hi = SCENE_MAX_SIDE,
     .shown_default = "the program's", .doc = "frame width in pixels (the command line's --width wins)"},
    {.key = "height", .type = FIELD_WHOLE, .flags = FIELD_FILE, .off = SET(rs.height), .lo = 1, .hi = SCENE_MAX_SIDE,
     .shown_default = "the program's", .doc = "frame height in pixels"},
    {.key = "depth", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SECONDARY, .off = SET(rs.depth), .lo = 0,
     .hi = SCENE_MAX_DEPTH, .def = 5, .doc = "bounces of reflected and refracted rays after the camera ray"},
    {.key = "depth_limit", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SECONDARY, .off = SET(rs.depth_limit),
     .words = limit_words, .def = LIMIT_BACKGROUND, .doc = "what a mirror's or glass's ray cut at the depth returns"},
    {.key = "cutoff", .type = FIELD_REAL, .group = SETTINGS_GROUP_SECONDARY, .flags = FIELD_HI_OPEN,
     .off = SET(rs.cutoff), .hi = 1, .def = 0.01, .doc = "a secondary ray that can add less than this is not traced"},
    {.key = "fresnel", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SECONDARY, .off = SET(rs.fresnel),
     .words = fresnel_words, .doc = "a dielectric's reflectance: Fresnel's equations or Schlick's approximation"},
    {.key = "glass_shadows", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SECONDARY, .off = SET(rs.glass_shadows),
     .words = glass_words, .def = 1, .doc = "shadow rays through dielectrics: stopped, or tinted by their colour"},
    {.key = "rough_samples", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SECONDARY, .flags = FIELD_ZERO_OK,
     .off = SET(rs.rough_samples), .lo = 1, .hi = SCENE_MAX_SAMPLES, .shown_default = "6 (product: 4)",
     .doc = "a rough mirror's rays: N x N a pixel (product: a ray)"},
    {.key = "lens_samples", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SAMPLING, .flags = FIELD_ZERO_OK,
     .off = SET(rs.lens_samples), .lo = 1, .hi = SCENE_MAX_SAMPLES, .shown_default = "3 (product: 4)",
     .doc = "rays through a lens: N x N a pixel (product: a pixel sample)"},
    {.key = "light_samples", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SAMPLING, .flags = FIELD_ZERO_OK,
     .off = SET(rs.light_samples), .lo = 1, .hi = LIGHT_MAX_SAMPLES, .shown_default = "0 (each light's own)",
     .doc = "every sphere and rect light: N x N points in place of its own samples"},
    {.key = "sampling", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.sampling),
     .words = sampling_words,
     .doc = "area lights, lenses, rough mirrors: their points shared by a pixel's rays, or taken by every ray"},
    {.key = "light_sampling", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.light_sampling),
     .words = light_sampling_words,
     .doc = "area lights: all of their points at every pixel, or one until a pixel's neighbours disagree (a penumbra)"},
    {.key = "integrator", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.integrator),
     .words = integrator_words,
     .doc = "Whitted's (lights, shadows, mirrors, glass; emission lights nothing), or a path tracer's (light bounces)"},
    {.key = "emitter_sampling", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.emitter_sampling),
     .words = emitter_words,
     .doc = "path: emissive surfaces found by next-event estimation and bounces weighed together (MIS), or one alone"},
    {.key = "roulette", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.roulette), .lo = 0,
     .hi = SCENE_MAX_DEPTH, .def = 5, .doc = "path: bounces before Russian roulette may end a path"},
    {.key = "clamp_indirect", .type = FIELD_REAL, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.clamp_indirect),
     .lo = 0, .hi = 1e6,
     .doc = "path: each light a sample gathers after its first bounce held to this sum of red, green and blue (fewer "
            "fireflies, a little darker; Cycles' Clamp Indirect); 0: never"},
    {.key = "filter_glossy", .type = FIELD_REAL, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.filter_glossy),
     .lo = 0, .hi = 10,
     .doc = "path: glossy surfaces, mirrors and glass blurred after a bounce that was unlikely to take its path, the "
            "more the higher (caustics without fireflies, blurred; Cycles' Filter Glossy); 0: never"},
    {.key = "caustics", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.caustics),
     .words = caustics_words,
     .doc = "path: the caustics kept: what a surface reached by a diffuse bounce reflects (mirrors, metals, "
            "highlights) and refracts (glass); without them no fireflies from them, and less light (Cycles' "
            "Reflective and Refractive Caustics)"},
    {.key = "batch", .type = FIELD_WHOLE, .flags = FIELD_WIRE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.batch),
     .lo = 0, .hi = 11, .doc = "path, N x N, N a power of two: each pixel's sums of this batch of its samples (0: its colour)"},
    {.key = "jitter", .type = FIELD_WHOLE, .flags = FIELD_WIRE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.jitter),
     .lo = 0, .hi = 65535, .doc = "path, one sample a pixel: its sample jitter - 1 (mod 1024) of its 32 x 32 (0: its centre)"},
    {.key = "contrast", .type = FIELD_WHOLE, .group = SETTINGS_GROUP_SAMPLING, .off = SET(rs.contrast), .lo = 0,
     .hi = 255, .def = 15,
     .doc = "adaptive: also refine where a neighbour's colour differs by more than this many codes (255: never)"},
    {.key = "exposure", .type = FIELD_REAL, .group = SETTINGS_GROUP_OUTPUT, .off = SET(rs.exposure), .lo = -32, .hi = 32,
     .doc = "stops: 8-bit output shows the light times 2^exposure"},
    {.key = "tonemap", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_OUTPUT, .off = SET(rs.tonemap),
     .words = tonemap_words,
     .doc = "8-bit output: light past white cut at white (none), or rolled off by ACES's filmic curve (Narkowicz's "
            "fit) or Khronos' PBR Neutral (its colours kept up to 0.76)"},
    {.key = "denoise", .type = FIELD_CHOICE, .group = SETTINGS_GROUP_OUTPUT, .off = SET(rs.denoise),
     .words = onoff_words,
     .doc = "path: the frame's noise filtered out, guided by the surfaces each pixel saw first (their colours, "
            "normals, distances)"},
    {.key = "guides", .type = FIELD_CHOICE, .flags = FIELD_WIRE, .group = SETTINGS_GROUP_OUTPUT, .off = SET(rs.guides),
     .words = onoff_words,
     .doc = "Whitted: each pixel also carries what its camera rays met first, for the server's history of moving "
            "frames"},
};

static const FieldRule settings_rules[] = {
    {RULE_EXCLUDES, "aa", "adaptive", "settings takes either 'aa' or 'adaptive', not both", NULL},
    {0, NULL, NULL, NULL, NULL},
};

const FieldKind settings_kind = {.name = "settings", .size = sizeof(SettingsSpec), .fields = settings_fields,
                                 .count = sizeof settings_fields / sizeof *settings_fields, .rules = settings_rules,
                                 .group_count = 3};

static const char *const light_kinds[] = {"point", "spot", "directional", "sphere", "rect", NULL};
enum {
    L_POINT = 1 << LIGHT_POINT,
    L_SPOT = 1 << LIGHT_SPOT,
    L_DIR = 1 << LIGHT_DIRECTIONAL,
    L_SPHERE = 1 << LIGHT_SPHERE,
    L_RECT = 1 << LIGHT_RECT
};

#define LIGHT(f) offsetof(LightSpec, f)
static const Field light_fields[] = {
    {.key = "color", .alias = "colour", .type = FIELD_VEC, .off = LIGHT(l.color), .hi = FIELD_INF, .def = 1,
     .doc = "its colour (linear light)"},
    {.key = "intensity", .type = FIELD_REAL, .off = LIGHT(l.intensity), .hi = FIELD_INF, .def = 1,
     .doc = "multiplies the colour"},
    {.key = "position", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = LIGHT(l.pos), .lo = -FIELD_INF,
     .hi = FIELD_INF, .variants = L_POINT | L_SPOT | L_SPHERE, .doc = "where it is (a sphere's centre)"},
    {.key = "corner", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = LIGHT(l.pos), .lo = -FIELD_INF,
     .hi = FIELD_INF, .variants = L_RECT, .doc = "a corner of the rectangle"},
    {.key = "attenuate", .type = FIELD_FLAG, .off = LIGHT(l.attenuate), .variants = L_POINT | L_SPOT | L_SPHERE | L_RECT,
     .doc = "falls off with the distance squared"},
    {.key = "direction", .type = FIELD_VEC, .flags = FIELD_NONZERO, .off = LIGHT(l.dir), .lo = -FIELD_INF,
     .hi = FIELD_INF, .variants = L_SPOT | L_DIR, .shown_default = "required (a spot: or `target`)",
     .doc = "the way the light travels"},
    {.key = "target", .type = FIELD_VEC, .flags = FIELD_FILE, .off = LIGHT(target), .lo = -FIELD_INF, .hi = FIELD_INF,
     .variants = L_SPOT, .shown_default = "none", .doc = "the point a spot aims at (or `direction`)"},
    {.key = "angle", .type = FIELD_REAL, .flags = FIELD_REQUIRED | FIELD_LO_OPEN | FIELD_HI_OPEN, .off = LIGHT(l.angle),
     .hi = 180, .variants = L_SPOT, .doc = "the beam's full angle, degrees"},
    {.key = "soft", .type = FIELD_REAL, .off = LIGHT(l.soft), .hi = FIELD_INF, .variants = L_SPOT,
     .doc = "degrees of the beam's edge over which it fades"},
    {.key = "radius", .type = FIELD_REAL, .flags = FIELD_REQUIRED | FIELD_LO_OPEN, .off = LIGHT(l.radius),
     .hi = FIELD_INF, .variants = L_SPHERE, .doc = "a round lamp's radius: soft shadows"},
    {.key = "edge1", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = LIGHT(l.edge1), .lo = -FIELD_INF,
     .hi = FIELD_INF, .variants = L_RECT, .doc = "one side of the rectangle, from the corner"},
    {.key = "edge2", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = LIGHT(l.edge2), .lo = -FIELD_INF,
     .hi = FIELD_INF, .variants = L_RECT, .doc = "the other side (not parallel to the first)"},
    {.key = "samples", .type = FIELD_WHOLE, .off = LIGHT(l.samples), .lo = 1, .hi = LIGHT_MAX_SAMPLES, .def = 4,
     .variants = L_SPHERE | L_RECT, .doc = "shadow rays: N x N points of the lamp a pixel (product: a ray)"},
};

static const FieldRule light_rules[] = {
    {RULE_EXCLUDES, "direction", "target", "a spot light takes either 'direction' or 'target', not both", NULL},
    {0, NULL, NULL, NULL, NULL},
};

const FieldKind light_kind = {.name = "light", .size = sizeof(LightSpec), .fields = light_fields,
                              .count = sizeof light_fields / sizeof *light_fields, .rules = light_rules,
                              .variants = light_kinds, .variant_off = LIGHT(l.kind)};

#define SPHERE(f) offsetof(Sphere, f)
static const Field sphere_fields[] = {
    {.key = "centre", .alias = "center", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = SPHERE(centre),
     .lo = -FIELD_INF, .hi = FIELD_INF, .doc = "its centre"},
    {.key = "radius", .type = FIELD_REAL, .flags = FIELD_REQUIRED | FIELD_LO_OPEN, .off = SPHERE(radius),
     .hi = FIELD_INF, .doc = "its radius"},
    {.key = "material", .type = FIELD_NAME, .off = SPHERE(material), .shown_default = "`default`",
     .doc = "a `material` by its name"},
};
const FieldKind sphere_kind = {.name = "sphere", .size = sizeof(Sphere), .fields = sphere_fields,
                               .count = sizeof sphere_fields / sizeof *sphere_fields};

#define PLANE(f) offsetof(Plane, f)
static const Field plane_fields[] = {
    {.key = "point", .type = FIELD_VEC, .flags = FIELD_REQUIRED, .off = PLANE(point), .lo = -FIELD_INF,
     .hi = FIELD_INF, .doc = "a point of the plane"},
    {.key = "normal", .type = FIELD_VEC, .flags = FIELD_REQUIRED | FIELD_NONZERO, .off = PLANE(normal),
     .lo = -FIELD_INF, .hi = FIELD_INF, .doc = "its normal (any length)"},
    {.key = "material", .type = FIELD_NAME, .off = PLANE(material), .shown_default = "`default`",
     .doc = "a `material` by its name"},
    {.key = "uvscale", .type = FIELD_REAL, .group = 1, .flags = FIELD_LO_OPEN, .off = PLANE(uv_scale), .hi = FIELD_INF,
     .def = 1, .doc = "world units per repeat of its texture"},
    {.key = "uvrotate", .type = FIELD_REAL, .group = 1, .off = PLANE(uv_rotate), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "its texture's turn about the normal, degrees"},
};
const FieldKind plane_kind = {.name = "plane", .size = sizeof(Plane), .fields = plane_fields,
                              .count = sizeof plane_fields / sizeof *plane_fields, .group_count = 1};

#define TRI(f) offsetof(TriSpec, f)
static const Field triangle_fields[] = {
    {.key = "vertices", .type = FIELD_REALS, .n = 9, .flags = FIELD_REQUIRED, .off = TRI(vertices), .lo = -FIELD_INF,
     .hi = FIELD_INF, .doc = "its corners, x y z each"},
    {.key = "material", .type = FIELD_NAME, .off = TRI(material), .shown_default = "`default`",
     .doc = "a `material` by its name"},
    {.key = "smooth", .type = FIELD_FLAG, .flags = FIELD_WIRE, .off = TRI(smooth), .doc = "it has vertex normals"},
    {.key = "textured", .type = FIELD_FLAG, .flags = FIELD_WIRE, .off = TRI(textured), .doc = "it has uv"},
    {.key = "normals", .type = FIELD_REALS, .n = 9, .group = 1, .flags = FIELD_NONZERO, .off = TRI(normals),
     .lo = -FIELD_INF, .hi = FIELD_INF, .shown_default = "the face's", .doc = "vertex normals: smooth shading"},
    {.key = "uv", .type = FIELD_REALS, .n = 6, .group = 2, .off = TRI(uv), .lo = -FIELD_INF, .hi = FIELD_INF,
     .shown_default = "none", .doc = "texture coordinates, u v each corner"},
};
const FieldKind triangle_kind = {.name = "triangle", .size = sizeof(TriSpec), .fields = triangle_fields,
                                 .count = sizeof triangle_fields / sizeof *triangle_fields, .group_count = 2};

#define INST(f) offsetof(Instance, f)
static const Field instance_fields[] = {
    {.key = "model", .type = FIELD_NAME, .flags = FIELD_WIRE, .off = INST(model), .doc = "the model"},
    {.key = "translate", .type = FIELD_VEC, .off = INST(translate), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "moved by this"},
    {.key = "rotate", .type = FIELD_VEC, .off = INST(rotate), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "turned by these degrees about x, then y, then z"},
    {.key = "scale", .type = FIELD_REAL, .flags = FIELD_LO_OPEN, .off = INST(scale), .hi = FIELD_INF, .def = 1,
     .doc = "scaled by this (uniform)"},
    {.key = "material", .type = FIELD_NAME, .off = INST(material), .def = -1, .shown_default = "the model's",
     .doc = "a `material` by its name, over the model's own"},
    {.key = "lights", .type = FIELD_FLAG, .flags = FIELD_FILE, .off = offsetof(InstanceSpec, lights),
     .doc = "the lights its model's glTF gives (KHR_lights_punctual), placed with it"},
    {.key = "camera", .type = FIELD_FLAG, .flags = FIELD_FILE, .off = offsetof(InstanceSpec, camera),
     .doc = "the scene's camera: its model's glTF's, placed with it"},
};
const FieldKind instance_kind = {.name = "instance", .size = sizeof(InstanceSpec), .fields = instance_fields,
                                 .count = sizeof instance_fields / sizeof *instance_fields};

static const Field model_fields[] = {
    {.key = "bvh", .type = FIELD_CHOICE, .flags = FIELD_FILE, .off = offsetof(ModelSpec, bvh), .words = bvh_kind_names,
     .def = BVH_SAH, .shown_default = "sah (a .tmd: its own)",
     .doc = "the tree's builder: spatial median, smallest merged box, or surface area; given, it rebuilds a .tmd's"},
    {.key = "smooth", .type = FIELD_FLAG, .flags = FIELD_FILE, .off = offsetof(ModelSpec, smooth),
     .doc = "smooth vertex normals where the model has none (an OBJ: its smoothing groups aside; another format: edges under 45 degrees)"},
};
const FieldKind model_kind = {.name = "model", .size = sizeof(ModelSpec), .fields = model_fields,
                              .count = sizeof model_fields / sizeof *model_fields};

#define ENV(f) offsetof(SceneEnvironment, f)
static const Field environment_fields[] = {
    {.key = "texture", .type = FIELD_NAME, .group = 1, .flags = FIELD_REQUIRED, .off = ENV(texture), .def = -1,
     .doc = "a `texture` by its name: an equirectangular panorama (a Radiance .hdr keeps light brighter than white)"},
    {.key = "strength", .type = FIELD_REAL, .group = 1, .off = ENV(strength), .hi = FIELD_INF, .def = 1,
     .doc = "its light times this"},
    {.key = "rotate", .type = FIELD_REAL, .group = 1, .off = ENV(rotate), .lo = -FIELD_INF, .hi = FIELD_INF,
     .doc = "turned by these degrees about +y (as a camera's yaw turns)"},
};
const FieldKind environment_kind = {.name = "environment", .size = sizeof(SceneEnvironment),
                                    .fields = environment_fields,
                                    .count = sizeof environment_fields / sizeof *environment_fields, .group_count = 1};

const FieldKind *const scene_kinds[] = {&camera_kind, &settings_kind,  &material_kind, &sphere_kind, &plane_kind,
                                        &triangle_kind, &model_kind, &instance_kind, &light_kind, &environment_kind, NULL};

int scene_fields_finish_camera(CameraSpec *sp, FieldSet given)
{
    const FieldKind *k = &camera_kind;
    Camera c = sp->cam;
    real zoom = R(1) / dmath_tanr(R(30) * REAL_PI / R(180));
    if (field_given(k, given, "zoom"))
        zoom = c.zoom;
    else if (field_given(k, given, "fov"))
        zoom = camera_zoom_for_fov(sp->fov);
    Camera out;
    if (field_given(k, given, "lookat")) {
        if (camera_look_at(&out, c.pos, sp->lookat, c.roll, zoom))
            return -1;
    } else {
        out = camera_from_angles(c.pos, c.yaw, c.pitch, c.roll, zoom);
    }
    if (field_given(k, given, "ortho")) {
        out.kind = CAMERA_ORTHO;
        out.size = c.size;
    } else if (field_given(k, given, "fisheye")) {
        out.kind = CAMERA_FISHEYE;
        out.fov = c.fov;
    }
    if (field_given(k, given, "aperture")) {
        out.aperture = c.aperture;
        out.focus = c.focus;
    }
    sp->cam = out;
    return 0;
}

void scene_fields_finish_settings(SettingsSpec *sp, FieldSet given)
{
    if (field_given(&settings_kind, given, "aa"))
        sp->rs.adaptive = 0;
    if (field_given(&settings_kind, given, "adaptive")) {
        sp->rs.aa = sp->adaptive;
        sp->rs.adaptive = 1;
    }
    if (field_given(&settings_kind, given, "aa") || field_given(&settings_kind, given, "adaptive"))
        sp->rs.sampling_given = 1;
}

const char *scene_fields_finish_light(LightSpec *sp, FieldSet given)
{
    Light *l = &sp->l;
    if (l->kind == LIGHT_SPOT && field_given(&light_kind, given, "target")) {
        l->dir = v3_sub(sp->target, l->pos);
        if (!(v3_len(l->dir) > R(0)))
            return "a spot light's 'target' must not be its position";
    }
    if ((l->kind == LIGHT_SPOT || l->kind == LIGHT_DIRECTIONAL) && !field_given(&light_kind, given, "direction") &&
        !field_given(&light_kind, given, "target"))
        return l->kind == LIGHT_SPOT ? "a spot light needs 'direction' or 'target'" : "a directional light needs 'direction'";
    return NULL;
}

int camera_line(const Camera *c, char *buf, size_t size)
{
    const int p = REAL_DIGITS;
    char proj[96];
    if (c->kind == CAMERA_ORTHO)
        snprintf(proj, sizeof proj, "ortho %.*g", p, (double)c->size);
    else if (c->kind == CAMERA_FISHEYE)
        snprintf(proj, sizeof proj, "fisheye %.*g", p, (double)c->fov);
    else if (c->aperture > R(0))
        snprintf(proj, sizeof proj, "zoom %.*g aperture %.*g focus %.*g", p, (double)c->zoom, p, (double)c->aperture, p,
                 (double)c->focus);
    else
        snprintf(proj, sizeof proj, "zoom %.*g", p, (double)c->zoom);
    return snprintf(buf, size, "camera position %.*g %.*g %.*g yaw %.*g pitch %.*g roll %.*g %s", p, (double)c->pos.x, p,
                    (double)c->pos.y, p, (double)c->pos.z, p, (double)c->yaw, p, (double)c->pitch, p, (double)c->roll,
                    proj);
}

const char *camera_problem(const Camera *c, char *buf, size_t size)
{
    CameraSpec sp = {.cam = *c};
    if (field_problem(&camera_kind, &sp, 0, buf, size))
        return buf;
    if ((c->kind == CAMERA_ORTHO && !(c->size > R(0))) || (c->kind == CAMERA_FISHEYE && !(c->fov > R(0))))
        snprintf(buf, size, "an orthographic camera needs a positive width, a fisheye 0 < fov <= 360");
    else if (c->aperture > R(0) && (c->kind != CAMERA_PINHOLE || !(c->focus > R(0))))
        snprintf(buf, size, "a camera's aperture is a pinhole's, with a positive focus distance");
    else
        return NULL;
    return buf;
}

const char *light_problem(const Light *l, char *buf, size_t size)
{
    LightSpec sp = {.l = *l};
    if ((unsigned)l->kind > LIGHT_RECT) {
        snprintf(buf, size, "unknown kind of light");
        return buf;
    }
    if (field_problem(&light_kind, &sp, (int)l->kind, buf, size))
        return buf;
    if (l->kind == LIGHT_RECT && !(v3_len(v3_cross(l->edge1, l->edge2)) > R(0))) {
        snprintf(buf, size, "the edges of a rect light must not be zero or parallel");
        return buf;
    }
    return NULL;
}

const char *settings_problem(const RenderSettings *rs, char *buf, size_t size)
{
    SettingsSpec sp = {.rs = *rs};
    const char *why = field_problem(&settings_kind, &sp, 0, buf, size);
    if (why)
        return why;
    /* a batch is one of a power-of-two grid's (render/progressive.h) */
    const int n = rs->aa;
    if (rs->batch && (rs->integrator != INTEGRATOR_PATH || rs->adaptive || (n & (n - 1)) != 0 ||
                      (1 << rs->batch) > 2 * n * n)) {
        snprintf(buf, size, "batch %d of a frame that is not path-traced on a regular grid of %d x %d, or past it",
                 rs->batch, n, n);
        return buf;
    }
    if (rs->jitter && (rs->integrator != INTEGRATOR_PATH || rs->adaptive || rs->aa != 1 || rs->batch)) {
        snprintf(buf, size, "jitter %d of a frame that is not path-traced at one sample a pixel", rs->jitter);
        return buf;
    }
    if (rs->guides && rs->integrator != INTEGRATOR_WHITTED) {
        snprintf(buf, size, "guides of a frame that is not Whitted's (a path-traced frame's come with denoise)");
        return buf;
    }
    return NULL;
}

TriSpec tri_spec(const Scene *s, uint32_t i)
{
    const TriAttr *a = &s->tri_attrs[i];
    TriSpec t;
    memset(&t, 0, sizeof t);
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++)
            t.vertices[3 * k + c] = s->tris[i].v[k][c];
    t.material = (int)a->material;
    t.smooth = a->smooth;
    t.textured = a->textured;
    for (int k = 0; a->smooth && k < 3; k++)
        for (int c = 0; c < 3; c++)
            t.normals[3 * k + c] = a->n[k].e[c];
    if (a->textured)
        memcpy(t.uv, a->uv, sizeof t.uv);
    return t;
}

int scene_add_tri_spec(Scene *s, const TriSpec *t, Err *err)
{
    vec3 p[3], n[3];
    for (int k = 0; k < 3; k++) {
        p[k] = v3(t->vertices[3 * k], t->vertices[3 * k + 1], t->vertices[3 * k + 2]);
        n[k] = v3(t->normals[3 * k], t->normals[3 * k + 1], t->normals[3 * k + 2]);
    }
    return scene_add_triangle(s, p, t->smooth ? n : NULL, t->textured ? t->uv : NULL, (uint32_t)t->material, err);
}
