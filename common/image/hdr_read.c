/* hdr_read.c - see hdr_read.h.  Every read goes through the cursor, so
 * that no byte past the end is touched whatever the file says. */
#include "image/hdr_read.h"

#include <stdlib.h>
#include <string.h>

#include "base/cursor.h"
#include "base/fileio.h"

/* One header line (without its newline) into buf; -1 at the end of data. */
static int read_line(Cursor *c, char *buf, size_t cap)
{
    size_t n = 0;
    uint8_t ch;
    for (;;) {
        if (cursor_get(c, &ch, 1))
            return -1;
        if (ch == '\n')
            break;
        if (n + 1 < cap)
            buf[n++] = (char)ch;
    }
    buf[n] = '\0';
    return 0;
}

/* A side of the resolution line: a decimal number in 1..HDR_MAX_SIDE. */
static int side(const char *s, const char **end)
{
    long v = 0;
    int digits = 0;
    while (*s >= '0' && *s <= '9' && digits < 7) {
        v = v * 10 + (*s++ - '0');
        digits++;
    }
    *end = s;
    return digits && v >= 1 && v <= HDR_MAX_SIDE ? (int)v : 0;
}

/* "-Y H +X W" (top row first) or "+Y H +X W" (bottom row first). */
static int resolution(const char *line, int *w, int *h, int *flip)
{
    if ((line[0] != '-' && line[0] != '+') || strncmp(line + 1, "Y ", 2) != 0)
        return -1;
    *flip = line[0] == '+';
    const char *s;
    *h = side(line + 3, &s);
    if (!*h || strncmp(s, " +X ", 4) != 0)
        return -1;
    *w = side(s + 4, &s);
    return *w && *s == '\0' ? 0 : -1;
}

/* One run-length coded scanline (each channel apart, runs over 128 repeat
 * the next byte) into row. */
static int rle_row(Cursor *c, int w, uint8_t *row)
{
    for (int ch = 0; ch < 4; ch++)
        for (int x = 0; x < w;) {
            uint8_t n, v = 0;
            if (cursor_get(c, &n, 1) || n == 0)
                return -1;
            const int run = n > 128, count = run ? n - 128 : n;
            if (count > w - x)
                return -1;
            for (int k = 0; k < count; k++, x++) {
                if ((!run || k == 0) && cursor_get(c, &v, 1))
                    return -1;
                row[4 * x + ch] = v;
            }
        }
    return 0;
}

static int read_rows(Cursor *c, int w, int h, int flip, uint8_t *px)
{
    for (int y = 0; y < h; y++) {
        uint8_t *row = px + (size_t)4 * w * (flip ? h - 1 - y : y), head[4];
        if (cursor_get(c, head, 4))
            return y;
        const int coded = head[0] == 2 && head[1] == 2 && ((head[2] << 8) | head[3]) == w && w >= 8 && w < 32768;
        if (coded) {
            if (rle_row(c, w, row))
                return y;
        } else { /* flat: the head was the row's first pixel */
            memcpy(row, head, 4);
            if (cursor_get(c, row + 4, (size_t)4 * (w - 1)))
                return y;
        }
    }
    return -1;
}

int hdr_parse(const uint8_t *data, size_t size, const char *name, int *width, int *height, uint8_t **rgbe, Err *err)
{
    Cursor c = cursor_make(data, size);
    char line[256];
    if (read_line(&c, line, sizeof line) || (strcmp(line, "#?RADIANCE") != 0 && strcmp(line, "#?RGBE") != 0))
        return err_set(err, "%s: not a Radiance .hdr (no #?RADIANCE line)", name);
    int lines = 1, format_ok = 1;
    for (;;) {
        if (read_line(&c, line, sizeof line))
            return err_set(err, "%s: the header ends without a resolution line", name);
        lines++;
        if (line[0] == '\0')
            break;
        if (strncmp(line, "FORMAT=", 7) == 0)
            format_ok = strcmp(line + 7, "32-bit_rle_rgbe") == 0;
    }
    if (!format_ok)
        return err_set(err, "%s: only FORMAT=32-bit_rle_rgbe is read", name);
    int w, h, flip;
    if (read_line(&c, line, sizeof line) || resolution(line, &w, &h, &flip))
        return err_set(err, "%s: line %d: not a resolution this reader takes (-Y H +X W, sides 1..%d)", name,
                       lines + 1, HDR_MAX_SIDE);
    /* the fewest bytes a row takes: flat, or coded in runs of 127 */
    const size_t least = (size_t)(4 * w < 4 + 8 * ((w + 126) / 127) ? 4 * w : 4 + 8 * ((w + 126) / 127));
    if (least * (size_t)h > size) /* refused before allocating */
        return err_set(err, "%s: %dx%d pixels cannot fit in %zu bytes", name, w, h, size);
    uint8_t *px = calloc((size_t)w * h, 4);
    if (!px)
        return err_set(err, "%s: out of memory for %dx%d pixels", name, w, h);
    const int bad = read_rows(&c, w, h, flip, px);
    if (bad >= 0) {
        free(px);
        return err_set(err, "%s: scanline %d of %d is cut short or badly coded", name, bad + 1, h);
    }
    *width = w;
    *height = h;
    *rgbe = px;
    return 0;
}

int hdr_read(const char *path, int *width, int *height, uint8_t **rgbe, Err *err)
{
    char *data;
    size_t len;
    if (file_read_all(path, (size_t)1 << 34, &data, &len, err))
        return -1;
    int r = hdr_parse((const uint8_t *)data, len, path, width, height, rgbe, err);
    free(data);
    return r;
}
