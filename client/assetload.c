/* assetload.c - see assetload.h. */
#include "assetload.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "model/model.h"

typedef struct Job {
    struct Job *next;
    uint32_t kind;
    uint8_t hash[PROTO_HASH];
    uint8_t *data; /* the payload's copy, freed once decoded */
    size_t len;
    int done, failed;
    AssetDecoded d;
    Err err;
} Job;

struct AssetLoad {
    pthread_mutex_t mu;
    pthread_cond_t cv;   /* a job queued, or quit (the thread waits on it) */
    pthread_cond_t idle; /* a job done (assetload_wait waits on it) */
    Job *head, *tail;    /* in the order queued; done ones at the front until taken */
    int quit, wake;
    pthread_t thread;
    Job *in; /* the asset whose slices are coming (the network thread's alone), or NULL */
    uint32_t in_got;
};

/* The hash checked, the payload decoded, and a model's trees for this
 * CPU's SIMD path built, so that the scene that names it only finds them
 * (world_build's model_prepare_simd). */
static void decode(Job *j)
{
    j->failed = asset_decode(j->kind, j->hash, j->data, j->len, &j->d, &j->err) ||
                (j->d.model && model_prepare_simd(j->d.model, &j->err));
    if (j->failed)
        asset_decoded_free(&j->d);
    free(j->data);
    j->data = NULL;
}

/* The first job not decoded yet, or NULL (under mu). */
static Job *first_pending(const AssetLoad *l)
{
    Job *j = l->head;
    while (j && j->done)
        j = j->next;
    return j;
}

static void *load_main(void *arg)
{
    AssetLoad *l = arg;
    pthread_mutex_lock(&l->mu);
    for (;;) {
        Job *j = first_pending(l);
        if (!j) {
            if (l->quit)
                break;
            pthread_cond_wait(&l->cv, &l->mu);
            continue;
        }
        pthread_mutex_unlock(&l->mu);
        decode(j); /* the job stays in the list, not done: only this thread touches it */
        pthread_mutex_lock(&l->mu);
        j->done = 1;
        pthread_cond_broadcast(&l->idle);
        const char b = 1;
        if (write(l->wake, &b, 1) < 0) { /* the pipe is full: the network thread is awake anyway */
        }
    }
    pthread_mutex_unlock(&l->mu);
    return NULL;
}

AssetLoad *assetload_create(int wake, Err *err)
{
    AssetLoad *l = calloc(1, sizeof *l);
    if (!l) {
        err_set(err, "out of memory");
        return NULL;
    }
    l->wake = wake;
    pthread_mutex_init(&l->mu, NULL);
    pthread_cond_init(&l->cv, NULL);
    pthread_cond_init(&l->idle, NULL);
    if (pthread_create(&l->thread, NULL, load_main, l) != 0) {
        pthread_mutex_destroy(&l->mu);
        pthread_cond_destroy(&l->cv);
        pthread_cond_destroy(&l->idle);
        free(l);
        err_set(err, "cannot start the assets' thread");
        return NULL;
    }
    return l;
}

static void job_free(Job *j)
{
    free(j->data);
    asset_decoded_free(&j->d);
    free(j);
}

void assetload_destroy(AssetLoad *l)
{
    if (!l)
        return;
    pthread_mutex_lock(&l->mu);
    /* the jobs not started are dropped; the one being decoded is finished */
    for (Job **p = &l->head; *p;) {
        Job *j = *p;
        if (j->done || j != l->head) {
            *p = j->next;
            job_free(j);
        } else {
            p = &j->next;
        }
    }
    l->quit = 1;
    pthread_cond_broadcast(&l->cv);
    pthread_mutex_unlock(&l->mu);
    pthread_join(l->thread, NULL);
    if (l->in)
        job_free(l->in);
    while (l->head) {
        Job *j = l->head;
        l->head = j->next;
        job_free(j);
    }
    pthread_mutex_destroy(&l->mu);
    pthread_cond_destroy(&l->cv);
    pthread_cond_destroy(&l->idle);
    free(l);
}

/* A whole payload queued to be decoded. */
static void push(AssetLoad *l, Job *j)
{
    pthread_mutex_lock(&l->mu);
    if (l->tail)
        l->tail->next = j;
    else
        l->head = j;
    l->tail = j;
    pthread_cond_signal(&l->cv);
    pthread_mutex_unlock(&l->mu);
}

int assetload_slice(AssetLoad *l, const MsgAsset *a, Err *err)
{
    Job *j = l->in;
    if (!j) {
        if (a->offset != 0)
            return err_set(err, "ASSET slice at byte %u of an asset whose start never came", a->offset);
        if (!(j = calloc(1, sizeof *j)) || !(j->data = malloc(a->total ? a->total : 1))) {
            free(j);
            return err_set(err, "out of memory for an asset of %u bytes", a->total);
        }
        j->kind = a->kind;
        memcpy(j->hash, a->hash, PROTO_HASH);
        j->len = a->total;
        l->in = j, l->in_got = 0;
    } else if (a->kind != j->kind || a->total != j->len || memcmp(a->hash, j->hash, PROTO_HASH) != 0 ||
               a->offset != l->in_got) {
        return err_set(err, "ASSET slice at byte %u of %u does not follow the one before (byte %u of %zu, its hash "
                            "%s)", a->offset, a->total, l->in_got, j->len,
                       memcmp(a->hash, j->hash, PROTO_HASH) ? "another" : "the same");
    }
    if (a->len)
        memcpy(j->data + a->offset, a->data, a->len);
    l->in_got += (uint32_t)a->len;
    if (l->in_got == j->len) {
        l->in = NULL;
        push(l, j);
    }
    return 0;
}

void assetload_wait(AssetLoad *l)
{
    pthread_mutex_lock(&l->mu);
    while (first_pending(l))
        pthread_cond_wait(&l->idle, &l->mu);
    pthread_mutex_unlock(&l->mu);
}

/* The first job if it is done, unlinked; else NULL. */
static Job *take_done(AssetLoad *l)
{
    pthread_mutex_lock(&l->mu);
    Job *j = l->head;
    if (j && j->done) {
        l->head = j->next;
        if (!l->head)
            l->tail = NULL;
    } else {
        j = NULL;
    }
    pthread_mutex_unlock(&l->mu);
    return j;
}

int assetload_take(AssetLoad *l, AssetCache *cache, void (*have)(void *ctx, const uint8_t *hash), void *ctx,
                   Err *err)
{
    Job *j;
    while ((j = take_done(l))) {
        if (j->failed) {
            *err = j->err;
            job_free(j);
            return -1;
        }
        uint8_t hash[PROTO_HASH];
        memcpy(hash, j->hash, PROTO_HASH);
        const int rc = asset_cache_put(cache, &j->d, err);
        job_free(j);
        if (rc)
            return -1;
        if (have)
            have(ctx, hash);
    }
    return 0;
}

void assetload_settle(AssetLoad *l, AssetCache *cache)
{
    if (l->in) {
        job_free(l->in);
        l->in = NULL;
    }
    assetload_wait(l);
    Err e;
    while (assetload_take(l, cache, NULL, NULL, &e)) {
    }
}
