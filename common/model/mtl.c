/* mtl.c - reads the MTL statements of materials: the Phong terms and map_Kd
 * that lanray draws, and Ka, Ke, Ni, d, Tr and illum, checked and kept
 * (mtl.h); other statements (the other maps, ...) are accepted and ignored.
 * Material names are
 * the rest of the newmtl line (exporters write names with spaces, and
 * empty ones); UTF-16 files are decoded first (textenc.h). */
#include "model/mtl.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/fileio.h"
#include "base/lex.h"
#include "base/textenc.h"

#define MTL_MAX_BYTES ((size_t)64 << 20)
#define MTL_MAX_MATERIALS 65536u

/* Grows the array at *pp (a pointer to any pointer) to n elements of
 * `size` bytes; the pointer is moved by memcpy, so its type is the
 * caller's own. */
static int grow(void *pp, size_t n, size_t size)
{
    void *old, *q;
    memcpy(&old, pp, sizeof old);
    if (!(q = realloc(old, n * size)))
        return -1;
    memcpy(pp, &q, sizeof q);
    return 0;
}

/* A map not given: no file, unscaled, unmoved, wrapping, strength 1. */
static const MtlMap map_none = {"", {R(1), R(1)}, {R(0), R(0)}, 0, FILE_AS_WRITTEN, R(1)};

static int add(MtlLib *lib, const char *name, int line)
{
    if (lib->count >= MTL_MAX_MATERIALS)
        return -1;
    const size_t n = lib->count + 1;
    if (grow(&lib->names, n, sizeof *lib->names) || grow(&lib->mats, n, sizeof *lib->mats) ||
        grow(&lib->maps, n, sizeof *lib->maps) || grow(&lib->dmaps, n, sizeof *lib->dmaps) ||
        grow(&lib->nmaps, n, sizeof *lib->nmaps) || grow(&lib->nkinds, n, sizeof *lib->nkinds) ||
        grow(&lib->emaps, n, sizeof *lib->emaps) ||
        grow(&lib->extra, n, sizeof *lib->extra))
        return -1;
    lib->extra[lib->count] = (MtlExtra){v3_splat(0), v3_splat(0), R(0), R(1), -1, line, lib->file_count - 1, 0};
    lib->maps[lib->count] = lib->dmaps[lib->count] = lib->nmaps[lib->count] = lib->emaps[lib->count] = map_none;
    lib->nkinds[lib->count] = MTL_NORMALS_NONE;
    snprintf(lib->names[lib->count], MTL_NAME_MAX, "%s", name);
    lib->mats[lib->count] = material_default();
    lib->count++;
    return 0;
}

static int read_vec(const Tokens *t, vec3 *out)
{
    if (t->n != 4 && t->n != 2)
        return -1;
    real v[3];
    for (int i = 0; i < 3; i++)
        if (lex_real(t->tok[t->n == 2 ? 1 : 1 + i], &v[i]) || v[i] < R(0))
            return -1;
    *out = v3(v[0], v[1], v[2]);
    return 0;
}

/* map_Kd [-option value...] file: -s and -o set the placement, -clamp the
 * edge rule, -bm a bump or normal map's strength; the other options
 * (blendu, blendv, boost, cc, imfchan, mm, t, texres, type) are read past
 * with their values.  The file name is the
 * rest of the line (names hold spaces), '\' read as '/', relative to the
 * library's directory. */
static int read_map(const Tokens *t, const char *lib_path, MtlMap *m)
{
    int i = 1;
    while (i < t->n && t->tok[i][0] == '-') {
        const char *o = t->tok[i++];
        if (strcmp(o, "-s") == 0 || strcmp(o, "-o") == 0 || strcmp(o, "-t") == 0) {
            real v[3] = {o[1] == 's' ? R(1) : R(0), o[1] == 's' ? R(1) : R(0), 0};
            int n = 0;
            while (n < 3 && i < t->n && lex_real(t->tok[i], &v[n]) == 0)
                n++, i++;
            if (n == 0)
                return -1;
            if (o[1] == 's')
                m->s[0] = v[0], m->s[1] = n > 1 ? v[1] : R(1);
            else if (o[1] == 'o')
                m->o[0] = v[0], m->o[1] = n > 1 ? v[1] : R(0);
        } else if (strcmp(o, "-clamp") == 0) {
            if (i >= t->n)
                return -1;
            m->clamp = strcmp(t->tok[i++], "on") == 0;
        } else if (strcmp(o, "-mm") == 0) {
            i += 2;
        } else if (strcmp(o, "-bm") == 0) {
            if (i >= t->n || lex_real(t->tok[i++], &m->bm))
                return -1;
        } else if (strcmp(o, "-blendu") == 0 || strcmp(o, "-blendv") == 0 ||
                   strcmp(o, "-boost") == 0 || strcmp(o, "-cc") == 0 || strcmp(o, "-imfchan") == 0 ||
                   strcmp(o, "-texres") == 0 || strcmp(o, "-type") == 0) {
            i += 1;
        } else {
            return -1;
        }
    }
    if (i >= t->n)
        return -1;
    char file[MTL_PATH_MAX] = "";
    for (; i < t->n; i++) {
        size_t used = strlen(file);
        snprintf(file + used, sizeof file - used, "%s%s", used ? " " : "", t->tok[i]);
    }
    for (char *q = file; *q; q++)
        if (*q == '\\')
            *q = '/';
    char dir[MTL_PATH_MAX];
    file_dirname(lib_path, dir, sizeof dir);
    m->found = (int)file_find_near(dir, file, m->file, sizeof m->file);
    return 0;
}

/* One number after the keyword (after `-halo` for d) in [lo, hi]. */
static int read_one(const Tokens *t, real lo, real hi, real *out)
{
    int i = t->n == 3 && strcmp(t->tok[1], "-halo") == 0 ? 2 : 1;
    if (t->n != i + 1 || lex_real(t->tok[i], out) || *out < lo || *out > hi)
        return -1;
    return 0;
}

int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err)
{
    Lexer lx = lex_make(text, len);
    Tokens t;
    Material *cur = NULL;
    void *f = realloc(lib->files, (lib->file_count + 1) * sizeof *lib->files);
    if (!f)
        return err_set(err, "%s: out of memory", name);
    lib->files = f;
    snprintf(lib->files[lib->file_count++], MTL_PATH_MAX, "%s", name);
    char *line;
    while ((line = lex_next_raw(&lx))) {
        char *s = line;
        while (*s == ' ' || *s == '\t')
            s++;
        if (strncmp(s, "newmtl", 6) == 0 && (s[6] == 0 || s[6] == ' ' || s[6] == '\t' || s[6] == '\r')) {
            /* the name is the rest of the line, blanks and all, up to a comment */
            char *n = s + 6;
            while (*n == ' ' || *n == '\t')
                n++;
            char *hash = strchr(n, '#');
            if (hash)
                *hash = 0;
            char *e = n + strlen(n);
            while (e > n && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
                *--e = 0;
            if (add(lib, n, lx.line))
                return err_set(err, "%s:%d: too many materials or out of memory", name, lx.line);
            cur = &lib->mats[lib->count - 1];
            continue;
        }
        lex_split(line, &t);
        if (t.n == 0)
            continue;
        const char *k = t.tok[0];
        MtlExtra *x = cur ? &lib->extra[lib->count - 1] : NULL;
        if (strcmp(k, "Kd") == 0 || strcmp(k, "Ks") == 0 || strcmp(k, "Ka") == 0 || strcmp(k, "Ke") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: %s before any newmtl", name, lx.line, k);
            vec3 v;
            if (read_vec(&t, &v))
                return err_set(err, "%s:%d: expected 3 non-negative numbers after %s", name, lx.line, k);
            if (k[1] == 'd')
                cur->kd = v;
            else if (k[1] == 's')
                cur->ks = v;
            else if (k[1] == 'a')
                x->ka = v;
            else
                x->ke = v, x->ke_given = 1;
        } else if (strcmp(k, "Ni") == 0 || strcmp(k, "d") == 0 || strcmp(k, "Tr") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: %s before any newmtl", name, lx.line, k);
            real v;
            /* Ni 0 is what several exporters write for "not set" */
            if (k[0] == 'N' ? read_one(&t, R(0), R(100), &v) : read_one(&t, R(0), R(1), &v))
                return err_set(err, "%s:%d: expected %s after %s", name, lx.line,
                               k[0] == 'N' ? "one number from 0 to 100" : "one number from 0 to 1", k);
            if (k[0] == 'N')
                x->ni = v;
            else
                x->d = k[0] == 'd' ? v : R(1) - v;
        } else if (strcmp(k, "illum") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: illum before any newmtl", name, lx.line);
            char *end;
            long v = t.n == 2 ? strtol(t.tok[1], &end, 10) : -1;
            if (t.n != 2 || *end || v < 0 || v > 10)
                return err_set(err, "%s:%d: expected a whole number from 0 to 10 after illum", name, lx.line);
            x->illum = (int)v;
        } else if (strcmp(k, "map_Kd") == 0 || strcmp(k, "map_d") == 0 || strcmp(k, "map_Ke") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: %s before any newmtl", name, lx.line, k);
            MtlMap *maps = k[4] == 'd' ? lib->dmaps : k[5] == 'e' ? lib->emaps : lib->maps;
            if (read_map(&t, name, &maps[lib->count - 1]))
                return err_set(err, "%s:%d: %s: bad option or no file name", name, lx.line, k);
        } else if (strcmp(k, "norm") == 0 || strcasecmp(k, "map_bump") == 0 || strcmp(k, "bump") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: %s before any newmtl", name, lx.line, k);
            const unsigned n = lib->count - 1, kind = k[0] == 'n' ? MTL_NORMALS_NORM : MTL_NORMALS_BUMP;
            MtlMap nm = map_none;
            if (read_map(&t, name, &nm))
                return err_set(err, "%s:%d: %s: bad option or no file name", name, lx.line, k);
            if (kind >= lib->nkinds[n]) /* norm says it is a normal map: it wins over a bump */
                lib->nmaps[n] = nm, lib->nkinds[n] = (unsigned char)kind;
        } else if (strcmp(k, "Ns") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: Ns before any newmtl", name, lx.line);
            real ns;
            if (t.n != 2 || lex_real(t.tok[1], &ns) || ns < R(0))
                return err_set(err, "%s:%d: expected one non-negative number after Ns", name, lx.line);
            cur->shininess = ns;
        }
    }
    return 0;
}

int mtl_read(MtlLib *lib, const char *path, Err *err)
{
    char *text;
    size_t len;
    if (text_read_file(path, MTL_MAX_BYTES, &text, &len, err))
        return -1;
    int rc = mtl_parse(lib, text, len, path, err);
    free(text);
    return rc;
}

int mtl_optics(const MtlExtra *x, Material *m)
{
    int did = 0;
    const int glass = x->illum == 4 || x->illum == 6 || x->illum == 7 || x->illum == 9;
    if (glass) {
        /* a dielectric; the opacity d is the diffuse share, the rest goes
         * through (a glass illum without d is clear) */
        real t = x->d < R(1) ? R(1) - x->d : R(1);
        m->ior = x->ni >= MATERIAL_IOR_MIN && x->ni <= MATERIAL_IOR_MAX ? x->ni : R(1.5);
        m->kt = v3_splat(t);
        m->kd = v3_scale(m->kd, R(1) - t);
        did = 1;
    } else if (x->d < R(1)) {
        /* dissolve: a blend with what is behind, unbent (index 1) */
        m->ior = R(1);
        m->kt = v3_splat(R(1) - x->d);
        m->kd = v3_scale(m->kd, x->d);
        m->ks = v3_scale(m->ks, x->d);
        did = 1;
    } else if ((x->illum == 3 || x->illum == 5 || x->illum == 8) && v3_max_comp(m->ks) > R(0)) {
        m->kr = m->ks; /* the reflectivity of a ray-traced illum is Ks */
        did = 1;
    }
    if (v3_max_comp(x->ke) > R(0)) {
        m->ke = x->ke;
        did = 1;
    }
    return did;
}

int mtl_find(const MtlLib *lib, const char *name)
{
    for (unsigned i = 0; i < lib->count; i++)
        if (strncmp(lib->names[i], name, MTL_NAME_MAX - 1) == 0 && (*name || !lib->names[i][0]))
            return (int)i;
    return -1;
}

void mtl_free(MtlLib *lib)
{
    free(lib->names);
    free(lib->mats);
    free(lib->maps);
    free(lib->dmaps);
    free(lib->nmaps);
    free(lib->nkinds);
    free(lib->emaps);
    free(lib->extra);
    free(lib->files);
    memset(lib, 0, sizeof *lib);
}
