/* framerate.c - see framerate.h. */
#include "framerate.h"

void framerate_add(FrameRate *r, double now)
{
    r->t[r->n % FRAMERATE_KEEP] = now;
    r->n++;
}

/* The time of the frame k frames before the last (k < n, k < KEEP). */
static double frame_t(const FrameRate *r, uint64_t k)
{
    return r->t[(r->n - 1 - k) % FRAMERATE_KEEP];
}

double framerate_get(const FrameRate *r, double now)
{
    if (r->n < 2)
        return 0;
    const uint64_t kept = r->n < FRAMERATE_KEEP ? r->n : FRAMERATE_KEEP;
    uint64_t k = 1; /* the first frame counted: k before the last */
    while (k + 1 < kept && frame_t(r, k + 1) >= now - FRAMERATE_WINDOW)
        k++;
    const double last = frame_t(r, 0), span = last - frame_t(r, k);
    const double rate = span > 0 ? (double)k / span : 0, late = now - last > 0 ? 2 / (now - last) : rate;
    return late < rate ? late : rate;
}
