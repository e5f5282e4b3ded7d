/* bvh_tasks.c - running a top-down builder's tasks on several threads.
 *
 * Each worker goes depth first through its own stack; a subtree big enough
 * to be worth a hand-over goes to the shared queue while another worker is
 * waiting for work.  Nodes come from an array sized for the largest binary
 * tree (2n - 1 nodes, and a chunk per worker), each worker taking chunks of
 * slots from an atomic counter, so their indices depend on timing, but not
 * the tree: children are linked by index and bvh_flatten lays the tree out
 * from the root by its shape (unused slots are never reached). */
#include <pthread.h>
#include <stdlib.h>

#include "base/bigmem.h"

#include "bvh/bvh_build.h"

/* primitives: smaller subtrees stay with their worker.  4096 left one of
 * the bunny's two workers waiting up to 3.6 ms of 20 at the end. */
#define SHARE_MIN 1024
#define TOP_MIN 65536 /* primitives: a smaller task is not worth the pool's hand-offs */
#define NODE_CHUNK 256 /* node slots a worker takes at a time: its nodes share no cache line with another's */

typedef struct {
    Builder *b;
    BuildStep step;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    BuildTask *queue; /* shared tasks */
    uint32_t queued, waiting, busy;
    int workers, done, failed;
} Run;

static void run_share(Run *r, BuildTask t)
{
    pthread_mutex_lock(&r->lock);
    r->queue[r->queued++] = t;
    pthread_cond_signal(&r->wake);
    pthread_mutex_unlock(&r->lock);
}

/* A task from the queue, or 0 once every worker is idle and the queue empty. */
static int run_take(Run *r, BuildTask *t)
{
    pthread_mutex_lock(&r->lock);
    r->busy--;
    while (r->queued == 0 && !r->done) {
        if (r->busy == 0) {
            r->done = 1;
            pthread_cond_broadcast(&r->wake);
            break;
        }
        __atomic_add_fetch(&r->waiting, 1, __ATOMIC_RELAXED);
        pthread_cond_wait(&r->wake, &r->lock);
        __atomic_sub_fetch(&r->waiting, 1, __ATOMIC_RELAXED);
    }
    int got = r->queued > 0;
    if (got) {
        *t = r->queue[--r->queued];
        r->busy++;
    }
    pthread_mutex_unlock(&r->lock);
    return got;
}

/* Gives cur's two children the node slots c and c + 1. */
static void run_link(Builder *b, const BuildTask *cur, BuildTask kids[2], uint32_t c)
{
    for (int k = 0; k < 2; k++) {
        kids[k].node = c + (uint32_t)k;
        kids[k].depth = cur->depth + 1;
        b->nodes[c + k] = (BuildNode){kids[k].box, -1, -1, kids[k].first, kids[k].count};
    }
    b->nodes[cur->node].left = (int32_t)c;
    b->nodes[cur->node].right = (int32_t)c + 1;
}

/* The top of the tree, while there are fewer tasks than workers: the
 * biggest task is stepped alone on the caller by the builder's top step,
 * whose passes run on the pool.  With two workers the root took one of
 * them a tenth of the build while the other waited.  A builder without a
 * top step starts its workers at once: stepping its top alone would only
 * keep them waiting longer. */
static void run_top(Run *r, BuildStep step)
{
    Builder *b = r->b;
    while (step && b->pool && r->workers > 1 && r->queued > 0 && r->queued < (uint32_t)r->workers) {
        uint32_t big = 0;
        for (uint32_t i = 1; i < r->queued; i++)
            if (r->queue[i].count > r->queue[big].count)
                big = i;
        if (r->queue[big].count < TOP_MIN)
            break;
        BuildTask cur = r->queue[big], kids[2];
        r->queue[big] = r->queue[--r->queued];
        if (step(b, &cur, kids) != 2)
            continue;
        run_link(b, &cur, kids, b->node_count);
        b->node_count += 2;
        if (cur.depth + 1 > b->max_depth)
            b->max_depth = cur.depth + 1;
        r->queue[r->queued++] = kids[0];
        r->queue[r->queued++] = kids[1];
    }
}

static void *run_worker(void *arg)
{
    Run *r = arg;
    Builder *b = r->b;
    uint32_t cap = 256, sp = 0, next = 0, end = 0, deepest = 1;
    BuildTask *stack = malloc(cap * sizeof *stack), t;
    while (stack && run_take(r, &t)) {
        stack[sp++] = t;
        while (sp) {
            BuildTask cur = stack[--sp];
            BuildTask kids[2];
            if (r->step(b, &cur, kids) != 2)
                continue;
            if (next == end) {
                next = __atomic_fetch_add(&b->node_count, NODE_CHUNK, __ATOMIC_RELAXED);
                end = next + NODE_CHUNK;
            }
            run_link(b, &cur, kids, next);
            next += 2;
            if (cur.depth + 1 > deepest)
                deepest = cur.depth + 1;
            /* the bigger child is shared when a worker waits, else both stay */
            int big = kids[1].count > kids[0].count;
            if (r->workers > 1 && kids[big].count >= SHARE_MIN && __atomic_load_n(&r->waiting, __ATOMIC_RELAXED) > 0) {
                run_share(r, kids[big]);
                stack[sp++] = kids[!big];
                continue;
            }
            if (sp + 2 > cap) { /* a deep chain (a spatial median on uneven input) */
                BuildTask *more = realloc(stack, 2 * cap * sizeof *stack);
                if (!more) {
                    __atomic_store_n(&r->failed, 1, __ATOMIC_RELAXED);
                    sp = 0;
                    break;
                }
                stack = more;
                cap *= 2;
            }
            stack[sp++] = kids[1];
            stack[sp++] = kids[0];
        }
    }
    if (!stack)
        __atomic_store_n(&r->failed, 1, __ATOMIC_RELAXED);
    free(stack);
    uint32_t seen = __atomic_load_n(&b->max_depth, __ATOMIC_RELAXED);
    while (deepest > seen && !__atomic_compare_exchange_n(&b->max_depth, &seen, deepest, 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
    }
    return NULL;
}

int builder_run(Builder *b, BuildStep step, BuildStep top_step, Err *err)
{
    /* a binary tree over n primitives has at most 2n - 1 nodes; each
     * worker may leave part of its last chunk unused */
    const int workers = b->opt->threads > 1 ? b->opt->threads : 1;
    uint32_t cap = 2 * b->n + (uint32_t)(workers + 1) * NODE_CHUNK;
    b->nodes = bigmem_alloc(cap * sizeof *b->nodes);
    Run r = {.b = b, .step = step, .workers = workers};
    r.queue = malloc(cap * sizeof *r.queue);
    if (!b->nodes || !r.queue) {
        free(r.queue);
        return err_set(err, "bvh: out of memory for %u primitives", b->n);
    }
    b->node_cap = cap;
    Aabb box, cbox;
    if (b->root_known)
        box = b->root_box, cbox = b->root_cbox;
    else
        builder_bounds_all(b, &box, &cbox);
    b->nodes[0] = (BuildNode){box, -1, -1, 0, b->n};
    b->node_count = 1;
    b->root = 0;
    b->max_depth = 1;
    r.queue[r.queued++] = (BuildTask){0, 0, b->n, 1, box, cbox};
    run_top(&r, top_step);
    r.busy = (uint32_t)r.workers; /* each worker starts by taking */
    pthread_mutex_init(&r.lock, NULL);
    pthread_cond_init(&r.wake, NULL);
    pthread_t th[64];
    int started = 0;
    for (int i = 1; i < r.workers && i < 64; i++)
        if (pthread_create(&th[started], NULL, run_worker, &r) == 0)
            started++;
    if (started < r.workers - 1) { /* fewer threads than asked: the missing ones are not busy */
        pthread_mutex_lock(&r.lock);
        r.busy -= (uint32_t)(r.workers - 1 - started);
        pthread_mutex_unlock(&r.lock);
    }
    run_worker(&r);
    for (int i = 0; i < started; i++)
        pthread_join(th[i], NULL);
    pthread_mutex_destroy(&r.lock);
    pthread_cond_destroy(&r.wake);
    free(r.queue);
    if (r.failed) /* a worker that ran out of memory left its subtrees unbuilt */
        return err_set(err, "bvh: out of memory building %u primitives", b->n);
    return 0;
}
