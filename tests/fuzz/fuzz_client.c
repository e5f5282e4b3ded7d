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
#include "net/pixcodec.h"

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
        /* by the encoders: their layouts are the protocol's, whatever its version */
        MsgOut o;
        msg_encode_server_hello(&(MsgServerHello){.magic = PROTO_MAGIC, .version = PROTO_VERSION, .bom = PROTO_BOM}, &o);
        fuzz_send_msg(st->fd, &o);
        msg_encode_welcome(&(MsgWelcome){.id = 1, .coding = PIX_ZSTD | PIX_PREDICT}, &o);
        fuzz_send_msg(st->fd, &o);
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
