/* err.h - error messages that travel up to main.
 *
 * Library functions never print and never exit: they return a negative code
 * and describe the problem here (file, line, packet, what was expected). */
#ifndef LANRAY_ERR_H
#define LANRAY_ERR_H

typedef struct {
    char msg[512];
} Err;

/* Sets the message (printf-style) and returns -1, so `return err_set(...)` reads naturally. */
int err_set(Err *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prepends "prefix: " to an existing message. Returns -1. */
int err_prefix(Err *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
