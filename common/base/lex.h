/* lex.h - line-oriented tokenising shared by the text formats (OBJ, MTL, scenes).
 *
 * Works in place on a mutable NUL-terminated buffer: each line is cut out and
 * split at whitespace; '#' starts a comment; "double quotes" group a token
 * with spaces.  Numbers must use the whole token and be finite. */
#ifndef LANRAY_LEX_H
#define LANRAY_LEX_H

#include <stddef.h>

#include "base/real.h"

#define LEX_MAX_TOKENS 256

typedef struct {
    char *p;   /* next unread byte */
    char *end;
    int line;  /* number of the line last returned */
} Lexer;

typedef struct {
    char *tok[LEX_MAX_TOKENS];
    int n;
    int truncated; /* the line had more than LEX_MAX_TOKENS tokens */
} Tokens;

/* A UTF-8 byte-order mark at the start (editors on Windows write one) is
 * not part of the first line: skipped, or the first directive or vertex
 * would not be recognised. */
static inline Lexer lex_make(char *text, size_t len)
{
    Lexer l = {text, text + len, 0};
    if (len >= 3 && (unsigned char)text[0] == 0xEF && (unsigned char)text[1] == 0xBB && (unsigned char)text[2] == 0xBF)
        l.p += 3;
    return l;
}

/* Splits the next line into tokens; returns 0 at the end of the text. */
int lex_next_line(Lexer *l, Tokens *t);
/* Like lex_next_line but keeps the raw line (for OBJ faces with many corners). */
char *lex_next_raw(Lexer *l);
/* Splits a raw line; returns the token count. */
int lex_split(char *line, Tokens *t);

int lex_real(const char *s, real *out);
int lex_double(const char *s, double *out);
int lex_long(const char *s, long *out);

/* strtol(s, end, 10), with a fast path for the short decimal integers of
 * OBJ face corners ("12/7/12"): a sign and up to 18 digits are read here,
 * anything else (blanks first, more digits) by strtol itself, so the
 * result and *end are always strtol's. */
long lex_strtol10(const char *s, char **end);

#endif
