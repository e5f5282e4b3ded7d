/* pace.h - the render scale that holds a frame rate while the view moves.
 *
 * Pure logic (no clock, no sockets), fed by the server's main loop with the
 * time each moving frame took and the scale it was rendered at; the tests
 * drive it with made-up times.  The cost of a frame is taken to be its
 * pixels times a cost a pixel, measured as it runs (an average over the
 * last frames, each frame counted at the scale it had), so the scale for
 * the target is the finest whose predicted time fits.  Hysteresis keeps it
 * from flickering between two scales: it goes coarser as soon as the
 * prediction misses the target, finer only when the finer scale is
 * predicted to take at most PACE_FINER of the target. */
#ifndef LANRAY_PACE_H
#define LANRAY_PACE_H

#include <stdint.h>

#define PACE_FINER 0.8

typedef struct {
    double target;    /* seconds a frame */
    double per_pixel; /* seconds a pixel (0: nothing measured yet) */
    int scale;
} Pace;

/* The scales a pace chooses from, finest first. */
extern const int pace_scales[];
extern const int pace_scale_count;

/* fps 0: no target (scale 1 always); else the scale starts at the coarsest. */
void pace_init(Pace *p, double fps);
/* A moving frame of width x height (the full frame) rendered at `scale` took
 * `seconds`: the scale for the next moving frame. */
int pace_update(Pace *p, double seconds, int scale, uint32_t width, uint32_t height);

#endif
