/* fuzz_client.c - the client's packet parser: every byte a server sends.
 *
 * Each input is a server's whole stream to a client session (one render
 * thread) on one end of a socketpair.  When the first byte is odd the
 * harness sends a valid SERVER_HELLO and WELCOME first, so that the rest
 * lands in an active session (ASSET, UPDATE, COMPUTE, ERROR, BYE and
 * whatever else); otherwise the rest is the stream from its first byte (the
 * handshake itself).  The stream then ends, which ends the session and
 * cancels any rendering; what the client sends back is left unread (the
 * client queues it). */
#include <pthread.h>
#include <stdio.h>
#include <sys/socket.h>
#include <unistd.h>

#include "client.h"
#include "fuzz.h"
#include "net/msg.h"

typedef struct {
    int fd;
    const uint8_t *data;
    size_t size;
} Stream;

/* The server's side: the stream, then end of stream.  A thread of its own,
 * because the input may be bigger than the socket's buffer. */
static void *serve(void *arg)
{
    Stream *st = arg;
    if (st->data[0] & 1) {
        uint8_t hello[8 + 16 + PROTO_NONCE] = {0};
        uint32_t h[6] = {PKT_SERVER_HELLO, sizeof hello, PROTO_MAGIC, PROTO_VERSION, PROTO_BOM, 0};
        memcpy(hello, h, sizeof h);
        fuzz_send_all(st->fd, hello, sizeof hello);
        uint32_t welcome[3] = {PKT_WELCOME, 12, 1};
        fuzz_send_all(st->fd, (const uint8_t *)welcome, sizeof welcome);
    }
    fuzz_send_all(st->fd, st->data + 1, st->size - 1);
    shutdown(st->fd, SHUT_WR);
    return NULL;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 1 << 20)
        return 0;
    int fds[2];
    if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds))
        abort();
    Stream st = {fds[1], data, size};
    pthread_t th;
    if (pthread_create(&th, NULL, serve, &st))
        abort();
    ClientConfig cfg = {"fuzz", 0, 1, NULL, 1, 0};
    volatile sig_atomic_t stop = 0;
    Err err;
    client_run_fd(&cfg, fds[0], &stop, NULL, &err);
    pthread_join(th, NULL);
    close(fds[1]);
    return 0;
}
