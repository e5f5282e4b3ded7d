/* net.c - see net.h. */
#include "net/net.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

int net_setup(int fd)
{
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one); /* fails harmlessly on a pipe */
    int fl = fcntl(fd, F_GETFL, 0);
    return fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0 ? -1 : 0;
}

static int sockaddr_is_loopback(const struct sockaddr *sa)
{
    if (sa->sa_family == AF_INET)
        return (ntohl(((const struct sockaddr_in *)sa)->sin_addr.s_addr) >> 24) == 127;
    if (sa->sa_family == AF_INET6) {
        const struct in6_addr *a = &((const struct sockaddr_in6 *)sa)->sin6_addr;
        return IN6_IS_ADDR_LOOPBACK(a) || (IN6_IS_ADDR_V4MAPPED(a) && a->s6_addr[12] == 127);
    }
    return 0;
}

/* "1.2.3.4:5" or "[::1]:5" */
static void sockaddr_text(const struct sockaddr *sa, char *buf, size_t size)
{
    char host[INET6_ADDRSTRLEN] = "?";
    int port = 0;
    if (sa->sa_family == AF_INET) {
        const struct sockaddr_in *s4 = (const struct sockaddr_in *)sa;
        inet_ntop(AF_INET, &s4->sin_addr, host, sizeof host);
        port = ntohs(s4->sin_port);
        snprintf(buf, size, "%s:%d", host, port);
    } else if (sa->sa_family == AF_INET6) {
        const struct sockaddr_in6 *s6 = (const struct sockaddr_in6 *)sa;
        inet_ntop(AF_INET6, &s6->sin6_addr, host, sizeof host);
        port = ntohs(s6->sin6_port);
        snprintf(buf, size, "[%s]:%d", host, port);
    } else {
        snprintf(buf, size, "?");
    }
}

static int resolve(const char *host, int port, int passive, struct addrinfo **out, Err *err)
{
    char ps[16];
    snprintf(ps, sizeof ps, "%d", port);
    struct addrinfo hints;
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = passive ? AI_PASSIVE : 0;
    int rc = getaddrinfo(host, ps, &hints, out);
    if (rc)
        return err_set(err, "cannot resolve '%s': %s", host, gai_strerror(rc));
    return 0;
}

int net_is_loopback(const char *addr)
{
    struct addrinfo *ai;
    if (resolve(addr, 0, 1, &ai, NULL))
        return 0;
    int all = 1;
    for (struct addrinfo *a = ai; a; a = a->ai_next)
        all &= sockaddr_is_loopback(a->ai_addr);
    freeaddrinfo(ai);
    return all;
}

int net_listen(const char *addr, int port, NetListener *out, Err *err)
{
    memset(out, 0, sizeof *out);
    out->fd = -1;
    struct addrinfo *ai;
    if (resolve(addr, port, 1, &ai, err))
        return -1;
    int saved = 0;
    for (struct addrinfo *a = ai; a && out->fd < 0; a = a->ai_next) {
        int fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol), one = 1;
        if (fd >= 0 && setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) == 0 &&
            bind(fd, a->ai_addr, a->ai_addrlen) == 0 && listen(fd, 128) == 0 && net_setup(fd) == 0) {
            out->fd = fd;
            break;
        }
        saved = errno;
        if (fd >= 0)
            close(fd);
    }
    freeaddrinfo(ai);
    if (out->fd < 0)
        return err_set(err, "cannot listen on %s port %d: %s", addr, port, strerror(saved));
    struct sockaddr_storage ss;
    socklen_t len = sizeof ss;
    getsockname(out->fd, (struct sockaddr *)&ss, &len);
    out->port = ss.ss_family == AF_INET6 ? ntohs(((struct sockaddr_in6 *)&ss)->sin6_port)
                                         : ntohs(((struct sockaddr_in *)&ss)->sin_port);
    sockaddr_text((struct sockaddr *)&ss, out->shown, sizeof out->shown);
    return 0;
}

int net_accept(int listen_fd, char *peer, size_t size)
{
    struct sockaddr_storage ss;
    socklen_t len = sizeof ss;
    int fd = accept(listen_fd, (struct sockaddr *)&ss, &len);
    if (fd < 0)
        return -1;
    sockaddr_text((struct sockaddr *)&ss, peer, size);
    if (net_setup(fd)) {
        close(fd);
        return -1;
    }
    return fd;
}

int net_dial(const char *host, int port, Err *err)
{
    struct addrinfo *ai;
    if (resolve(host, port, 0, &ai, err))
        return -1;
    int fd = -1, saved = 0;
    for (struct addrinfo *a = ai; a; a = a->ai_next) {
        fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (fd >= 0 && connect(fd, a->ai_addr, a->ai_addrlen) == 0)
            break;
        saved = errno;
        if (fd >= 0)
            close(fd);
        fd = -1;
    }
    freeaddrinfo(ai);
    if (fd < 0)
        return err_set(err, "cannot connect to %s port %d: %s", host, port, strerror(saved));
    if (net_setup(fd)) {
        close(fd);
        return err_set(err, "cannot set up the connection to %s: %s", host, strerror(errno));
    }
    return fd;
}
