/* opt.h - a program's command line from one table: the parser, its errors
 * and the --help text all come from the same entries, so that the help
 * cannot list an option the parser lacks, a range it does not check or a
 * default that is not the real one (the default printed is the variable's
 * value before parsing).
 *
 * Every program takes --help (usage on standard output, exit 0) and
 * --version.  Values follow the option as the next word or after '='
 * (--width 64, --width=64).  A bad value is an error that names the option,
 * what it wants and what it got: "--width wants 1..16384, got '0'". */
#ifndef LANRAY_OPT_H
#define LANRAY_OPT_H

#include <stdio.h>

#include "base/err.h"

#define LANRAY_VERSION "0.13"

typedef enum {
    OPT_FLAG,   /* int *: set to 1 */
    OPT_INT,    /* int *: a whole number in lo..hi */
    OPT_REAL,   /* double *: a finite number, in rlo..rhi unless both are 0 */
    OPT_STRING, /* const char **: any word */
    OPT_CHOICE, /* int *: the index of the word in choices */
    OPT_CUSTOM, /* parse(value, dst, err) */
} OptKind;

typedef struct {
    const char *name;  /* "--width" */
    const char *alias; /* "-o", or NULL */
    OptKind kind;
    void *dst;
    const char *arg;   /* the value's name in the help: "W" (CHOICE: its words by default) */
    const char *help;  /* what it does, one line */
    long lo, hi;       /* OPT_INT */
    double rlo, rhi;   /* OPT_REAL */
    const char *const *choices; /* OPT_CHOICE: NULL-terminated */
    int (*parse)(const char *value, void *dst, Err *err); /* OPT_CUSTOM: 0 or -1 with what it wants in err */
    const char *range; /* OPT_CUSTOM: the allowed values, for the help and errors */
    const char *def;   /* the default as text where the value's start does not say it ("all cores") */
    int *seen;         /* optional: set to 1 when the option is given */
} Opt;

typedef struct {
    const char *prog;     /* "lanray-render" */
    const char *synopsis; /* "[scene] [options]" */
    const char *about;    /* one paragraph */
    const Opt *opts;      /* ends with an entry whose name is NULL */
    const char **args;    /* where the words that are not options go */
    int min_args, max_args, nargs;
    const char *missing;  /* what to say when fewer than min_args are given: "which server?" */
    const char *exits;    /* the exit statuses, one per line: "0  written" */
} OptSpec;

enum { OPT_OK = 0, OPT_HELP = 1, OPT_VERSION = 2 };

/* Fills the table's variables from argv.  OPT_OK; OPT_HELP or OPT_VERSION
 * when --help or --version is anywhere on the line (then nothing else is
 * parsed, so the variables still hold their defaults for opt_usage: print
 * it or opt_version and exit 0); or -1 with the reason in err (exit 2). */
int opt_parse(OptSpec *spec, int argc, char **argv, Err *err);
/* A program's start: parses, prints --help or --version to standard output
 * and a bad command line (with the usage) to standard error.  Returns
 * OPT_GO when the program should go on, else the exit status to return at
 * once: 0 after --help or --version, 2 after a bad command line. */
#define OPT_GO (-1)
int opt_run(OptSpec *spec, int argc, char **argv);
/* Usage, every option with its range and default, the exit statuses. */
void opt_usage(const OptSpec *spec, FILE *f);
void opt_version(const OptSpec *spec, FILE *f);
/* The index of word s among n names, or -1: the enum a keyword stands for
 * (a scene's settings, a builder's name). */
int opt_word_index(const char *const *names, int n, const char *s);

#endif
