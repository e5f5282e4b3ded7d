/* obj.c - see obj.h.  Parsing collects indexed triangles first; the Mesh is
 * assembled at the end, once it is known which attributes are really used. */
#include "model/obj.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "base/bigmem.h"
#include "base/fileio.h"
#include "base/lex.h"
#include "model/mtl.h"
#include "model/smooth.h"
#include "base/textenc.h"

#define OBJ_MAX_BYTES ((size_t)1 << 31)
#define OBJ_MAX_ITEMS (1u << 26)

typedef struct {
    int32_t p[3], t[3], n[3];
    int32_t mat;    /* index into Obj.used while parsing, into Obj.lib after obj_resolve; -1: none */
    uint32_t group; /* its smoothing group (s); 0: none (flat) */
} ObjTri;
_Static_assert(sizeof(ObjTri) % sizeof(int32_t) == 0, "smooth_normals walks ObjTri in 32-bit words");

/* A material name a usemtl gave, resolved once the whole file is read: a
 * library may come after the faces that use its materials. */
typedef struct {
    char name[MTL_NAME_MAX];
    int line; /* its first usemtl */
} ObjUse;

typedef struct {
    vec3 *v;
    vec3 *vc; /* vertex colours, beside v from the first coloured vertex on (NULL before) */
    real *vt; /* 2 per entry */
    vec3 *vn;
    ObjTri *tris;
    uint32_t nv, nvt, nvn, ntri;
    uint32_t cv, cvc, cvt, cvn, ctri;
    int colour_line; /* the first coloured vertex's line */
    int colour_ints; /* every colour number so far a whole number (0..255 exporters) */
    real colour_max;
    int32_t (*corner)[3];
    uint32_t ccorner;
    MtlLib lib;
    ObjUse *used;
    uint32_t nused, cused;
} Obj;

static int grow(void **p, uint32_t *cap, uint32_t need, size_t elem)
{
    return array_reserve(p, cap, need, elem, OBJ_MAX_ITEMS);
}

/* Resolves a 1-based or negative (relative) OBJ index against count. */
static int resolve(long idx, uint32_t count, int32_t *out)
{
    if (idx > 0 && (unsigned long)idx <= count) {
        *out = (int32_t)(idx - 1);
        return 0;
    }
    if (idx < 0 && idx >= -(long)count) { /* no negation of idx: LONG_MIN has no positive twin */
        *out = (int32_t)((long)count + idx);
        return 0;
    }
    return -1;
}

static const char *const skip_names[OBJ_SKIP_KINDS] = {
    "lines (l)", "points (p)", "free-form curves and surfaces", "merging groups (mg)",
    "level of detail (lod)", "display attributes", "unknown statements",
};

const char *obj_skip_name(ObjSkip k) { return (unsigned)k < OBJ_SKIP_KINDS ? skip_names[k] : "?"; }

/* Keywords a triangle renderer reads past, by kind. */
static ObjSkip skip_kind(const char *k)
{
    static const char *const freeform[] = {"vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm",
                                           "trim", "hole", "scrv", "sp", "end", "con", "ctech", "stech", NULL};
    static const char *const display[] = {"usemap", "maplib", "shadow_obj", "trace_obj", "bevel", "c_interp",
                                          "d_interp", "call", "csh", NULL};
    if (strcmp(k, "l") == 0)
        return OBJ_SKIP_LINE;
    if (strcmp(k, "p") == 0)
        return OBJ_SKIP_POINT;
    if (strcmp(k, "mg") == 0)
        return OBJ_SKIP_MERGING;
    if (strcmp(k, "lod") == 0)
        return OBJ_SKIP_LOD;
    for (int i = 0; freeform[i]; i++)
        if (strcmp(k, freeform[i]) == 0)
            return OBJ_SKIP_FREEFORM;
    for (int i = 0; display[i]; i++)
        if (strcmp(k, display[i]) == 0)
            return OBJ_SKIP_DISPLAY;
    return OBJ_SKIP_UNKNOWN;
}

typedef struct {
    const ObjOptions *opt;
    ObjStats *st;
    const char *name;
    Err *err;
} Warner;

/* One warning about `file` (line 0: the file as a whole): counted, handed
 * to the caller's callback; with `strict` an error instead (returns -1 with
 * the message in err). */
static int vwarn(Warner *w, const char *file, int line, const char *fmt, va_list ap)
{
    char what[512], msg[1024 + MTL_PATH_MAX];
    vsnprintf(what, sizeof what, fmt, ap);
    if (line > 0)
        snprintf(msg, sizeof msg, "%s:%d: %s", file, line, what);
    else
        snprintf(msg, sizeof msg, "%s: %s", file, what);
    return obj_warning(w->opt, &w->st->warnings, w->err, msg);
}

int obj_warning(const ObjOptions *opt, unsigned long *count, Err *err, const char *msg)
{
    if (opt && opt->strict)
        return err_set(err, "%s (an error with --strict)", msg);
    (*count)++;
    if (opt && opt->warn)
        opt->warn(opt->warn_ctx, msg);
    return 0;
}

/* A warning about the OBJ file itself. */
static int warn(Warner *w, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int warn(Warner *w, int line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = vwarn(w, w->name, line, fmt, ap);
    va_end(ap);
    return rc;
}

/* The rest of a line after its keyword, without surrounding blanks and any
 * comment: material names may hold spaces. */
static char *rest_of_line(char *s, size_t keyword_len)
{
    while (*s == ' ' || *s == '\t')
        s++;
    s += keyword_len;
    while (*s == ' ' || *s == '\t')
        s++;
    char *e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = 0;
    return s;
}

/* Parses one face corner "v", "v/t", "v//n" or "v/t/n". */
static int parse_corner(const char *s, const Obj *o, int32_t c[3], const char **what)
{
    c[0] = c[1] = c[2] = -1;
    char *end;
    long v = lex_strtol10(s, &end);
    *what = "vertex index";
    if (end == s || resolve(v, o->nv, &c[0]))
        return -1;
    if (*end == 0)
        return 0;
    if (*end != '/')
        return -1;
    s = end + 1;
    if (*s != '/') {
        *what = "texture coordinate index";
        long t = lex_strtol10(s, &end);
        if (end == s || resolve(t, o->nvt, &c[1]))
            return -1;
        if (*end == 0)
            return 0;
        if (*end != '/')
            return -1;
        s = end;
    }
    s++;
    *what = "normal index";
    long n = lex_strtol10(s, &end);
    if (end == s || *end != 0 || resolve(n, o->nvn, &c[2]))
        return -1;
    return 0;
}

static int read_reals(const Tokens *t, int first, int want, int allow_extra, real *out)
{
    if (t->n - first < want || (!allow_extra && t->n - first > want) || t->n - first > want + 1)
        return -1;
    for (int i = 0; i < want; i++)
        if (lex_real(t->tok[first + i], &out[i]))
            return -1;
    return 0;
}

/* A first pass over the text counts the lines of vertices, texture
 * coordinates, normals and faces, so that each array is allocated once, at
 * its size and on huge pages, instead of grown by doubling: a big model
 * then takes a page fault per 2 MiB rather than per 4 KiB, and no copies
 * (measured: tools/bench/bench-import).  The counts only size the arrays; a face
 * with more corners, or a line that turns out not to be a vertex, is
 * handled by the growth that remains. */
static void obj_presize(Obj *o, const char *text, size_t len)
{
    uint32_t n[4] = {0, 0, 0, 0}; /* v, vt, vn, f */
    const char *p = text, *end = text + len;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t'))
            p++;
        if (end - p >= 2) {
            int blank = p[1] == ' ' || p[1] == '\t';
            if (p[0] == 'v')
                n[0] += blank, n[1] += p[1] == 't', n[2] += p[1] == 'n';
            else if (p[0] == 'f')
                n[3] += blank;
        }
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl)
            break;
        p = nl + 1;
    }
    void **arr[4] = {(void **)&o->v, (void **)&o->vt, (void **)&o->vn, (void **)&o->tris};
    uint32_t *cap[4] = {&o->cv, &o->cvt, &o->cvn, &o->ctri};
    const size_t elem[4] = {sizeof *o->v, 2 * sizeof *o->vt, sizeof *o->vn, sizeof *o->tris};
    for (int k = 0; k < 4; k++) {
        if (n[k] < 4096 || n[k] > OBJ_MAX_ITEMS)
            continue; /* small arrays grow cheaply; a count past the limit fails where it is met */
        void *a = bigmem_alloc((size_t)n[k] * elem[k]);
        if (a) {
            *arr[k] = a;
            *cap[k] = n[k];
        }
    }
}

static void obj_free(Obj *o)
{
    free(o->v);
    free(o->vc);
    free(o->vt);
    free(o->vn);
    free(o->tris);
    free(o->corner);
    free(o->used);
    mtl_free(&o->lib);
}

/* What a map is for: a material's colour (map_Kd), a cutout's mask
 * (map_d), its normal map (norm), a bump map (bump, map_Bump) that is a
 * normal map unless its image is grey (then a height map), or its
 * emission's colour (map_Ke). */
typedef enum { MAP_COLOUR, MAP_CUTOUT, MAP_NORMALS, MAP_BUMP, MAP_EMISSION } MapRole;

/* One map's texture: the id of the same file read before with the same
 * edge rule (for another material, or as this one's other map), else the
 * file read now; -1, after a warning, where it cannot be read.  A bump
 * map's image that is grey is a height map (*height set). */
static int obj_map_texture(const MtlMap *map, MapRole role, const char *mat, const MtlMap **seen, int32_t *seen_id,
                           uint32_t *nseen, Mesh *out, Warner *w, int32_t *id, int *height)
{
    static const char *const whats[] = {"texture", "cutout mask (map_d)", "normal map (norm)", "bump map",
                                        "emission texture (map_Ke)"};
    static const char *const left[] = {"untextured", "solid, no cutout", "its normals as they are",
                                       "its normals as they are", "its emission untextured"};
    const char *what = whats[role];
    *id = -1;
    *height = 0;
    for (uint32_t j = 0; j < *nseen && *id < 0; j++)
        if (strcmp(seen[j]->file, map->file) == 0 && seen[j]->clamp == map->clamp)
            *id = seen_id[j];
    if (*id >= 0) {
        *height = role == MAP_BUMP && texture_grey(out->textures[*id]);
        return 0;
    }
    const int elsewhere = map->found > FILE_AS_WRITTEN;
    w->st->found_elsewhere += elsewhere;
    if (elsewhere && warn(w, 0, "material '%s': %s not where the library says; using %s (%s)", mat, what, map->file,
                          file_found_how((FileFound)map->found, "the library")))
        return -1;
    Texture *t;
    Err terr;
    if (texture_read(map->file, &t, &terr)) {
        w->st->missing_textures++;
        return warn(w, 0, "material '%s': %s not read (%s): %s", mat, what, terr.msg, left[role]);
    }
    *height = role == MAP_BUMP && texture_grey(t);
    t->wrap[0] = t->wrap[1] = map->clamp ? TEXTURE_CLAMP : TEXTURE_REPEAT;
    uint32_t tid;
    if (mesh_add_texture(out, t, &tid, w->err))
        return -1;
    *id = (int32_t)tid;
    seen[*nseen] = map, seen_id[(*nseen)++] = *id;
    return 0;
}

/* The textures of the materials faces use, each file read once: the
 * diffuse one (map_Kd), a cutout's mask (map_d: its alpha, or a grey
 * image's level, under 0.5 a hole), and a normal map (norm; bump or
 * map_Bump where its image is not grey; a grey one is a height map), its
 * -bm its strength (a height map's: the height of its white), and the
 * emission's (map_Ke, times Ke, or alone where there is no Ke).  A texture
 * that cannot be read is a warning and leaves its material untextured,
 * solid, with its normals as they are, or its emission untextured. */
static int obj_textures(Obj *o, const int32_t *remap, Mesh *out, Warner *w)
{
    const MtlMap **seen = malloc(4 * (size_t)o->lib.count * sizeof *seen + 1);
    int32_t *seen_id = malloc(4 * (size_t)o->lib.count * sizeof *seen_id + 1);
    uint32_t nseen = 0;
    int rc = seen && seen_id ? 0 : err_set(w->err, "out of memory for the materials' textures");
    for (uint32_t k = 0; rc == 0 && k < o->lib.count; k++) {
        if (remap[k] < 0)
            continue;
        Material *m = &out->materials[remap[k]];
        int32_t id;
        int height;
        if (o->lib.maps[k].file[0]) {
            rc = obj_map_texture(&o->lib.maps[k], MAP_COLOUR, o->lib.names[k], seen, seen_id, &nseen, out, w, &id, &height);
            if (rc == 0 && id >= 0)
                m->texture = id;
        }
        if (rc == 0 && o->lib.dmaps[k].file[0]) {
            rc = obj_map_texture(&o->lib.dmaps[k], MAP_CUTOUT, o->lib.names[k], seen, seen_id, &nseen, out, w, &id, &height);
            if (rc == 0 && id >= 0)
                m->mask = id, m->cutoff = R(0.5);
        }
        const MtlMap *nm = &o->lib.nmaps[k];
        if (rc == 0 && nm->file[0] && nm->bm > R(0)) {
            MapRole role = o->lib.nkinds[k] == MTL_NORMALS_NORM ? MAP_NORMALS : MAP_BUMP;
            rc = obj_map_texture(nm, role, o->lib.names[k], seen, seen_id, &nseen, out, w, &id, &height);
            if (rc == 0 && id >= 0 && height) /* -bm: the height of its white, in the model's units */
                m->normal_map = id, m->normal_scale = 1, m->bump_height = real_min(nm->bm, MATERIAL_BUMP_HEIGHT_MAX);
            else if (rc == 0 && id >= 0)
                m->normal_map = id, m->normal_scale = real_min(nm->bm, MATERIAL_NORMAL_SCALE_MAX);
        }
        if (rc == 0 && o->lib.emaps[k].file[0]) {
            rc = obj_map_texture(&o->lib.emaps[k], MAP_EMISSION, o->lib.names[k], seen, seen_id, &nseen, out, w, &id,
                                 &height);
            if (rc == 0 && id >= 0 && !o->lib.extra[k].ke_given) /* map_Ke alone: the texture is the glow */
                m->ke = v3_splat(R(1));
            if (rc == 0 && id >= 0)
                m->emit_map = id, m->emit_mapped = 1;
        }
    }
    free(seen);
    free(seen_id);
    return rc;
}

/* The usemtl names against the libraries (all read by now): faces get
 * library indices; an undefined name is the default material, one warning
 * at its first usemtl; an empty name is the library's unnamed material if
 * it has one. */
static int obj_resolve(Obj *o, Warner *w)
{
    int32_t *to = malloc((o->nused ? o->nused : 1) * sizeof *to);
    if (!to)
        return err_set(w->err, "%s: out of memory", w->name);
    int rc = 0;
    for (uint32_t i = 0; i < o->nused && rc == 0; i++) {
        const ObjUse *u = &o->used[i];
        to[i] = mtl_find(&o->lib, u->name);
        if (to[i] < 0)
            w->st->undefined_mtl++;
        if (!u->name[0])
            rc = warn(w, u->line, "usemtl without a name: %s",
                      to[i] < 0 ? "the default material" : "the library's unnamed material");
        else if (to[i] < 0)
            rc = warn(w, u->line, "material '%s' is not defined by any material library: the default material",
                      u->name);
    }
    for (uint32_t i = 0; i < o->ntri && rc == 0; i++)
        if (o->tris[i].mat >= 0)
            o->tris[i].mat = to[o->tris[i].mat];
    free(to);
    return rc;
}

/* Builds the Mesh from the indexed triangles, keeping only used attributes. */
static int obj_assemble(Obj *o, const ObjOptions *opt, Mesh *out, ObjStats *st, const char *name, Err *err)
{
    int has_n = opt && opt->smooth, has_t = 0, has_m = 0, grouped = 0;
    for (uint32_t i = 0; i < o->ntri; i++) {
        const ObjTri *t = &o->tris[i];
        const int file_n = t->n[0] >= 0 && t->n[1] >= 0 && t->n[2] >= 0;
        has_n |= file_n;
        grouped |= !file_n && t->group != 0;
        has_t |= t->t[0] >= 0 && t->t[1] >= 0 && t->t[2] >= 0;
        has_m |= t->mat >= 0;
    }
    /* only the materials that faces use, renumbered; faces before any usemtl get a default */
    int32_t *remap = NULL;
    uint32_t nmat = 0;
    if (has_m) {
        remap = malloc((o->lib.count + 1) * sizeof *remap);
        if (!remap)
            return err_set(err, "%s: out of memory", name);
        for (uint32_t i = 0; i <= o->lib.count; i++)
            remap[i] = -1;
        for (uint32_t i = 0; i < o->ntri; i++) {
            uint32_t k = o->tris[i].mat < 0 ? o->lib.count : (uint32_t)o->tris[i].mat;
            if (remap[k] < 0)
                remap[k] = (int32_t)nmat++;
        }
    }
    /* smooth normals where the file has none: by smoothing group, and
     * with --smooth the faces outside any group together */
    has_n |= grouped;
    vec3 *smooth = NULL;
    uint32_t *smooth_of = NULL;
    const SmoothInput sin = {o->v, o->nv, o->tris ? o->tris[0].p : NULL, o->tris ? &o->tris[0].group : NULL,
                             sizeof(ObjTri) / sizeof(int32_t), o->ntri, opt && opt->smooth};
    if ((grouped || sin.group0) && smooth_normals(&sin, &smooth_of, &smooth, err)) {
        free(remap);
        return err_prefix(err, "%s", name);
    }
    /* vertex colours: the diffuse colour of a model without materials of its own */
    Warner w = {opt, st, name, err};
    int has_c = o->vc != NULL, rc = 0;
    real cscale = R(1);
    if (has_c && has_m) {
        has_c = 0;
        st->colours_ignored = 1;
        rc = warn(&w, o->colour_line, "vertex colours ignored: the model's materials (usemtl) give its colours");
    } else if (has_c && o->colour_ints && o->colour_max > R(1) && o->colour_max <= R(255)) {
        cscale = R(1) / R(255);
        rc = warn(&w, o->colour_line, "vertex colours are whole numbers up to %g: read as 0..255",
                  (double)o->colour_max);
    }
    st->colours = has_c;
    if (rc == 0)
        rc = mesh_init(out, (has_n ? MESH_NORMALS : 0u) | (has_t ? MESH_UVS : 0u) | (has_m ? MESH_MATERIALS : 0u) |
                                (has_c ? MESH_COLOURS : 0u),
                       err);
    if (rc == 0)
        rc = mesh_reserve(out, o->ntri, err);
    for (uint32_t i = 0; rc == 0 && i < nmat; i++)
        rc = mesh_add_material(out, material_default(), err);
    if (rc == 0 && has_m)
        for (uint32_t k = 0; k <= o->lib.count; k++)
            if (remap[k] >= 0 && k < o->lib.count)
                out->materials[remap[k]] = o->lib.mats[k];
    /* reflection, glass, transparency and emission of the used materials */
    for (uint32_t k = 0; rc == 0 && has_m && k < o->lib.count; k++)
        if (remap[k] >= 0 && mtl_optics(&o->lib.extra[k], &out->materials[remap[k]]))
            st->optics_mtl++;
    if (rc == 0 && has_m && has_t)
        rc = obj_textures(o, remap, out, &w);
    for (uint32_t i = 0; rc == 0 && i < o->ntri; i++) {
        const ObjTri *t = &o->tris[i];
        vec3 p[3], n[3], col[3];
        real uv[6] = {0};
        for (int k = 0; k < 3; k++) {
            p[k] = o->v[t->p[k]];
            if (has_c)
                col[k] = o->vc[t->p[k]].x < R(0) ? material_default().kd : v3_scale(o->vc[t->p[k]], cscale);
        }
        if (mesh_tri_is_degenerate(p)) {
            st->degenerate++;
            continue;
        }
        vec3 fn = v3_norm_any(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])));
        int file_n = t->n[0] >= 0 && t->n[1] >= 0 && t->n[2] >= 0;
        if (!file_n && smooth_of && smooth_of[3 * i] != SMOOTH_FLAT)
            st->smoothed++;
        for (int k = 0; k < 3; k++) {
            const uint32_t sk = smooth_of ? smooth_of[3 * i + (uint32_t)k] : SMOOTH_FLAT;
            n[k] = file_n ? v3_norm(o->vn[t->n[k]]) : (sk != SMOOTH_FLAT ? v3_norm(smooth[sk]) : fn);
            if (!(v3_dot(n[k], n[k]) > R(0.5)))
                n[k] = fn; /* a zero normal in the file or a cancelling fan */
            if (t->t[k] >= 0) {
                uv[2 * k] = o->vt[2 * t->t[k]];
                uv[2 * k + 1] = o->vt[2 * t->t[k] + 1];
                if (t->mat >= 0 && o->lib.maps[t->mat].file[0]) { /* map_Kd -s and -o place the texture */
                    const MtlMap *map = &o->lib.maps[t->mat];
                    uv[2 * k] = uv[2 * k] * map->s[0] + map->o[0];
                    uv[2 * k + 1] = uv[2 * k + 1] * map->s[1] + map->o[1];
                }
            }
        }
        uint32_t mat = has_m ? (uint32_t)remap[t->mat < 0 ? o->lib.count : (uint32_t)t->mat] : 0;
        rc = mesh_add(out, p, n, uv, col, mat, err);
    }
    free(remap);
    free(smooth);
    free(smooth_of);
    if (rc == 0)
        st->triangles = out->tri_count;
    else
        mesh_free(out);
    return rc;
}

/* One library, or several separated by blanks; '\' as a separator is read
 * as '/'.  A library that is missing or unreadable is a warning (its
 * materials will be undefined, hence default); one that is there but
 * malformed is an error. */
static int mtl_one(Obj *o, char *file, const char *dir, Warner *w, int line)
{
    for (char *q = file; *q; q++)
        if (*q == '\\')
            *q = '/';
    char path[4096];
    if (!dir) {
        w->st->missing_mtllib++;
        return warn(w, line, "material library '%s' cannot be looked up here: default materials", file);
    }
    FileFound how = file_find_near(dir, file, path, sizeof path);
    if (how == FILE_NOT_FOUND) {
        w->st->missing_mtllib++;
        return warn(w, line, "material library '%s' not found: default materials", path);
    }
    w->st->found_elsewhere += how != FILE_AS_WRITTEN;
    if (how != FILE_AS_WRITTEN && warn(w, line, "material library '%s' not where the file says; using %s (%s)", file,
                                       path, file_found_how(how, "the model")))
        return -1;
    if (mtl_read(&o->lib, path, w->err)) {
        err_prefix(w->err, "%s:%d: mtllib", w->name, line);
        return -1;
    }
    return 0;
}

static int obj_mtllib(Obj *o, char *rest, const char *dir, Warner *w, int line)
{
    if (!*rest)
        return warn(w, line, "mtllib without a file name: skipped");
    char path[4096];
    /* the whole rest of the line first: a file name with spaces */
    if (dir && strchr(rest, ' ') && file_join(dir, rest, path, sizeof path) == 0) {
        char whole[4096];
        snprintf(whole, sizeof whole, "%s", rest);
        for (char *q = whole; *q; q++)
            if (*q == '\\')
                *q = '/';
        if (file_find_near(dir, whole, path, sizeof path) != FILE_NOT_FOUND)
            return mtl_one(o, whole, dir, w, line);
    }
    Tokens t;
    lex_split(rest, &t);
    for (int i = 0; i < t.n; i++)
        if (mtl_one(o, t.tok[i], dir, w, line))
            return -1;
    return 0;
}

/* A '\\' at the end continues the line: the lines are adjacent in the
 * buffer, so the terminators between them become blanks. */
static void join_continued(Lexer *lx, char *line)
{
    for (;;) {
        char *e = line + strlen(line);
        while (e > line && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
            e--;
        if (e == line || e[-1] != '\\')
            return;
        char *next = lex_next_raw(lx);
        if (!next)
            return;
        e[-1] = ' ';
        for (char *q = e; q < next; q++)
            if (*q == 0)
                *q = ' ';
    }
}

/* The line being read, for errors. */
typedef struct {
    const char *name;
    int line;
    Err *err;
} Where;

/* A face's corners after the 'f' (any number of them: split without the
 * token limit), fanned into triangles of material mat. */
static int parse_face(Obj *o, char *p, int32_t mat, uint32_t group, ObjStats *st, const Where *at)
{
    uint32_t nc = 0;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\r')
            p++;
        if (*p == 0 || *p == '#')
            break;
        char *tok = p;
        while (*p && *p != ' ' && *p != '\t' && *p != '\r' && *p != '#')
            p++;
        char c = *p;
        *p = 0;
        const char *what;
        if (grow((void **)&o->corner, &o->ccorner, nc + 1, sizeof *o->corner))
            return err_set(at->err, "%s:%d: face too large or out of memory", at->name, at->line);
        if (parse_corner(tok, o, o->corner[nc], &what))
            return err_set(at->err, "%s:%d: bad %s in face corner '%s' (%u vertices, %u texture coordinates, %u normals defined so far)",
                           at->name, at->line, what, tok, o->nv, o->nvt, o->nvn);
        nc++;
        if (c == 0 || c == '#')
            break;
        p++;
    }
    if (nc < 3)
        return err_set(at->err, "%s:%d: a face needs at least 3 corners, this one has %u", at->name, at->line, nc);
    st->faces++;
    /* fan triangulation: exact for the convex polygons OBJ exporters write */
    for (uint32_t k = 1; k + 1 < nc; k++) {
        if (grow((void **)&o->tris, &o->ctri, o->ntri + 1, sizeof *o->tris))
            return err_set(at->err, "%s:%d: too many triangles or out of memory", at->name, at->line);
        ObjTri *tr = &o->tris[o->ntri++];
        const uint32_t idx[3] = {0, k, k + 1};
        for (int j = 0; j < 3; j++) {
            tr->p[j] = o->corner[idx[j]][0];
            tr->t[j] = o->corner[idx[j]][1];
            tr->n[j] = o->corner[idx[j]][2];
        }
        tr->mat = mat;
        tr->group = group;
    }
    return 0;
}

/* v: x y z, x y z w, and x y z r g b (or w r g b) as many exporters write
 * vertex colours. */
static int parse_vertex(Obj *o, const Tokens *t, ObjStats *st, const Where *at)
{
    real v[3], vw, c[3] = {-1, -1, -1};
    int nums = t->n - 1, rgb = nums == 6 ? 4 : 5;
    if (!(nums == 3 || nums == 4 || nums == 6 || nums == 7) || lex_real(t->tok[1], &v[0]) ||
        lex_real(t->tok[2], &v[1]) || lex_real(t->tok[3], &v[2]) ||
        ((nums == 4 || nums == 7) && lex_real(t->tok[4], &vw)) ||
        (nums >= 6 &&
         (lex_real(t->tok[rgb], &c[0]) || lex_real(t->tok[rgb + 1], &c[1]) || lex_real(t->tok[rgb + 2], &c[2]))))
        return err_set(at->err, "%s:%d: expected 3 finite numbers after 'v' (and a w, colours, or both)", at->name,
                       at->line);
    if (nums >= 6 && !(c[0] >= R(0) && c[1] >= R(0) && c[2] >= R(0)))
        return err_set(at->err, "%s:%d: a vertex colour below 0", at->name, at->line);
    if (grow((void **)&o->v, &o->cv, o->nv + 1, sizeof *o->v))
        return err_set(at->err, "%s:%d: too many vertices or out of memory", at->name, at->line);
    if (nums >= 6 || o->vc) {
        if (nums >= 6 && !st->coloured++) {
            o->colour_line = at->line;
            o->colour_ints = 1;
        }
        int first = o->vc == NULL;
        if (grow((void **)&o->vc, &o->cvc, o->nv + 1, sizeof *o->vc))
            return err_set(at->err, "%s:%d: too many vertices or out of memory", at->name, at->line);
        for (uint32_t i = 0; first && i < o->nv; i++) /* uncoloured so far: marked, given the default later */
            o->vc[i] = v3(-1, -1, -1);
        o->vc[o->nv] = v3(c[0], c[1], c[2]);
        for (int i = 0; i < 3 && nums >= 6; i++) {
            o->colour_max = real_max(o->colour_max, c[i]);
            o->colour_ints &= c[i] == floor(c[i]);
        }
    }
    o->v[o->nv++] = v3(v[0], v[1], v[2]);
    return 0;
}

static int parse_uv(Obj *o, const Tokens *t, const Where *at)
{
    real v[2] = {0, 0};
    if (t->n < 2 || t->n > 4 || lex_real(t->tok[1], &v[0]) || (t->n >= 3 && lex_real(t->tok[2], &v[1])))
        return err_set(at->err, "%s:%d: expected 1 to 3 finite numbers after 'vt'", at->name, at->line);
    if (grow((void **)&o->vt, &o->cvt, o->nvt + 1, 2 * sizeof *o->vt))
        return err_set(at->err, "%s:%d: too many texture coordinates or out of memory", at->name, at->line);
    o->vt[2 * o->nvt] = v[0];
    o->vt[2 * o->nvt + 1] = v[1];
    o->nvt++;
    return 0;
}

static int parse_normal(Obj *o, const Tokens *t, const Where *at)
{
    real v[3];
    if (read_reals(t, 1, 3, 0, v))
        return err_set(at->err, "%s:%d: expected 3 finite numbers after 'vn'", at->name, at->line);
    if (grow((void **)&o->vn, &o->cvn, o->nvn + 1, sizeof *o->vn))
        return err_set(at->err, "%s:%d: too many normals or out of memory", at->name, at->line);
    o->vn[o->nvn++] = v3(v[0], v[1], v[2]);
    return 0;
}

/* s N or s off: the smoothing group of the faces after it (0 and off:
 * none); anything else is a warning and turns smoothing off. */
static int parse_smoothing(const Tokens *t, uint32_t *group, ObjStats *st, Warner *w, int line)
{
    *group = 0;
    st->smoothing++;
    if (t->n == 2 && strcmp(t->tok[1], "off") == 0)
        return 0;
    const char *s = t->n == 2 ? t->tok[1] : "";
    char *end = NULL;
    unsigned long long g = *s >= '0' && *s <= '9' ? strtoull(s, &end, 10) : 0;
    if (end && *end == 0 && g <= UINT32_MAX) {
        *group = (uint32_t)g;
        return 0;
    }
    return warn(w, line, "'s' wants a smoothing group number or 'off': the faces after it are flat");
}

/* usemtl: the material by name into *mat; the names are resolved against
 * the libraries at the end. */
static int parse_usemtl(Obj *o, const char *rest, int32_t *mat, const Where *at)
{
    *mat = -1;
    for (uint32_t i = o->nused; i-- > 0 && *mat < 0;)
        if (strncmp(o->used[i].name, rest, MTL_NAME_MAX - 1) == 0)
            *mat = (int32_t)i;
    if (*mat >= 0)
        return 0;
    if (grow((void **)&o->used, &o->cused, o->nused + 1, sizeof *o->used))
        return err_set(at->err, "%s:%d: too many materials or out of memory", at->name, at->line);
    size_t nlen = strnlen(rest, MTL_NAME_MAX - 1); /* longer names are cut, as the library's */
    memcpy(o->used[o->nused].name, rest, nlen);
    o->used[o->nused].name[nlen] = 0;
    o->used[o->nused].line = at->line;
    *mat = (int32_t)o->nused++;
    return 0;
}

/* usemtl and mtllib take the rest of the line (names and paths may hold
 * spaces), copied into rest before the split cuts the line up. */
static void rest_for_names(char *s, char rest[4096])
{
    rest[0] = 0;
    if ((strncmp(s, "usemtl", 6) == 0 || strncmp(s, "mtllib", 6) == 0) &&
        (s[6] == 0 || s[6] == ' ' || s[6] == '\t' || s[6] == '\r')) {
        char *r = rest_of_line(s, 6);
        char *hash = strchr(r, '#');
        if (hash) {
            *hash = 0;
            r = rest_of_line(r, 0);
        }
        snprintf(rest, 4096, "%s", r);
    }
}

int obj_parse(char *text, size_t len, const char *name, const char *dir, const ObjOptions *opt, Mesh *out,
              ObjStats *st, Err *err)
{
    Obj o = {0};
    ObjStats local;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    memset(out, 0, sizeof *out);
    obj_presize(&o, text, len);
    Lexer lx = lex_make(text, len);
    Tokens t;
    int32_t mat = -1;
    uint32_t group = 0; /* the smoothing group of the faces that follow */
    int rc = -1, bad = 0, warned_kind[OBJ_SKIP_KINDS] = {0};
    Warner w = {opt, st, name, err};
    char *line;
    while (!bad && (line = lex_next_raw(&lx))) {
        join_continued(&lx, line);
        Where at = {name, lx.line, err};
        char *s = line;
        while (*s == ' ' || *s == '\t')
            s++;
        if (s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) {
            bad = parse_face(&o, s + 1, mat, group, st, &at);
            continue;
        }
        char rest[4096];
        rest_for_names(s, rest);
        lex_split(line, &t);
        if (t.n == 0)
            continue;
        const char *k = t.tok[0];
        if (strcmp(k, "v") == 0) {
            bad = parse_vertex(&o, &t, st, &at);
        } else if (strcmp(k, "vt") == 0) {
            bad = parse_uv(&o, &t, &at);
        } else if (strcmp(k, "vn") == 0) {
            bad = parse_normal(&o, &t, &at);
        } else if (strcmp(k, "o") == 0 || strcmp(k, "g") == 0) {
            st->groups++;
        } else if (strcmp(k, "mtllib") == 0) {
            bad = obj_mtllib(&o, rest, dir, &w, lx.line);
        } else if (strcmp(k, "usemtl") == 0) {
            bad = parse_usemtl(&o, rest, &mat, &at);
        } else if (strcmp(k, "s") == 0) {
            bad = parse_smoothing(&t, &group, st, &w, lx.line);
        } else {
            /* l, p, curves and the rest do not describe triangles: skipped, counted, one warning per kind */
            ObjSkip kind = skip_kind(k);
            st->skipped[kind]++;
            bad = !warned_kind[kind]++ &&
                  warn(&w, lx.line, "'%s' skipped (%s: a triangle renderer does not draw them)", k, obj_skip_name(kind));
        }
    }
    st->vertices = o.nv;
    if (!bad && !obj_resolve(&o, &w))
        rc = obj_assemble(&o, opt, out, st, name, err);
    obj_free(&o);
    return rc;
}

int obj_read(const char *path, const ObjOptions *opt, Mesh *out, ObjStats *stats, Err *err)
{
    char *text;
    size_t len;
    if (text_read_file(path, OBJ_MAX_BYTES, &text, &len, err))
        return -1;
    char dir[4096];
    file_dirname(path, dir, sizeof dir);
    int rc = obj_parse(text, len, path, dir, opt, out, stats, err);
    free(text);
    return rc;
}
