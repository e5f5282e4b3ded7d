/* wire.c - see wire.h.  Every item travels by its field table (field.h,
 * scene/scene_fields.c): scalars as float64, which holds a float or a
 * double exactly, so that the client renders with bit-for-bit the server's
 * values; what only some items use (a lens, glass, a textured plane) in
 * groups that cost nothing where unused. */
#include "net/wire.h"

#include "scene/scene_fields.h"

#include <stdlib.h>
#include <string.h>

static void put_vec(Sink *s, vec3 v)
{
    for (int k = 0; k < 3; k++) {
        double d = (double)v.e[k];
        sink_put(s, &d, sizeof d);
    }
}

static vec3 get_vec(Cursor *c)
{
    double d[3] = {0, 0, 0};
    cursor_get(c, d, sizeof d);
    return v3((real)d[0], (real)d[1], (real)d[2]);
}

/* The sections after the header, in order: what each holds a count of. */
enum { SEC_TEXTURES, SEC_MATERIALS, SEC_SPHERES, SEC_PLANES, SEC_TRIANGLES, SEC_MODELS, SEC_INSTANCES, SEC_LIGHTS, SECTIONS };

int wire_encode_scene(const Scene *s, const Asset *model_assets, const Asset *texture_assets, Sink *o, Err *err)
{
    if (!s->checked) /* the scene's checks have passed */
        return err_set(err, "wire: scene not checked");
    sink_u32(o, WIRE_MAGIC);
    sink_u32(o, WIRE_VERSION);
    sink_u32(o, PROTO_BOM);
    CameraSpec cam = {.cam = s->camera};
    field_encode(&camera_kind, &cam, o);
    put_vec(o, s->ambient);
    put_vec(o, s->background);
    field_encode(&environment_kind, &s->environment, o);
    SettingsSpec set = {.rs = s->settings};
    field_encode(&settings_kind, &set, o);
    uint32_t counts[SECTIONS] = {s->texture_count, s->material_count, s->sphere_count, s->plane_count,
                                 s->tri_count,     s->model_count,    s->instance_count, s->light_count};
    sink_put(o, counts, sizeof counts);
    for (uint32_t i = 0; i < s->texture_count; i++)
        sink_put(o, texture_assets[i].hash, PROTO_HASH);
    for (uint32_t i = 0; i < s->material_count; i++)
        field_encode(&material_kind, &s->materials[i], o);
    for (uint32_t i = 0; i < s->sphere_count; i++)
        field_encode(&sphere_kind, &s->spheres[i], o);
    for (uint32_t i = 0; i < s->plane_count; i++)
        field_encode(&plane_kind, &s->planes[i], o);
    for (uint32_t i = 0; i < s->tri_count; i++) {
        TriSpec t = tri_spec(s, i);
        field_encode(&triangle_kind, &t, o);
    }
    for (uint32_t i = 0; i < s->model_count; i++)
        sink_put(o, model_assets[i].hash, PROTO_HASH);
    for (uint32_t i = 0; i < s->instance_count; i++)
        field_encode(&instance_kind, &s->instances[i], o);
    for (uint32_t i = 0; i < s->light_count; i++) {
        LightSpec l = {.l = s->lights[i]};
        field_encode(&light_kind, &l, o);
    }
    return o->failed ? err_set(err, "wire: out of memory serialising the scene") : 0;
}

/* The header, the camera, the colours and the settings; the sections' counts
 * checked against the bytes left (each item's fewest bytes). */
static const char *decode_head(Cursor *c, Scene *s, uint32_t n[SECTIONS])
{
    CameraSpec cam;
    memset(&cam, 0, sizeof cam);
    if (field_decode(&camera_kind, c, &cam, sizeof cam))
        return c->failed ? "truncated header" : "bad camera";
    s->camera = cam.cam;
    s->ambient = get_vec(c);
    s->background = get_vec(c);
    SceneEnvironment env;
    memset(&env, 0, sizeof env);
    if (field_decode(&environment_kind, c, &env, sizeof env))
        return c->failed ? "truncated header" : "bad environment";
    s->environment = env;
    SettingsSpec set;
    memset(&set, 0, sizeof set);
    if (field_decode(&settings_kind, c, &set, sizeof set))
        return c->failed ? "truncated header" : "bad settings";
    s->settings = set.rs;
    cursor_get(c, n, SECTIONS * sizeof *n);
    if (c->failed)
        return "truncated header";
    const uint32_t min_size[SECTIONS] = {PROTO_HASH,
                                         field_min_bytes(&material_kind),
                                         field_min_bytes(&sphere_kind),
                                         field_min_bytes(&plane_kind),
                                         field_min_bytes(&triangle_kind),
                                         PROTO_HASH,
                                         field_min_bytes(&instance_kind),
                                         field_min_bytes(&light_kind)};
    uint64_t need = 0;
    for (int i = 0; i < SECTIONS; i++)
        need += (uint64_t)n[i] * min_size[i];
    return need > c->left ? "counts larger than the data" : NULL;
}

/* An asset section: hashes, each of an asset the client holds. */
static const char *decode_assets(Cursor *c, Scene *s, const AssetCache *cache, int models, uint32_t n, int *rc,
                                 Err *err)
{
    for (uint32_t i = 0; *rc == 0 && i < n; i++) {
        uint8_t h[PROTO_HASH];
        cursor_get(c, h, PROTO_HASH);
        if (models) {
            Model *m = asset_cache_model(cache, h);
            if (!m)
                return "model asset not received";
            *rc = scene_add_model(s, m, NULL, err);
        } else {
            Texture *t = asset_cache_texture(cache, h);
            if (!t)
                return "texture asset not received";
            *rc = scene_add_texture(s, t, NULL, err);
        }
    }
    return NULL;
}

/* The items of the sections after the textures, by their tables. */
static const char *decode_items(Cursor *c, Scene *s, const AssetCache *cache, const uint32_t n[SECTIONS], int *rc,
                                Err *err)
{
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_MATERIALS]; i++) {
        Material m;
        memset(&m, 0, sizeof m);
        if (field_decode(&material_kind, c, &m, sizeof m))
            return c->failed ? "truncated data" : "bad material";
        *rc = scene_add_material(s, m, NULL, err);
    }
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_SPHERES]; i++) {
        Sphere sp;
        memset(&sp, 0, sizeof sp);
        if (field_decode(&sphere_kind, c, &sp, sizeof sp))
            return c->failed ? "truncated data" : "bad sphere";
        *rc = scene_add_sphere(s, sp, err);
    }
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_PLANES]; i++) {
        Plane p;
        memset(&p, 0, sizeof p);
        if (field_decode(&plane_kind, c, &p, sizeof p))
            return c->failed ? "truncated data" : "bad plane";
        *rc = scene_add_plane(s, p, err);
    }
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_TRIANGLES]; i++) {
        TriSpec t;
        memset(&t, 0, sizeof t);
        if (field_decode(&triangle_kind, c, &t, sizeof t))
            return c->failed ? "truncated data" : "bad triangle";
        *rc = scene_add_tri_spec(s, &t, err);
    }
    const char *bad = *rc ? NULL : decode_assets(c, s, cache, 1, n[SEC_MODELS], rc, err);
    if (bad)
        return bad;
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_INSTANCES]; i++) {
        InstanceSpec in; /* the kind's file-only fields (lights, camera) get their defaults there */
        memset(&in, 0, sizeof in);
        if (field_decode(&instance_kind, c, &in, sizeof in))
            return c->failed ? "truncated data" : "bad instance";
        *rc = scene_add_instance(s, in.in, err);
    }
    for (uint32_t i = 0; *rc == 0 && i < n[SEC_LIGHTS]; i++) {
        LightSpec l;
        memset(&l, 0, sizeof l);
        if (field_decode(&light_kind, c, &l, sizeof l))
            return c->failed ? "truncated data" : "bad light";
        *rc = scene_add_light(s, l.l, err);
    }
    return NULL;
}

int wire_decode_scene(const void *data, size_t len, const AssetCache *cache, Scene **out, Err *err)
{
    *out = NULL;
    Cursor c = cursor_make(data, len);
    uint32_t head[3];
    if (cursor_get(&c, head, sizeof head))
        return err_set(err, "scene: %zu bytes is too short for a header", len);
    if (head[0] != WIRE_MAGIC)
        return err_set(err, "scene: bad magic 0x%08x", head[0]);
    if (head[2] != PROTO_BOM)
        return err_set(err, "scene: byte-order mark 0x%08x: the sender has the other byte order", head[2]);
    if (head[1] != WIRE_VERSION)
        return err_set(err, "scene: version %u, this build reads %u", head[1], WIRE_VERSION);
    Scene *s = scene_create();
    if (!s)
        return err_set(err, "scene: out of memory");
    s->borrowed_assets = 1;
    uint32_t n[SECTIONS];
    int rc = 0;
    const char *bad = decode_head(&c, s, n);
    if (!bad)
        bad = decode_assets(&c, s, cache, 0, n[SEC_TEXTURES], &rc, err);
    if (!bad && rc == 0)
        bad = decode_items(&c, s, cache, n, &rc, err);
    if (!bad && rc == 0 && c.failed)
        bad = "truncated data";
    if (!bad && rc == 0 && c.left != 0)
        bad = "trailing bytes";
    if (bad)
        rc = err_set(err, "scene: %s", bad);
    /* scene_check checks every reference and value (the tables' ranges, indices) */
    if (rc == 0 && scene_check(s, err))
        rc = -1;
    if (rc) {
        scene_destroy(s);
        return -1;
    }
    *out = s;
    return 0;
}

int wire_encode_view(const View *v, Sink *o, Err *err)
{
    CameraSpec cam = {.cam = v->camera};
    field_encode(&camera_kind, &cam, o);
    SettingsSpec set = {.rs = v->settings};
    field_encode(&settings_kind, &set, o);
    return o->failed ? err_set(err, "wire: out of memory serialising the view") : 0;
}

int wire_decode_view(const void *data, size_t len, View *out, Err *err)
{
    Cursor c = cursor_make(data, len);
    CameraSpec cam;
    SettingsSpec set;
    memset(&cam, 0, sizeof cam);
    memset(&set, 0, sizeof set);
    if (field_decode(&camera_kind, &c, &cam, sizeof cam))
        return err_set(err, "view: %s", c.failed ? "truncated camera" : "bad camera");
    if (field_decode(&settings_kind, &c, &set, sizeof set))
        return err_set(err, "view: %s", c.failed ? "truncated settings" : "bad settings");
    if (c.left != 0)
        return err_set(err, "view: %zu trailing bytes", c.left);
    char why[160];
    if (settings_problem(&set.rs, why, sizeof why))
        return err_set(err, "view: settings: %s", why);
    if (camera_problem(&cam.cam, why, sizeof why))
        return err_set(err, "view: camera: %s", why);
    *out = (View){.camera = cam.cam, .settings = set.rs};
    return 0;
}
