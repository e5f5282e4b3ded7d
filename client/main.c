/* lanray-client - renders segments for a lanray-server.
 *
 *   lanray-client HOST[:PORT] [--threads T] [--token T] [--once] [--quiet]
 *
 * The token may also come from LANRAY_TOKEN.  Reconnects with backoff when
 * the server goes away (unless --once); exits 1 when the server refuses it. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "client.h"
#include "proto.h"

static volatile sig_atomic_t stop_flag;
static void on_stop(int sig) { (void)sig; stop_flag = 1; }

int main(int argc, char **argv)
{
    ClientConfig cfg = {NULL, PROTO_DEFAULT_PORT, (int)sysconf(_SC_NPROCESSORS_ONLN), getenv("LANRAY_TOKEN"), 0, 1};
    if (cfg.threads < 1)
        cfg.threads = 1;
    if (cfg.token && !*cfg.token)
        cfg.token = NULL;
    static char host[256];
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--threads") == 0 && i + 1 < argc) {
            char *end;
            long t = strtol(argv[++i], &end, 10);
            if (*end || t < 1 || t > 1024) {
                fprintf(stderr, "lanray-client: --threads wants 1..1024\n");
                return 2;
            }
            cfg.threads = (int)t;
        } else if (strcmp(a, "--token") == 0 && i + 1 < argc) {
            cfg.token = argv[++i];
        } else if (strcmp(a, "--once") == 0) {
            cfg.reconnect = 0;
        } else if (strcmp(a, "--quiet") == 0) {
            cfg.quiet = 1;
        } else if (a[0] != '-' && !cfg.host) {
            snprintf(host, sizeof host, "%s", a);
            char *colon = strrchr(host, ':');
            if (colon) {
                *colon = 0;
                char *end;
                long p = strtol(colon + 1, &end, 10);
                if (*end || p < 1 || p > 65535) {
                    fprintf(stderr, "lanray-client: bad port in '%s'\n", a);
                    return 2;
                }
                cfg.port = (int)p;
            }
            cfg.host = host;
        } else {
            fprintf(stderr, "usage: lanray-client HOST[:PORT] [--threads T] [--token T] [--once] [--quiet]\n");
            return 2;
        }
    }
    if (!cfg.host) {
        fprintf(stderr, "usage: lanray-client HOST[:PORT] [--threads T] [--token T] [--once] [--quiet]\n");
        return 2;
    }
    signal(SIGINT, on_stop);
    signal(SIGTERM, on_stop);
    signal(SIGPIPE, SIG_IGN);
    Err err = {{0}};
    if (client_run(&cfg, &stop_flag, &err)) {
        fprintf(stderr, "lanray-client: %s\n", err.msg);
        return 1;
    }
    return 0;
}
