/* fuzz_mdns.c - a farm's discovery records (mdns_txt_read) on arbitrary
 * bytes: TXT record data as a resolver hands it over (length-prefixed
 * strings).  What it reads must be terminated strings within their fields;
 * the records it reads, written again by Avahi, must read the same. */
#include <assert.h>
#include <avahi-common/strlst.h>
#include <string.h>

#include "fuzz.h"
#include "net/mdns.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    MdnsFarm m;
    long v = mdns_txt_read(data, size, &m);
    assert(memchr(m.size, 0, sizeof m.size) && memchr(m.name, 0, sizeof m.name) && memchr(m.host, 0, sizeof m.host));
    assert(v >= -1 && v <= 999999999);
    if (v < 0)
        return 0;
    /* what was read, written as a server announces it, read back */
    AvahiStringList *l = NULL; /* the empty list */
    l = avahi_string_list_add_printf(l, "proto=%ld", v);
    l = avahi_string_list_add_printf(l, "size=%s", m.size);
    l = avahi_string_list_add_printf(l, "token=%s", m.token ? "yes" : "no");
    uint8_t buf[512];
    size_t n = avahi_string_list_serialize(l, buf, sizeof buf);
    avahi_string_list_free(l);
    MdnsFarm back;
    assert(mdns_txt_read(buf, n, &back) == v);
    assert(strcmp(back.size, m.size) == 0 && back.token == m.token);
    return 0;
}
