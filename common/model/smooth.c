/* smooth.c - see smooth.h.  The corners of the smoothed triangles are
 * gathered by vertex (counts, then a prefix sum: linear, where a hash of
 * (vertex, group) pairs would cost a probe a corner); a vertex whose
 * corners all share one group, nearly every vertex, sums them in one pass,
 * and one where groups meet sorts its corners by (group, corner) first. */
#include "model/smooth.h"

#include <stdlib.h>

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

int smooth_normals(const SmoothInput *in, uint32_t **corner_out, vec3 **normals_out, Err *err)
{
    const size_t corners = (size_t)in->ntri * 3;
    uint32_t *start = calloc((size_t)in->nv + 1, sizeof *start);
    uint32_t *list = malloc((corners ? corners : 1) * sizeof *list);
    uint32_t *corner = malloc((corners ? corners : 1) * sizeof *corner);
    uint64_t *keys = NULL;
    vec3 *normals = NULL;
    if (!start || !list || !corner)
        goto oom;
    /* corners a vertex, then where each vertex's run starts */
    uint32_t most = 0, smoothed = 0;
    for (uint32_t i = 0; i < in->ntri; i++)
        if (smooth_tri(in, i))
            for (int k = 0; k < 3; k++)
                start[in->p[(size_t)i * in->stride + k] + 1]++;
    for (uint32_t p = 0; p < in->nv; p++) {
        most = start[p + 1] > most ? start[p + 1] : most;
        start[p + 1] += start[p];
    }
    smoothed = start[in->nv];
    keys = malloc((most ? most : 1) * sizeof *keys);
    normals = malloc((smoothed ? smoothed : 1) * sizeof *normals); /* at most one a corner */
    if (!keys || !normals)
        goto oom;
    uint32_t *fill = malloc(((size_t)in->nv + 1) * sizeof *fill);
    if (!fill)
        goto oom;
    for (uint32_t p = 0; p <= in->nv; p++)
        fill[p] = start[p];
    for (uint32_t i = 0; i < in->ntri; i++) {
        for (int k = 0; k < 3; k++) {
            const uint32_t c = 3 * i + (uint32_t)k;
            corner[c] = SMOOTH_FLAT;
            if (smooth_tri(in, i))
                list[fill[in->p[(size_t)i * in->stride + k]]++] = c;
        }
    }
    free(fill);
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
