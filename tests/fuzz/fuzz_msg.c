/* fuzz_msg.c - every packet decoder (msg.h) on arbitrary bodies, the first
 * byte choosing the packet type; a body a decoder accepts must encode back
 * to the very same bytes (the codec has one layout, read and written). */
#include "fuzz.h"
#include "net/msg.h"

static void same(const MsgOut *o, const uint8_t *body, size_t len)
{
    if (o->head_len + o->tail_len != len || memcmp(o->head, body, o->head_len) != 0 ||
        (o->tail_len && memcmp(o->tail, body + o->head_len, o->tail_len) != 0))
        abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    const uint8_t *b = data + 1;
    size_t n = size - 1;
    MsgOut o;
    switch (data[0] % 9) {
    case 0: {
        MsgServerHello m;
        if (msg_decode_server_hello(b, n, &m, NULL) == 0)
            msg_encode_server_hello(&m, &o), same(&o, b, n);
        break;
    }
    case 1: {
        MsgHello m;
        if (msg_decode_hello(b, n, &m, NULL) == 0)
            msg_encode_hello(&m, &o), same(&o, b, n);
        break;
    }
    case 2: {
        MsgWelcome m;
        if (msg_decode_welcome(b, n, &m, NULL) == 0)
            msg_encode_welcome(&m, &o), same(&o, b, n);
        break;
    }
    case 3: {
        MsgUpdate m;
        if (msg_decode_update(b, n, &m, NULL) == 0)
            msg_encode_update(&m, &o), same(&o, b, n);
        break;
    }
    case 4: {
        MsgCompute m;
        if (msg_decode_compute(b, n, &m, NULL) == 0)
            msg_encode_compute(&m, &o), same(&o, b, n);
        break;
    }
    case 5: {
        MsgData m; /* both pixel sizes: RGB8 and RGBE */
        for (uint32_t bpp = 3; bpp <= 4; bpp++)
            if (msg_decode_data(b, n, bpp, &m, NULL) == 0)
                msg_encode_data(&m, &o), same(&o, b, n);
        break;
    }
    case 6: {
        MsgAsset m;
        if (msg_decode_asset(b, n, &m, NULL) == 0)
            msg_encode_asset(&m, &o), same(&o, b, n);
        break;
    }
    case 7: {
        MsgHave m;
        if (msg_decode_have(b, n, &m, NULL) == 0)
            msg_encode_have(&m, &o), same(&o, b, n);
        break;
    }
    default: {
        char text[PROTO_MAX_ERROR_TEXT + 1];
        if (msg_decode_error(b, n, text, NULL) == 0 && strlen(text) != (n < PROTO_MAX_ERROR_TEXT ? n : PROTO_MAX_ERROR_TEXT))
            abort(); /* NUL bytes become '?': the text keeps its length */
        break;
    }
    }
    return 0;
}
