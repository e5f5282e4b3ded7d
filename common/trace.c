/* trace.c - the top level of traversal: scene BVH, planes, model instances. */
#include "trace.h"

#include "bvh_traverse.h"

#include <string.h>

/* Ray in an instance's model space.  The map x -> R^T (x - T) / s is affine,
 * so distances t along the ray are the same in both spaces. */
static Ray instance_ray(const Instance *in, const Ray *r)
{
    real inv = R(1) / in->scale;
    vec3 o = v3_scale(m3_apply_t(&in->rot, v3_sub(r->org, in->translate)), inv);
    vec3 d = v3_scale(m3_apply_t(&in->rot, r->dir), inv);
    return ray_make(o, d, r->tmin, r->tmax);
}

static int leaf_closest(const Scene *s, uint32_t p, const Ray *r, Hit *hit)
{
    real t, b1 = 0, b2 = 0;
    if (p < s->sphere_count) {
        const Sphere *sp = &s->spheres[p];
        if (!sphere_intersect(r, sp->centre, sp->radius, hit->t, &t))
            return 0;
        *hit = (Hit){t, 0, 0, HIT_SPHERE, p, 0};
        return 1;
    }
    p -= s->sphere_count;
    if (p < s->tri_count) {
        if (!tri_intersect(r, &s->tris[p], hit->t, &t, &b1, &b2))
            return 0;
        *hit = (Hit){t, b1, b2, HIT_TRIANGLE, p, 0};
        return 1;
    }
    p -= s->tri_count;
    const Instance *in = &s->instances[p];
    Ray mr;
    const Ray *rr = in->identity ? r : (mr = instance_ray(in, r), &mr);
    ModelHit mh;
    if (!model_intersect(s->models[in->model], rr, hit->t, &mh))
        return 0;
    *hit = (Hit){mh.t, mh.b1, mh.b2, HIT_INSTANCE, p, mh.tri};
    return 1;
}

static int leaf_occluded(const Scene *s, uint32_t p, const Ray *r, real tmax)
{
    real t, b1, b2;
    if (p < s->sphere_count)
        return sphere_intersect(r, s->spheres[p].centre, s->spheres[p].radius, tmax, &t);
    p -= s->sphere_count;
    if (p < s->tri_count)
        return tri_intersect(r, &s->tris[p], tmax, &t, &b1, &b2);
    p -= s->tri_count;
    const Instance *in = &s->instances[p];
    Ray mr;
    const Ray *rr = in->identity ? r : (mr = instance_ray(in, r), &mr);
    return model_occluded(s->models[in->model], rr, tmax);
}

typedef struct {
    const Scene *s;
    Hit *hit;
} ClosestCtx;

static inline __attribute__((always_inline)) int top_leaf_closest(void *vctx, uint32_t first, uint32_t count,
                                                                  const Ray *r, real *tmax)
{
    ClosestCtx *c = vctx;
    int found = 0;
    for (uint32_t i = 0; i < count; i++)
        found |= leaf_closest(c->s, c->s->top.prims[first + i], r, c->hit);
    *tmax = c->hit->t;
    return found;
}

static inline __attribute__((always_inline)) int top_leaf_any(const void *vctx, uint32_t first, uint32_t count,
                                                              const Ray *r, real tmax)
{
    const Scene *s = vctx;
    for (uint32_t i = 0; i < count; i++)
        if (leaf_occluded(s, s->top.prims[first + i], r, tmax))
            return 1;
    return 0;
}

int trace_closest(const Scene *s, const Ray *r, Hit *hit)
{
    hit->t = r->tmax;
    hit->kind = HIT_NONE;
    if (scene_uses(s, FEAT_PLANES))
        for (uint32_t i = 0; i < s->plane_count; i++) {
            real t;
            if (plane_intersect(r, s->planes[i].point, s->planes[i].unit, hit->t, &t))
                *hit = (Hit){t, 0, 0, HIT_PLANE, i, 0};
        }
    ClosestCtx c = {s, hit};
    real tmax = hit->t;
    bvh_closest(&s->top, r, &tmax, top_leaf_closest, &c);
    return hit->kind != HIT_NONE;
}

int trace_occluded(const Scene *s, const Ray *r, real tmax)
{
    if (scene_uses(s, FEAT_PLANES))
        for (uint32_t i = 0; i < s->plane_count; i++) {
            real t;
            if (plane_intersect(r, s->planes[i].point, s->planes[i].unit, tmax, &t))
                return 1;
        }
    return bvh_any(&s->top, r, tmax, top_leaf_any, s);
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

static const Material fallback_material = {{{R(0.8), R(0.8), R(0.8)}}, {{0, 0, 0}}, R(1), -1};

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

void trace_surface(const Scene *s, const Ray *r, const Hit *h, Surface *out)
{
    memset(out, 0, sizeof *out);
    out->mat = &fallback_material;
    /* a smooth triangle's corners and vertex normals, for the terminator
     * point (model space for an instance) */
    vec3 tv[3], tn[3], pm = v3_splat(0);
    const Instance *inst = NULL;
    switch (h->kind) {
    case HIT_SPHERE: {
        const Sphere *sp = &s->spheres[h->index];
        vec3 p = ray_at(r, h->t);
        out->ng = v3_norm(v3_sub(p, sp->centre));
        /* re-project onto the surface: removes the error of o + t*d */
        out->p = v3_madd(sp->centre, out->ng, sp->radius);
        /* r * n carries the normalisation's error; adding the centre rounds once more */
        out->err = real_gamma(6) * sp->radius + real_gamma(2) * real_max(v3_max_comp(v3_abs(sp->centre)), v3_max_comp(v3_abs(out->p)));
        out->ns = out->ng;
        if (scene_uses(s, FEAT_TEXTURES)) {
            /* spherical mapping: u the longitude from +z towards +x, v the
             * latitude from the bottom pole (0) to the top (1) */
            vec3 n = out->ng;
            out->u = R(0.5) + atan2(n.x, n.z) / (R(2) * REAL_PI);
            out->v = R(0.5) + asin(real_clamp(n.y, R(-1), R(1))) / REAL_PI;
            out->has_uv = 1;
        }
        out->mat = &s->materials[sp->material];
        out->object = h->index;
        break;
    }
    case HIT_PLANE: {
        const Plane *pl = &s->planes[h->index];
        vec3 p = ray_at(r, h->t);
        /* project onto the plane for the same reason */
        out->p = v3_madd(p, pl->unit, v3_dot(v3_sub(pl->point, p), pl->unit));
        out->err = real_gamma(4) * real_max(v3_max_comp(v3_abs(out->p)), v3_max_comp(v3_abs(pl->point)));
        out->ng = out->ns = pl->unit;
        if (scene_uses(s, FEAT_TEXTURES)) {
            vec3 d = v3_sub(out->p, pl->point);
            out->u = v3_dot(d, pl->tu);
            out->v = v3_dot(d, pl->tv);
            out->has_uv = 1;
        }
        out->mat = &s->materials[pl->material];
        out->object = s->sphere_count + h->index;
        break;
    }
    case HIT_TRIANGLE: {
        const Tri *t = &s->tris[h->index];
        const TriAttr *a = &s->tri_attrs[h->index];
        vec3 v0 = tri_vertex(t, 0), v1 = tri_vertex(t, 1), v2 = tri_vertex(t, 2);
        out->p = trace_triangle_point(v0, v1, v2, h->b1, h->b2, &out->err);
        out->ng = v3_norm(v3_cross(v3_sub(v1, v0), v3_sub(v2, v0)));
        out->ns = out->ng;
        if (scene_uses(s, FEAT_SMOOTH) && a->smooth) {
            out->ns = v3_norm(bary(a->n[0], a->n[1], a->n[2], h->b1, h->b2));
            out->smooth = 1;
            tv[0] = v0, tv[1] = v1, tv[2] = v2;
            memcpy(tn, a->n, sizeof tn);
        }
        if (scene_uses(s, FEAT_TEXTURES) && a->textured) {
            out->u = (R(1) - h->b1 - h->b2) * a->uv[0] + h->b1 * a->uv[2] + h->b2 * a->uv[4];
            out->v = (R(1) - h->b1 - h->b2) * a->uv[1] + h->b1 * a->uv[3] + h->b2 * a->uv[5];
            out->has_uv = 1;
        }
        out->mat = &s->materials[a->material];
        /* scene triangles of one material form one surface (a quad is two triangles) */
        out->object = s->sphere_count + s->plane_count + a->material;
        break;
    }
    case HIT_INSTANCE: {
        const Instance *in = &s->instances[h->index];
        const Model *m = s->models[in->model];
        const Tri *t = &m->tris[h->sub];
        vec3 v0 = tri_vertex(t, 0), v1 = tri_vertex(t, 1), v2 = tri_vertex(t, 2);
        pm = bary(v0, v1, v2, h->b1, h->b2);
        out->p = v3_add(v3_scale(m3_apply(&in->rot, pm), in->scale), in->translate);
        /* the model-space point's error carried through rotation and scale, plus
         * the rounding of adding the translation (and of subtracting it again
         * when a new ray goes back into model space) */
        real vmax = v3_max_comp(v3_max(v3_abs(v0), v3_max(v3_abs(v1), v3_abs(v2))));
        out->err = real_gamma(10) * R(3) * in->scale * vmax +
                   real_gamma(2) * real_max(v3_max_comp(v3_abs(in->translate)), v3_max_comp(v3_abs(out->p)));
        /* uniform scale: normals transform by the rotation alone */
        out->ng = v3_norm(m3_apply(&in->rot, v3_cross(v3_sub(v1, v0), v3_sub(v2, v0))));
        if (scene_uses(s, FEAT_SMOOTH) && m->normals) {
            const vec3 *n = &m->normals[3 * h->sub];
            out->ns = v3_norm(m3_apply(&in->rot, bary(n[0], n[1], n[2], h->b1, h->b2)));
            out->smooth = 1;
            tv[0] = v0, tv[1] = v1, tv[2] = v2;
            memcpy(tn, n, sizeof tn);
            inst = in;
        } else {
            out->ns = out->ng;
        }
        if (scene_uses(s, FEAT_TEXTURES) && m->uvs) {
            const real *uv = &m->uvs[6 * h->sub];
            out->u = (R(1) - h->b1 - h->b2) * uv[0] + h->b1 * uv[2] + h->b2 * uv[4];
            out->v = (R(1) - h->b1 - h->b2) * uv[1] + h->b1 * uv[3] + h->b2 * uv[5];
            out->has_uv = 1;
        }
        if (in->material >= 0)
            out->mat = &s->materials[in->material];
        else if (m->mat_ids)
            out->mat = &m->materials[m->mat_ids[h->sub]];
        else if (s->material_count)
            out->mat = &s->materials[0];
        out->object = s->sphere_count + s->plane_count + s->material_count + h->index;
        break;
    }
    default:
        break;
    }
    /* face the viewer: all surfaces are two-sided */
    if (v3_dot(out->ng, r->dir) > R(0))
        out->ng = v3_neg(out->ng);
    int flip = v3_dot(out->ns, out->ng) < R(0);
    if (flip)
        out->ns = v3_neg(out->ns);
    out->ps = out->p;
    out->ps_err = out->err;
    if (!out->smooth)
        return;
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
    out->ps = v3_add(v3_scale(m3_apply(&inst->rot, lifted), inst->scale), inst->translate);
    out->ps_err = out->err + e * inst->scale * (R(1) + real_gamma(8)) +
                  real_gamma(10) * R(3) * inst->scale * v3_max_comp(v3_abs(lifted)) +
                  real_gamma(2) * v3_max_comp(v3_abs(out->ps));
}

vec3 trace_offset_origin(vec3 p, vec3 n, real err)
{
    /* distance along n that covers the error box of p: |n| . err (PBRT 3.9.5) */
    real d = err * (fabs(n.x) + fabs(n.y) + fabs(n.z));
    vec3 o = v3_madd(p, n, d);
    for (int a = 0; a < 3; a++) {
        if (n.e[a] > R(0))
            o.e[a] = nextafter(o.e[a], REAL_INF);
        else if (n.e[a] < R(0))
            o.e[a] = nextafter(o.e[a], -REAL_INF);
    }
    return o;
}
