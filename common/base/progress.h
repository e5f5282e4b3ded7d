/* progress.h - a progress line on a terminal: for work longer than a
 * second, a thread asks the caller four times a second what to say and
 * rewrites one line of standard error with it; the line is cleared when the
 * work ends.  Nothing is printed when standard error is not a terminal, so
 * logs and pipes stay clean. */
#ifndef LANRAY_PROGRESS_H
#define LANRAY_PROGRESS_H

#include <stddef.h>

/* Fills line with what to show; elapsed is seconds since the start. */
typedef void (*ProgressFn)(void *ctx, double elapsed, char *line, size_t size);

typedef struct Progress Progress;

/* NULL (and nothing shown) when disabled or standard error is no terminal. */
Progress *progress_start(const char *prog, int enabled, ProgressFn fn, void *ctx);
void progress_stop(Progress *p);
/* Seconds, as "42 s", "3 min 5 s" or "2 h 10 min". */
void progress_duration(double seconds, char *buf, size_t size);

#endif
