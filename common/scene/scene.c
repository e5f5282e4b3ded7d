/* scene.c - a scene description: its construction and its one check. */
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "geom/aabb.h"
#include "geom/intersect.h"
#include "scene/scene_fields.h"

Scene *scene_create(void)
{
    Scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    camera_look_at(&s->camera, v3(0, 1, 5), v3(0, 0, 0), 0, camera_zoom_for_fov(60));
    /* linear light: what shows as 0.1 and 0.25-0.3 on screen */
    s->ambient = v3_splat(R(0.01));
    s->background = v3(R(0.004), R(0.004), R(0.007));
    s->environment = (SceneEnvironment){.texture = -1, .strength = R(1), .rotate = R(0)};
    s->settings = render_settings_default();
    return s;
}

void scene_destroy(Scene *s)
{
    if (!s)
        return;
    for (uint32_t i = 0; i < s->texture_count && !s->borrowed_assets; i++)
        texture_destroy(s->textures[i]);
    for (uint32_t i = 0; i < s->model_count && !s->borrowed_assets; i++)
        model_destroy(s->models[i]);
    free(s->materials);
    free(s->textures);
    free(s->spheres);
    free(s->planes);
    free(s->tris);
    free(s->tri_attrs);
    free(s->models);
    free(s->instances);
    free(s->lights);
    for (uint32_t i = 0; i < s->source_count; i++)
        free(s->sources[i]);
    free(s->sources);
    free(s);
}

RenderSettings render_settings_default(void)
{
    SettingsSpec sp;
    memset(&sp, 0, sizeof sp);
    field_defaults(&settings_kind, &sp, sizeof sp, 0);
    return sp.rs;
}


#define PUSH(s, arr, count, cap, limit, value, what)                                                   \
    do {                                                                                               \
        if (array_reserve((void **)&(s)->arr, &(s)->cap, (s)->count + 1, sizeof *(s)->arr, (limit)))  \
            return err_set(err, "scene: too many %s (limit %u) or out of memory", what, (limit));      \
        (s)->arr[(s)->count++] = (value);                                                              \
        (s)->checked = 0;                                                                              \
    } while (0)

int scene_add_material(Scene *s, Material m, uint32_t *id, Err *err)
{
    PUSH(s, materials, material_count, material_cap, SCENE_MAX_ITEMS, m, "materials");
    if (id)
        *id = s->material_count - 1;
    return 0;
}

int scene_add_texture(Scene *s, Texture *t, uint32_t *id, Err *err)
{
    if (array_reserve((void **)&s->textures, &s->texture_cap, s->texture_count + 1, sizeof *s->textures, 65536)) {
        if (!s->borrowed_assets)
            texture_destroy(t);
        return err_set(err, "scene: too many textures or out of memory");
    }
    s->textures[s->texture_count++] = t;
    if (id)
        *id = s->texture_count - 1;
    return 0;
}

int scene_add_sphere(Scene *s, Sphere sp, Err *err)
{
    PUSH(s, spheres, sphere_count, sphere_cap, SCENE_MAX_ITEMS, sp, "spheres");
    return 0;
}

int scene_add_plane(Scene *s, Plane p, Err *err)
{
    PUSH(s, planes, plane_count, plane_cap, 4096, p, "planes");
    return 0;
}

int scene_add_triangle(Scene *s, const vec3 p[3], const vec3 *n, const real *uv, uint32_t material, Err *err)
{
    if (array_reserve((void **)&s->tri_attrs, &s->tri_attr_cap, s->tri_count + 1, sizeof *s->tri_attrs, SCENE_MAX_ITEMS))
        return err_set(err, "scene: too many triangles or out of memory");
    TriAttr a;
    memset(&a, 0, sizeof a);
    a.material = material;
    if (n) {
        memcpy(a.n, n, sizeof a.n);
        a.smooth = 1;
    }
    if (uv) {
        memcpy(a.uv, uv, sizeof a.uv);
        a.textured = 1;
    }
    Tri t;
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++)
            t.v[k][c] = p[k].e[c];
    s->tri_attrs[s->tri_count] = a;
    PUSH(s, tris, tri_count, tri_cap, SCENE_MAX_ITEMS, t, "triangles");
    return 0;
}

int scene_add_model(Scene *s, Model *m, uint32_t *id, Err *err)
{
    if (array_reserve((void **)&s->models, &s->model_cap, s->model_count + 1, sizeof *s->models, 65536)) {
        if (!s->borrowed_assets)
            model_destroy(m);
        return err_set(err, "scene: too many models or out of memory");
    }
    s->models[s->model_count++] = m;
    if (id)
        *id = s->model_count - 1;
    return 0;
}

int scene_add_instance(Scene *s, Instance in, Err *err)
{
    PUSH(s, instances, instance_count, instance_cap, SCENE_MAX_ITEMS, in, "instances");
    return 0;
}

int scene_add_light(Scene *s, Light l, Err *err)
{
    PUSH(s, lights, light_count, light_cap, SCENE_MAX_LIGHTS, l, "lights");
    return 0;
}

int scene_add_source(Scene *s, const char *path, Err *err)
{
    char *copy = strdup(path);
    if (!copy || array_reserve((void **)&s->sources, &s->source_cap, s->source_count + 1, sizeof *s->sources, 65536)) {
        free(copy);
        return err_set(err, "scene: too many files or out of memory");
    }
    s->sources[s->source_count++] = copy;
    return 0;
}

Plane plane_make(vec3 point, vec3 normal, uint32_t material)
{
    Plane p;
    memset(&p, 0, sizeof p);
    p.point = point;
    p.normal = normal;
    p.material = material;
    p.uv_scale = R(1);
    return p;
}

Light light_point(vec3 pos, vec3 color, real intensity, int attenuate)
{
    Light l;
    memset(&l, 0, sizeof l);
    l.kind = LIGHT_POINT;
    l.pos = pos;
    l.color = color;
    l.intensity = intensity;
    l.attenuate = attenuate;
    return l;
}

Light light_spot(vec3 pos, vec3 dir, real angle, real soft, vec3 color, real intensity, int attenuate)
{
    Light l = light_point(pos, color, intensity, attenuate);
    l.kind = LIGHT_SPOT;
    l.dir = dir;
    l.angle = angle;
    l.soft = soft;
    return l;
}

Light light_directional(vec3 dir, vec3 color, real intensity)
{
    Light l = light_point(v3_splat(0), color, intensity, 0);
    l.kind = LIGHT_DIRECTIONAL;
    l.dir = dir;
    return l;
}

Light light_sphere(vec3 centre, real radius, int samples, vec3 color, real intensity, int attenuate)
{
    Light l = light_point(centre, color, intensity, attenuate);
    l.kind = LIGHT_SPHERE;
    l.radius = radius;
    l.samples = samples;
    return l;
}

Light light_rect(vec3 corner, vec3 edge1, vec3 edge2, int samples, vec3 color, real intensity, int attenuate)
{
    Light l = light_point(corner, color, intensity, attenuate);
    l.kind = LIGHT_RECT;
    l.edge1 = edge1;
    l.edge2 = edge2;
    l.samples = samples;
    return l;
}

Instance instance_make(uint32_t model, vec3 translate, vec3 rotate, real scale)
{
    Instance in;
    memset(&in, 0, sizeof in);
    in.model = model;
    in.translate = translate;
    in.rotate = rotate;
    in.scale = scale;
    in.material = -1;
    return in;
}

uint32_t instances_copy(Instance **buf, uint32_t *cap, const Instance *src, uint32_t n)
{
    if (n > *cap) {
        Instance *grown = realloc(*buf, (size_t)n * sizeof *grown);
        if (!grown)
            return 0;
        *buf = grown, *cap = n;
    }
    if (n)
        memcpy(*buf, src, (size_t)n * sizeof *src);
    return n;
}

static int check_material(const Scene *s, uint32_t m, const char *what, uint32_t i, Err *err)
{
    if (m >= s->material_count)
        return err_set(err, "scene: %s %u uses material %u but the scene has %u", what, i, m, s->material_count);
    return 0;
}

int scene_check_view(const Camera *c, const RenderSettings *rs, Err *err)
{
    char why[160];
    if (settings_problem(rs, why, sizeof why))
        return err_set(err, "scene: settings: %s", why);
    if (camera_problem(c, why, sizeof why))
        return err_set(err, "scene: camera: %s", why);
    return 0;
}

static int check_materials(const Scene *s, Err *err)
{
    for (uint32_t i = 0; i < s->material_count; i++) {
        const Material *m = &s->materials[i];
        char why[160];
        if (material_problem(m, why, sizeof why))
            return err_set(err, "scene: material %u: %s", i, why);
        if (m->texture < -1 || m->texture >= (int32_t)s->texture_count)
            return err_set(err, "scene: material %u uses texture %d but the scene has %u", i, m->texture, s->texture_count);
        if (material_cuts(m))
            return err_set(err, "scene: material %u is a cutout: only a model's own materials cut holes", i);
        const struct {
            int has;
            const char *what;
        } own[] = {{material_bumps(m), "a normal map"},
                   {material_emit_mapped(m), "an emission texture"},
                   {material_occludes(m), "an occlusion texture"},
                   {material_metal_mapped(m), "a metal-roughness texture"}};
        for (size_t k = 0; k < sizeof own / sizeof *own; k++)
            if (own[k].has)
                return err_set(err, "scene: material %u has %s: only a model's own materials have one", i, own[k].what);
    }
    return 0;
}

static int check_primitives(const Scene *s, Err *err)
{
    char why[160];
    for (uint32_t i = 0; i < s->sphere_count; i++) {
        if (field_problem(&sphere_kind, &s->spheres[i], 0, why, sizeof why))
            return err_set(err, "scene: sphere %u: %s", i, why);
        if (check_material(s, s->spheres[i].material, "sphere", i, err))
            return -1;
    }
    for (uint32_t i = 0; i < s->plane_count; i++) {
        if (field_problem(&plane_kind, &s->planes[i], 0, why, sizeof why))
            return err_set(err, "scene: plane %u: %s", i, why);
        if (check_material(s, s->planes[i].material, "plane", i, err))
            return -1;
    }
    for (uint32_t i = 0; i < s->tri_count; i++) {
        TriSpec t = tri_spec(s, i);
        if (field_problem(&triangle_kind, &t, 0, why, sizeof why))
            return err_set(err, "scene: triangle %u: %s", i, why);
        if (check_material(s, s->tri_attrs[i].material, "triangle", i, err))
            return -1;
        /* the table skips a group at its defaults; a smooth triangle's
         * normals are there whatever their values (from the wire, from code) */
        for (int k = 0; t.smooth && k < 3; k++)
            if (!(v3_dot(s->tri_attrs[i].n[k], s->tri_attrs[i].n[k]) > R(0)))
                return err_set(err, "scene: triangle %u: 'normals' has a zero vector", i);
    }
    return 0;
}

/* Instances, and the materials of the models they show. */
static int check_instances(const Scene *s, Err *err)
{
    char why[160];
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const Instance *in = &s->instances[i];
        if (in->model >= s->model_count)
            return err_set(err, "scene: instance %u uses model %u but the scene has %u", i, in->model, s->model_count);
        if (field_problem(&instance_kind, in, 0, why, sizeof why))
            return err_set(err, "scene: instance %u: %s", i, why);
        if (in->material < -1)
            return err_set(err, "scene: instance %u: material %d", i, in->material);
        if (in->material >= 0 && check_material(s, (uint32_t)in->material, "instance", i, err))
            return -1;
        const Model *m = s->models[in->model];
        for (uint32_t k = 0; k < m->material_count; k++)
            if (material_problem(&m->materials[k], why, sizeof why))
                return err_set(err, "scene: model %u, material %u: %s", in->model, k, why);
    }
    return 0;
}

static int check_environment(const Scene *s, Err *err)
{
    const SceneEnvironment *e = &s->environment;
    char buf[160];
    const char *why = field_problem(&environment_kind, e, 0, buf, sizeof buf);
    if (why)
        return err_set(err, "scene: environment: %s", why);
    if (e->texture < -1 || e->texture >= (int32_t)s->texture_count)
        return err_set(err, "scene: the environment uses texture %d but the scene has %u", e->texture,
                       s->texture_count);
    return 0;
}

static int check_lights(const Scene *s, Err *err)
{
    for (uint32_t i = 0; i < s->light_count; i++) {
        char why[160];
        if (light_problem(&s->lights[i], why, sizeof why))
            return err_set(err, "scene: light %u: %s", i, why);
    }
    return 0;
}

int scene_check(Scene *s, Err *err)
{
    s->checked = 0;
    if (scene_check_view(&s->camera, &s->settings, err))
        return -1;
    if (!v3_is_finite(s->ambient) || !v3_is_finite(s->background))
        return err_set(err, "scene: ambient and background colours must be finite");
    if (check_materials(s, err) || check_primitives(s, err) || check_instances(s, err) || check_lights(s, err) ||
        check_environment(s, err))
        return -1;
    s->checked = 1;
    return 0;
}

int scene_rebuild_models(Scene *s, const BvhOptions *opt, Err *err)
{
    for (uint32_t i = 0; i < s->model_count; i++)
        if (model_rebuild(s->models[i], opt, err))
            return -1;
    s->checked = 0;
    return 0;
}

uint64_t scene_triangle_count(const Scene *s)
{
    uint64_t n = s->tri_count;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += s->models[s->instances[i].model]->tri_count;
    return n;
}

int scene_bounds(const Scene *s, vec3 *centre, real *radius)
{
    Aabb b = aabb_empty();
    for (uint32_t i = 0; i < s->sphere_count; i++) {
        aabb_grow(&b, v3_sub(s->spheres[i].centre, v3_splat(s->spheres[i].radius)));
        aabb_grow(&b, v3_add(s->spheres[i].centre, v3_splat(s->spheres[i].radius)));
    }
    for (uint32_t i = 0; i < s->tri_count; i++)
        for (int k = 0; k < 3; k++)
            aabb_grow(&b, tri_vertex(&s->tris[i], k));
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const Instance *in = &s->instances[i];
        if (in->model >= s->model_count || aabb_is_empty(s->models[in->model]->bounds))
            continue;
        /* the model's bounding sphere about its origin, scaled and moved:
         * whatever its turn, the instance lies inside */
        const Aabb mb = s->models[in->model]->bounds;
        const real r = (v3_len(aabb_centre(mb)) + R(0.5) * v3_len(aabb_extent(mb))) * in->scale;
        aabb_grow(&b, v3_sub(in->translate, v3_splat(r)));
        aabb_grow(&b, v3_add(in->translate, v3_splat(r)));
    }
    if (aabb_is_empty(b) || !isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z))
        return -1;
    *centre = aabb_centre(b);
    *radius = R(0.5) * v3_len(aabb_extent(b));
    return 0;
}
