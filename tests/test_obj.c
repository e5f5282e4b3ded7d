/* test_obj.c - the OBJ/MTL reader on good and malformed input. */
#include "helpers.h"

#include <sys/stat.h>

#include "base/fileio.h"
#include "image/image.h"
#include "model/mtl.h"
#include "model/obj.h"
#include "model/tmd.h"

static int parse(const char *text, Mesh *m, ObjStats *st, Err *err, int smooth)
{
    char *buf = strdup(text);
    ObjOptions opt = {.smooth = smooth};
    int rc = obj_parse(buf, strlen(buf), "t.obj", test_tmpdir(), &opt, m, st, err);
    free(buf);
    return rc;
}

static void index_forms_and_negative_indices(void **state)
{
    (void)state;
    const char *text = "# all four corner forms\n"
                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "vn 0 0 1\n"
                       "o thing\ng part\n"
                       "f 1 2 3\n"
                       "f 1/1 2/2 3/3\n"
                       "f 1//1 2//1 3//1\n"
                       "f 1/1/1 2/2/1 3/3/1\n"
                       "f -4/-4/-1 -3/-3/-1 -2/-2/-1\r\n";
    Mesh m;
    ObjStats st;
    Err err;
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(m.tri_count, 5);
    assert_int_equal(st.vertices, 4);
    assert_int_equal(st.groups, 2);
    assert_non_null(m.nrm);
    assert_non_null(m.uv);
    assert_null(m.mat);
    /* the negative-index face is the same as the first */
    assert_memory_equal(&m.pos[0], &m.pos[12], 3 * sizeof(vec3));
    /* texture coordinates of the 2nd face: (0,0) (1,0) (1,1) */
    assert_float_equal(m.uv[6 + 2], 1, 0);
    assert_float_equal(m.uv[6 + 5], 1, 0);
    /* face 1 has no file normals: the flat normal +z */
    assert_float_equal(m.nrm[0].z, 1, R(1e-6));
    mesh_free(&m);
}

/* A UTF-8 byte-order mark is not part of the first line: with it, the
 * first vertex was skipped and every index shifted. */
static void byte_order_mark_is_skipped(void **state)
{
    (void)state;
    Mesh m;
    ObjStats st;
    Err err;
    if (parse("\xEF\xBB\xBF" "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(st.vertices, 3);
    assert_int_equal(m.tri_count, 1);
    assert_float_equal(m.pos[1].x, 1, 0);
    mesh_free(&m);
}

static void polygons_are_triangulated_and_degenerates_dropped(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 3 0\nv 0 2 0\nv 5 5 5\n"
                       "f 1 2 3 4 5\n"   /* pentagon: 3 triangles */
                       "f 1 2 3 5\n"     /* quad: 2 */
                       "f 1 1 2\n"       /* repeated vertex: zero area */
                       "f 1 2 2\n";
    Mesh m;
    ObjStats st;
    Err err;
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(m.tri_count, 5);
    assert_int_equal(st.faces, 4);
    assert_int_equal(st.degenerate, 2);
    /* positions only: no normals, uvs or materials were used */
    assert_null(m.nrm);
    assert_null(m.uv);
    assert_null(m.mat);
    /* the pentagon's area is kept: 2*2 square + triangle of area 1 */
    real area = 0;
    for (int i = 0; i < 3; i++)
        area += v3_len(v3_cross(v3_sub(m.pos[3 * i + 1], m.pos[3 * i]), v3_sub(m.pos[3 * i + 2], m.pos[3 * i]))) / 2;
    assert_float_equal(area, 5, R(1e-5));
    mesh_free(&m);
}

static void materials_from_mtllib(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "%s/t.mtl", test_tmpdir());
    test_write_file(path, "newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 32\nillum 2\n"
                          "newmtl unused\nKd 0 1 0\n"
                          "newmtl blue\nKd 0 0 1\nmap_Kd ignored.png\n");
    const char *text = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                       "f 1 2 3\nusemtl blue\nf 2 4 3\nusemtl red\nf 1 2 4\n";
    Mesh m;
    Err err;
    if (parse(text, &m, NULL, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(m.tri_count, 3);
    assert_non_null(m.mat);
    /* default (for the face before usemtl), blue and red: "unused" is dropped */
    assert_int_equal(m.material_count, 3);
    const Material *blue = &m.materials[m.mat[1]], *red = &m.materials[m.mat[2]];
    assert_float_equal(blue->kd.z, 1, 0);
    assert_float_equal(red->kd.x, 1, 0);
    assert_float_equal(red->ks.y, R(0.5), 0);
    assert_float_equal(red->shininess, 32, 0);
    assert_true(m.mat[0] != m.mat[1] && m.mat[1] != m.mat[2]);
    mesh_free(&m);
}

/* Writes a w x h PNG of rgb texels (and alphas a, or none) as name in the
 * test's folder. */
static void write_png(const char *name, uint32_t w, uint32_t h, const uint8_t *rgb, const uint8_t *a)
{
    Sink png = {0};
    assert_int_equal(image_encode_png_alpha(rgb, a, w, h, &png), 0);
    char path[256];
    snprintf(path, sizeof path, "%s/%s", test_tmpdir(), name);
    FILE *f = fopen(path, "wb");
    fwrite(png.data, 1, png.len, f);
    fclose(f);
    sink_free(&png);
}

/* map_d: a cutout's mask (cutoff 0.5), the same file as map_Kd read once
 * (its alpha the holes); a mask that cannot be read leaves the material
 * solid, with a warning. */
static void map_d_makes_a_cutout(void **state)
{
    (void)state;
    const uint8_t rgb[12] = {255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255}, a[4] = {0, 255, 255, 0};
    write_png("leaf.png", 2, 2, rgb, a);
    char path[256];
    snprintf(path, sizeof path, "%s/cut.mtl", test_tmpdir());
    test_write_file(path, "newmtl leaf\nmap_Kd leaf.png\nmap_d leaf.png\nnewmtl lost\nmap_d nothere.png\n");
    const char *text = "mtllib cut.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                       "usemtl leaf\nf 1/1 2/2 3/3\nusemtl lost\nf 1/1 3/3 2/2\n";
    Mesh m;
    ObjStats st;
    Err err;
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    const Material *leaf = &m.materials[m.mat[0]], *lost = &m.materials[m.mat[1]];
    assert_true(material_cuts(leaf));
    assert_float_equal(leaf->cutoff, R(0.5), 0);
    assert_int_equal(leaf->mask, leaf->texture); /* one file, read once */
    assert_int_equal(m.texture_count, 1);
    assert_non_null(m.textures[leaf->mask]->alpha);
    assert_false(material_cuts(lost));
    assert_int_equal(st.missing_textures, 1);
    assert_int_equal(st.warnings, 1);
    mesh_free(&m);
}

/* norm is a normal map, -bm its strength; bump and map_Bump are one where
 * the image is not grey (Blender writes its normal maps so), and a grey
 * one is a height map, -bm the height of its white (1 when not given). */
static void norm_and_coloured_bump_maps_are_normal_maps(void **state)
{
    (void)state;
    const uint8_t blue[6] = {128, 128, 255, 200, 128, 230}, grey[6] = {10, 10, 10, 200, 200, 200};
    write_png("n.png", 2, 1, blue, NULL);
    write_png("h.png", 2, 1, grey, NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/nm.mtl", test_tmpdir());
    test_write_file(path, "newmtl a\nnorm -bm 0.25 n.png\nnewmtl b\nmap_Bump -bm 1.0 n.png\nnewmtl c\nbump h.png\n"
                          "newmtl d\nbump h.png\nnorm n.png\nnewmtl e\nbump -bm 0.02 h.png\n");
    const char *text = "mtllib nm.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                       "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 1/1 3/3 2/2\nusemtl c\nf 1/1 2/2 3/3\n"
                       "usemtl d\nf 1/1 3/3 2/2\nusemtl e\nf 1/1 2/2 3/3\n";
    Mesh m;
    ObjStats st;
    Err err;
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    const Material *a = &m.materials[m.mat[0]], *b = &m.materials[m.mat[1]], *c = &m.materials[m.mat[2]],
                   *d = &m.materials[m.mat[3]], *e = &m.materials[m.mat[4]];
    assert_true(material_bumps(a));
    assert_float_equal(a->normal_scale, 0.25, 0);
    assert_true(material_bumps(b));
    assert_float_equal(b->normal_scale, 1, 0);
    assert_int_equal(a->normal_map, b->normal_map); /* one file, read once */
    assert_false(material_heights(a) || material_heights(b));
    assert_true(material_bumps(c) && material_heights(c)); /* the grey one: a height map */
    assert_float_equal(c->bump_height, 1, 0);
    assert_int_not_equal(c->normal_map, a->normal_map);
    assert_true(material_bumps(d)); /* norm wins over the grey bump */
    assert_false(material_heights(d));
    assert_int_equal(d->normal_map, a->normal_map);
    assert_true(material_heights(e));
    assert_float_equal(e->bump_height, 0.02, 1e-7);
    assert_int_equal(e->normal_map, c->normal_map); /* one file, read once */
    assert_int_equal(m.texture_count, 2);
    assert_int_equal(st.warnings, 0);
    mesh_free(&m);
}

/* map_Ke is the emission's texture: times Ke, or alone (Ke 1) where the
 * material gives no Ke; with Ke 0 nothing glows. */
static void map_Ke_is_the_emission_texture(void **state)
{
    (void)state;
    const uint8_t rgb[6] = {0, 0, 0, 255, 200, 100};
    write_png("e.png", 2, 1, rgb, NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/ke.mtl", test_tmpdir());
    test_write_file(path, "newmtl alone\nmap_Ke e.png\nnewmtl times\nKe 0.5 0.25 0.5\nmap_Ke e.png\n"
                          "newmtl off\nKe 0 0 0\nmap_Ke e.png\n");
    const char *text = "mtllib ke.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                       "usemtl alone\nf 1/1 2/2 3/3\nusemtl times\nf 1/1 3/3 2/2\nusemtl off\nf 1/1 2/2 3/3\n";
    Mesh m;
    ObjStats st;
    Err err;
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    const Material *alone = &m.materials[m.mat[0]], *times = &m.materials[m.mat[1]], *off = &m.materials[m.mat[2]];
    assert_true(material_emit_mapped(alone) && material_emits(alone));
    assert_float_equal(alone->ke.y, 1, 0);
    assert_true(material_emit_mapped(times));
    assert_float_equal(times->ke.y, 0.25, 0);
    assert_int_equal(times->emit_map, alone->emit_map); /* one file, read once */
    assert_false(material_emits(off));
    assert_int_equal(m.texture_count, 1);
    assert_int_equal(st.warnings, 0);
    mesh_free(&m);
}

static void smooth_normals_average_faces(void **state)
{
    (void)state;
    /* two faces folded at 90 degrees along the shared edge 1-2 */
    const char *text = "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\n";
    Mesh m;
    Err err;
    if (parse(text, &m, NULL, &err, 1))
        fail_msg("%s", err.msg);
    assert_non_null(m.nrm);
    /* vertex 1 is shared: its normal is the mean of -z and -x (area weighted, equal areas) */
    vec3 n = m.nrm[0];
    assert_float_equal(v3_len(n), 1, R(1e-5));
    assert_float_equal(fabs(n.x), fabs(n.z), R(1e-5));
    assert_float_equal(n.y, 0, R(1e-6));
    mesh_free(&m);
}

/* Smoothing groups (s): faces of one group meet smoothly at a vertex they
 * share, faces of two groups at a crease, faces after `s off` stay flat;
 * --smooth smooths those together too. */
static void smoothing_groups_share_normals(void **state)
{
    (void)state;
    /* a roof: two faces folded along the edge 1-2 (normals -z and -x),
     * and a third beyond the fold (normal +y) */
    const char *roof = "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nv 0 0 -1\n"
                       "s %s\nf 1 2 3\ns %s\nf 1 4 2\ns %s\nf 1 3 5\n";
    char text[256];
    Mesh m;
    Err err;
    ObjStats st;
    /* one group: vertex 1's normal is shared by all three faces */
    snprintf(text, sizeof text, roof, "1", "1", "1");
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_non_null(m.nrm);
    assert_int_equal(st.smoothing, 3);
    assert_int_equal(st.smoothed, 3);
    const vec3 a = m.nrm[0], b = m.nrm[3], c = m.nrm[6]; /* vertex 1 in each face */
    assert_float_equal(v3_len(a), 1, R(1e-5));
    assert_true(v3_len(v3_sub(a, b)) < R(1e-6) && v3_len(v3_sub(a, c)) < R(1e-6));
    mesh_free(&m);
    /* two groups: faces 1 and 2 smooth together, face 3 apart (crease) */
    snprintf(text, sizeof text, roof, "1", "1", "2");
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_true(v3_len(v3_sub(m.nrm[0], m.nrm[3])) < R(1e-6));
    assert_float_equal(fabs(m.nrm[0].x), fabs(m.nrm[0].z), R(1e-5)); /* the mean of -z and -x */
    assert_float_equal(m.nrm[0].y, 0, R(1e-6));
    const vec3 n3 = v3_norm(v3_cross(v3_sub(m.pos[7], m.pos[6]), v3_sub(m.pos[8], m.pos[6])));
    for (int k = 6; k < 9; k++) /* face 3 alone in its group: its own face normal at every corner */
        assert_true(v3_len(v3_sub(m.nrm[k], n3)) < R(1e-6));
    /* the fold's far corners: vertex 3 is shared by faces 1 and 3 only, of two groups */
    assert_true(v3_len(v3_sub(m.nrm[2], m.nrm[7])) > R(0.5));
    mesh_free(&m);
    /* s off and s 0: flat; face 2 flat between two smooth ones */
    snprintf(text, sizeof text, roof, "1", "off", "1");
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(st.smoothed, 2);
    const vec3 n2 = v3_norm(v3_cross(v3_sub(m.pos[4], m.pos[3]), v3_sub(m.pos[5], m.pos[3])));
    for (int k = 3; k < 6; k++)
        assert_true(v3_len(v3_sub(m.nrm[k], n2)) < R(1e-6));
    assert_true(v3_len(v3_sub(m.nrm[0], m.nrm[6])) < R(1e-6)); /* faces 1 and 3 share group 1 */
    assert_true(v3_len(v3_sub(m.nrm[0], n2)) > R(0.1));
    mesh_free(&m);
    /* every face flat: no normals at all; with --smooth all smooth together */
    snprintf(text, sizeof text, roof, "off", "0", "off");
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_null(m.nrm);
    assert_int_equal(st.smoothed, 0);
    mesh_free(&m);
    if (parse(text, &m, &st, &err, 1))
        fail_msg("%s", err.msg);
    assert_int_equal(st.smoothed, 3);
    assert_true(v3_len(v3_sub(m.nrm[0], m.nrm[3])) < R(1e-6) && v3_len(v3_sub(m.nrm[0], m.nrm[6])) < R(1e-6));
    mesh_free(&m);
    /* a group number that is none: a warning, the faces flat */
    snprintf(text, sizeof text, roof, "1", "x", "1");
    if (parse(text, &m, &st, &err, 0))
        fail_msg("%s", err.msg);
    assert_int_equal(st.warnings, 1);
    assert_int_equal(st.smoothed, 2);
    mesh_free(&m);
}

static void expect_error(const char *text, const char *what)
{
    Mesh m;
    Err err = {{0}};
    assert_int_equal(parse(text, &m, NULL, &err, 0), -1);
    assert_contains(err.msg, what);
}

static void malformed_input_names_file_and_line(void **state)
{
    (void)state;
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "t.obj:4: bad vertex index in face corner '4'");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "t.obj:4: bad vertex index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "t.obj:4: bad vertex index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "t.obj:4: bad texture coordinate index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//1 3//1\n", "t.obj:4: bad normal index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "t.obj:4: bad texture coordinate index");
    expect_error("v 0 0 0\nv 1 0 0\nf 1 2\n", "t.obj:3: a face needs at least 3 corners, this one has 2");
    expect_error("v 0 zero 0\n", "t.obj:1: expected 3 finite numbers after 'v'");
    expect_error("v 0 0\n", "t.obj:1: expected 3 finite numbers after 'v'");
    expect_error("v 1e999 0 0\n", "t.obj:1: expected 3 finite numbers after 'v'");
    expect_error("vn 0 nan 1\n", "t.obj:1: expected 3 finite numbers after 'vn'");
    expect_error("vt\n", "t.obj:1: expected 1 to 3 finite numbers after 'vt'");
    /* an undefined material and a missing library are warnings now
     * (exporters_habits_convert_with_warnings); a malformed library is not */
    char path[256];
    snprintf(path, sizeof path, "%s/bad.mtl", test_tmpdir());
    test_write_file(path, "newmtl a\nKd 1 0\n");
    expect_error("mtllib bad.mtl\n", "bad.mtl:2: expected 3 non-negative numbers after Kd");
}

/* The habits of real exporters (tests/data/obj): each file converts, with
 * the warnings the reader counts, and its materials land where they should. */
typedef struct {
    int lines;
    char last[1024];
} Heard;

static void hear(void *ctx, const char *msg)
{
    Heard *h = ctx;
    h->lines++;
    snprintf(h->last, sizeof h->last, "%s", msg);
}

static void read_file(const char *name, Mesh *m, ObjStats *st, Heard *h, int strict, int expect_rc)
{
    char path[256];
    snprintf(path, sizeof path, "tests/data/obj/%s", name);
    ObjOptions opt = {.strict = strict, .warn = hear, .warn_ctx = h};
    Err err = {{0}};
    memset(h, 0, sizeof *h);
    int rc = obj_read(path, &opt, m, st, &err);
    if ((rc == 0) != (expect_rc == 0))
        fail_msg("%s: rc %d, expected %d (%s)", name, rc, expect_rc, err.msg);
    if (rc)
        snprintf(h->last, sizeof h->last, "%s", err.msg);
}

static void exporters_habits_convert_with_warnings(void **state)
{
    (void)state;
    Mesh m;
    ObjStats st;
    Heard h;
    /* usemtl Default and no library: the default material, one warning naming the line */
    read_file("undefined-usemtl.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 2);
    assert_int_equal(st.undefined_mtl, 1);
    assert_int_equal(h.lines, 1);
    assert_non_null(strstr(h.last, "undefined-usemtl.obj:6:"));
    mesh_free(&m);
    read_file("missing-mtllib.obj", &m, &st, &h, 0, 0);
    assert_int_equal(st.missing_mtllib, 1);
    assert_int_equal(st.undefined_mtl, 1);
    assert_int_equal(st.warnings, 2);
    mesh_free(&m);
    /* a library whose file name and material names hold spaces, and an unnamed material */
    read_file("spaces.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 2);
    assert_non_null(m.mat);
    assert_int_equal(m.material_count, 2);
    assert_float_equal(m.materials[m.mat[0]].kd.x, 1, 0); /* "red paint" */
    assert_float_equal(m.materials[m.mat[1]].kd.z, 1, 0); /* the unnamed one: blue */
    assert_int_equal(st.warnings, 1);                       /* usemtl without a name */
    mesh_free(&m);
    /* vertex colours in a model without materials: kept, per corner, no warning (x y z r g b and x y z w r g b) */
    read_file("colours.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 2);
    assert_int_equal(st.coloured, 4);
    assert_int_equal(st.warnings, 0);
    assert_true(st.colours);
    assert_non_null(m.col);
    assert_null(m.mat);
    assert_true(m.col[0].x == 1 && m.col[0].y == 0 && m.col[1].y == 1 && m.col[2].z == 1); /* fan 1 2 3 */
    assert_true(m.col[5].x == 1 && m.col[5].y == 1 && m.col[5].z == 1);                    /* fan 1 3 4: the w form */
    assert_float_equal(m.pos[5].y, 1, 0);
    mesh_free(&m);
    /* beside materials: ignored, one warning naming the first coloured vertex */
    read_file("colours-mtl.obj", &m, &st, &h, 0, 0);
    assert_null(m.col);
    assert_true(st.colours_ignored);
    assert_int_equal(st.warnings, 1);
    assert_non_null(strstr(h.last, "colours-mtl.obj:2: vertex colours ignored"));
    mesh_free(&m);
    /* whole numbers up to 255: read as 0..255, with a warning */
    read_file("colours-255.obj", &m, &st, &h, 0, 0);
    assert_int_equal(st.warnings, 1);
    assert_non_null(strstr(h.last, "colours-255.obj:2: vertex colours are whole numbers up to 255"));
    assert_true(m.col[0].x == 1 && m.col[1].y == 1);
    assert_float_equal(m.col[2].z, R(0.2), 1e-6);
    mesh_free(&m);
    /* some vertices without a colour: the default material's diffuse colour */
    read_file("colours-partial.obj", &m, &st, &h, 0, 0);
    assert_int_equal(st.warnings, 0);
    assert_int_equal(st.coloured, 2);
    assert_true(m.col[0].x == material_default().kd.x && m.col[1].y == 1 && m.col[1].x == 0);
    assert_true(m.col[5].x == R(0.5) && m.col[5].y == R(0.25));
    mesh_free(&m);
    /* CRLF, tabs, a 100000-byte line, a continued face, a backslash path, no final newline */
    read_file("habits.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 2);
    assert_int_equal(st.warnings, 0);
    assert_non_null(m.mat);
    assert_float_equal(m.materials[0].kd.y, 1, 0); /* green, from sub\habit.mtl */
    mesh_free(&m);
    /* a library after the faces that use its materials: resolved at the end, no warning */
    read_file("late-mtllib.obj", &m, &st, &h, 1, 0);
    assert_int_equal(m.tri_count, 2);
    assert_int_equal(m.material_count, 1);
    assert_float_equal(m.materials[m.mat[1]].kd.y, 1, 0); /* green */
    mesh_free(&m);
    /* UTF-16, both byte orders, the library too */
    for (int be = 0; be < 2; be++) {
        read_file(be ? "utf16be.obj" : "utf16le.obj", &m, &st, &h, 0, 0);
        assert_int_equal(m.tri_count, 2);
        assert_int_equal(st.warnings, 0);
        assert_float_equal(m.materials[0].kd.z, 1, 0);
        mesh_free(&m);
    }
    /* what a triangle renderer cannot use: skipped, counted by kind, one warning per kind */
    read_file("skipped.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 1);
    assert_int_equal(st.smoothing, 2); /* s 1, s off: read, not skipped; the face after them flat */
    assert_int_equal(st.smoothed, 0);
    assert_null(m.nrm);
    assert_int_equal(st.skipped[OBJ_SKIP_LINE], 1);
    assert_int_equal(st.skipped[OBJ_SKIP_POINT], 1);
    assert_int_equal(st.skipped[OBJ_SKIP_FREEFORM], 5);
    assert_int_equal(st.skipped[OBJ_SKIP_MERGING], 1);
    assert_int_equal(st.skipped[OBJ_SKIP_LOD], 1);
    assert_int_equal(st.skipped[OBJ_SKIP_DISPLAY], 1);
    assert_int_equal(st.skipped[OBJ_SKIP_UNKNOWN], 1);
    assert_int_equal(h.lines, 7);
    mesh_free(&m);
}

/* Ka, Ke, Ni, d, Tr and illum: read, checked and kept, and mapped onto
 * reflection, refraction and emission (mtl_optics) for the used materials. */
static void material_extras_are_kept_and_mapped(void **state)
{
    (void)state;
    MtlLib lib = {0};
    Err err;
    if (mtl_read(&lib, "tests/data/obj/effects.mtl", &err))
        fail_msg("%s", err.msg);
    assert_int_equal(lib.count, 5);
    const MtlExtra *plain = &lib.extra[0], *glass = &lib.extra[1], *mirror = &lib.extra[2], *lamp = &lib.extra[3],
                   *unused = &lib.extra[4];
    assert_float_equal(plain->ka.y, R(0.1), 1e-6);
    assert_float_equal(plain->ni, R(1.45), 1e-6);
    assert_true(plain->d == 1 && plain->illum == 2 && plain->line == 2);
    assert_true(glass->d == R(0.4) && glass->illum == 7 && glass->ni == R(1.5));
    assert_true(mirror->d == 1 && mirror->illum == 3); /* Tr 0: opaque */
    assert_true(lamp->ke.x == 1 && lamp->ke.z == R(0.25) && lamp->d == 1 && lamp->illum == -1);
    assert_true(unused->d == R(0.5) && unused->illum == 4);
    assert_string_equal(lib.files[unused->file], "tests/data/obj/effects.mtl");
    /* the mapping: plain stays plain; glass is a dielectric of Ni 1.5 keeping
     * d = 0.4 of its diffuse colour and passing 0.6; the mirror reflects Ks;
     * the lamp emits Ke; a glass illum without Ni is 1.5, without d clear */
    Material m = lib.mats[0];
    assert_int_equal(mtl_optics(plain, &m), 0);
    assert_true(!material_reflects(&m) && !material_dielectric(&m) && !material_emits(&m));
    m = lib.mats[1];
    assert_int_equal(mtl_optics(glass, &m), 1);
    assert_true(m.ior == R(1.5) && !material_reflects(&m));
    assert_float_equal(m.kt.x, R(0.6), 1e-6);
    assert_float_equal(m.kd.x, R(0.9) * R(0.4), 1e-6);
    m = lib.mats[2];
    assert_int_equal(mtl_optics(mirror, &m), 1);
    assert_true(m.kr.x == 1 && m.kr.y == 1 && m.kr.z == 1 && !material_dielectric(&m));
    m = lib.mats[3];
    assert_int_equal(mtl_optics(lamp, &m), 1);
    assert_true(m.ke.x == 1 && m.ke.y == R(0.5) && m.ke.z == R(0.25));
    m = lib.mats[4];
    assert_int_equal(mtl_optics(unused, &m), 1);
    assert_true(m.ior == R(1.5) && m.kt.x == R(0.5));
    char why[160];
    assert_null(material_problem(&m, why, sizeof why));
    /* a dissolve alone blends, unbent */
    MtlExtra half = *plain;
    half.d = R(0.25);
    m = lib.mats[0];
    assert_int_equal(mtl_optics(&half, &m), 1);
    assert_true(m.ior == R(1) && m.kt.x == R(0.75));
    assert_float_equal(m.kd.x, R(0.5) * R(0.25), 1e-6);
    mtl_free(&lib);

    /* through the reader, and into a .tmd (version 4) and back */
    Mesh mesh;
    ObjStats st;
    Heard h;
    read_file("effects.obj", &mesh, &st, &h, 0, 0);
    assert_int_equal(mesh.material_count, 4);
    assert_int_equal(st.optics_mtl, 3); /* glass, mirror, lamp; not plain, and not the unused one */
    assert_int_equal(h.lines, 0);
    int dielectrics = 0, mirrors = 0, lamps = 0;
    for (uint32_t i = 0; i < mesh.material_count; i++) {
        dielectrics += material_dielectric(&mesh.materials[i]);
        mirrors += material_reflects(&mesh.materials[i]);
        lamps += material_emits(&mesh.materials[i]);
    }
    assert_true(dielectrics == 1 && mirrors == 1 && lamps == 1);
    BvhOptions opt = bvh_options_default(BVH_SAH);
    Model *model, *back;
    assert_int_equal(model_from_mesh(&model, &mesh, &opt, NULL), 0);
    void *data;
    size_t len;
    const int wide = sizeof(real) == 8; /* the double build's own numbers, as it sends them */
    assert_int_equal(tmd_encode(model, wide, &data, &len, NULL), 0);
    uint32_t version;
    memcpy(&version, (const char *)data + 8, 4);
    assert_int_equal(version, TMD_VERSION);
    assert_int_equal(tmd_decode(data, len, "effects.tmd", &back, &err), 0);
    for (uint32_t i = 0; i < model->material_count; i++) {
        const Material *a = &model->materials[i], *b = &back->materials[i];
        assert_true(a->ior == b->ior && a->kt.x == b->kt.x && a->kr.y == b->kr.y && a->ke.z == b->ke.z);
    }
    model_destroy(back);
    /* a material's optics out of range is refused, naming the material */
    for (uint32_t i = 0; i < model->material_count; i++)
        if (material_dielectric(&model->materials[i]))
            model->materials[i].ior = 40;
    free(data);
    assert_int_equal(tmd_encode(model, wide, &data, &len, NULL), 0);
    assert_int_equal(tmd_decode(data, len, "effects.tmd", &back, &err), -1);
    assert_non_null(strstr(err.msg, "'ior' must be 0 or from 0.0625 to 16"));
    free(data);
    model_destroy(model);
    mesh_free(&mesh);

    const struct {
        const char *text, *says;
    } bad[] = {
        {"newmtl a\nd 1.5\n", "t.mtl:2: expected one number from 0 to 1 after d"},
        {"newmtl a\nTr x\n", "t.mtl:2: expected one number from 0 to 1 after Tr"},
        {"newmtl a\nNi -1\n", "t.mtl:2: expected one number from 0 to 100 after Ni"},
        {"newmtl a\nillum 11\n", "t.mtl:2: expected a whole number from 0 to 10 after illum"},
        {"newmtl a\nillum 2.5\n", "t.mtl:2: expected a whole number from 0 to 10 after illum"},
        {"newmtl a\nKa -1 0 0\n", "t.mtl:2: expected 3 non-negative numbers after Ka"},
        {"newmtl a\nKe 1 nan 0\n", "t.mtl:2: expected 3 non-negative numbers after Ke"},
        {"d 0.5\n", "t.mtl:1: d before any newmtl"},
        {"map_d m.png\n", "t.mtl:1: map_d before any newmtl"},
        {"newmtl a\nmap_d\n", "t.mtl:2: map_d: bad option or no file name"},
        {"newmtl a\nmap_d -zz 1 m.png\n", "t.mtl:2: map_d: bad option or no file name"},
        {"newmtl a\nmap_Kd -s\n", "t.mtl:2: map_Kd: bad option or no file name"},
        {"bump m.png\n", "t.mtl:1: bump before any newmtl"},
        {"newmtl a\nnorm -bm\n", "t.mtl:2: norm: bad option or no file name"},
        {"newmtl a\nmap_Bump -bm inf n.png\n", "t.mtl:2: map_Bump: bad option or no file name"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char text[64];
        snprintf(text, sizeof text, "%s", bad[i].text);
        MtlLib l = {0};
        Err e = {{0}};
        assert_int_equal(mtl_parse(&l, text, strlen(text), "t.mtl", &e), -1);
        if (!strstr(e.msg, bad[i].says))
            fail_msg("'%s' gives '%s', not '%s'", bad[i].text, e.msg, bad[i].says);
        mtl_free(&l);
    }
}

/* Files a model names, found as written, by their last component, or by it in another case. */
static void named_files_are_found_near(void **state)
{
    (void)state;
    char dir[256], path[512], buf[512];
    snprintf(dir, sizeof dir, "%s/near", test_tmpdir());
    mkdir(dir, 0700);
    snprintf(path, sizeof path, "%s/wood.png", dir);
    test_write_file(path, "x");
    assert_int_equal(file_find_near(dir, "wood.png", buf, sizeof buf), FILE_AS_WRITTEN);
    assert_string_equal(buf, path);
    assert_int_equal(file_find_near(dir, "C:/Users/a/wood.png", buf, sizeof buf), FILE_BY_NAME);
    assert_string_equal(buf, path);
    assert_int_equal(file_find_near(dir, "tex/WOOD.PNG", buf, sizeof buf), FILE_BY_NAME_CASE);
    assert_string_equal(buf, path);
    assert_int_equal(file_find_near(dir, "tex/stone.png", buf, sizeof buf), FILE_NOT_FOUND);
    snprintf(path, sizeof path, "%s/tex/stone.png", dir);
    assert_string_equal(buf, path); /* as written, for the message */
    assert_int_equal(file_find_near(dir, "tex/", buf, sizeof buf), FILE_NOT_FOUND);
    /* a path written on Windows, '\\' its separator: as written, relative */
    assert_int_equal(file_find_near(dir, ".\\wood.png", buf, sizeof buf), FILE_AS_WRITTEN);
    /* the end of the written path under the folder or one above: a model in
     * near/car/ whose texture was D:\\work\\near\\tex\\Stone.PNG on the machine
     * that wrote it, now near/tex/stone.png */
    char car[512];
    snprintf(car, sizeof car, "%s/car", dir);
    mkdir(car, 0700);
    snprintf(path, sizeof path, "%s/tex", dir);
    mkdir(path, 0700);
    snprintf(path, sizeof path, "%s/tex/stone.png", dir);
    test_write_file(path, "x");
    assert_int_equal(file_find_near(car, "D:\\work\\near\\tex\\Stone.PNG", buf, sizeof buf), FILE_NEARBY);
    struct stat found, stone; /* the very file, whichever way the path goes */
    assert_int_equal(stat(buf, &found), 0);
    assert_int_equal(stat(path, &stone), 0);
    assert_true(found.st_ino == stone.st_ino && found.st_dev == stone.st_dev);
    assert_int_equal(file_find_near(car, "..\\tex\\stone.png", buf, sizeof buf), FILE_AS_WRITTEN);
    /* a tail that names no file there, or climbs: not found */
    assert_int_equal(file_find_near(car, "D:/work/other/stone.png", buf, sizeof buf), FILE_NOT_FOUND);
    assert_int_equal(file_find_near(car, "D:/work/../gone.png", buf, sizeof buf), FILE_NOT_FOUND);
    assert_string_equal(file_found_how(FILE_NEARBY, "the model"), "the end of its path, in a folder near the model");
}

static void wrong_data_stays_an_error(void **state)
{
    (void)state;
    Mesh m;
    ObjStats st;
    Heard h;
    const struct {
        const char *file, *says;
    } cases[] = {
        {"index-zero.obj", "index-zero.obj:5: bad vertex index"},
        {"index-range.obj", "index-range.obj:5: bad vertex index"},
        {"two-corners.obj", "two-corners.obj:5: a face needs at least 3 corners"},
        {"not-a-number.obj", "not-a-number.obj:2: expected 3 finite numbers"},
        {"colours-negative.obj", "colours-negative.obj:2: a vertex colour below 0"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        read_file(cases[i].file, &m, &st, &h, 0, -1);
        if (!strstr(h.last, cases[i].says))
            fail_msg("%s: '%s' does not say '%s'", cases[i].file, h.last, cases[i].says);
    }
    /* lines and points only, or nothing: it reads, with no triangle (obj2tmd refuses it) */
    read_file("lines-only.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 0);
    mesh_free(&m);
    read_file("empty.obj", &m, &st, &h, 0, 0);
    assert_int_equal(m.tri_count, 0);
    mesh_free(&m);
    /* --strict: the first warning is an error naming file and line */
    read_file("undefined-usemtl.obj", &m, &st, &h, 1, -1);
    assert_non_null(strstr(h.last, "undefined-usemtl.obj:6: material 'Default'"));
    read_file("skipped.obj", &m, &st, &h, 1, -1);
    assert_non_null(strstr(h.last, "skipped.obj:7: 'l' skipped"));
    read_file("habits.obj", &m, &st, &h, 1, 0); /* nothing to warn about */
    mesh_free(&m);
    read_file("colours.obj", &m, &st, &h, 1, 0); /* kept colours are no warning */
    mesh_free(&m);
    read_file("colours-mtl.obj", &m, &st, &h, 1, -1);
    assert_non_null(strstr(h.last, "colours-mtl.obj:2: vertex colours ignored"));
}

/* A triangle is degenerate by its normal's largest component, not its
 * squared length, which overflowed at 1e10 (and underflowed at 1e-11)
 * and dropped every triangle of a model measured in such units; a
 * straight or pointlike one, or one with a coordinate not finite, still is. */
static void degenerates_are_told_at_any_scale(void **state)
{
    (void)state;
    const real scales[] = {R(1e-15), R(1e-11), R(1e-9), 1, R(1e9), R(1e10), R(1e15)};
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        const real k = scales[i];
        const vec3 tri[3] = {v3(0, 0, 0), v3(k, 0, 0), v3(0, k, 0)};
        const vec3 line[3] = {v3(0, 0, 0), v3(k, k, 0), v3(2 * k, 2 * k, 0)};
        const vec3 point[3] = {v3(k, k, k), v3(k, k, k), v3(k, k, k)};
        if (mesh_tri_is_degenerate(tri))
            fail_msg("a right triangle of side %g taken for degenerate", (double)k);
        assert_true(mesh_tri_is_degenerate(line));
        assert_true(mesh_tri_is_degenerate(point));
    }
    const vec3 inf[3] = {v3(0, 0, 0), v3(REAL_INF, 0, 0), v3(0, 1, 0)};
    assert_true(mesh_tri_is_degenerate(inf));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(index_forms_and_negative_indices),
        cmocka_unit_test(exporters_habits_convert_with_warnings),
        cmocka_unit_test(wrong_data_stays_an_error),
        cmocka_unit_test(named_files_are_found_near),
        cmocka_unit_test(byte_order_mark_is_skipped),
        cmocka_unit_test(polygons_are_triangulated_and_degenerates_dropped),
        cmocka_unit_test(degenerates_are_told_at_any_scale),
        cmocka_unit_test(materials_from_mtllib),
        cmocka_unit_test(map_d_makes_a_cutout),
        cmocka_unit_test(norm_and_coloured_bump_maps_are_normal_maps),
        cmocka_unit_test(map_Ke_is_the_emission_texture),
        cmocka_unit_test(material_extras_are_kept_and_mapped),
        cmocka_unit_test(smooth_normals_average_faces),
        cmocka_unit_test(smoothing_groups_share_normals),
        cmocka_unit_test(malformed_input_names_file_and_line),
    };
    return cmocka_run_group_tests_name("obj", tests, NULL, NULL);
}
