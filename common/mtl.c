/* mtl.c - reads the subset of MTL that Phong shading uses; other statements
 * (illum, map_*, Ni, d, ...) are accepted and ignored.  Material names are
 * the rest of the newmtl line (exporters write names with spaces, and
 * empty ones); UTF-16 files are decoded first (textenc.h). */
#include "mtl.h"

#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#include "lex.h"
#include "textenc.h"

#define MTL_MAX_BYTES ((size_t)64 << 20)
#define MTL_MAX_MATERIALS 65536u

static int add(MtlLib *lib, const char *name)
{
    if (lib->count >= MTL_MAX_MATERIALS)
        return -1;
    void *n = realloc(lib->names, (lib->count + 1) * sizeof *lib->names);
    if (!n)
        return -1;
    lib->names = n;
    void *m = realloc(lib->mats, (lib->count + 1) * sizeof *lib->mats);
    if (!m)
        return -1;
    lib->mats = m;
    void *mp = realloc(lib->maps, (lib->count + 1) * sizeof *lib->maps);
    if (!mp)
        return -1;
    lib->maps = mp;
    lib->maps[lib->count] = (MtlMap){"", {R(1), R(1)}, {R(0), R(0)}, 0};
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
 * edge rule; the other options (blendu, blendv, bm, boost, cc, imfchan, mm,
 * t, texres, type) are read past with their values.  The file name is the
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
        } else if (strcmp(o, "-blendu") == 0 || strcmp(o, "-blendv") == 0 || strcmp(o, "-bm") == 0 ||
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
    if (file_join(dir, file, m->file, sizeof m->file))
        return -1;
    return 0;
}

int mtl_parse(MtlLib *lib, char *text, size_t len, const char *name, Err *err)
{
    Lexer lx = lex_make(text, len);
    Tokens t;
    Material *cur = NULL;
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
            if (add(lib, n))
                return err_set(err, "%s:%d: too many materials or out of memory", name, lx.line);
            cur = &lib->mats[lib->count - 1];
            continue;
        }
        lex_split(line, &t);
        if (t.n == 0)
            continue;
        const char *k = t.tok[0];
        if (strcmp(k, "Kd") == 0 || strcmp(k, "Ks") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: %s before any newmtl", name, lx.line, k);
            vec3 v;
            if (read_vec(&t, &v))
                return err_set(err, "%s:%d: expected 3 non-negative numbers after %s", name, lx.line, k);
            if (k[1] == 'd')
                cur->kd = v;
            else
                cur->ks = v;
        } else if (strcmp(k, "map_Kd") == 0) {
            if (!cur)
                return err_set(err, "%s:%d: map_Kd before any newmtl", name, lx.line);
            if (read_map(&t, name, &lib->maps[lib->count - 1]))
                return err_set(err, "%s:%d: map_Kd: bad option or no file name", name, lx.line);
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
    if (file_read_all(path, MTL_MAX_BYTES, &text, &len, err))
        return -1;
    if (text_to_utf8(&text, &len, path, err)) {
        free(text);
        return -1;
    }
    int rc = mtl_parse(lib, text, len, path, err);
    free(text);
    return rc;
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
    memset(lib, 0, sizeof *lib);
}
