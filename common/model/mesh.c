/* mesh.c - growable triangle lists. */
#include "model/mesh.h"

#include <stdlib.h>
#include <string.h>

#include "base/bigmem.h"

#define MESH_MAX_TRIS (1u << 26)

int mesh_init(Mesh *m, unsigned attrs, Err *err)
{
    memset(m, 0, sizeof *m);
    m->cap = 1024;
    m->pos = malloc(m->cap * 3 * sizeof *m->pos);
    m->nrm = attrs & MESH_NORMALS ? malloc(m->cap * 3 * sizeof *m->nrm) : NULL;
    m->uv = attrs & MESH_UVS ? malloc(m->cap * 6 * sizeof *m->uv) : NULL;
    m->mat = attrs & MESH_MATERIALS ? malloc(m->cap * sizeof *m->mat) : NULL;
    m->col = attrs & MESH_COLOURS ? malloc(m->cap * 3 * sizeof *m->col) : NULL;
    if (!m->pos || mesh_attrs(m) != attrs) {
        mesh_free(m);
        return err_set(err, "mesh: out of memory");
    }
    return 0;
}

void mesh_free(Mesh *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->mat);
    free(m->col);
    free(m->materials);
    for (uint32_t i = 0; i < m->texture_count; i++)
        texture_destroy(m->textures[i]);
    free(m->textures);
    memset(m, 0, sizeof *m);
}

/* *p replaced by a block of cap elements holding its first n */
static int move_to(void **p, size_t elem, uint32_t n, uint32_t cap)
{
    if (!*p)
        return 0;
    void *q = bigmem_alloc((size_t)cap * elem);
    if (!q)
        return -1;
    memcpy(q, *p, (size_t)n * elem);
    free(*p);
    *p = q;
    return 0;
}

int mesh_reserve(Mesh *m, uint32_t tris, Err *err)
{
    if (tris <= m->cap)
        return 0;
    if (tris > MESH_MAX_TRIS)
        return err_set(err, "mesh: more than %u triangles", MESH_MAX_TRIS);
    uint32_t n = m->tri_count;
    if (move_to((void **)&m->pos, 3 * sizeof *m->pos, n, tris) || move_to((void **)&m->nrm, 3 * sizeof *m->nrm, n, tris) ||
        move_to((void **)&m->uv, 6 * sizeof *m->uv, n, tris) || move_to((void **)&m->mat, sizeof *m->mat, n, tris) ||
        move_to((void **)&m->col, 3 * sizeof *m->col, n, tris))
        return err_set(err, "mesh: out of memory for %u triangles", tris);
    m->cap = tris;
    return 0;
}

int mesh_add_texture(Mesh *m, Texture *t, uint32_t *id, Err *err)
{
    if (m->texture_count >= 65536) {
        texture_destroy(t);
        return err_set(err, "mesh: more than 65536 textures");
    }
    Texture **p = realloc(m->textures, (m->texture_count + 1) * sizeof *p);
    if (!p) {
        texture_destroy(t);
        return err_set(err, "mesh: out of memory");
    }
    m->textures = p;
    *id = m->texture_count;
    p[m->texture_count++] = t;
    return 0;
}

static int grow(void **p, size_t elem, uint32_t cap)
{
    if (!*p)
        return 0;
    void *q = realloc(*p, elem * cap);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

unsigned mesh_attrs(const Mesh *m)
{
    return (m->nrm ? MESH_NORMALS : 0u) | (m->uv ? MESH_UVS : 0u) | (m->mat ? MESH_MATERIALS : 0u) |
           (m->col ? MESH_COLOURS : 0u);
}

int mesh_add(Mesh *m, const vec3 pos[3], const vec3 *nrm, const real *uv, const vec3 *col, uint32_t mat, Err *err)
{
    if (m->tri_count == m->cap) {
        if (m->cap >= MESH_MAX_TRIS)
            return err_set(err, "mesh: more than %u triangles", MESH_MAX_TRIS);
        uint32_t cap = m->cap * 2;
        if (grow((void **)&m->pos, 3 * sizeof *m->pos, cap) || grow((void **)&m->nrm, 3 * sizeof *m->nrm, cap) ||
            grow((void **)&m->uv, 6 * sizeof *m->uv, cap) || grow((void **)&m->mat, sizeof *m->mat, cap) ||
            grow((void **)&m->col, 3 * sizeof *m->col, cap))
            return err_set(err, "mesh: out of memory at %u triangles", m->tri_count);
        m->cap = cap;
    }
    uint32_t i = m->tri_count++;
    memcpy(&m->pos[3 * i], pos, 3 * sizeof *pos);
    if (m->nrm)
        memcpy(&m->nrm[3 * i], nrm, 3 * sizeof *nrm);
    if (m->uv)
        memcpy(&m->uv[6 * i], uv, 6 * sizeof *uv);
    if (m->mat)
        m->mat[i] = mat;
    if (m->col)
        memcpy(&m->col[3 * i], col, 3 * sizeof *col);
    return 0;
}

int mesh_add_material(Mesh *m, Material mat, Err *err)
{
    if (m->material_count >= 65536)
        return err_set(err, "mesh: more than 65536 materials");
    Material *p = realloc(m->materials, (m->material_count + 1) * sizeof *p);
    if (!p)
        return err_set(err, "mesh: out of memory");
    m->materials = p;
    p[m->material_count++] = mat;
    return 0;
}

int mesh_tri_is_degenerate(const vec3 p[3])
{
    vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
    /* the normal's largest component, not its squared length: that
     * overflowed (or underflowed) for a model measured in units 1e9 times
     * too small (or 1e-10 too large) for it, and dropped every triangle */
    real a = v3_max_comp(v3_abs(n));
    return !(a > R(0)) || !isfinite(a) || !v3_is_finite(p[0]) || !v3_is_finite(p[1]) || !v3_is_finite(p[2]);
}
