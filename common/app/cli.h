/* cli.h - what the programs share on their command lines: option values
 * with the same meaning in every tool (--aa, --bvh, --threads), opening a
 * scene argument, making output directories and checking that a frame fits
 * in memory before anything is rendered. */
#ifndef LANRAY_CLI_H
#define LANRAY_CLI_H

#include <stddef.h>
#include <stdint.h>

#include "base/opt.h"
#include "scene/scene.h"

/* --aa N | adaptive[:N]: N x N samples everywhere, or one and N x N where
 * neighbours differ.  `given` is set once the option is parsed. */
typedef struct {
    int aa, adaptive, given;
} CliAa;
int cli_parse_aa(const char *value, void *dst, Err *err);
#define CLI_AA_RANGE "1..32, adaptive or adaptive:1..32"


/* --segment LINES|auto: lines per segment into a uint32_t, 0 for auto; at
 * most the tallest frame a server takes. */
#define CLI_MAX_SEGMENT 16384
#define CLI_SEGMENT_RANGE "1..16384 or auto"
int cli_parse_segment(const char *value, void *dst, Err *err);

/* --simd PATH: forces a traversal path (simd.h) at once; dst is unused.
 * cli_simd_env checks LANRAY_SIMD the same way (0, or -1 with the reason). */
int cli_parse_simd(const char *value, void *dst, Err *err);
int cli_simd_env(Err *err);
#define CLI_SIMD_RANGE "scalar, sse, avx2, avx512 or auto"
#define CLI_SIMD_DEFAULT "auto: the CPU's best, or LANRAY_SIMD"

/* --threads: 0 means one per core. */
int cli_threads(int requested);

/* The scene a program was given: NULL for the built-in scene, a scene file,
 * or an .obj/.tmd model, which gets a preview scene (camera framed on its
 * bounding box, two lights).  force: rebuild .tmd models with bvh.
 * smooth (CLI_SMOOTH_OPT): the model alone's vertex normals where it has
 * none; refused for a scene file, whose models say it themselves. */
int cli_open_scene(const char *path, const BvhOptions *bvh, int force, int smooth, Scene **out, Err *err);

/* --smooth for a model given alone, as obj2tmd's */
#define CLI_SMOOTH_OPT(var) \
    {.name = "--smooth", .kind = OPT_FLAG, .dst = (var), \
     .help = "a model given alone: smooth vertex normals where it has none, as obj2tmd --smooth (an STL " \
             "or an OBJ without normals looks faceted; edges sharper than 45 degrees stay)"}
/* A model reader's warnings (ObjOptions.warn, ctx a CliWarnings) on
 * standard error as "PROG: warning: ...": the first CLI_WARNINGS_SHOWN,
 * then one line "PROG: REST" saying what became of the others. */
#define CLI_WARNINGS_SHOWN 20
typedef struct {
    const char *prog, *rest;
    unsigned long shown;
} CliWarnings;
void cli_warning(void *ctx, const char *msg);
/* The models' warnings as cli_open_scene loads them (model_load_warnings),
 * printed by cli_warning (the rest: obj2tmd counts them all).  prog is a
 * string that lasts. */
void cli_show_warnings(const char *prog);

/* --environment FILE, --environment-strength S, --environment-rotate D:
 * an image around any scene (scene.md's `environment`: a model's preview
 * lit by a studio or a sky), in place of the scene's own; or the scene's
 * own made stronger or turned. */
typedef struct {
    const char *file;
    double strength, rotate;
    int strength_given, rotate_given;
} CliEnvironment;
/* Its three entries of a program's option table (base/opt.h), into e. */
#define CLI_ENVIRONMENT_OPTS(e) \
    {.name = "--environment", .kind = OPT_STRING, .dst = &(e)->file, .arg = "FILE", \
     .help = "an equirectangular panorama (a Radiance .hdr) around the scene, lighting it, in place of its own"}, \
    {.name = "--environment-strength", .kind = OPT_REAL, .dst = &(e)->strength, .arg = "S", .rlo = 0, .rhi = 1e30, \
     .seen = &(e)->strength_given, .help = "the environment's light times S", .def = "the scene's, else 1"}, \
    {.name = "--environment-rotate", .kind = OPT_REAL, .dst = &(e)->rotate, .arg = "DEG", .rlo = -1e6, .rhi = 1e6, \
     .seen = &(e)->rotate_given, .help = "the environment turned by DEG degrees about +y", .def = "the scene's, else 0"}
/* --clamp-indirect, --filter-glossy and --caustics, the path
 * integrator's light paths (Cycles' panel of that name), lanray-render's
 * and the server's, over the scene's settings (cli_put_light_paths). */
typedef struct {
    double clamp, blur;
    int caustics; /* a Caustics */
    int clamp_given, blur_given, caustics_given;
} CliLightPaths;
/* Its three entries of a program's option table (base/opt.h), into l. */
#define CLI_LIGHT_PATHS_OPTS(l) \
    {.name = "--clamp-indirect", .kind = OPT_REAL, .dst = &(l)->clamp, .arg = "L", .rlo = 0, .rhi = 1e6, \
     .seen = &(l)->clamp_given, \
     .help = "path: each light a sample gathers after its first bounce held to L, the sum of its red, green and " \
             "blue (fewer fireflies, a little less light; Cycles' Clamp Indirect); 0 = never", \
     .def = "the scene's, else 0"}, \
    {.name = "--filter-glossy", .kind = OPT_REAL, .dst = &(l)->blur, .arg = "F", .rlo = 0, .rhi = 10, \
     .seen = &(l)->blur_given, \
     .help = "path: glossy surfaces, mirrors and glass blurred after a bounce that was unlikely to take its path, " \
             "the more the higher F (caustics without fireflies, blurred; Cycles' Filter Glossy, whose default " \
             "is 1); 0 = never", \
     .def = "the scene's, else 0"}, \
    {.name = "--caustics", .kind = OPT_CHOICE, .dst = &(l)->caustics, \
     .choices = field_words(&settings_kind, "caustics"), .seen = &(l)->caustics_given, \
     .def = "the scene's, else both", \
     .help = "path: the caustics kept: what a surface reached by a diffuse bounce reflects (mirrors, metals, " \
             "highlights) and refracts (glass); without them no fireflies from them, and less light (Cycles' " \
             "Reflective and Refractive Caustics)"}
/* Puts the light paths given on the command line into rs. */
void cli_put_light_paths(RenderSettings *rs, const CliLightPaths *l);
/* --tonemap, lanray-render's and the server's: a Tonemap's word into *to
 * (an int; given: *given) */
#define CLI_TONEMAP_OPT(to, given) \
    {.name = "--tonemap", .kind = OPT_CHOICE, .dst = to, .choices = field_words(&settings_kind, "tonemap"), \
     .seen = given, .def = "the scene's, else none", \
     .help = "8-bit output: light past white cut at white, or rolled off by ACES's filmic curve or Khronos' PBR " \
             "Neutral (docs/renderer.md)"}
/* Puts e into s, the scene of `path` (cli_open_scene's: after the file's
 * settings, and again after every edit); a model's preview then takes the
 * environment in place of its own two lamps and its ambient light (a
 * glTF's own lights stay).  -1 with
 * err naming the file, or saying that there is no environment to make
 * stronger or to turn. */
int cli_put_environment(Scene *s, const CliEnvironment *e, const char *path, Err *err);

/* --camera, lanray-render's and the server's: a `camera` directive's
 * fields, or the whole line the window's K prints, in place of the
 * scene's camera (cli_put_camera) */
#define CLI_CAMERA_OPT(var) \
    {.name = "--camera", .kind = OPT_STRING, .dst = (var), .arg = "FIELDS", \
     .help = "the scene's camera replaced: a camera directive's fields ('position 0 1 5 lookat 0 0 0 fov 40', " \
             "docs/scene.md), or the line the server's window prints for its view (K)"}
/* Puts --camera's camera (text, NULL: none) into s; -1 with err saying
 * what is wrong with it. */
int cli_put_camera(Scene *s, const char *text, Err *err);

/* Warns on standard error about what a user would not want in a scene:
 * no light (only the ambient colour would show it). */
void cli_warn_scene(const char *prog, const Scene *s);

/* Creates dir and its parents (mkdir -p). */
int cli_make_dirs(const char *dir, Err *err);

/* Fails, saying how much is needed and how much there is, when `bytes` for
 * `what` cannot fit in the memory this machine has available. */
int cli_check_memory(uint64_t bytes, const char *what, Err *err);
/* MemAvailable from /proc/meminfo, or the address-space limit when that is
 * lower (0 when neither is known). */
uint64_t cli_available_memory(void);

#endif
