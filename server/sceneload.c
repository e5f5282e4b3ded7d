/* sceneload.c - see sceneload.h. */
#include "sceneload.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

struct SceneLoad {
    pthread_t thread;
    SceneReadFn fn;
    const void *ctx;
    atomic_int done; /* set by the thread as its last step: the read is in `read` */
    SceneRead read; /* its path a copy: the caller's may go while the thread reads */
};

static void *load_main(void *arg)
{
    SceneLoad *l = arg;
    l->fn(l->ctx, l->read.path, &l->read);
    atomic_store_explicit(&l->done, 1, memory_order_release);
    return NULL;
}

SceneLoad *sceneload_start(const char *path, SceneReadFn fn, const void *ctx, Err *err)
{
    SceneLoad *l = calloc(1, sizeof *l);
    if (!l || !(l->read.path = strdup(path))) {
        free(l);
        err_set(err, "%s: out of memory", path);
        return NULL;
    }
    l->fn = fn;
    l->ctx = ctx;
    atomic_init(&l->done, 0);
    const int rc = pthread_create(&l->thread, NULL, load_main, l);
    if (rc != 0) {
        err_set(err, "%s: cannot start a thread to read it: %s", path, strerror(rc));
        free(l->read.path);
        free(l);
        return NULL;
    }
    return l;
}

int sceneload_done(SceneLoad *l) { return atomic_load_explicit(&l->done, memory_order_acquire); }

const char *sceneload_path(const SceneLoad *l) { return l->read.path; }

SceneRead sceneload_finish(SceneLoad *l)
{
    pthread_join(l->thread, NULL);
    SceneRead r = l->read;
    free(l);
    return r;
}
