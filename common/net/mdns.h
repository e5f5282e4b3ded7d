/* mdns.h - the farm on the LAN by DNS-SD over mDNS, through the Avahi
 * daemon (libavahi-client): the server announces itself as a _lanray._tcp
 * service with its protocol version as a subtype (_vN._sub._lanray._tcp)
 * and TXT records (proto, the frame size, whether a token is needed); a
 * client with no address browses that subtype only, so that it sees the
 * farms it can work with.  Without a daemon both sides say so and go on
 * with addresses as given. */
#ifndef LANRAY_MDNS_H
#define LANRAY_MDNS_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"

#define MDNS_TYPE "_lanray._tcp"

typedef struct MdnsAnnounce MdnsAnnounce;

/* Announces a server on `port` (name: "lanray on HOST", made unique by
 * Avahi where taken), held until mdns_withdraw; NULL with the reason in
 * err where there is no daemon or it refused. */
MdnsAnnounce *mdns_announce(int port, int width, int height, int token, Err *err);
void mdns_withdraw(MdnsAnnounce *a);

typedef struct {
    char name[64];     /* the service's name */
    char host[256];    /* the address to connect to (numeric) */
    int port;
    char size[32];     /* its TXT size=, or "" */
    int token;         /* its TXT token=yes */
} MdnsFarm;

/* A farm's TXT records as they come on the wire (length-prefixed strings,
 * RFC 6763) into m's size and token: the protocol version it says
 * (proto=), or -1 where the records do not parse or say none. */
long mdns_txt_read(const uint8_t *rdata, size_t len, MdnsFarm *m);

/* The farms of this protocol version seen within `seconds`, resolved: how
 * many (at most max into out), or -1 with the reason in err (no daemon). */
int mdns_find(double seconds, MdnsFarm *out, int max, Err *err);

#endif
