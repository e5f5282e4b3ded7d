/* trace.c - the top level of traversal: scene BVH, planes, model instances. */
#include "scene/trace.h"

#include "bvh/bvh4_walk.h"
#include "bvh/bvh_packet.h"
#include "bvh/bvh_traverse.h"
#include "base/simd.h"

#include <string.h>

/* The model an instance's rays meet: its placed copy in world space
 * (world.h), else the model itself. */
static inline const Model *instance_model(const World *w, const WorldInstance *in)
{
    return in->placed ? in->placed : w->models[in->model];
}

/* Whether an instance's rays must be moved into its model's space. */
static inline int instance_moves(const WorldInstance *in) { return !in->identity && !in->placed; }

/* Ray in an instance's model space.  The map x -> R^T (x - T) / s is affine,
 * so distances t along the ray are the same in both spaces. */
static void instance_ray(Ray *out, const WorldInstance *in, const Ray *r)
{
    real inv = R(1) / in->scale;
    vec3 o = v3_scale(m3_apply_t(&in->rot, v3_sub(r->org, in->translate)), inv);
    vec3 d = v3_scale(m3_apply_t(&in->rot, r->dir), inv);
    ray_init(out, o, d, r->tmin, r->tmax);
}

/* The scene's closest hit does not depend on the order its parts are
 * visited in, so that a packet of rays (visiting leaves in the packet's
 * order) gives each ray the hit it finds alone: the smallest t; of equal t
 * a plane (tested first, in index order), then the top-level primitive of
 * smallest index (spheres, scene triangles, instances: its position in the
 * top tree's primitive numbering), then inside a model the triangle of
 * smallest index (model.h).  `key` is 0 while the hit is none or a plane,
 * else the primitive's number + 1; a tie is taken when the new key is lower. */
typedef struct {
    Hit *hit;
    uint32_t key;
} Best;

static int takes(const Best *b, real t, uint32_t key) { return t < b->hit->t || (t == b->hit->t && key < b->key); }

static inline __attribute__((always_inline)) int leaf_closest(const World *w, uint32_t p, const Ray *r, Best *b)
{
    real t, b1 = 0, b2 = 0;
    const uint32_t key = p + 1;
    if (p < w->sphere_count) {
        const Sphere *sp = &w->spheres[p];
        /* the nearest root beyond tmin, then the rule (a tie at hit->t counts) */
        if (!sphere_intersect(r, sp->centre, sp->radius, REAL_INF, &t) || !takes(b, t, key))
            return 0;
        *b->hit = (Hit){t, 0, 0, HIT_SPHERE, p, 0};
        b->key = key;
        return 1;
    }
    p -= w->sphere_count;
    if (p < w->tri_count) {
        if (!tri_solve(r, &w->tris[p], &t, &b1, &b2) || !takes(b, t, key))
            return 0;
        *b->hit = (Hit){t, b1, b2, HIT_TRIANGLE, p, 0};
        b->key = key;
        return 1;
    }
    p -= w->tri_count;
    const WorldInstance *in = &w->instances[p];
    Ray mr;
    const Ray *rr = instance_moves(in) ? (instance_ray(&mr, in, r), &mr) : r;
    ModelHit mh;
    if (!model_intersect(instance_model(w, in), rr, b->hit->t, key < b->key, &mh))
        return 0;
    *b->hit = (Hit){mh.t, mh.b1, mh.b2, HIT_INSTANCE, p, mh.tri};
    b->key = key;
    return 1;
}

/* Whether top-level primitive p is part of the lamp of light l (NULL:
 * none): the light's shadow rays pass it (scene.h). */
static inline int lamp_part(const World *w, const WorldLight *l, uint32_t p)
{
    for (uint32_t k = 0; l && k < l->lamp_count; k++)
        if (w->lamps[l->lamp_first + k] == p)
            return 1;
    return 0;
}

static int leaf_occluded(const World *w, uint32_t p, const Ray *r, real tmax, const WorldLight *lamp)
{
    real t, b1, b2;
    if (lamp && lamp_part(w, lamp, p))
        return 0;
    if (p < w->sphere_count)
        return sphere_intersect(r, w->spheres[p].centre, w->spheres[p].radius, tmax, &t);
    p -= w->sphere_count;
    if (p < w->tri_count)
        return tri_intersect(r, &w->tris[p], tmax, &t, &b1, &b2);
    p -= w->tri_count;
    const WorldInstance *in = &w->instances[p];
    Ray mr;
    const Ray *rr = instance_moves(in) ? (instance_ray(&mr, in, r), &mr) : r;
    return model_occluded(instance_model(w, in), rr, tmax);
}

typedef struct {
    const World *w;
    Best *best;
    const uint8_t *only; /* trace_closest_glass: the primitives it looks at (World.glassy), or NULL: all */
} ClosestCtx;

static inline __attribute__((always_inline)) int top_leaf_closest(void *vctx, uint32_t first, uint32_t count,
                                                                  const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    int found = 0;
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t p = c->w->tree->prims[first + i];
        if (!c->only || c->only[p])
            found |= leaf_closest(c->w, p, r, c->best);
    }
    *tmax = c->best->hit->t;
    return found;
}

typedef struct {
    const World *w;
    const WorldLight *lamp; /* the light whose lamp the ray passes, or NULL */
    const uint8_t *glassy;  /* trace_shadow: the primitives it passes (World.glassy), or NULL */
    int *glass;             /* and where it notes that it passed one */
} AnyCtx;

static inline __attribute__((always_inline)) int top_leaf_any(const void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real tmax)
{
    const AnyCtx *c = vctx;
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t p = c->w->tree->prims[first + i];
        if (!leaf_occluded(c->w, p, r, tmax, c->lamp))
            continue;
        if (!c->glassy || !c->glassy[p])
            return 1;
        *c->glass = 1;
    }
    return 0;
}

/* The light whose lamp shadow rays towards l pass: l, or NULL where it has none. */
static const WorldLight *lamp_of(const WorldLight *l) { return l && l->lamp_count ? l : NULL; }

/* The top tree four-wide (bvh/bvh4.h), where the world has one and the
 * SIMD path is not the scalar one (which keeps the binary walks: both
 * give the same hits); else NULL. */
static inline const Bvh4 *top4(const World *w)
{
#if BVH4_COMPILED
    return w->top && w->top->wide.node_count && simd_path() != SIMD_SCALAR ? &w->top->wide : NULL;
#else
    (void)w;
    return NULL;
#endif
}

/* The nearest plane (with glass_only, glass plane) r meets, as hit. */
static inline __attribute__((always_inline)) void closest_planes(const World *w, const Ray *r, Hit *hit, int glass_only)
{
    hit->t = r->tmax;
    hit->kind = HIT_NONE;
    if (world_uses(w, FEAT_PLANES))
        for (uint32_t i = 0; i < w->plane_count; i++) {
            real t;
            if (glass_only && !material_dielectric(&w->materials[w->planes[i].material]))
                continue;
            if (plane_intersect(r, w->planes[i].point, w->planes[i].unit, hit->t, &t))
                *hit = (Hit){t, 0, 0, HIT_PLANE, i, 0};
        }
}

/* Whether a plane blocks r before tmax; with glass (trace_shadow), a glass
 * plane does not, and sets *glass where r crosses it. */
static inline __attribute__((always_inline)) int occluded_planes(const World *w, const Ray *r, real tmax, int *glass)
{
    if (world_uses(w, FEAT_PLANES))
        for (uint32_t i = 0; i < w->plane_count; i++) {
            real t;
            if (!plane_intersect(r, w->planes[i].point, w->planes[i].unit, tmax, &t))
                continue;
            if (!glass || !material_dielectric(&w->materials[w->planes[i].material]))
                return 1;
            *glass = 1;
        }
    return 0;
}

const Material *trace_instance_material(const World *w, uint32_t instance, uint32_t tri)
{
    const WorldInstance *in = &w->instances[instance];
    const Model *m = w->models[in->model];
    if (in->material >= 0)
        return &w->materials[in->material];
    if (m->mat_ids)
        return &m->materials[m->mat_ids[tri]];
    return w->material_count ? &w->materials[0] : NULL;
}

int trace_any_lamp(const World *w, const Hit *h)
{
    if (h->kind != HIT_SPHERE && h->kind != HIT_TRIANGLE)
        return 0;
    const uint32_t p = h->kind == HIT_SPHERE ? h->index : w->sphere_count + h->index;
    for (uint32_t k = 0; k < w->lamp_total; k++) /* every light's lamp, one after another */
        if (w->lamps[k] == p)
            return 1;
    return 0;
}

int trace_lamp_part(const World *w, const WorldLight *l, const Hit *h)
{
    if (h->kind == HIT_SPHERE)
        return lamp_part(w, l, h->index);
    if (h->kind == HIT_TRIANGLE)
        return lamp_part(w, l, w->sphere_count + h->index);
    return 0;
}

/* The closest hit among the planes (glass_only: the glass ones) and the
 * top tree's primitives that `only` marks (NULL: all). */
static int closest_of(const World *w, const Ray *r, Hit *hit, int glass_only, const uint8_t *only)
{
    closest_planes(w, r, hit, glass_only);
    Best b = {hit, 0};
    if (w->lone_model && !only) { /* the one instance (top primitive 0), without the walk's set-up */
        leaf_closest(w, 0, r, &b);
        return hit->kind != HIT_NONE;
    }
    if (only && w->glass_count <= WORLD_GLASS_LIST) { /* a few: each alone (the rule makes the order free) */
        for (uint32_t i = 0; i < w->glass_count; i++)
            leaf_closest(w, w->glass_list[i], r, &b);
        return hit->kind != HIT_NONE;
    }
    ClosestCtx c = {w, &b, only};
    real tmax = hit->t;
#if BVH4_COMPILED
    const Bvh4 *t4 = top4(w);
    if (t4) {
        bvh4_closest(t4, r, &tmax, top_leaf_closest, &c);
        return hit->kind != HIT_NONE;
    }
#endif
    bvh_closest(w->tree, r, &tmax, top_leaf_closest, &c);
    return hit->kind != HIT_NONE;
}

/* The scene's hit of a ray to tmax that met the one model (got) at mh, or nothing. */
static inline int lone_hit(Hit *hit, int got, const ModelHit *mh, real tmax)
{
    if (!got) {
        hit->t = tmax;
        hit->kind = HIT_NONE;
        return 0;
    }
    *hit = (Hit){mh->t, mh->b1, mh->b2, HIT_INSTANCE, 0, mh->tri};
    return 1;
}

/* The model of a world of one untransformed model and no plane (make
 * bench's mesh scenes, a model's preview), or NULL: there rays go to the
 * model's walk directly (closest_of's planes, Best and leaf dispatch come
 * to nothing). */
static inline const Model *lone_of(const World *w)
{
    return w->lone_model && !(world_uses(w, FEAT_PLANES) && w->plane_count) ? w->models[w->instances[0].model] : NULL;
}

/* (lone_of's shortcut: closest_of's set-up was a twentieth of a diffuse
 * bounce's instructions on the bunny) */
int trace_closest(const World *w, const Ray *r, Hit *hit)
{
    const Model *m = lone_of(w);
    if (m) {
        ModelHit mh;
        return lone_hit(hit, model_intersect(m, r, r->tmax, 0, &mh), &mh, r->tmax);
    }
    return closest_of(w, r, hit, 0, NULL);
}

/* (a world of one model goes to its pairs' walk in trace_closest_each,
 * lone_closest, before it gets here) */
uint32_t trace_closest_pair(const World *w, const Ray *a, const Ray *b, Hit *ha, Hit *hb)
{
#if BVH4_COMPILED
    const Bvh4 *t4 = top4(w);
    if (t4 && !w->lone_model) { /* closest_of, by pairs */
        closest_planes(w, a, ha, 0);
        closest_planes(w, b, hb, 0);
        Best ba = {ha, 0}, bb = {hb, 0};
        ClosestCtx ca = {w, &ba, NULL}, cb = {w, &bb, NULL};
        real ta = ha->t, tb = hb->t;
        bvh4_closest_pair(t4, a, b, &ta, &tb, top_leaf_closest, &ca, &cb);
        return (uint32_t)(ha->kind != HIT_NONE) | (uint32_t)(hb->kind != HIT_NONE) << 1;
    }
#endif
    return (uint32_t)trace_closest(w, a, ha) | (uint32_t)trace_closest(w, b, hb) << 1;
}

/* trace_closest's shortcut for n > 1 rays in a world of one untransformed
 * model and no plane: the model's walk as a packet, or (pairs) each ray
 * alone, two walks side by side; 0 where the world is not such a one.
 * No planes, Best keys or glass to ask about.  Measured (packets,
 * tools/bench/rayclass, the bunny's camera rays, one thread):
 * instructions of the tracing 284.7M -> 259.9M (callgrind), 16.8 ->
 * 18.1-18.3 Mrays/s, against Embree's 16-ray packets' 17.3-17.5 in the
 * same runs. */
static int lone_closest(const World *w, const Ray *rays, int n, Hit *hits, int pairs)
{
    const Model *m = lone_of(w);
    const Wide *wd = m && !m->cut ? m->wide : NULL; /* a cutout's walks are model_intersect's */
    if (!wd || n < 2)
        return 0;
    const Ray *rr[TRACE_PACKET] = {0};
    real tm[TRACE_PACKET] = {0};
    const uint32_t tie[TRACE_PACKET] = {0};
    ModelHit mh[TRACE_PACKET];
    for (int i = 0; i < n; i++)
        rr[i] = &rays[i], tm[i] = rays[i].tmax;
    const uint32_t got = (pairs ? wd->closest_pairs : wd->closest_packet)(wd, rr, n, tm, tie, mh);
    for (int i = 0; i < n; i++)
        lone_hit(&hits[i], got >> i & 1, &mh[i], tm[i]);
    return 1;
}

void trace_closest_each(const World *w, const Ray *rays, int n, Hit *hits)
{
    /* every ray in one call to the pairs' walk: measured (tools/bench/
     * rayclass, one thread, Mrays/s, mirrored / refracted rays, against
     * pairs by trace_closest_pair): the bunny 4.21 / 2.81 -> 4.30 / 2.84,
     * the 1M sphere 3.41 / 1.69 -> 3.48 / 1.74.  A walk that took the next
     * ray as soon as its own ended, so that two walks went side by side to
     * the last ray, lost 6-8% (3.85 / 2.59, 3.21 / 1.59). */
    if (lone_closest(w, rays, n, hits, 1))
        return;
    int i = 0;
    for (; i + 1 < n; i += 2)
        trace_closest_pair(w, &rays[i], &rays[i + 1], &hits[i], &hits[i + 1]);
    if (i < n)
        trace_closest(w, &rays[i], &hits[i]);
}

int trace_closest_glass(const World *w, const Ray *r, Hit *hit)
{
    return w->glassy ? closest_of(w, r, hit, 1, w->glassy) : trace_closest(w, r, hit);
}

/* Any top-level primitive that blocks r before tmax (top_leaf_any). */
static int top_any(const World *w, const Ray *r, real tmax, const AnyCtx *c)
{
    if (w->lone_model) /* the one leaf, without the walk's set-up */
        return top_leaf_any(c, 0, 1, r, tmax);
#if BVH4_COMPILED
    const Bvh4 *t4 = top4(w);
    if (t4)
        return bvh4_any(t4, r, tmax, top_leaf_any, c);
#endif
    return bvh_any(w->tree, r, tmax, top_leaf_any, c);
}

int trace_occluded(const World *w, const Ray *r, real tmax, const WorldLight *towards)
{
    AnyCtx c = {w, lamp_of(towards), NULL, NULL};
    return occluded_planes(w, r, tmax, NULL) || top_any(w, r, tmax, &c);
}

int trace_shadow(const World *w, const Ray *r, real tmax, const WorldLight *towards, int *glass)
{
    *glass = 0; /* and stays so where the world has no glass (glassy NULL) */
    AnyCtx c = {w, lamp_of(towards), w->glassy, glass};
    if (occluded_planes(w, r, tmax, w->glassy ? glass : NULL) || top_any(w, r, tmax, &c)) {
        *glass = 0;
        return 1;
    }
    return 0;
}

/* Instance p of the top tree against the rays of `mask`, as one packet in model space. */
static uint32_t instance_packet(const World *w, uint32_t p, const Ray *rays, uint32_t mask, Best *best, int closest,
                                const real *tmax)
{
    const WorldInstance *in = &w->instances[p - w->sphere_count - w->tri_count];
    Ray mr[TRACE_PACKET];
    const Ray *rr[TRACE_PACKET];
    real tm[TRACE_PACKET];
    int at[TRACE_PACKET], which[TRACE_PACKET], n = 0;
    if (!mask) /* never from the walks, but GCC cannot see that the arrays get filled */
        return 0;
    for (uint32_t m = mask; m; m &= m - 1) {
        int i = __builtin_ctz(m);
        if (instance_moves(in))
            instance_ray(&mr[n], in, &rays[i]), rr[n] = &mr[n];
        else
            rr[n] = &rays[i];
        tm[n] = closest ? best[i].hit->t : tmax[i];
        at[n] = closest && p + 1 < best[i].key;
        which[n++] = i;
    }
    const Model *m = instance_model(w, in);
    uint32_t got = 0;
    if (closest) {
        ModelHit mh[TRACE_PACKET];
        uint32_t found = model_intersect_packet(m, rr, n, tm, at, mh);
        for (int k = 0; k < n; k++)
            if (found >> k & 1) {
                Best *b = &best[which[k]];
                *b->hit = (Hit){mh[k].t, mh[k].b1, mh[k].b2, HIT_INSTANCE, p - w->sphere_count - w->tri_count, mh[k].tri};
                b->key = p + 1;
            }
    } else {
        uint32_t hit = model_occluded_packet(m, rr, n, tm);
        for (int k = 0; k < n; k++)
            if (hit >> k & 1)
                got |= 1u << which[k];
    }
    return got;
}

typedef struct {
    const World *w;
    const Ray *rays;
    Best *best;        /* closest hits; NULL for occlusion */
    const real *tmax;  /* occlusion's limits */
    const WorldLight *lamp; /* occlusion: the lamp its light passes */
    const uint8_t *glassy;  /* trace_shadow_packet: the primitives it passes, or NULL */
    uint32_t *glass;        /* and the rays that passed one */
} PacketCtx;

/* A primitive of the top tree against the packet's rays that reach it:
 * one by one, except instances, which take the packet to their model.
 * Closest hits follow the rule above, so the order is free. */
static inline __attribute__((always_inline)) uint32_t top_leaf_packet(void *vctx, uint32_t p, uint32_t rs, real *far)
{
    const PacketCtx *c = vctx;
    const World *w = c->w;
    const int closest = c->best != NULL;
    uint32_t done = 0;
    if (p >= w->sphere_count + w->tri_count) {
        done = instance_packet(w, p, c->rays, rs, c->best, closest, c->tmax);
    } else if (closest) {
        for (uint32_t m = rs; m; m &= m - 1) {
            int i = __builtin_ctz(m);
            leaf_closest(w, p, &c->rays[i], &c->best[i]);
        }
    } else if (!(c->lamp && lamp_part(w, c->lamp, p))) { /* the light's own lamp: passed by all of them */
        for (uint32_t m = rs; m; m &= m - 1) {
            int i = __builtin_ctz(m);
            if (leaf_occluded(w, p, &c->rays[i], c->tmax[i], NULL))
                done |= 1u << i;
        }
    }
    if (!closest && done && c->glassy && c->glassy[p]) { /* passed, noted */
        *c->glass |= done;
        done = 0;
    }
    if (closest)
        for (uint32_t m = rs; m; m &= m - 1) {
            int i = __builtin_ctz(m);
            far[i] = c->best[i].hit->t;
        }
    return done;
}

/* top_leaf_packet for the one instance of a lone-model world (top
 * primitive 0) and all n rays: the same rays, limits and rule (a plane met
 * at a ray's limit keeps it: key 0 before the instance's 1), the same
 * glass rule, straight to the model's packet walk. */
static uint32_t lone_packet(const PacketCtx *c, int n)
{
    const World *w = c->w;
    const Model *m = w->models[w->instances[0].model];
    const Ray *rr[TRACE_PACKET];
    real tm[TRACE_PACKET];
    for (int i = 0; i < n; i++)
        rr[i] = &c->rays[i], tm[i] = c->best ? c->best[i].hit->t : c->tmax[i];
    if (c->best) {
        int at[TRACE_PACKET];
        ModelHit mh[TRACE_PACKET];
        for (int i = 0; i < n; i++)
            at[i] = 1 < c->best[i].key;
        for (uint32_t found = model_intersect_packet(m, rr, n, tm, at, mh); found; found &= found - 1) {
            const int k = __builtin_ctz(found);
            *c->best[k].hit = (Hit){mh[k].t, mh[k].b1, mh[k].b2, HIT_INSTANCE, 0, mh[k].tri};
            c->best[k].key = 1;
        }
        return 0;
    }
    uint32_t done = model_occluded_packet(m, rr, n, tm);
    if (done && c->glassy && c->glassy[0]) { /* passed, noted */
        *c->glass |= done;
        done = 0;
    }
    return done;
}

/* The four-wide top level's interval walk (bvh4_packet) serves shadow
 * rays, from neighbouring points towards one light, and closest-hit
 * packets from one point (a pinhole camera's); other closest-hit packets
 * (what mirrors and glass send on, from points across a surface) walk the
 * binary tree.  Measured (tools/bench/rayclass, the default scene,
 * instructions of the tracing, binary -> four-wide): camera rays 350M ->
 * 310M, shadow rays to the point light 223M -> 207M and to the area light
 * 3259M -> 2929M; with the interval for every closest-hit packet whose
 * signs agree, refracted rays 202M -> 237M (their origins spread over the
 * glass), mirrored ones 337M -> 328M; with this limit both as before. */
#define TRACE_ORIGIN_SPREAD 0.0f

/* The top tree for a packet (bvh_packet.h, bvh4_walk.h).  A world of one
 * untransformed model (World.lone_model) sends the packet to the model
 * itself, as the tree's one leaf and instance_packet would, without their
 * bookkeeping (a fifth of a camera packet's instructions on the bunny). */
static uint32_t top_packet(const World *w, const Ray *rays, int n, Best *best, const real *tmax, const WorldLight *lamp,
                           uint32_t *glass)
{
    if (w->lone_model) {
        PacketCtx c = {w, rays, best, tmax, lamp, glass ? w->glassy : NULL, glass};
        return lone_packet(&c, n);
    }
    real far[(TRACE_PACKET + 3) / 4 * 4] = {0}; /* the box tests read it four at a time */
    for (int i = 0; i < n; i++)
        far[i] = best ? best[i].hit->t : tmax[i];
    PacketCtx c = {w, rays, best, tmax, lamp, glass ? w->glassy : NULL, glass};
#if BVH4_COMPILED
    const Bvh4 *t4 = top4(w);
    if (t4)
        return bvh4_packet(t4, w->tree, rays, n, far, best ? TRACE_ORIGIN_SPREAD : INFINITY, !best,
                           top_leaf_packet, &c);
#endif
    return bvh_packet(w->tree, rays, n, far, top_leaf_packet, &c, simd_path() != SIMD_SCALAR);
}

void trace_closest_packet(const World *w, const Ray *rays, int n, Hit *hits)
{
    if (lone_closest(w, rays, n, hits, 0))
        return;
    Best best[TRACE_PACKET];
    for (int i = 0; i < n; i++) {
        closest_planes(w, &rays[i], &hits[i], 0);
        best[i] = (Best){&hits[i], 0};
    }
    top_packet(w, rays, n, best, NULL, NULL, NULL);
}

/* In a world of one untransformed model, a packet whose directions part
 * (its first and last rays more than WIDE_DIR_SPREAD apart on an axis), or
 * whose origins do (more than WIDE_BOUNCE_LEAVES mean leaf sizes: wide.h),
 * would reach the model's walk only to go ray by ray there (wide_kernel.h),
 * or walk there as one interval where each ray's walk is its own: it goes
 * ray by ray from here, without the layers between (the top
 * level's packet, the instance's).  Measured (tools/bench/rayclass, the
 * bunny, 1 thread, Mrays/s, three runs): mirrored rays 7.63-7.76 ->
 * 8.01-8.09, refracted 5.08-5.20 -> 5.23-5.31; the first and last ray
 * alone, as a full check of all eight cost camera packets 8% more
 * instructions, hence this entry of its own and not trace_closest_packet. */
void trace_closest_bounced(const World *w, const Ray *rays, int n, Hit *hits)
{
    if (w->lone_model && n > 1) {
        const Model *m = w->models[w->instances[0].model];
        const real os = m->wide ? R(WIDE_BOUNCE_LEAVES) * (real)m->wide->leaf_size : REAL_INF;
        const vec3 d = v3_sub(rays[0].dir, rays[n - 1].dir), o = v3_sub(rays[0].org, rays[n - 1].org);
        if (!(fabs(d.x) <= R(WIDE_DIR_SPREAD) && fabs(d.y) <= R(WIDE_DIR_SPREAD) && fabs(d.z) <= R(WIDE_DIR_SPREAD)) ||
            !(fabs(o.x) <= os && fabs(o.y) <= os && fabs(o.z) <= os)) {
            trace_closest_each(w, rays, n, hits);
            return;
        }
    }
    trace_closest_packet(w, rays, n, hits);
}

/* trace_occluded_packet, and with glass (not NULL) trace_shadow_packet. */
static uint32_t occluded_packet(const World *w, const Ray *rays, int n, const real *tmax, const WorldLight *towards,
                                uint32_t *glass)
{
    const WorldLight *lamp = lamp_of(towards);
    uint32_t blocked = 0, gl = 0;
    if (glass && !w->glassy) { /* no glass in the world: plain occlusion */
        *glass = 0;
        glass = NULL;
    }
    const Model *lone = glass ? NULL : lone_of(w);
    if (lone) {
        /* straight to the model, as lone_packet would take the packet:
         * the planes' loop, the packing and the top level's context were
         * 4% of the bunny's area-light shadow rays' instructions (1355M ->
         * 1300M, callgrind); 8.5-8.6 Mrays/s against Embree's 16-ray
         * packets' 7.9-8.0, one thread */
        const Ray *rr[TRACE_PACKET];
        for (int i = 0; i < n; i++)
            rr[i] = &rays[i];
        return model_occluded_packet(lone, rr, n, tmax);
    }
    for (int i = 0; i < n; i++) {
        int g = 0;
        if (occluded_planes(w, &rays[i], tmax[i], glass ? &g : NULL))
            blocked |= 1u << i;
        gl |= (uint32_t)g << i;
    }
    uint32_t rest = ((1u << n) - 1) & ~blocked, got = 0, ggot = 0;
    if (rest == (1u << n) - 1) {
        blocked = top_packet(w, rays, n, NULL, tmax, lamp, glass ? &ggot : NULL);
        gl |= ggot;
    } else if (rest) { /* the unblocked rays, packed */
        Ray rr[TRACE_PACKET];
        real tm[TRACE_PACKET];
        int which[TRACE_PACKET], m = 0;
        for (uint32_t k = rest; k; k &= k - 1) {
            int i = __builtin_ctz(k);
            rr[m] = rays[i], tm[m] = tmax[i], which[m++] = i;
        }
        got = top_packet(w, rr, m, NULL, tm, lamp, glass ? &ggot : NULL);
        for (int k = 0; k < m; k++) {
            blocked |= (got >> k & 1) << which[k];
            gl |= (ggot >> k & 1) << which[k];
        }
    }
    if (glass)
        *glass = gl & ~blocked;
    return blocked;
}

uint32_t trace_occluded_packet(const World *w, const Ray *rays, int n, const real *tmax, const WorldLight *towards)
{
    return occluded_packet(w, rays, n, tmax, towards, NULL);
}

uint32_t trace_shadow_packet(const World *w, const Ray *rays, int n, const real *tmax, const WorldLight *towards,
                             uint32_t *glass)
{
    return occluded_packet(w, rays, n, tmax, towards, glass);
}

static vec3 bary(vec3 a, vec3 b, vec3 c, real b1, real b2)
{
    return v3_add(v3_add(v3_scale(a, R(1) - b1 - b2), v3_scale(b, b1)), v3_scale(c, b2));
}

vec3 trace_triangle_point(vec3 v0, vec3 v1, vec3 v2, real b1, real b2, real *err)
{
    *err = real_gamma(7) * v3_max_comp(v3_max(v3_abs(v0), v3_max(v3_abs(v1), v3_abs(v2))));
    return bary(v0, v1, v2, b1, b2);
}

static const Material fallback_material = {.kd = {{R(0.8), R(0.8), R(0.8)}}, .shininess = R(1), .texture = -1};

vec3 trace_terminator_point(vec3 p, const vec3 v[3], const vec3 n[3], real b1, real b2, real *err)
{
    const real w[3] = {R(1) - b1 - b2, b1, b2};
    vec3 lift = v3_splat(0);
    real mag = v3_max_comp(v3_abs(p));
    for (int i = 0; i < 3; i++) {
        vec3 ni = v3_norm(n[i]);
        real d = v3_dot(v3_sub(p, v[i]), ni);
        if (d < R(0)) /* below the vertex's tangent plane: up onto it */
            lift = v3_madd(lift, ni, -d * w[i]);
        mag = real_max(mag, v3_max_comp(v3_abs(v[i])));
    }
    vec3 q = v3_add(p, lift);
    /* the differences p - v_i, their dot products and the weighted sum each
     * round: a bound of the same form as a hit point's, on the larger numbers */
    *err += real_gamma(16) * (mag + v3_max_comp(v3_abs(lift))) + real_gamma(2) * v3_max_comp(v3_abs(q));
    return q;
}

/* A smooth triangle's point lifted onto the curved surface its vertex
 * normals describe (trace_terminator_point), for out->ps.  Apart from
 * surface_at: inlined, its registers cost the other hits of a scene with
 * smooth normals too (measured before the copies: 8 instructions of a
 * flat hit). */
static __attribute__((noinline)) void surface_lift(Surface *out, const Hit *h, const vec3 tv[3], vec3 tn[3], int flip,
                                                  const WorldInstance *inst, vec3 pm)
{
    /* the vertex normals face the side shading (and shadow rays) use */
    for (int i = 0; i < 3 && flip; i++)
        tn[i] = v3_neg(tn[i]);
    if (!inst) {
        out->ps = trace_terminator_point(out->p, tv, tn, h->b1, h->b2, &out->ps_err);
        return;
    }
    /* an instance: lifted in model space, carried to the world as p is */
    real e = 0;
    vec3 lifted = trace_terminator_point(pm, tv, tn, h->b1, h->b2, &e);
    out->ps = world_instance_point(inst, lifted);
    out->ps_err = out->err + e * inst->scale * (R(1) + real_gamma(8)) +
                  real_gamma(10) * R(3) * inst->scale * v3_max_comp(v3_abs(lifted)) +
                  real_gamma(2) * v3_max_comp(v3_abs(out->ps));
}

/* A smooth triangle's corners and vertex normals, for the terminator point
 * (model space for an instance: pm, and the instance). */
typedef struct {
    vec3 tv[3], tn[3], pm;
    const WorldInstance *inst;
} Lift;

/* The tangent frame of a model's triangle whose material has a normal
 * map: the directions in which u and v grow across it (from its corners'
 * positions and texture coordinates, as pbrt's triangles without tangents
 * take them), turned into the world, into the surface; for a normal map
 * (not a height map) u's direction is the corners' smooth tangents
 * interpolated where the model has them (model_tangents.c), so that the
 * frame does not break at the triangle's edges, and v's only says which
 * way the bitangent points.  None (sf->nmap left NULL) where the texture
 * coordinates do not span the triangle. */
static __attribute__((noinline)) void bump_frame(const Model *m, const Hit *h, const WorldInstance *in,
                                                const Material *mat, Surface *sf)
{
    const uint32_t tri = h->sub;
    vec3 dpdu, dpdv;
    if (!model_tri_frame(m, tri, &dpdu, &dpdv))
        return;
    if (m->tangents && !material_heights(mat)) {
        const vec3 *tg = &m->tangents[3 * tri];
        const vec3 s = bary(tg[0], tg[1], tg[2], h->b1, h->b2);
        if (v3_dot(s, s) > R(0))
            dpdu = s;
    }
    sf->dpdu = m3_apply(&in->rot, dpdu);
    sf->dpdv = m3_apply(&in->rot, dpdv);
    sf->nscale = mat->normal_scale;
    sf->nheight = mat->bump_height;
    sf->nmap = m->textures[mat->normal_map];
}

/* The normal of a surface bumped by a height map, on n's side, not unit
 * (Blinn's bump mapping, "Simulation of wrinkled surfaces", 1978, as
 * pbrt's BumpMap takes it): displaced along n by the map's height (its
 * red as a fraction, times nheight), the surface moves with u by
 * dpdu + n dh/du and with v by dpdv + n dh/dv, and their cross product is
 * its normal.  dpdu and dpdv are the shading surface's, in the plane of
 * the smooth normal n (pbrt's shading geometry), so that a level map
 * leaves n as it is; the triangle's own would give its flat normal, and a
 * smooth low-poly model under a height map showed every facet.  The
 * slopes are central differences a texel apart, or the footprint's width
 * apart where that is wider (a far surface's bumps average out as its
 * texels do). */
static vec3 height_normal(const Surface *sf, const Texture *map, const TexFootprint *fp, vec3 n)
{
    real du = R(1) / (real)map->w, dv = R(1) / (real)map->h;
    if (fp) {
        du = real_max(du, R(0.5) * (fabs(fp->dudx) + fabs(fp->dudy)));
        dv = real_max(dv, R(0.5) * (fabs(fp->dvdx) + fabs(fp->dvdy)));
    }
    const real u = sf->u, v = sf->v, k = sf->nheight;
    const real bu = k * (texture_fractions(map, u + du, v, fp).x - texture_fractions(map, u - du, v, fp).x) / (R(2) * du);
    const real bv = k * (texture_fractions(map, u, v + dv, fp).x - texture_fractions(map, u, v - dv, fp).x) / (R(2) * dv);
    const vec3 su = v3_sub(sf->dpdu, v3_scale(n, v3_dot(n, sf->dpdu)));
    const vec3 sv = v3_sub(sf->dpdv, v3_scale(n, v3_dot(n, sf->dpdv)));
    const vec3 p = v3_cross(v3_madd(su, n, bu), v3_madd(sv, n, bv));
    return v3_dot(p, n) < R(0) ? v3_neg(p) : p;
}

/* The shading normal of a normal-mapped surface: the map's vector (x, y
 * tilted by the scale) in the frame of the tangent (u's direction made
 * perpendicular to the normal), the bitangent (n x t, turned towards v's
 * direction, so mirrored texture coordinates mirror it) and the normal the
 * vertices give, on the side the map was made for (the normal before
 * surface_at turned it to the viewer), then turned as that one was
 * (ns_turned).  A mapped normal that would face away from the
 * viewer, or a frame that does not exist, leaves ns as it was. */
void trace_surface_bump_apply(Surface *out, const TexFootprint *fp)
{
    const Texture *map = out->nmap;
    out->nmap = NULL; /* applied once */
    const int flip = out->ns_turned;
    const vec3 n = flip ? v3_neg(out->ns) : out->ns;
    vec3 p;
    if (out->nheight > R(0)) {
        p = height_normal(out, map, fp, n);
    } else {
        vec3 t = v3_sub(out->dpdu, v3_scale(n, v3_dot(n, out->dpdu)));
        const real tl = v3_len(t);
        if (!(tl > R(0)) || !isfinite(tl))
            return;
        t = v3_scale(t, R(1) / tl);
        vec3 b = v3_cross(n, t);
        if (v3_dot(b, out->dpdv) < R(0))
            b = v3_neg(b);
        const vec3 c = texture_normal(map, out->u, out->v, fp);
        p = v3_madd(v3_madd(v3_scale(n, c.z), t, c.x * out->nscale), b, c.y * out->nscale);
    }
    const real pl = v3_len(p);
    if (!(pl > R(0)) || !isfinite(pl))
        return;
    p = v3_scale(p, flip ? R(-1) / pl : R(1) / pl);
    if (v3_dot(p, out->ng) > R(0)) {
        out->bumped = 1;
        out->ns = p;
    }
}

void trace_surface_metal_apply(const World *w, Surface *sf, const TexFootprint *fp)
{
    const Material *mt = sf->mat;
    const vec3 c = texture_fractions(sf->mtex, sf->u, sf->v, fp);
    Material *l = &sf->local;
    *l = *mt;
    l->metal_map = 0, l->metal_mapped = 0;
    l->kr = v3_scale(mt->kr, c.z);
    l->kre = v3_scale(mt->kre, c.z); /* the metal's rim: its share, white (not tinted by the colour texture) */
    l->kd = v3_max(v3_sub(mt->kd, l->kr), v3_splat(R(0)));
    if (sf->tex) {
        sf->local_tex = texture_sample(sf->tex, sf->u, sf->v, fp, w->view.settings.filter);
        sf->local_read = 1;
        l->kr = v3_mul(l->kr, sf->local_tex);
    }
    l->ks = l->kr;
    l->roughness = mt->roughness * c.y;
    l->shininess = material_phong_exponent(l->roughness);
    if (material_coats(mt)) { /* the coat of the dielectric share: 1 - the texel's metal */
        const real kd = v3_max_comp(mt->kd), factor = kd > R(0) ? v3_max_comp(mt->kr) / kd : R(0);
        l->coat = mt->coat * real_max(R(0), R(1) - c.z * factor);
        l->coat_roughness = mt->coat_roughness * c.y;
    }
    sf->mat = l;
    sf->mtex = NULL; /* applied: not a second time */
}

void trace_surface_blend_apply(Surface *sf)
{
    const real a = texture_coverage(sf->btex, sf->u, sf->v);
    Material *l = trace_surface_local(sf);
    l->mask_blend = 0;
    l->kd = v3_scale(l->kd, a), l->ks = v3_scale(l->ks, a);
    l->kr = v3_scale(l->kr, a), l->kre = v3_scale(l->kre, a);
    l->kt = v3_sub(v3_splat(R(1)), v3_scale(v3_sub(v3_splat(R(1)), l->kt), a));
    l->ke = v3_scale(l->ke, a); /* its light too: the see-through share emits nothing (emitters.c's glow_at alike) */
    sf->btex = NULL; /* applied: not a second time */
}

/* The surfaces of each kind of hit, for surface_at; `optional` as there. */
static inline __attribute__((always_inline)) void surface_sphere(const World *w, const Ray *r, const Hit *h,
                                                                 Surface *out, const int optional)
{
    const Sphere *sp = &w->spheres[h->index];
    vec3 p = ray_at(r, h->t);
    out->ng = v3_norm(v3_sub(p, sp->centre));
    /* re-project onto the surface: removes the error of o + t*d */
    out->p = v3_madd(sp->centre, out->ng, sp->radius);
    /* r * n carries the normalisation's error; adding the centre rounds once more */
    out->err = real_gamma(6) * sp->radius + real_gamma(2) * real_max(v3_max_comp(v3_abs(sp->centre)), v3_max_comp(v3_abs(out->p)));
    out->ns = out->ng;
    out->mat = &w->materials[sp->material];
    if (optional && world_uses(w, FEAT_TEXTURES) && material_wants_uv(out->mat)) {
        /* spherical mapping: u the longitude from +z towards +x, v the
         * latitude from the bottom pole (0) to the top (1); only for a
         * textured material (the arc functions showed in the profile) */
        vec3 n = out->ng;
        out->u = R(0.5) + atan2(n.x, n.z) / (R(2) * REAL_PI);
        out->v = R(0.5) + asin(real_clamp(n.y, R(-1), R(1))) / REAL_PI;
        out->has_uv = 1;
    }
    out->object = h->index;
}

static inline __attribute__((always_inline)) void surface_plane(const World *w, const Ray *r, const Hit *h, Surface *out,
                                                                const int optional)
{
    const WorldPlane *pl = &w->planes[h->index];
    vec3 p = ray_at(r, h->t);
    /* project onto the plane for the same reason */
    out->p = v3_madd(p, pl->unit, v3_dot(v3_sub(pl->point, p), pl->unit));
    out->err = real_gamma(4) * real_max(v3_max_comp(v3_abs(out->p)), v3_max_comp(v3_abs(pl->point)));
    out->ng = out->ns = pl->unit;
    out->mat = &w->materials[pl->material];
    if (optional && world_uses(w, FEAT_TEXTURES) && material_wants_uv(out->mat)) {
        vec3 d = v3_sub(out->p, pl->point);
        out->u = v3_dot(d, pl->tu);
        out->v = v3_dot(d, pl->tv);
        out->has_uv = 1;
    }
    out->object = w->sphere_count + h->index;
}

static inline __attribute__((always_inline)) void surface_triangle(const World *w, const Hit *h, Surface *out,
                                                                   Lift *lift, const int optional)
{
    const Tri *t = &w->tris[h->index];
    const TriAttr *a = &w->tri_attrs[h->index];
    vec3 v0 = tri_vertex(t, 0), v1 = tri_vertex(t, 1), v2 = tri_vertex(t, 2);
    out->p = trace_triangle_point(v0, v1, v2, h->b1, h->b2, &out->err);
    out->ng = v3_norm_any(v3_cross(v3_sub(v1, v0), v3_sub(v2, v0)));
    out->ns = out->ng;
    if (optional && world_uses(w, FEAT_SMOOTH) && a->smooth) {
        out->ns = v3_norm(bary(a->n[0], a->n[1], a->n[2], h->b1, h->b2));
        out->smooth = 1;
        lift->tv[0] = v0, lift->tv[1] = v1, lift->tv[2] = v2;
        memcpy(lift->tn, a->n, sizeof lift->tn);
    }
    if (optional && world_uses(w, FEAT_TEXTURES) && a->textured) {
        out->u = (R(1) - h->b1 - h->b2) * a->uv[0] + h->b1 * a->uv[2] + h->b2 * a->uv[4];
        out->v = (R(1) - h->b1 - h->b2) * a->uv[1] + h->b1 * a->uv[3] + h->b2 * a->uv[5];
        out->has_uv = 1;
    }
    out->mat = &w->materials[a->material];
    /* scene triangles of one material form one surface (a quad is two triangles) */
    out->object = w->sphere_count + w->plane_count + a->material;
}

/* Returns 1 where the surface takes the model's own material (and texture). */
static inline __attribute__((always_inline)) int surface_instance(const World *w, const Hit *h, Surface *out, Lift *lift,
                                                                  const int optional)
{
    int model_tex = 0;
    const WorldInstance *in = &w->instances[h->index];
    const Model *m = w->models[in->model];
    const Tri *t = &m->tris[h->sub];
    vec3 v0 = tri_vertex(t, 0), v1 = tri_vertex(t, 1), v2 = tri_vertex(t, 2);
    lift->pm = bary(v0, v1, v2, h->b1, h->b2);
    out->p = world_instance_point(in, lift->pm);
    /* the model-space point's error carried through rotation and scale, plus
     * the rounding of adding the translation (and of subtracting it again
     * when a new ray goes back into model space) */
    real vmax = v3_max_comp(v3_max(v3_abs(v0), v3_max(v3_abs(v1), v3_abs(v2))));
    out->err = real_gamma(10) * R(3) * in->scale * vmax +
               real_gamma(2) * real_max(v3_max_comp(v3_abs(in->translate)), v3_max_comp(v3_abs(out->p)));
    /* uniform scale: normals transform by the rotation alone */
    out->ng = v3_norm_any(m3_apply(&in->rot, v3_cross(v3_sub(v1, v0), v3_sub(v2, v0))));
    if (optional && world_uses(w, FEAT_SMOOTH) && m->normals) {
        const vec3 *n = &m->normals[3 * h->sub];
        out->ns = v3_norm(m3_apply(&in->rot, bary(n[0], n[1], n[2], h->b1, h->b2)));
        out->smooth = 1;
        lift->tv[0] = v0, lift->tv[1] = v1, lift->tv[2] = v2;
        memcpy(lift->tn, n, sizeof lift->tn);
        lift->inst = in;
    } else {
        out->ns = out->ng;
    }
    if (optional && world_uses(w, FEAT_TEXTURES) && m->uvs) {
        const real *uv = &m->uvs[6 * h->sub];
        out->u = (R(1) - h->b1 - h->b2) * uv[0] + h->b1 * uv[2] + h->b2 * uv[4];
        out->v = (R(1) - h->b1 - h->b2) * uv[1] + h->b1 * uv[3] + h->b2 * uv[5];
        out->has_uv = 1;
    }
    if (optional && world_uses(w, FEAT_COLOURS) && m->colours && in->material < 0) {
        const vec3 *c = &m->colours[3 * h->sub];
        out->colour = bary(c[0], c[1], c[2], h->b1, h->b2);
        out->has_colour = 1;
    }
    const Material *mat = trace_instance_material(w, h->index, h->sub);
    if (mat)
        out->mat = mat;
    if (in->material < 0 && m->mat_ids) {
        /* a model's own material names the model's own texture */
        out->tex = out->mat->texture >= 0 ? m->textures[out->mat->texture] : NULL;
        model_tex = 1;
        if (optional && world_uses(w, FEAT_NORMAL_MAP) && out->has_uv && material_bumps(out->mat))
            bump_frame(m, h, in, out->mat, out);
        if (optional && out->has_uv && material_emit_mapped(out->mat))
            out->etex = m->textures[out->mat->emit_map];
        if (optional && out->has_uv && material_occludes(out->mat))
            out->aotex = m->textures[out->mat->ao_map];
        if (optional && out->has_uv && material_metal_mapped(out->mat))
            out->mtex = m->textures[out->mat->metal_map];
        if (optional && out->has_uv && material_blends(out->mat))
            out->btex = m->textures[out->mat->mask];
    }
    out->object = w->sphere_count + w->plane_count + w->material_count + h->index;
    return model_tex;
}

/* trace_surface's body; `optional` (a constant in each copy) lets the
 * paths of smooth normals, textures and vertex colours in. */
static inline __attribute__((always_inline)) void surface_at(const World *w, const Ray *r, const Hit *h, Surface *out,
                                                             const int optional)
{
    /* field by field, not memset: its string store's start-up showed in
     * every hit (every case below sets p, the normals, err, mat, object) */
    out->p = out->ng = out->ns = out->colour = v3_splat(0);
    out->u = out->v = out->err = 0;
    out->has_uv = out->has_colour = out->smooth = out->inside = out->bumped = out->local_read = 0;
    out->mat = &fallback_material;
    out->etex = out->aotex = out->mtex = out->btex = NULL;
    out->object = 0;
    Lift lift;
    lift.pm = v3_splat(0);
    lift.inst = NULL;
    out->nmap = NULL;
    int model_tex = 0;
    switch (h->kind) {
    case HIT_SPHERE: surface_sphere(w, r, h, out, optional); break;
    case HIT_PLANE: surface_plane(w, r, h, out, optional); break;
    case HIT_TRIANGLE: surface_triangle(w, h, out, &lift, optional); break;
    case HIT_INSTANCE: model_tex = surface_instance(w, h, out, &lift, optional); break;
    default: break;
    }
    if (!model_tex)
        out->tex = out->mat->texture >= 0 ? w->textures[out->mat->texture] : NULL;
    /* face the viewer: all surfaces are two-sided */
    if (v3_dot(out->ng, r->dir) > R(0)) {
        out->ng = v3_neg(out->ng);
        out->inside = 1;
    }
    int flip = v3_dot(out->ns, out->ng) < R(0);
    if (flip)
        out->ns = v3_neg(out->ns);
    out->ps = out->p;
    out->ps_err = out->err;
    if (out->smooth)
        surface_lift(out, h, lift.tv, lift.tn, flip, lift.inst, lift.pm);
    out->ns_turned = flip;
    out->nv = out->ns;
}

void trace_surface(const World *w, const Ray *r, const Hit *h, Surface *out)
{
    /* a scene without any of them takes a copy without their paths: with
     * them in the one body, each flat hit executed 100 instructions more
     * than a build with the features compiled out (the bigger function's
     * code, spread thin: registers, spills, vector shuffles) */
    if (world_uses(w, FEAT_SMOOTH | FEAT_TEXTURES | FEAT_COLOURS))
        surface_at(w, r, h, out, 1);
    else
        surface_at(w, r, h, out, 0);
}

vec3 trace_emission(const World *w, const Surface *sf, const TexFootprint *fp)
{
    if (!sf->etex)
        return sf->mat->ke;
    return v3_mul(sf->mat->ke, texture_sample(sf->etex, sf->u, sf->v, fp, w->view.settings.filter));
}

real trace_occlusion(const Surface *sf, const TexFootprint *fp)
{
    if (!sf->aotex)
        return R(1);
    /* glTF 2.0, 3.9.3: 1 + strength (r - 1) */
    const real r = texture_fractions(sf->aotex, sf->u, sf->v, fp).x;
    return R(1) + sf->mat->ao_strength * (r - R(1));
}

vec3 trace_lifted_origin(const Surface *sf, real a)
{
    if (!(a > R(0)))
        return trace_offset_origin(sf->p, sf->ng, sf->err);
    if (a >= R(1))
        return trace_offset_origin(sf->ps, sf->ng, sf->ps_err);
    const vec3 q = v3_madd(sf->p, v3_sub(sf->ps, sf->p), a);
    /* p and ps each within their bounds; the difference, product and sum round */
    const real e = real_max(sf->err, sf->ps_err) +
                   real_gamma(3) * (v3_max_comp(v3_abs(sf->p)) + v3_max_comp(v3_abs(sf->ps)));
    return trace_offset_origin(q, sf->ng, e);
}

/* Coordinate o one step further the way n points (none where n is 0). */
static inline real offset_step(real o, real n)
{
    return n > R(0) ? real_next_up(o) : n < R(0) ? real_next_down(o) : o;
}

vec3 trace_offset_origin(vec3 p, vec3 n, real err)
{
    /* distance along n that covers the error box of p: |n| . err (PBRT 3.9.5) */
    real d = err * (fabs(n.x) + fabs(n.y) + fabs(n.z));
    const vec3 o = v3_madd(p, n, d);
    /* coordinate by coordinate, not a loop over o.e[]: the loop kept o in
     * memory, four bytes a store, and the result left as an eight-byte
     * load across two of them, which waits for both to reach the cache
     * (a third of this function's time, path-traced) */
    return v3(offset_step(o.x, n.x), offset_step(o.y, n.y), offset_step(o.z, n.z));
}

/* Barycentric changes (db1, db2) of a displacement dp in the plane of the
 * triangle with edges e1, e2 (least squares: dp's part in the plane). */
static void bary_change(vec3 e1, vec3 e2, vec3 dp, real *db1, real *db2)
{
    real g11 = v3_dot(e1, e1), g12 = v3_dot(e1, e2), g22 = v3_dot(e2, e2);
    real r1 = v3_dot(dp, e1), r2 = v3_dot(dp, e2), det = g11 * g22 - g12 * g12;
    if (!(fabs(det) > R(0))) {
        *db1 = *db2 = R(0);
        return;
    }
    *db1 = (g22 * r1 - g12 * r2) / det;
    *db2 = (g11 * r2 - g12 * r1) / det;
}

/* How the unit normal normalise(n) changes when n changes by dn. */
static vec3 unit_change(vec3 n, vec3 dn)
{
    real len = v3_len(n);
    if (!(len > R(0)))
        return v3_splat(0);
    vec3 u = v3_scale(n, R(1) / len);
    return v3_scale(v3_madd(dn, u, -v3_dot(u, dn)), R(1) / len);
}

/* A triangle's texture coordinate and normal changes (model space) for the
 * footprint's two sides dp[2]; uv (6) and n (3) may be NULL. */
static void tri_changes(const Tri *t, const real *uv, const vec3 *n, real b1, real b2, const vec3 dp[2], real duv[4],
                        vec3 dn[2])
{
    vec3 v0 = tri_vertex(t, 0), e1 = v3_sub(tri_vertex(t, 1), v0), e2 = v3_sub(tri_vertex(t, 2), v0);
    for (int k = 0; k < 2; k++) {
        real d1, d2;
        bary_change(e1, e2, dp[k], &d1, &d2);
        if (uv) {
            duv[2 * k] = d1 * (uv[2] - uv[0]) + d2 * (uv[4] - uv[0]);
            duv[2 * k + 1] = d1 * (uv[3] - uv[1]) + d2 * (uv[5] - uv[1]);
        }
        if (n) {
            vec3 nn = bary(n[0], n[1], n[2], b1, b2);
            dn[k] = unit_change(nn, v3_add(v3_scale(v3_sub(n[1], n[0]), d1), v3_scale(v3_sub(n[2], n[0]), d2)));
        }
    }
}

void trace_surface_change(const World *w, const Hit *h, const Surface *sf, vec3 dpdx, vec3 dpdy, TexFootprint *fp,
                          vec3 *dndx, vec3 *dndy)
{
    real duv[4] = {0, 0, 0, 0};
    vec3 dn[2] = {v3_splat(0), v3_splat(0)};
    const vec3 dp[2] = {dpdx, dpdy};
    vec3 n_ref = sf->ns; /* the normal whose change dn is, before the surface turned it to face the ray */
    switch (h->kind) {
    case HIT_SPHERE: {
        const Sphere *sp = &w->spheres[h->index];
        vec3 n = v3_scale(v3_sub(sf->p, sp->centre), R(1) / sp->radius);
        n_ref = n;
        for (int k = 0; k < 2; k++)
            dn[k] = v3_scale(v3_madd(dp[k], n, -v3_dot(dp[k], n)), R(1) / sp->radius);
        /* u = 1/2 + atan2(nx, nz) / 2pi, v = 1/2 + asin(ny) / pi (surface_at) */
        real r2 = n.x * n.x + n.z * n.z, c = sqrt(real_max(R(0), R(1) - n.y * n.y));
        for (int k = 0; k < 2; k++) {
            duv[2 * k] = r2 > R(0) ? (n.z * dn[k].x - n.x * dn[k].z) / (R(2) * REAL_PI * r2) : R(0);
            duv[2 * k + 1] = c > R(0) ? dn[k].y / (REAL_PI * c) : R(0);
        }
        break;
    }
    case HIT_PLANE: {
        const WorldPlane *pl = &w->planes[h->index];
        for (int k = 0; k < 2; k++) {
            duv[2 * k] = v3_dot(dp[k], pl->tu);
            duv[2 * k + 1] = v3_dot(dp[k], pl->tv);
        }
        break;
    }
    case HIT_TRIANGLE: {
        const TriAttr *a = &w->tri_attrs[h->index];
        tri_changes(&w->tris[h->index], a->textured ? a->uv : NULL, a->smooth ? a->n : NULL, h->b1, h->b2, dp, duv, dn);
        if (a->smooth)
            n_ref = bary(a->n[0], a->n[1], a->n[2], h->b1, h->b2);
        break;
    }
    case HIT_INSTANCE: {
        const WorldInstance *in = &w->instances[h->index];
        const Model *m = w->models[in->model];
        /* into model space, where the triangle's coordinates are */
        const vec3 dpm[2] = {v3_scale(m3_apply_t(&in->rot, dpdx), R(1) / in->scale),
                             v3_scale(m3_apply_t(&in->rot, dpdy), R(1) / in->scale)};
        const vec3 *n = m->normals ? &m->normals[3 * h->sub] : NULL;
        tri_changes(&m->tris[h->sub], m->uvs ? &m->uvs[6 * h->sub] : NULL, n, h->b1, h->b2, dpm, duv, dn);
        if (n) {
            for (int k = 0; k < 2; k++)
                dn[k] = m3_apply(&in->rot, dn[k]);
            n_ref = m3_apply(&in->rot, bary(n[0], n[1], n[2], h->b1, h->b2));
        }
        break;
    }
    default:
        break;
    }
    /* the normal was turned to face the ray (surface_at): its change turns with it */
    if (v3_dot(n_ref, sf->ns) < R(0))
        dn[0] = v3_neg(dn[0]), dn[1] = v3_neg(dn[1]);
    *fp = (TexFootprint){duv[0], duv[1], duv[2], duv[3]};
    *dndx = dn[0];
    *dndy = dn[1];
}
