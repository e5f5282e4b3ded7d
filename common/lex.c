/* lex.c - see lex.h. */
#include "lex.h"

#include <errno.h>
#include <stdlib.h>

char *lex_next_raw(Lexer *l)
{
    if (l->p >= l->end)
        return NULL;
    char *line = l->p;
    char *nl = line;
    while (nl < l->end && *nl != '\n')
        nl++;
    l->p = nl < l->end ? nl + 1 : l->end;
    if (nl > line && nl[-1] == '\r')
        nl[-1] = 0;
    if (nl < l->end)
        *nl = 0;
    l->line++;
    return line;
}

int lex_split(char *s, Tokens *t)
{
    t->n = 0;
    t->truncated = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\f' || *s == '\v')
            s++;
        if (*s == 0 || *s == '#')
            break;
        char *start = s;
        if (*s == '"') {
            start = ++s;
            while (*s && *s != '"')
                s++;
        } else {
            while (*s && *s != ' ' && *s != '\t' && *s != '\r' && *s != '\f' && *s != '\v' && *s != '#')
                s++;
        }
        if (t->n == LEX_MAX_TOKENS) {
            t->truncated = 1;
            break;
        }
        t->tok[t->n++] = start;
        if (*s == 0)
            break;
        char c = *s;
        *s++ = 0;
        if (c == '#')
            break;
    }
    return t->n;
}

int lex_next_line(Lexer *l, Tokens *t)
{
    char *line = lex_next_raw(l);
    if (!line)
        return 0;
    lex_split(line, t);
    return 1;
}

int lex_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != 0 || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

int lex_real(const char *s, real *out)
{
    double d;
    if (lex_double(s, &d) || !isfinite((real)d))
        return -1;
    *out = (real)d;
    return 0;
}

int lex_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end != 0 || errno == ERANGE)
        return -1;
    *out = v;
    return 0;
}
