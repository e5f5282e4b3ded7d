/* framewriter.h - the frames a headless server writes, written on a thread
 * of their own: encoding a 1024x768 PNG takes 20-40 ms, and in the
 * server's loop the clients waited for it (a frame at a render scale is a
 * few segments).  A frame is copied into a free slot and written in the
 * order given; with every slot taken the caller waits, so no frame is
 * dropped.  Each file is written under a temporary name and renamed
 * (image_write). */
#ifndef LANRAY_FRAMEWRITER_H
#define LANRAY_FRAMEWRITER_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "image/image.h"

typedef struct FrameWriter FrameWriter;

/* A writer of width x height frames of bpp bytes a pixel with `slots`
 * frames queued at most; NULL with the reason. */
FrameWriter *framewriter_create(int width, int height, int bpp, int slots, Err *err);
/* Queues a copy of pixels to be written to path (at most
 * FRAMEWRITER_PATH - 1 bytes).  Returns how many writes failed since the
 * last call, the first of them said in err. */
#define FRAMEWRITER_PATH 4200
int framewriter_put(FrameWriter *fw, const char *path, const uint8_t *pixels, ImageEncoding enc, Err *err);
/* Waits until every queued frame is written; returns how many writes
 * failed since the last call, as framewriter_put. */
int framewriter_flush(FrameWriter *fw, Err *err);
/* Writes what is queued, then stops the thread and frees the writer. */
void framewriter_destroy(FrameWriter *fw);

#endif
