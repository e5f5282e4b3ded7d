/* textenc.c - see textenc.h. */
#include "base/textenc.h"

#include "base/fileio.h"

#include <stdint.h>
#include <stdlib.h>

TextEncoding text_encoding(const char *data, size_t len)
{
    const unsigned char *u = (const unsigned char *)data;
    if (len >= 2 && u[0] == 0xFF && u[1] == 0xFE)
        return TEXT_UTF16LE;
    if (len >= 2 && u[0] == 0xFE && u[1] == 0xFF)
        return TEXT_UTF16BE;
    return TEXT_UTF8;
}

static size_t put_utf8(unsigned char *o, uint32_t c)
{
    if (c < 0x80) {
        o[0] = (unsigned char)c;
        return 1;
    }
    if (c < 0x800) {
        o[0] = (unsigned char)(0xC0 | c >> 6);
        o[1] = (unsigned char)(0x80 | (c & 0x3F));
        return 2;
    }
    if (c < 0x10000) {
        o[0] = (unsigned char)(0xE0 | c >> 12);
        o[1] = (unsigned char)(0x80 | (c >> 6 & 0x3F));
        o[2] = (unsigned char)(0x80 | (c & 0x3F));
        return 3;
    }
    o[0] = (unsigned char)(0xF0 | c >> 18);
    o[1] = (unsigned char)(0x80 | (c >> 12 & 0x3F));
    o[2] = (unsigned char)(0x80 | (c >> 6 & 0x3F));
    o[3] = (unsigned char)(0x80 | (c & 0x3F));
    return 4;
}

int text_to_utf8(char **data, size_t *len, const char *name, Err *err)
{
    TextEncoding e = text_encoding(*data, *len);
    if (e == TEXT_UTF8)
        return 0;
    const unsigned char *in = (const unsigned char *)*data;
    size_t units = (*len - 2) / 2;
    /* a unit becomes at most 3 bytes (a surrogate pair, two units, 4) */
    unsigned char *out = malloc(units * 3 + 1);
    if (!out)
        return err_set(err, "%s: out of memory decoding UTF-16", name);
    size_t o = 0;
    for (size_t i = 0; i < units; i++) {
        const unsigned char *p = in + 2 + 2 * i;
        uint32_t c = e == TEXT_UTF16LE ? (uint32_t)(p[0] | p[1] << 8) : (uint32_t)(p[0] << 8 | p[1]);
        if (c >= 0xD800 && c < 0xDC00 && i + 1 < units) {
            const unsigned char *q = p + 2;
            uint32_t d = e == TEXT_UTF16LE ? (uint32_t)(q[0] | q[1] << 8) : (uint32_t)(q[0] << 8 | q[1]);
            if (d >= 0xDC00 && d < 0xE000) {
                c = 0x10000 + ((c - 0xD800) << 10) + (d - 0xDC00);
                i++;
            } else {
                c = 0xFFFD;
            }
        } else if (c >= 0xD800 && c < 0xE000) {
            c = 0xFFFD;
        }
        o += put_utf8(out + o, c);
    }
    out[o] = 0;
    free(*data);
    *data = (char *)out;
    *len = o;
    return 0;
}

int text_read_file(const char *path, size_t max_bytes, char **data, size_t *len, Err *err)
{
    if (file_read_all(path, max_bytes, data, len, err))
        return -1;
    if (text_to_utf8(data, len, path, err)) {
        free(*data);
        *data = NULL;
        return -1;
    }
    return 0;
}
