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
#include "scene/scene_fields.h"
#include "scene/scene_gltf.h"

#define SCENE_MAX_BYTES ((size_t)256 << 20)
#define NAME_MAX_LEN 64
#define MAX_KEYS 24

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
    char **model_paths; /* each model's file, by its id */
    uint32_t model_path_count;
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

/* "file:line", for the field reader's errors. */
static const char *where(Ctx *c, char *buf, size_t size)
{
    snprintf(buf, size, "%s:%d", c->file, c->line);
    return buf;
}

/* A directive's keys by its kind's table (field.h) into item, which holds
 * its defaults. */
static int read_fields(Ctx *c, const FieldKind *k, const Tokens *t, int start, int variant, void *item, FieldSet *given,
                       const char **names)
{
    char at[512];
    for (uint32_t i = 0; i < k->count; i++)
        names[i] = NULL;
    return field_read(k, t, start, variant, item, given, names, where(c, at, sizeof at), c->err);
}

/* A new item of kind k (its size bytes zero, then the table's defaults)
 * from a directive's keys. */
static int read_new(Ctx *c, const FieldKind *k, const Tokens *t, int start, int variant, void *item, size_t size,
                    FieldSet *given, const char **names)
{
    memset(item, 0, size);
    if (k->variants)
        *(int *)((char *)item + k->variant_off) = variant;
    field_defaults(k, item, size, variant);
    return read_fields(c, k, t, start, variant, item, given, names);
}

/* The material named by the directive's key `key`, where it names one,
 * into *id (else *id keeps its default). */
static int lookup_material(Ctx *c, const FieldKind *k, const char **names, const char *key, int *id)
{
    const char *name = names[field_index(k, key)];
    uint32_t m;
    if (!name)
        return 0;
    if (names_find(&c->materials, name, &m))
        return fail(c, "unknown material '%s' (define it with 'material %s ...' first)", name, name);
    *id = (int)m;
    return 0;
}

static int do_camera(Ctx *c, const Tokens *t)
{
    CameraSpec sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_new(c, &camera_kind, t, 1, 0, &sp, sizeof sp, &given, names))
        return -1;
    if (scene_fields_finish_camera(&sp, given))
        return fail(c, "camera 'lookat' point equals its position");
    c->s->camera = sp.cam;
    return 0;
}

static int do_colour(Ctx *c, const Tokens *t, vec3 *out)
{
    real v[3];
    if (t->n != 4 || lex_real(t->tok[1], &v[0]) || lex_real(t->tok[2], &v[1]) || lex_real(t->tok[3], &v[2]))
        return fail(c, "%s expects 3 finite numbers (red green blue)", t->tok[0]);
    *out = v3(v[0], v[1], v[2]);
    if (!(v[0] >= R(0) && v[1] >= R(0) && v[2] >= R(0)))
        return fail(c, "'colour' of %s must not be negative", t->tok[0]);
    return 0;
}

static int do_settings(Ctx *c, const Tokens *t)
{
    SettingsSpec sp = {.rs = c->s->settings, .adaptive = 1};
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_fields(c, &settings_kind, t, 1, 0, &sp, &given, names))
        return -1;
    scene_fields_finish_settings(&sp, given);
    c->s->settings = sp.rs;
    return 0;
}

/* A wrap mode's name (texture.h's TextureWrap); -1 for another word. */
static int wrap_named(const char *s)
{
    static const char *const names[TEXTURE_WRAP_COUNT] = {"repeat", "clamp", "mirror"};
    for (int i = 0; i < TEXTURE_WRAP_COUNT; i++)
        if (strcmp(s, names[i]) == 0)
            return i;
    return -1;
}

/* texture NAME FILE [smooth|closest] [wrap U [V]]: the words after the
 * file; 0, or -1 with the error said. */
static int texture_options(Ctx *c, const Tokens *t, int *closest, uint8_t wrap[2])
{
    static const char *const usage =
        "texture expects a name, a file, how magnified texels look and how coordinates wrap: "
        "texture NAME FILE [smooth|closest] [wrap repeat|clamp|mirror [repeat|clamp|mirror]]";
    int i = 3;
    *closest = 0;
    wrap[0] = wrap[1] = TEXTURE_REPEAT;
    if (t->n < 3)
        return fail(c, "%s", usage);
    if (i < t->n && (strcmp(t->tok[i], "closest") == 0 || strcmp(t->tok[i], "smooth") == 0))
        *closest = strcmp(t->tok[i++], "closest") == 0;
    if (i < t->n && strcmp(t->tok[i], "wrap") == 0) {
        int u = i + 1 < t->n ? wrap_named(t->tok[i + 1]) : -1;
        if (u < 0)
            return fail(c, "texture wrap expects repeat, clamp or mirror (for u and v, or u then v)%s%s%s",
                        i + 1 < t->n ? ", not '" : "", i + 1 < t->n ? t->tok[i + 1] : "", i + 1 < t->n ? "'" : "");
        int v = i + 2 < t->n ? wrap_named(t->tok[i + 2]) : u;
        if (v < 0)
            return fail(c, "texture wrap expects repeat, clamp or mirror for v, not '%s'", t->tok[i + 2]);
        wrap[0] = (uint8_t)u, wrap[1] = (uint8_t)v;
        i += 2 + (i + 2 < t->n);
    }
    if (i < t->n)
        return fail(c, "%s; '%s' is none of them", usage, t->tok[i]);
    return 0;
}

static int do_texture(Ctx *c, const Tokens *t)
{
    int closest;
    uint8_t wrap[2];
    if (texture_options(c, t, &closest, wrap))
        return -1;
    char path[4096];
    if (file_join(c->dir, t->tok[2], path, sizeof path))
        return fail(c, "texture file name '%s' is too long", t->tok[2]);
    Texture *tex;
    if (scene_add_source(c->s, path, c->err) || texture_read(path, &tex, c->err))
        return err_prefix(c->err, "%s:%d", c->file, c->line);
    tex->closest = closest;
    tex->wrap[0] = wrap[0], tex->wrap[1] = wrap[1];
    uint32_t id;
    if (scene_add_texture(c->s, tex, &id, c->err))
        return -1;
    return names_add(c, &c->textures, "texture", t->tok[1], id);
}

static int do_material(Ctx *c, const Tokens *t)
{
    if (t->n < 2)
        return fail(c, "material expects a name: material NAME diffuse R G B ...");
    Material m = material_default();
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_fields(c, &material_kind, t, 2, 0, &m, &given, names))
        return -1;
    material_file_defaults(&m, given);
    const char *tex = names[field_index(&material_kind, "texture")];
    if (tex) {
        uint32_t id;
        if (names_find(&c->textures, tex, &id))
            return fail(c, "unknown texture '%s' (define it with 'texture %s FILE' first)", tex, tex);
        m.texture = (int32_t)id;
    }
    uint32_t id;
    if (scene_add_material(c->s, m, &id, c->err))
        return -1;
    return names_add(c, &c->materials, "material", t->tok[1], id);
}

static int do_sphere(Ctx *c, const Tokens *t)
{
    Sphere sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    int mat = 0;
    if (read_new(c, &sphere_kind, t, 1, 0, &sp, sizeof sp, &given, names) ||
        lookup_material(c, &sphere_kind, names, "material", &mat))
        return -1;
    sp.material = (uint32_t)mat;
    return scene_add_sphere(c->s, sp, c->err);
}

static int do_plane(Ctx *c, const Tokens *t)
{
    Plane p;
    FieldSet given;
    const char *names[FIELD_MAX];
    int mat = 0;
    if (read_new(c, &plane_kind, t, 1, 0, &p, sizeof p, &given, names) || lookup_material(c, &plane_kind, names, "material", &mat))
        return -1;
    p.material = (uint32_t)mat;
    return scene_add_plane(c->s, p, c->err);
}

static int do_triangle(Ctx *c, const Tokens *t)
{
    TriSpec tr;
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_new(c, &triangle_kind, t, 1, 0, &tr, sizeof tr, &given, names) ||
        lookup_material(c, &triangle_kind, names, "material", &tr.material))
        return -1;
    vec3 p[3];
    for (int k = 0; k < 3; k++)
        p[k] = v3(tr.vertices[3 * k], tr.vertices[3 * k + 1], tr.vertices[3 * k + 2]);
    if (mesh_tri_is_degenerate(p))
        return fail(c, "triangle has zero area (its vertices are on one line)");
    tr.smooth = field_given(&triangle_kind, given, "normals");
    tr.textured = field_given(&triangle_kind, given, "uv");
    for (int k = 0; tr.smooth && k < 3; k++) { /* kept unit length: what the wire carries */
        vec3 n = v3_norm(v3(tr.normals[3 * k], tr.normals[3 * k + 1], tr.normals[3 * k + 2]));
        tr.normals[3 * k] = n.x, tr.normals[3 * k + 1] = n.y, tr.normals[3 * k + 2] = n.z;
    }
    return scene_add_tri_spec(c->s, &tr, c->err);
}

static int do_model(Ctx *c, const Tokens *t)
{
    if (t->n < 3)
        return fail(c, "model expects a name and a file: model NAME FILE.tmd|FILE.obj");
    ModelSpec sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_new(c, &model_kind, t, 3, 0, &sp, sizeof sp, &given, names))
        return -1;
    const int bvh_given = field_given(&model_kind, given, "bvh");
    BvhOptions opt = *c->bvh;
    if (bvh_given && !c->force) /* the command line's --bvh wins */
        opt.kind = (BvhKind)sp.bvh;
    char path[4096];
    if (file_join(c->dir, t->tok[2], path, sizeof path))
        return fail(c, "model file name '%s' is too long", t->tok[2]);
    if (!model_load_knows(path))
        return fail(c, "model file '%s' must end in .tmd, .obj, or a format the importer reads (.ply, .stl, .gltf, .glb, ...)", t->tok[2]);
    Model *m = NULL;
    if (scene_add_source(c->s, path, c->err) || model_load(path, &opt, c->force || bvh_given, sp.smooth, &m, c->err))
        return err_prefix(c->err, "%s:%d", c->file, c->line);
    uint32_t id;
    if (scene_add_model(c->s, m, &id, c->err))
        return -1;
    char **paths = id < c->model_path_count ? c->model_paths : realloc(c->model_paths, (id + 1) * sizeof *paths);
    if (!paths)
        return fail(c, "out of memory");
    c->model_paths = paths;
    for (; c->model_path_count <= id; c->model_path_count++)
        paths[c->model_path_count] = NULL;
    if (!(paths[id] = strdup(path)))
        return fail(c, "out of memory");
    return names_add(c, &c->models, "model", t->tok[1], id);
}

/* What an instance takes from its model's file: a glTF's lights and
 * camera, placed with it (scene_gltf.h).  Asked of a file that has none,
 * an error: the scene would not be lit or framed as its writer meant. */
static int instance_takes(Ctx *c, const InstanceSpec *sp, const char *name)
{
    const int want = (sp->lights ? SCENE_GLTF_LIGHTS : 0) | (sp->camera ? SCENE_GLTF_CAMERA : 0);
    if (!want)
        return 0;
    const char *path = sp->in.model < c->model_path_count ? c->model_paths[sp->in.model] : NULL;
    const char *what = sp->lights && sp->camera ? "lights and camera" : sp->lights ? "lights" : "camera";
    if (!path || !scene_gltf_is(path))
        return fail(c, "instance '%s' takes its model's %s, which only a glTF (.gltf, .glb) gives", name, what);
    int got;
    if (scene_gltf_take(c->s, path, &sp->in, want, &got, c->err))
        return err_prefix(c->err, "%s:%d", c->file, c->line);
    if ((want & SCENE_GLTF_LIGHTS) && !(got & SCENE_GLTF_LIGHTS))
        return fail(c, "instance '%s' takes its model's lights, but %s gives none (KHR_lights_punctual) that can be placed there",
                    name, path);
    if ((want & SCENE_GLTF_CAMERA) && !(got & SCENE_GLTF_CAMERA))
        return fail(c, "instance '%s' takes its model's camera, but %s gives none that can be placed there", name, path);
    return 0;
}

static int do_instance(Ctx *c, const Tokens *t)
{
    if (t->n < 2)
        return fail(c, "instance expects a model name: instance MODEL translate X Y Z ...");
    uint32_t model;
    if (names_find(&c->models, t->tok[1], &model))
        return fail(c, "unknown model '%s' (define it with 'model %s FILE' first)", t->tok[1], t->tok[1]);
    InstanceSpec sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    int mat = -1;
    if (read_new(c, &instance_kind, t, 2, 0, &sp, sizeof sp, &given, names) ||
        lookup_material(c, &instance_kind, names, "material", &mat))
        return -1;
    sp.in.model = model;
    sp.in.material = mat;
    return scene_add_instance(c->s, sp.in, c->err) || instance_takes(c, &sp, t->tok[1]) ? -1 : 0;
}

static int do_light(Ctx *c, const Tokens *t)
{
    if (t->n < 2)
        return fail(c, "light expects a kind: point, spot, directional, sphere or rect");
    int kind = field_variant(&light_kind, t->tok[1]);
    if (kind < 0)
        return fail(c, "unknown light kind '%s' (point, spot, directional, sphere or rect)", t->tok[1]);
    LightSpec sp;
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_new(c, &light_kind, t, 2, kind, &sp, sizeof sp, &given, names))
        return -1;
    const char *why = scene_fields_finish_light(&sp, given);
    char buf[160];
    if (!why)
        why = light_problem(&sp.l, buf, sizeof buf);
    if (why)
        return fail(c, "%s", why);
    return scene_add_light(c->s, sp.l, c->err);
}

static int do_environment(Ctx *c, const Tokens *t)
{
    if (c->s->environment.texture >= 0)
        return fail(c, "a scene has one environment");
    SceneEnvironment e;
    FieldSet given;
    const char *names[FIELD_MAX];
    if (read_new(c, &environment_kind, t, 1, 0, &e, sizeof e, &given, names))
        return -1;
    const char *tex = names[field_index(&environment_kind, "texture")];
    uint32_t id;
    if (names_find(&c->textures, tex, &id))
        return fail(c, "unknown texture '%s' (define it with 'texture %s FILE' first)", tex, tex);
    e.texture = (int32_t)id;
    c->s->environment = e;
    return 0;
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
    {"environment", do_environment}, {NULL, NULL}};

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
                          "sphere, plane, triangle, model, instance, light or environment)", t.tok[0]);
        else
            rc = d->fn(&c, &t);
    }
    if (rc == 0 && scene_check(c.s, err))
        rc = err_prefix(err, "%s", name);
    free(c.materials.items);
    free(c.textures.items);
    free(c.models.items);
    for (uint32_t i = 0; i < c.model_path_count; i++)
        free(c.model_paths[i]);
    free(c.model_paths);
    if (rc) {
        scene_destroy(c.s);
        return -1;
    }
    *out = c.s;
    return 0;
}

int scene_parse_camera(const char *text, const char *name, Camera *out, Err *err)
{
    char line[1024];
    const int whole = strncmp(text, "camera", 6) == 0 && (text[6] == ' ' || text[6] == '\t');
    const int n = snprintf(line, sizeof line, "%s%s", whole ? "" : "camera ", text);
    if (n < 0 || (size_t)n >= sizeof line)
        return err_set(err, "%s: more than %zu characters", name, sizeof line - 8);
    if (strpbrk(line, "\n\r"))
        return err_set(err, "%s: one line, without line breaks", name);
    Ctx c;
    memset(&c, 0, sizeof c);
    c.file = name;
    c.dir = ".";
    c.err = err;
    c.line = 1;
    if (!(c.s = scene_create()))
        return err_set(err, "%s: out of memory", name);
    Lexer lx = lex_make(line, (size_t)n);
    Tokens t;
    int rc = lex_next_line(&lx, &t) && t.n > 0 ? 0 : err_set(err, "%s: no camera fields", name);
    if (rc == 0 && t.truncated)
        rc = fail(&c, "line has more than 256 words");
    rc = rc ? rc : do_camera(&c, &t);
    if (rc == 0)
        *out = c.s->camera;
    scene_destroy(c.s);
    return rc ? -1 : 0;
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
    if (rc == 0 && scene_add_source(*out, path, err)) {
        scene_destroy(*out);
        *out = NULL;
        return -1;
    }
    return rc;
}
