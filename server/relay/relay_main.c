/* gale-relay: arguments, signals, run (relay.h). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "relay.h"
#include "svc_notify.h"

static relay *g_relay;

static void on_signal(int sig)
{
    (void)sig;
    if (g_relay) {
        relay_stop(g_relay);
    }
}

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-relay --nats URL --port N [--iface ADDR] [--wait S]\n"
               "  --nats URL    the NATS server(s) gale-server publishes on (nats://HOST:PORT,\n"
               "                comma-separated for a cluster)\n"
               "  --port N      WebSocket/HTTP port for clients, 0 for any free one\n"
               "  --iface ADDR  listen address (default 127.0.0.1; all or 0.0.0.0: every\n"
               "                interface)\n"
               "  --wait S      seconds to wait at start for gale-server on NATS (default 30)\n"
               "Clients see exactly gale-server's protocol (protocol/PROTOCOL.md); the relay\n"
               "selects their views itself with the server's rule, and every other control\n"
               "message goes to the server over NATS, which checks tokens and answers.\n");
}

int main(int argc, char **argv)
{
    relay_desc d = { .port = -2, .iface = "127.0.0.1" };
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--nats") && v) {
            d.nats_url = v;
            i++;
        } else if (!strcmp(a, "--port") && v) {
            char *end;
            long p = strtol(v, &end, 10);
            if (*end || end == v || p < 0 || p > 65535) {
                fprintf(stderr, "gale-relay: --port: expected 0..65535, got \"%s\"\n", v);
                return 2;
            }
            d.port = p ? (int)p : -1;
            i++;
        } else if (!strcmp(a, "--iface") && v) {
            d.iface = !strcmp(v, "all") || !strcmp(v, "0.0.0.0") ? NULL : v;
            i++;
        } else if (!strcmp(a, "--wait") && v) {
            char *end;
            d.wait_s = strtod(v, &end);
            if (*end || end == v || !(d.wait_s >= 0.1 && d.wait_s <= 3600)) {
                fprintf(stderr, "gale-relay: --wait: expected seconds in [0.1, 3600], got \"%s\"\n",
                        v);
                return 2;
            }
            i++;
        } else {
            fprintf(stderr, "gale-relay: unknown or incomplete argument \"%s\"\n", a);
            usage(stderr);
            return 2;
        }
    }
    if (!d.nats_url || d.port == -2) {
        fprintf(stderr, "gale-relay: --nats and --port are required\n");
        usage(stderr);
        return 2;
    }
    signal(SIGPIPE, SIG_IGN);
    gale_err err;
    relay *r = relay_create(&d, &err);
    if (!r) {
        fprintf(stderr, "gale-relay: %s\n", err.msg);
        return 1;
    }
    g_relay = r;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    fprintf(stderr, "gale-relay: relaying NATS %s to %s port %d\n", d.nats_url,
            d.iface ? d.iface : "every interface,", relay_port(r));
    printf("gale-relay: listening on port %d\n", relay_port(r));
    fflush(stdout);
    char status_line[160];
    snprintf(status_line, sizeof status_line, "READY=1\nSTATUS=relaying NATS %s, port %d",
             d.nats_url, relay_port(r));
    svc_notify(status_line);
    int rc = relay_run(r);
    svc_notify("STOPPING=1\nSTATUS=stopping");
    g_relay = NULL;
    relay_destroy(r);
    return rc ? 1 : 0;
}
