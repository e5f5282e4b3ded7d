/* test_import.c - what the importer makes of a glTF's metal-roughness
 * materials (import.c): a metal reflects its base colour at its roughness,
 * emission, transmission (its volume's attenuation too) and a blended
 * opacity map onto lanray's terms, a non-metal's specular reflection
 * (and KHR_materials_clearcoat) onto a clear coat, and
 * what cannot be read per texel, or is only glTF's defaults, stays diffuse;
 * vertex colours multiply the base colour; samplers wrap each axis; a
 * MASK material cuts holes by its texture's alpha. */
#include "helpers.h"

#include "model/gltf_json.h"
#include "model/import.h"

static void expect_vec(vec3 v, real x, real y, real z)
{
    assert_float_equal(v.x, x, 1e-6);
    assert_float_equal(v.y, y, 1e-6);
    assert_float_equal(v.z, z, 1e-6);
}

static void gltf_materials_map_onto_lanrays(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/pbr.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_true(m.material_count >= 9);
    assert_int_equal(st.optics, 8); /* the half metal reflects too */
    /* gold: metallic 1, roughness 0.2: all mirror, no diffuse, a tight highlight */
    const Material *gold = &m.materials[0];
    expect_vec(gold->kd, 0, 0, 0);
    expect_vec(gold->kr, 1, 0.8, 0.3);
    expect_vec(gold->ks, 1, 0.8, 0.3);
    assert_float_equal(gold->roughness, 0.2, 1e-6);
    assert_float_equal(gold->shininess, 2 / (0.04 * 0.04) - 2, 1e-2);
    /* its colour head on, rising to white at grazing angles (glTF's Schlick, F0 the base colour) */
    expect_vec(gold->kre, 1, 1, 1);
    assert_true(material_edged(gold));
    expect_vec(material_mirror_at(gold, 1), 1, 0.8, 0.3);
    expect_vec(material_mirror_at(gold, 0), 1, 1, 1);
    /* a lamp: its emissive factor times KHR_materials_emissive_strength's 4 (read by lanray: not by Assimp 5.2) */
    expect_vec(m.materials[1].ke, 4, 2, 1);
    expect_vec(m.materials[1].kr, 0, 0, 0);
    /* glass: transmission through a tint of the base colour, its own index */
    const Material *glass = &m.materials[2];
    assert_float_equal(glass->ior, 1.33, 1e-6);
    expect_vec(glass->kt, 0.9, 1, 0.9);
    expect_vec(glass->kd, 0, 0, 0);
    /* frosted by the material's roughness: glTF's default, 1, where the
     * file gives none (the metal over glass below gives 0: clear) */
    assert_float_equal(glass->roughness, 1, 0);
    assert_true(material_frosted(glass));
    /* a blended veil of alpha 0.25: three quarters see-through, unbent */
    const Material *veil = &m.materials[3];
    assert_float_equal(veil->ior, 1, 0);
    expect_vec(veil->kt, 0.75, 0.75, 0.75);
    expect_vec(veil->kd, 0.25, 0, 0);
    /* a metalness texture not read: not all metal; glTF's defaults alone: white diffuse */
    expect_vec(m.materials[4].kr, 0, 0, 0);
    expect_vec(m.materials[4].kd, 0.5, 0.5, 0.5);
    expect_vec(m.materials[5].kr, 0, 0, 0);
    expect_vec(m.materials[5].kd, 1, 1, 1);
    /* metallic 0.5 over transmission 0.5 (glTF: the transmission is the
     * dielectric half's): a mirror of half the base colour over glass that
     * transmits and scatters a quarter each; it loads (it was refused: "a
     * dielectric ... takes no mirror reflectance") */
    char why[160];
    const Material *mg = &m.materials[6];
    expect_vec(mg->kr, 0.4, 0.5, 0.3);
    expect_vec(mg->kd, 0.2, 0.25, 0.15);
    expect_vec(mg->kt, 0.2, 0.25, 0.15);
    expect_vec(mg->kre, 0.5, 0.5, 0.5); /* the metal half's rim: half of white */
    assert_float_equal(mg->ior, 1.5, 1e-6);
    assert_false(material_frosted(mg));
    assert_null(material_problem(mg, why, sizeof why));
    /* a blended metal of alpha 0.5: half see-through, half mirror */
    const Material *bm = &m.materials[7];
    expect_vec(bm->kr, 0.45, 0.45, 0.45);
    expect_vec(bm->kd, 0, 0, 0);
    expect_vec(bm->kt, 0.5, 0.5, 0.5);
    expect_vec(bm->kre, 0.5, 0.5, 0.5); /* its rim blended as its colour */
    assert_float_equal(bm->ior, 1, 0);
    assert_null(material_problem(bm, why, sizeof why));
    /* KHR_materials_volume: attenuation colour (0.5 0.8 1) over distance 2
     * is Beer-Lambert absorption -ln(c) / 2; the glass above has none */
    const Material *vol = &m.materials[8];
    expect_vec(vol->absorb, -log(0.5) / 2, -log(0.8) / 2, 0);
    expect_vec(glass->absorb, 0, 0, 0);
    assert_null(material_problem(vol, why, sizeof why));
    /* clear coats: a non-metal's base is a dielectric of index 1.5, its
     * specular reflection a coat of its roughness; a metal by its factors
     * keeps the coat of its dielectric share; glass and glTF's defaults
     * none; KHR_materials_clearcoat's factor and roughness in its place */
    assert_true(m.material_count >= 12);
    assert_float_equal(m.materials[9].coat, 1, 1e-6);
    assert_float_equal(m.materials[9].coat_roughness, 0.3, 1e-6);
    expect_vec(m.materials[9].kd, 0.2, 0.4, 0.8);
    assert_float_equal(m.materials[10].coat, 0.75, 1e-6);
    assert_float_equal(m.materials[10].coat_roughness, 0.5, 1e-6);
    expect_vec(m.materials[10].kr, 0.2, 0.2, 0.2);
    expect_vec(m.materials[10].kre, 0.25, 0.25, 0.25); /* metallic 0.25 of white at grazing */
    expect_vec(m.materials[9].kre, 0, 0, 0);          /* a non-metal: no rim of its own */
    expect_vec(glass->kre, 0, 0, 0);
    assert_float_equal(m.materials[11].coat, 0.8, 1e-6);
    assert_float_equal(m.materials[11].coat_roughness, 0.05, 1e-6);
    assert_float_equal(gold->coat, 0, 0);
    assert_float_equal(glass->coat, 0, 0);
    assert_float_equal(vol->coat, 0, 0);
    assert_float_equal(m.materials[5].coat, 0, 0);
    assert_float_equal(m.materials[4].coat, 1, 1e-6); /* its texture unread: a non-metal */
    /* KHR_materials_specular (read from the JSON: Assimp 5.2 does not):
     * the coat times specularFactor x the largest of its colour factor */
    assert_true(m.material_count >= 14);
    assert_float_equal(m.materials[12].coat, 0, 0);
    assert_float_equal(m.materials[12].coat_roughness, 0, 0);
    assert_float_equal(m.materials[13].coat, 0.5, 1e-6);
    assert_float_equal(m.materials[13].coat_roughness, 0.4, 1e-6);
    assert_int_equal(st.speculars, 2);
    for (uint32_t i = 0; i < 14; i++)
        assert_null(material_problem(&m.materials[i], why, sizeof why));
    mesh_free(&m);
}

/* A glTF's COLOR_0 multiplies its material's base colour (the glTF spec):
 * kept beside the materials, as the diffuse colour at each corner; a mesh
 * without colours in such a model keeps its material's colour. */
static void gltf_vertex_colours_multiply_the_base_colour(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/colours.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_non_null(m.col);
    assert_non_null(m.mat);
    assert_int_equal(st.colours_ignored, 0);
    assert_int_equal(m.tri_count, 2);
    const int tinted = m.pos[0].x < R(1.5) ? 0 : 1; /* the coloured triangle is the one at x 0..1 */
    const vec3 *c = &m.col[3 * tinted], *p = &m.col[3 * (1 - tinted)];
    expect_vec(c[0], 0.5, 0, 0);
    expect_vec(c[1], 0, 1, 0);
    expect_vec(c[2], 0, 0, 1);
    for (int k = 0; k < 3; k++)
        expect_vec(p[k], 0.2, 0.3, 0.4);
    mesh_free(&m);
}

/* A glTF sampler's wrap modes, each axis its own (wrapS MIRRORED_REPEAT
 * with wrapT CLAMP_TO_EDGE on the sample models' textured box, whose u
 * runs to 6): three materials read one image through three samplers and
 * get three textures, not the first material's. */
static void gltf_samplers_wrap_each_axis(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/wrap.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_true(m.material_count >= 3); /* Assimp adds a default one */
    assert_int_equal(m.texture_count, 3);
    const uint8_t want[3][2] = {{TEXTURE_MIRROR, TEXTURE_CLAMP}, {TEXTURE_REPEAT, TEXTURE_REPEAT},
                                {TEXTURE_CLAMP, TEXTURE_CLAMP}};
    for (int i = 0; i < 3; i++) {
        assert_true(m.materials[i].texture >= 0);
        const Texture *t = m.textures[m.materials[i].texture];
        assert_int_equal(t->wrap[0], want[i][0]);
        assert_int_equal(t->wrap[1], want[i][1]);
    }
    mesh_free(&m);
}

/* glTF's alphaMode MASK: the material cuts holes where its base colour
 * texture's alpha (times the factor's) is under alphaCutoff (the texture is
 * its own mask, its alpha kept); an OPAQUE material with the same image
 * stays solid. */
static void gltf_mask_materials_cut(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/mask.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_true(m.material_count >= 2);
    const Material *leaf = &m.materials[0], *opaque = &m.materials[1];
    assert_true(material_cuts(leaf));
    assert_float_equal(leaf->cutoff, 0.3, 1e-6);
    assert_int_equal(leaf->mask, leaf->texture);
    assert_false(material_cuts(opaque));
    /* the base colour factor's alpha 0.5 halves every texel's: they cut under 0.3 / 0.5 */
    assert_true(m.material_count >= 3);
    assert_float_equal(m.materials[2].cutoff, 0.6, 1e-6);
    const Texture *t = m.textures[leaf->texture];
    assert_non_null(t->alpha);
    assert_int_equal(t->alpha[0], 255);
    assert_int_equal(t->alpha[1], 64);
    mesh_free(&m);
}

/* glTF normalTexture: a material's normal map and its scale; one on a
 * second set of texture coordinates (which lanray does not read) is none. */
static void gltf_normal_maps_are_read(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/normalmap.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_true(m.material_count >= 3); /* Assimp adds a default one */
    const Material *bumpy = &m.materials[0], *second = &m.materials[1], *unscaled = &m.materials[2];
    assert_true(material_bumps(bumpy));
    assert_float_equal(bumpy->normal_scale, 0.5, 1e-6);
    assert_true(bumpy->texture >= 0 && bumpy->normal_map != bumpy->texture);
    assert_false(material_bumps(second));
    assert_int_equal(second->normal_map, 0);
    assert_true(material_bumps(unscaled));
    assert_float_equal(unscaled->normal_scale, 1, 0);
    assert_int_equal(unscaled->normal_map, bumpy->normal_map);
    /* the map's texels as the file has them: left tilts to +u, right to -u */
    const Texture *t = m.textures[bumpy->normal_map];
    assert_int_equal(t->w, 2);
    assert_int_equal(t->level[0].rgb[0], 218);
    assert_int_equal(t->level[0].rgb[3], 38);
    assert_true(t->closest);
    mesh_free(&m);
}

/* KHR_texture_transform: a material's texture coordinates become offset +
 * rotation(scale x uv) in glTF's frame (v down), as the extension's sample
 * model checks it: offset (0.25, 0) with scale 2, and a quarter turn. */
static void gltf_texture_transforms_apply(void **state)
{
    (void)state;
    Mesh m;
    ImportStats st;
    Err err;
    if (import_read("tests/data/gltf/uvtransform.gltf", NULL, &m, &st, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(m.tri_count, 2);
    /* glTF uv (0,0), (1,0), (0,1) of each: lanray's v runs up (1 - v) */
    const double want[2][6] = {{0.25, 1, 2.25, 1, 0.25, -1}, {0, 1, 0, 2, 1, 1}};
    for (uint32_t t = 0; t < 2; t++) {
        const int k = (int)m.mat[t]; /* the file's material order */
        for (int j = 0; j < 6; j++)
            if (fabs((double)m.uv[6 * t + (uint32_t)j] - want[k][j]) > 1e-5)
                fail_msg("triangle %u uv %d: %g, not %g", t, j, (double)m.uv[6 * t + (uint32_t)j], want[k][j]);
    }
    mesh_free(&m);
}

/* The warnings an import gave, one after another. */
static void keep_warning(void *ctx, const char *msg)
{
    char *all = ctx;
    strncat(all, msg, 1023 - strlen(all));
}

/* KHR_materials_emissive_strength, which Assimp 5.2.5 does not read: an
 * emission times its strength, the material found by its name, emissive
 * and base colour though Assimp numbers the materials in the order the
 * meshes use them (last to first here); two alike but for their strengths
 * keep their factor, with a warning; from a .gltf, a .glb and a .glb in
 * memory alike. */
static void gltf_emissive_strength_applies(void **state)
{
    (void)state;
    for (int form = 0; form < 3; form++) {
        Mesh m;
        ImportStats st;
        Err err;
        char warned[1024] = "";
        ObjOptions opt = {.warn = keep_warning, .warn_ctx = warned};
        uint8_t *bytes = NULL;
        int rc;
        if (form < 2) {
            rc = import_read(form ? "tests/data/gltf/strength.glb" : "tests/data/gltf/strength.gltf", &opt, &m, &st,
                             &err);
        } else {
            FILE *f = fopen("tests/data/gltf/strength.glb", "rb");
            assert_non_null(f);
            bytes = malloc(1 << 16);
            size_t n = fread(bytes, 1, 1 << 16, f);
            fclose(f);
            rc = import_read_memory(bytes, n, "glb", "strength.glb", &opt, &m, &st, &err);
        }
        if (rc)
            fail_msg("%s", err.msg);
        assert_true(m.material_count >= 5);
        assert_int_equal(st.strengths, 2);
        assert_int_equal(st.strength_unknown, 2);
        assert_non_null(strstr(warned, "emissive_strength) of 2 materials not applied"));
        int seen = 0;
        for (uint32_t i = 0; i < m.material_count; i++) {
            const vec3 ke = m.materials[i].ke;
            const real want = m.materials[i].kd.x < R(0.75) ? R(0.5) /* dark: its base colour tells it apart */
                              : ke.x > R(1.5)                ? R(4) /* bright */
                                                             : R(1); /* plain, and the twins */
            if (!material_emits(&m.materials[i]))
                continue;
            expect_vec(ke, want, want * R(0.5), want * R(0.25));
            seen |= want == R(4) ? 1 : want == R(0.5) ? 2 : 4;
        }
        assert_int_equal(seen, 7);
        mesh_free(&m);
        free(bytes);
    }
}

/* A GLB whose header lies is refused before Assimp reads it (Assimp 5.2.5
 * allocates a chunk's length as its header gives it): a total length of 0
 * with a JSON chunk claiming 2.9 GB (fuzz_import's out-of-memory inputs
 * of 2026-11-29: the chunks were checked only within the total length),
 * a total under a header and a chunk's, a chunk past the file; the file
 * itself loads. */
static void a_glb_that_lies_is_refused(void **state)
{
    (void)state;
    FILE *f = fopen("tests/data/gltf/strength.glb", "rb");
    assert_non_null(f);
    uint8_t *good = malloc(1 << 16), *bytes = malloc(1 << 16);
    const size_t n = fread(good, 1, 1 << 16, f);
    fclose(f);
    assert_true(n > 20 && n < (1 << 16));
    const struct {
        size_t at;
        uint32_t value;
        const char *says;
    } lies[] = {{8, 0, "the GLB header says 0 bytes"},
                {8, 19, "the GLB header says 19 bytes"},
                {12, 0xab070000u, "GLB chunk 0 claims 2869362688 bytes"},
                {8, (uint32_t)n + 1, "the GLB header says"}};
    Mesh m;
    ImportStats st;
    Err err;
    for (size_t i = 0; i <= sizeof lies / sizeof *lies; i++) {
        memcpy(bytes, good, n);
        if (i == sizeof lies / sizeof *lies) {
            if (import_read_memory(bytes, n, "glb", "good.glb", NULL, &m, &st, &err))
                fail_msg("the GLB itself: %s", err.msg);
            mesh_free(&m);
            break;
        }
        memcpy(bytes + lies[i].at, &lies[i].value, 4);
        assert_int_not_equal(import_read_memory(bytes, n, "glb", "lie.glb", NULL, &m, &st, &err), 0);
        if (!strstr(err.msg, lies[i].says) || !strstr(err.msg, "lie.glb"))
            fail_msg("lie %zu: '%s', expected '%s'", i, err.msg, lies[i].says);
    }
    free(good), free(bytes);
}

/* gltf_json.c on bytes that are not what they claim: a GLB cut short, one
 * whose JSON chunk claims more bytes than there are (by one, and by
 * 2^32 - 1), one whose first chunk is not JSON or of another version,
 * JSON that does not parse or stops halfway, materials that are not an
 * array, and members of the wrong types: no materials, or the glTF
 * defaults where a member is wrong, and never a read past the bytes
 * (AddressSanitizer in check-asan). */
static void gltf_json_takes_nothing_from_bad_bytes(void **state)
{
    (void)state;
    GltfMaterials gm;
    const char json[] = "{\"materials\":[{\"name\":\"a\",\"emissiveFactor\":[1,1,1],"
                        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":3}}}]}";
    const uint32_t jl = (uint32_t)strlen(json);
    uint8_t glb[20 + sizeof json];
    memcpy(glb, "glTF", 4);
    const uint32_t head[4] = {2, 20 + jl, jl, 0x4E4F534Au};
    memcpy(glb + 4, head, sizeof head);
    memcpy(glb + 20, json, jl);
    gltf_materials_read(glb, 20 + jl, 1, &gm); /* the good one, as a check that the bad ones are bad */
    assert_int_equal(gm.n, 1);
    assert_float_equal(gm.m[0].strength, 3, 0);
    gltf_materials_free(&gm);
    const size_t cuts[] = {0, 3, 12, 19, 20, 20 + jl / 2, 20 + jl - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof *cuts; i++) {
        gltf_materials_read(glb, cuts[i], 1, &gm);
        assert_int_equal(gm.n, 0);
    }
    const struct {
        size_t at;
        uint32_t value;
    } bad[] = {{12, jl + 1}, {12, UINT32_MAX}, {16, 0x004E4942u /* BIN */}, {4, 1}};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        uint8_t b[sizeof glb];
        memcpy(b, glb, sizeof b);
        memcpy(b + bad[i].at, &bad[i].value, 4);
        gltf_materials_read(b, 20 + jl, 1, &gm);
        assert_int_equal(gm.n, 0);
    }
    const char *texts[] = {"", "not json", "{\"materials\":[{\"name\":", "{\"materials\":{}}", "[1,2,3]",
                           "{\"materials\":7}"};
    for (size_t i = 0; i < sizeof texts / sizeof *texts; i++) {
        gltf_materials_read((const uint8_t *)texts[i], strlen(texts[i]), 0, &gm);
        assert_int_equal(gm.n, 0);
    }
    /* members of the wrong types: the material is there, with glTF's defaults */
    const char *odd = "{\"materials\":[{\"name\":5,\"emissiveFactor\":[1,\"x\",1],"
                      "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5]},"
                      "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":-2},"
                      "\"KHR_materials_specular\":{\"specularFactor\":7,\"specularColorFactor\":[1,\"y\",1]}}}, 3]}";
    gltf_materials_read((const uint8_t *)odd, strlen(odd), 0, &gm);
    assert_int_equal(gm.n, 2);
    assert_string_equal(gm.m[0].name, "");
    assert_float_equal(gm.m[0].emissive[0], 0, 0);
    assert_float_equal(gm.m[0].base[0], 1, 0);
    assert_float_equal(gm.m[0].strength, 1, 0);
    assert_float_equal(gm.m[0].specular, 1, 0);
    assert_int_equal(gm.extra, 0);
    gltf_materials_free(&gm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gltf_materials_map_onto_lanrays),
        cmocka_unit_test(gltf_vertex_colours_multiply_the_base_colour),
        cmocka_unit_test(gltf_samplers_wrap_each_axis),
        cmocka_unit_test(gltf_mask_materials_cut),
        cmocka_unit_test(gltf_texture_transforms_apply),
        cmocka_unit_test(gltf_normal_maps_are_read),
        cmocka_unit_test(gltf_emissive_strength_applies),
        cmocka_unit_test(a_glb_that_lies_is_refused),
        cmocka_unit_test(gltf_json_takes_nothing_from_bad_bytes),
    };
    return cmocka_run_group_tests_name("import", tests, NULL, NULL);
}
