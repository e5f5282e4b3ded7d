/* denoisestage.h - a denoised server's frames filtered on a thread of their
 * own (render/denoise.h), so that the loop goes on handing out segments and
 * taking results while the filter runs: in the loop a 1024x768 frame's
 * filter (0.24 s on 2 cores) was time in which the clients' results waited
 * and no segment went out.  One frame at a time: the loop hands a copy in
 * and takes the filtered frame out, in order; handing in a frame while the
 * one before is still being filtered waits for it.  A stage without its
 * filter serves a Whitted view's history alone (render/temporal.h): its
 * moving frames are added up there, and leave without their guides. */
#ifndef LANRAY_DENOISESTAGE_H
#define LANRAY_DENOISESTAGE_H

#include <stdint.h>

#include "base/err.h"
#include "render/temporal.h"

typedef struct DenoiseStage DenoiseStage;

/* What the loop keeps of a frame for its showing (server.c's show_frame). */
typedef struct {
    uint32_t id;
    int scale, still, converged;
    double t0;
    int samples; /* a pixel's (at most, adaptive) */
    int temporal; /* added to the history before it is filtered (path-traced) ... */
    Camera cam;   /* ... as seen by this camera, of this description's and settings' numbers */
    uint64_t epoch;
    const Instance *instances; /* ... its instances placed so (copied in by the put: the stage's own after it) */
    uint32_t instance_count;
} StageFrame;

/* A stage for frames of up to width x height guided pixels of colour_bytes
 * of colour (then the guide), filtered (filter 0: not) on `threads`
 * threads (the stage's own and threads - 1 more), with a history of
 * `temporal` frames (0: none) that frames marked temporal are added to
 * first; NULL with the reason. */
DenoiseStage *denoise_stage_create(uint32_t width, uint32_t height, uint32_t colour_bytes, int threads, int filter,
                                   int temporal, Err *err);
/* Stops the thread (a frame being filtered is finished first) and frees the stage. */
void denoise_stage_destroy(DenoiseStage *st);
/* Hands in a copy of a w x h frame (linear: its codes are linear) with
 * what its showing needs.  The stage must be empty (denoise_stage_take
 * took the frame before). */
void denoise_stage_put(DenoiseStage *st, const uint8_t *pixels, uint32_t w, uint32_t h, int linear,
                       const StageFrame *frame);
/* Whether a frame is in the stage (filtered or not yet). */
int denoise_stage_holds(DenoiseStage *st);
/* The frame handed in, once filtered (wait: until it is): 1 with its
 * colours (valid until the next put) and what was kept of it, the stage
 * then empty; 0 where none is ready. */
int denoise_stage_take(DenoiseStage *st, int wait, const uint8_t **colours, StageFrame *frame);

#endif
