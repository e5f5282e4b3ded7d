/* field.c - see field.h. */
#include "base/field.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/opt.h"

static int takes(const Field *f, int variant) { return f->variants == 0 || (f->variants >> variant & 1); }
static int on_wire(const Field *f) { return !(f->flags & FIELD_FILE); }
static int in_files(const Field *f) { return !(f->flags & FIELD_WIRE); }

/* Numbers a field holds (0 for the integer types). */
static int reals_of(const Field *f)
{
    return f->type == FIELD_REAL ? 1 : f->type == FIELD_VEC ? 3 : f->type == FIELD_REALS ? f->n : 0;
}

static real *real_at(const Field *f, void *item) { return (real *)((char *)item + f->off); }
static const real *real_at_c(const Field *f, const void *item) { return (const real *)((const char *)item + f->off); }
static int *int_at(const Field *f, void *item) { return (int *)((char *)item + f->off); }
static const int *int_at_c(const Field *f, const void *item) { return (const int *)((const char *)item + f->off); }

void field_defaults(const FieldKind *k, void *item, size_t size, int variant)
{
    if (size < k->size) { /* a caller's error, not the input's */
        fprintf(stderr, "field_defaults: %zu bytes for an item of kind %s, which addresses %zu\n", size, k->name, k->size);
        abort();
    }
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (!takes(f, variant))
            continue;
        int n = reals_of(f);
        for (int j = 0; j < n; j++)
            real_at(f, item)[j] = (real)f->def;
        if (n == 0)
            *int_at(f, item) = f->type == FIELD_FLAG ? 0 : (int)f->def;
    }
}

int field_index(const FieldKind *k, const char *key)
{
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (in_files(f) && (strcmp(f->key, key) == 0 || (f->alias && strcmp(f->alias, key) == 0)))
            return (int)i;
    }
    return -1;
}

static int word_count(const char *const *w)
{
    int n = 0;
    while (w && w[n])
        n++;
    return n;
}

int field_variant(const FieldKind *k, const char *word)
{
    return k->variants ? opt_word_index(k->variants, word_count(k->variants), word) : -1;
}

const char *const *field_words(const FieldKind *k, const char *key)
{
    int i = field_index(k, key);
    return i >= 0 && k->fields[i].type == FIELD_CHOICE ? k->fields[i].words : NULL;
}

/* The range a number must be in, in words ("must be positive"); a stored
 * value may also be 0 where the field allows "none" (FIELD_ZERO_OK), a
 * file's may not (it gave the key to have one). */
static void range_words(const Field *f, int stored, char *buf, size_t size)
{
    const int lo_open = (f->flags & FIELD_LO_OPEN) != 0, hi_open = (f->flags & FIELD_HI_OPEN) != 0;
    const int no_hi = f->hi >= FIELD_INF, no_lo = f->lo <= -FIELD_INF;
    if (stored && (f->flags & FIELD_ZERO_OK) && (no_hi || f->lo == 0)) /* 0 joins the range */
        snprintf(buf, size, no_hi ? "must not be negative" : "must be from 0 to %g", f->hi);
    else if (stored && (f->flags & FIELD_ZERO_OK))
        snprintf(buf, size, "must be 0 or from %g to %g", f->lo, f->hi);
    else if (f->type == FIELD_WHOLE)
        snprintf(buf, size, "must be a whole number from %g to %g", f->lo, f->hi);
    else if (no_lo && no_hi)
        snprintf(buf, size, "must be finite");
    else if (no_hi && f->lo == 0)
        snprintf(buf, size, lo_open ? "must be positive" : "must not be negative");
    else if (no_hi)
        snprintf(buf, size, lo_open ? "must be above %g" : "must be at least %g", f->lo);
    else if (lo_open && hi_open)
        snprintf(buf, size, "must be between %g and %g", f->lo, f->hi);
    else if (hi_open)
        snprintf(buf, size, "must be from %g up to (not including) %g", f->lo, f->hi);
    else if (lo_open)
        snprintf(buf, size, "must be above %g and at most %g", f->lo, f->hi);
    else
        snprintf(buf, size, "must be from %g to %g", f->lo, f->hi);
}

static int in_range(const Field *f, int stored, double v)
{
    if (!isfinite(v))
        return 0;
    if (stored && v == 0 && (f->flags & FIELD_ZERO_OK))
        return 1;
    if (f->flags & FIELD_LO_OPEN ? !(v > f->lo) : !(v >= f->lo))
        return 0;
    if (f->flags & FIELD_HI_OPEN ? !(v < f->hi) : !(v <= f->hi))
        return 0;
    return f->type != FIELD_WHOLE || v == floor(v);
}


/* "a, b or c" */
static void words_list(const char *const *w, char *buf, size_t size)
{
    int n = word_count(w);
    buf[0] = 0;
    for (int i = 0; i < n; i++) {
        size_t l = strlen(buf);
        snprintf(buf + l, size - l, "%s%s", i == 0 ? "" : i == n - 1 ? " or " : ", ", w[i]);
    }
}

/* What is wrong with field f's value in item, in words after the key
 * ("must be positive"), into buf; or NULL. */
static const char *value_problem(const Field *f, int stored, const void *item, char *buf, size_t size)
{
    int n = reals_of(f);
    if (n) {
        const real *v = real_at_c(f, item);
        for (int j = 0; j < n; j++)
            if (!in_range(f, stored, (double)v[j])) {
                range_words(f, stored, buf, size);
                return buf;
            }
        /* a vector, or each vector of a list, must not be zero (nor so
         * small that its length is: it is divided by) */
        for (int j = 0; (f->flags & FIELD_NONZERO) && j + 2 < n; j += 3)
            if (!(v3_len(v3(v[j], v[j + 1], v[j + 2])) > R(0))) {
                snprintf(buf, size, "must not be zero");
                return buf;
            }
        return NULL;
    }
    int i = *int_at_c(f, item);
    if (f->type == FIELD_WHOLE && !in_range(f, stored, (double)i)) {
        range_words(f, stored, buf, size);
        return buf;
    }
    if (f->type == FIELD_CHOICE && (i < 0 || i >= word_count(f->words))) {
        snprintf(buf, size, "is not one of its words");
        return buf;
    }
    if (f->type == FIELD_FLAG && (i & ~1)) {
        snprintf(buf, size, "is not 0 or 1");
        return buf;
    }
    return NULL;
}

static int at_default(const Field *f, const void *item);

const char *field_problem(const FieldKind *k, const void *item, int variant, char *buf, size_t size)
{
    char words[96];
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        /* a group at its defaults is absent: nothing to check */
        if (!on_wire(f) || !takes(f, variant) || (f->group && at_default(f, item)))
            continue;
        if (value_problem(f, 1, item, words, sizeof words)) {
            snprintf(buf, size, "'%s' %s", f->key, words);
            return buf;
        }
    }
    return NULL;
}

/* The keys a variant takes, for an error: "position, color, intensity". */
static void key_list(const FieldKind *k, int variant, char *buf, size_t size)
{
    buf[0] = 0;
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (!in_files(f) || !takes(f, variant))
            continue;
        size_t l = strlen(buf);
        snprintf(buf + l, size - l, "%s%s", l ? ", " : "", f->key);
    }
}

/* The directive's name for errors: "sphere", "spot light". */
static void directive_name(const FieldKind *k, int variant, char *buf, size_t size)
{
    if (k->variants)
        snprintf(buf, size, "%s %s", k->variants[variant], k->name);
    else
        snprintf(buf, size, "%s", k->name);
}

/* One key's value from tokens at *i. */
static int read_value(const Field *f, const char *dname, const Tokens *t, int *i, void *item, const char **name,
                      const char *where, Err *err)
{
    if (f->type == FIELD_FLAG) {
        *int_at(f, item) = 1;
        return 0;
    }
    if (f->type == FIELD_NAME || f->type == FIELD_CHOICE) {
        if (*i >= t->n)
            return err_set(err, "%s: '%s' of %s expects a %s", where, f->key, dname,
                           f->type == FIELD_NAME ? "name" : "word");
        const char *w = t->tok[(*i)++];
        if (f->type == FIELD_NAME) {
            *name = w;
            return 0;
        }
        int j = opt_word_index(f->words, word_count(f->words), w);
        if (j >= 0) {
            *int_at(f, item) = j;
            return 0;
        }
        char list[160];
        words_list(f->words, list, sizeof list);
        return err_set(err, "%s: '%s' of %s must be %s, not '%s'", where, f->key, dname, list, w);
    }
    int n = f->type == FIELD_WHOLE ? 1 : reals_of(f);
    real v[16];
    for (int j = 0; j < n; j++, (*i)++)
        if (*i >= t->n || lex_real(t->tok[*i], &v[j]))
            return err_set(err, "%s: '%s' of %s expects %d finite number%s, got '%s'", where, f->key, dname, n,
                           n > 1 ? "s" : "", *i < t->n ? t->tok[*i] : "end of line");
    char words[96];
    if (f->type == FIELD_WHOLE) {
        if (!in_range(f, 0, (double)v[0])) {
            range_words(f, 0, words, sizeof words);
            return err_set(err, "%s: '%s' of %s %s", where, f->key, dname, words);
        }
        *int_at(f, item) = (int)v[0];
        return 0;
    }
    memcpy(real_at(f, item), v, (size_t)n * sizeof *v);
    if (value_problem(f, 0, item, words, sizeof words))
        return err_set(err, "%s: '%s' of %s %s", where, f->key, dname, words);
    return 0;
}

/* The rules between keys (field.h). */
static int check_rules(const FieldKind *k, FieldSet given, const char *dname, const char *where, Err *err)
{
    for (const FieldRule *r = k->rules; r && r->a; r++) {
        int a = field_index(k, r->a), b = field_index(k, r->b);
        const int b2 = r->or_b ? field_index(k, r->or_b) : -1;
        int ha = a >= 0 && (given >> a & 1), hb = (b >= 0 && (given >> b & 1)) || (b2 >= 0 && (given >> b2 & 1));
        int broken = r->kind == RULE_NEEDS ? ha && !hb : r->kind == RULE_EXCLUDES ? ha && hb : ha != hb;
        if (!broken)
            continue;
        if (r->why)
            return err_set(err, "%s: %s", where, r->why);
        if (r->kind == RULE_NEEDS)
            return err_set(err, "%s: '%s' of %s needs '%s'", where, r->a, dname, r->b);
        if (r->kind == RULE_EXCLUDES)
            return err_set(err, "%s: %s takes either '%s' or '%s', not both", where, dname, r->a, r->b);
        return err_set(err, "%s: %s takes '%s' and '%s' together", where, dname, r->a, r->b);
    }
    return 0;
}

int field_read(const FieldKind *k, const Tokens *t, int start, int variant, void *item, FieldSet *given,
               const char **names, const char *where, Err *err)
{
    char dname[64], keys[256];
    directive_name(k, variant, dname, sizeof dname);
    *given = 0;
    if (k->count > FIELD_MAX)
        return err_set(err, "%s: %s has %u fields, more than %d", where, k->name, k->count, FIELD_MAX);
    for (int i = start; i < t->n;) {
        int fi = field_index(k, t->tok[i]);
        if (fi < 0) {
            key_list(k, variant, keys, sizeof keys);
            return err_set(err, "%s: unknown keyword '%s' for %s (expected one of: %s)", where, t->tok[i], dname, keys);
        }
        const Field *f = &k->fields[fi];
        if (!takes(f, variant)) {
            key_list(k, variant, keys, sizeof keys);
            return err_set(err, "%s: a %s takes no '%s' (it takes: %s)", where, dname, f->key, keys);
        }
        if (*given >> fi & 1)
            return err_set(err, "%s: keyword '%s' given twice for %s", where, f->key, dname);
        *given |= (FieldSet)1 << fi;
        i++;
        if (read_value(f, dname, t, &i, item, &names[fi], where, err))
            return -1;
    }
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if ((f->flags & FIELD_REQUIRED) && takes(f, variant) && !(*given >> i & 1))
            return err_set(err, "%s: %s needs '%s'", where, dname, f->key);
    }
    return check_rules(k, *given, dname, where, err);
}

/* Whether field f of item holds its default (for the wire's groups). */
static int at_default(const Field *f, const void *item)
{
    int n = reals_of(f);
    for (int j = 0; j < n; j++)
        if (real_at_c(f, item)[j] != (real)f->def)
            return 0;
    return n ? 1 : *int_at_c(f, item) == (f->type == FIELD_FLAG ? 0 : (int)f->def);
}

/* Whether field f of an item of this variant, with these group bits, is on the wire. */
static int sent(const Field *f, int variant, uint32_t groups)
{
    return on_wire(f) && takes(f, variant) && (!f->group || (groups >> f->group & 1));
}

static int variant_of(const FieldKind *k, const void *item)
{
    return k->variants ? *(const int *)((const char *)item + k->variant_off) : 0;
}

/* The fields of an item of this variant and these groups, in table order:
 * written to out, or, without out, read from in. */
static void walk_fields(const FieldKind *k, int variant, uint32_t groups, void *item, Sink *out, Cursor *in)
{
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (!sent(f, variant, groups))
            continue;
        int n = reals_of(f);
        for (int j = 0; j < n; j++) {
            double d = (double)real_at(f, item)[j];
            if (out)
                sink_put(out, &d, sizeof d);
            else if (cursor_get(in, &d, sizeof d) == 0)
                real_at(f, item)[j] = (real)d;
        }
        if (n == 0 && out)
            sink_u32(out, (uint32_t)*int_at(f, item));
        else if (n == 0)
            *int_at(f, item) = (int)cursor_u32(in);
    }
}

void field_encode(const FieldKind *k, const void *item, Sink *out)
{
    const int variant = variant_of(k, item);
    if (k->variants)
        sink_u32(out, (uint32_t)variant);
    uint32_t groups = 0;
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (f->group && on_wire(f) && takes(f, variant) && !at_default(f, item))
            groups |= 1u << f->group;
    }
    if (k->group_count)
        sink_u32(out, groups);
    walk_fields(k, variant, groups, (void *)item, out, NULL); /* only read from */
}

int field_decode(const FieldKind *k, Cursor *c, void *item, size_t size)
{
    int variant = 0;
    if (k->variants) {
        uint32_t v = cursor_u32(c);
        if (c->failed || v >= (uint32_t)word_count(k->variants))
            return -1;
        variant = (int)v;
    }
    field_defaults(k, item, size, variant);
    if (k->variants)
        *(int *)((char *)item + k->variant_off) = variant;
    uint32_t groups = k->group_count ? cursor_u32(c) : 0;
    if (groups & ~(((1u << k->group_count) - 1) << 1))
        return -1;
    walk_fields(k, variant, groups, item, NULL, c);
    return c->failed ? -1 : 0;
}

uint32_t field_min_bytes(const FieldKind *k)
{
    uint32_t min = UINT32_MAX;
    int nv = k->variants ? word_count(k->variants) : 1;
    for (int v = 0; v < nv; v++) {
        uint32_t b = (k->variants ? 4 : 0) + (k->group_count ? 4 : 0);
        for (uint32_t i = 0; i < k->count; i++) {
            const Field *f = &k->fields[i];
            if (on_wire(f) && takes(f, v) && !f->group)
                b += reals_of(f) ? 8 * (uint32_t)reals_of(f) : 4;
        }
        min = b < min ? b : min;
    }
    return min;
}

/* A field's values in words, for the docs. */
static void values_words(const Field *f, char *buf, size_t size)
{
    char range[96] = "";
    if (f->type == FIELD_CHOICE) {
        words_list(f->words, range, sizeof range);
        snprintf(buf, size, "%s", range);
        return;
    }
    if (f->type == FIELD_FLAG) {
        snprintf(buf, size, "the word alone");
        return;
    }
    if (f->type == FIELD_NAME) {
        snprintf(buf, size, "a name");
        return;
    }
    range_words(f, 0, range, sizeof range);
    const char *r = strcmp(range, "must be finite") == 0                     ? ""
                    : strncmp(range, "must be a whole number ", 23) == 0 ? range + 23
                    : strcmp(range, "must not be negative") == 0         ? "not negative"
                    : strncmp(range, "must be ", 8) == 0                 ? range + 8
                                                                         : range;
    int n = reals_of(f);
    const char *what = f->type == FIELD_WHOLE ? "a whole number" : n == 1 ? "a number" : NULL;
    char count[32];
    if (!what)
        snprintf(count, sizeof count, "%d numbers", n);
    snprintf(buf, size, "%s%s%s%s", what ? what : count, *r ? ", " : "", r,
             f->flags & FIELD_NONZERO ? (n > 3 ? ", none of the vectors zero" : ", not all zero") : "");
}

void field_doc(const FieldKind *k, Sink *out)
{
    char line[1024], values[160], def[64], vars[128];
    const char *head = k->variants ? "| key | values | default | lights | meaning |\n|---|---|---|---|---|\n"
                                   : "| key | values | default | meaning |\n|---|---|---|---|\n";
    sink_put(out, head, strlen(head));
    for (uint32_t i = 0; i < k->count; i++) {
        const Field *f = &k->fields[i];
        if (!in_files(f))
            continue;
        values_words(f, values, sizeof values);
        if (f->shown_default)
            snprintf(def, sizeof def, "%s", f->shown_default);
        else if (f->flags & FIELD_REQUIRED)
            snprintf(def, sizeof def, "required");
        else if (f->type == FIELD_CHOICE)
            snprintf(def, sizeof def, "%s", f->words[(int)f->def]);
        else if (f->type == FIELD_FLAG)
            snprintf(def, sizeof def, "off");
        else if (f->type == FIELD_NAME)
            snprintf(def, sizeof def, "none");
        else if (f->type == FIELD_VEC)
            snprintf(def, sizeof def, "%g %g %g", f->def, f->def, f->def);
        else if (f->type == FIELD_REALS)
            snprintf(def, sizeof def, "none");
        else
            snprintf(def, sizeof def, "%g", f->def);
        vars[0] = 0;
        for (int v = 0; k->variants && k->variants[v]; v++)
            if (takes(f, v)) {
                size_t l = strlen(vars);
                snprintf(vars + l, sizeof vars - l, "%s%s", l ? ", " : "", k->variants[v]);
            }
        char key[64];
        snprintf(key, sizeof key, f->alias ? "`%s` (`%s`)" : "`%s`", f->key, f->alias);
        if (k->variants)
            snprintf(line, sizeof line, "| %s | %s | %s | %s | %s |\n", key, values, def, vars, f->doc);
        else
            snprintf(line, sizeof line, "| %s | %s | %s | %s |\n", key, values, def, f->doc);
        sink_put(out, line, strlen(line));
    }
}

void field_wire_doc(const FieldKind *k, Sink *out)
{
    char line[2048];
    snprintf(line, sizeof line, "- `%s`:%s%s", k->name, k->variants ? " u32 kind," : "",
             k->group_count ? " u32 group bits," : "");
    for (uint32_t g = 0; g <= k->group_count; g++) {
        int first = 1;
        for (uint32_t i = 0; i < k->count; i++) {
            const Field *f = &k->fields[i];
            if (!on_wire(f) || f->group != g)
                continue;
            size_t l = strlen(line);
            int n = reals_of(f);
            char type[16];
            snprintf(type, sizeof type, n > 1 ? "f64[%d]" : n ? "f64" : f->type == FIELD_NAME ? "i32" : "u32", n);
            char num[16] = ""; /* "10:", not the character after '9' */
            if (first && g)
                snprintf(num, sizeof num, "%u:", g);
            snprintf(line + l, sizeof line - l, "%s%s `%s` %s", first && g ? " group " : first ? "" : ",", num, f->key,
                     type);
            char vars[128] = "";
            for (int v = 0; k->variants && f->variants && k->variants[v]; v++)
                if (takes(f, v)) {
                    size_t m = strlen(vars);
                    snprintf(vars + m, sizeof vars - m, "%s%s", m ? ", " : "", k->variants[v]);
                }
            if (vars[0]) {
                l = strlen(line);
                snprintf(line + l, sizeof line - l, " (%s)", vars);
            }
            first = 0;
        }
        if (g < k->group_count)
            strncat(line, ";", sizeof line - strlen(line) - 1);
    }
    strncat(line, "\n", sizeof line - strlen(line) - 1);
    sink_put(out, line, strlen(line));
}
