/* opt.c - see opt.h. */
#include "base/opt.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/real.h"

static const Opt *find(const Opt *opts, const char *name, size_t len)
{
    for (const Opt *o = opts; o->name; o++)
        if ((strlen(o->name) == len && strncmp(o->name, name, len) == 0) ||
            (o->alias && strlen(o->alias) == len && strncmp(o->alias, name, len) == 0))
            return o;
    return NULL;
}

/* The allowed values as the help and the errors say them. */
static void range_text(const Opt *o, char *buf, size_t size)
{
    buf[0] = 0;
    switch (o->kind) {
    case OPT_INT:
        snprintf(buf, size, "%ld..%ld", o->lo, o->hi);
        break;
    case OPT_REAL:
        if (o->rlo != 0 || o->rhi != 0)
            snprintf(buf, size, "a number in %g..%g", o->rlo, o->rhi);
        else
            snprintf(buf, size, "a number");
        break;
    case OPT_CHOICE:
        for (const char *const *c = o->choices; *c; c++) {
            size_t n = strlen(buf);
            snprintf(buf + n, size - n, "%s%s", c == o->choices ? "" : c[1] ? ", " : " or ", *c);
        }
        break;
    case OPT_CUSTOM:
        snprintf(buf, size, "%s", o->range ? o->range : "a value");
        break;
    default:
        break;
    }
}

static int bad_value(const Opt *o, const char *v, Err *err)
{
    char r[256];
    range_text(o, r, sizeof r);
    return err_set(err, "%s wants %s, got '%s'", o->name, r, v);
}

static int set_value(const Opt *o, const char *v, Err *err)
{
    char *end;
    switch (o->kind) {
    case OPT_INT: {
        errno = 0;
        long n = strtol(v, &end, 10);
        if (end == v || *end || errno || n < o->lo || n > o->hi)
            return bad_value(o, v, err);
        *(int *)o->dst = (int)n;
        return 0;
    }
    case OPT_REAL: {
        double d = strtod(v, &end);
        if (end == v || *end || !isfinite(d) || ((o->rlo != 0 || o->rhi != 0) && (d < o->rlo || d > o->rhi)))
            return bad_value(o, v, err);
        *(double *)o->dst = d;
        return 0;
    }
    case OPT_STRING:
        *(const char **)o->dst = v;
        return 0;
    case OPT_CHOICE:
        for (int i = 0; o->choices[i]; i++)
            if (strcmp(o->choices[i], v) == 0) {
                *(int *)o->dst = i;
                return 0;
            }
        return bad_value(o, v, err);
    case OPT_CUSTOM:
        return o->parse(v, o->dst, err) ? bad_value(o, v, err) : 0;
    default:
        return -1;
    }
}

int opt_parse(OptSpec *spec, int argc, char **argv, Err *err)
{
    spec->nargs = 0;
    for (int i = 1; i < argc && strcmp(argv[i], "--") != 0; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return OPT_HELP;
        if (strcmp(argv[i], "--version") == 0)
            return OPT_VERSION;
    }
    int options_end = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!options_end && strcmp(a, "--") == 0) {
            options_end = 1;
            continue;
        }
        if (options_end || a[0] != '-' || a[1] == 0) { /* "-" alone is a word: standard input or output */
            if (spec->nargs >= spec->max_args)
                return err_set(err, "unexpected argument '%s' (usage: %s %s)", a, spec->prog, spec->synopsis);
            spec->args[spec->nargs++] = a;
            continue;
        }
        const char *eq = strchr(a, '=');
        size_t len = eq && a[1] == '-' ? (size_t)(eq - a) : strlen(a);
        const Opt *o = find(spec->opts, a, len);
        if (!o)
            return err_set(err, "unknown option '%.*s' (%s --help lists them)", (int)len, a, spec->prog);
        if (o->seen)
            *o->seen = 1;
        if (o->kind == OPT_FLAG) {
            if (len != strlen(a))
                return err_set(err, "%s takes no value", o->name);
            *(int *)o->dst = 1;
            continue;
        }
        const char *v = len != strlen(a) ? a + len + 1 : i + 1 < argc ? argv[++i] : NULL;
        if (!v) {
            char r[256];
            range_text(o, r, sizeof r);
            return err_set(err, "%s needs a value%s%s%s", o->name, r[0] ? " (" : "", r, r[0] ? ")" : "");
        }
        if (set_value(o, v, err))
            return -1;
    }
    return OPT_OK;
}

int opt_run(OptSpec *spec, int argc, char **argv)
{
    Err err = {{0}};
    int r = opt_parse(spec, argc, argv, &err);
    if (r == OPT_HELP || r == OPT_VERSION) {
        (r == OPT_HELP ? opt_usage : opt_version)(spec, stdout);
        return 0;
    }
    if (r == OPT_OK && spec->nargs < spec->min_args)
        r = err_set(&err, "%s (usage: %s %s)", spec->missing ? spec->missing : "an argument is missing", spec->prog,
                    spec->synopsis);
    if (r == OPT_OK)
        return OPT_GO;
    fprintf(stderr, "%s: %s\n", spec->prog, err.msg);
    return 2;
}

/* The default as the help shows it, or "" for none. */
static void default_text(const Opt *o, char *buf, size_t size)
{
    buf[0] = 0;
    if (o->def) {
        snprintf(buf, size, "%s", o->def);
        return;
    }
    switch (o->kind) {
    case OPT_INT:
        snprintf(buf, size, "%d", *(const int *)o->dst);
        break;
    case OPT_REAL:
        snprintf(buf, size, "%g", *(const double *)o->dst);
        break;
    case OPT_STRING:
        if (*(const char *const *)o->dst)
            snprintf(buf, size, "%s", *(const char *const *)o->dst);
        break;
    case OPT_CHOICE:
        snprintf(buf, size, "%s", o->choices[*(const int *)o->dst]);
        break;
    default:
        break;
    }
}

/* One entry of the option list: the names and value on the left, then the
 * help, the range and the default, wrapped to fit 100 columns. */
static void usage_line(FILE *f, const char *left, const char *help, const char *range, const char *def)
{
    enum { COLUMN = 26, WIDTH = 100 };
    char text[1024];
    snprintf(text, sizeof text, "%s%s%s%s%s%s", help, range[0] ? "; " : "", range, def[0] ? " (default " : "", def,
             def[0] ? ")" : "");
    if (strlen(left) >= COLUMN)
        fprintf(f, "%s\n%-*s", left, COLUMN, "");
    else
        fprintf(f, "%-*s", COLUMN, left);
    const char *p = text;
    for (;;) {
        size_t n = strlen(p);
        if (n <= WIDTH - COLUMN) {
            fprintf(f, "%s\n", p);
            return;
        }
        size_t cut = WIDTH - COLUMN;
        while (cut > 0 && p[cut] != ' ')
            cut--;
        if (cut == 0)
            cut = WIDTH - COLUMN;
        fprintf(f, "%.*s\n%-*s", (int)cut, p, COLUMN, "");
        p += cut + (p[cut] == ' ');
    }
}

void opt_usage(const OptSpec *spec, FILE *f)
{
    fprintf(f, "usage: %s %s\n", spec->prog, spec->synopsis);
    if (spec->about)
        fprintf(f, "\n%s\n", spec->about);
    fprintf(f, "\noptions:\n");
    for (const Opt *o = spec->opts; o->name; o++) {
        char left[160], arg[128], r[256], d[128];
        range_text(o, r, sizeof r);
        default_text(o, d, sizeof d);
        arg[0] = 0;
        if (o->arg) {
            snprintf(arg, sizeof arg, " %s", o->arg);
        } else if (o->kind == OPT_CHOICE) { /* the words are the range: shown once, as the value */
            for (const char *const *c = o->choices; *c; c++) {
                size_t n = strlen(arg);
                snprintf(arg + n, sizeof arg - n, "%s%s", c == o->choices ? " " : "|", *c);
            }
            r[0] = 0;
        }
        if (o->kind == OPT_REAL && strcmp(r, "a number") == 0)
            r[0] = 0;
        snprintf(left, sizeof left, "  %s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "", o->name, arg);
        usage_line(f, left, o->help, r, d);
    }
    usage_line(f, "  -h, --help", "print this help and exit", "", "");
    usage_line(f, "  --version", "print the version and exit", "", "");
    if (spec->exits)
        fprintf(f, "\nexit status:\n%s", spec->exits);
}

void opt_version(const OptSpec *spec, FILE *f)
{
    fprintf(f, "%s %s (%s precision)\n", spec->prog, LANRAY_VERSION, REAL_NAME);
}

int opt_word_index(const char *const *names, int n, const char *s)
{
    for (int i = 0; i < n; i++)
        if (strcmp(s, names[i]) == 0)
            return i;
    return -1;
}
