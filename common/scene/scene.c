/* scene.c - scene construction, validation and the top-level BVH. */
#include "scene/scene.h"

#include <stdlib.h>
#include <string.h>

#include "base/array.h"
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
    free(s->lamps);
    bvh_destroy(&s->top);
    free(s);
}

RenderSettings render_settings_default(void)
{
    SettingsSpec sp;
    memset(&sp, 0, sizeof sp);
    field_defaults(&settings_kind, &sp, 0);
    return sp.rs;
}


#define PUSH(s, arr, count, cap, limit, value, what)                                                   \
    do {                                                                                               \
        if (array_reserve((void **)&(s)->arr, &(s)->cap, (s)->count + 1, sizeof *(s)->arr, (limit)))  \
            return err_set(err, "scene: too many %s (limit %u) or out of memory", what, (limit));      \
        (s)->arr[(s)->count++] = (value);                                                              \
        (s)->prepared = 0;                                                                             \
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

static Aabb instance_world_box(const Instance *in, Aabb b)
{
    Aabb w = aabb_empty();
    for (int c = 0; c < 8; c++) {
        vec3 p = v3(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z);
        aabb_grow(&w, v3_add(v3_scale(m3_apply(&in->rot, p), in->scale), in->translate));
    }
    /* pad by the rounding of the transform so that the box stays conservative */
    vec3 pad = v3_scale(v3_max(v3_abs(w.min), v3_abs(w.max)), real_gamma(8));
    w.min = v3_sub(w.min, pad);
    w.max = v3_add(w.max, pad);
    return w;
}

/* Planar mapping: u along the world x axis laid onto the plane (z for a
 * plane facing x), v = n x u, both turned by uv_rotate about the normal and
 * divided by uv_scale.  A floor (normal +y) has u along +x and v along -z. */
static void plane_axes(Plane *p)
{
    vec3 n = p->unit, a = fabs(n.x) < R(0.9) ? v3(1, 0, 0) : v3(0, 0, 1);
    vec3 u = v3_norm(v3_sub(a, v3_scale(n, v3_dot(a, n))));
    vec3 v = v3_cross(n, u);
    real r = p->uv_rotate * REAL_PI / R(180), c = cos(r), s = sin(r), k = R(1) / p->uv_scale;
    p->tu = v3_scale(v3_add(v3_scale(u, c), v3_scale(v, s)), k);
    p->tv = v3_scale(v3_sub(v3_scale(v, c), v3_scale(u, s)), k);
}

static int check_material(const Scene *s, uint32_t m, const char *what, uint32_t i, Err *err)
{
    if (m >= s->material_count)
        return err_set(err, "scene: %s %u uses material %u but the scene has %u", what, i, m, s->material_count);
    return 0;
}

static uint32_t material_features(const Material *m)
{
    return (material_reflects(m) ? FEAT_REFLECT : 0u) | (material_dielectric(m) ? FEAT_REFRACT : 0u) |
           (material_emits(m) ? FEAT_EMIT : 0u) | (material_rough(m) ? FEAT_ROUGH : 0u);
}

/* Whether emissive sphere sp shows light l: the light's centre is inside
 * it, or it is inside the light's sphere (a point light has radius 0). */
static int sphere_shows(const Sphere *sp, const Light *l)
{
    real d = v3_len(v3_sub(sp->centre, l->kind == LIGHT_RECT ? v3_add(l->pos, v3_scale(v3_add(l->edge1, l->edge2), R(0.5)))
                                                             : l->pos));
    return d <= real_max(sp->radius, l->kind == LIGHT_SPHERE ? l->radius : R(0));
}

/* Whether triangle t shows rectangle light l: its corners lie in the
 * light's plane (to a thousandth of the light's size) and its box meets
 * the light's. */
static int tri_shows(const Tri *t, const Light *l)
{
    real size = real_max(v3_len(l->edge1), v3_len(l->edge2)), tol = size * R(1e-3);
    Aabb lb = aabb_point(l->pos), tb = aabb_empty();
    aabb_grow(&lb, v3_add(l->pos, l->edge1));
    aabb_grow(&lb, v3_add(l->pos, l->edge2));
    aabb_grow(&lb, v3_add(l->pos, v3_add(l->edge1, l->edge2)));
    for (int k = 0; k < 3; k++) {
        vec3 v = tri_vertex(t, k);
        if (!(fabs(v3_dot(v3_sub(v, l->pos), l->axis)) <= tol))
            return 0;
        aabb_grow(&tb, v);
    }
    for (int a = 0; a < 3; a++)
        if (tb.min.e[a] > lb.max.e[a] + tol || tb.max.e[a] < lb.min.e[a] - tol)
            return 0;
    return 1;
}

/* Every light's lamp (scene.h): its emissive spheres and, for a
 * rectangle, its emissive scene triangles, as top-level primitive numbers
 * in increasing order.  Only emissive primitives are looked at: a scene
 * without emission pays one pass over its materials. */
static int pair_lamps(Scene *s, Err *err)
{
    s->lamp_total = 0;
    for (uint32_t i = 0; i < s->light_count; i++)
        s->lights[i].lamp_first = s->lights[i].lamp_count = 0;
    int emits = 0;
    for (uint32_t m = 0; m < s->material_count && !emits; m++)
        emits = material_emits(&s->materials[m]);
    if (!emits || s->light_count == 0)
        return 0;
    uint32_t *cand = NULL, nc = 0, cap = 0;
    for (uint32_t p = 0; p < s->sphere_count + s->tri_count; p++) {
        uint32_t m = p < s->sphere_count ? s->spheres[p].material : s->tri_attrs[p - s->sphere_count].material;
        if (!material_emits(&s->materials[m]))
            continue;
        if (array_reserve((void **)&cand, &cap, nc + 1, sizeof *cand, SCENE_MAX_ITEMS * 2)) {
            free(cand);
            return err_set(err, "scene: out of memory for the lights' lamps");
        }
        cand[nc++] = p;
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        Light *l = &s->lights[i];
        l->lamp_first = s->lamp_total;
        for (uint32_t k = 0; k < nc && l->kind != LIGHT_DIRECTIONAL; k++) {
            uint32_t p = cand[k];
            if (p < s->sphere_count ? !sphere_shows(&s->spheres[p], l)
                                    : l->kind != LIGHT_RECT || !tri_shows(&s->tris[p - s->sphere_count], l))
                continue;
            if (array_reserve((void **)&s->lamps, &s->lamp_cap, s->lamp_total + 1, sizeof *s->lamps, UINT32_MAX / 8)) {
                free(cand);
                return err_set(err, "scene: out of memory for the lights' lamps");
            }
            s->lamps[s->lamp_total++] = p;
            l->lamp_count++;
        }
    }
    free(cand);
    return 0;
}

/* The settings, the camera and the colours, by their tables. */
static int prepare_view(const Scene *s, uint32_t *f, Err *err)
{
    char why[160];
    if (settings_problem(&s->settings, why, sizeof why))
        return err_set(err, "scene: settings: %s", why);
    if (camera_problem(&s->camera, why, sizeof why))
        return err_set(err, "scene: camera: %s", why);
    if (s->camera.aperture > R(0))
        *f |= FEAT_LENS;
    if (!v3_is_finite(s->ambient) || !v3_is_finite(s->background))
        return err_set(err, "scene: ambient and background colours must be finite");
    return 0;
}

static int prepare_materials(const Scene *s, uint32_t *f, Err *err)
{
    for (uint32_t i = 0; i < s->material_count; i++) {
        const Material *m = &s->materials[i];
        char why[160];
        if (material_problem(m, why, sizeof why))
            return err_set(err, "scene: material %u: %s", i, why);
        if (m->texture < -1 || m->texture >= (int32_t)s->texture_count)
            return err_set(err, "scene: material %u uses texture %d but the scene has %u", i, m->texture, s->texture_count);
        if (m->texture >= 0)
            *f |= FEAT_TEXTURES;
        if (v3_max_comp(m->ks) > R(0))
            *f |= FEAT_SPECULAR;
        *f |= material_features(m);
    }
    return 0;
}

/* Spheres, planes (their unit normals and texture axes) and triangles. */
static int prepare_primitives(Scene *s, uint32_t *f, Err *err)
{
    char why[160];
    for (uint32_t i = 0; i < s->sphere_count; i++) {
        if (field_problem(&sphere_kind, &s->spheres[i], 0, why, sizeof why))
            return err_set(err, "scene: sphere %u: %s", i, why);
        if (check_material(s, s->spheres[i].material, "sphere", i, err))
            return -1;
    }
    for (uint32_t i = 0; i < s->plane_count; i++) {
        Plane *p = &s->planes[i];
        if (field_problem(&plane_kind, p, 0, why, sizeof why))
            return err_set(err, "scene: plane %u: %s", i, why);
        p->unit = v3_norm(p->normal);
        plane_axes(p);
        if (check_material(s, p->material, "plane", i, err))
            return -1;
        *f |= FEAT_PLANES;
    }
    for (uint32_t i = 0; i < s->tri_count; i++) {
        TriSpec t = tri_spec(s, i);
        if (field_problem(&triangle_kind, &t, 0, why, sizeof why))
            return err_set(err, "scene: triangle %u: %s", i, why);
        if (check_material(s, s->tri_attrs[i].material, "triangle", i, err))
            return -1;
        if (s->tri_attrs[i].smooth)
            *f |= FEAT_SMOOTH;
    }
    return 0;
}

/* Instances: their transforms and world boxes, and what their models use. */
static int prepare_instances(Scene *s, uint32_t *f, Err *err)
{
    char why[160];
    for (uint32_t i = 0; i < s->instance_count; i++) {
        Instance *in = &s->instances[i];
        if (in->model >= s->model_count)
            return err_set(err, "scene: instance %u uses model %u but the scene has %u", i, in->model, s->model_count);
        if (field_problem(&instance_kind, in, 0, why, sizeof why))
            return err_set(err, "scene: instance %u: %s", i, why);
        if (in->material < -1)
            return err_set(err, "scene: instance %u: material %d", i, in->material);
        if (in->material >= 0 && check_material(s, (uint32_t)in->material, "instance", i, err))
            return -1;
        in->rot = m3_rotation_xyz(in->rotate);
        in->identity = in->scale == R(1) && in->rotate.x == R(0) && in->rotate.y == R(0) && in->rotate.z == R(0) &&
                       in->translate.x == R(0) && in->translate.y == R(0) && in->translate.z == R(0);
        const Model *m = s->models[in->model];
        if (m->normals)
            *f |= FEAT_SMOOTH;
        if (m->uvs)
            *f |= FEAT_TEXTURES;
        if (m->colours && in->material < 0)
            *f |= FEAT_COLOURS;
        for (uint32_t k = 0; k < m->material_count; k++) {
            if (material_problem(&m->materials[k], why, sizeof why))
                return err_set(err, "scene: model %u, material %u: %s", in->model, k, why);
            if (v3_max_comp(m->materials[k].ks) > R(0))
                *f |= FEAT_SPECULAR;
            *f |= material_features(&m->materials[k]);
        }
        in->world_box = m->tri_count ? instance_world_box(in, m->bounds) : aabb_empty();
    }
    for (uint32_t i = 0; i < s->model_count; i++)
        if (model_prepare_simd(s->models[i], err))
            return err_prefix(err, "scene");
    return 0;
}

/* Lights: their axes and spot cones. */
static int prepare_lights(Scene *s, uint32_t *f, Err *err)
{
    for (uint32_t i = 0; i < s->light_count; i++) {
        Light *l = &s->lights[i];
        char why[160];
        if (light_problem(l, why, sizeof why))
            return err_set(err, "scene: light %u: %s", i, why);
        if (light_has_direction(l))
            l->axis = v3_norm(l->dir);
        if (l->kind == LIGHT_RECT)
            l->axis = v3_norm(v3_cross(l->edge1, l->edge2));
        if (light_is_area(l))
            *f |= FEAT_AREA;
        if (l->kind == LIGHT_SPOT) {
            real half = l->angle * R(0.5) * REAL_PI / R(180);
            real inner = real_max(R(0), l->angle * R(0.5) - l->soft) * REAL_PI / R(180);
            l->cos_outer = cos(half);
            l->cos_inner = cos(inner);
            *f |= FEAT_SPOT;
        }
        if (l->attenuate && l->kind != LIGHT_DIRECTIONAL)
            *f |= FEAT_ATTENUATION;
    }
    if (s->settings.shadows && s->light_count)
        *f |= FEAT_SHADOWS;
    return 0;
}

/* The top-level BVH: one box per sphere, scene triangle and instance. */
static int build_top(Scene *s, Err *err)
{
    bvh_destroy(&s->top);
    uint32_t nb = s->sphere_count + s->tri_count + s->instance_count;
    if (nb == 0)
        return 0;
    Aabb *boxes = malloc(nb * sizeof *boxes);
    if (!boxes)
        return err_set(err, "scene: out of memory");
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->sphere_count; i++) {
        const Sphere *sp = &s->spheres[i];
        vec3 r = v3_splat(sp->radius * (R(1) + real_gamma(4)));
        boxes[k++] = (Aabb){v3_sub(sp->centre, r), v3_add(sp->centre, r)};
    }
    for (uint32_t i = 0; i < s->tri_count; i++) {
        Aabb b = aabb_point(tri_vertex(&s->tris[i], 0));
        aabb_grow(&b, tri_vertex(&s->tris[i], 1));
        aabb_grow(&b, tri_vertex(&s->tris[i], 2));
        boxes[k++] = b;
    }
    for (uint32_t i = 0; i < s->instance_count; i++) {
        Aabb b = s->instances[i].world_box;
        /* an empty model still needs a valid box: a point at its position */
        boxes[k++] = aabb_is_empty(b) ? aabb_point(s->instances[i].translate) : b;
    }
    BvhOptions opt = bvh_options_default(BVH_SAH);
    opt.max_leaf = 2;
    int rc = bvh_build(&s->top, boxes, nb, &opt, err);
    free(boxes);
    return rc ? err_prefix(err, "scene") : 0;
}

int scene_prepare(Scene *s, Err *err)
{
    uint32_t f = 0;
    if (prepare_view(s, &f, err) || prepare_materials(s, &f, err) || prepare_primitives(s, &f, err) ||
        prepare_instances(s, &f, err) || prepare_lights(s, &f, err) || pair_lamps(s, err) || build_top(s, err))
        return -1;
    s->features = f;
    s->prepared = 1;
    return 0;
}

int scene_rebuild_models(Scene *s, const BvhOptions *opt, Err *err)
{
    for (uint32_t i = 0; i < s->model_count; i++)
        if (model_rebuild(s->models[i], opt, err))
            return -1;
    s->prepared = 0;
    return 0;
}

uint64_t scene_triangle_count(const Scene *s)
{
    uint64_t n = s->tri_count;
    for (uint32_t i = 0; i < s->instance_count; i++)
        n += s->models[s->instances[i].model]->tri_count;
    return n;
}
