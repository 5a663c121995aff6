/* gale-ctl: one kiosk command from a script (exhibit scripts, tests): connects to
 * gale-server as a kiosk with the token, sends one wind command (PROTOCOL.md "wind":
 * dial, release, scenario, replay) and reports whether the server took it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_net.h"
#include "mono.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: gale-ctl --url ws://HOST:PORT [--token-file F | --token T] COMMAND\n"
            "commands:\n"
            "  wind [--speed M/S] [--dir DEG]   hold a 1-minute sustained wind (0..90 m/s)\n"
            "                                   and/or the direction it comes FROM\n"
            "                                   (degrees clockwise from north)\n"
            "  release                          drop the dial: the scenario's wind resumes\n"
            "  scenario NAME                    restart the server's scenario (NAME as it is\n"
            "                                   called, e.g. andrew1992; \"\" = release)\n"
            "  replay [--at landfall|MIN] [--speed X]\n"
            "                                   jump a storm replay to landfall (storm minute\n"
            "                                   0) or minute MIN, and/or run it X times real time\n"
            "options:\n"
            "  --url ws://HOST:PORT  the server (required)\n"
            "  --token-file F        the kiosk token: the file's first line\n"
            "  --token T             the kiosk token (else $GALE_KIOSK_TOKEN)\n"
            "  --wait S              seconds to wait for the server (default 10)\n"
            "Exit status: 0 the server took the command, 1 it refused it or could not be\n"
            "reached, 2 bad arguments.\n");
}

/* The first line of path into out[cap]; 0 or -1 with a message. */
static int read_token(const char *path, char *out, size_t cap)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "gale-ctl: --token-file %s: cannot open\n", path);
        return -1;
    }
    if (!fgets(out, (int)cap, f)) {
        out[0] = '\0';
    }
    fclose(f);
    out[strcspn(out, "\r\n")] = '\0';
    if (!out[0]) {
        fprintf(stderr, "gale-ctl: --token-file %s: the first line is empty\n", path);
        return -1;
    }
    return 0;
}

static int number(const char *opt, const char *v, double lo, double hi, float *out)
{
    char *end;
    double x = v ? strtod(v, &end) : (double)NAN;
    if (!v || *end || end == v || !(x >= lo && x <= hi)) {
        fprintf(stderr, "gale-ctl: %s: expected a number in [%g, %g], got \"%s\"\n", opt, lo, hi,
                v ? v : "");
        return -1;
    }
    *out = (float)x;
    return 0;
}

/* The command words after the options into *w; 0 or -1 with a message. */
static int parse_command(int argc, char **argv, int i, ctl_wind *w)
{
    if (i >= argc) {
        fprintf(stderr, "gale-ctl: expected a command: wind, release, scenario or replay\n");
        return -1;
    }
    const char *cmd = argv[i++];
    if (!strcmp(cmd, "release")) {
        w->release = true;
    } else if (!strcmp(cmd, "scenario")) {
        if (i >= argc || strlen(argv[i]) >= sizeof w->scenario) {
            fprintf(stderr, "gale-ctl: scenario: expected a NAME under %zu bytes\n",
                    sizeof w->scenario);
            return -1;
        }
        w->has_scenario = true;
        snprintf(w->scenario, sizeof w->scenario, "%s", argv[i++]);
    } else if (!strcmp(cmd, "wind") || !strcmp(cmd, "replay")) {
        bool wind = !strcmp(cmd, "wind");
        for (; i < argc; i += 2) {
            const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
            float x;
            if (wind && !strcmp(o, "--speed")) {
                if (number(o, v, 0, 90, &w->speed_ms)) {
                    return -1;
                }
                w->has_speed = true;
            } else if (wind && !strcmp(o, "--dir")) {
                if (number(o, v, 0, 360, &x)) {
                    return -1;
                }
                /* from, clockwise from north → the wire's toward, from +x counter-clockwise */
                w->dir_deg = (float)fmod(270.0 - (double)x + 720.0, 360.0);
                w->has_dir = true;
            } else if (!wind && !strcmp(o, "--at")) {
                if (v && !strcmp(v, "landfall")) {
                    w->replay_at_min = 0.0f; /* the track's reference row is landfall */
                } else if (number(o, v, -1e5, 1e5, &w->replay_at_min)) {
                    return -1;
                }
                w->has_replay_at = true;
            } else if (!wind && !strcmp(o, "--speed")) {
                if (number(o, v, 1, 10000, &w->replay_speed)) {
                    return -1;
                }
                w->has_replay_speed = true;
            } else {
                fprintf(stderr, "gale-ctl: %s: unknown option \"%s\" (see --help)\n", cmd, o);
                return -1;
            }
        }
        if (wind ? !w->has_speed && !w->has_dir : !w->has_replay_at && !w->has_replay_speed) {
            fprintf(stderr, "gale-ctl: %s: expected %s\n", cmd,
                    wind ? "--speed and/or --dir" : "--at and/or --speed");
            return -1;
        }
    } else {
        fprintf(stderr, "gale-ctl: unknown command \"%s\" (see --help)\n", cmd);
        return -1;
    }
    if (i < argc) {
        fprintf(stderr, "gale-ctl: unexpected \"%s\" after the command\n", argv[i]);
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *url = NULL, *token = getenv("GALE_KIOSK_TOKEN");
    char token_buf[CTL_MAX_TOKEN];
    double wait_s = 10.0;
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i += 2) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            usage(stdout);
            return 0;
        }
        if (!v) {
            fprintf(stderr, "gale-ctl: %s: expected a value\n", o);
            return 2;
        }
        if (!strcmp(o, "--url")) {
            url = v;
        } else if (!strcmp(o, "--token")) {
            token = v;
        } else if (!strcmp(o, "--token-file")) {
            if (read_token(v, token_buf, sizeof token_buf)) {
                return 2;
            }
            token = token_buf;
        } else if (!strcmp(o, "--wait")) {
            wait_s = atof(v);
            if (!(wait_s > 0.0 && wait_s <= 3600.0)) {
                fprintf(stderr, "gale-ctl: --wait: expected seconds in (0, 3600], got \"%s\"\n", v);
                return 2;
            }
        } else {
            fprintf(stderr, "gale-ctl: unknown option \"%s\" (see --help)\n", o);
            return 2;
        }
    }
    ctl_wind w;
    memset(&w, 0, sizeof w);
    if (!url) {
        fprintf(stderr, "gale-ctl: --url ws://HOST:PORT is required (see --help)\n");
        return 2;
    }
    if (!token || !token[0]) {
        fprintf(stderr, "gale-ctl: a kiosk token is required (--token-file F, --token T or "
                        "$GALE_KIOSK_TOKEN)\n");
        return 2;
    }
    if (parse_command(argc, argv, i, &w)) {
        return 2;
    }
    snprintf(w.token, sizeof w.token, "%s", token);
    w.keep = w.has_speed || w.has_dir; /* the dial stays after gale-ctl hangs up */
    gale_err err = { 0 };
    cli_net *n = cli_net_create(&(cli_net_desc){ .url = url, .role = CTL_ROLE_KIOSK, .token = token },
                                NULL, &err);
    if (!n) {
        fprintf(stderr, "gale-ctl: %s\n", err.msg);
        return err.code == GALE_E_ARG ? 2 : 1;
    }
    int status = 1;
    const double until = mono_s() + wait_s;
    cli_net_stats st = cli_net_get_stats(n);
    while (mono_s() < until && st.state != CLI_NET_LIVE && st.state != CLI_NET_REFUSED) {
        cli_net_poll(n, mono_s());
        usleep(2000);
        st = cli_net_get_stats(n);
    }
    if (st.state != CLI_NET_LIVE) {
        fprintf(stderr, "gale-ctl: %s: %s\n", cli_net_server_name(n),
                st.last_error[0] ? st.last_error : "no welcome in time");
        goto done;
    }
    if (cli_net_send_wind(n, &w, &err)) {
        fprintf(stderr, "gale-ctl: %s\n", err.msg);
        goto done;
    }
    /* a refusal is an error message and a close; none within a short while: taken */
    const double settle = mono_s() + 0.5;
    uint32_t connects = st.connects;
    while (mono_s() < settle) {
        cli_net_poll(n, mono_s());
        usleep(2000);
        st = cli_net_get_stats(n);
        if (st.state != CLI_NET_LIVE || st.connects != connects) {
            break;
        }
    }
    if (st.state != CLI_NET_LIVE) {
        fprintf(stderr, "gale-ctl: %s refused the command: %s\n", cli_net_server_name(n),
                st.last_error[0] ? st.last_error : "connection closed");
        goto done;
    }
    printf("gale-ctl: %s took the command\n", cli_net_server_name(n));
    status = 0;
done:
    cli_net_destroy(n);
    return status;
}
