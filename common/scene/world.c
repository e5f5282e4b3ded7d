/* world.c - a world from a scene description: derived items, lamps, the
 * top-level BVH (shared with the previous world where its boxes are the
 * same) and the features the inner loop asks about. */
#include "scene/world.h"

#include "base/dmath.h"

#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "scene/emitters.h"

View scene_view(const Scene *s) { return (View){.camera = s->camera, .settings = s->settings}; }

static uint32_t material_features(const Material *m)
{
    return (material_reflects(m) ? FEAT_REFLECT : 0u) | (material_dielectric(m) ? FEAT_REFRACT : 0u) |
           (material_emits(m) ? FEAT_EMIT : 0u) | (material_rough(m) || material_frosted(m) ? FEAT_ROUGH : 0u) |
           (v3_max_comp(m->ks) > R(0) ? FEAT_SPECULAR : 0u) |
           (material_checkered(m) ? FEAT_CHECKER | (m->checker_uv ? FEAT_TEXTURES : 0u) : 0u) |
           (material_bumps(m) ? FEAT_NORMAL_MAP : 0u) | (material_coats(m) ? FEAT_COAT : 0u) |
           (material_null(m) ? FEAT_NULL : 0u);
}

/* Planar mapping: u along the world x axis laid onto the plane (z for a
 * plane facing x), v = n x u, both turned by uv_rotate about the normal and
 * divided by uv_scale.  A floor (normal +y) has u along +x and v along -z. */
static WorldPlane plane_derive(const Plane *p)
{
    WorldPlane w = {.point = p->point, .unit = v3_norm(p->normal), .material = p->material};
    vec3 n = w.unit, a = fabs(n.x) < R(0.9) ? v3(1, 0, 0) : v3(0, 0, 1);
    vec3 u = v3_norm(v3_sub(a, v3_scale(n, v3_dot(a, n))));
    vec3 v = v3_cross(n, u);
    real c, s, k = R(1) / p->uv_scale;
    dmath_sincosr(p->uv_rotate * REAL_PI / R(180), &s, &c);
    w.tu = v3_scale(v3_add(v3_scale(u, c), v3_scale(v, s)), k);
    w.tv = v3_scale(v3_sub(v3_scale(v, c), v3_scale(u, s)), k);
    return w;
}

WorldInstance world_instance_derive(const Instance *in)
{
    return (WorldInstance){
        .model = in->model,
        .rot = m3_rotation_xyz(in->rotate),
        .translate = in->translate,
        .scale = in->scale,
        .material = in->material,
        .identity = in->scale == R(1) && in->rotate.x == R(0) && in->rotate.y == R(0) && in->rotate.z == R(0) &&
                    in->translate.x == R(0) && in->translate.y == R(0) && in->translate.z == R(0),
    };
}

static Aabb instance_world_box(const WorldInstance *in, Aabb b)
{
    Aabb w = aabb_empty();
    for (int c = 0; c < 8; c++) {
        vec3 p = v3(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z);
        aabb_grow(&w, world_instance_point(in, p));
    }
    /* pad by the rounding of the transform so that the box stays conservative */
    vec3 pad = v3_scale(v3_max(v3_abs(w.min), v3_abs(w.max)), real_gamma(8));
    w.min = v3_sub(w.min, pad);
    w.max = v3_add(w.max, pad);
    return w;
}

static WorldLight light_derive(const Light *l)
{
    WorldLight w = {.kind = l->kind, .pos = l->pos, .color = l->color, .intensity = l->intensity,
                    .attenuate = l->attenuate, .radius = l->radius, .edge1 = l->edge1, .edge2 = l->edge2,
                    .samples = l->samples};
    if (light_has_direction(l))
        w.axis = v3_norm(l->dir);
    if (l->kind == LIGHT_RECT)
        w.axis = v3_norm(v3_cross(l->edge1, l->edge2));
    if (l->kind == LIGHT_SPOT) {
        real half = l->angle * R(0.5) * REAL_PI / R(180);
        real inner = real_max(R(0), l->angle * R(0.5) - l->soft) * REAL_PI / R(180);
        w.cos_outer = dmath_cosr(half);
        w.cos_inner = dmath_cosr(inner);
    }
    return w;
}

static uint32_t light_features(const WorldLight *l)
{
    return (world_light_is_area(l) ? FEAT_AREA : 0u) | (l->kind == LIGHT_SPOT ? FEAT_SPOT : 0u) |
           (l->attenuate && l->kind != LIGHT_DIRECTIONAL ? FEAT_ATTENUATION : 0u);
}

/* Whether emissive sphere sp shows light l: the light's centre is inside
 * it, or it is inside the light's sphere (a point light has radius 0). */
static int sphere_shows(const Sphere *sp, const WorldLight *l)
{
    real d = v3_len(v3_sub(sp->centre, l->kind == LIGHT_RECT ? v3_add(l->pos, v3_scale(v3_add(l->edge1, l->edge2), R(0.5)))
                                                             : l->pos));
    return d <= real_max(sp->radius, l->kind == LIGHT_SPHERE ? l->radius : R(0));
}

/* Whether triangle t shows rectangle light l: its corners lie in the
 * light's plane (to a thousandth of the light's size) and its box meets
 * the light's. */
static int tri_shows(const Tri *t, const WorldLight *l)
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

static int lamp_push(World *w, uint32_t *cap, uint32_t p)
{
    if (array_reserve((void **)&w->parts->lamps, cap, w->lamp_total + 1, sizeof *w->lamps, UINT32_MAX / 8))
        return -1;
    w->lamps = w->parts->lamps;
    w->lamps[w->lamp_total++] = p;
    return 0;
}

/* Every light's lamp (scene.h): its emissive spheres and, for a
 * rectangle, its emissive scene triangles, as top-level primitive numbers
 * in increasing order.  Only emissive primitives are looked at: a scene
 * without emission pays one pass over its materials. */
static int pair_lamps(World *w, Err *err)
{
    if (!(w->item_features & FEAT_EMIT) || w->light_count == 0)
        return 0;
    uint32_t *cand = NULL, nc = 0, cap = 0, lamp_cap = 0;
    for (uint32_t p = 0; p < w->sphere_count + w->tri_count; p++) {
        uint32_t m = p < w->sphere_count ? w->spheres[p].material : w->tri_attrs[p - w->sphere_count].material;
        if (!material_emits(&w->materials[m]))
            continue;
        if (array_reserve((void **)&cand, &cap, nc + 1, sizeof *cand, SCENE_MAX_ITEMS * 2)) {
            free(cand);
            return err_set(err, "scene: out of memory for the lights' lamps");
        }
        cand[nc++] = p;
    }
    for (uint32_t i = 0; i < w->light_count; i++) {
        WorldLight *l = &w->lights[i];
        l->lamp_first = w->lamp_total;
        for (uint32_t k = 0; k < nc && l->kind != LIGHT_DIRECTIONAL; k++) {
            uint32_t p = cand[k];
            if (p < w->sphere_count ? !sphere_shows(&w->spheres[p], l)
                                    : l->kind != LIGHT_RECT || !tri_shows(&w->tris[p - w->sphere_count], l))
                continue;
            if (lamp_push(w, &lamp_cap, p)) {
                free(cand);
                return err_set(err, "scene: out of memory for the lights' lamps");
            }
            l->lamp_count++;
        }
    }
    free(cand);
    return 0;
}

/* Planes, instances (and their models) and lights, derived; what they use. */
static int derive_items(World *w, const Scene *s, Err *err)
{
    WorldParts *pt = calloc(1, sizeof *pt);
    if (!pt)
        return err_set(err, "scene: out of memory");
    atomic_init(&pt->refs, 1);
    w->parts = pt;
    w->planes = pt->planes = calloc(s->plane_count ? s->plane_count : 1, sizeof *w->planes);
    w->instances = pt->instances = calloc(s->instance_count ? s->instance_count : 1, sizeof *w->instances);
    pt->instance_count = w->instances ? s->instance_count : 0;
    w->lights = pt->lights = calloc(s->light_count ? s->light_count : 1, sizeof *w->lights);
    if (!w->planes || !w->instances || !w->lights)
        return err_set(err, "scene: out of memory");
    uint32_t f = 0;
    for (uint32_t i = 0; i < s->material_count; i++) /* a model's textures come with its uvs */
        f |= material_features(&s->materials[i]) | (s->materials[i].texture >= 0 ? FEAT_TEXTURES : 0u);
    for (uint32_t i = 0; i < s->plane_count; i++, f |= FEAT_PLANES)
        w->planes[i] = plane_derive(&s->planes[i]);
    for (uint32_t i = 0; i < s->tri_count; i++)
        f |= s->tri_attrs[i].smooth ? FEAT_SMOOTH : 0u;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        w->instances[i] = world_instance_derive(&s->instances[i]);
        const Model *m = s->models[s->instances[i].model];
        f |= (m->normals ? FEAT_SMOOTH : 0u) | (m->uvs ? FEAT_TEXTURES : 0u) |
             (m->colours && s->instances[i].material < 0 ? FEAT_COLOURS : 0u);
        for (uint32_t k = 0; k < m->material_count; k++)
            f |= material_features(&m->materials[k]);
    }
    for (uint32_t i = 0; i < s->model_count; i++)
        if (model_prepare_simd(s->models[i], err))
            return err_prefix(err, "scene");
    for (uint32_t i = 0; i < s->instance_count; i++) {
        WorldInstance *in = &w->instances[i];
        const Model *m = s->models[in->model];
        if (!in->identity && m->tri_count <= WORLD_PLACED_TRIS && !m->cutout && /* a copy without masks */
            model_place(&in->placed, m, &in->rot, in->translate, in->scale, err))
            return err_prefix(err, "scene");
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        w->lights[i] = light_derive(&s->lights[i]);
        f |= light_features(&w->lights[i]);
    }
    w->plane_count = s->plane_count;
    w->instance_count = s->instance_count;
    w->light_count = s->light_count;
    w->item_features = f;
    return 0;
}

/* Which top-level primitives may be dielectrics (World.glassy): where
 * the scene has any, one byte each of spheres, triangles, instances. */
static int classify_glass(World *w, Err *err)
{
    if (!(w->item_features & FEAT_REFRACT))
        return 0;
    uint32_t nb = w->sphere_count + w->tri_count + w->instance_count, k = 0;
    uint8_t *g = w->parts->glassy = malloc(nb ? nb : 1);
    if (!g)
        return err_set(err, "scene: out of memory");
    for (uint32_t i = 0; i < w->sphere_count; i++)
        g[k++] = material_dielectric(&w->materials[w->spheres[i].material]);
    for (uint32_t i = 0; i < w->tri_count; i++)
        g[k++] = material_dielectric(&w->materials[w->tri_attrs[i].material]);
    for (uint32_t i = 0; i < w->instance_count; i++) {
        const WorldInstance *in = &w->instances[i];
        const Model *m = w->models[in->model];
        int glass = 0;
        if (in->material >= 0)
            glass = material_dielectric(&w->materials[in->material]);
        else if (m->mat_ids)
            for (uint32_t j = 0; j < m->material_count && !glass; j++)
                glass = material_dielectric(&m->materials[j]);
        else
            glass = w->material_count && material_dielectric(&w->materials[0]);
        g[k++] = (uint8_t)glass;
    }
    uint32_t n = 0, planes = 0;
    for (uint32_t i = 0; i < nb; i++)
        if (g[i] && n++ < WORLD_GLASS_LIST)
            w->parts->glass_list[n - 1] = i;
    for (uint32_t i = 0; i < w->plane_count; i++)
        planes += material_dielectric(&w->materials[w->planes[i].material]);
    if (n == 0 && planes == 0) { /* a glass material that nothing wears */
        free(g);
        w->parts->glassy = NULL;
        return 0;
    }
    w->glassy = g;
    w->glass_list = w->parts->glass_list;
    w->glass_count = n <= WORLD_GLASS_LIST ? n : UINT32_MAX;
    return 0;
}

/* The boxes of the top level: one per sphere, scene triangle and instance. */
static Aabb *top_boxes(const World *w, uint32_t nb, Err *err)
{
    Aabb *boxes = malloc(nb * sizeof *boxes);
    if (!boxes) {
        err_set(err, "scene: out of memory");
        return NULL;
    }
    uint32_t k = 0;
    for (uint32_t i = 0; i < w->sphere_count; i++) {
        const Sphere *sp = &w->spheres[i];
        vec3 r = v3_splat(sp->radius * (R(1) + real_gamma(4)));
        boxes[k++] = (Aabb){v3_sub(sp->centre, r), v3_add(sp->centre, r)};
    }
    for (uint32_t i = 0; i < w->tri_count; i++)
        boxes[k++] = tri_box(&w->tris[i]);
    for (uint32_t i = 0; i < w->instance_count; i++) {
        const WorldInstance *in = &w->instances[i];
        const Model *m = w->models[in->model];
        /* an empty model still needs a valid box: a point at its position */
        boxes[k++] = m->tri_count ? instance_world_box(in, m->bounds) : aabb_point(in->translate);
    }
    return boxes;
}

/* The environment of the description, where it has one. */
static int build_environment(World *w, const Scene *desc, Err *err)
{
    const SceneEnvironment *e = &desc->environment;
    if (e->texture < 0)
        return 0;
    const Environment *env = w->parts->env = environment_create(desc->textures[e->texture], e->strength, e->rotate, err);
    if (!env)
        return -1;
    w->env = env;
    if (!env->has_sun)
        return 0;
    /* its sun, a directional light after the scene's for the Whitted integrator */
    WorldLight *l = realloc(w->parts->lights, (w->light_count + 1) * sizeof *l);
    if (!l)
        return err_set(err, "scene: out of memory");
    w->lights = w->parts->lights = l;
    const Light sun = light_directional(v3_neg(env->sun_dir), env->sun_light, R(1));
    w->lights[w->light_count] = light_derive(&sun);
    w->whitted_lights = 1;
    w->item_features |= light_features(&w->lights[w->light_count]);
    return 0;
}

static atomic_uint_fast64_t tree_builds;

uint64_t world_tree_builds(void) { return atomic_load(&tree_builds); }

static void top_drop(WorldTop *t)
{
    if (t && atomic_fetch_sub(&t->refs, 1) == 1) {
        bvh4_destroy(&t->wide);
        bvh_destroy(&t->bvh);
        free(t->boxes);
        free(t);
    }
}

/* The top-level BVH over the boxes: previous's where its boxes are these
 * (to the bit), else a new one.  Takes boxes. */
static int build_top(World *w, const World *previous, Aabb *boxes, uint32_t nb, Err *err)
{
    WorldTop *pt = previous ? previous->top : NULL;
    if (pt && pt->count == nb && memcmp(pt->boxes, boxes, nb * sizeof *boxes) == 0) {
        free(boxes);
        atomic_fetch_add(&pt->refs, 1);
        w->top = pt;
        return 0;
    }
    WorldTop *t = calloc(1, sizeof *t);
    if (!t) {
        free(boxes);
        return err_set(err, "scene: out of memory");
    }
    t->boxes = boxes;
    t->count = nb;
    atomic_init(&t->refs, 1);
    BvhOptions opt = bvh_options_default(BVH_SAH);
    opt.max_leaf = 2;
    if (bvh_build(&t->bvh, boxes, nb, &opt, err) || bvh4_build(&t->wide, &t->bvh, err)) {
        top_drop(t);
        return err_prefix(err, "scene");
    }
    atomic_fetch_add(&tree_builds, 1);
    w->top = t;
    return 0;
}

static const Bvh empty_tree;

World *world_build(const Scene *desc, const World *previous, Err *err)
{
    if (!desc->checked) {
        err_set(err, "scene: not checked");
        return NULL;
    }
    World *w = calloc(1, sizeof *w);
    if (!w) {
        err_set(err, "scene: out of memory");
        return NULL;
    }
    *w = (World){.desc = desc, .view = scene_view(desc), .materials = desc->materials,
                 .material_count = desc->material_count, .textures = desc->textures, .spheres = desc->spheres,
                 .sphere_count = desc->sphere_count, .tris = desc->tris, .tri_attrs = desc->tri_attrs,
                 .tri_count = desc->tri_count, .models = desc->models, .ambient = desc->ambient,
                 .background = desc->background, .tree = &empty_tree};
    uint32_t nb = desc->sphere_count + desc->tri_count + desc->instance_count;
    Aabb *boxes = NULL;
    if (derive_items(w, desc, err) || pair_lamps(w, err) || emitters_build(w, err) || classify_glass(w, err) ||
        build_environment(w, desc, err) ||
        (nb && !(boxes = top_boxes(w, nb, err))) ||
        (nb && build_top(w, previous, boxes, nb, err)) || world_set_view(w, &w->view, err)) {
        world_destroy(w);
        return NULL;
    }
    if (w->top)
        w->tree = &w->top->bvh;
    w->lone_model = nb == 1 && desc->instance_count == 1 && w->instances[0].identity;
    return w;
}

int world_set_view(World *w, const View *v, Err *err)
{
    if (scene_check_view(&v->camera, &v->settings, err))
        return -1;
    w->view = *v;
    w->features = w->item_features | (v->camera.aperture > R(0) ? FEAT_LENS : 0u) |
                  (v->settings.shadows && w->light_count + w->whitted_lights ? FEAT_SHADOWS : 0u);
    return 0;
}

World *world_with_view(const World *w, const View *v, Err *err)
{
    World *n = malloc(sizeof *n);
    if (!n) {
        err_set(err, "scene: out of memory");
        return NULL;
    }
    *n = *w;
    if (world_set_view(n, v, err)) {
        free(n);
        return NULL;
    }
    if (n->parts)
        atomic_fetch_add(&n->parts->refs, 1);
    if (n->top) {
        atomic_fetch_add(&n->top->refs, 1);
        n->tree = &n->top->bvh;
    }
    return n;
}

int world_shares_top(const World *w, const World *previous)
{
    return w && previous && w->top && w->top == previous->top;
}

void world_destroy(World *w)
{
    if (!w)
        return;
    WorldParts *pt = w->parts;
    if (pt && atomic_fetch_sub(&pt->refs, 1) == 1) {
        for (uint32_t i = 0; i < pt->instance_count; i++)
            model_destroy(pt->instances[i].placed);
        free(pt->planes);
        free(pt->instances);
        free(pt->lights);
        free(pt->lamps);
        free(pt->emitters);
        free(pt->emit_cells);
        free(pt->glassy);
        environment_destroy(pt->env);
        free(pt);
    }
    top_drop(w->top);
    free(w);
}
