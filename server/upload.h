/* upload.h - assets on their way to one client, sent slice by slice.
 *
 * A model of a million triangles is some 50 MB.  Queued on a connection
 * whole, it holds back every packet behind it until the last byte is
 * through: on a 100 Mbit/s link four seconds with no COMPUTE for that
 * client, whose frames then stop.  Sent ahead of the frames that need it
 * (ahead.c), it goes as ASSET slices of PROTO_ASSET_SLICE bytes, a slice
 * queued only while less than UPLOAD_LOW bytes wait to go on the
 * connection (its queue and the socket's), so that a frame's packets wait
 * behind a quarter of a megabyte at most.  An asset the next frame needs
 * goes at once, every slice queued (upload_pump's `all`).
 *
 * The assets are shared, counted (AssetSet): a scene replaced while its
 * assets are on their way keeps them until the last client has them. */
#ifndef LANRAY_UPLOAD_H
#define LANRAY_UPLOAD_H

#include <stdint.h>

#include "net/asset.h"
#include "net/conn.h"

#define UPLOAD_LOW (256u << 10)

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
} Upload;

/* set->a[i] to be sent after what is queued; -1 when out of memory. */
int upload_push(Upload *u, AssetSet *set, uint32_t i);
/* Queues slices on c: every one left (all), or while less than
 * UPLOAD_LOW bytes wait to go.  The bytes queued; -1 with err where the
 * connection refused them. */
long upload_pump(Upload *u, Conn *c, int all, Err *err);
int upload_pending(const Upload *u);
void upload_free(Upload *u);

#endif
