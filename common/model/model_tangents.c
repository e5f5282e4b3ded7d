/* model_tangents.c - smooth tangents for a model's normal maps.
 *
 * A normal map is baked in the tangent frame of the surface it was made
 * for: nearly always the frames MikkTSpace gives (Blender, Substance,
 * xNormal; glTF's default), which are per vertex, smooth across the
 * triangles that share a vertex.  A frame made per triangle (its own
 * dp/du) turns from one triangle to the next on a curved surface, and the
 * map's tilts, read in it, break at every edge: a low-poly model shows
 * its triangles through the map made to hide them.
 *
 * So, as MikkTSpace does: each triangle's dp/du, made perpendicular to a
 * corner's vertex normal and weighted by the corner's angle, summed over
 * the corners that are one vertex (the same position, normal and texture
 * coordinates, and the same orientation of the texture on the surface:
 * a mirrored half of a model keeps its own frames), normalised.  Not
 * MikkTSpace bit for bit (it also splits a vertex whose triangles' frames
 * part by more than a threshold, and weighs the lengths apart), but the
 * same frames on a smooth, regularly unwrapped surface.
 *
 * Made when a scene is prepared (model_prepare_simd), from what the model
 * holds, in its triangle order with float arithmetic in a fixed order and
 * no libm call but sqrt: the same frames on every machine of a farm, so
 * nothing travels on the wire or in a .tmd. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/model.h"

/* Whether some material of the model reads a normal map through the
 * frame (a height map takes the triangle's own derivatives: their lengths
 * are its slopes' scale). */
static int model_wants_tangents(const Model *m)
{
    if (!m->normals || !m->uvs || !m->textures)
        return 0;
    for (uint32_t i = 0; i < m->material_count; i++)
        if (material_bumps(&m->materials[i]) && !material_heights(&m->materials[i]))
            return 1;
    return 0;
}

/* acos for the corners' weights, from sqrt and a polynomial (Abramowitz
 * and Stegun 4.4.45, within 7e-5 radians): libm's may differ in its last
 * bit between machines, and a weight needs no more. */
static real acos_weight(real c)
{
    const real x = fabs(c);
    const real a =
        (real)sqrt(R(1) - x) * (R(1.5707288) + x * (R(-0.2121144) + x * (R(0.0742610) + x * R(-0.0187293))));
    return c < R(0) ? R(3.14159265358979) - a : a;
}

/* A corner's key: its position, normal and texture coordinates (-0 read
 * as 0) and the texture's orientation on the triangle. */
typedef struct {
    real f[8];
    int side;
} Corner;

static Corner corner_of(const Model *m, uint32_t tri, int k, int side)
{
    Corner c;
    memset(&c, 0, sizeof c); /* the padding too: keys are compared as bytes */
    const vec3 p = tri_vertex(&m->tris[tri], k), n = m->normals[3 * tri + (uint32_t)k];
    const real *uv = &m->uvs[6 * tri + 2 * (uint32_t)k];
    const real f[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv[0], uv[1]};
    for (int i = 0; i < 8; i++)
        c.f[i] = f[i] + R(0); /* -0 + 0 is +0 */
    c.side = side;
    return c;
}

static uint64_t corner_hash(const Corner *c)
{
    uint32_t w[sizeof *c / 4];
    memcpy(w, c, sizeof w);
    uint64_t h = 0x9e3779b97f4a7c15u;
    for (size_t i = 0; i < sizeof w / 4; i++)
        h = (h ^ w[i]) * 0xff51afd7ed558ccdu;
    return h ^ h >> 32;
}

int model_tri_frame(const Model *m, uint32_t tri, vec3 *dpdu, vec3 *dpdv)
{
    const Tri *t = &m->tris[tri];
    const real *uv = &m->uvs[6 * tri];
    const vec3 e1 = v3_sub(tri_vertex(t, 1), tri_vertex(t, 0)), e2 = v3_sub(tri_vertex(t, 2), tri_vertex(t, 0));
    const real du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
    const real det = du1 * dv2 - du2 * dv1;
    if (!(fabs(det) > R(0)) || !isfinite(det))
        return 0;
    *dpdu = v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), R(1) / det);
    *dpdv = v3_scale(v3_sub(v3_scale(e2, du1), v3_scale(e1, du2)), R(1) / det);
    return det > R(0) ? 1 : 2;
}

/* Corner k's share: dp/du in the plane of its normal, unit, times the
 * corner's angle in that plane; zero where there is none. */
static vec3 corner_share(const Model *m, uint32_t tri, int k, vec3 dpdu)
{
    vec3 n = m->normals[3 * tri + (uint32_t)k];
    const real nl = v3_len(n);
    if (!(nl > R(0)) || !isfinite(nl))
        return v3_splat(R(0));
    n = v3_scale(n, R(1) / nl);
    const Tri *t = &m->tris[tri];
    const vec3 p = tri_vertex(t, k);
    vec3 a = v3_sub(tri_vertex(t, (k + 1) % 3), p), b = v3_sub(tri_vertex(t, (k + 2) % 3), p);
    a = v3_sub(a, v3_scale(n, v3_dot(n, a)));
    b = v3_sub(b, v3_scale(n, v3_dot(n, b)));
    vec3 s = v3_sub(dpdu, v3_scale(n, v3_dot(n, dpdu)));
    const real al = v3_len(a), bl = v3_len(b), sl = v3_len(s);
    if (!(al > R(0)) || !(bl > R(0)) || !(sl > R(0)) || !isfinite(al * bl * sl))
        return v3_splat(R(0));
    const real c = real_clamp(v3_dot(a, b) / (al * bl), R(-1), R(1));
    return v3_scale(s, acos_weight(c) / sl);
}

int model_tangents_build(Model *m, Err *err)
{
    const size_t corners = 3 * (size_t)m->tri_count;
    if (m->tangents || !model_wants_tangents(m) || corners == 0 || corners >= UINT32_MAX)
        return 0; /* (past 1.4 G triangles, each triangle's own frame) */
    size_t cap = 16;
    while (cap < 2 * corners)
        cap *= 2;
    uint32_t *slot = calloc(cap, sizeof *slot);       /* a vertex's first corner + 1, or 0 */
    uint32_t *group = malloc(corners * sizeof *group); /* each corner's vertex */
    vec3 *sum = calloc(corners, sizeof *sum);          /* by vertex */
    uint8_t *side = malloc(m->tri_count);
    vec3 *out = malloc(corners * sizeof *out);
    int rc = slot && group && sum && side && out ? 0 : err_set(err, "model: out of memory for its tangents");
    uint32_t vertices = 0;
    for (uint32_t i = 0; rc == 0 && i < m->tri_count; i++) {
        /* (a vertex's first corner lies in this triangle or an earlier
         * one, whose side is known by then) */
        vec3 dpdu = v3_splat(R(0)), dpdv;
        side[i] = (uint8_t)model_tri_frame(m, i, &dpdu, &dpdv);
        for (int k = 0; k < 3; k++) {
            const uint32_t c = 3 * i + (uint32_t)k;
            const Corner key = corner_of(m, i, k, side[i]);
            for (size_t h = (size_t)corner_hash(&key) & (cap - 1);; h = (h + 1) & (cap - 1)) {
                if (!slot[h]) {
                    slot[h] = c + 1;
                    group[c] = vertices++;
                    break;
                }
                const uint32_t first = slot[h] - 1;
                const Corner seen = corner_of(m, first / 3, (int)(first % 3), side[first / 3]);
                if (memcmp(&seen, &key, sizeof key) == 0) {
                    group[c] = group[first];
                    break;
                }
            }
            if (side[i])
                sum[group[c]] = v3_add(sum[group[c]], corner_share(m, i, k, dpdu));
        }
    }
    for (size_t c = 0; rc == 0 && c < corners; c++) {
        const vec3 s = sum[group[c]];
        const real l = v3_len(s);
        out[c] = l > R(0) && isfinite(l) ? v3_scale(s, R(1) / l) : v3_splat(R(0));
    }
    free(slot);
    free(group);
    free(sum);
    free(side);
    if (rc) {
        free(out);
        return rc;
    }
    m->tangents = out;
    return 0;
}
