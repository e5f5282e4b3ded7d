/* field.h - a kind of item described once, as a table of its fields.
 *
 * A field is a scene-file keyword (with another spelling, maybe), where its
 * value sits in the item's struct, its type, its range and default, whether
 * a file must give it, the group it travels in on the wire, which variants
 * of the kind take it (the kinds of light), and a line of documentation.
 * The scene parser reads keys by the table, the scene codec writes and
 * reads items by it, the checks of an item's values walk it, and the
 * tables in docs/scene.md are printed from it: a field added is a row
 * added (the scene's tables are in scene/scene_fields.c, the material's in
 * shading/material.c).
 *
 * On the wire an item is its fields in table order, reals as float64 (a
 * float or a double exactly) and the rest as u32; where the kind has
 * groups, a u32 of group bits first, a group's fields present only where
 * one of them is not its default, so that an item pays for what it uses. */
#ifndef LANRAY_FIELD_H
#define LANRAY_FIELD_H

#include <stddef.h>
#include <stdint.h>

#include "base/cursor.h"
#include "base/err.h"
#include "base/lex.h"
#include "base/vec.h"

typedef enum {
    FIELD_REAL,   /* a number (real) */
    FIELD_VEC,    /* three numbers (vec3) */
    FIELD_REALS,  /* n numbers (real[n]) */
    FIELD_WHOLE,  /* a whole number (int) */
    FIELD_CHOICE, /* one of its words (int: the word's index) */
    FIELD_FLAG,   /* the keyword alone (int: 1) */
    FIELD_NAME,   /* the name of another item (int32: its index, resolved by the caller; -1 none) */
} FieldType;

enum {
    FIELD_REQUIRED = 1 << 0, /* a file must give it */
    FIELD_LO_OPEN = 1 << 1,  /* the range excludes lo */
    FIELD_HI_OPEN = 1 << 2,  /* the range excludes hi */
    FIELD_NONZERO = 1 << 3,  /* a vector or list of vectors that must not be zero */
    FIELD_FILE = 1 << 4,     /* in files only: not stored as itself, not on the wire (a kind's hook uses it) */
    FIELD_WIRE = 1 << 5,     /* on the wire only: not a scene-file keyword */
    FIELD_ZERO_OK = 1 << 6,  /* 0 is allowed besides the range: "none" */
};

#define FIELD_INF 1e300

typedef struct {
    const char *key;   /* the keyword */
    const char *alias; /* another spelling, or NULL */
    FieldType type;
    uint8_t n;         /* FIELD_REALS: how many */
    uint8_t group;     /* 0: always on the wire; else a group bit (1..31) */
    uint16_t flags;
    size_t off;        /* in the item's struct */
    double lo, hi;     /* each number's range (FIELD_WHOLE, FIELD_REAL, FIELD_VEC, FIELD_REALS) */
    double def;        /* the default: each number's, a choice's index, a name's index */
    const char *const *words; /* FIELD_CHOICE: its words, NULL-terminated */
    uint32_t variants; /* the variants that take it (bit v for variant v); 0: all */
    const char *doc;   /* what it means, for docs/scene.md */
    const char *shown_default; /* the docs' default where it is not `def` alone, or NULL */
} Field;

/* A rule between two fields of a file's directive (by their keys). */
typedef enum {
    RULE_NEEDS,    /* a is given only with b */
    RULE_EXCLUDES, /* not both */
    RULE_TOGETHER, /* both or neither */
} RuleKind;

typedef struct {
    RuleKind kind;
    const char *a, *b;
    const char *why; /* the error, or NULL for the rule's own words */
    const char *or_b; /* RULE_NEEDS: a is given with b or with this one (NULL: b alone) */
} FieldRule;

typedef struct {
    const char *name;          /* the directive */
    const Field *fields;       /* in wire order */
    uint32_t count;
    const FieldRule *rules;    /* NULL-keyed end, or NULL */
    const char *const *variants; /* the variants' words (light kinds), NULL-terminated; NULL: none */
    size_t variant_off;        /* where the item keeps its variant (an int) */
    uint32_t group_count;      /* group bits in use: 0 for a kind without groups */
    size_t size;               /* the bytes of the item (its spec) the offsets address, file-only fields
                                * included: field_defaults and field_decode are given at least these */
} FieldKind;

/* Which fields a directive gave: bit i for field i; a kind has at most
 * FIELD_MAX fields. */
typedef uint64_t FieldSet;
#define FIELD_MAX 64

/* Every field of item that the variant takes (0 for a kind without) at
 * its default, FIELD_FILE fields included; the rest is left alone.  item
 * holds `size` bytes, at least the kind's (an item smaller than its spec,
 * whose file-only fields lie past it, stops the program: a write past it
 * would go unseen). */
void field_defaults(const FieldKind *k, void *item, size_t size, int variant);

/* The keys of tokens [start, n) of a directive into item, which holds its
 * defaults: unknown, repeated, malformed and out-of-range keys, missing
 * required ones and broken rules are errors naming `where` (file:line),
 * the key and the directive.  A variant's fields must be its own.  A
 * FIELD_NAME's word is left in names[field index] (for the caller to
 * resolve); *given says which keys were there. */
int field_read(const FieldKind *k, const Tokens *t, int start, int variant, void *item, FieldSet *given,
               const char **names, const char *where, Err *err);

/* The index of the field with that key (or alias), or -1. */
int field_index(const FieldKind *k, const char *key);
/* The variant a word names (a light's kind), or -1. */
int field_variant(const FieldKind *k, const char *word);

/* The words of the choice with that key (NULL-terminated, in the order of
 * its values), or NULL: for a command line that offers the same choice. */
const char *const *field_words(const FieldKind *k, const char *key);

/* Whether a directive gave that key. */
static inline int field_given(const FieldKind *k, FieldSet given, const char *key)
{
    int i = field_index(k, key);
    return i >= 0 && (given >> i & 1);
}

/* What is wrong with item's values, or NULL: a number that is not finite
 * or out of its field's range, a zero vector where it must not be, a
 * choice out of range.  `variant`: the item's (0 for a kind without). */
const char *field_problem(const FieldKind *k, const void *item, int variant, char *buf, size_t size);

/* The item on the wire (its variant first, where the kind has variants). */
void field_encode(const FieldKind *k, const void *item, Sink *out);
/* ... and back, into an item that is all zero: it holds the fields'
 * defaults where a group is absent.  Returns -1 on an unknown variant or
 * group bits, or truncation. */
int field_decode(const FieldKind *k, Cursor *c, void *item, size_t size);
/* The fewest bytes an item takes on the wire: to bound counts by the bytes left. */
uint32_t field_min_bytes(const FieldKind *k);

/* The kind's table for docs/scene.md, in markdown: key, values, default, meaning. */
void field_doc(const FieldKind *k, Sink *out);
/* The kind's wire layout for docs/protocol.md, one markdown line: the
 * variant and group words, then each field's name and type in order, a
 * group's fields after "group N:". */
void field_wire_doc(const FieldKind *k, Sink *out);

#endif
