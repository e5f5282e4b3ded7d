/* assetload.h - the assets a client is sent, checked and decoded on a
 * thread of their own.
 *
 * A model of a million triangles is some 50 MB: its hash checked, its
 * .tmd image decoded and its wide tree built take the better part of a
 * second.  Done on the network thread, the client sent no pixels and took
 * no work meanwhile; the server now sends a new scene's assets ahead of
 * its frames (server/ahead.c), and the client goes on rendering the frames
 * of the scene shown while this thread takes them in.  Each asset decoded
 * is put in the cache by the network thread (assetload_take), in the order
 * the assets came, and answered with a HAVE. */
#ifndef LANRAY_ASSETLOAD_H
#define LANRAY_ASSETLOAD_H

#include "base/err.h"
#include "net/asset.h"
#include "net/msg.h"

typedef struct AssetLoad AssetLoad;

/* Starts the thread; it writes a byte to `wake` (a non-blocking pipe's
 * end) each time an asset is done. */
AssetLoad *assetload_create(int wake, Err *err);
/* Waits for the asset being decoded, drops those queued, ends the thread. */
void assetload_destroy(AssetLoad *l);
/* An ASSET's slice, gathered (network thread); a payload whole is queued
 * to be checked and decoded.  -1 with err for a slice that does not follow
 * the one before (another asset before this one was whole, a gap). */
int assetload_slice(AssetLoad *l, const MsgAsset *a, Err *err);
/* Waits until every asset queued is decoded (or failed). */
void assetload_wait(AssetLoad *l);
/* The assets decoded so far, in the order they were queued, into cache,
 * have(ctx, hash) called for each; stops at the first one not done yet.
 * -1 with err at the first that failed (a payload that is not its hash,
 * a model that does not decode: the server's mistake, which ends the
 * session); the ones after it stay queued. */
int assetload_take(AssetLoad *l, AssetCache *cache, void (*have)(void *ctx, const uint8_t *hash), void *ctx,
                   Err *err);
/* At a session's end: waits for them all, keeps what decoded, drops the
 * rest and an asset half sent (a new session's server sends what the
 * client still lacks). */
void assetload_settle(AssetLoad *l, AssetCache *cache);

#endif
