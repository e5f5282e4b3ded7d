/* pace.h - the render scale that holds a frame rate while the view moves.
 *
 * Pure logic (no clock, no sockets), fed by the server's main loop with the
 * time each moving frame took and the scale it was rendered at; the tests
 * drive it with made-up times.  It keeps each scale's time as measured (an
 * average that weighs the last frames most; a change at the scale in use
 * carries over to the others: the view turned to a costlier part) and
 * predicts an unmeasured scale from the two measured ones nearest in
 * pixels, on a line of a fixed cost a frame and a cost a pixel (a small
 * frame's time is mostly the fixed part).  The scale for the target is the
 * finest predicted to fit.  Hysteresis keeps it from flickering between
 * two scales: it goes coarser as soon as a frame misses the target, finer
 * only when the finer scale is predicted to take at most PACE_FINER of it;
 * a finer scale never measured is tried once the frames take at most
 * PACE_PROBE of the target (the finest never measured whose time in
 * proportion to its pixels fits, so that the first move does not walk
 * down from the coarsest one scale a frame).  A finer scale's time is
 * measured again after PACE_RETRY frames in a row that took at most
 * PACE_FINER of the target: a frame slowed once (the machine busy, a file
 * written) left that scale's time too high, and the flight stayed at a
 * coarse scale to its end.  Going finer onto a scale never measured
 * stays where this frame's time in proportion to the pixels is at most
 * PACE_REACH times the target: a wrong prediction costs one frame of a
 * few targets, not a whole frame's time.  A frame rendered at another
 * scale than the pace's (started before its last change: a pipelined
 * farm) adds its time but moves the scale only coarser, where it missed:
 * the frames between decisions would otherwise decide too, and the
 * sharpness alternated frame by frame. */
#ifndef LANRAY_PACE_H
#define LANRAY_PACE_H

#include <stdint.h>

#define PACE_FINER 0.8
#define PACE_PROBE 0.75
#define PACE_SCALES 14
#define PACE_RETRY 30 /* 2 s at 15 fps */
#define PACE_REACH 4.0 /* times the target */

typedef struct {
    double target;         /* seconds a frame */
    double t[PACE_SCALES]; /* seconds a frame at each of pace_scales (0: not measured) */
    int scale;
    int easy; /* frames in a row at scale with room to spare (PACE_FINER) that stayed there */
    double shown_t;   /* pace_shown: when the period being measured began (0: no frame yet) */
    int shown_frames; /* and the moving frames shown in it */
    int after_still;  /* the period began at a still frame (pace_still) */
} Pace;

/* The scales a pace chooses from, finest first, in quarter steps (upscale.h). */
extern const int pace_scales[];
extern const int pace_scale_count;

/* fps 0: no target (scale 1, UPSCALE_ONE, always); else the scale starts
 * at the coarsest, and the first frame shown (pace_shown: its time from
 * its start) moves it. */
void pace_init(Pace *p, double fps);
/* A new target (the window's T key), the times measured kept; 0: none,
 * every frame whole. */
void pace_set_target(Pace *p, double fps);
/* A moving frame of width x height (the full frame) rendered at `scale`
 * (quarter steps) took `seconds`: the scale for the next moving frame. */
int pace_update(Pace *p, double seconds, int scale, uint32_t width, uint32_t height);
/* A moving frame rendered at `scale`, started at `started`, was shown at
 * `now` (seconds, one clock): pace_update with the period between shows,
 * where the frames
 * shown less than half a target after the last update count together (a
 * pipelined farm hands over frames in bursts, two in one wake-up of the
 * server, the second's period a few microseconds: taken alone, a probe
 * from the coarsest scale went to every pixel at once).  The scale for
 * the next moving frame; without a target, p->scale (a period starts). */
int pace_shown(Pace *p, double now, double started, int scale, uint32_t width, uint32_t height);
/* A still frame was shown at `now`: the next moving frame's period starts
 * there, or where that frame was started if later (the farm idled in
 * between: a window's converged picture waits for a move, and the seconds
 * it waited, taken as the first moving frame's time, sent the scale to the
 * coarsest and every finer scale's time up with it; the window then showed
 * frames at scale 4.5 at 58 fps where 15 were asked, coming finer one
 * scale every PACE_RETRY frames). */
void pace_still(Pace *p, double now);

#endif
