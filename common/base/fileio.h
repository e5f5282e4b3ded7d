/* fileio.h - whole-file reads with a size limit, and atomic writes.
 *
 * Outputs are written to a temporary name beside the target and renamed into
 * place, so a crash, a full disk or an error never leaves a partial file. */
#ifndef LANRAY_FILEIO_H
#define LANRAY_FILEIO_H

#include <stddef.h>
#include <stdio.h>

#include "base/err.h"

/* Reads all of path into a malloc'd buffer (NUL-terminated for text parsers). */
int file_read_all(const char *path, size_t max_bytes, char **data, size_t *len, Err *err);

/* A file being written under a temporary name beside its target: commit
 * flushes, syncs and renames it into place; abort (or a failed commit)
 * removes it.  Opening first also checks, before any work, that the
 * directory exists and is writable. */
typedef struct {
    FILE *f;
    char *tmp;
    const char *path;
    int slot; /* where the signal handler finds its name, or -1 */
} AtomicFile;
int file_atomic_open(AtomicFile *a, const char *path, Err *err);
/* Makes SIGINT, SIGTERM and SIGHUP remove every temporary file still being
 * written before the process ends by the signal's default action, so that
 * an interrupted program leaves nothing behind (a program that handles
 * those signals itself aborts its files instead). */
void file_atomic_on_signals(void);
int file_atomic_commit(AtomicFile *a, Err *err);
void file_atomic_abort(AtomicFile *a);

/* Atomic write through a callback that writes to the open temporary FILE. */
typedef int (*file_write_fn)(FILE *f, void *ctx, Err *err);
int file_write_atomic(const char *path, file_write_fn fn, void *ctx, Err *err);
int file_write_bytes(const char *path, const void *data, size_t len, Err *err);

/* Whether path ends in suffix, in any case (a model from a Windows machine
 * is often MODEL.OBJ). */
int file_has_suffix(const char *path, const char *suffix);
/* Directory part of path ("." when none) into buf. */
void file_dirname(const char *path, char *buf, size_t size);
/* The name after path's last '/' (path itself when none). */
const char *file_basename(const char *path);
/* Joins dir and a relative name; absolute names are kept as they are. */
int file_join(const char *dir, const char *name, char *buf, size_t size);
/* Whether path names a regular file this process can read. */
int file_exists(const char *path);

/* Where a file that another file names is (a texture an MTL names, an MTL
 * an OBJ names), '\' read as '/': as written, relative to dir; else, as
 * viewers do for models moved from the machine that wrote them
 * ("C:\Users\...\wood.png"), its last component in dir; else a file in
 * dir whose name differs from it only in case (names written on Windows);
 * else the end of its path ("tex/wood.png") under dir or one of the two
 * folders above it.  The path found goes to buf (as written when none is). */
typedef enum {
    FILE_NOT_FOUND = -1,
    FILE_AS_WRITTEN = 0,
    FILE_BY_NAME = 1,      /* the last component, in dir */
    FILE_BY_NAME_CASE = 2, /* the last component in another case, in dir */
    FILE_NEARBY = 3,       /* the end of its path, under dir or a folder above */
} FileFound;
FileFound file_find_near(const char *dir, const char *name, char *buf, size_t size);
/* How a file was found, for a warning: "its file name beside `beside`", ...
 * (a static buffer: one call a message). */
const char *file_found_how(FileFound how, const char *beside);

#endif
