/* image.h - writing RGB8 frames as PNG (libpng) or binary PPM, atomically. */
#ifndef LANRAY_IMAGE_H
#define LANRAY_IMAGE_H

#include <stdint.h>

#include "err.h"

/* The format follows the extension: .png or .ppm. */
int image_write(const char *path, int width, int height, const uint8_t *rgb, Err *err);
/* Reads a PNG written by image_write (8-bit RGB) into a malloc'd buffer. */
int image_read_png(const char *path, int *width, int *height, uint8_t **rgb, Err *err);

#endif
