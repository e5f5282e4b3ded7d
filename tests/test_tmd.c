/* test_tmd.c - .tmd round trips and a reader that rejects every malformed file cleanly. */
#include "helpers.h"
#include "sah_model.h"

#include <sys/stat.h>

#include "scene/scene_default.h"
#include "model/tmd.h"

/* attrs: the MESH_* arrays the model has */
static Model *sample_model(unsigned attrs)
{
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, attrs, NULL), 0);
    Rng rng = {11};
    if (attrs & MESH_MATERIALS) {
        Material a = {.kd = v3(1, 0, 0), .ks = v3(R(0.5), R(0.5), R(0.5)), .shininess = 20, .texture = -1}, b = {.kd = v3(0, 0, 1), .ks = v3(0, 0, 0), .shininess = 1, .texture = -1};
        assert_int_equal(mesh_add_material(&mesh, a, NULL), 0);
        assert_int_equal(mesh_add_material(&mesh, b, NULL), 0);
    }
    for (uint32_t i = 0; i < 200; i++) {
        vec3 c = rng_vec(&rng, -5, 5);
        vec3 p[3] = {c, v3_add(c, rng_vec(&rng, R(0.1), 1)), v3_add(c, rng_vec(&rng, -1, R(-0.1)))};
        if (mesh_tri_is_degenerate(p)) {
            i--;
            continue;
        }
        vec3 n[3] = {rng_dir(&rng), rng_dir(&rng), rng_dir(&rng)};
        real uv[6];
        for (int k = 0; k < 6; k++)
            uv[k] = rng_real(&rng, 0, 1);
        vec3 col[3] = {rng_vec(&rng, 0, 1), rng_vec(&rng, 0, 1), rng_vec(&rng, 0, 1)};
        assert_int_equal(mesh_add(&mesh, p, n, uv, col, i % 2, NULL), 0);
    }
    Model *m = sah_model(&mesh);
    return m;
}

static void assert_models_equal(const Model *a, const Model *b)
{
    assert_int_equal(a->tri_count, b->tri_count);
    assert_int_equal(a->bvh.node_count, b->bvh.node_count);
    assert_int_equal(a->bvh.kind, b->bvh.kind);
    assert_int_equal(a->bvh.depth, b->bvh.depth);
    assert_memory_equal(a->tris, b->tris, a->tri_count * sizeof *a->tris);
    for (uint32_t i = 0; i < a->bvh.node_count; i++) { /* field by field: a double build's node has padding */
        const BvhNode *x = &a->bvh.nodes[i], *y = &b->bvh.nodes[i];
        assert_memory_equal(x->bmin, y->bmin, sizeof x->bmin);
        assert_memory_equal(x->bmax, y->bmax, sizeof x->bmax);
        assert_int_equal(x->first, y->first);
        assert_int_equal(x->count, y->count);
    }
    assert_int_equal(a->normals != NULL, b->normals != NULL);
    assert_int_equal(a->uvs != NULL, b->uvs != NULL);
    assert_int_equal(a->mat_ids != NULL, b->mat_ids != NULL);
    assert_int_equal(a->colours != NULL, b->colours != NULL);
    if (a->colours)
        assert_memory_equal(a->colours, b->colours, 3 * a->tri_count * sizeof *a->colours);
    if (a->normals)
        assert_memory_equal(a->normals, b->normals, 3 * a->tri_count * sizeof *a->normals);
    if (a->uvs)
        assert_memory_equal(a->uvs, b->uvs, 6 * a->tri_count * sizeof *a->uvs);
    if (a->mat_ids) {
        assert_memory_equal(a->mat_ids, b->mat_ids, a->tri_count * sizeof *a->mat_ids);
        assert_int_equal(a->material_count, b->material_count);
        for (uint32_t i = 0; i < a->material_count; i++) {
            assert_memory_equal(&a->materials[i].kd, &b->materials[i].kd, sizeof(vec3));
            assert_true(a->materials[i].shininess == b->materials[i].shininess);
        }
    }
}

static void round_trip_through_a_file(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "%s/model.tmd", test_tmpdir());
    for (unsigned mask = 0; mask < 16; mask++) {
        Model *m = sample_model(mask), *back;
        Err err;
        if (tmd_write(path, m, &err) || tmd_read(path, &back, &err))
            fail_msg("%s", err.msg);
        /* in every build the decoded model encodes to the same bytes */
        void *a, *b;
        size_t alen, blen;
        assert_int_equal(tmd_encode(m, 0, &a, &alen, NULL), 0);
        assert_int_equal(tmd_encode(back, 0, &b, &blen, NULL), 0);
        assert_int_equal(alen, blen);
        assert_memory_equal(a, b, alen);
        free(b);
#ifndef LANRAY_DOUBLE
        /* the float build stores what it computes: the model itself comes back exactly */
        assert_models_equal(m, back);
#else
        (void)assert_models_equal;
#endif
        /* only the attributes the model has take space */
        struct stat st;
        assert_int_equal(stat(path, &st), 0);
        size_t want = 64 + 32 * (size_t)m->bvh.node_count + 36 * (size_t)m->tri_count;
        if (mask & 1)
            want += 36 * (size_t)m->tri_count;
        if (mask & 2)
            want += 24 * (size_t)m->tri_count;
        if (mask & 4) /* two materials by their table: group bits, diffuse, specular, shininess (f64), texture */
            want += 2 * 64 + 4 * (size_t)m->tri_count;
        if (mask & 8)
            want += 36 * (size_t)m->tri_count;
        assert_int_equal((size_t)st.st_size, want);
        /* the version written, with the file's length and checksum */
        uint32_t version, length;
        memcpy(&version, (const char *)a + 8, 4);
        memcpy(&length, (const char *)a + TMD_LENGTH_AT, 4);
        assert_int_equal(version, TMD_VERSION);
        assert_int_equal(length, alen);
        free(a);
        model_destroy(m);
        model_destroy(back);
    }
}

/* The wide form (float64, what a double build sends its clients) gives the
 * model back bit for bit in every build, with every attribute; its truncations
 * fail cleanly too. */
static void wide_form_is_exact(void **state)
{
    (void)state;
    for (unsigned mask = 0; mask < 16; mask++) {
        Model *m = sample_model(mask), *back = NULL;
        void *data;
        size_t len;
        Err err;
        assert_int_equal(tmd_encode(m, 1, &data, &len, NULL), 0);
        if (tmd_decode(data, len, "wide.tmd", &back, &err))
            fail_msg("%s", err.msg);
        assert_models_equal(m, back);
        for (size_t n = 0; n < len; n += 97)
            assert_int_equal(tmd_decode(data, n, "cut.tmd", &(Model *){NULL}, &err), -1);
        free(data);
        model_destroy(m);
        model_destroy(back);
    }
}

/* Every truncation of a valid file fails with a message, and never crashes. */
static void truncated_files_are_rejected(void **state)
{
    (void)state;
    Model *m = sample_model(MESH_NORMALS | MESH_UVS | MESH_MATERIALS | MESH_COLOURS);
    void *data;
    size_t len;
    assert_int_equal(tmd_encode(m, 0, &data, &len, NULL), 0);
    for (size_t n = 0; n < len; n++) {
        Model *back = NULL;
        Err err = {{0}};
        assert_int_equal(tmd_decode(data, n, "cut.tmd", &back, &err), -1);
        assert_null(back);
        assert_contains(err.msg, "cut.tmd");
    }
    free(data);
    model_destroy(m);
}

/* A patched file sealed again: its length and checksum made right, so that
 * the reader's checks behind them are what answer. */
static void seal(uint8_t *d, size_t len)
{
    uint32_t l = (uint32_t)len, c;
    memcpy(d + TMD_LENGTH_AT, &l, 4);
    c = tmd_checksum(d, len);
    memcpy(d + TMD_CHECKSUM_AT, &c, 4);
}

/* A version 1 to 4 file from a version-5 one without textures: the same
 * layout, without the length and checksum. */
static void as_old(uint8_t *d, uint32_t version)
{
    memcpy(d + 8, &version, 4);
    memset(d + TMD_LENGTH_AT, 0, 16);
}

static void expect_error(const uint8_t *data, size_t len, const char *what)
{
    Model *back = NULL;
    Err err = {{0}};
    assert_int_equal(tmd_decode(data, len, "bad.tmd", &back, &err), -1);
    assert_null(back);
    assert_contains(err.msg, what);
}

static void corrupted_fields_are_rejected(void **state)
{
    (void)state;
    Model *m = sample_model(MESH_MATERIALS);
    uint8_t *data;
    size_t len;
    assert_int_equal(tmd_encode(m, 0, (void **)&data, &len, NULL), 0);
    uint8_t *bad = malloc(len);
    uint32_t v;
#define PATCH(off, val) (memcpy(bad, data, len), v = (val), memcpy(bad + (off), &v, 4), seal(bad, len))
    memcpy(bad, data, len);
    bad[0] = 'X';
    expect_error(bad, len, "bad magic");
    PATCH(8, 99);
    expect_error(bad, len, "version 99");
    PATCH(12, 0x04030201);
    expect_error(bad, len, "other byte order");
    /* unsealed: a changed byte is corruption, a missing one a cut */
    memcpy(bad, data, len);
    bad[len / 2] ^= 1;
    expect_error(bad, len, "corrupt: checksum");
    expect_error(data, len - 4, "corrupt or cut short: the file has");
    /* an old version has no checksum, so its reserved words must be zero */
    memcpy(bad, data, len);
    v = 4;
    memcpy(bad + 8, &v, 4);
    expect_error(bad, len, "reserved header fields");
    PATCH(20, 0x80);
    expect_error(bad, len, "unknown flags");
    PATCH(24, 7);
    expect_error(bad, len, "BVH kind");
    PATCH(32, 0xffffffffu);
    expect_error(bad, len, "implausible counts");
    PATCH(28, m->bvh.node_count + 1);
    expect_error(bad, len, "header promises");
    /* the root's child index pointing back at itself */
    PATCH(64 + 12, 0);
    expect_error(bad, len, "child index");
    /* a NaN vertex coordinate */
    float nan = NAN;
    memcpy(bad, data, len);
    memcpy(bad + 64 + 32 * m->bvh.node_count, &nan, 4);
    seal(bad, len);
    expect_error(bad, len, "not a finite number");
    /* a triangle using a material that does not exist */
    PATCH(len - 4, 2);
    expect_error(bad, len, "uses material 2");
    /* a leaf covering primitives past the end */
    uint32_t leaf = 0;
    while (m->bvh.nodes[leaf].count == 0)
        leaf++;
    PATCH(64 + 32 * leaf + 28, m->tri_count + 5);
    expect_error(bad, len, "beyond");
#undef PATCH
    free(bad);
    free(data);
    model_destroy(m);
}

/* Vertex colours: version 3 on, finite, not negative. */
static void corrupted_colours_are_rejected(void **state)
{
    (void)state;
    Model *m = sample_model(MESH_COLOURS);
    uint8_t *data;
    size_t len;
    assert_int_equal(tmd_encode(m, 0, (void **)&data, &len, NULL), 0);
    as_old(data, TMD_VERSION_TEXTURES);
    expect_error(data, len, "unknown flags");
    as_old(data, TMD_VERSION_COLOURS);
    Model *back;
    Err err;
    if (tmd_decode(data, len, "old.tmd", &back, &err)) /* an old file reads */
        fail_msg("%s", err.msg);
    model_destroy(back);
    float f = -0.5f;
    memcpy(data + len - 4, &f, 4);
    expect_error(data, len, "negative vertex colour");
    f = INFINITY;
    memcpy(data + len - 8, &f, 4);
    expect_error(data, len, "vertex colour is not a finite number");
    free(data);
    model_destroy(m);
}

/* A small textured model: 12 triangles, a material with an 8 x 8 texture. */
static Model *textured_model(void)
{
    Mesh mesh;
    assert_int_equal(mesh_init(&mesh, MESH_UVS | MESH_MATERIALS, NULL), 0);
    uint8_t px[8 * 8 * 3];
    for (int i = 0; i < 8 * 8 * 3; i++)
        px[i] = (uint8_t)(i * 37);
    uint32_t tid;
    assert_int_equal(mesh_add_texture(&mesh, texture_from_rgb8(8, 8, px), &tid, NULL), 0);
    Material mt = material_default();
    mt.texture = (int32_t)tid;
    assert_int_equal(mesh_add_material(&mesh, mt, NULL), 0);
    Rng rng = {5};
    for (int i = 0; i < 12; i++) {
        vec3 c = rng_vec(&rng, -5, 5);
        vec3 p[3] = {c, v3_add(c, v3(1, 0, 0)), v3_add(c, v3(0, 1, 0))};
        real uv[6] = {0, 0, 1, 0, 0, 1};
        assert_int_equal(mesh_add(&mesh, p, NULL, uv, NULL, 0, NULL), 0);
    }
    Model *m = sah_model(&mesh);
    return m;
}

/* Textures travel as images (a PNG here, made from the texels) and come
 * back with the same texels; and a single flipped bit anywhere in a file,
 * its header, tree, triangles or texture, is refused as corruption. */
static void textures_round_trip_and_every_bit_is_checked(void **state)
{
    (void)state;
    Model *m = textured_model(), *back = NULL;
    uint8_t *data;
    size_t len;
    Err err = {{0}};
    assert_int_equal(tmd_encode(m, 0, (void **)&data, &len, NULL), 0);
    if (tmd_decode(data, len, "t.tmd", &back, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(back->texture_count, 1);
    assert_int_equal(back->textures[0]->codec, TEXTURE_PNG);
    assert_memory_equal(back->textures[0]->texels, m->textures[0]->texels, texture_bytes(m->textures[0]));
    model_destroy(back);
    /* cut inside the texture: said to be cut short (before version 5 it was
     * "implausible size") */
    assert_int_equal(tmd_decode(data, len - 10, "cut.tmd", &back, &err), -1);
    assert_contains(err.msg, "cut.tmd: corrupt or cut short: the file has");
    for (size_t bit = 0; bit < 8 * len; bit++) {
        data[bit / 8] ^= (uint8_t)(1u << (bit % 8));
        back = NULL;
        err.msg[0] = 0;
        assert_int_equal(tmd_decode(data, len, "flip.tmd", &back, &err), -1);
        assert_null(back);
        if (!strstr(err.msg, "corrupt"))
            fail_msg("bit %zu of %zu: \"%s\" does not name corruption", bit, 8 * len, err.msg);
        data[bit / 8] ^= (uint8_t)(1u << (bit % 8));
    }
    free(data);
    model_destroy(m);
}

/* A material's maps (a cutout's mask, a normal map, an emission, metal-
 * roughness or occlusion texture) travel with it, and one that names a
 * texture the file does not hold is refused, naming the material. */
static void material_maps_travel_and_are_checked(void **state)
{
    (void)state;
    Model *m = textured_model(), *back = NULL;
    Material *mt = &m->materials[0];
    mt->mask = 0, mt->cutoff = R(0.5);
    mt->normal_map = 0, mt->normal_scale = R(0.75);
    mt->ke = v3(1, 1, 1), mt->emit_map = 0, mt->emit_mapped = 1;
    mt->kr = v3(R(0.5), R(0.5), R(0.5)), mt->metal_map = 0, mt->metal_mapped = 1;
    mt->ao_map = 0, mt->ao_strength = R(0.25);
    uint8_t *data;
    size_t len;
    Err err = {{0}};
    assert_int_equal(tmd_encode(m, 0, (void **)&data, &len, NULL), 0);
    if (tmd_decode(data, len, "maps.tmd", &back, &err))
        fail_msg("%s", err.msg);
    const Material *b = &back->materials[0];
    assert_true(material_cuts(b) && material_bumps(b) && material_emit_mapped(b) && material_metal_mapped(b) &&
                material_occludes(b));
    assert_float_equal(b->normal_scale, 0.75, 0);
    assert_float_equal(b->ao_strength, 0.25, 0);
    model_destroy(back);
    free(data);
    int32_t *maps[] = {&mt->mask, &mt->normal_map, &mt->emit_map, &mt->metal_map, &mt->ao_map};
    for (size_t k = 0; k < sizeof maps / sizeof *maps; k++) {
        *maps[k] = 1; /* the file holds texture 0 alone */
        assert_int_equal(tmd_encode(m, 0, (void **)&data, &len, NULL), 0);
        back = NULL;
        assert_int_equal(tmd_decode(data, len, "maps.tmd", &back, &err), -1);
        assert_null(back);
        assert_contains(err.msg, "maps.tmd: material 0 names texture");
        assert_contains(err.msg, "of 1");
        free(data);
        *maps[k] = 0;
    }
    model_destroy(m);
}

static void unwritable_destination_leaves_nothing(void **state)
{
    (void)state;
    Model *m = sample_model(0);
    Err err = {{0}};
    assert_int_equal(tmd_write("/nonexistent-dir/x.tmd", m, &err), -1);
    assert_contains(err.msg, "/nonexistent-dir/x.tmd");
    Model *back;
    assert_int_equal(tmd_read("/nonexistent-dir/x.tmd", &back, &err), -1);
    assert_contains(err.msg, "cannot open");
    model_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip_through_a_file),
        cmocka_unit_test(wide_form_is_exact),
        cmocka_unit_test(truncated_files_are_rejected),
        cmocka_unit_test(corrupted_fields_are_rejected),
        cmocka_unit_test(corrupted_colours_are_rejected),
        cmocka_unit_test(material_maps_travel_and_are_checked),
        cmocka_unit_test(textures_round_trip_and_every_bit_is_checked),
        cmocka_unit_test(unwritable_destination_leaves_nothing),
    };
    return cmocka_run_group_tests_name("tmd", tests, NULL, NULL);
}
