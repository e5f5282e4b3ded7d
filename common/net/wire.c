/* wire.c - see wire.h.  Scalars travel as float64, which holds a float or a
 * double exactly: the client renders with bit-for-bit the server's values. */
#include "net/wire.h"

#include <stdlib.h>
#include <string.h>

enum { TRI_SMOOTH = 1, TRI_UV = 2 };
enum { PLANE_MAPPED = 1 };
/* The extras word: what only some scenes carry.  WIRE_OPTICS: a material
 * reflects, refracts or emits; the settings of secondary rays follow, and
 * every material carries a word of MAT_* flags and the fields they name.
 * WIRE_CAMERA: the camera is not a plain pinhole; its kind, its size (the
 * orthographic width, or the fisheye's field of view), a pinhole's aperture
 * and focus distance and the lens samples follow.  WIRE_EXPOSURE: the
 * exposure in stops (f64) follows.  WIRE_HDR: the frame is high dynamic
 * range, its pixels RGBE (4 bytes, DATA packets included); nothing follows.
 * WIRE_PRODUCT: the sampled effects multiply (settings sampling product);
 * nothing follows. */
enum { WIRE_OPTICS = 1, WIRE_CAMERA = 2, WIRE_EXPOSURE = 4, WIRE_HDR = 8, WIRE_PRODUCT = 16 };
enum { MAT_REFLECT = 1, MAT_DIELECTRIC = 2, MAT_EMIT = 4 };

static uint32_t material_optics(const Material *m)
{
    return (material_reflects(m) ? MAT_REFLECT : 0u) | (material_dielectric(m) ? MAT_DIELECTRIC : 0u) |
           (material_emits(m) ? MAT_EMIT : 0u);
}

static void put_f64(Sink *s, real v)
{
    double d = (double)v;
    sink_put(s, &d, sizeof d);
}
static void put_vec(Sink *s, vec3 v)
{
    put_f64(s, v.x);
    put_f64(s, v.y);
    put_f64(s, v.z);
}

int wire_encode_scene(const Scene *s, const Asset *model_assets, const Asset *texture_assets, Sink *o, Err *err)
{
    if (!s->prepared) /* what it carries follows the features scene_prepare derives */
        return err_set(err, "wire: scene not prepared");
    sink_u32(o, WIRE_MAGIC);
    sink_u32(o, WIRE_VERSION);
    sink_u32(o, PROTO_BOM);
    const Camera *c = &s->camera;
    put_vec(o, c->pos);
    put_f64(o, c->yaw);
    put_f64(o, c->pitch);
    put_f64(o, c->roll);
    put_f64(o, c->zoom);
    put_vec(o, s->ambient);
    put_vec(o, s->background);
    const RenderSettings *rs = &s->settings;
    uint32_t set[6] = {(uint32_t)rs->aa,      (uint32_t)rs->adaptive, (uint32_t)rs->shading,
                       (uint32_t)rs->shadows, (uint32_t)rs->filter,   (uint32_t)rs->linear};
    sink_put(o, set, sizeof set);
    /* the settings of secondary rays go where any material, the scene's or
     * a model's (a .tmd carries them), has optics: what scene_prepare found */
    uint32_t extras = scene_has(s, FEAT_REFLECT | FEAT_REFRACT | FEAT_EMIT) ? WIRE_OPTICS : 0u;
    if (c->kind != CAMERA_PINHOLE || c->aperture > R(0))
        extras |= WIRE_CAMERA;
    if (rs->exposure != R(0))
        extras |= WIRE_EXPOSURE;
    if (rs->hdr)
        extras |= WIRE_HDR;
    if (rs->sampling == SAMPLING_PRODUCT)
        extras |= WIRE_PRODUCT;
    sink_u32(o, extras);
    if (extras & WIRE_EXPOSURE)
        put_f64(o, rs->exposure);
    if (extras & WIRE_CAMERA) {
        sink_u32(o, (uint32_t)c->kind);
        put_f64(o, c->kind == CAMERA_ORTHO ? c->size : c->kind == CAMERA_FISHEYE ? c->fov : R(0));
        put_f64(o, c->aperture);
        put_f64(o, c->focus);
        sink_u32(o, (uint32_t)rs->lens_samples);
    }
    if (extras & WIRE_OPTICS) {
        sink_u32(o, (uint32_t)rs->depth);
        put_f64(o, rs->cutoff);
        sink_u32(o, (uint32_t)rs->fresnel);
        sink_u32(o, (uint32_t)rs->glass_shadows);
        sink_u32(o, (uint32_t)rs->rough_samples);
        sink_u32(o, (uint32_t)rs->depth_limit);
    }
    uint32_t counts[8] = {s->texture_count, s->material_count, s->sphere_count, s->plane_count,
                          s->tri_count,     s->model_count,    s->instance_count, s->light_count};
    sink_put(o, counts, sizeof counts);
    for (uint32_t i = 0; i < s->texture_count; i++)
        sink_put(o, texture_assets[i].hash, PROTO_HASH);
    for (uint32_t i = 0; i < s->material_count; i++) {
        const Material *m = &s->materials[i];
        put_vec(o, m->kd);
        put_vec(o, m->ks);
        put_f64(o, m->shininess);
        sink_u32(o, (uint32_t)m->texture);
        if (!(extras & WIRE_OPTICS))
            continue;
        uint32_t opt = material_optics(m);
        sink_u32(o, opt);
        if (opt & MAT_REFLECT) {
            put_vec(o, m->kr);
            put_f64(o, m->roughness);
        }
        if (opt & MAT_DIELECTRIC) {
            put_f64(o, m->ior);
            put_vec(o, m->kt);
            put_vec(o, m->absorb);
        }
        if (opt & MAT_EMIT)
            put_vec(o, m->ke);
    }
    for (uint32_t i = 0; i < s->sphere_count; i++) {
        put_vec(o, s->spheres[i].centre);
        put_f64(o, s->spheres[i].radius);
        sink_u32(o, s->spheres[i].material);
    }
    for (uint32_t i = 0; i < s->plane_count; i++) {
        const Plane *p = &s->planes[i];
        put_vec(o, p->point);
        put_vec(o, p->normal);
        sink_u32(o, p->material);
        /* the texture mapping only when it is not the default */
        int mapped = p->uv_scale != R(1) || p->uv_rotate != R(0);
        sink_u32(o, mapped ? PLANE_MAPPED : 0);
        if (mapped) {
            put_f64(o, p->uv_scale);
            put_f64(o, p->uv_rotate);
        }
    }
    for (uint32_t i = 0; i < s->tri_count; i++) {
        const TriAttr *a = &s->tri_attrs[i];
        for (int k = 0; k < 3; k++)
            put_vec(o, tri_vertex(&s->tris[i], k));
        sink_u32(o, a->material);
        sink_u32(o, (a->smooth ? TRI_SMOOTH : 0) | (a->textured ? TRI_UV : 0));
        for (int k = 0; a->smooth && k < 3; k++)
            put_vec(o, a->n[k]);
        for (int k = 0; a->textured && k < 6; k++)
            put_f64(o, a->uv[k]);
    }
    for (uint32_t i = 0; i < s->model_count; i++)
        sink_put(o, model_assets[i].hash, PROTO_HASH);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const Instance *in = &s->instances[i];
        sink_u32(o, in->model);
        put_vec(o, in->translate);
        put_vec(o, in->rotate);
        put_f64(o, in->scale);
        sink_u32(o, (uint32_t)in->material);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const Light *l = &s->lights[i];
        sink_u32(o, (uint32_t)l->kind);
        put_vec(o, l->color);
        put_f64(o, l->intensity);
        if (l->kind != LIGHT_DIRECTIONAL) {
            put_vec(o, l->pos);
            sink_u32(o, (uint32_t)l->attenuate);
        }
        if (light_has_direction(l))
            put_vec(o, l->dir);
        if (l->kind == LIGHT_SPOT) {
            put_f64(o, l->angle);
            put_f64(o, l->soft);
        }
        if (l->kind == LIGHT_SPHERE)
            put_f64(o, l->radius);
        if (l->kind == LIGHT_RECT) {
            put_vec(o, l->edge1);
            put_vec(o, l->edge2);
        }
        if (light_is_area(l))
            sink_u32(o, (uint32_t)l->samples);
    }
    return o->failed ? err_set(err, "wire: out of memory serialising the scene") : 0;
}

static real get_f64(Cursor *c)
{
    double d = 0;
    cursor_get(c, &d, sizeof d);
    return (real)d;
}
static vec3 get_vec(Cursor *c)
{
    real x = get_f64(c), y = get_f64(c);
    return v3(x, y, get_f64(c));
}

/* Smallest encoded size of one item of each section, to bound counts by the bytes left. */
enum { MIN_TEXTURE = 32, MIN_MATERIAL = 60, MIN_SPHERE = 36, MIN_PLANE = 56, MIN_TRI = 80, MIN_MODEL = 32,
       MIN_INSTANCE = 64, MIN_LIGHT = 36 };

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
    vec3 pos = get_vec(&c);
    real yaw = get_f64(&c), pitch = get_f64(&c), roll = get_f64(&c), zoom = get_f64(&c);
    s->camera = camera_from_angles(pos, yaw, pitch, roll, zoom);
    s->ambient = get_vec(&c);
    s->background = get_vec(&c);
    uint32_t set[6], n[8], extras = 0, optics[5] = {0, 0, 0, 0, 0}, lens_samples = 0;
    real cutoff = R(0), aperture = R(0), focus = R(0), exposure = R(0);
    cursor_get(&c, set, sizeof set);
    extras = cursor_u32(&c);
    if (extras & WIRE_EXPOSURE)
        exposure = get_f64(&c);
    uint32_t cam_kind = CAMERA_PINHOLE;
    real cam_size = R(0);
    if (extras & WIRE_CAMERA) {
        cam_kind = cursor_u32(&c);
        cam_size = get_f64(&c);
        aperture = get_f64(&c);
        focus = get_f64(&c);
        lens_samples = cursor_u32(&c);
    }
    if (extras & WIRE_OPTICS) {
        optics[0] = cursor_u32(&c);
        cutoff = get_f64(&c);
        optics[1] = cursor_u32(&c);
        optics[2] = cursor_u32(&c);
        optics[3] = cursor_u32(&c);
        optics[4] = cursor_u32(&c);
    }
    cursor_get(&c, n, sizeof n);
    const char *bad = NULL;
    static const uint32_t min_size[8] = {MIN_TEXTURE, MIN_MATERIAL, MIN_SPHERE, MIN_PLANE, MIN_TRI, MIN_MODEL, MIN_INSTANCE, MIN_LIGHT};
    uint64_t need = 0;
    for (int i = 0; i < 8; i++)
        need += (uint64_t)n[i] * min_size[i];
    if (c.failed)
        bad = "truncated header";
    else if (need > c.left)
        bad = "counts larger than the data";
    else if (set[0] < 1 || set[0] > AA_MAX || set[1] > 1 || set[2] > SHADE_DIFFUSE || set[3] > 1 || set[4] >= FILTER_COUNT ||
             set[5] > 1)
        bad = "invalid settings";
    else if (extras & ~(uint32_t)(WIRE_OPTICS | WIRE_CAMERA | WIRE_EXPOSURE | WIRE_HDR | WIRE_PRODUCT))
        bad = "unknown extras";
    else if (cam_kind > CAMERA_FISHEYE || ((extras & WIRE_CAMERA) && cam_kind == CAMERA_PINHOLE && !(aperture > R(0))))
        bad = "invalid camera kind";
    else if (lens_samples > SCENE_MAX_SAMPLES || optics[3] > SCENE_MAX_SAMPLES)
        bad = "invalid sample counts";
    else if (optics[0] > SCENE_MAX_DEPTH || !(cutoff >= R(0) && cutoff < R(1)) || optics[1] > FRESNEL_SCHLICK ||
             optics[2] > 1 || optics[4] >= LIMIT_COUNT)
        bad = "invalid secondary-ray settings";
    if (!bad) {
        s->camera.kind = (CameraKind)cam_kind;
        if (cam_kind == CAMERA_ORTHO)
            s->camera.size = cam_size;
        else if (cam_kind == CAMERA_FISHEYE)
            s->camera.fov = cam_size;
        s->camera.aperture = aperture;
        s->camera.focus = focus;
        RenderSettings *rs = &s->settings;
        rs->aa = (int)set[0];
        rs->adaptive = (int)set[1];
        rs->shading = (ShadeModel)set[2];
        rs->shadows = (int)set[3];
        rs->filter = (TextureFilter)set[4];
        rs->linear = (int)set[5];
        rs->exposure = exposure;
        rs->hdr = (extras & WIRE_HDR) != 0;
        rs->sampling = extras & WIRE_PRODUCT ? SAMPLING_PRODUCT : SAMPLING_BUDGET;
        if (extras & WIRE_OPTICS) {
            rs->depth = (int)optics[0];
            rs->cutoff = cutoff;
            rs->fresnel = (FresnelModel)optics[1];
            rs->glass_shadows = (int)optics[2];
            rs->rough_samples = (int)optics[3];
            rs->depth_limit = (DepthLimit)optics[4];
        }
        if (extras & WIRE_CAMERA)
            rs->lens_samples = (int)lens_samples;
    }
    int rc = 0;
    for (uint32_t i = 0; !bad && rc == 0 && i < n[0]; i++) {
        uint8_t h[PROTO_HASH];
        cursor_get(&c, h, PROTO_HASH);
        Texture *t = asset_cache_texture(cache, h);
        if (!t)
            bad = "texture asset not received";
        else
            rc = scene_add_texture(s, t, NULL, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[1]; i++) {
        Material m = {0};
        m.kd = get_vec(&c);
        m.ks = get_vec(&c);
        m.shininess = get_f64(&c);
        m.texture = (int32_t)cursor_u32(&c);
        uint32_t opt = extras & WIRE_OPTICS ? cursor_u32(&c) : 0;
        if (opt & ~(uint32_t)(MAT_REFLECT | MAT_DIELECTRIC | MAT_EMIT)) {
            bad = "unknown material flags";
            break;
        }
        if (opt & MAT_REFLECT) {
            m.kr = get_vec(&c);
            m.roughness = get_f64(&c);
        }
        if (opt & MAT_DIELECTRIC) {
            m.ior = get_f64(&c);
            m.kt = get_vec(&c);
            m.absorb = get_vec(&c);
        }
        if (opt & MAT_EMIT)
            m.ke = get_vec(&c);
        rc = scene_add_material(s, m, NULL, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[2]; i++) {
        Sphere sp;
        sp.centre = get_vec(&c);
        sp.radius = get_f64(&c);
        sp.material = cursor_u32(&c);
        rc = scene_add_sphere(s, sp, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[3]; i++) {
        vec3 point = get_vec(&c), normal = get_vec(&c);
        Plane p = plane_make(point, normal, cursor_u32(&c));
        uint32_t flags = cursor_u32(&c);
        if (flags & ~(uint32_t)PLANE_MAPPED) {
            bad = "unknown plane flags";
            break;
        }
        if (flags & PLANE_MAPPED) {
            p.uv_scale = get_f64(&c);
            p.uv_rotate = get_f64(&c);
        }
        rc = scene_add_plane(s, p, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[4]; i++) {
        vec3 p[3], nn[3];
        real uv[6];
        for (int k = 0; k < 3; k++)
            p[k] = get_vec(&c);
        uint32_t mat = cursor_u32(&c), flags = cursor_u32(&c);
        if (flags & ~(uint32_t)(TRI_SMOOTH | TRI_UV)) {
            bad = "unknown triangle flags";
            break;
        }
        for (int k = 0; (flags & TRI_SMOOTH) && k < 3; k++)
            nn[k] = get_vec(&c);
        for (int k = 0; (flags & TRI_UV) && k < 6; k++)
            uv[k] = get_f64(&c);
        rc = scene_add_triangle(s, p, (flags & TRI_SMOOTH) ? nn : NULL, (flags & TRI_UV) ? uv : NULL, mat, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[5]; i++) {
        uint8_t h[PROTO_HASH];
        cursor_get(&c, h, PROTO_HASH);
        Model *m = asset_cache_model(cache, h);
        if (!m)
            bad = "model asset not received";
        else
            rc = scene_add_model(s, m, NULL, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[6]; i++) {
        uint32_t model = cursor_u32(&c);
        vec3 t = get_vec(&c), r = get_vec(&c);
        real sc = get_f64(&c);
        Instance in = instance_make(model, t, r, sc);
        in.material = (int32_t)cursor_u32(&c);
        rc = scene_add_instance(s, in, err);
    }
    for (uint32_t i = 0; !bad && rc == 0 && i < n[7]; i++) {
        Light l;
        memset(&l, 0, sizeof l);
        uint32_t kind = cursor_u32(&c);
        if (kind > LIGHT_RECT) {
            bad = "unknown light kind";
            break;
        }
        l.kind = (LightKind)kind;
        l.color = get_vec(&c);
        l.intensity = get_f64(&c);
        if (l.kind != LIGHT_DIRECTIONAL) {
            l.pos = get_vec(&c);
            l.attenuate = cursor_u32(&c) != 0;
        }
        if (light_has_direction(&l))
            l.dir = get_vec(&c);
        if (l.kind == LIGHT_SPOT) {
            l.angle = get_f64(&c);
            l.soft = get_f64(&c);
        }
        if (l.kind == LIGHT_SPHERE)
            l.radius = get_f64(&c);
        if (l.kind == LIGHT_RECT) {
            l.edge1 = get_vec(&c);
            l.edge2 = get_vec(&c);
        }
        if (light_is_area(&l))
            l.samples = (int)cursor_u32(&c);
        rc = scene_add_light(s, l, err);
    }
    if (!bad && rc == 0 && c.failed)
        bad = "truncated data";
    if (!bad && rc == 0 && c.left != 0)
        bad = "trailing bytes";
    if (bad)
        rc = err_set(err, "scene: %s", bad);
    /* scene_prepare checks every reference and value (indices, finiteness, ranges) */
    if (rc == 0 && scene_prepare(s, err))
        rc = -1;
    if (rc) {
        scene_destroy(s);
        return -1;
    }
    *out = s;
    return 0;
}
