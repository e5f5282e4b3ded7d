/* progress.c - see progress.h. */
#include "base/progress.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/timer.h"

struct Progress {
    const char *prog;
    ProgressFn fn;
    void *ctx;
    double start;
    int quit, shown;
    size_t width; /* of the last line, to clear it */
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
};

static void *progress_thread(void *arg)
{
    Progress *p = arg;
    pthread_mutex_lock(&p->mu);
    while (!p->quit) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += 250000000;
        if (ts.tv_nsec >= 1000000000) {
            ts.tv_sec++;
            ts.tv_nsec -= 1000000000;
        }
        pthread_cond_timedwait(&p->cv, &p->mu, &ts);
        double elapsed = timer_now() - p->start;
        if (p->quit || elapsed < 1)
            continue;
        char line[200];
        line[0] = 0;
        p->fn(p->ctx, elapsed, line, sizeof line);
        size_t n = strlen(line) + strlen(p->prog) + 2;
        fprintf(stderr, "\r%s: %s%*s", p->prog, line, p->width > n ? (int)(p->width - n) : 0, "");
        p->width = n;
        p->shown = 1;
    }
    if (p->shown)
        fprintf(stderr, "\r%*s\r", (int)p->width, "");
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

Progress *progress_start(const char *prog, int enabled, ProgressFn fn, void *ctx)
{
    if (!enabled || !isatty(STDERR_FILENO))
        return NULL;
    Progress *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->prog = prog;
    p->fn = fn;
    p->ctx = ctx;
    p->start = timer_now();
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->cv, NULL);
    if (pthread_create(&p->thread, NULL, progress_thread, p) != 0) {
        pthread_mutex_destroy(&p->mu);
        pthread_cond_destroy(&p->cv);
        free(p);
        return NULL; /* no progress line is no reason to fail */
    }
    return p;
}

void progress_stop(Progress *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_signal(&p->cv);
    pthread_mutex_unlock(&p->mu);
    pthread_join(p->thread, NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->cv);
    free(p);
}

void progress_duration(double s, char *buf, size_t size)
{
    if (!(s >= 0) || s > 1e7)
        snprintf(buf, size, "?");
    else if (s < 60)
        snprintf(buf, size, "%.0f s", s);
    else if (s < 3600)
        snprintf(buf, size, "%d min %d s", (int)s / 60, (int)s % 60);
    else
        snprintf(buf, size, "%d h %d min", (int)s / 3600, (int)s % 3600 / 60);
}
