/* test_fields.c - the scene's field tables against what uses them: every
 * key of every directive, given a value the table allows, lands where the
 * table says, travels the wire unchanged, and is in docs/scene.md's table
 * for its directive as field_doc prints it.
 *
 *   test_fields                 the tests
 *   test_fields --write         rewrites the docs' tables (make scene-doc) */
#include "helpers.h"

#include <stdio.h>

#include "base/fileio.h"
#include "scene/scene_fields.h"
#include "scene/scene_parse.h"

#define DOC "docs/scene.md"
#define PROTOCOL "docs/protocol.md"

/* The table of kind k as docs/scene.md holds it (or its wire layout, as
 * docs/protocol.md does), between its markers. */
static char *doc_table(const FieldKind *k, int wire)
{
    Sink out = {0};
    char open[64];
    snprintf(open, sizeof open, "<!-- %s %s -->\n", wire ? "wire" : "fields", k->name);
    sink_put(&out, open, strlen(open));
    if (wire)
        field_wire_doc(k, &out);
    else
        field_doc(k, &out);
    sink_put(&out, "<!-- end -->", 13);
    return (char *)out.data;
}

/* Rewrites each table of path in place (the prose around them stays). */
static int write_tables(const char *path, int wire)
{
    char *text;
    size_t len;
    Err err;
    if (file_read_all(path, 1 << 24, &text, &len, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    for (const FieldKind *const *k = scene_kinds; *k; k++) {
        if (wire && *k == &model_kind) /* not on the wire */
            continue;
        char open[64];
        snprintf(open, sizeof open, "<!-- %s %s -->", wire ? "wire" : "fields", (*k)->name);
        char *a = strstr(text, open), *b = a ? strstr(a, "<!-- end -->") : NULL;
        if (!b) {
            fprintf(stderr, "%s: no '%s' ... '<!-- end -->'\n", path, open);
            free(text);
            return 1;
        }
        char *table = doc_table(*k, wire);
        size_t before = (size_t)(a - text), after = strlen(b + 12);
        char *next = malloc(before + strlen(table) + after + 1);
        memcpy(next, text, before);
        memcpy(next + before, table, strlen(table));
        memcpy(next + before + strlen(table), b + 12, after + 1);
        free(table);
        free(text);
        text = next;
    }
    FILE *f = fopen(path, "w");
    int rc = !f || fputs(text, f) < 0;
    if (f)
        rc |= fclose(f) != 0;
    free(text);
    return rc;
}

/* docs/scene.md shows every directive's table as field_doc prints it, and
 * docs/protocol.md every item's wire layout as field_wire_doc does: a key
 * added to a table and not to the docs (or the other way) fails here. */
static void docs_show(const char *doc, int wire)
{
    char *text;
    size_t len;
    Err err;
    if (file_read_all(doc, 1 << 24, &text, &len, &err))
        fail_msg("%s", err.msg);
    for (const FieldKind *const *k = scene_kinds; *k; k++) {
        if (wire && *k == &model_kind)
            continue;
        char *table = doc_table(*k, wire);
        if (!strstr(text, table)) {
            /* name the first line of the table that the docs lack */
            char *line = table;
            while (line && *line) {
                char *end = strchr(line, '\n');
                size_t n = end ? (size_t)(end - line) : strlen(line);
                char want[1024];
                snprintf(want, sizeof want, "%.*s", (int)(n < 1000 ? n : 1000), line);
                if (!strstr(text, want))
                    fail_msg("%s: the %s table differs at: %s (make scene-doc rewrites it)", doc, (*k)->name, want);
                line = end ? end + 1 : NULL;
            }
            fail_msg("%s: the %s table is not as printed from its fields (make scene-doc)", doc, (*k)->name);
        }
        free(table);
    }
    free(text);
}

static void docs_show_every_table(void **state)
{
    (void)state;
    docs_show(DOC, 0);
    docs_show(PROTOCOL, 1);
}

/* A value the field allows and that is not its default, as scene-file text
 * into buf, and as numbers into v (ints as reals). */
static void sample_value(const Field *f, int salt, char *buf, size_t size, real *v)
{
    int n = f->type == FIELD_VEC ? 3 : f->type == FIELD_REALS ? f->n : 1;
    buf[0] = 0;
    if (f->type == FIELD_FLAG) {
        v[0] = 1;
        return;
    }
    for (int j = 0; j < n; j++) {
        double lo = f->lo <= -FIELD_INF ? -4 : f->lo, hi = f->hi >= FIELD_INF ? lo + 8 : f->hi;
        double x = lo + (hi - lo) * (0.25 + 0.125 * ((j + salt) % 4));
        if (f->type == FIELD_WHOLE)
            x = floor(x) > lo || !(f->flags & FIELD_LO_OPEN) ? floor(x) : floor(x) + 1;
        if (f->type == FIELD_CHOICE) {
            int words = 0;
            while (f->words[words])
                words++;
            x = ((int)f->def + 1) % words;
            snprintf(buf, size, "%s", f->words[(int)x]);
            v[0] = (real)x;
            return;
        }
        if (x == f->def)
            x = (x + hi) / 2;
        v[j] = (real)x;
        size_t l = strlen(buf);
        snprintf(buf + l, size - l, "%s%.17g", j ? " " : "", x);
    }
}

/* The item a parsed scene holds for kind k, as the kind's struct (or spec). */
static const void *parsed_item(const Scene *s, const FieldKind *k, void *spec)
{
    if (k == &material_kind)
        return &s->materials[s->material_count - 1];
    if (k == &sphere_kind)
        return &s->spheres[0];
    if (k == &plane_kind)
        return &s->planes[0];
    if (k == &instance_kind)
        return &s->instances[0];
    if (k == &triangle_kind) {
        *(TriSpec *)spec = tri_spec(s, 0);
        return spec;
    }
    if (k == &light_kind) {
        memset(spec, 0, sizeof(LightSpec));
        ((LightSpec *)spec)->l = s->lights[0];
        return spec;
    }
    if (k == &environment_kind)
        return &s->environment;
    if (k == &settings_kind) {
        memset(spec, 0, sizeof(SettingsSpec));
        ((SettingsSpec *)spec)->rs = s->settings;
        return spec;
    }
    memset(spec, 0, sizeof(CameraSpec));
    ((CameraSpec *)spec)->cam = s->camera;
    return spec;
}

/* The numbers of field f in item, as reals. */
static void field_values(const Field *f, const void *item, real *v)
{
    const char *p = (const char *)item + f->off;
    int n = f->type == FIELD_VEC ? 3 : f->type == FIELD_REALS ? f->n : f->type == FIELD_REAL ? 1 : 0;
    if (n)
        memcpy(v, p, (size_t)n * sizeof *v);
    else
        v[0] = (real) * (const int *)p;
}

/* The text of a scene with one directive of kind k (variant v) giving
 * field fi a sample value (and the kind's required fields theirs). */
static void directive(const FieldKind *k, int v, int fi, char *buf, size_t size, real *want)
{
    static const char *const heads[][2] = {{"material", "material m"}, {"instance", "instance cube"},
                                           {"model", "model cube cube.obj"}};
    const char *head = k->name;
    for (size_t i = 0; i < sizeof heads / sizeof heads[0]; i++)
        if (strcmp(heads[i][0], k->name) == 0)
            head = heads[i][1];
    snprintf(buf, size, "%s%s%s", strcmp(k->name, "instance") == 0 ? "model cube cube.obj\n" : "", head,
             k->variants ? " " : "");
    if (k->variants)
        snprintf(buf + strlen(buf), size - strlen(buf), "%s", k->variants[v]);
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if ((f->flags & FIELD_WIRE) || (f->variants && !(f->variants >> v & 1)))
            continue;
        if (!((f->flags & FIELD_REQUIRED) || (int)i == fi))
            continue;
        char val[400];
        real dummy[16];
        sample_value(f, (int)i, val, sizeof val, (int)i == fi ? want : dummy);
        if (f->type == FIELD_NAME)
            snprintf(val, sizeof val, "%s", strcmp(f->key, "texture") == 0 ? "t" : "default");
        snprintf(buf + strlen(buf), size - strlen(buf), " %s%s%s", f->key, f->type == FIELD_FLAG ? "" : " ",
                 f->type == FIELD_FLAG ? "" : val);
    }
    /* what the kinds' own rules ask for besides */
    if (k == &material_kind && fi >= 0 &&
        (strcmp(k->fields[fi].key, "roughness") == 0 || strcmp(k->fields[fi].key, "reflect_edge") == 0))
        strncat(buf, " reflect 1 1 1", size - strlen(buf) - 1);
    if (k == &material_kind && fi >= 0 &&
        (strcmp(k->fields[fi].key, "transmit") == 0 || strcmp(k->fields[fi].key, "absorb") == 0))
        strncat(buf, " ior 1.5", size - strlen(buf) - 1);
    if (k == &material_kind && fi >= 0 &&
        (strcmp(k->fields[fi].key, "checker_size") == 0 || strcmp(k->fields[fi].key, "checker_uv") == 0))
        strncat(buf, " checker 0.1 0.2 0.3", size - strlen(buf) - 1);
    if (k == &material_kind && fi >= 0 && strcmp(k->fields[fi].key, "coat_roughness") == 0)
        strncat(buf, " coat 0.5", size - strlen(buf) - 1);
    if (k == &camera_kind && fi >= 0 && (strcmp(k->fields[fi].key, "aperture") == 0))
        strncat(buf, " focus 3", size - strlen(buf) - 1);
    if (k == &camera_kind && fi >= 0 && (strcmp(k->fields[fi].key, "focus") == 0))
        strncat(buf, " aperture 0.1", size - strlen(buf) - 1);
    if (k == &light_kind && (v == LIGHT_SPOT || v == LIGHT_DIRECTIONAL) &&
        !(fi >= 0 && (strcmp(k->fields[fi].key, "direction") == 0 || strcmp(k->fields[fi].key, "target") == 0)))
        strncat(buf, " direction 0 -1 0.5", size - strlen(buf) - 1);
    strncat(buf, "\n", size - strlen(buf) - 1);
}

/* Every key of every directive: parsed, it holds the value given; sent,
 * it comes back the same. */
/* Every field of every kind lies within the item its kind says it
 * addresses (FieldKind.size: the spec, file-only fields included), so that
 * field_defaults and field_decode, given at least that, write nothing past
 * it (a decoder once filled an instance's file-only fields past the
 * Instance on its stack); and an item smaller than that stops the program
 * rather than be written past. */
static void every_field_lies_within_its_item(void **state)
{
    (void)state;
    const FieldKind *const kinds[] = {&camera_kind, &settings_kind, &material_kind, &sphere_kind, &plane_kind,
                                      &triangle_kind, &model_kind, &instance_kind, &light_kind, &environment_kind};
    for (size_t i = 0; i < sizeof kinds / sizeof *kinds; i++) {
        const FieldKind *k = kinds[i];
        assert_true(k->size > 0);
        for (uint32_t j = 0; j < k->count; j++) {
            const Field *f = &k->fields[j];
            const size_t bytes = f->type == FIELD_REAL ? sizeof(real)
                                 : f->type == FIELD_VEC ? sizeof(vec3)
                                 : f->type == FIELD_REALS ? (size_t)f->n * sizeof(real)
                                                          : sizeof(int);
            if (f->off + bytes > k->size)
                fail_msg("%s's '%s' at %zu + %zu, past its %zu bytes", k->name, f->key, f->off, bytes, k->size);
        }
        if (k->variants)
            assert_true(k->variant_off + sizeof(int) <= k->size);
    }
    assert_true(sizeof(InstanceSpec) > sizeof(Instance) && instance_kind.size == sizeof(InstanceSpec));
}

static void every_key_parses_and_travels(void **state)
{
    (void)state;
    const char *dir = test_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/cube.obj", dir);
    FILE *f = fopen(path, "w");
    fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", f);
    fclose(f);
    snprintf(path, sizeof path, "%s/t.ppm", dir);
    f = fopen(path, "w");
    fputs("P3 1 1 255 200 100 50\n", f);
    fclose(f);
    int checked = 0;
    for (const FieldKind *const *kp = scene_kinds; *kp; kp++) {
        const FieldKind *k = *kp;
        int variants = 1;
        while (k->variants && k->variants[variants])
            variants++;
        for (int v = 0; v < variants; v++)
            for (uint32_t i = 0; i < k->count; i++) {
                const Field *fd = &k->fields[i];
                if ((fd->flags & (FIELD_WIRE | FIELD_FILE)) || fd->type == FIELD_NAME || (fd->variants && !(fd->variants >> v & 1)))
                    continue;
                char text[2048];
                real want[16];
                snprintf(text, sizeof text, "texture t t.ppm\n");
                directive(k, v, (int)i, text + strlen(text), sizeof text - strlen(text), want);
                Scene *s;
                Err err;
                BvhOptions opt = bvh_options_default(BVH_SAH);
                char *copy = strdup(text);
                if (scene_parse(copy, strlen(copy), "t.scene", dir, &opt, 0, &s, &err))
                    fail_msg("%s (the scene: %s)", err.msg, text);
                free(copy);
                if (k == &model_kind) { /* not an item of the wire */
                    scene_destroy(s);
                    continue;
                }
                union {
                    CameraSpec c;
                    SettingsSpec st;
                    LightSpec l;
                    TriSpec t;
                } spec;
                const void *item = parsed_item(s, k, &spec);
                real got[16];
                field_values(fd, item, got);
                int n = fd->type == FIELD_VEC ? 3 : fd->type == FIELD_REALS ? fd->n : 1;
                for (int j = 0; j < n; j++)
                    if (got[j] != want[j] && !(fd->type == FIELD_REALS && fd->flags & FIELD_NONZERO))
                        fail_msg("%s %s: '%s' number %d is %g, the file said %g", k->name, k->variants ? k->variants[v] : "",
                                 fd->key, j, (double)got[j], (double)want[j]);
                /* and back from the wire, every field as it was */
                Sink blob = {0};
                field_encode(k, item, &blob);
                union {
                    Material m;
                    Sphere sp;
                    Plane p;
                    InstanceSpec in;
                    SceneEnvironment env;
                    CameraSpec c;
                    SettingsSpec st;
                    LightSpec l;
                    TriSpec t;
                } back;
                memset(&back, 0, sizeof back);
                Cursor c = cursor_make(blob.data, blob.len);
                assert_int_equal(field_decode(k, &c, &back, sizeof back), 0);
                assert_int_equal(c.left, 0);
                for (uint32_t w = 0; w < k->count; w++) {
                    const Field *wf = &k->fields[w];
                    if ((wf->flags & FIELD_FILE) || (wf->variants && !(wf->variants >> v & 1)))
                        continue;
                    real a[16], b2[16];
                    field_values(wf, item, a);
                    field_values(wf, &back, b2);
                    int m = wf->type == FIELD_VEC ? 3 : wf->type == FIELD_REALS ? wf->n : 1;
                    for (int j = 0; j < m; j++)
                        if (a[j] != b2[j])
                            fail_msg("%s: '%s' number %d went out as %g and came back %g", k->name, wf->key, j,
                                     (double)a[j], (double)b2[j]);
                }
                sink_free(&blob);
                scene_destroy(s);
                checked++;
            }
    }
    assert_true(checked > 60);
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--write") == 0)
        return write_tables(DOC, 0) || write_tables(PROTOCOL, 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(docs_show_every_table),
        cmocka_unit_test(every_field_lies_within_its_item),
        cmocka_unit_test(every_key_parses_and_travels),
    };
    return cmocka_run_group_tests_name("fields", tests, NULL, NULL);
}
