/* err.c - formatting of error messages. */
#include "base/err.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int err_set(Err *e, const char *fmt, ...)
{
    if (!e)
        return -1;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    return -1;
}

int err_prefix(Err *e, const char *fmt, ...)
{
    if (!e)
        return -1;
    char prefix[256], old[sizeof e->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    memcpy(old, e->msg, sizeof old);
    /* truncation of an over-long message is acceptable: keep the start */
    int n = snprintf(e->msg, sizeof e->msg, "%s: ", prefix);
    if (n > 0 && (size_t)n < sizeof e->msg)
        memcpy(e->msg + n, old, strnlen(old, sizeof e->msg - (size_t)n - 1) + 1);
    e->msg[sizeof e->msg - 1] = 0;
    return -1;
}
