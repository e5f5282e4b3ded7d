/* fileio.c - see fileio.h. */
#define _POSIX_C_SOURCE 200809L
#include "base/fileio.h"

#include "base/bigmem.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

int file_read_all(const char *path, size_t max_bytes, char **data, size_t *len, Err *err)
{
    *data = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return err_set(err, "%s: not a regular file", path);
    }
    if ((unsigned long long)st.st_size > max_bytes) {
        fclose(f);
        return err_set(err, "%s: %lld bytes exceed the limit of %zu", path, (long long)st.st_size, max_bytes);
    }
    size_t n = (size_t)st.st_size;
    /* a big model's text on huge pages: a page fault per 2 MiB, not per 4 KiB */
    char *buf = bigmem_alloc(n + 1);
    if (!buf) {
        fclose(f);
        return err_set(err, "%s: out of memory for %zu bytes", path, n);
    }
    size_t got = fread(buf, 1, n, f);
    int bad = ferror(f) || got != n;
    fclose(f);
    if (bad) {
        free(buf);
        return err_set(err, "%s: read error", path);
    }
    buf[n] = 0;
    *data = buf;
    *len = n;
    return 0;
}

/* The temporary files being written, for a signal handler to remove:
 * copies of their names (the handler may run on any thread, while the
 * AtomicFile's own name is freed), each slot claimed atomically. */
#define PENDING_MAX 16
#define PENDING_NAME 4200
static struct {
    int claimed;                /* owned by an AtomicFile (atomic) */
    volatile sig_atomic_t live; /* name holds a file that exists */
    char name[PENDING_NAME];
} pending[PENDING_MAX];

static int pending_add(const char *tmp)
{
    if (strlen(tmp) >= PENDING_NAME)
        return -1;
    for (int i = 0; i < PENDING_MAX; i++) {
        int free_slot = 0;
        if (__atomic_compare_exchange_n(&pending[i].claimed, &free_slot, 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_RELAXED)) {
            strcpy(pending[i].name, tmp);
            pending[i].live = 1;
            return i;
        }
    }
    return -1; /* more files at once than slots: that one is not removed on a signal */
}

static void pending_drop(int slot)
{
    if (slot < 0)
        return;
    pending[slot].live = 0;
    __atomic_store_n(&pending[slot].claimed, 0, __ATOMIC_RELEASE);
}

static void on_stop_signal(int sig)
{
    for (int i = 0; i < PENDING_MAX; i++)
        if (pending[i].live)
            unlink(pending[i].name); /* async-signal-safe */
    signal(sig, SIG_DFL);
    raise(sig);
}

void file_atomic_on_signals(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++)
        sigaction(sigs[i], &sa, NULL);
}

int file_atomic_open(AtomicFile *a, const char *path, Err *err)
{
    memset(a, 0, sizeof a[0]);
    a->path = path;
    size_t n = strlen(path);
    a->tmp = malloc(n + 16);
    if (!a->tmp)
        return err_set(err, "%s: out of memory", path);
    snprintf(a->tmp, n + 16, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(a->tmp);
    if (fd < 0) {
        char dir[4096];
        file_dirname(path, dir, sizeof dir);
        if (errno == ENOENT || errno == ENOTDIR)
            err_set(err, "%s: cannot write: the directory %s does not exist", path, dir);
        else
            err_set(err, "%s: cannot write in %s: %s", path, dir, strerror(errno));
        free(a->tmp);
        a->tmp = NULL;
        return -1;
    }
    a->slot = pending_add(a->tmp);
    a->f = fdopen(fd, "wb");
    if (!a->f) {
        int e = errno;
        close(fd);
        file_atomic_abort(a);
        return err_set(err, "%s: cannot open: %s", path, strerror(e));
    }
    return 0;
}

void file_atomic_abort(AtomicFile *a)
{
    if (a->f)
        fclose(a->f);
    if (a->tmp) {
        unlink(a->tmp);
        pending_drop(a->slot);
        free(a->tmp);
    }
    a->f = NULL;
    a->tmp = NULL;
}

int file_atomic_commit(AtomicFile *a, Err *err)
{
    int rc = 0;
    if (fflush(a->f) != 0 || ferror(a->f) || fsync(fileno(a->f)) != 0)
        rc = err_set(err, "%s: write failed: %s", a->path, strerror(errno));
    if (fclose(a->f) != 0 && rc == 0)
        rc = err_set(err, "%s: write failed: %s", a->path, strerror(errno));
    a->f = NULL;
    /* mkstemp creates 0600; outputs are ordinary files */
    if (rc == 0) {
        mode_t mask = umask(0);
        umask(mask);
        chmod(a->tmp, 0666 & ~mask);
    }
    if (rc == 0 && rename(a->tmp, a->path) != 0)
        rc = err_set(err, "%s: cannot rename into place: %s", a->path, strerror(errno));
    if (rc != 0)
        unlink(a->tmp);
    pending_drop(a->slot);
    free(a->tmp);
    a->tmp = NULL;
    return rc;
}

int file_write_atomic(const char *path, file_write_fn fn, void *ctx, Err *err)
{
    AtomicFile a;
    if (file_atomic_open(&a, path, err))
        return -1;
    if (fn(a.f, ctx, err) != 0) {
        err_prefix(err, "%s", path);
        file_atomic_abort(&a);
        return -1;
    }
    return file_atomic_commit(&a, err);
}

typedef struct {
    const void *data;
    size_t len;
} Bytes;

static int write_bytes(FILE *f, void *ctx, Err *err)
{
    Bytes *b = ctx;
    (void)err;
    fwrite(b->data, 1, b->len, f);
    return 0; /* ferror is checked by the caller */
}

int file_write_bytes(const char *path, const void *data, size_t len, Err *err)
{
    Bytes b = {data, len};
    return file_write_atomic(path, write_bytes, &b, err);
}

int file_has_suffix(const char *path, const char *suffix)
{
    const size_t n = strlen(path), m = strlen(suffix);
    return n >= m && strcasecmp(path + n - m, suffix) == 0;
}

void file_dirname(const char *path, char *buf, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(buf, size, ".");
    else if (slash == path)
        snprintf(buf, size, "/");
    else
        snprintf(buf, size, "%.*s", (int)(slash - path), path);
}

const char *file_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

int file_join(const char *dir, const char *name, char *buf, size_t size)
{
    int n = name[0] == '/' ? snprintf(buf, size, "%s", name) : snprintf(buf, size, "%s/%s", dir, name);
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, R_OK) == 0;
}

/* name's last component, in dir or in another case there: FILE_BY_NAME,
 * FILE_BY_NAME_CASE (the path in buf), or FILE_NOT_FOUND. */
static FileFound find_in(const char *dir, const char *base, char *buf, size_t size)
{
    if (!*base)
        return FILE_NOT_FOUND;
    if (file_join(dir, base, buf, size) == 0 && file_exists(buf))
        return FILE_BY_NAME;
    DIR *d = opendir(dir);
    FileFound how = FILE_NOT_FOUND;
    for (struct dirent *e; d && how == FILE_NOT_FOUND && (e = readdir(d));)
        if (strcasecmp(e->d_name, base) == 0 && file_join(dir, e->d_name, buf, size) == 0 && file_exists(buf))
            how = FILE_BY_NAME_CASE;
    if (d)
        closedir(d);
    return how;
}

/* The ends of name's path (two components or more, the longest first),
 * each under dir and the two folders above it: a texture written as
 * D:\work\models\tex\wood.png for a model now in models/car/ is
 * models/tex/wood.png.  The last component may differ in case. */
static FileFound find_by_tail(const char *dir, const char *name, char *buf, size_t size)
{
    for (const char *tail = name; (tail = strchr(tail, '/')) != NULL;) {
        tail++;
        const char *last = strrchr(tail, '/');
        if (!last || strncmp(tail, "../", 3) == 0 || strncmp(tail, "./", 2) == 0 || *tail == '/')
            continue; /* one component (find_in's), or a tail that climbs */
        char base[4096], sub[4096];
        snprintf(base, sizeof base, "%s", dir);
        for (int up = 0; up < 3; up++) {
            if (snprintf(sub, sizeof sub, "%s/%.*s", base, (int)(last - tail), tail) < (int)sizeof sub &&
                find_in(sub, last + 1, buf, size) != FILE_NOT_FOUND)
                return FILE_NEARBY;
            if (strlen(base) + 4 >= sizeof base)
                break;
            strcat(base, "/..");
        }
    }
    return FILE_NOT_FOUND;
}

const char *file_found_how(FileFound how, const char *beside)
{
    static char out[128];
    switch (how) {
    case FILE_BY_NAME: snprintf(out, sizeof out, "its file name beside %s", beside); return out;
    case FILE_BY_NAME_CASE: return "its file name in another case";
    case FILE_NEARBY: snprintf(out, sizeof out, "the end of its path, in a folder near %s", beside); return out;
    default: return "as written";
    }
}

FileFound file_find_near(const char *dir, const char *name, char *buf, size_t size)
{
    char n[4096]; /* '\' as '/': paths written on Windows */
    snprintf(n, sizeof n, "%s", name);
    for (char *q = n; *q; q++)
        if (*q == '\\')
            *q = '/';
    if (file_join(dir, n, buf, size) == 0 && file_exists(buf))
        return FILE_AS_WRITTEN;
    char written[4096];
    snprintf(written, sizeof written, "%s", buf);
    FileFound how = find_in(dir, file_basename(n), buf, size); /* a bare name's exact try repeats the one above */
    if (how == FILE_NOT_FOUND)
        how = find_by_tail(dir, n, buf, size);
    if (how == FILE_NOT_FOUND)
        snprintf(buf, size, "%s", written);
    return how;
}
