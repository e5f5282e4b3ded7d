/* scene_gltf.c - see scene_gltf.h. */
#include "scene/scene_gltf.h"

#include "base/dmath.h"

#include <math.h>
#include <stdlib.h>

#include "base/fileio.h"
#include "model/gltf_json.h"
#include "model/gltf_scene.h"
#include "scene/world.h"

int scene_gltf_is(const char *path) { return file_has_suffix(path, ".glb") || file_has_suffix(path, ".gltf"); }

/* Where the instance puts a point and a direction (world_instance_point),
 * or (placed 0) the file's own numbers, untouched. */
typedef struct {
    int placed;
    WorldInstance in;
} Place;

static vec3 place_point(const Place *p, const double v[3])
{
    const vec3 a = v3((real)v[0], (real)v[1], (real)v[2]);
    return p->placed ? world_instance_point(&p->in, a) : a;
}

static vec3 place_dir(const Place *p, const double v[3])
{
    const vec3 a = v3((real)v[0], (real)v[1], (real)v[2]);
    return p->placed ? m3_apply(&p->in.rot, a) : a;
}

/* The camera a glTF gives, placed (its up by the roll); -1 where it
 * cannot be made. */
static int take_camera(Camera *out, const GltfCamera *c, const Place *p)
{
    const vec3 eye = place_point(p, c->pos), fwd = place_dir(p, c->fwd), up = place_dir(p, c->up);
    const double aspect = c->aspect > 0.0 ? c->aspect : 4.0 / 3.0;
    /* atan(x) as atan2(x, 1): glibc's atan is one of two variants by the CPU, its atan2 one (dmath.h) */
    const real fov = (real)(2.0 * atan2(dmath_tan(c->yfov * 0.5) * aspect, 1.0) * 180.0 / 3.14159265358979323846);
    Camera cam;
    if (!v3_is_finite(eye) ||
        camera_look_at(&cam, eye, v3_add(eye, fwd), R(0), c->ortho ? R(1) : camera_zoom_for_fov(real_min(fov, R(179)))))
        return -1;
    vec3 r, u, f;
    camera_basis(&cam, &r, &u, &f);
    cam.roll = atan2(-v3_dot(up, r), v3_dot(up, u)) * R(180) / REAL_PI; /* up' = u cos - r sin */
    if (c->ortho) {
        cam.kind = CAMERA_ORTHO;
        cam.size = (real)(2.0 * c->xmag) * p->in.scale;
    }
    *out = cam;
    return 0;
}

/* The lights a glTF gives (those a float holds), placed, in lanray's
 * units, counted into *added: a point or spot light of I candela lights a diffuse surface as
 * lanray's light of intensity I / (683 pi) attenuated (683 lumens a watt;
 * Blender's importer and Cycles agree: scene2cycles), a directional one of
 * E lux as E / (683 pi). */
static int take_lights(Scene *s, const GltfScene *g, const Place *p, int *added, Err *err)
{
    const real unit = R(1) / (R(683) * REAL_PI), deg = R(180) / REAL_PI;
    for (size_t i = 0; i < g->light_count; i++) {
        const GltfLight *l = &g->lights[i];
        const vec3 pos = place_point(p, l->pos), dir = place_dir(p, l->dir);
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
        ++*added;
    }
    return 0;
}

int scene_gltf_take(Scene *s, const char *path, const Instance *place, int want, int *got, Err *err)
{
    *got = 0;
    if (!scene_gltf_is(path))
        return 0;
    const int glb = file_has_suffix(path, ".glb");
    size_t len;
    uint8_t *json = gltf_file_json(path, glb, &len); /* (the importer has read it: NULL reads as none) */
    GltfScene g;
    const int rc = gltf_scene_read(json, json ? len : 0, glb, &g);
    free(json);
    if (rc)
        return err_set(err, "%s: out of memory reading its lights", path);
    Place p = {.in.scale = R(1)};
    if (place)
        p = (Place){1, world_instance_derive(place)};
    int bad = 0;
    if ((want & SCENE_GLTF_CAMERA) && g.has_camera && take_camera(&s->camera, &g.camera, &p) == 0) {
        *got |= SCENE_GLTF_CAMERA;
        if (!place && g.camera.aspect > 0.0) { /* a glTF opened alone: the file's frame, 1024 wide */
            s->settings.width = 1024;
            s->settings.height = (int)real_clamp((real)floor(1024.0 / g.camera.aspect + 0.5), R(1), R(SCENE_MAX_SIDE));
        }
    }
    int added = 0;
    if ((want & SCENE_GLTF_LIGHTS) && g.light_count > 0) {
        bad = take_lights(s, &g, &p, &added, err);
        *got |= added > 0 ? SCENE_GLTF_LIGHTS : 0;
    }
    gltf_scene_free(&g);
    return bad ? -1 : 0;
}
