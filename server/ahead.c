/* ahead.c - a new scene's assets sent ahead of its frames.
 *
 * A scene read again (an edit, a file dropped on the window) may bring
 * models and textures the clients lack: a million triangles are some 50 MB
 * to send, and a client spends about half a second checking and decoding
 * them and building their trees.  Sent with the first frame that needed
 * them, every client did that at once and the frames stopped meanwhile
 * (1.4-1.8 s with two clients on one machine; over a LAN the transfer's
 * time more).  So they are sent the moment the scene is handed over,
 * slice by slice between the frames' packets (upload.h), each client
 * decodes them on a thread of its own (client/assetload.c) while it renders
 * the frames of the scene shown, and says HAVE for each; the frames of the
 * new scene start once every client has said it for every asset it was
 * sent, or AHEAD_WAIT_S after, whichever comes first (a client still
 * taking them in then gets the rest at once, before the new frame's
 * UPDATE, as a client that joins does). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "base/log.h"
#include "base/timer.h"
#include "measure.h"
#include "server_impl.h"

static int client_has(const Client *c, const uint8_t *hash)
{
    for (uint32_t i = 0; i < c->nsent; i++)
        if (memcmp(c->sent[i].hash, hash, PROTO_HASH) == 0)
            return 1;
    return 0;
}

/* The assets of set the client was not sent yet put on its way, each
 * remembered and awaited (its HAVE); their bytes. */
static uint64_t send_missing(Server *s, Client *c, AssetSet *set)
{
    uint64_t bytes = 0;
    for (uint32_t i = 0; set && i < set->n && !c->closing; i++) {
        if (client_has(c, set->a[i].hash))
            continue;
        if (array_reserve((void **)&c->sent, &c->sent_cap, c->nsent + 1, sizeof *c->sent, 1u << 20) ||
            upload_push(&c->up, set, i)) {
            server_drop(s, c, "out of memory for the assets it holds");
            break;
        }
        SentAsset *e = &c->sent[c->nsent++];
        memcpy(e->hash, set->a[i].hash, PROTO_HASH);
        e->have = 0;
        c->awaiting++;
        bytes += set->a[i].len;
    }
    return bytes;
}

/* Slices of the client's uploads queued on its connection (all of them, or
 * as upload.h paces them) and sent what the socket takes. */
static void pump(Server *s, Client *c, int all)
{
    Err e;
    const long bytes = upload_pump(&c->up, &c->conn, all, &e);
    if (bytes < 0 || (bytes > 0 && conn_flush(&c->conn, &e) < 0)) {
        server_drop(s, c, e.msg);
        return;
    }
    if (bytes > 0)
        measure_asset_sent(&s->m, (uint64_t)bytes);
}

/* The scene shown's assets the client lacks, and whatever of a new
 * scene's is still on its way, queued whole: its next UPDATE needs the
 * first, and an asset's slices go in order. */
void ahead_send_now(Server *s, Client *c)
{
    send_missing(s, c, s->assets);
    if (!c->closing)
        pump(s, c, 1);
}

/* A client that joins while a new scene waits is sent its assets too
 * (after those of the scene shown, which its first UPDATE brings). */
void ahead_joined(Server *s, Client *c)
{
    if (s->next_scene)
        s->ahead_bytes += send_missing(s, c, s->next_assets);
}

/* Every client's uploads paced onto its connection; whether any is left
 * (the loop then comes back within a millisecond: nothing else wakes it
 * when the socket's queue drains). */
int ahead_pump(Server *s)
{
    int left = 0;
    for (uint32_t i = 0; i < s->nclients; i++) {
        Client *c = s->clients[i];
        if (c->state == CLIENT_ACTIVE && !c->closing && upload_pending(&c->up)) {
            pump(s, c, 0);
            left |= !c->closing && upload_pending(&c->up);
        }
    }
    return left;
}

void server_set_scene(Server *s, Scene *next, Asset *assets, uint32_t nassets)
{
    AssetSet *set = assetset_make(assets, nassets);
    if (!set) { /* (a few bytes); a scene handed over before is the caller's to free now */
        log_line(s->cfg.quiet, "lanray-server", "out of memory: a new scene is not taken");
        assetset_drop(s->next_assets);
        s->next_assets = NULL, s->next_scene = NULL;
        return;
    }
    assetset_drop(s->next_assets);
    s->next_scene = next;
    s->next_assets = set;
    uint64_t bytes = 0;
    for (uint32_t i = 0; i < s->nclients; i++)
        if (s->clients[i]->state == CLIENT_ACTIVE && !s->clients[i]->closing)
            bytes += send_missing(s, s->clients[i], s->next_assets);
    if (bytes && !s->ahead_t) { /* the first of several scenes handed over before one was taken */
        s->ahead_t = timer_now();
        s->ahead_frame = s->frame;
        s->ahead_bytes = 0;
    }
    s->ahead_bytes += bytes;
    ahead_pump(s);
}

/* The clients that have not said HAVE for every asset they were sent. */
static uint32_t awaited(const Server *s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nclients; i++) {
        const Client *c = s->clients[i];
        n += c->state == CLIENT_ACTIVE && !c->closing && c->awaiting > 0;
    }
    return n;
}

int ahead_ready(const Server *s)
{
    return s->next_scene && (awaited(s) == 0 || timer_now() - s->ahead_t > AHEAD_WAIT_S);
}

/* The new description: its assets, its camera where it moved the file's,
 * its settings; said in the log where its assets went ahead. */
void ahead_swap(Server *s)
{
    if (s->ahead_t) {
        const uint32_t late = awaited(s);
        const double t = timer_now() - s->ahead_t;
        if (late)
            log_line(s->cfg.quiet, "lanray-server",
                     "a new scene's models and textures (%.1f MB) not taken in by %u client%s in %.0f s: its frames start",
                     (double)s->ahead_bytes / 1e6, late, late == 1 ? "" : "s", t);
        else if (s->frame > s->ahead_frame)
            log_line(s->cfg.quiet, "lanray-server",
                     "a new scene's models and textures (%.1f MB) taken in by every client in %.2f s (%u frames meanwhile)",
                     (double)s->ahead_bytes / 1e6, t, s->frame - s->ahead_frame);
        else /* a still window makes no frame meanwhile */
            log_line(s->cfg.quiet, "lanray-server",
                     "a new scene's models and textures (%.1f MB) taken in by every client in %.2f s",
                     (double)s->ahead_bytes / 1e6, t);
        s->ahead_t = 0;
    }
    const Camera before = s->scene->camera;
    s->scene = s->next_scene;
    s->next_scene = NULL;
    assetset_drop(s->assets);
    s->assets = s->next_assets;
    s->next_assets = NULL;
    if (!camera_same(&before, &s->scene->camera))
        s->view.camera = s->scene->camera;
    s->view.settings = s->scene->settings;
    s->dirty = 1;
    s->edit_id++;
}

void ahead_on_have(Server *s, Client *c)
{
    MsgHave h;
    Err e;
    if (msg_decode_have(c->conn.body, c->conn.body_size, &h, &e)) {
        server_drop(s, c, e.msg);
        return;
    }
    for (uint32_t i = 0; i < c->nsent; i++)
        if (!c->sent[i].have && memcmp(c->sent[i].hash, h.hash, PROTO_HASH) == 0) {
            c->sent[i].have = 1;
            c->awaiting--;
            return;
        }
    server_drop(s, c, "HAVE for an asset it was not sent, or said twice");
}
