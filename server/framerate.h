/* framerate.h - the frame rate the window shows (its title and panel).
 *
 * Pure logic, fed the times frames were shown.  The rate is taken over
 * the frames shown in the last second, and over the last two frames at
 * least, from the first of them to the last: never over a window of fixed
 * length that a frame falls in or not.  Counted over each half second, as
 * it was, still frames of 0.67 s (the default scene refining its soft
 * shadows) read 0.0 and 2.0 fps in turn.  A frame later than twice the
 * last ones' interval lowers the rate as it waits (at most 2 / the time
 * since the last frame): the last still frame of 3 s that follows frames
 * of 0.67 s, or a farm that stopped, is not shown at the old rate.  (A
 * reading of 0 once a frame was late by a few intervals showed 0.0 fps
 * for the 3 s of that last still frame.) */
#ifndef LANRAY_FRAMERATE_H
#define LANRAY_FRAMERATE_H

#include <stdint.h>

#define FRAMERATE_KEEP 128 /* the last frames' times kept: a second's at up to 127 fps */
#define FRAMERATE_WINDOW 1.0

typedef struct {
    double t[FRAMERATE_KEEP]; /* ring of the last frames' times */
    uint64_t n;               /* frames added */
} FrameRate;

/* A frame was shown at `now` (seconds, any clock, not decreasing). */
void framerate_add(FrameRate *r, double now);
/* Frames a second at `now`; 0 before two frames. */
double framerate_get(const FrameRate *r, double now);

#endif
