/* lex.c - see lex.h. */
#include "base/lex.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

char *lex_next_raw(Lexer *l)
{
    if (l->p >= l->end)
        return NULL;
    char *line = l->p;
    char *nl = memchr(line, '\n', (size_t)(l->end - line));
    if (!nl)
        nl = l->end;
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

/* Clinger's fast path: a decimal whose digits, read as an integer m, stay
 * below 2^53, scaled by 10^e with |e| <= 22, is m * 10^e or m / 10^-e: one
 * correctly rounded operation on two exact doubles, hence the very double
 * that strtod (correctly rounded) gives.  OBJ files are millions of such
 * numbers; anything else (more digits, large exponents, hex, inf, nan,
 * malformed text) is left to strtod.  Returns 0 when it took the number. */
static int fast_double(const char *s, double *out)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                     1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *p = s;
    int neg = *p == '-';
    if (*p == '-' || *p == '+')
        p++;
    uint64_t m = 0;
    int digits = 0, frac = 0, any = 0;
    for (; (unsigned)(*p - '0') < 10; p++, any = 1)
        if ((m = m * 10 + (uint64_t)(*p - '0')) && ++digits > 15)
            return -1;
    if (*p == '.')
        for (p++; (unsigned)(*p - '0') < 10; p++, any = 1, frac++)
            if ((m = m * 10 + (uint64_t)(*p - '0')) && ++digits > 15)
                return -1;
    if (!any)
        return -1;
    int e = 0;
    if (*p == 'e' || *p == 'E') {
        p++;
        int eneg = *p == '-';
        if (*p == '-' || *p == '+')
            p++;
        if ((unsigned)(*p - '0') >= 10)
            return -1;
        for (; (unsigned)(*p - '0') < 10; p++)
            if ((e = e * 10 + (*p - '0')) > 1000)
                return -1;
        if (eneg)
            e = -e;
    }
    if (*p != 0)
        return -1;
    e -= frac;
    if (e < -22 || e > 22)
        return -1;
    /* at most 15 significant digits: m < 10^15 < 2^53, exact */
    double v = (double)m;
    v = e < 0 ? v / pow10[-e] : v * pow10[e];
    *out = neg ? -v : v;
    return 0;
}

int lex_double(const char *s, double *out)
{
    if (fast_double(s, out) == 0)
        return 0;
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

long lex_strtol10(const char *s, char **end)
{
    const char *p = s;
    int neg = *p == '-';
    if (*p == '-' || *p == '+')
        p++;
    if ((unsigned)(*p - '0') >= 10)
        return strtol(s, end, 10); /* blanks, no digits: strtol's rules */
    long v = 0;
    int n = 0;
    for (; (unsigned)(*p - '0') < 10; p++)
        if (++n > 18)
            return strtol(s, end, 10); /* may overflow: strtol clamps and sets errno */
        else
            v = v * 10 + (*p - '0');
    *end = (char *)p;
    return neg ? -v : v;
}
