/* denoisestage.c - the filter's thread of denoisestage.h. */
#include "denoisestage.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/pool.h"
#include "render/denoise.h"

enum { EMPTY, WAITING, FILTERED };

struct DenoiseStage {
    Denoiser *denoiser;
    Temporal *history; /* NULL: none */
    Pool *pool;
    uint32_t cb, bpp;
    uint8_t *in, *out; /* the frame handed in (guided), and filtered */
    uint32_t w, h;
    int linear;
    StageFrame frame;
    Instance *inst; /* the frame's instances (frame.instances), the stage's copy */
    uint32_t inst_cap;
    int state, stop;
    pthread_mutex_t lock;
    pthread_cond_t changed;
    pthread_t thread;
    int started;
};

static void *stage_main(void *arg)
{
    DenoiseStage *st = arg;
    pthread_mutex_lock(&st->lock);
    for (;;) {
        while (st->state != WAITING && !st->stop)
            pthread_cond_wait(&st->changed, &st->lock);
        if (st->state != WAITING)
            break;
        pthread_mutex_unlock(&st->lock);
        Err err;
        /* cannot fail: both were made for the largest frame */
        const StageFrame *f = &st->frame;
        if (st->history && f->temporal)
            temporal_add(st->history, st->in, st->w, st->h, st->cb, st->linear,
                         &(TemporalFrame){f->cam, f->epoch, f->samples, f->still, !st->denoiser, f->instances,
                                          f->instance_count});
        if (!st->denoiser) /* the history alone: the colours without their guides */
            for (size_t i = 0; i < (size_t)st->w * st->h; i++)
                memcpy(st->out + i * st->cb, st->in + i * st->bpp, st->cb);
        else if (denoise_frame(st->denoiser, st->in, st->w, st->h, st->cb, st->linear, st->out, &err))
            memset(st->out, 0, (size_t)st->w * st->h * st->cb);
        pthread_mutex_lock(&st->lock);
        st->state = FILTERED;
        pthread_cond_broadcast(&st->changed);
    }
    pthread_mutex_unlock(&st->lock);
    return NULL;
}

DenoiseStage *denoise_stage_create(uint32_t width, uint32_t height, uint32_t colour_bytes, int threads, int filter,
                                   int temporal, Err *err)
{
    DenoiseStage *st = calloc(1, sizeof *st);
    if (!st) {
        err_set(err, "out of memory for the denoiser");
        return NULL;
    }
    st->cb = colour_bytes, st->bpp = colour_bytes + DENOISE_GUIDE_BYTES;
    const size_t n = (size_t)width * height;
    st->in = malloc(n * st->bpp);
    st->out = malloc(n * st->cb);
    st->pool = pool_create(threads, err);
    st->denoiser = st->pool && filter ? denoiser_create(st->pool, width, height) : NULL;
    st->history = st->pool && temporal ? temporal_create(st->pool, width, height, temporal) : NULL;
    pthread_mutex_init(&st->lock, NULL);
    pthread_cond_init(&st->changed, NULL);
    if (!st->in || !st->out || (filter && !st->denoiser) || (temporal && !st->history) ||
        pthread_create(&st->thread, NULL, stage_main, st) != 0) {
        if (st->pool)
            err_set(err, "out of memory or threads for the %s of %ux%u frames",
                    !filter ? "history (--temporal)" : temporal ? "denoiser and the history (--temporal)" : "denoiser",
                    width, height);
        denoise_stage_destroy(st);
        return NULL;
    }
    st->started = 1;
    return st;
}

void denoise_stage_destroy(DenoiseStage *st)
{
    if (!st)
        return;
    if (st->started) {
        pthread_mutex_lock(&st->lock);
        st->stop = 1;
        pthread_cond_broadcast(&st->changed);
        pthread_mutex_unlock(&st->lock);
        pthread_join(st->thread, NULL);
    }
    pthread_mutex_destroy(&st->lock);
    pthread_cond_destroy(&st->changed);
    denoiser_destroy(st->denoiser);
    temporal_destroy(st->history);
    pool_destroy(st->pool);
    free(st->in);
    free(st->out);
    free(st->inst);
    free(st);
}

void denoise_stage_put(DenoiseStage *st, const uint8_t *pixels, uint32_t w, uint32_t h, int linear,
                       const StageFrame *frame)
{
    /* the stage is empty: the thread reads none of this until WAITING */
    memcpy(st->in, pixels, (size_t)w * h * st->bpp);
    /* none where memory ran out: the history then follows no instance */
    const uint32_t n = instances_copy(&st->inst, &st->inst_cap, frame->instances, frame->instance_count);
    pthread_mutex_lock(&st->lock);
    st->w = w, st->h = h, st->linear = linear, st->frame = *frame;
    st->frame.instances = st->inst, st->frame.instance_count = n;
    st->state = WAITING;
    pthread_cond_broadcast(&st->changed);
    pthread_mutex_unlock(&st->lock);
}

int denoise_stage_holds(DenoiseStage *st)
{
    pthread_mutex_lock(&st->lock);
    const int holds = st->state != EMPTY;
    pthread_mutex_unlock(&st->lock);
    return holds;
}

int denoise_stage_take(DenoiseStage *st, int wait, const uint8_t **colours, StageFrame *frame)
{
    pthread_mutex_lock(&st->lock);
    while (wait && st->state == WAITING)
        pthread_cond_wait(&st->changed, &st->lock);
    const int ready = st->state == FILTERED;
    if (ready) {
        *colours = st->out;
        *frame = st->frame;
        st->state = EMPTY;
    }
    pthread_mutex_unlock(&st->lock);
    return ready;
}
