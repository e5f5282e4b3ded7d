/* fuzz.h - the libFuzzer entry point every harness defines.  Built with
 * clang -fsanitize=fuzzer for `make fuzz`, or with replay.c's main for
 * `make check`, which runs the corpus and every saved crash input. */
#ifndef LANRAY_FUZZ_H
#define LANRAY_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "net/msg.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The text parsers work in place on a NUL-terminated buffer: a malloc'd copy
 * of the input (NULL when out of memory; the caller frees it). */
static inline char *fuzz_text(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (text) {
        memcpy(text, data, size);
        text[size] = 0;
    }
    return text;
}

/* The stream readers (images, textures) read a FILE: the input as one in
 * memory, or NULL when it is empty or cannot be opened (the caller, or the
 * reader, closes it). */
static inline FILE *fuzz_file(const uint8_t *data, size_t size)
{
    return size ? fmemopen((void *)data, size, "rb") : NULL;
}

/* Writes all of p to a socket (the packet harnesses' side of a socketpair);
 * stops quietly when the peer has hung up, since the rest no longer matters. */
static inline void fuzz_send_all(int fd, const uint8_t *p, size_t n)
{
    while (n > 0) {
        ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
        if (w <= 0)
            return;
        p += w;
        n -= (size_t)w;
    }
}

/* A packet as conn_send_msg would queue it: header, fixed part, tail. */
static inline void fuzz_send_msg(int fd, const MsgOut *o)
{
    uint32_t head[2] = {o->type, (uint32_t)(PROTO_HEADER + o->head_len + o->tail_len)};
    fuzz_send_all(fd, (const uint8_t *)head, sizeof head);
    fuzz_send_all(fd, o->head, o->head_len);
    if (o->tail_len)
        fuzz_send_all(fd, (const uint8_t *)o->tail, o->tail_len);
}

#endif
