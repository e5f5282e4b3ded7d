/* scene_preview.c - see scene_preview.h. */
#include "scene/scene_preview.h"

#include "model/model_load.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "model/gltf_json.h"
#include "model/gltf_scene.h"

/* Whether path names a glTF (by its ending, as the importer is chosen). */
static int is_gltf(const char *path, int *glb)
{
    const size_t n = strlen(path);
    *glb = n >= 4 && strcasecmp(path + n - 4, ".glb") == 0;
    return *glb || (n >= 5 && strcasecmp(path + n - 5, ".gltf") == 0);
}

/* The camera a glTF gives (glTF's vertical field of view across the
 * file's aspect ratio, else 4:3, as lanray's horizontal one; its up by the
 * roll); -1 where it cannot be made. */
static int gltf_camera(Scene *s, const GltfCamera *c)
{
    const vec3 eye = v3((real)c->pos[0], (real)c->pos[1], (real)c->pos[2]);
    const vec3 fwd = v3((real)c->fwd[0], (real)c->fwd[1], (real)c->fwd[2]);
    const vec3 up = v3((real)c->up[0], (real)c->up[1], (real)c->up[2]);
    const double aspect = c->aspect > 0.0 ? c->aspect : 4.0 / 3.0;
    const real fov = (real)(2.0 * atan(tan(c->yfov * 0.5) * aspect) * 180.0 / 3.14159265358979323846);
    Camera cam;
    if (camera_look_at(&cam, eye, v3_add(eye, fwd), R(0), c->ortho ? R(1) : camera_zoom_for_fov(real_min(fov, R(179)))))
        return -1;
    vec3 r, u, f;
    camera_basis(&cam, &r, &u, &f);
    cam.roll = atan2(-v3_dot(up, r), v3_dot(up, u)) * R(180) / REAL_PI; /* up' = u cos - r sin */
    if (c->ortho) {
        cam.kind = CAMERA_ORTHO;
        cam.size = (real)(2.0 * c->xmag);
    }
    s->camera = cam;
    if (c->aspect > 0.0) { /* the file's frame: 1024 wide */
        s->settings.width = 1024;
        s->settings.height = (int)real_clamp((real)floor(1024.0 / c->aspect + 0.5), R(1), R(SCENE_MAX_SIDE));
    }
    return 0;
}

/* The lights a glTF gives (those a float holds), in lanray's units: a point or spot light of
 * I candela lights a diffuse surface as lanray's light of intensity
 * I / (683 pi) attenuated (683 lumens a watt; Blender's importer and
 * Cycles agree: scene2cycles), a directional one of E lux as E / (683 pi). */
static int gltf_lights(Scene *s, const GltfScene *g, Err *err)
{
    const real unit = R(1) / (R(683) * REAL_PI), deg = R(180) / REAL_PI;
    for (size_t i = 0; i < g->light_count; i++) {
        const GltfLight *l = &g->lights[i];
        const vec3 pos = v3((real)l->pos[0], (real)l->pos[1], (real)l->pos[2]);
        const vec3 dir = v3((real)l->dir[0], (real)l->dir[1], (real)l->dir[2]);
        const vec3 col = v3((real)l->color[0], (real)l->color[1], (real)l->color[2]);
        const real power = (real)(l->intensity * (double)unit);
        if (!v3_is_finite(pos) || !v3_is_finite(col) || !isfinite(power)) /* past a float's range */
            continue;
        const real angle = real_min((real)l->outer * 2 * deg, R(179));
        Light lt = l->kind == GLTF_POINT ? light_point(pos, col, power, 1)
                   : l->kind == GLTF_SPOT
                       ? light_spot(pos, dir, angle, real_min((real)(l->outer - l->inner) * deg, angle / 2), col, power, 1)
                       : light_directional(dir, col, power);
        if (scene_add_light(s, lt, err))
            return -1;
    }
    return 0;
}

/* A glTF's own camera and lights, where it has them, in place of the
 * preview's framing and lamps: 1 where it had lights, 0 where none, -1. */
static int gltf_view(Scene *s, const char *path, Err *err)
{
    int glb;
    if (!is_gltf(path, &glb))
        return 0;
    size_t len;
    uint8_t *json = gltf_file_json(path, glb, &len); /* (the importer has read it: NULL reads as none) */
    GltfScene g;
    const int rc = gltf_scene_read(json, json ? len : 0, glb, &g);
    free(json);
    if (rc)
        return err_set(err, "%s: out of memory reading its lights", path);
    if (g.has_camera && gltf_camera(s, &g.camera))
        g.has_camera = 0; /* the framing stays */
    const int lit = g.light_count > 0;
    const int bad = lit && gltf_lights(s, &g, err);
    gltf_scene_free(&g);
    return bad ? -1 : lit;
}

int scene_preview(const char *model_path, const BvhOptions *bvh, int rebuild, Scene **out, Err *err)
{
    *out = NULL;
    Model *m;
    if (model_load(model_path, bvh, rebuild, 0, &m, err))
        return -1;
    Scene *s = scene_create();
    uint32_t id = 0;
    if (!s) {
        model_destroy(m);
        return err_set(err, "out of memory");
    }
    int rc = scene_add_material(s, material_default(), NULL, err);
    rc = rc ? rc : scene_add_model(s, m, &id, err);
    rc = rc ? rc : scene_add_instance(s, instance_make(id, v3_splat(0), v3_splat(0), R(1)), err);
    if (rc == 0 && m->tri_count == 0)
        rc = err_set(err, "%s: the model has no triangles", model_path);
    if (rc == 0) {
        Aabb b = m->bounds;
        vec3 c = v3_scale(v3_add(b.min, b.max), R(0.5));
        real r = R(0.5) * v3_len(v3_sub(b.max, b.min));
        if (!(r > R(0)))
            r = R(1);
        /* a 40 degree lens: the bounding sphere fits the shorter (vertical,
         * at 4:3) side with a margin */
        real fov = R(40), half_v = atan(tan(fov * R(0.5) * REAL_PI / R(180)) * R(0.75));
        /* three quarters from the front of +z, or, for a model longer
         * along z than along x (a cow or a car walking along z), from the
         * side: seen along its length it was a narrow view of its back */
        vec3 ext = v3_sub(b.max, b.min);
        vec3 dir = v3_norm(ext.z > ext.x ? v3(R(1), R(0.4), R(0.55)) : v3(R(0.55), R(0.4), R(1)));
        vec3 eye = v3_madd(c, dir, r * R(1.1) / sin(half_v));
        if (camera_look_at(&s->camera, eye, c, 0, camera_zoom_for_fov(fov)))
            rc = err_set(err, "%s: cannot frame the model", model_path);
        s->background = v3(R(0.16), R(0.17), R(0.2));
        /* a glTF's own camera and lights (Blender's exporter writes them) */
        const int lit = rc ? 0 : gltf_view(s, model_path, err);
        rc = lit < 0 ? -1 : rc;
        vec3 key = v3_madd(c, v3_norm(v3(R(-0.6), R(1), R(0.8))), R(4) * r);
        if (!lit) {
            rc = rc ? rc : scene_add_light(s, light_point(key, v3_splat(1), R(0.85), 0), err);
            rc = rc ? rc : scene_add_light(s, light_directional(v3(R(-0.7), R(-0.2), R(-0.4)), v3(R(0.8), R(0.85), R(1)), R(0.25)), err);
            s->ambient = v3_splat(R(0.12));
            s->preview_lamps = 1;
        } else { /* the background's light, unshadowed, as the Whitted integrator's ambient (the
                  * path integrator's background lights the scene itself) */
            s->ambient = s->background;
        }
    }
    rc = rc ? rc : scene_add_source(s, model_path, err);
    rc = rc ? rc : scene_check(s, err);
    if (rc) {
        scene_destroy(s);
        return -1;
    }
    *out = s;
    return 0;
}
