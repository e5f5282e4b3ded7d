/* lanray-client - renders segments for a lanray-server (options: --help).
 *
 * The token may also come from LANRAY_TOKEN.  Reconnects with backoff when
 * the server goes away (unless --once). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/cli.h"
#include "client.h"
#include "base/log.h"
#include "base/opt.h"
#include "net/mdns.h"
#include "net/msg.h"

static volatile sig_atomic_t stop_flag;
static void on_stop(int sig) { (void)sig; stop_flag = 1; }

/* HOST, HOST:PORT, an IPv6 address alone or [ADDRESS]:PORT. */
static int split_host(const char *arg, char *host, size_t size, int *port, Err *err)
{
    const char *colon = strrchr(arg, ':');
    const char *h = arg;
    size_t len = strlen(arg);
    if (arg[0] == '[') {
        const char *close = strchr(arg, ']');
        if (!close || (close[1] && close[1] != ':'))
            return err_set(err, "bad address '%s' (an IPv6 address with a port is written [ADDRESS]:PORT)", arg);
        h = arg + 1;
        len = (size_t)(close - h);
        colon = close[1] ? close + 1 : NULL;
    } else if (colon && strchr(arg, ':') != colon) {
        colon = NULL; /* an IPv6 address without a port */
    } else if (colon) {
        len = (size_t)(colon - arg);
    }
    if (len == 0 || len >= size)
        return err_set(err, "bad host in '%s'", arg);
    memcpy(host, h, len);
    host[len] = 0;
    if (colon) {
        char *end;
        long p = strtol(colon + 1, &end, 10);
        if (end == colon + 1 || *end || p < 1 || p > 65535)
            return err_set(err, "bad port in '%s' (1..65535)", arg);
        *port = (int)p;
    }
    return 0;
}

/* No address given: the one farm of this protocol version that mDNS shows
 * on the LAN (1.5 s of looking), into host and port; with none or several,
 * -1 and the reason (the farms listed). */
static int find_server(char *host, size_t size, int *port, Err *err)
{
    MdnsFarm farms[16];
    int n = mdns_find(1.5, farms, 16, err);
    if (n < 0) {
        char why[sizeof err->msg];
        memcpy(why, err->msg, sizeof why); /* err_set writes where it would read */
        return err_set(err, "no address given, and no way to look for one: %s; give HOST[:PORT]", why);
    }
    if (n == 0)
        return err_set(err, "no address given, and no lanray-server of protocol %u announced on the LAN (mDNS); give "
                       "HOST[:PORT]", PROTO_VERSION);
    if (n > 1) {
        fprintf(stderr, "lanray-client: %d farms on the LAN:\n", n);
        for (int i = 0; i < n; i++)
            fprintf(stderr, "  %s:%d  %s  (%s%s)\n", farms[i].host, farms[i].port, farms[i].name, farms[i].size,
                    farms[i].token ? ", token needed" : "");
        return err_set(err, "%d farms on the LAN: give the address of one", n);
    }
    snprintf(host, size, "%s", farms[0].host);
    *port = farms[0].port;
    fprintf(stderr, "lanray-client: found %s at %s:%d (mDNS)\n", farms[0].name, host, *port);
    return 0;
}

int main(int argc, char **argv)
{
    ClientConfig cfg = {NULL, PROTO_DEFAULT_PORT, 0, getenv("LANRAY_TOKEN"), 0, 1};
    int once = 0, simd_given = 0;
    const Opt opts[] = {
        {.name = "--simd", .kind = OPT_CUSTOM, .parse = cli_parse_simd, .arg = "PATH", .range = CLI_SIMD_RANGE,
         .seen = &simd_given, .help = "traversal path (every path gives the same pixels)", .def = CLI_SIMD_DEFAULT},
        {.name = "--threads", .kind = OPT_INT, .dst = &cfg.threads, .arg = "T", .lo = 0, .hi = 1024,
         .help = "render threads, 0 = one per core", .def = "0: all cores"},
        {.name = "--token", .kind = OPT_STRING, .dst = &cfg.token, .arg = "T",
         .help = "the server's token (or LANRAY_TOKEN in the environment)", .def = "none"},
        {.name = "--once", .kind = OPT_FLAG, .dst = &once,
         .help = "end when the session ends instead of reconnecting; fail if no session starts"},
        {.name = "--quiet", .kind = OPT_FLAG, .dst = &cfg.quiet, .help = "print errors only"},
        {0},
    };
    const char *args[1] = {NULL};
    OptSpec spec = {.prog = "lanray-client", .synopsis = "[HOST[:PORT]] [options]",
                    .about = "Renders line segments for a lanray-server.  HOST is a name or an address (IPv6: [ADDRESS]:PORT);\n"
                    "the port defaults to 7878.  Without HOST it looks on the LAN for a server of its protocol version\n"
                    "(DNS-SD over mDNS, through avahi-daemon) and takes it, or lists them where there are several.\n"
                    "Without --once it reconnects (0.1 s doubling to 5 s) when the server goes away or is not there yet.",
                    .opts = opts, .args = args, .min_args = 0, .max_args = 1,
                    .exits = "  0  the session ended (the server finished or said goodbye), or SIGINT/SIGTERM\n"
                    "  1  the server refused this client (token, version, precision), or with --once no session started\n"
                    "  2  bad command line\n"};
    int go = opt_run(&spec, argc, argv);
    if (go != OPT_GO)
        return go;
    static char host[256];
    Err err = {{0}};
    if (!simd_given && cli_simd_env(&err)) {
        fprintf(stderr, "lanray-client: %s\n", err.msg);
        return 2;
    }
    if (args[0] ? split_host(args[0], host, sizeof host, &cfg.port, &err) : find_server(host, sizeof host, &cfg.port, &err)) {
        fprintf(stderr, "lanray-client: %s\n", err.msg);
        return args[0] ? 2 : 1;
    }
    cfg.host = host;
    cfg.reconnect = !once;
    if (cfg.threads == 0)
        cfg.threads = sysconf(_SC_NPROCESSORS_ONLN) > 0 ? (int)sysconf(_SC_NPROCESSORS_ONLN) : 1;
    if (cfg.token && !*cfg.token)
        cfg.token = NULL;
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGPIPE, SIG_IGN);
    ClientStats st;
    int rc = client_run(&cfg, &stop_flag, &st, &err);
    /* the reason first; what was done after it, when anything was */
    if (rc)
        fprintf(stderr, "lanray-client: %s\n", err.msg);
    if (st.sessions)
        log_line(cfg.quiet, "lanray-client", "rendered %llu segments, %llu pixels; %llu scenes decoded, %llu top-level trees built",
                 (unsigned long long)st.segments, (unsigned long long)st.pixels, (unsigned long long)st.scenes,
                 (unsigned long long)st.trees);
    return rc ? 1 : 0;
}
