/* pool.c - see pool.h. */
#include "base/pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

struct Pool {
    int n; /* worker threads: the pool's size less the caller */
    pthread_t *threads;
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    uint64_t generation;
    int running, quit;
    PoolFn fn;
    void *ctx;
    uint32_t chunks;
    atomic_uint next;
};

typedef struct {
    Pool *pool;
    int id;
} WorkerArg;

static void *worker(void *arg)
{
    WorkerArg *wa = arg;
    Pool *p = wa->pool;
    int id = wa->id;
    free(wa);
    uint64_t seen = 0;
    for (;;) {
        pthread_mutex_lock(&p->mu);
        while (p->generation == seen && !p->quit)
            pthread_cond_wait(&p->go, &p->mu);
        if (p->quit) {
            pthread_mutex_unlock(&p->mu);
            return NULL;
        }
        seen = p->generation;
        pthread_mutex_unlock(&p->mu);
        uint32_t c;
        while ((c = atomic_fetch_add(&p->next, 1)) < p->chunks)
            p->fn(p->ctx, c, id);
        pthread_mutex_lock(&p->mu);
        if (--p->running == 0)
            pthread_cond_signal(&p->done);
        pthread_mutex_unlock(&p->mu);
    }
}

Pool *pool_create(int threads, Err *err)
{
    if (threads < 1 || threads > POOL_MAX_THREADS) {
        err_set(err, "pool: %d threads out of range 1..%d", threads, POOL_MAX_THREADS);
        return NULL;
    }
    Pool *p = calloc(1, sizeof *p);
    if (!p || !(p->threads = calloc((size_t)threads, sizeof *p->threads))) {
        free(p);
        err_set(err, "pool: out of memory");
        return NULL;
    }
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int i = 0; i < threads - 1; i++) {
        WorkerArg *wa = malloc(sizeof *wa);
        if (!wa || pthread_create(&p->threads[i], NULL, worker, (wa->pool = p, wa->id = i, wa)) != 0) {
            free(wa);
            p->n = i;
            pool_destroy(p);
            err_set(err, "pool: cannot start worker thread %d", i);
            return NULL;
        }
        p->n = i + 1;
    }
    return p;
}

void pool_destroy(Pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (int i = 0; i < p->n; i++)
        pthread_join(p->threads[i], NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    free(p->threads);
    free(p);
}

int pool_threads(const Pool *p) { return p->n + 1; }

void pool_run(Pool *p, PoolFn fn, void *ctx, uint32_t chunks)
{
    pthread_mutex_lock(&p->mu);
    p->fn = fn;
    p->ctx = ctx;
    p->chunks = chunks;
    atomic_store(&p->next, 0);
    p->running = p->n;
    p->generation++;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    uint32_t c;
    while ((c = atomic_fetch_add(&p->next, 1)) < chunks)
        fn(ctx, c, p->n);
    pthread_mutex_lock(&p->mu);
    while (p->running > 0)
        pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

typedef struct {
    PoolRangeFn fn;
    void *ctx;
    uint64_t n, size;
} RangeJob;

static void range_chunk(void *ctx, uint32_t chunk, int thread)
{
    const RangeJob *j = ctx;
    uint64_t lo = (uint64_t)chunk * j->size, hi = lo + j->size < j->n ? lo + j->size : j->n;
    j->fn(j->ctx, lo, hi, thread);
}

void pool_for(Pool *p, uint64_t n, uint64_t grain, PoolRangeFn fn, void *ctx)
{
    if (grain < 1)
        grain = 1;
    if (!p || p->n == 0 || n < 2 * grain) {
        if (n)
            fn(ctx, 0, n, 0);
        return;
    }
    uint64_t chunks = n / grain, most = 4 * (uint64_t)pool_threads(p);
    if (chunks > most)
        chunks = most;
    RangeJob j = {fn, ctx, n, (n + chunks - 1) / chunks};
    pool_run(p, range_chunk, &j, (uint32_t)((n + j.size - 1) / j.size));
}
