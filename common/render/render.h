/* render.h - rendering lines of a frame with a pool of threads.
 *
 * render_lines is the one entry point both the standalone renderer and the
 * network client use: the calling thread and the pool's workers (one fewer
 * than the pool's size) take chunks of CHUNK pixels through an atomic
 * counter, so lines of very different cost still balance.  Results do not
 * depend on the thread count or on how a frame is cut into segments: every
 * pixel is a pure function of the scene and its coordinates. */
#ifndef LANRAY_RENDER_H
#define LANRAY_RENDER_H

#include <stdatomic.h>
#include <stdint.h>

#include "render/denoise.h"
#include "render/pixel.h"
#include "render/progressive.h"
#include "scene/shade.h"

#define RENDER_MAX_SIDE 65536
#define RENDER_MAX_THREADS 1024

typedef struct RenderPool RenderPool;

/* Bytes a pixel of the scene's frames as rendered and sent: its colour,
 * then with settings denoise its guide (render/denoise.h), which the
 * frame's filter reads and the picture shown no longer has; with settings
 * batch, its sums (reals in host order, as the rest of the wire). */
static inline uint32_t render_pixel_bytes(const RenderSettings *rs)
{
    if (rs->batch) /* a batch of a path-traced still: its sums (render/progressive.h) */
        return progressive_reals(rs) * (uint32_t)sizeof(real);
    return render_shown_bytes(rs);
}

/* Pixels finished and rays traced so far, for a progress line that another
 * thread reads while the pool renders (relaxed atomics: a rough count). */
typedef struct {
    atomic_uint_fast64_t pixels, rays;
} RenderProgress;

RenderPool *render_pool_create(int threads, Err *err);
/* Counts every later render into progress (NULL: stop counting). */
void render_pool_watch(RenderPool *p, RenderProgress *progress);
void render_pool_destroy(RenderPool *p);
int render_pool_threads(const RenderPool *p);
/* Its threads, for other work between renders (the denoiser's passes). */
Pool *render_pool_pool(RenderPool *p);

/* Renders lines [first_line, first_line + count) of a width x height frame of
 * the prepared scene into pixels (RGB8, count*width*3 bytes; with settings
 * hdr, RGBE, count*width*4). */
int render_lines(RenderPool *p, const World *w, int width, int height, int first_line, int count, uint8_t *pixels,
                 RayStats *stats, Err *err);

/* Whether w's frames take adaptive light sampling: settings light_sampling
 * adaptive, an area light of more than one point, and one sample a pixel
 * or adaptive anti-aliasing (a regular N x N grid takes every point). */
int render_probes_lights(const World *w);

#define RENDER_CANCELLED 1
/* Renders pixels [first, first + count) in row-major order (a segment may
 * start or end inside a line).  When cancel is not NULL and becomes non-zero,
 * the workers stop taking chunks and RENDER_CANCELLED is returned (the
 * pixels are then incomplete). */
int render_span(RenderPool *p, const World *w, int width, int height, uint64_t first, uint64_t count, uint8_t *pixels,
                RayStats *stats, const atomic_int *cancel, Err *err);

#endif
