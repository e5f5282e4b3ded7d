/* upload.c - see upload.h. */
#include "upload.h"

#include <linux/sockios.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>

#include "base/array.h"
#include "base/timer.h"

AssetSet *assetset_make(Asset *a, uint32_t n)
{
    AssetSet *s = malloc(sizeof *s);
    if (!s) {
        assets_free(a, n);
        return NULL;
    }
    *s = (AssetSet){a, n, 1};
    return s;
}

AssetSet *assetset_ref(AssetSet *s)
{
    s->refs++;
    return s;
}

void assetset_drop(AssetSet *s)
{
    if (s && --s->refs == 0) {
        assets_free(s->a, s->n);
        free(s);
    }
}

int upload_push(Upload *u, AssetSet *set, uint32_t i)
{
    if (u->head && u->head == u->n) /* all sent: start the queue again */
        u->head = u->n = 0;
    if (u->n == 0)
        u->t = 0; /* the link's pace measured again from the next pump */
    if (array_reserve((void **)&u->q, &u->cap, u->n + 1, sizeof *u->q, 1u << 20))
        return -1;
    u->q[u->n++] = (UploadItem){assetset_ref(set), i, 0};
    return 0;
}

/* Bytes queued on the socket and not yet sent (SIOCOUTQ), or 0 where it
 * cannot say (not a socket: a test's pipe). */
static size_t socket_waiting(int fd)
{
    int n = 0;
    return ioctl(fd, SIOCOUTQ, &n) == 0 && n > 0 ? (size_t)n : 0;
}

/* The bytes that may wait to go on c: the link's pace (the bytes its
 * socket delivered a second, sampled every 5 ms or more while it sends
 * assets) times UPLOAD_AHEAD_S, within UPLOAD_LOW_MIN and UPLOAD_LOW_MAX. */
static size_t paced_limit(Upload *u, const Conn *c, size_t in_socket)
{
    const double now = timer_now();
    const uint64_t gone = c->bytes_out - in_socket;
    if (u->t == 0) {
        u->t = now, u->gone = gone;
    } else if (now - u->t >= 0.005) {
        const double r = (double)(gone - u->gone) / (now - u->t);
        u->rate = u->rate > 0 ? 0.5 * (u->rate + r) : r;
        u->t = now, u->gone = gone;
    }
    const double limit = u->rate * UPLOAD_AHEAD_S;
    return limit < UPLOAD_LOW_MIN ? UPLOAD_LOW_MIN : limit > UPLOAD_LOW_MAX ? UPLOAD_LOW_MAX : (size_t)limit;
}

long upload_pump(Upload *u, Conn *c, int all, Err *err)
{
    long queued = 0;
    const size_t in_socket = socket_waiting(c->fd);
    const size_t limit = all ? SIZE_MAX : paced_limit(u, c, in_socket);
    while (u->head < u->n && (all || conn_pending(c) + in_socket < limit)) {
        UploadItem *it = &u->q[u->head];
        const Asset *a = &it->set->a[it->i];
        const size_t left = a->len - it->at;
        MsgAsset m = {a->kind, {0}, (uint32_t)a->len, it->at, a->data + it->at,
                      left < UPLOAD_SLICE ? left : UPLOAD_SLICE};
        memcpy(m.hash, a->hash, PROTO_HASH);
        MsgOut out;
        msg_encode_asset(&m, &out);
        if (conn_send_msg(c, &out, CONN_MAX_QUEUE, err))
            return -1;
        queued += (long)(PROTO_HEADER + out.head_len + out.tail_len);
        it->at += (uint32_t)m.len;
        if (it->at == a->len) {
            assetset_drop(it->set);
            u->head++;
        }
    }
    return queued;
}

int upload_pending(const Upload *u) { return u->head < u->n; }

void upload_free(Upload *u)
{
    for (uint32_t i = u->head; i < u->n; i++)
        assetset_drop(u->q[i].set);
    free(u->q);
    memset(u, 0, sizeof *u);
}
