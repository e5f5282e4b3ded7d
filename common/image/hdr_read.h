/* hdr_read.h - reading Radiance .hdr images (RGBE): lanray's own and other
 * renderers' (Blender's Cycles writes run-length coded scanlines), for
 * comparing the light of two frames (lanray-imgdiff --relative). */
#ifndef LANRAY_HDR_READ_H
#define LANRAY_HDR_READ_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"

/* The largest side read (a frame of lanray's is at most 65536). */
#define HDR_MAX_SIDE 65536

/* Parses the bytes of a .hdr (header, "-Y H +X W" or "+Y H +X W"; flat or
 * run-length coded scanlines) into malloc'd RGBE pixels, 4 bytes each, top
 * row first.  `name` labels errors, which say what was wrong and where. */
int hdr_parse(const uint8_t *data, size_t size, const char *name, int *width, int *height, uint8_t **rgbe, Err *err);
/* The same from a file. */
int hdr_read(const char *path, int *width, int *height, uint8_t **rgbe, Err *err);

#endif
