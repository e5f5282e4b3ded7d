/* watch.c - see watch.h. */
#include "watch.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <unistd.h>

#include "base/fileio.h"

#define WATCH_MAX_DIRS 64

typedef struct {
    int wd;
    char dir[4096];
} Dir;

struct Watch {
    int fd;
    Dir dirs[WATCH_MAX_DIRS];
    int ndirs;
    char **names; /* the sources' base names, and the directory each is in: */
    int *dir_of;
    uint32_t count;
};

/* The watch of dir, added where it is new: its index, or -1. */
static int dir_index(Watch *w, const char *dir, Err *err)
{
    for (int i = 0; i < w->ndirs; i++)
        if (strcmp(w->dirs[i].dir, dir) == 0)
            return i;
    if (w->ndirs == WATCH_MAX_DIRS)
        return err_set(err, "watch: the scene's files are in more than %d directories", WATCH_MAX_DIRS);
    int wd = inotify_add_watch(w->fd, dir, IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_ATTRIB);
    if (wd < 0)
        return err_set(err, "watch: %s: %s", dir, strerror(errno));
    w->dirs[w->ndirs].wd = wd;
    snprintf(w->dirs[w->ndirs].dir, sizeof w->dirs[w->ndirs].dir, "%s", dir);
    return w->ndirs++;
}

Watch *watch_open(const Scene *s, Err *err)
{
    Watch *w = calloc(1, sizeof *w);
    if (!w || !(w->names = calloc(s->source_count + 1, sizeof *w->names)) ||
        !(w->dir_of = calloc(s->source_count + 1, sizeof *w->dir_of))) {
        err_set(err, "watch: out of memory");
        watch_close(w);
        return NULL;
    }
    w->fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (w->fd < 0) {
        err_set(err, "watch: inotify: %s", strerror(errno));
        watch_close(w);
        return NULL;
    }
    for (uint32_t i = 0; i < s->source_count; i++) {
        char dir[4096];
        file_dirname(s->sources[i], dir, sizeof dir);
        int d = dir_index(w, dir, err);
        if (d < 0 || !(w->names[i] = strdup(file_basename(s->sources[i])))) {
            if (d >= 0)
                err_set(err, "watch: out of memory");
            w->count = i + 1;
            watch_close(w);
            return NULL;
        }
        w->dir_of[i] = d;
        w->count = i + 1;
    }
    return w;
}

void watch_close(Watch *w)
{
    if (!w)
        return;
    if (w->fd > 0)
        close(w->fd);
    for (uint32_t i = 0; w->names && i < w->count; i++)
        free(w->names[i]);
    free(w->names);
    free(w->dir_of);
    free(w);
}

/* Whether the event for name in the directory of watch wd is a source's. */
static int is_source(const Watch *w, int wd, const char *name)
{
    for (uint32_t i = 0; i < w->count; i++)
        if (w->dirs[w->dir_of[i]].wd == wd && strcmp(w->names[i], name) == 0)
            return 1;
    return 0;
}

int watch_changed(Watch *w)
{
    char buf[8192] __attribute__((aligned(__alignof__(struct inotify_event))));
    int changed = 0;
    for (;;) {
        ssize_t n = read(w->fd, buf, sizeof buf);
        if (n <= 0)
            return changed;
        for (char *p = buf; p < buf + n;) {
            const struct inotify_event *e = (const struct inotify_event *)(void *)p;
            if (e->len && is_source(w, e->wd, e->name))
                changed = 1;
            p += sizeof *e + e->len;
        }
    }
}
