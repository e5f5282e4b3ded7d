/* textenc.h - text files as exporters save them: UTF-16 to UTF-8.
 *
 * Some Windows tools save OBJ and MTL files as UTF-16 with a byte-order
 * mark.  The text formats' lexers read bytes as ASCII/UTF-8, so such a file
 * is decoded first: every line and number stays where it was. */
#ifndef LANRAY_TEXTENC_H
#define LANRAY_TEXTENC_H

#include <stddef.h>

#include "base/err.h"

typedef enum { TEXT_UTF8 = 0, TEXT_UTF16LE, TEXT_UTF16BE } TextEncoding;

/* The encoding its byte-order mark names (UTF-8 without a mark). */
TextEncoding text_encoding(const char *data, size_t len);

/* Replaces *data (malloc'd, NUL-terminated, *len bytes) by its UTF-8
 * decoding when it starts with a UTF-16 mark; unpaired surrogates become
 * U+FFFD and an odd last byte is dropped.  `name` labels errors. */
int text_to_utf8(char **data, size_t *len, const char *name, Err *err);

/* A whole text file (at most max_bytes), decoded to UTF-8 as above,
 * NUL-terminated, into *data (the caller frees it). */
int text_read_file(const char *path, size_t max_bytes, char **data, size_t *len, Err *err);

#endif
