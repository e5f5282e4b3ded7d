/* upload.h - assets on their way to one client, sent slice by slice.
 *
 * A model of a million triangles is some 50 MB.  Queued on a connection
 * whole, it holds back every packet behind it until the last byte is
 * through: on a 100 Mbit/s link four seconds with no COMPUTE for that
 * client, whose frames then stop.  Sent ahead of the frames that need it
 * (ahead.c), it goes as ASSET slices of UPLOAD_SLICE bytes, a slice queued
 * only while what waits to go on the connection (its queue and the
 * socket's) is less than UPLOAD_AHEAD_S of the link's time: the bytes the
 * socket was seen to deliver a second, measured as it goes, from
 * UPLOAD_LOW_MIN (before any is measured) up to UPLOAD_LOW_MAX.  The most
 * is there because "delivered" is what the client's kernel took, not what
 * the client read: on one machine (loopback) the socket drains at memory
 * speed while the client, sharing the cores, reads slower, and what its
 * kernel holds unread (megabytes) waits in front of a frame's packets too.
 * An asset the next frame needs goes at once, every slice queued
 * (upload_pump's `all`).
 *
 * Measured (2026-12-02, 2 cores, 128x96 frames, two one-thread clients):
 * a 200k-triangle model, 19.5 MB to the two, behind a 100 Mbit/s tbf link:
 * sent whole, no frame for 1.55 s (before it was sent ahead, 1.76 s);
 * fixed 256 KiB a frame every 150 ms during the 1.8 s transfer; 64 KiB,
 * none over 0.1 s apart (63 frames a second), as with the paced limit
 * (102-125 frames in 1.8 s).  A million triangles, 98 MB, on loopback: at
 * a fixed 64 KiB taken in in 1.33-1.55 s (the loop refills every
 * millisecond; 32 KiB 1.9-2.4 s), with the paced limit up to 256 KiB in
 * 1.08-1.15 s and no frame over 50 ms apart, up to 1 MiB in 0.89-1.05 s
 * but a 0.19 s gap each time (the client's unread kernel buffer).
 *
 * The assets are shared, counted (AssetSet): a scene replaced while its
 * assets are on their way keeps them until the last client has them. */
#ifndef LANRAY_UPLOAD_H
#define LANRAY_UPLOAD_H

#include <stdint.h>

#include "net/asset.h"
#include "net/conn.h"

#ifndef UPLOAD_SLICE
#define UPLOAD_SLICE (64u << 10)
#endif
#define UPLOAD_AHEAD_S 0.01
#ifndef UPLOAD_LOW_MIN
#define UPLOAD_LOW_MIN (64u << 10)
#endif
#ifndef UPLOAD_LOW_MAX
#define UPLOAD_LOW_MAX (256u << 10)
#endif
_Static_assert(UPLOAD_SLICE <= PROTO_ASSET_SLICE, "a slice the clients take");

/* A scene's assets, shared by the server and the uploads (the loop's
 * thread alone touches the count). */
typedef struct {
    Asset *a;
    uint32_t n;
    uint32_t refs;
} AssetSet;

/* A set of a[n] (taken, freed with the set); NULL when out of memory (a is
 * freed then). */
AssetSet *assetset_make(Asset *a, uint32_t n);
AssetSet *assetset_ref(AssetSet *s);
void assetset_drop(AssetSet *s);

typedef struct {
    AssetSet *set;
    uint32_t i;  /* the asset, set->a[i] */
    uint32_t at; /* its bytes sent so far */
} UploadItem;

typedef struct {
    UploadItem *q; /* in order, from head */
    uint32_t head, n, cap;
    /* the link's pace: bytes the socket delivered a second, and the last
     * sample's time and count (t 0: none since the queue was empty) */
    double rate, t;
    uint64_t gone;
} Upload;

/* set->a[i] to be sent after what is queued; -1 when out of memory. */
int upload_push(Upload *u, AssetSet *set, uint32_t i);
/* Queues slices on c: every one left (all), or while less than
 * UPLOAD_AHEAD_S of the link's time waits to go.  The bytes queued; -1
 * with err where the connection refused them. */
long upload_pump(Upload *u, Conn *c, int all, Err *err);
int upload_pending(const Upload *u);
void upload_free(Upload *u);

#endif
