/* test_msg.c - the packet codec (msg.h): every packet survives encode then
 * decode field for field, decoders refuse bodies that do not fit their
 * layout, and docs/protocol.md shows the layouts and size limits the codec
 * has (its generated table is compared line for line). */
#include "helpers.h"

#include "net/pixcodec.h"

#include "base/fileio.h"
#include "net/conn.h"
#include "net/mdns.h"
#include "net/msg.h"
#include "net/net.h"

#include <poll.h>
#include <sys/socket.h>

/* head + tail, as the wire carries the body */
static size_t body_of(const MsgOut *o, uint8_t *buf)
{
    memcpy(buf, o->head, o->head_len);
    if (o->tail_len)
        memcpy(buf + o->head_len, o->tail, o->tail_len);
    return o->head_len + o->tail_len;
}

static void packets_round_trip(void **state)
{
    (void)state;
    static uint8_t buf[4096];
    MsgOut o;
    Err err;
    size_t n;

    MsgServerHello sh = {PROTO_MAGIC, PROTO_VERSION, PROTO_BOM, HELLO_TOKEN_REQUIRED, {0}}, sh2;
    for (int i = 0; i < (int)PROTO_NONCE; i++)
        sh.nonce[i] = (uint8_t)(i * 7 + 1);
    msg_encode_server_hello(&sh, &o);
    n = body_of(&o, buf);
    assert_int_equal(o.type, PKT_SERVER_HELLO);
    assert_int_equal(n + PROTO_HEADER, msg_max_size(PKT_SERVER_HELLO));
    assert_int_equal(msg_decode_server_hello(buf, n, &sh2, &err), 0);
    assert_memory_equal(&sh, &sh2, sizeof sh);

    MsgHello h = {.magic = PROTO_MAGIC, .version = PROTO_VERSION, .bom = PROTO_BOM, .threads = 16, .real_size = 4,
                  .codecs = PIX_CODEC_MASK},
             h2;
    for (int i = 0; i < (int)PROTO_NONCE; i++)
        h.nonce[i] = (uint8_t)i, h.proof[i] = (uint8_t)(255 - i);
    msg_encode_hello(&h, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_hello(buf, n, &h2, &err), 0);
    assert_memory_equal(&h, &h2, sizeof h);
    uint32_t first;
    memcpy(&first, buf, 4);
    assert_int_equal(first, PROTO_MAGIC); /* the magic leads, as the docs say */

    MsgWelcome w = {.id = 42, .coding = PIX_LZ4}, w2;
    msg_encode_welcome(&w, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_welcome(buf, n, &w2, &err), 0);
    assert_int_equal(w2.id, 42);

    /* the view (3 bytes) and the scene (5) are one block: with the scene, or the view alone */
    const uint8_t block[8] = {9, 8, 7, 1, 2, 3, 4, 5};
    for (uint32_t nseg = 0; nseg <= 2; nseg++)
        for (size_t scene_len = 0; scene_len <= 5; scene_len += 5) {
            MsgUpdate u = {.frame = 7, .width = 640, .height = 480, .keep = 6, .scene_id = 3, .view_len = 3, .nseg = nseg,
                           .seg = {{10, 20}, {30, 40}}, .view = block, .scene_len = scene_len},
                      u2;
            msg_encode_update(&u, &o);
            n = body_of(&o, buf);
            assert_int_equal(n, 28 + 8 * nseg + 3 + scene_len);
            assert_int_equal(msg_decode_update(buf, n, &u2, &err), 0);
            assert_true(u2.frame == 7 && u2.width == 640 && u2.height == 480 && u2.nseg == nseg);
            assert_true(u2.keep == 6 && u2.scene_id == 3 && u2.view_len == 3);
            for (uint32_t k = 0; k < nseg; k++)
                assert_memory_equal(&u2.seg[k], &u.seg[k], sizeof(Segment));
            assert_memory_equal(u2.view, block, 3);
            assert_int_equal(u2.scene_len, scene_len);
            if (scene_len)
                assert_memory_equal(u2.scene, block + 3, scene_len);
        }

    MsgCompute c = {9, {100, 200}}, c2;
    msg_encode_compute(&c, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_compute(buf, n, &c2, &err), 0);
    assert_memory_equal(&c, &c2, sizeof c);

    const uint8_t px[6] = {1, 2, 3, 4, 5, 6};
    MsgData d = {.frame = 3, .seg = {5, 2}, .render_us = 1234, .pixels = px, .len = 6, .bpp = 3}, d2;
    msg_encode_data(&d, &o);
    n = body_of(&o, buf);
    assert_int_equal(n, 20 + 6);
    assert_int_equal(msg_decode_data(buf, n, 3, &d2, &err), 0);
    assert_true(d2.frame == 3 && d2.seg.first == 5 && d2.seg.count == 2 && d2.render_us == 1234 && d2.bpp == 3);
    assert_true(d2.coding == PIX_RAW && d2.len == 6);
    assert_memory_equal(d2.pixels, px, 6);
    /* an hdr frame's pixels are RGBE: 4 bytes each, the same 6 bytes no longer fit */
    assert_int_equal(msg_decode_data(buf, n, 4, &d2, &err), -1);
    const uint8_t rgbe[8] = {1, 2, 3, 130, 5, 6, 7, 140};
    MsgData hd = {.frame = 4, .seg = {7, 2}, .render_us = 99, .pixels = rgbe, .len = 8, .bpp = 4};
    msg_encode_data(&hd, &o);
    n = body_of(&o, buf);
    assert_int_equal(n, 20 + 8);
    assert_int_equal(msg_decode_data(buf, n, 4, &d2, &err), 0);
    assert_true(d2.frame == 4 && d2.seg.first == 7 && d2.seg.count == 2 && d2.bpp == 4);
    assert_memory_equal(d2.pixels, rgbe, 8);
    /* coded: fewer bytes than the segment's, the coding carried */
    MsgData cd = {.frame = 3, .seg = {5, 4}, .coding = PIX_ZSTD | PIX_PREDICT, .pixels = px, .len = 6, .bpp = 3};
    msg_encode_data(&cd, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_data(buf, n, 3, &d2, &err), 0);
    assert_true(d2.coding == (PIX_ZSTD | PIX_PREDICT) && d2.len == 6 && d2.seg.count == 4);

    /* a slice: the payload's bytes 10 .. 15 of 16 */
    MsgAsset a = {ASSET_TEXTURE, {0}, 16, 10, px, sizeof px}, a2;
    a.hash[0] = 0xab, a.hash[31] = 0xcd;
    msg_encode_asset(&a, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_asset(buf, n, &a2, &err), 0);
    assert_true(a2.kind == ASSET_TEXTURE && a2.len == sizeof px && a2.hash[0] == 0xab && a2.hash[31] == 0xcd);
    assert_true(a2.total == 16 && a2.offset == 10);
    assert_memory_equal(a2.data, px, sizeof px);
    /* past its total, or a total past the most an asset may be */
    a.offset = 11;
    msg_encode_asset(&a, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_asset(buf, n, &a2, &err), -1);
    assert_non_null(strstr(err.msg, "ASSET slice of 6 bytes at 11 of an asset of 16 bytes"));
    a.offset = 0, a.total = PROTO_ASSET_MAX + 1;
    msg_encode_asset(&a, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_asset(buf, n, &a2, &err), -1);
    assert_non_null(strstr(err.msg, "ASSET of 1073741825 bytes"));

    MsgHave hv = {{0}}, hv2;
    hv.hash[0] = 7, hv.hash[31] = 9;
    msg_encode_have(&hv, &o);
    n = body_of(&o, buf);
    assert_int_equal(n, PROTO_HASH);
    assert_int_equal(msg_decode_have(buf, n, &hv2, &err), 0);
    assert_memory_equal(hv2.hash, hv.hash, PROTO_HASH);
    assert_int_equal(msg_decode_have(buf, n - 1, &hv2, &err), -1);

    char text[PROTO_MAX_ERROR_TEXT + 1];
    msg_encode_error(&(MsgError){"bad\nthing", 9}, &o);
    n = body_of(&o, buf);
    assert_int_equal(msg_decode_error(buf, n, text, &err), 0);
    assert_string_equal(text, "bad?thing"); /* made printable */
    char longer[2000];
    memset(longer, 'x', sizeof longer);
    msg_encode_error(&(MsgError){longer, sizeof longer}, &o);
    assert_int_equal(o.tail_len, PROTO_MAX_ERROR_TEXT); /* cut to what the packet may carry */

    msg_encode_bye(&o);
    assert_true(o.type == PKT_BYE && o.head_len == 0 && o.tail_len == 0);
}

static void bodies_that_do_not_fit_are_refused(void **state)
{
    (void)state;
    uint8_t buf[256] = {0};
    Err err;
    MsgHello h;
    assert_int_equal(msg_decode_hello(buf, 87, &h, &err), -1);
    assert_non_null(strstr(err.msg, "HELLO packet of 87 bytes is too short"));
    assert_int_equal(msg_decode_hello(buf, 89, &h, &err), -1);
    assert_non_null(strstr(err.msg, "HELLO packet of 89 bytes, its layout has 88"));
    MsgUpdate u;
    uint32_t three[7] = {1, 2, 3, 1, 1, 0, 3}; /* frame, width, height, keep, scene id, view length, nseg */
    memcpy(buf, three, sizeof three);
    assert_int_equal(msg_decode_update(buf, 200, &u, &err), -1);
    assert_non_null(strstr(err.msg, "UPDATE packet with 3 segments"));
    uint32_t two[7] = {1, 2, 3, 1, 1, 0, 2};
    memcpy(buf, two, sizeof two);
    assert_int_equal(msg_decode_update(buf, 28 + 15, &u, &err), -1);
    assert_non_null(strstr(err.msg, "too short for its segments"));
    uint32_t long_view[7] = {1, 2, 3, 1, 1, 10, 0}; /* a view of 10 bytes, 9 there */
    memcpy(buf, long_view, sizeof long_view);
    assert_int_equal(msg_decode_update(buf, 28 + 9, &u, &err), -1);
    assert_non_null(strstr(err.msg, "view of 10 bytes and 9 bytes left"));
    MsgData d;
    uint32_t data[5] = {1, 0, 10, 5, PIX_RAW}; /* 10 pixels claimed, raw */
    memcpy(buf, data, sizeof data);
    assert_int_equal(msg_decode_data(buf, 20 + 29, 3, &d, &err), -1);
    assert_non_null(strstr(err.msg, "DATA packet of 29 raw pixel bytes for a segment of 10 pixels of 3 bytes"));
    assert_int_equal(msg_decode_data(buf, 20 + 30, 3, &d, &err), 0);
    assert_int_equal(msg_decode_data(buf, 20 + 30, 4, &d, &err), -1);
    assert_int_equal(msg_decode_data(buf, 20 + 40, 4, &d, &err), 0);
    /* coded: a packet that claims as many bytes as its segment's pixels, or more, is refused */
    uint32_t coded[5] = {1, 0, 10, 5, PIX_LZ4};
    memcpy(buf, coded, sizeof coded);
    assert_int_equal(msg_decode_data(buf, 20 + 29, 3, &d, &err), 0);
    assert_int_equal(msg_decode_data(buf, 20 + 30, 3, &d, &err), -1);
    assert_non_null(strstr(err.msg, "DATA packet of 30 coded pixel bytes for a segment of 10 pixels"));
    assert_int_equal(msg_decode_data(buf, 20 + 200, 3, &d, &err), -1);
    MsgAsset a;
    assert_int_equal(msg_decode_asset(buf, 43, &a, &err), -1);
    assert_int_equal(msg_type_name(99)[0], 'u'); /* "unknown" */
    assert_int_equal(msg_max_size(99), 0);
}

typedef struct {
    char text[8192];
    size_t len;
} Text;

static void add_row(void *ctx, const char *line)
{
    Text *t = ctx;
    char type[32], off[32], size[32], name[32];
    assert_int_equal(sscanf(line, "%31s %31s %31s %31s", type, off, size, name), 4);
    t->len += (size_t)snprintf(t->text + t->len, sizeof t->text - t->len, "| %s | %s | %s | %s |\n", type, off, size, name);
}

/* docs/protocol.md holds the table msg_layout gives, between two markers,
 * and the size limits msg_min_size and msg_max_size give. */
static void protocol_doc_matches_the_codec(void **state)
{
    (void)state;
    Text want = {"| packet | offset | size | field |\n|---|---|---|---|\n", 0};
    want.len = strlen(want.text);
    msg_layout(add_row, &want);
    char *doc;
    size_t len;
    Err err;
    if (file_read_all("docs/protocol.md", 1 << 20, &doc, &len, &err))
        fail_msg("%s", err.msg);
    const char *begin = strstr(doc, "<!-- msg_layout: generated from common/net/msg.c, checked by tests/test_msg.c -->\n");
    const char *end = begin ? strstr(begin, "<!-- end msg_layout -->") : NULL;
    if (!begin || !end)
        fail_msg("docs/protocol.md has no msg_layout block");
    begin = strchr(begin, '\n') + 1;
    if ((size_t)(end - begin) != want.len || memcmp(begin, want.text, want.len) != 0)
        fail_msg("docs/protocol.md's layout table differs from the codec's; it should read:\n%s", want.text);
    for (uint32_t type = 1; type < PKT_TYPE_END; type++) {
        char row[128];
        uint32_t lo = msg_min_size(type), hi = msg_max_size(type);
        snprintf(row, sizeof row, "| %u | %s | ", type, msg_type_name(type));
        const char *r = strstr(doc, row);
        if (!r)
            fail_msg("docs/protocol.md has no size row for %s", msg_type_name(type));
        char limit[64];
        if (lo == hi)
            snprintf(limit, sizeof limit, "| exactly %u |", lo);
        else
            snprintf(limit, sizeof limit, "| %u .. ", lo);
        const char *eol = strchr(r, '\n');
        const char *l = strstr(r, limit);
        if (!l || l > eol)
            fail_msg("docs/protocol.md: %s's size limits do not start '%s'", msg_type_name(type), limit);
    }
    free(doc);
}

/* A connection reads ahead: two packets and part of a third sent at once
 * come out one by one, the second without the socket having anything new
 * (conn_buffered says so, or a poll() loop would wait on it for ever), the
 * part only once its rest arrives (conn_buffered does not count it). */
static void reads_ahead_and_says_so(void **state)
{
    (void)state;
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
    assert_int_equal(net_setup(sv[0]), 0);
    uint8_t wire[3 * 20];
    for (uint32_t k = 0; k < 3; k++) {
        MsgOut o;
        msg_encode_compute(&(MsgCompute){.frame = 7, .seg = {k * 10, 10}}, &o);
        uint32_t head[2] = {o.type, (uint32_t)(PROTO_HEADER + o.head_len)};
        memcpy(wire + 20 * k, head, 8);
        memcpy(wire + 20 * k + 8, o.head, o.head_len);
    }
    assert_int_equal(write(sv[1], wire, 50), 50); /* two and a half */
    Conn c;
    conn_init(&c, sv[0]);
    Err err;
    MsgCompute m;
    assert_int_equal(conn_read(&c, &err), 1);
    assert_int_equal(msg_decode_compute(c.body, c.body_size, &m, &err), 0);
    assert_int_equal(m.seg.first, 0);
    assert_true(conn_buffered(&c));
    assert_int_equal(conn_read(&c, &err), 1);
    assert_int_equal(msg_decode_compute(c.body, c.body_size, &m, &err), 0);
    assert_int_equal(m.seg.first, 10);
    assert_false(conn_buffered(&c)); /* half a packet: its rest comes through the socket */
    assert_int_equal(conn_read(&c, &err), 0);
    assert_int_equal(write(sv[1], wire + 50, 10), 10);
    struct pollfd p = {sv[0], POLLIN, 0};
    assert_int_equal(poll(&p, 1, 1000), 1); /* as a loop waits, after the recv that emptied the socket */
    assert_int_equal(conn_read(&c, &err), 1);
    assert_int_equal(msg_decode_compute(c.body, c.body_size, &m, &err), 0);
    assert_int_equal(m.seg.first, 20);
    assert_false(conn_buffered(&c));
    /* a header the limits refuse is ready at once, so that conn_read says why */
    uint32_t lie[2] = {PKT_DATA, 0xffffffffu};
    assert_int_equal(write(sv[1], lie, 8), 8);
    assert_int_equal(conn_read(&c, &err), 0); /* the last recv emptied the socket: no recv before a poll */
    assert_int_equal(poll(&p, 1, 1000), 1);
    assert_int_equal(conn_read(&c, &err), -1);
    assert_non_null(strstr(err.msg, "DATA packet claims 4294967295 bytes"));
    conn_close(&c);
    close(sv[1]);
}

/* A farm's discovery records as a resolver hands them over: a server's
 * announcement reads back; a missing or malformed proto= or records that
 * run past their data are refused. */
static void discovery_records_read(void **state)
{
    (void)state;
    static const uint8_t ok[] = "\x08proto=10\x0dsize=1024x768\x09token=yes";
    static const uint8_t no_proto[] = "\x08size=1x1";
    static const uint8_t bad_proto[] = "\x08proto=1o";
    static const uint8_t signed_proto[] = "\x08proto=+9";
    static const uint8_t past_end[] = "\x08proto=10\x20size";
    MdnsFarm m;
    assert_int_equal(mdns_txt_read(ok, sizeof ok - 1, &m), 10);
    assert_string_equal(m.size, "1024x768");
    assert_int_equal(m.token, 1);
    assert_int_equal(mdns_txt_read(no_proto, sizeof no_proto - 1, &m), -1);
    assert_string_equal(m.size, "1x1");
    assert_int_equal(mdns_txt_read(bad_proto, sizeof bad_proto - 1, &m), -1);
    assert_int_equal(mdns_txt_read(signed_proto, sizeof signed_proto - 1, &m), -1);
    assert_int_equal(mdns_txt_read(past_end, sizeof past_end - 1, &m), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(packets_round_trip),
        cmocka_unit_test(bodies_that_do_not_fit_are_refused),
        cmocka_unit_test(protocol_doc_matches_the_codec),
        cmocka_unit_test(reads_ahead_and_says_so),
        cmocka_unit_test(discovery_records_read),
    };
    return cmocka_run_group_tests_name("msg", tests, NULL, NULL);
}
