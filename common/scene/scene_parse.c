/* scene_parse.c - see scene_parse.h.  Each directive lists the keys it
 * accepts with their arity; one generic reader checks them all, so every
 * directive reports unknown, repeated, missing and malformed keys the same way. */
#include "scene/scene_parse.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"
#include "base/lex.h"
#include "model/model_load.h"

#define SCENE_MAX_BYTES ((size_t)256 << 20)
#define NAME_MAX_LEN 64
#define MAX_KEYS 24

typedef enum { ARG_NUM, ARG_WORD, ARG_FLAG } ArgKind;

typedef struct {
    const char *key;
    ArgKind kind;
    int n;        /* numbers for ARG_NUM */
    int required;
} KeySpec;

typedef struct {
    int present[MAX_KEYS];
    real num[MAX_KEYS][9];
    const char *word[MAX_KEYS];
} KeyVals;

typedef struct {
    char name[NAME_MAX_LEN];
    uint32_t id;
} Named;

typedef struct {
    Named *items;
    uint32_t count;
} NameTable;

typedef struct {
    Scene *s;
    const char *file, *dir;
    int line;
    const BvhOptions *bvh;
    int force;
    NameTable materials, textures, models;
    Err *err;
} Ctx;

static int fail(Ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(Ctx *c, const char *fmt, ...)
{
    char what[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return err_set(c->err, "%s:%d: %s", c->file, c->line, what);
}

static int names_find(const NameTable *t, const char *name, uint32_t *id)
{
    for (uint32_t i = 0; i < t->count; i++)
        if (strcmp(t->items[i].name, name) == 0) {
            *id = t->items[i].id;
            return 0;
        }
    return -1;
}

static int names_add(Ctx *c, NameTable *t, const char *kind, const char *name, uint32_t id)
{
    uint32_t dummy;
    if (strlen(name) >= NAME_MAX_LEN)
        return fail(c, "%s name '%s' is longer than 63 characters", kind, name);
    if (names_find(t, name, &dummy) == 0)
        return fail(c, "%s '%s' is defined twice", kind, name);
    Named *p = realloc(t->items, (t->count + 1) * sizeof *p);
    if (!p)
        return fail(c, "out of memory");
    t->items = p;
    snprintf(p[t->count].name, NAME_MAX_LEN, "%s", name);
    p[t->count++].id = id;
    return 0;
}

static void key_list(const KeySpec *spec, char *buf, size_t size)
{
    buf[0] = 0;
    for (int i = 0; spec[i].key; i++) {
        size_t n = strlen(buf);
        snprintf(buf + n, size - n, "%s%s", i ? ", " : "", spec[i].key);
    }
}

/* Both spellings are taken; the tables use one of each. */
static const char *key_spelling(const char *key)
{
    if (strcmp(key, "center") == 0)
        return "centre";
    if (strcmp(key, "colour") == 0)
        return "color";
    return key;
}

/* Reads keyword/value pairs from tokens [start, n) against spec. */
static int read_keys(Ctx *c, const Tokens *t, int start, const char *directive, const KeySpec *spec, KeyVals *kv)
{
    memset(kv, 0, sizeof *kv);
    char keys[256];
    key_list(spec, keys, sizeof keys);
    for (int i = start; i < t->n;) {
        int k = 0;
        while (spec[k].key && strcmp(spec[k].key, key_spelling(t->tok[i])) != 0)
            k++;
        if (!spec[k].key) {
            err_set(c->err, "%s:%d: unknown keyword '%s' for %s (expected one of: %s)", c->file, c->line, t->tok[i],
                    directive, keys);
            return -1;
        }
        if (kv->present[k])
            return fail(c, "keyword '%s' given twice for %s", spec[k].key, directive);
        kv->present[k] = 1;
        i++;
        if (spec[k].kind == ARG_FLAG)
            continue;
        if (spec[k].kind == ARG_WORD) {
            if (i >= t->n)
                return fail(c, "'%s' of %s expects a name", spec[k].key, directive);
            kv->word[k] = t->tok[i++];
            continue;
        }
        for (int j = 0; j < spec[k].n; j++, i++) {
            if (i >= t->n || lex_real(t->tok[i], &kv->num[k][j])) {
                err_set(c->err, "%s:%d: '%s' of %s expects %d finite number%s, got '%s'", c->file, c->line,
                        spec[k].key, directive, spec[k].n, spec[k].n > 1 ? "s" : "", i < t->n ? t->tok[i] : "end of line");
                return -1;
            }
        }
    }
    for (int k = 0; spec[k].key; k++)
        if (spec[k].required && !kv->present[k])
            return fail(c, "%s needs '%s'", directive, spec[k].key);
    return 0;
}

static vec3 kv_vec(const KeyVals *kv, int k) { return v3(kv->num[k][0], kv->num[k][1], kv->num[k][2]); }

static int lookup_material(Ctx *c, const KeyVals *kv, int k, uint32_t *id)
{
    if (!kv->present[k]) {
        *id = 0; /* "default" */
        return 0;
    }
    if (names_find(&c->materials, kv->word[k], id))
        return fail(c, "unknown material '%s' (define it with 'material %s ...' first)", kv->word[k], kv->word[k]);
    return 0;
}

static int positive(Ctx *c, real v, const char *what, const char *directive)
{
    return v > R(0) ? 0 : fail(c, "'%s' of %s must be positive", what, directive);
}

static int non_negative_vec(Ctx *c, vec3 v, const char *what, const char *directive)
{
    return v.x >= R(0) && v.y >= R(0) && v.z >= R(0) ? 0 : fail(c, "'%s' of %s must not be negative", what, directive);
}

static int do_camera(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"position", ARG_NUM, 3, 1}, {"lookat", ARG_NUM, 3, 0}, {"yaw", ARG_NUM, 1, 0},
                                   {"pitch", ARG_NUM, 1, 0},    {"roll", ARG_NUM, 1, 0},   {"zoom", ARG_NUM, 1, 0},
                                   {"fov", ARG_NUM, 1, 0},      {"ortho", ARG_NUM, 1, 0},  {"fisheye", ARG_NUM, 1, 0},
                                   {"aperture", ARG_NUM, 1, 0}, {"focus", ARG_NUM, 1, 0},  {0, 0, 0, 0}};
    KeyVals kv;
    if (read_keys(c, t, 1, "camera", spec, &kv))
        return -1;
    if (kv.present[5] + kv.present[6] + kv.present[7] + kv.present[8] > 1)
        return fail(c, "camera takes one of 'zoom', 'fov' (a pinhole), 'ortho' and 'fisheye'");
    if (kv.present[7] && !(kv.num[7][0] > R(0)))
        return fail(c, "'ortho' of camera (the view's width) must be positive");
    if (kv.present[8] && !(kv.num[8][0] > R(0) && kv.num[8][0] <= CAMERA_FISHEYE_MAX))
        return fail(c, "'fisheye' of camera (its field of view) must be above 0 and at most 360 degrees");
    if (kv.present[9] != kv.present[10])
        return fail(c, "camera takes 'aperture' and 'focus' together (a thin lens)");
    if (kv.present[9] && (kv.present[7] || kv.present[8]))
        return fail(c, "'aperture' is a pinhole camera's lens, not an orthographic or fisheye camera's");
    if (kv.present[9] && !(kv.num[9][0] >= R(0) && kv.num[10][0] > R(0)))
        return fail(c, "camera 'aperture' must not be negative and 'focus' must be positive");
    if (kv.present[1] && (kv.present[2] || kv.present[3]))
        return fail(c, "camera takes either 'lookat' or 'yaw'/'pitch', not both");
    if (kv.present[5] && kv.present[6])
        return fail(c, "camera takes either 'zoom' or 'fov', not both");
    real zoom = R(1) / tan(R(30) * REAL_PI / R(180));
    if (kv.present[5]) {
        if (positive(c, kv.num[5][0], "zoom", "camera"))
            return -1;
        zoom = kv.num[5][0];
    } else if (kv.present[6]) {
        if (!(kv.num[6][0] > R(0) && kv.num[6][0] < R(180)))
            return fail(c, "'fov' of camera must be between 0 and 180 degrees");
        zoom = camera_zoom_for_fov(kv.num[6][0]);
    }
    vec3 pos = kv_vec(&kv, 0);
    if (kv.present[1]) {
        if (camera_look_at(&c->s->camera, pos, kv_vec(&kv, 1), kv.num[4][0], zoom))
            return fail(c, "camera 'lookat' point equals its position");
    } else {
        c->s->camera = camera_from_angles(pos, kv.num[2][0], kv.num[3][0], kv.num[4][0], zoom);
    }
    if (kv.present[7]) {
        c->s->camera.kind = CAMERA_ORTHO;
        c->s->camera.size = kv.num[7][0];
    } else if (kv.present[8]) {
        c->s->camera.kind = CAMERA_FISHEYE;
        c->s->camera.fov = kv.num[8][0];
    }
    if (kv.present[9]) {
        c->s->camera.aperture = kv.num[9][0];
        c->s->camera.focus = kv.num[10][0];
    }
    return 0;
}

static int do_colour(Ctx *c, const Tokens *t, vec3 *out)
{
    real v[3];
    if (t->n != 4 || lex_real(t->tok[1], &v[0]) || lex_real(t->tok[2], &v[1]) || lex_real(t->tok[3], &v[2]))
        return fail(c, "%s expects 3 finite numbers (red green blue)", t->tok[0]);
    *out = v3(v[0], v[1], v[2]);
    return non_negative_vec(c, *out, "colour", t->tok[0]);
}

static int do_settings(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"aa", ARG_NUM, 1, 0},       {"adaptive", ARG_NUM, 1, 0}, {"shading", ARG_WORD, 0, 0},
                                   {"shadows", ARG_WORD, 0, 0}, {"filter", ARG_WORD, 0, 0},  {"width", ARG_NUM, 1, 0},
                                   {"height", ARG_NUM, 1, 0},   {"depth", ARG_NUM, 1, 0},    {"cutoff", ARG_NUM, 1, 0},
                                   {"fresnel", ARG_WORD, 0, 0}, {"glass_shadows", ARG_WORD, 0, 0},
                                   {"rough_samples", ARG_NUM, 1, 0}, {"lens_samples", ARG_NUM, 1, 0},
                                   {"exposure", ARG_NUM, 1, 0}, {"sampling", ARG_WORD, 0, 0},
                                   {"depth_limit", ARG_WORD, 0, 0}, {0, 0, 0, 0}};
    KeyVals kv;
    if (read_keys(c, t, 1, "settings", spec, &kv))
        return -1;
    RenderSettings *rs = &c->s->settings;
    for (int k = 0; k < 2; k++)
        if (kv.present[k]) {
            real n = kv.num[k][0];
            if (!(n >= 1 && n <= AA_MAX && n == floor(n)))
                return fail(c, "'%s' of settings must be a whole number from 1 to 16", spec[k].key);
            rs->aa = (int)n;
            rs->adaptive = k == 1;
            rs->sampling_given = 1;
        }
    if (kv.present[0] && kv.present[1])
        return fail(c, "settings takes either 'aa' or 'adaptive', not both");
    for (int k = 5; k < 7; k++)
        if (kv.present[k]) {
            real n = kv.num[k][0];
            if (!(n >= 1 && n <= SCENE_MAX_SIDE && n == floor(n)))
                return fail(c, "'%s' of settings must be a whole number from 1 to %d", spec[k].key, SCENE_MAX_SIDE);
            *(k == 5 ? &rs->width : &rs->height) = (int)n;
        }
    /* the keys that name one of two words, in the order of their enums (0, 1) */
    static const struct {
        int key;
        const char *words[2];
    } choice[] = {{2, {"phong", "diffuse"}}, {3, {"off", "on"}}, {9, {"exact", "schlick"}}, {10, {"opaque", "tinted"}},
                  {14, {"budget", "product"}}};
    int *const dst[] = {(int *)&rs->shading, &rs->shadows, (int *)&rs->fresnel, &rs->glass_shadows, (int *)&rs->sampling};
    for (int i = 0; i < 5; i++) {
        int k = choice[i].key;
        if (!kv.present[k])
            continue;
        int w = strcmp(kv.word[k], choice[i].words[0]) == 0 ? 0 : strcmp(kv.word[k], choice[i].words[1]) == 0 ? 1 : -1;
        if (w < 0)
            return fail(c, "'%s' must be %s or %s, not '%s'", spec[k].key, choice[i].words[0], choice[i].words[1],
                        kv.word[k]);
        *dst[i] = w;
    }
    if (kv.present[4] && texture_filter_parse(kv.word[4], &rs->filter))
        return fail(c, "'filter' must be nearest, bilinear, trilinear or anisotropic, not '%s'", kv.word[4]);
    if (kv.present[15] && depth_limit_parse(kv.word[15], &rs->depth_limit))
        return fail(c, "'depth_limit' must be black, background, ambient or local, not '%s'", kv.word[15]);
    if (kv.present[7]) {
        real n = kv.num[7][0];
        if (!(n >= 0 && n <= SCENE_MAX_DEPTH && n == floor(n)))
            return fail(c, "'depth' of settings must be a whole number from 0 to %d", SCENE_MAX_DEPTH);
        rs->depth = (int)n;
    }
    if (kv.present[13]) {
        if (!(kv.num[13][0] >= R(-32) && kv.num[13][0] <= R(32)))
            return fail(c, "'exposure' of settings must be from -32 to 32 stops");
        rs->exposure = kv.num[13][0];
    }
    for (int k = 11; k < 13; k++)
        if (kv.present[k]) {
            real n = kv.num[k][0];
            if (!(n >= 1 && n <= SCENE_MAX_SAMPLES && n == floor(n)))
                return fail(c, "'%s' of settings must be a whole number from 1 to %d", spec[k].key, SCENE_MAX_SAMPLES);
            *(k == 11 ? &rs->rough_samples : &rs->lens_samples) = (int)n;
        }
    if (kv.present[8]) {
        if (!(kv.num[8][0] >= R(0) && kv.num[8][0] < R(1)))
            return fail(c, "'cutoff' of settings must be from 0 up to (not including) 1");
        rs->cutoff = kv.num[8][0];
    }
    return 0;
}

static int do_texture(Ctx *c, const Tokens *t)
{
    if (t->n < 3 || t->n > 4 || (t->n == 4 && strcmp(t->tok[3], "closest") != 0 && strcmp(t->tok[3], "smooth") != 0))
        return fail(c, "texture expects a name, a file and how magnified texels look: texture NAME FILE [smooth|closest]");
    char path[4096];
    if (file_join(c->dir, t->tok[2], path, sizeof path))
        return fail(c, "texture file name '%s' is too long", t->tok[2]);
    Texture *tex;
    if (texture_read(path, &tex, c->err))
        return err_prefix(c->err, "%s:%d", c->file, c->line);
    tex->closest = t->n == 4 && strcmp(t->tok[3], "closest") == 0;
    uint32_t id;
    if (scene_add_texture(c->s, tex, &id, c->err))
        return -1;
    return names_add(c, &c->textures, "texture", t->tok[1], id);
}

static int do_material(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"diffuse", ARG_NUM, 3, 0}, {"specular", ARG_NUM, 3, 0}, {"shininess", ARG_NUM, 1, 0},
                                   {"texture", ARG_WORD, 0, 0}, {"reflect", ARG_NUM, 3, 0},  {"ior", ARG_NUM, 1, 0},
                                   {"transmit", ARG_NUM, 3, 0}, {"absorb", ARG_NUM, 3, 0},   {"emit", ARG_NUM, 3, 0},
                                   {"roughness", ARG_NUM, 1, 0}, {0, 0, 0, 0}};
    if (t->n < 2)
        return fail(c, "material expects a name: material NAME diffuse R G B ...");
    KeyVals kv;
    if (read_keys(c, t, 2, "material", spec, &kv))
        return -1;
    Material m = material_default();
    /* a mirror or a glass is that alone unless a diffuse colour is given */
    if (kv.present[4] || kv.present[5])
        m.kd = v3_splat(R(0));
    if (kv.present[0])
        m.kd = kv_vec(&kv, 0);
    if (kv.present[1])
        m.ks = kv_vec(&kv, 1);
    if (kv.present[2])
        m.shininess = kv.num[2][0];
    if (non_negative_vec(c, m.kd, "diffuse", "material") || non_negative_vec(c, m.ks, "specular", "material") ||
        (m.shininess < 0 && fail(c, "'shininess' of material must not be negative")))
        return -1;
    if (kv.present[4])
        m.kr = kv_vec(&kv, 4);
    if (kv.present[5]) {
        m.ior = kv.num[5][0];
        m.kt = v3_splat(R(1));
        if (!(m.ior >= MATERIAL_IOR_MIN && m.ior <= MATERIAL_IOR_MAX))
            return fail(c, "'ior' of material must be from 0.0625 to 16");
    }
    if ((kv.present[6] || kv.present[7]) && !kv.present[5])
        return fail(c, "'%s' of material needs 'ior' (a dielectric)", kv.present[6] ? "transmit" : "absorb");
    if (kv.present[4] && kv.present[5])
        return fail(c, "material takes either 'reflect' (a mirror) or 'ior' (a dielectric, reflecting by Fresnel), not both");
    if (kv.present[6])
        m.kt = kv_vec(&kv, 6);
    if (kv.present[7])
        m.absorb = kv_vec(&kv, 7);
    if (kv.present[8])
        m.ke = kv_vec(&kv, 8);
    if (kv.present[9]) {
        if (!kv.present[4])
            return fail(c, "'roughness' of material needs 'reflect' (a mirror or a metal)");
        if (!(kv.num[9][0] >= R(0) && kv.num[9][0] <= R(1)))
            return fail(c, "'roughness' of material must be from 0 to 1");
        m.roughness = kv.num[9][0];
    }
    if (non_negative_vec(c, m.kr, "reflect", "material") || non_negative_vec(c, m.kt, "transmit", "material") ||
        non_negative_vec(c, m.absorb, "absorb", "material") || non_negative_vec(c, m.ke, "emit", "material"))
        return -1;
    if (kv.present[3]) {
        uint32_t tex;
        if (names_find(&c->textures, kv.word[3], &tex))
            return fail(c, "unknown texture '%s' (define it with 'texture %s FILE' first)", kv.word[3], kv.word[3]);
        m.texture = (int32_t)tex;
    }
    uint32_t id;
    if (scene_add_material(c->s, m, &id, c->err))
        return -1;
    return names_add(c, &c->materials, "material", t->tok[1], id);
}

static int do_sphere(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"centre", ARG_NUM, 3, 1}, {"radius", ARG_NUM, 1, 1}, {"material", ARG_WORD, 0, 0}, {0, 0, 0, 0}};
    KeyVals kv;
    if (read_keys(c, t, 1, "sphere", spec, &kv) || positive(c, kv.num[1][0], "radius", "sphere"))
        return -1;
    Sphere sp = {kv_vec(&kv, 0), kv.num[1][0], 0};
    return lookup_material(c, &kv, 2, &sp.material) || scene_add_sphere(c->s, sp, c->err) ? -1 : 0;
}

static int do_plane(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"point", ARG_NUM, 3, 1},    {"normal", ARG_NUM, 3, 1},   {"material", ARG_WORD, 0, 0},
                                   {"uvscale", ARG_NUM, 1, 0}, {"uvrotate", ARG_NUM, 1, 0}, {0, 0, 0, 0}};
    KeyVals kv;
    if (read_keys(c, t, 1, "plane", spec, &kv))
        return -1;
    Plane p = plane_make(kv_vec(&kv, 0), kv_vec(&kv, 1), 0);
    if (!(v3_len(p.normal) > R(0)))
        return fail(c, "'normal' of plane must not be zero");
    if (kv.present[3] && positive(c, kv.num[3][0], "uvscale", "plane"))
        return -1;
    if (kv.present[3])
        p.uv_scale = kv.num[3][0];
    p.uv_rotate = kv.num[4][0];
    return lookup_material(c, &kv, 2, &p.material) || scene_add_plane(c->s, p, c->err) ? -1 : 0;
}

static int do_triangle(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"vertices", ARG_NUM, 9, 1}, {"normals", ARG_NUM, 9, 0}, {"uv", ARG_NUM, 6, 0},
                                   {"material", ARG_WORD, 0, 0}, {0, 0, 0, 0}};
    KeyVals kv;
    if (read_keys(c, t, 1, "triangle", spec, &kv))
        return -1;
    vec3 p[3], n[3];
    for (int k = 0; k < 3; k++) {
        p[k] = v3(kv.num[0][3 * k], kv.num[0][3 * k + 1], kv.num[0][3 * k + 2]);
        n[k] = v3_norm(v3(kv.num[1][3 * k], kv.num[1][3 * k + 1], kv.num[1][3 * k + 2]));
        if (kv.present[1] && !(v3_len(n[k]) > R(0)))
            return fail(c, "'normals' of triangle must not be zero");
    }
    if (mesh_tri_is_degenerate(p))
        return fail(c, "triangle has zero area (its vertices are on one line)");
    uint32_t mat = 0;
    if (lookup_material(c, &kv, 3, &mat))
        return -1;
    return scene_add_triangle(c->s, p, kv.present[1] ? n : NULL, kv.present[2] ? kv.num[2] : NULL, mat, c->err);
}

static int do_model(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"bvh", ARG_WORD, 0, 0}, {"smooth", ARG_FLAG, 0, 0}, {0, 0, 0, 0}};
    if (t->n < 3)
        return fail(c, "model expects a name and a file: model NAME FILE.tmd|FILE.obj");
    KeyVals kv;
    if (read_keys(c, t, 3, "model", spec, &kv))
        return -1;
    BvhOptions opt = *c->bvh;
    if (kv.present[0] && !c->force && bvh_kind_parse(kv.word[0], &opt.kind))
        return fail(c, "unknown bvh '%s' (sbt, mst or sah)", kv.word[0]);
    char path[4096];
    if (file_join(c->dir, t->tok[2], path, sizeof path))
        return fail(c, "model file name '%s' is too long", t->tok[2]);
    if (!model_load_knows(path))
        return fail(c, "model file '%s' must end in .tmd, .obj, or a format the importer reads (.ply, .stl, .gltf, .glb, ...)", t->tok[2]);
    Model *m = NULL;
    if (model_load(path, &opt, c->force || kv.present[0], kv.present[1], &m, c->err))
        return err_prefix(c->err, "%s:%d", c->file, c->line);
    uint32_t id;
    if (scene_add_model(c->s, m, &id, c->err))
        return -1;
    return names_add(c, &c->models, "model", t->tok[1], id);
}

static int do_instance(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"translate", ARG_NUM, 3, 0}, {"rotate", ARG_NUM, 3, 0}, {"scale", ARG_NUM, 1, 0},
                                   {"material", ARG_WORD, 0, 0}, {0, 0, 0, 0}};
    if (t->n < 2)
        return fail(c, "instance expects a model name: instance MODEL translate X Y Z ...");
    uint32_t model;
    if (names_find(&c->models, t->tok[1], &model))
        return fail(c, "unknown model '%s' (define it with 'model %s FILE' first)", t->tok[1], t->tok[1]);
    KeyVals kv;
    if (read_keys(c, t, 2, "instance", spec, &kv))
        return -1;
    Instance in = instance_make(model, kv_vec(&kv, 0), kv_vec(&kv, 1), kv.present[2] ? kv.num[2][0] : R(1));
    if (positive(c, in.scale, "scale", "instance"))
        return -1;
    if (kv.present[3]) {
        uint32_t mat = 0;
        if (lookup_material(c, &kv, 3, &mat))
            return -1;
        in.material = (int32_t)mat;
    }
    return scene_add_instance(c->s, in, c->err);
}

static int do_light(Ctx *c, const Tokens *t)
{
    static const KeySpec spec[] = {{"position", ARG_NUM, 3, 0}, {"direction", ARG_NUM, 3, 0}, {"target", ARG_NUM, 3, 0},
                                   {"color", ARG_NUM, 3, 0},    {"intensity", ARG_NUM, 1, 0}, {"attenuate", ARG_FLAG, 0, 0},
                                   {"angle", ARG_NUM, 1, 0},    {"soft", ARG_NUM, 1, 0},      {"radius", ARG_NUM, 1, 0},
                                   {"corner", ARG_NUM, 3, 0},   {"edge1", ARG_NUM, 3, 0},     {"edge2", ARG_NUM, 3, 0},
                                   {"samples", ARG_NUM, 1, 0},  {0, 0, 0, 0}};
    if (t->n < 2)
        return fail(c, "light expects a kind: point, spot, directional, sphere or rect");
    const char *kind = t->tok[1];
    KeyVals kv;
    if (read_keys(c, t, 2, "light", spec, &kv))
        return -1;
    vec3 color = kv.present[3] ? kv_vec(&kv, 3) : v3_splat(1);
    real intensity = kv.present[4] ? kv.num[4][0] : R(1);
    if (non_negative_vec(c, color, "color", "light") || (intensity < 0 && fail(c, "'intensity' must not be negative")))
        return -1;
    vec3 dir = kv_vec(&kv, 1);
    if (kv.present[2])
        dir = v3_sub(kv_vec(&kv, 2), kv_vec(&kv, 0));
    Light l;
    int area = strcmp(kind, "sphere") == 0 || strcmp(kind, "rect") == 0;
    if (!area && (kv.present[8] || kv.present[9] || kv.present[10] || kv.present[11] || kv.present[12]))
        return fail(c, "'radius', 'corner', 'edge1', 'edge2' and 'samples' are for sphere and rect lights");
    int samples = 4;
    if (kv.present[12]) {
        real n = kv.num[12][0];
        if (!(n >= 1 && n <= LIGHT_MAX_SAMPLES && n == floor(n)))
            return fail(c, "'samples' of light must be a whole number from 1 to %d", LIGHT_MAX_SAMPLES);
        samples = (int)n;
    }
    if (strcmp(kind, "sphere") == 0) {
        if (!kv.present[0] || !kv.present[8] || kv.present[1] || kv.present[2] || kv.present[6] || kv.present[7] ||
            kv.present[9] || kv.present[10] || kv.present[11])
            return fail(c, "a sphere light takes 'position' and 'radius' (and samples, color, intensity, attenuate) only");
        if (positive(c, kv.num[8][0], "radius", "light"))
            return -1;
        return scene_add_light(c->s, light_sphere(kv_vec(&kv, 0), kv.num[8][0], samples, color, intensity, kv.present[5]),
                               c->err);
    }
    if (strcmp(kind, "rect") == 0) {
        if (!kv.present[9] || !kv.present[10] || !kv.present[11] || kv.present[0] || kv.present[1] || kv.present[2] ||
            kv.present[6] || kv.present[7] || kv.present[8])
            return fail(c, "a rect light takes 'corner', 'edge1' and 'edge2' (and samples, color, intensity, attenuate) only");
        if (!(v3_len(v3_cross(kv_vec(&kv, 10), kv_vec(&kv, 11))) > R(0)))
            return fail(c, "the edges of a rect light must not be zero or parallel");
        return scene_add_light(c->s, light_rect(kv_vec(&kv, 9), kv_vec(&kv, 10), kv_vec(&kv, 11), samples, color, intensity,
                                                kv.present[5]),
                               c->err);
    }
    if (strcmp(kind, "point") == 0) {
        if (!kv.present[0] || kv.present[1] || kv.present[2] || kv.present[6] || kv.present[7])
            return fail(c, "a point light takes 'position' (and color, intensity, attenuate) only");
        l = light_point(kv_vec(&kv, 0), color, intensity, kv.present[5]);
    } else if (strcmp(kind, "spot") == 0) {
        if (!kv.present[0] || kv.present[1] == kv.present[2] || !kv.present[6])
            return fail(c, "a spot light needs 'position', 'angle' and one of 'direction' or 'target'");
        if (!(kv.num[6][0] > 0 && kv.num[6][0] < 180) || kv.num[7][0] < 0)
            return fail(c, "spot 'angle' must be between 0 and 180 degrees and 'soft' not negative");
        l = light_spot(kv_vec(&kv, 0), dir, kv.num[6][0], kv.num[7][0], color, intensity, kv.present[5]);
    } else if (strcmp(kind, "directional") == 0) {
        if (!kv.present[1] || kv.present[0] || kv.present[2] || kv.present[5] || kv.present[6] || kv.present[7])
            return fail(c, "a directional light takes 'direction' (and color, intensity) only");
        l = light_directional(dir, color, intensity);
    } else {
        return fail(c, "unknown light kind '%s' (point, spot, directional, sphere or rect)", kind);
    }
    if (l.kind != LIGHT_POINT && !(v3_len(dir) > R(0)))
        return fail(c, "light direction must not be zero");
    return scene_add_light(c->s, l, c->err);
}

typedef struct {
    const char *name;
    int (*fn)(Ctx *, const Tokens *);
} Directive;

static int do_ambient(Ctx *c, const Tokens *t) { return do_colour(c, t, &c->s->ambient); }
static int do_background(Ctx *c, const Tokens *t) { return do_colour(c, t, &c->s->background); }

static const Directive directives[] = {
    {"camera", do_camera},     {"ambient", do_ambient},   {"background", do_background}, {"settings", do_settings},
    {"texture", do_texture},   {"material", do_material}, {"sphere", do_sphere},         {"plane", do_plane},
    {"triangle", do_triangle}, {"model", do_model},       {"instance", do_instance},     {"light", do_light},
    {NULL, NULL}};

int scene_parse(char *text, size_t len, const char *name, const char *dir, const BvhOptions *bvh, int force,
                Scene **out, Err *err)
{
    *out = NULL;
    Ctx c;
    memset(&c, 0, sizeof c);
    c.s = scene_create();
    c.file = name;
    c.dir = dir ? dir : ".";
    c.bvh = bvh;
    c.force = force;
    c.err = err;
    int rc = c.s ? 0 : err_set(err, "%s: out of memory", name);
    uint32_t id;
    rc = rc ? rc : scene_add_material(c.s, material_default(), &id, err);
    rc = rc ? rc : names_add(&c, &c.materials, "material", "default", id);
    Lexer lx = lex_make(text, len);
    Tokens t;
    while (rc == 0 && lex_next_line(&lx, &t)) {
        c.line = lx.line;
        if (t.n == 0)
            continue;
        if (t.truncated) {
            rc = fail(&c, "line has more than 256 words");
            break;
        }
        const Directive *d = directives;
        while (d->name && strcmp(d->name, t.tok[0]) != 0)
            d++;
        if (!d->name)
            rc = fail(&c, "unknown directive '%s' (expected camera, ambient, background, settings, texture, material, "
                          "sphere, plane, triangle, model, instance or light)", t.tok[0]);
        else
            rc = d->fn(&c, &t);
    }
    if (rc == 0 && scene_prepare(c.s, err))
        rc = err_prefix(err, "%s", name);
    free(c.materials.items);
    free(c.textures.items);
    free(c.models.items);
    if (rc) {
        scene_destroy(c.s);
        return -1;
    }
    *out = c.s;
    return 0;
}

int scene_load(const char *path, const BvhOptions *bvh, int force, Scene **out, Err *err)
{
    char *text;
    size_t len;
    *out = NULL;
    if (file_read_all(path, SCENE_MAX_BYTES, &text, &len, err))
        return -1;
    char dir[4096];
    file_dirname(path, dir, sizeof dir);
    int rc = scene_parse(text, len, path, dir, bvh, force, out, err);
    free(text);
    return rc;
}
