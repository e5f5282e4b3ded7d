/* scene_preview.c - see scene_preview.h. */
#include "scene/scene_preview.h"

#include "base/dmath.h"
#include "model/model_load.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_gltf.h"

int scene_preview(const char *model_path, const BvhOptions *bvh, int rebuild, int smooth, Scene **out, Err *err)
{
    *out = NULL;
    Model *m;
    if (model_load(model_path, bvh, rebuild, smooth, &m, err))
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
        /* (atan as atan2(x, 1): the double build's atan varies by the CPU, scene_gltf.c) */
        real fov = R(40), half_v = atan2(dmath_tanr(fov * R(0.5) * REAL_PI / R(180)) * R(0.75), R(1));
        /* three quarters from the front of +z, or, for a model longer
         * along z than along x (a cow or a car walking along z), from the
         * side: seen along its length it was a narrow view of its back */
        vec3 ext = v3_sub(b.max, b.min);
        vec3 dir = v3_norm(ext.z > ext.x ? v3(R(1), R(0.4), R(0.55)) : v3(R(0.55), R(0.4), R(1)));
        vec3 eye = v3_madd(c, dir, r * R(1.1) / dmath_sinr(half_v));
        if (camera_look_at(&s->camera, eye, c, 0, camera_zoom_for_fov(fov)))
            rc = err_set(err, "%s: cannot frame the model", model_path);
        s->background = v3(R(0.16), R(0.17), R(0.2));
        /* a glTF's own camera and lights (Blender's exporter writes them) */
        int got = 0;
        rc = rc ? rc : scene_gltf_take(s, model_path, NULL, SCENE_GLTF_LIGHTS | SCENE_GLTF_CAMERA, &got, err);
        const int lit = got & SCENE_GLTF_LIGHTS;
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
