/* emitters.c - see emitters.h. */
#include "scene/emitters.h"

#include "base/dmath.h"

#include <stdlib.h>

#include "base/array.h"
#include "base/sample.h"

/* The material of an emitter candidate (NULL: none). */
static const Material *candidate_material(const World *w, HitKind kind, uint32_t index, uint32_t sub)
{
    if (kind == HIT_SPHERE)
        return &w->materials[w->spheres[index].material];
    if (kind == HIT_TRIANGLE)
        return &w->materials[w->tri_attrs[index].material];
    return trace_instance_material(w, index, sub);
}

/* A triangle's corners in the world: a scene triangle's, or a model's
 * moved as its instance says (instance_world_box's map). */
static void corners(const World *w, HitKind kind, uint32_t index, uint32_t sub, vec3 c[3])
{
    if (kind == HIT_TRIANGLE) {
        for (int k = 0; k < 3; k++)
            c[k] = tri_vertex(&w->tris[index], k);
        return;
    }
    const WorldInstance *in = &w->instances[index];
    const Tri *t = &w->models[in->model]->tris[sub];
    for (int k = 0; k < 3; k++)
        c[k] = world_instance_point(in, tri_vertex(t, k));
}

static real sphere_area(const Sphere *sp) { return R(4) * REAL_PI * sp->radius * sp->radius; }

/* A triangle's area, from its corners' cross product. */
static real triangle_area(vec3 cr) { return R(0.5) * v3_len(cr); }
static vec3 corners_cross(const vec3 c[3]) { return v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0])); }

static real area_of(const World *w, HitKind kind, uint32_t index, uint32_t sub)
{
    if (kind == HIT_SPHERE)
        return sphere_area(&w->spheres[index]);
    vec3 c[3];
    corners(w, kind, index, sub, c);
    return triangle_area(corners_cross(c));
}

/* What picking an emitter weighs: its area times its mean emission. */
static real power_of(real area, const Material *m) { return area * (m->ke.x + m->ke.y + m->ke.z) / R(3); }

/* The weights of a triangle's corners at the point (u, v) names, uniform
 * over its area: where sample_triangle samples and in_hole looks. */
static inline void triangle_weights(real u, real v, real b[3])
{
    const real su = sqrt(u);
    b[0] = R(1) - su, b[1] = v * su, b[2] = R(1) - b[0] - b[1];
}

/* Whether emitter candidate's emission is a texture's (glow_at reads it). */
static int glow_mapped(const World *w, HitKind kind, uint32_t index, const Material *m)
{
    return kind == HIT_INSTANCE && material_emit_mapped(m) && w->instances[index].material < 0 &&
           w->models[w->instances[index].model]->uvs;
}

/* The box of a model's triangle's texture coordinates. */
static void uv_box(const Model *mo, uint32_t sub, real lo[2], real hi[2])
{
    lo[0] = lo[1] = REAL_MAX, hi[0] = hi[1] = -REAL_MAX;
    for (int k = 0; k < 3; k++) {
        real uv[2];
        model_uv(mo, sub, k == 1 ? R(1) : R(0), k == 2 ? R(1) : R(0), &uv[0], &uv[1]);
        for (int a = 0; a < 2; a++)
            lo[a] = real_min(lo[a], uv[a]), hi[a] = real_max(hi[a], uv[a]);
    }
}

#define GLOW_SHARE_MIN R(1.0 / 64)
#define GLOW_CELLS 8 /* a side of the grid of cells over a textured emitter triangle */
#define GLOW_CELL_COUNT (GLOW_CELLS * GLOW_CELLS)
#define GLOW_CELL_EMITTERS 16384 /* textured triangles given cells, at most (the rest: uniform) */

/* An emission texture's (r + g + b) / 3 over footprint fp at (u, v),
 * trilinear whatever the view's filter (a client that builds the world
 * later must weigh it alike), at least GLOW_SHARE_MIN (NaN: that). */
static real glow_read(const Texture *t, real u, real v, const TexFootprint *fp)
{
    const vec3 c = texture_sample(t, u, v, fp, FILTER_TRILINEAR);
    const real g = (c.x + c.y + c.z) / R(3);
    return g > GLOW_SHARE_MIN ? g : GLOW_SHARE_MIN;
}

/* How bright a model's triangle's emission texture is, for its pick: the
 * mean (r + g + b) / 3 of the texture over the box of the triangle's
 * texture coordinates (one trilinear read, the mip-map level as wide as
 * the box, at its centre, whatever the view's filter, so that a
 * client that builds the world later weighs it alike), and no less than
 * GLOW_SHARE_MIN, so that a triangle with light in a corner the mean
 * misses is still picked now and then: any weights that leave none that
 * glows out keep next-event estimation unbiased, and these put its samples
 * on the bright triangles of a finely made emitter (a sign's letters, a
 * facade's lit windows), not its black ones.  1 without a texture. */
static real glow_share(const World *w, HitKind kind, uint32_t index, uint32_t sub, const Material *m)
{
    if (!glow_mapped(w, kind, index, m))
        return R(1);
    const Model *mo = w->models[w->instances[index].model];
    real lo[2], hi[2];
    uv_box(mo, sub, lo, hi);
    const TexFootprint fp = {.dudx = hi[0] - lo[0], .dvdx = 0, .dudy = 0, .dvdy = hi[1] - lo[1]};
    return glow_read(mo->textures[m->emit_map], R(0.5) * (lo[0] + hi[0]), R(0.5) * (lo[1] + hi[1]), &fp);
}

/* The cells of a textured emitter triangle: the unit square that
 * triangle_weights spreads evenly over it, cut into GLOW_CELLS x GLOW_CELLS
 * cells of equal area on the triangle, each as likely as its texture's
 * mean there (read at its centre, a cell's share of the triangle's box
 * wide), at least GLOW_SHARE_MIN: into cdf, their running sum over the
 * whole (cell k = i x GLOW_CELLS + j: u in [i, i + 1) / GLOW_CELLS, v in
 * [j, j + 1) / GLOW_CELLS). */
static void glow_cells(const World *w, const Emitter *e, real *cdf)
{
    const WorldInstance *in = &w->instances[e->index];
    const Model *mo = w->models[in->model];
    const Material *m = candidate_material(w, e->kind, e->index, e->sub);
    real lo[2], hi[2];
    uv_box(mo, e->sub, lo, hi);
    const TexFootprint fp = {.dudx = (hi[0] - lo[0]) / GLOW_CELLS, .dvdx = 0, .dudy = 0,
                             .dvdy = (hi[1] - lo[1]) / GLOW_CELLS};
    real sum = 0;
    for (int k = 0; k < GLOW_CELL_COUNT; k++) {
        real b[3], tu, tv;
        triangle_weights(((real)(k / GLOW_CELLS) + R(0.5)) / GLOW_CELLS, ((real)(k % GLOW_CELLS) + R(0.5)) / GLOW_CELLS, b);
        model_uv(mo, e->sub, b[1], b[2], &tu, &tv);
        sum += glow_read(mo->textures[m->emit_map], tu, tv, &fp);
        cdf[k] = sum;
    }
    for (int k = 0; k < GLOW_CELL_COUNT; k++)
        cdf[k] /= sum;
    cdf[GLOW_CELL_COUNT - 1] = R(1);
}

/* Cells for the first GLOW_CELL_EMITTERS textured emitters (World.emit_cells). */
static int glow_cells_build(World *w)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < w->emitter_count && n < GLOW_CELL_EMITTERS; i++) {
        const Emitter *e = &w->emitters[i];
        n += (uint32_t)glow_mapped(w, e->kind, e->index, candidate_material(w, e->kind, e->index, e->sub));
    }
    if (!n)
        return 0;
    w->parts->emit_cells = malloc((size_t)n * GLOW_CELL_COUNT * sizeof *w->emit_cells);
    if (!w->parts->emit_cells)
        return -1;
    w->emit_cells = w->parts->emit_cells;
    uint32_t k = 0;
    for (uint32_t i = 0; i < w->emitter_count && k < n; i++) {
        Emitter *e = &w->emitters[i];
        if (!glow_mapped(w, e->kind, e->index, candidate_material(w, e->kind, e->index, e->sub)))
            continue;
        glow_cells(w, e, &w->emit_cells[(size_t)k * GLOW_CELL_COUNT]);
        e->cells = k++;
    }
    return 0;
}

static int push(World *w, uint32_t *cap, HitKind kind, uint32_t index, uint32_t sub, real *total)
{
    const Material *m = candidate_material(w, kind, index, sub);
    if (!m || !material_emits(m))
        return 0;
    const real share = glow_share(w, kind, index, sub, m), pw = power_of(area_of(w, kind, index, sub), m) * share;
    if (!(pw > R(0)) || !isfinite(pw))
        return 0;
    if (array_reserve((void **)&w->parts->emitters, cap, w->emitter_count + 1, sizeof *w->emitters, UINT32_MAX / 64))
        return -1;
    w->emitters = w->parts->emitters;
    *total += pw;
    w->emitters[w->emitter_count++] = (Emitter){kind, index, sub, *total, share, EMITTER_NO_CELLS};
    return 0;
}

int emitters_build(World *w, Err *err)
{
    w->emit_cells = NULL;
    w->emitters = NULL;
    w->emitter_count = 0;
    w->emit_power = 0;
    if (!(w->item_features & FEAT_EMIT))
        return 0;
    uint32_t cap = 0;
    real total = 0;
    int bad = 0;
    for (uint32_t i = 0; i < w->sphere_count && !bad; i++)
        bad = !trace_any_lamp(w, &(Hit){.kind = HIT_SPHERE, .index = i}) && push(w, &cap, HIT_SPHERE, i, 0, &total);
    for (uint32_t i = 0; i < w->tri_count && !bad; i++)
        bad = !trace_any_lamp(w, &(Hit){.kind = HIT_TRIANGLE, .index = i}) && push(w, &cap, HIT_TRIANGLE, i, 0, &total);
    for (uint32_t i = 0; i < w->instance_count && !bad; i++)
        for (uint32_t k = 0; k < w->models[w->instances[i].model]->tri_count && !bad; k++)
            bad = push(w, &cap, HIT_INSTANCE, i, k, &total);
    if (bad || glow_cells_build(w))
        return err_set(err, "scene: out of memory for the emitters");
    /* cumulative power to probability; the last is exactly 1 */
    for (uint32_t i = 0; i < w->emitter_count; i++)
        w->emitters[i].cdf /= total;
    if (w->emitter_count)
        w->emitters[w->emitter_count - 1].cdf = R(1);
    w->emit_power = total;
    return 0;
}

/* The probability of picking an emitter of this area and material. */
static real pick_probability(const World *w, real area, const Material *m) { return power_of(area, m) / w->emit_power; }

/* Sphere sp seen from p: 1 - the cosine of the cone it fills (0: p is
 * inside or on it).  As sin^2 / (1 + cos), exact for small cones. */
static real cone_gap(const Sphere *sp, vec3 p)
{
    const vec3 to = v3_sub(sp->centre, p);
    const real d2 = v3_dot(to, to), r2 = sp->radius * sp->radius;
    if (!(d2 > r2))
        return 0;
    const real s2 = r2 / d2;
    return s2 / (R(1) + sqrt(R(1) - s2));
}

static int sample_ball(const Sphere *sp, vec3 p, real u, real v, EmitterSample *out)
{
    const real gap = cone_gap(sp, p), phi = R(2) * REAL_PI * v;
    vec3 q;
    if (gap > R(0)) { /* outside: uniform in the cone of directions it fills */
        const vec3 to = v3_sub(sp->centre, p);
        const real dc = v3_len(to), cos_t = R(1) - u * gap, sin_t = sqrt(real_max(R(0), R(1) - cos_t * cos_t));
        const vec3 axis = v3_scale(to, R(1) / dc);
        vec3 a, b;
        v3_frame(axis, &a, &b);
        real sphi, cphi;
        dmath_sincosr(phi, &sphi, &cphi);
        out->dir = v3_norm(v3_add(v3_scale(axis, cos_t), v3_add(v3_scale(a, sin_t * cphi), v3_scale(b, sin_t * sphi))));
        const real r2 = sp->radius * sp->radius;
        out->dist = dc * cos_t - sqrt(real_max(R(0), r2 - dc * dc * sin_t * sin_t));
        out->pdf = R(1) / (R(2) * REAL_PI * gap);
        return out->dist > R(0);
    }
    /* inside: uniformly over its area */
    const vec3 n = sample_sphere(u, v);
    q = v3_add(sp->centre, v3_scale(n, sp->radius));
    const vec3 to = v3_sub(q, p);
    const real d2 = v3_dot(to, to);
    if (!(d2 > R(0)))
        return 0;
    out->dist = sqrt(d2);
    out->dir = v3_scale(to, R(1) / out->dist);
    const real c = fabs(v3_dot(n, out->dir));
    if (!(c > R(0)))
        return 0;
    out->pdf = d2 / (c * sphere_area(sp));
    return 1;
}

/* Uniformly over triangle c's area (into *area, for its pick). */
static int sample_triangle(const vec3 c[3], vec3 p, real u, real v, EmitterSample *out, real *area_out)
{
    real b[3];
    triangle_weights(u, v, b);
    const vec3 q = v3_add(v3_add(v3_scale(c[0], b[0]), v3_scale(c[1], b[1])), v3_scale(c[2], b[2]));
    const vec3 cr = corners_cross(c);
    const real area = triangle_area(cr);
    *area_out = area;
    const vec3 to = v3_sub(q, p);
    const real d2 = v3_dot(to, to);
    if (!(d2 > R(0)) || !(area > R(0)))
        return 0;
    out->dist = sqrt(d2);
    out->dir = v3_scale(to, R(1) / out->dist);
    const real cl = fabs(v3_dot(cr, out->dir)) / (R(2) * area);
    if (!(cl > R(1e-9)))
        return 0;
    out->pdf = d2 / (cl * area);
    return 1;
}

/* Whether the point sample_triangle takes for (u, v) on a model's
 * emitting triangle lies in a hole of its cutout: no light comes from
 * there.  Sampling the whole triangle and counting a hole's points as
 * dark stays unbiased, and a path's own rays pass the holes. */
static int in_hole(const World *w, const Emitter *e, real u, real v)
{
    if (e->kind != HIT_INSTANCE)
        return 0;
    const Model *m = w->models[w->instances[e->index].model];
    if (!m->cutout)
        return 0;
    real b[3];
    triangle_weights(u, v, b);
    return model_hole(m, e->sub, b[1], b[2]);
}

/* What emitter e's point at (u, v) emits: its material's `emit`, times the
 * emission texture's colour there where a model's own material has one
 * (read at one point, as path.c reads it at a hit), times a see-through
 * blend's coverage there (trace_surface_blend: its see-through share
 * emits nothing). */
static vec3 glow_at(const World *w, const Emitter *e, const Material *m, real u, real v)
{
    if (e->kind != HIT_INSTANCE || !(material_emit_mapped(m) || material_blends(m)) ||
        w->instances[e->index].material >= 0)
        return m->ke;
    const Model *mo = w->models[w->instances[e->index].model];
    if (!mo->uvs)
        return m->ke;
    real b[3], tu, tv;
    triangle_weights(u, v, b);
    model_uv(mo, e->sub, b[1], b[2], &tu, &tv);
    vec3 ke = m->ke;
    if (material_emit_mapped(m))
        ke = v3_mul(ke, texture_sample(mo->textures[m->emit_map], tu, tv, NULL, w->view.settings.filter));
    if (material_blends(m))
        ke = v3_scale(ke, texture_coverage(mo->textures[m->mask], tu, tv));
    return ke;
}

/* The emitter entry of the model's triangle that h met: found by halving,
 * as the table lists a model's emitters by instance, then triangle (after
 * the spheres and the scene's triangles); NULL where it has none. */
static const Emitter *emitter_of(const World *w, const Hit *h)
{
    uint32_t lo = 0, hi = w->emitter_count;
    while (lo < hi) { /* the first instance emitter at or past (index, sub) */
        const uint32_t mid = lo + (hi - lo) / 2;
        const Emitter *e = &w->emitters[mid];
        const int before = e->kind != HIT_INSTANCE || e->index < h->index || (e->index == h->index && e->sub < h->sub);
        if (before)
            lo = mid + 1;
        else
            hi = mid;
    }
    const Emitter *e = lo < w->emitter_count ? &w->emitters[lo] : NULL;
    return e && e->kind == HIT_INSTANCE && e->index == h->index && e->sub == h->sub ? e : NULL;
}

/* A cell of a textured emitter's cdf (glow_cells) by u: the cell whose
 * running sum first passes it; (u, v) become the point of the square in
 * it that u's place in the cell's interval and v say.  Its density over
 * the square's (uniform: 1), which multiplies the point's density. */
static real cell_pick(const real *cdf, real *u, real *v)
{
    int k = 0;
    while (k < GLOW_CELL_COUNT - 1 && !(cdf[k] > *u))
        k++;
    const real before = k ? cdf[k - 1] : R(0), p = cdf[k] - before;
    const real in = real_min((*u - before) / p, R(1) - REAL_EPS);
    *u = ((real)(k / GLOW_CELLS) + in) / GLOW_CELLS;
    *v = ((real)(k % GLOW_CELLS) + *v) / GLOW_CELLS;
    return p * GLOW_CELL_COUNT;
}

/* The same density for the point of the triangle with barycentrics b1, b2
 * (of its corners 1 and 2): the square's point triangle_weights maps
 * there, u = (b1 + b2)^2, v = b1 / (b1 + b2), and its cell. */
static real cell_density(const real *cdf, real b1, real b2)
{
    const real su = b1 + b2, u = su * su, v = su > R(0) ? b1 / su : R(0);
    const int i = (int)real_min(real_max(u * GLOW_CELLS, R(0)), GLOW_CELLS - 1);
    const int j = (int)real_min(real_max(v * GLOW_CELLS, R(0)), GLOW_CELLS - 1);
    const int k = i * GLOW_CELLS + j;
    return (cdf[k] - (k ? cdf[k - 1] : R(0))) * GLOW_CELL_COUNT;
}

int emitters_sample(const World *w, vec3 p, real pick, real u, real v, EmitterSample *out)
{
    if (!w->emitter_count)
        return 0;
    uint32_t lo = 0, hi = w->emitter_count - 1; /* the first whose cdf exceeds pick */
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (w->emitters[mid].cdf > pick)
            hi = mid;
        else
            lo = mid + 1;
    }
    const Emitter *e = &w->emitters[lo];
    const Material *m = candidate_material(w, e->kind, e->index, e->sub);
    int ok;
    real area, cell = R(1);
    if (e->cells != EMITTER_NO_CELLS) /* a textured triangle: a cell by its brightness, the point in it */
        cell = cell_pick(&w->emit_cells[(size_t)e->cells * GLOW_CELL_COUNT], &u, &v);
    if (e->kind == HIT_SPHERE) {
        area = sphere_area(&w->spheres[e->index]);
        ok = sample_ball(&w->spheres[e->index], p, u, v, out);
    } else {
        vec3 c[3];
        corners(w, e->kind, e->index, e->sub, c);
        ok = sample_triangle(c, p, u, v, out, &area);
    }
    if (!ok || in_hole(w, e, u, v))
        return 0;
    out->radiance = glow_at(w, e, m, u, v);
    out->pdf *= pick_probability(w, area, m) * e->share * cell;
    return out->pdf > R(0) && isfinite(out->pdf);
}

real emitters_pdf(const World *w, vec3 p, const Ray *r, const Hit *h)
{
    if (!w->emitter_count || h->kind == HIT_PLANE || h->kind == HIT_NONE)
        return 0;
    const Material *m = candidate_material(w, h->kind, h->index, h->sub);
    if (!m || !material_emits(m))
        return 0;
    if (trace_any_lamp(w, h))
        return 0;
    if (h->kind == HIT_SPHERE) {
        const Sphere *sp = &w->spheres[h->index];
        const real pick = pick_probability(w, sphere_area(sp), m), gap = cone_gap(sp, p);
        if (gap > R(0))
            return pick / (R(2) * REAL_PI * gap);
        const vec3 q = v3_add(r->org, v3_scale(r->dir, h->t));
        const real c = fabs(v3_dot(v3_scale(v3_sub(q, sp->centre), R(1) / sp->radius), r->dir));
        return c > R(0) ? pick * h->t * h->t / (c * sphere_area(sp)) : 0;
    }
    vec3 c[3];
    corners(w, h->kind, h->index, h->sub, c);
    const vec3 cr = corners_cross(c);
    const real area = triangle_area(cr), cl = fabs(v3_dot(cr, r->dir)) / (R(2) * area);
    real share = R(1);
    if (glow_mapped(w, h->kind, h->index, m)) { /* its texture's share and, where it has them, its cell's */
        const Emitter *e = emitter_of(w, h);
        share = !e ? R(1)
                : e->cells == EMITTER_NO_CELLS
                    ? e->share
                    : e->share * cell_density(&w->emit_cells[(size_t)e->cells * GLOW_CELL_COUNT], h->b1, h->b2);
    }
    return cl > R(1e-9) ? pick_probability(w, area, m) * share * h->t * h->t / (cl * area) : 0;
}
