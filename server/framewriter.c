/* framewriter.c - see framewriter.h.  Slots form a ring: the caller fills
 * slot `head` and moves it on; the thread writes slot `tail` and moves it
 * on; `queued` counts the filled slots, and both sides wait on one
 * condition for the count to change. */
#include "framewriter.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    uint8_t *pixels;
    char path[FRAMEWRITER_PATH];
    ImageEncoding enc;
} Slot;

struct FrameWriter {
    int width, height, bpp, nslots;
    Slot *slots;
    int head, tail, queued, stop;
    int failures;  /* failed writes not yet reported */
    Err first;     /* the first of them */
    pthread_mutex_t lock;
    pthread_cond_t changed;
    pthread_t thread;
    int started;
};

static void *writer_main(void *arg)
{
    FrameWriter *fw = arg;
    pthread_mutex_lock(&fw->lock);
    for (;;) {
        while (!fw->queued && !fw->stop)
            pthread_cond_wait(&fw->changed, &fw->lock);
        if (!fw->queued)
            break; /* stopped with nothing left */
        Slot *s = &fw->slots[fw->tail];
        pthread_mutex_unlock(&fw->lock);
        Err err;
        const int rc = image_write(s->path, fw->width, fw->height, s->pixels, s->enc, &err);
        pthread_mutex_lock(&fw->lock);
        if (rc && fw->failures++ == 0)
            fw->first = err;
        fw->tail = (fw->tail + 1) % fw->nslots;
        fw->queued--;
        pthread_cond_broadcast(&fw->changed);
    }
    pthread_mutex_unlock(&fw->lock);
    return NULL;
}

FrameWriter *framewriter_create(int width, int height, int bpp, int slots, Err *err)
{
    FrameWriter *fw = calloc(1, sizeof *fw);
    if (fw)
        fw->slots = calloc((size_t)slots, sizeof *fw->slots);
    if (!fw || !fw->slots) {
        free(fw);
        err_set(err, "out of memory for the frame writer");
        return NULL;
    }
    *fw = (FrameWriter){.width = width, .height = height, .bpp = bpp, .nslots = slots, .slots = fw->slots};
    pthread_mutex_init(&fw->lock, NULL);
    pthread_cond_init(&fw->changed, NULL);
    const size_t bytes = (size_t)width * (size_t)height * (size_t)bpp;
    for (int i = 0; i < slots; i++)
        if (!(fw->slots[i].pixels = malloc(bytes))) {
            err_set(err, "out of memory for %d frames of %dx%d in the frame writer", slots, width, height);
            framewriter_destroy(fw);
            return NULL;
        }
    if (pthread_create(&fw->thread, NULL, writer_main, fw) != 0) {
        err_set(err, "cannot start the frame writer's thread");
        framewriter_destroy(fw);
        return NULL;
    }
    fw->started = 1;
    return fw;
}

/* The failures since the last report (the lock held). */
static int take_failures(FrameWriter *fw, Err *err)
{
    const int n = fw->failures;
    if (n)
        *err = fw->first;
    fw->failures = 0;
    return n;
}

int framewriter_put(FrameWriter *fw, const char *path, const uint8_t *pixels, ImageEncoding enc, Err *err)
{
    pthread_mutex_lock(&fw->lock);
    while (fw->queued == fw->nslots)
        pthread_cond_wait(&fw->changed, &fw->lock);
    /* the slot at head is free, and the thread does not touch it until queued counts it */
    pthread_mutex_unlock(&fw->lock);
    Slot *s = &fw->slots[fw->head];
    memcpy(s->pixels, pixels, (size_t)fw->width * (size_t)fw->height * (size_t)fw->bpp);
    snprintf(s->path, sizeof s->path, "%s", path);
    s->enc = enc;
    pthread_mutex_lock(&fw->lock);
    fw->head = (fw->head + 1) % fw->nslots;
    fw->queued++;
    pthread_cond_broadcast(&fw->changed);
    const int n = take_failures(fw, err);
    pthread_mutex_unlock(&fw->lock);
    return n;
}

int framewriter_flush(FrameWriter *fw, Err *err)
{
    pthread_mutex_lock(&fw->lock);
    while (fw->queued)
        pthread_cond_wait(&fw->changed, &fw->lock);
    const int n = take_failures(fw, err);
    pthread_mutex_unlock(&fw->lock);
    return n;
}

void framewriter_destroy(FrameWriter *fw)
{
    if (!fw)
        return;
    if (fw->started) {
        pthread_mutex_lock(&fw->lock);
        fw->stop = 1;
        pthread_cond_broadcast(&fw->changed);
        pthread_mutex_unlock(&fw->lock);
        pthread_join(fw->thread, NULL);
    }
    pthread_mutex_destroy(&fw->lock);
    pthread_cond_destroy(&fw->changed);
    for (int i = 0; i < fw->nslots; i++)
        free(fw->slots[i].pixels);
    free(fw->slots);
    free(fw);
}
