/* pool.h - a pool of threads that runs one job over numbered chunks.
 *
 * A pool of T threads is the caller of pool_run plus T - 1 workers that
 * wait between runs: the caller takes chunks too, so a one-thread pool
 * runs inline with no hand-off (two thread wake-ups, about 80 us on a
 * shared VM, were a third of the cost of a one-line segment).  Chunks go
 * out through an atomic counter, so chunks of very different cost still
 * balance; which thread runs which chunk depends on timing, so a job must
 * give the same result whichever does (render.c's pixels are pure
 * functions of their coordinates).  The BVH builders' tasks have their own
 * scheduler (bvh_tasks.c): a work-sharing stack of subtrees, on threads
 * that live for one build. */
#ifndef LANRAY_POOL_H
#define LANRAY_POOL_H

#include <stdint.h>

#include "base/err.h"

#define POOL_MAX_THREADS 1024

typedef struct Pool Pool;

/* fn(ctx, chunk, thread): thread in [0, pool_threads(p)), the caller being
 * the last; a job keeps per-thread results by it, without locks. */
typedef void (*PoolFn)(void *ctx, uint32_t chunk, int thread);

Pool *pool_create(int threads, Err *err);
void pool_destroy(Pool *p);
int pool_threads(const Pool *p);
/* Runs fn over chunks [0, chunks) on the caller and every worker; returns
 * when all are done.  One run at a time. */
void pool_run(Pool *p, PoolFn fn, void *ctx, uint32_t chunks);

/* A loop over [0, n) in ranges of at least `grain` items, a few per
 * thread: fn(ctx, lo, hi, thread).  A NULL pool, or fewer than 2 * grain
 * items, make one call on the caller (thread 0).  For the builders' passes
 * over every primitive (bvh.c, bvh_sah.c, model.c): a reduction keeps
 * per-thread results by `thread` (at most pool_threads). */
typedef void (*PoolRangeFn)(void *ctx, uint64_t lo, uint64_t hi, int thread);
void pool_for(Pool *p, uint64_t n, uint64_t grain, PoolRangeFn fn, void *ctx);

#endif
