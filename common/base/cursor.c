/* cursor.c - the growable sink (the reader is all inline). */
#include "base/cursor.h"

#include <stdlib.h>

int sink_put(Sink *s, const void *src, size_t n)
{
    if (s->failed)
        return -1;
    if (n > s->cap - s->len) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap - s->len < n) {
            if (cap > SIZE_MAX / 2) {
                s->failed = 1;
                return -1;
            }
            cap *= 2;
        }
        uint8_t *p = realloc(s->data, cap);
        if (!p) {
            s->failed = 1;
            return -1;
        }
        s->data = p;
        s->cap = cap;
    }
    if (n) /* an empty array may come as NULL, which memcpy may not be given */
        memcpy(s->data + s->len, src, n);
    s->len += n;
    return 0;
}

void sink_free(Sink *s)
{
    free(s->data);
    memset(s, 0, sizeof *s);
}
