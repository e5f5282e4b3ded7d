/* smooth.c - see smooth.h.  The corners of the smoothed triangles are
 * gathered by vertex (corners_by_vertex: linear, where a hash of (vertex,
 * group) pairs would cost a probe a corner); a vertex whose
 * corners all share one group, nearly every vertex, sums them in one pass,
 * and one where groups meet sorts its corners by (group, corner) first. */
#include "model/smooth.h"

#include "base/dmath.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Triangle i's face normal, its length twice the area: the weight. */
static vec3 face_normal(const SmoothInput *in, uint32_t i)
{
    const int32_t *p = &in->p[(size_t)i * in->stride];
    const vec3 a = in->v[p[0]], b = in->v[p[1]], c = in->v[p[2]];
    return v3_cross(v3_sub(b, a), v3_sub(c, a));
}

static uint32_t group_of(const SmoothInput *in, uint32_t corner) { return in->group[(size_t)(corner / 3) * in->stride]; }

static int by_key(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The corners list[0..n) of one vertex, in triangle order: one normal per
 * group among them, appended to normals at *count.  keys: room for n. */
static void smooth_vertex(const SmoothInput *in, const uint32_t *list, uint32_t n, uint64_t *keys, uint32_t *corner,
                          vec3 *normals, uint32_t *count)
{
    const uint32_t g0 = group_of(in, list[0]);
    uint32_t same = 1;
    while (same < n && group_of(in, list[same]) == g0)
        same++;
    if (same == n) { /* one group: the sum in triangle order */
        vec3 s = v3_splat(0);
        for (uint32_t j = 0; j < n; j++) {
            s = v3_add(s, face_normal(in, list[j] / 3));
            corner[list[j]] = *count;
        }
        normals[(*count)++] = s;
        return;
    }
    for (uint32_t j = 0; j < n; j++) /* corner numbers below 2^32: (group, corner) orders by group, then triangle */
        keys[j] = (uint64_t)group_of(in, list[j]) << 32 | list[j];
    qsort(keys, n, sizeof *keys, by_key);
    for (uint32_t j = 0; j < n;) {
        const uint32_t g = (uint32_t)(keys[j] >> 32);
        vec3 s = v3_splat(0);
        for (; j < n && (uint32_t)(keys[j] >> 32) == g; j++) {
            const uint32_t c = (uint32_t)keys[j];
            s = v3_add(s, face_normal(in, c / 3));
            corner[c] = *count;
        }
        normals[(*count)++] = s;
    }
}

/* The corners of each vertex, in corner order (a count, a prefix sum and a
 * fill: linear): vertex[c] is corner c's vertex, below nv, or SMOOTH_FLAT
 * for a corner left out; vertex v's corners are list[start[v] ..
 * start[v + 1]) (start: nv + 1 entries).  Returns the most at one vertex. */
static uint32_t corners_by_vertex(const uint32_t *vertex, size_t n, size_t nv, uint32_t *start, uint32_t *list)
{
    memset(start, 0, (nv + 1) * sizeof *start);
    for (size_t c = 0; c < n; c++)
        if (vertex[c] != SMOOTH_FLAT)
            start[vertex[c] + 1]++;
    uint32_t most = 0;
    for (size_t v = 0; v < nv; v++) {
        most = start[v + 1] > most ? start[v + 1] : most;
        start[v + 1] += start[v];
    }
    for (size_t c = 0; c < n; c++) /* each start[v] moves on to its run's end, the next run's start */
        if (vertex[c] != SMOOTH_FLAT)
            list[start[vertex[c]]++] = (uint32_t)c;
    for (size_t v = nv; v > 0; v--)
        start[v] = start[v - 1];
    start[0] = 0;
    return most;
}

int smooth_normals(const SmoothInput *in, uint32_t **corner_out, vec3 **normals_out, Err *err)
{
    const size_t corners = (size_t)in->ntri * 3;
    uint32_t *start = malloc(((size_t)in->nv + 1) * sizeof *start);
    uint32_t *list = malloc((corners ? corners : 1) * sizeof *list);
    uint32_t *corner = malloc((corners ? corners : 1) * sizeof *corner);
    uint64_t *keys = NULL;
    vec3 *normals = NULL;
    if (!start || !list || !corner)
        goto oom;
    /* corner[] holds each corner's vertex for the gathering (SMOOTH_FLAT:
     * a flat triangle's), then its normal's index */
    for (uint32_t i = 0; i < in->ntri; i++)
        for (int k = 0; k < 3; k++)
            corner[3 * (size_t)i + (size_t)k] =
                smooth_tri(in, i) ? (uint32_t)in->p[(size_t)i * in->stride + (size_t)k] : SMOOTH_FLAT;
    const uint32_t most = corners_by_vertex(corner, corners, in->nv, start, list), smoothed = start[in->nv];
    keys = malloc((most ? most : 1) * sizeof *keys);
    normals = malloc((smoothed ? smoothed : 1) * sizeof *normals); /* at most one a corner */
    if (!keys || !normals)
        goto oom;
    uint32_t count = 0;
    for (uint32_t p = 0; p < in->nv; p++)
        if (start[p + 1] > start[p])
            smooth_vertex(in, &list[start[p]], start[p + 1] - start[p], keys, corner, normals, &count);
    free(start);
    free(list);
    free(keys);
    *corner_out = corner;
    *normals_out = normals;
    return 0;
oom:
    free(start);
    free(list);
    free(corner);
    free(keys);
    free(normals);
    return err_set(err, "out of memory for smooth normals");
}

/* A position's hash, -0 read as +0 (the same point). */
static uint64_t position_hash(vec3 p)
{
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; k++) {
        const real v = p.e[k] + R(0);
        uint64_t bits = 0;
        memcpy(&bits, &v, sizeof v);
        h = (h ^ bits) * 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

/* Each corner's vertex: the first corner at its position (open addressing). */
static int weld(const Mesh *m, uint32_t *vertex)
{
    const size_t n = (size_t)m->tri_count * 3;
    size_t size = 16;
    while (size < 2 * n)
        size *= 2;
    uint32_t *slot = malloc(size * sizeof *slot);
    if (!slot)
        return -1;
    memset(slot, 0xff, size * sizeof *slot);
    for (size_t c = 0; c < n; c++) {
        size_t at = (size_t)position_hash(m->pos[c]) & (size - 1);
        while (slot[at] != UINT32_MAX && !v3_same(m->pos[slot[at]], m->pos[c]))
            at = (at + 1) & (size - 1);
        if (slot[at] == UINT32_MAX)
            slot[at] = (uint32_t)c;
        vertex[c] = slot[at];
    }
    free(slot);
    return 0;
}

static vec3 mesh_face_normal(const Mesh *m, uint32_t t)
{
    const vec3 *p = &m->pos[3 * (size_t)t];
    return v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
}

/* The corners list[0..k) at one vertex: each one's normal, its faces'
 * normals (and lengths) taken once. */
static void crease_vertex(const Mesh *m, const uint32_t *list, uint32_t k, real cos_crease, vec3 *nrm)
{
    if (k > SMOOTH_CREASE_MAX) { /* all of them together, the crease unchecked: linear */
        vec3 s = v3_splat(0);
        for (uint32_t b = 0; b < k; b++)
            s = v3_add(s, mesh_face_normal(m, list[b] / 3));
        for (uint32_t a = 0; a < k; a++)
            nrm[list[a]] = s;
        return;
    }
    vec3 f[SMOOTH_CREASE_MAX];
    real len[SMOOTH_CREASE_MAX];
    for (uint32_t b = 0; b < k; b++)
        f[b] = mesh_face_normal(m, list[b] / 3), len[b] = v3_len(f[b]);
    for (uint32_t a = 0; a < k; a++) {
        vec3 s = v3_splat(0);
        for (uint32_t b = 0; b < k; b++)
            if (b == a || v3_dot(f[a], f[b]) >= cos_crease * len[a] * len[b])
                s = v3_add(s, f[b]);
        nrm[list[a]] = s;
    }
}

int mesh_smooth(Mesh *m, real crease_deg, Err *err)
{
    const size_t n = (size_t)m->tri_count * 3;
    uint32_t *vertex = malloc((n ? n : 1) * sizeof *vertex), *start = malloc((n + 1) * sizeof *start);
    uint32_t *list = malloc((n ? n : 1) * sizeof *list);
    vec3 *nrm = malloc(((size_t)m->cap ? (size_t)m->cap : 1) * 3 * sizeof *nrm);
    if (!vertex || !start || !list || !nrm || weld(m, vertex)) {
        free(vertex), free(start), free(list), free(nrm);
        return err_set(err, "out of memory for smooth normals");
    }
    corners_by_vertex(vertex, n, n, start, list); /* a vertex is named by its first corner */
    const real cos_crease = (real)dmath_cos((double)crease_deg * 3.14159265358979323846 / 180.0);
    for (size_t v = 0; v < n; v++)
        if (start[v + 1] > start[v])
            crease_vertex(m, &list[start[v]], start[v + 1] - start[v], cos_crease, nrm);
    for (size_t c = 0; c < n; c++) {
        nrm[c] = v3_norm_any(nrm[c]);
        if (!(v3_dot(nrm[c], nrm[c]) > R(0.5)))
            nrm[c] = v3_norm_any(mesh_face_normal(m, (uint32_t)(c / 3))); /* a cancelling fan: the face's own */
    }
    free(vertex), free(start), free(list);
    free(m->nrm);
    m->nrm = nrm;
    return 0;
}
