/* timer.h - monotonic wall-clock seconds, and a thread's CPU seconds, for
 * timings and statistics. */
#ifndef LANRAY_TIMER_H
#define LANRAY_TIMER_H

#include <time.h>

static inline double timer_seconds(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static inline double timer_now(void) { return timer_seconds(CLOCK_MONOTONIC); }

/* CPU seconds the calling thread has run. */
static inline double timer_thread_cpu(void) { return timer_seconds(CLOCK_THREAD_CPUTIME_ID); }

#endif
