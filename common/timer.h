/* timer.h - monotonic wall-clock seconds for timings and statistics. */
#ifndef LANRAY_TIMER_H
#define LANRAY_TIMER_H

#include <time.h>

static inline double timer_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#endif
