/* temporal.h - a path-traced view's frames added up while its camera
 * moves (temporal accumulation, reprojected).
 *
 * A moving frame has one sample a pixel, and one sample of light that
 * bounces is grain.  Each moving frame of a farm takes another of the
 * pixel's samples (settings jitter: sample k of the pixel's 32 x 32, in
 * their progressive order), and the server adds each pixel to what the
 * frames before showed of the same surface point: the point (its guide's
 * distance along the pixel's ray) is projected into the frame before's
 * camera (geom/camera.h camera_project), and that frame's pixels about it
 * count where they saw a surface at that distance (within 5%) facing the
 * same way (normals within 25 degrees): the four about it weighed
 * bilinearly, their light by Catmull-Rom's cubic of the sixteen where all
 * of those saw it; a pixel that finds none (a surface coming into view)
 * starts again.  The mean
 * weighs the last `frames` frames at most (an exponential average of
 * weight 1/frames after that), so that light that changes (a mirror's
 * image, a shadow that moves) lags by a few frames, not for ever.
 *
 * Still frames (the camera as the frame before's) add their samples up on
 * their own (render/progressive.h); while a pixel's still samples are
 * fewer than its history's, it shows both, weighed by their samples (the
 * first still frame, one sample, is not noisier than the moving frames
 * before it), then the still frame's own bytes: a converged frame is
 * lanray-render's.  A new scene or new settings (the epoch) drop the
 * history; a model's turn (lanray-server --rotate) does not: the rest of
 * the picture keeps it, and a pixel whose guide names the instance it saw
 * (Guide.instance) looks for its point where the instance had it in the
 * frame before (TemporalFrame.instances).
 *
 * Pixels keep their layout (colour, then the guide, render/denoise.h):
 * the colour becomes the history's, and the guide's noise byte the
 * standard error of its mean where 4 frames or more weigh in, so that the
 * denoiser that follows smooths what is still noisy and keeps what is not.
 * A Whitted view's moving frames near the full size are added up too
 * (lanray-server --whitted-temporal; settings guides: each pixel's guide
 * is what its camera ray met first, mirrors and glass included), without
 * jitter (a jittered sample made the edges noise that two frames did not
 * add up: the camera's own motion moves the samples over the surfaces)
 * and with the clip: the light the history brings is held within the
 * frame's own about the pixel (its 3 x 3's least and most, channel by
 * channel), so that a highlight or a reflection that moved with the view
 * does not linger, where a penumbra's grain leaves the range wide.
 *
 * Every pixel is computed alone, in float arithmetic in a fixed order: a
 * farm's frames and lanray-render --server-frame's are the same bytes. */
#ifndef LANRAY_TEMPORAL_H
#define LANRAY_TEMPORAL_H

#include <stdint.h>

#include "base/pool.h"
#include "geom/camera.h"
#include "scene/scene.h"

#define TEMPORAL_DEFAULT_FRAMES 4
/* ... and a Whitted view's (a longer history blurred its edges and
 * highlights more than it took out of its lamps' grain) */
#define TEMPORAL_WHITTED_FRAMES 2
#define TEMPORAL_MAX_FRAMES 64

/* The frames a history weighs over a view of settings rs (one rule for a
 * server's frames and lanray-render --server-frame's): a path-traced
 * view's `temporal` where it is denoised (the guides are its filter's), a
 * Whitted one's `whitted` where it is not (denoised, its guides would be
 * filtered); 0: none. */
static inline int temporal_history(const RenderSettings *rs, int temporal, int whitted)
{
    if (rs->integrator == INTEGRATOR_PATH)
        return rs->denoise ? temporal : 0;
    return rs->denoise ? 0 : whitted;
}

typedef struct Temporal Temporal;

/* What a frame is, for its adding up. */
typedef struct {
    Camera camera;
    uint64_t epoch; /* its scene's (but for turns) and settings' number: a new one drops the history */
    int samples;    /* a pixel's: 1 for a moving frame, a still frame's so far */
    int still;      /* its camera is the frame before's: a still frame */
    int clip;       /* the history held within the light of the frame's 3 x 3 about each pixel */
    /* the scene's instances as this frame places them (NULL, 0: none): a
     * pixel whose guide names one that moved since the frame before (a
     * turning model) finds its history where that move had its point */
    const Instance *instances;
    uint32_t instance_count;
} TemporalFrame;

/* A history for frames of up to max_w x max_h pixels weighing `frames`
 * frames at most (1..TEMPORAL_MAX_FRAMES), its rows run on pool (may be
 * NULL); NULL where memory ran out. */
Temporal *temporal_create(Pool *pool, uint32_t max_w, uint32_t max_h, int frames);
/* The bytes of its history (two frames of 60 bytes a pixel) and of a
 * frame's light for the clip (12). */
uint64_t temporal_bytes(uint32_t max_w, uint32_t max_h);
void temporal_destroy(Temporal *t);

/* A w x h frame of guided pixels (colour_bytes of colour, 3 codes, sRGB
 * unless linear, or 4 of RGBE, then the guide) added to the history, its
 * pixels rewritten in place as the history shows them.  0, or -1 where
 * the frame is larger than the history was made for (px untouched). */
int temporal_add(Temporal *t, uint8_t *px, uint32_t w, uint32_t h, uint32_t colour_bytes, int linear,
                 const TemporalFrame *f);

#endif
