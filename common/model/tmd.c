/* tmd.c - reading and writing .tmd files; the reader trusts nothing. */
#include "model/tmd.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include "base/cursor.h"
#include "base/fileio.h"

/* float32 on disk in every build; bounds are rounded outward so that a
 * double-precision tree stays conservative after the narrowing. */
static float f32_down(real x)
{
    float f = (float)x;
    return (real)f > x ? nextafterf(f, -INFINITY) : f;
}
static float f32_up(real x)
{
    float f = (float)x;
    return (real)f < x ? nextafterf(f, INFINITY) : f;
}

/* One number as float32, or as float64 when wide; dir rounds a narrowed
 * box bound outward (-1 down, +1 up, 0 nearest). */
static void put_real(Sink *s, real x, int wide, int dir)
{
    if (wide) {
        double d = (double)x;
        sink_put(s, &d, sizeof d);
    } else {
        sink_f32(s, dir < 0 ? f32_down(x) : dir > 0 ? f32_up(x) : (float)x);
    }
}

uint32_t tmd_checksum(const void *data, size_t len)
{
    /* CRC-32 (zlib's) of the bytes, the checksum field read as zero: every
     * error of one bit, and of a burst up to 32 bits, changes it */
    const uint8_t *p = data;
    const uint8_t zero[4] = {0, 0, 0, 0};
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32_z(crc, p, TMD_CHECKSUM_AT);
    crc = crc32_z(crc, zero, 4);
    crc = crc32_z(crc, p + TMD_CHECKSUM_AT + 4, len - TMD_CHECKSUM_AT - 4);
    return (uint32_t)crc;
}

int tmd_encode(const Model *m, int wide, void **data, size_t *len, Err *err)
{
    Sink s = {0};
    const int textured = m->mat_ids && m->texture_count > 0;
    uint32_t flags = (m->normals ? TMD_HAS_NORMALS : 0) | (m->uvs ? TMD_HAS_UVS : 0) |
                     (m->mat_ids ? TMD_HAS_MATERIALS : 0) | (wide ? TMD_WIDE : 0) | (textured ? TMD_HAS_TEXTURES : 0) |
                     (m->colours ? TMD_HAS_COLOURS : 0);
    char magic[8] = TMD_MAGIC;
    sink_put(&s, magic, 8);
    /* the file's length and checksum (offsets 48 and 52) are filled in last */
    uint32_t head[14] = {TMD_VERSION, TMD_BOM, TMD_HEADER_BYTES, flags,
                         (uint32_t)m->bvh.kind, m->bvh.node_count, m->tri_count, m->mat_ids ? m->material_count : 0,
                         m->bvh.depth, textured ? m->texture_count : 0, 0, 0, 0, 0};
    sink_put(&s, head, sizeof head);
    for (uint32_t i = 0; i < m->bvh.node_count; i++) {
        const BvhNode *n = &m->bvh.nodes[i];
        for (int a = 0; a < 3; a++)
            put_real(&s, n->bmin[a], wide, -1);
        sink_u32(&s, n->first);
        for (int a = 0; a < 3; a++)
            put_real(&s, n->bmax[a], wide, 1);
        sink_u32(&s, n->count);
    }
    for (uint32_t i = 0; i < m->tri_count; i++)
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                put_real(&s, m->tris[i].v[k][a], wide, 0);
    if (m->normals)
        for (uint32_t i = 0; i < 3 * m->tri_count; i++)
            for (int a = 0; a < 3; a++)
                put_real(&s, m->normals[i].e[a], wide, 0);
    if (m->uvs)
        for (uint32_t i = 0; i < 6 * m->tri_count; i++)
            put_real(&s, m->uvs[i], wide, 0);
    if (m->mat_ids) {
        /* each by the material's table: what the scene's wire carries */
        for (uint32_t i = 0; i < m->material_count; i++) {
            /* a texture that did not come along is none: no holes, tilt, glow or metal map */
            const Material mt = textured ? m->materials[i] : material_untextured(m->materials[i]);
            field_encode(&material_kind, &mt, &s);
        }
        sink_put(&s, m->mat_ids, m->tri_count * sizeof *m->mat_ids);
    }
    if (m->colours)
        for (uint32_t i = 0; i < 3 * m->tri_count; i++)
            for (int a = 0; a < 3; a++)
                put_real(&s, m->colours[i].e[a], wide, 0);
    for (uint32_t i = 0; textured && i < m->texture_count; i++)
        texture_encode(m->textures[i], &s);
    if (s.failed || s.len > TMD_MAX_FILE_BYTES) {
        sink_free(&s);
        return err_set(err, "tmd: out of memory encoding %u triangles, or more than %zu bytes", m->tri_count,
                       TMD_MAX_FILE_BYTES);
    }
    uint32_t total = (uint32_t)s.len, crc;
    memcpy(s.data + TMD_LENGTH_AT, &total, 4);
    crc = tmd_checksum(s.data, s.len);
    memcpy(s.data + TMD_CHECKSUM_AT, &crc, 4);
    *data = s.data;
    *len = s.len;
    return 0;
}

int tmd_write(const char *path, const Model *m, Err *err)
{
    void *data;
    size_t len;
    if (tmd_encode(m, 0, &data, &len, err))
        return err_prefix(err, "%s", path);
    int rc = file_write_bytes(path, data, len, err);
    free(data);
    return rc;
}

/* n numbers, float32 or (wide) float64; a float build narrows a wide
 * box bound outward (dir as in put_real) so that the tree stays conservative. */
static int read_reals(Cursor *c, int wide, int dir, real *dst, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        double d = 0;
        if (wide)
            cursor_get(c, &d, sizeof d);
        else
            d = cursor_f32(c);
        if (!isfinite(d))
            return -1;
        real r = (real)d;
        if (dir < 0 && (double)r > d)
            r = nextafter(r, -REAL_INF);
        else if (dir > 0 && (double)r < d)
            r = nextafter(r, REAL_INF);
        if (!isfinite(r))
            return -1;
        dst[i] = r;
    }
    return c->failed ? -1 : 0;
}

/* The textures at the end of the file: in versions 2 to 4 as float
 * texels, each size checked against the bytes left before anything is
 * allocated; from version 5 in their byte form (texture_read_form).  The
 * file ends with them. */
static int tmd_read_textures(Cursor *c, uint32_t version, uint32_t texs, Model *m, const char *name, Err *err)
{
    m->textures = calloc(texs, sizeof *m->textures);
    if (!m->textures)
        return err_set(err, "%s: out of memory for %u textures", name, texs);
    for (uint32_t i = 0; i < texs; i++) {
        char label[1100];
        snprintf(label, sizeof label, "%s: texture %u", name, i);
        Texture *t;
        if (version >= TMD_VERSION_FORMS) {
            if (texture_read_form(c, label, &t, err))
                return -1;
        } else {
            uint32_t tw = cursor_u32(c), th = cursor_u32(c), tf = cursor_u32(c);
            if (c->failed)
                return err_set(err, "%s: the file is cut short in the texture's header", label);
            if (!texture_size_ok(tw, th) || tf > 1)
                return err_set(err, "%s: implausible size %ux%u or flags %u", label, tw, th, tf);
            if ((uint64_t)tw * th * 12 > c->left)
                return err_set(err, "%s: the file is cut short: %ux%u texels need %llu bytes, %zu are left", label, tw,
                               th, (unsigned long long)tw * th * 12, c->left);
            if (texture_read_texels(c, tw, th, label, &t, err))
                return -1;
            t->wrap[0] = t->wrap[1] = tf ? TEXTURE_CLAMP : TEXTURE_REPEAT;
        }
        m->textures[m->texture_count++] = t;
    }
    if (c->left != 0)
        return err_set(err, "%s: %zu bytes after the last texture", name, c->left);
    return 0;
}

/* A header's numbers: the fields after the magic (tmd.h), named. */
typedef struct {
    uint32_t version, flags, kind, nodes, tris, mats, depth, texs;
    int wide, optics, textured;
} Header;

/* The header checked against itself and the file's length and checksum,
 * before anything is allocated. */
static int check_header(const void *data, size_t len, const char *name, Header *hd, Err *err)
{
    Cursor c = cursor_make(data, len);
    char magic[8];
    uint32_t h[14];
    if (cursor_get(&c, magic, 8) || cursor_get(&c, h, sizeof h))
        return err_set(err, "%s: %zu bytes is too short for a .tmd header (64 bytes): not a .tmd file, or one cut short",
                       name, len);
    if (memcmp(magic, TMD_MAGIC, 8) != 0)
        return err_set(err, "%s: not a .tmd file, or a corrupt one (bad magic)", name);
    if (h[1] != TMD_BOM)
        return err_set(err, "%s: byte-order mark 0x%08x: written on a machine of the other byte order, or corrupt", name,
                       h[1]);
    if (h[0] < TMD_VERSION_PLAIN || h[0] > TMD_VERSION)
        return err_set(err, "%s: format version %u, this build reads versions %u to %u: a newer lanray's file, or a "
                       "corrupt one", name, h[0], TMD_VERSION_PLAIN, TMD_VERSION);
    if (h[0] >= TMD_VERSION_FORMS) {
        /* the length first, so that a file cut short says so; then every bit */
        if (h[10] != len)
            return err_set(err, "%s: corrupt or cut short: the file has %zu bytes, its header says %u", name, len, h[10]);
        uint32_t crc = tmd_checksum(data, len);
        if (crc != h[11])
            return err_set(err, "%s: corrupt: checksum 0x%08x, the header says 0x%08x", name, crc, h[11]);
        if (h[12] || h[13])
            return err_set(err, "%s: reserved header fields are not zero", name);
    } else if (h[10] || h[11] || h[12] || h[13]) {
        return err_set(err, "%s: corrupt: version %u with reserved header fields that are not zero", name, h[0]);
    }
    *hd = (Header){.version = h[0], .flags = h[3], .kind = h[4], .nodes = h[5], .tris = h[6], .mats = h[7],
                   .depth = h[8], .texs = h[9]};
    const uint32_t flags = hd->flags;
    if (h[2] != TMD_HEADER_BYTES)
        return err_set(err, "%s: header size %u, expected %u", name, h[2], TMD_HEADER_BYTES);
    if (flags & ~(TMD_HAS_NORMALS | TMD_HAS_UVS | TMD_HAS_MATERIALS | TMD_WIDE | TMD_HAS_TEXTURES | TMD_HAS_COLOURS |
                  TMD_HAS_OPTICS) ||
        ((flags & TMD_HAS_TEXTURES) && h[0] < TMD_VERSION_TEXTURES) ||
        ((flags & TMD_HAS_COLOURS) && h[0] < TMD_VERSION_COLOURS) || ((flags & TMD_HAS_OPTICS) && h[0] < TMD_VERSION_OPTICS) ||
        ((flags & TMD_HAS_OPTICS) && (!(flags & TMD_HAS_MATERIALS) || h[0] >= TMD_VERSION_FIELDS)))
        return err_set(err, "%s: unknown flags 0x%x", name, flags);
    hd->optics = (flags & TMD_HAS_OPTICS) != 0;
    hd->textured = (flags & TMD_HAS_TEXTURES) != 0;
    hd->wide = (flags & TMD_WIDE) != 0;
    if (hd->textured != (hd->texs > 0) || hd->texs > 65536 || (hd->textured && !(flags & TMD_HAS_MATERIALS)))
        return err_set(err, "%s: implausible texture count %u", name, hd->texs);
    if (hd->kind >= BVH_KIND_COUNT)
        return err_set(err, "%s: unknown BVH kind %u", name, hd->kind);
    if (hd->tris > BVH_MAX_PRIMS || hd->nodes > 2 * hd->tris || (hd->tris > 0) != (hd->nodes > 0))
        return err_set(err, "%s: implausible counts (%u nodes, %u triangles)", name, hd->nodes, hd->tris);
    if (hd->mats > 65536 || ((flags & TMD_HAS_MATERIALS) != 0) != (hd->mats > 0))
        return err_set(err, "%s: implausible material count %u", name, hd->mats);
    if (hd->depth > BVH_MAX_DEPTH)
        return err_set(err, "%s: tree depth %u exceeds %u", name, hd->depth, BVH_MAX_DEPTH);
    /* the exact size follows from the header */
    uint64_t w = hd->wide ? 8 : 4; /* bytes per number */
    uint64_t want = TMD_HEADER_BYTES + (uint64_t)hd->nodes * (6 * w + 8) + (uint64_t)hd->tris * 9 * w;
    if (flags & TMD_HAS_NORMALS)
        want += (uint64_t)hd->tris * 9 * w;
    if (flags & TMD_HAS_UVS)
        want += (uint64_t)hd->tris * 6 * w;
    /* from version 6 a material takes as many bytes as it uses: at least
     * its table's fewest, the file's end is checked after reading */
    const int exact = hd->version < TMD_VERSION_FIELDS && !hd->textured;
    if (flags & TMD_HAS_MATERIALS)
        want += (uint64_t)hd->mats * (hd->version >= TMD_VERSION_FIELDS ? field_min_bytes(&material_kind)
                                                                        : (hd->optics ? 21 : 7) * w + (hd->textured ? 4 : 0)) +
                (uint64_t)hd->tris * 4;
    if (flags & TMD_HAS_COLOURS)
        want += (uint64_t)hd->tris * 9 * w;
    /* textures follow, each with its own size: at least their 12-byte headers */
    if (hd->textured)
        want += (uint64_t)hd->texs * 12;
    if (exact ? want != len : want > len)
        return err_set(err, "%s: header promises %llu bytes but the file has %zu", name, (unsigned long long)want, len);
    return 0;
}

/* The tree's nodes, the triangles and their normals and texture
 * coordinates: NULL, or what was not a finite number. */
static const char *read_geometry(Cursor *c, const Header *hd, Model *m)
{
    for (uint32_t i = 0; i < hd->nodes; i++) {
        BvhNode *n = &m->bvh.nodes[i];
        if (read_reals(c, hd->wide, -1, n->bmin, 3))
            return "node box";
        n->first = cursor_u32(c);
        if (read_reals(c, hd->wide, 1, n->bmax, 3))
            return "node box";
        n->count = cursor_u32(c);
    }
    for (uint32_t i = 0; i < hd->tris; i++)
        if (read_reals(c, hd->wide, 0, &m->tris[i].v[0][0], 9))
            return "triangle vertex";
    for (uint32_t i = 0; m->normals && i < 3 * hd->tris; i++)
        if (read_reals(c, hd->wide, 0, m->normals[i].e, 3))
            return "normal";
    if (m->uvs && read_reals(c, hd->wide, 0, m->uvs, (size_t)6 * hd->tris))
        return "texture coordinate";
    return NULL;
}

/* The materials, each with its texture and optics where the file has them. */
static int read_materials(Cursor *c, const Header *hd, Model *m, const char *name, Err *err)
{
    for (uint32_t i = 0; i < hd->mats && hd->version >= TMD_VERSION_FIELDS; i++) {
        Material *mt = &m->materials[i];
        memset(mt, 0, sizeof *mt);
        if (field_decode(&material_kind, c, mt, sizeof *mt))
            return err_set(err, "%s: material %u is %s", name, i, c->failed ? "cut short" : "malformed (unknown groups)");
        if (!material_textures_in(mt, (int32_t)hd->texs))
            return err_set(err,
                           "%s: material %u names texture %d (colour), %d (cutout), %d (normal map), %d (emission), %d "
                           "(metal) or %d (occlusion) of %u",
                           name, i, mt->texture, mt->mask, mt->normal_map, mt->emit_map, mt->metal_map, mt->ao_map,
                           hd->texs);
    }
    for (uint32_t i = 0; i < hd->mats && hd->version < TMD_VERSION_FIELDS; i++) {
        Material *mt = &m->materials[i];
        *mt = material_default();
        if (read_reals(c, hd->wide, 0, mt->kd.e, 3) || read_reals(c, hd->wide, 0, mt->ks.e, 3) ||
            read_reals(c, hd->wide, 0, &mt->shininess, 1))
            return err_set(err, "%s: material is not a finite number", name);
        if (hd->textured) {
            int32_t t = (int32_t)cursor_u32(c);
            if (t < -1 || t >= (int32_t)hd->texs)
                return err_set(err, "%s: material %u uses texture %d of %u", name, i, t, hd->texs);
            mt->texture = t;
        }
        real o[14];
        if (!hd->optics)
            continue;
        if (read_reals(c, hd->wide, 0, o, 14))
            return err_set(err, "%s: material is not a finite number", name);
        mt->kr = v3(o[0], o[1], o[2]);
        mt->roughness = o[3];
        mt->ior = o[4];
        mt->kt = v3(o[5], o[6], o[7]);
        mt->absorb = v3(o[8], o[9], o[10]);
        mt->ke = v3(o[11], o[12], o[13]);
    }
    char why[160];
    for (uint32_t i = 0; i < hd->mats; i++)
        if (material_problem(&m->materials[i], why, sizeof why))
            return err_set(err, "%s: material %u: %s", name, i, why);
    return 0;
}

/* Each triangle's material and its vertex colours, where the file has them. */
static int read_per_triangle(Cursor *c, const Header *hd, Model *m, const char *name, Err *err)
{
    if (m->mat_ids && cursor_get(c, m->mat_ids, (size_t)hd->tris * 4) == 0)
        for (uint32_t i = 0; i < hd->tris; i++)
            if (m->mat_ids[i] >= hd->mats)
                return err_set(err, "%s: triangle %u uses material %u of %u", name, i, m->mat_ids[i], hd->mats);
    for (uint32_t i = 0; m->colours && i < 3 * hd->tris; i++) {
        if (read_reals(c, hd->wide, 0, m->colours[i].e, 3))
            return err_set(err, "%s: vertex colour is not a finite number", name);
        if (m->colours[i].x < R(0) || m->colours[i].y < R(0) || m->colours[i].z < R(0))
            return err_set(err, "%s: triangle %u: a negative vertex colour", name, i / 3);
    }
    return 0;
}

int tmd_decode(const void *data, size_t len, const char *name, Model **out, Err *err)
{
    *out = NULL;
    Header hd = {0};
    if (check_header(data, len, name, &hd, err))
        return -1;
    const uint32_t flags = hd.flags;
    Model *m = model_alloc(hd.tris, hd.nodes, hd.mats,
                           (flags & TMD_HAS_NORMALS ? MESH_NORMALS : 0u) | (flags & TMD_HAS_UVS ? MESH_UVS : 0u) |
                               (flags & TMD_HAS_MATERIALS ? MESH_MATERIALS : 0u) |
                               (flags & TMD_HAS_COLOURS ? MESH_COLOURS : 0u));
    if (!m)
        return err_set(err, "%s: out of memory for %u triangles", name, hd.tris);
    m->bvh.kind = (BvhKind)hd.kind;
    m->bvh.depth = hd.depth;
    Cursor c = cursor_make((const uint8_t *)data + TMD_HEADER_BYTES, len - TMD_HEADER_BYTES); /* after the header */
    const char *bad = read_geometry(&c, &hd, m);
    int rc = bad ? err_set(err, "%s: %s is not a finite number", name, bad) : 0;
    if (rc == 0)
        rc = read_materials(&c, &hd, m, name, err);
    if (rc == 0)
        rc = read_per_triangle(&c, &hd, m, name, err);
    if (rc == 0 && c.failed)
        rc = err_set(err, "%s: data is not a finite number", name);
    if (rc == 0 && hd.textured)
        rc = tmd_read_textures(&c, hd.version, hd.texs, m, name, err);
    else if (rc == 0 && c.left != 0)
        rc = err_set(err, "%s: %zu bytes after the last section", name, c.left);
    if (rc == 0 && bvh_validate(&m->bvh, &m->bvh.depth, err))
        rc = err_prefix(err, "%s", name);
    if (rc) {
        model_destroy(m);
        return -1;
    }
    m->bounds = hd.nodes ? bvh_node_box(&m->bvh.nodes[0]) : aabb_empty();
    *out = m;
    return 0;
}

int tmd_read(const char *path, Model **out, Err *err)
{
    char *data;
    size_t len;
    if (file_read_all(path, TMD_MAX_FILE_BYTES, &data, &len, err))
        return -1;
    int rc = tmd_decode(data, len, path, out, err);
    free(data);
    return rc;
}
