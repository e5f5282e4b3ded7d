/* mdns.c - see mdns.h. */
#include "net/mdns.h"

#include <avahi-client/client.h>
#include <avahi-client/lookup.h>
#include <avahi-client/publish.h>
#include <avahi-common/alternative.h>
#include <avahi-common/error.h>
#include <avahi-common/malloc.h>
#include <avahi-common/simple-watch.h>
#include <avahi-common/thread-watch.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "net/msg.h"

struct MdnsAnnounce {
    AvahiThreadedPoll *poll;
    AvahiClient *client;
    AvahiEntryGroup *group;
    char *name;
    int port;
    char txt[3][48];
    char subtype[48];
};

static int no_daemon(int error, Err *err)
{
    return err_set(err, "mDNS: %s (is avahi-daemon running?)", avahi_strerror(error));
}

/* Registers the service in the group (again under another name where the
 * name was taken); called with the poll's lock held. */
static void publish(MdnsAnnounce *a, AvahiClient *c)
{
    if (!a->group && !(a->group = avahi_entry_group_new(c, NULL, NULL)))
        return;
    for (int tries = 0; tries < 8; tries++) {
        int r = avahi_entry_group_add_service(a->group, AVAHI_IF_UNSPEC, AVAHI_PROTO_UNSPEC, 0, a->name, MDNS_TYPE,
                                              NULL, NULL, (uint16_t)a->port, a->txt[0], a->txt[1], a->txt[2], NULL);
        if (r == AVAHI_ERR_COLLISION) {
            char *n = avahi_alternative_service_name(a->name);
            avahi_free(a->name);
            a->name = n;
            continue;
        }
        if (r >= 0)
            r = avahi_entry_group_add_service_subtype(a->group, AVAHI_IF_UNSPEC, AVAHI_PROTO_UNSPEC, 0, a->name,
                                                      MDNS_TYPE, NULL, a->subtype);
        if (r >= 0)
            avahi_entry_group_commit(a->group);
        return;
    }
}

static void on_client(AvahiClient *c, AvahiClientState state, void *ctx)
{
    MdnsAnnounce *a = ctx;
    if (state == AVAHI_CLIENT_S_RUNNING && (!a->group || avahi_entry_group_is_empty(a->group)))
        publish(a, c);
    else if (state == AVAHI_CLIENT_S_COLLISION || state == AVAHI_CLIENT_S_REGISTERING) {
        if (a->group)
            avahi_entry_group_reset(a->group);
    }
}

MdnsAnnounce *mdns_announce(int port, int width, int height, int token, Err *err)
{
    MdnsAnnounce *a = calloc(1, sizeof *a);
    if (!a || !(a->poll = avahi_threaded_poll_new())) {
        free(a);
        err_set(err, "mDNS: out of memory");
        return NULL;
    }
    char host[256] = "this machine";
    FILE *f = fopen("/proc/sys/kernel/hostname", "r");
    if (f) {
        if (fgets(host, sizeof host, f))
            host[strcspn(host, "\n")] = 0;
        fclose(f);
    }
    char name[300];
    snprintf(name, sizeof name, "lanray on %.60s", host);
    a->name = avahi_strdup(name);
    a->port = port;
    snprintf(a->txt[0], sizeof a->txt[0], "proto=%u", PROTO_VERSION);
    snprintf(a->txt[1], sizeof a->txt[1], "size=%dx%d", width, height);
    snprintf(a->txt[2], sizeof a->txt[2], "token=%s", token ? "yes" : "no");
    snprintf(a->subtype, sizeof a->subtype, "_v%u._sub." MDNS_TYPE, PROTO_VERSION);
    int error = 0;
    avahi_threaded_poll_lock(a->poll);
    a->client = avahi_client_new(avahi_threaded_poll_get(a->poll), 0, on_client, a, &error);
    avahi_threaded_poll_unlock(a->poll);
    if (!a->client || avahi_threaded_poll_start(a->poll) < 0) {
        no_daemon(a->client ? AVAHI_ERR_FAILURE : error, err);
        mdns_withdraw(a);
        return NULL;
    }
    return a;
}

void mdns_withdraw(MdnsAnnounce *a)
{
    if (!a)
        return;
    avahi_threaded_poll_stop(a->poll);
    if (a->client)
        avahi_client_free(a->client); /* frees the group too */
    avahi_threaded_poll_free(a->poll);
    avahi_free(a->name);
    free(a);
}

typedef struct {
    AvahiClient *client;
    MdnsFarm *out;
    int max, n;
} Find;

static void txt_value(AvahiStringList *txt, const char *key, char *out, size_t size)
{
    AvahiStringList *t = avahi_string_list_find(txt, key);
    char *k = NULL, *v = NULL;
    out[0] = 0;
    if (t && avahi_string_list_get_pair(t, &k, &v, NULL) == 0 && v)
        snprintf(out, size, "%s", v);
    avahi_free(k);
    avahi_free(v);
}

/* A farm's TXT records into m (size, token): its protocol version, or -1
 * where proto= is missing or not a plain decimal number. */
static long farm_read(AvahiStringList *txt, MdnsFarm *m)
{
    char proto_v[16], tok[8];
    txt_value(txt, "proto", proto_v, sizeof proto_v);
    txt_value(txt, "size", m->size, sizeof m->size);
    txt_value(txt, "token", tok, sizeof tok);
    m->token = strcmp(tok, "yes") == 0;
    long v = 0;
    if (!proto_v[0] || strlen(proto_v) > 9)
        return -1;
    for (const char *p = proto_v; *p; p++) {
        if (*p < '0' || *p > '9')
            return -1;
        v = v * 10 + (*p - '0');
    }
    return v;
}

long mdns_txt_read(const uint8_t *rdata, size_t len, MdnsFarm *m)
{
    AvahiStringList *txt = NULL;
    memset(m, 0, sizeof *m);
    if (avahi_string_list_parse(rdata, len, &txt) < 0)
        return -1;
    long v = farm_read(txt, m);
    avahi_string_list_free(txt);
    return v;
}

static void on_resolved(AvahiServiceResolver *r, AvahiIfIndex iface, AvahiProtocol proto, AvahiResolverEvent event,
                        const char *name, const char *type, const char *domain, const char *host,
                        const AvahiAddress *addr, uint16_t port, AvahiStringList *txt, AvahiLookupResultFlags flags,
                        void *ctx)
{
    (void)iface, (void)proto, (void)type, (void)domain, (void)host, (void)flags;
    Find *f = ctx;
    if (event == AVAHI_RESOLVER_FOUND && f->n < f->max) {
        MdnsFarm m;
        memset(&m, 0, sizeof m);
        const long version = farm_read(txt, &m);
        /* one farm once: by name (a service seen on several interfaces),
         * and by address and port (the server's own announcement beside a
         * static Avahi service file for it) */
        char at[256];
        avahi_address_snprint(at, sizeof at, addr);
        int dup = 0;
        for (int i = 0; i < f->n; i++)
            dup |= strcmp(f->out[i].name, name) == 0 || (strcmp(f->out[i].host, at) == 0 && f->out[i].port == port);
        if (!dup && version == PROTO_VERSION) { /* the subtype said so; the record agrees */
            snprintf(m.name, sizeof m.name, "%s", name);
            avahi_address_snprint(m.host, sizeof m.host, addr);
            m.port = port;
            f->out[f->n++] = m;
        }
    }
    avahi_service_resolver_free(r);
}

static void on_browsed(AvahiServiceBrowser *b, AvahiIfIndex iface, AvahiProtocol proto, AvahiBrowserEvent event,
                       const char *name, const char *type, const char *domain, AvahiLookupResultFlags flags, void *ctx)
{
    (void)b, (void)flags, (void)type; /* the service's own type, not the subtype browsed, names it for the resolver */
    Find *f = ctx;
    if (event == AVAHI_BROWSER_NEW)
        avahi_service_resolver_new(f->client, iface, proto, name, MDNS_TYPE, domain, AVAHI_PROTO_INET, 0, on_resolved, f);
}

int mdns_find(double seconds, MdnsFarm *out, int max, Err *err)
{
    AvahiSimplePoll *poll = avahi_simple_poll_new();
    if (!poll)
        return err_set(err, "mDNS: out of memory");
    int error = 0;
    Find f = {.out = out, .max = max};
    f.client = avahi_client_new(avahi_simple_poll_get(poll), 0, NULL, NULL, &error);
    if (!f.client) {
        avahi_simple_poll_free(poll);
        return no_daemon(error, err);
    }
    char subtype[48];
    snprintf(subtype, sizeof subtype, "_v%u._sub." MDNS_TYPE, PROTO_VERSION);
    AvahiServiceBrowser *b =
        avahi_service_browser_new(f.client, AVAHI_IF_UNSPEC, AVAHI_PROTO_UNSPEC, subtype, NULL, 0, on_browsed, &f);
    struct timespec t0, t;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        clock_gettime(CLOCK_MONOTONIC, &t);
        double left = seconds - ((double)(t.tv_sec - t0.tv_sec) + (double)(t.tv_nsec - t0.tv_nsec) * 1e-9);
        if (left <= 0 || !b)
            break;
        if (avahi_simple_poll_iterate(poll, (int)(left * 1000) + 1) != 0)
            break;
    }
    if (b)
        avahi_service_browser_free(b);
    avahi_client_free(f.client);
    avahi_simple_poll_free(poll);
    return f.n;
}
