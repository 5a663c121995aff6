/* gale-ctl: one kiosk command from a script (exhibit scripts, tests): connects to
 * gale-server as a kiosk with the token, sends one command (PROTOCOL.md "wind": dial,
 * release, scenario, replay; "reset") and reports whether the server took it; or prints
 * the scenarios the server offers (its welcome's list). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_net.h"
#include "mono.h"
#include "token_file.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: gale-ctl --url ws://HOST:PORT [--token-file F | --token T] COMMAND\n"
            "commands:\n"
            "  wind [--speed M/S] [--dir DEG]   hold a 1-minute sustained wind (0..90 m/s)\n"
            "                                   and/or the direction it comes FROM\n"
            "                                   (degrees clockwise from north)\n"
            "  release                          drop the dial: the scenario's wind resumes\n"
            "  scenario NAME                    run the server's scenario NAME from its start\n"
            "                                   (one of `gale-ctl scenarios`, e.g. andrew1992;\n"
            "                                   \"\" = back to the scene's playlist)\n"
            "  replay [--at landfall|MIN] [--speed X] [--pause | --play]\n"
            "                                   jump a storm replay to landfall (storm minute\n"
            "                                   0) or minute MIN, run it X times real time,\n"
            "                                   hold its storm clock or run it again\n"
            "  reset                            heal the forest, drop the dial, back to the\n"
            "                                   playlist's first scenario from its start\n"
            "  scenarios                        print the scenarios the server offers, one a\n"
            "                                   line: name, kind, mean wind [m/s], title\n"
            "                                   (needs no token)\n"
            "options:\n"
            "  --url ws://HOST:PORT  the server (required)\n"
            "  --token-file F        the kiosk token: the file's first line\n"
            "  --token T             the kiosk token (else $GALE_KIOSK_TOKEN)\n"
            "  --wait S              seconds to wait for the server (default 10)\n"
            "Exit status: 0 the server took the command, 1 it refused it or could not be\n"
            "reached, 2 bad arguments.\n");
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

enum ctl_cmd { CMD_WIND, CMD_RESET, CMD_SCENARIOS };

/* The command words after the options into *w (wind commands) and *cmd; 0 or -1 with a
 * message. */
static int parse_command(int argc, char **argv, int i, ctl_wind *w, int *cmd)
{
    if (i >= argc) {
        fprintf(stderr, "gale-ctl: expected a command: wind, release, scenario, replay, reset "
                        "or scenarios\n");
        return -1;
    }
    const char *cmd_word = argv[i++];
    *cmd = CMD_WIND;
    if (!strcmp(cmd_word, "release")) {
        w->release = true;
    } else if (!strcmp(cmd_word, "reset")) {
        *cmd = CMD_RESET;
    } else if (!strcmp(cmd_word, "scenarios")) {
        *cmd = CMD_SCENARIOS;
    } else if (!strcmp(cmd_word, "scenario")) {
        if (i >= argc || strlen(argv[i]) >= sizeof w->scenario) {
            fprintf(stderr, "gale-ctl: scenario: expected a NAME under %zu bytes\n",
                    sizeof w->scenario);
            return -1;
        }
        w->has_scenario = true;
        snprintf(w->scenario, sizeof w->scenario, "%s", argv[i++]);
    } else if (!strcmp(cmd_word, "wind") || !strcmp(cmd_word, "replay")) {
        bool wind = !strcmp(cmd_word, "wind");
        while (i < argc) {
            const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
            float x;
            i += 2; /* an option and its value; the flags below take one word back */
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
            } else if (!wind && (!strcmp(o, "--pause") || !strcmp(o, "--play"))) {
                if (w->has_replay_paused) {
                    fprintf(stderr, "gale-ctl: replay: expected one of --pause and --play\n");
                    return -1;
                }
                w->has_replay_paused = true;
                w->replay_paused = !strcmp(o, "--pause");
                i--;
            } else {
                fprintf(stderr, "gale-ctl: %s: unknown option \"%s\" (see --help)\n", cmd_word,
                        o);
                return -1;
            }
        }
        if (wind ? !w->has_speed && !w->has_dir
                 : !w->has_replay_at && !w->has_replay_speed && !w->has_replay_paused) {
            fprintf(stderr, "gale-ctl: %s: expected %s\n", cmd_word,
                    wind ? "--speed and/or --dir" : "--at, --speed, --pause or --play");
            return -1;
        }
    } else {
        fprintf(stderr, "gale-ctl: unknown command \"%s\" (see --help)\n", cmd_word);
        return -1;
    }
    if (i < argc) {
        fprintf(stderr, "gale-ctl: unexpected \"%s\" after the command\n", argv[i]);
        return -1;
    }
    return 0;
}

/* What gale-ctl keeps of the welcome (cli_net's on_welcome): the scenario list, printed
 * for `scenarios`, and its names for a refused `scenario NAME`. */
typedef struct ctl_seen {
    bool print;      /* print the list (the scenarios command) */
    bool welcomed;
    char names[2300]; /* comma-separated: at most 32 names of 63 bytes */
} ctl_seen;

static void on_welcome(void *user, const ctl_welcome *w)
{
    ctl_seen *seen = user;
    if (seen->welcomed) {
        return;
    }
    seen->welcomed = true;
    size_t at = 0;
    for (uint32_t k = 0; k < w->n_scenarios; k++) {
        const ctl_scenario_info *c = &w->scenarios[k];
        if (seen->print) {
            printf("%s\t%s\t%.1f\t%s\n", c->name,
                   c->kind == CTL_SCENARIO_REPLAY ? "replay" : "steady", (double)c->sustained_ms,
                   c->title);
        }
        int n = snprintf(seen->names + at, sizeof seen->names - at, "%s%s", k ? ", " : "",
                         c->name);
        if (n > 0 && (size_t)n < sizeof seen->names - at) {
            at += (size_t)n;
        }
    }
    fflush(stdout);
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
            if (token_file_read("gale-ctl", v, token_buf, sizeof token_buf)) {
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
    int cmd = CMD_WIND;
    if (!url) {
        fprintf(stderr, "gale-ctl: --url ws://HOST:PORT is required (see --help)\n");
        return 2;
    }
    if (parse_command(argc, argv, i, &w, &cmd)) {
        return 2;
    }
    /* the list is in every welcome: without a token it is read as a viewer */
    const bool kiosk = cmd != CMD_SCENARIOS || (token && token[0]);
    if (kiosk && (!token || !token[0])) {
        fprintf(stderr, "gale-ctl: a kiosk token is required (--token-file F, --token T or "
                        "$GALE_KIOSK_TOKEN)\n");
        return 2;
    }
    if (kiosk) {
        snprintf(w.token, sizeof w.token, "%s", token);
    }
    w.keep = w.has_speed || w.has_dir; /* the dial stays after gale-ctl hangs up */
    gale_err err = { 0 };
    ctl_seen seen = { .print = cmd == CMD_SCENARIOS };
    cli_net_handler h = { .user = &seen, .on_welcome = on_welcome };
    cli_net *n = cli_net_create(&(cli_net_desc){ .url = url,
                                                 .role = kiosk ? CTL_ROLE_KIOSK : CTL_ROLE_VIEWER,
                                                 .token = kiosk ? token : NULL },
                                &h, &err);
    if (!n) {
        fprintf(stderr, "gale-ctl: %s\n", err.msg);
        return err.code == GALE_E_ARG ? 2 : 1;
    }
    int status = 1;
    const double until = mono_s() + wait_s;
    cli_net_stats st = cli_net_get_stats(n);
    while (mono_s() < until && st.state != CLI_NET_LIVE && st.state != CLI_NET_REFUSED) {
        cli_net_poll(n);
        usleep(2000);
        st = cli_net_get_stats(n);
    }
    if (st.state != CLI_NET_LIVE) {
        fprintf(stderr, "gale-ctl: %s: %s\n", cli_net_server_name(n),
                st.last_error[0] ? st.last_error : "no welcome in time");
        goto done;
    }
    /* live means the welcome is in cli_net's inbox: this poll hands it to on_welcome */
    cli_net_poll(n);
    if (cmd == CMD_SCENARIOS) {
        status = seen.welcomed ? 0 : 1;
        goto done;
    }
    ctl_msg reset = { .type = CTL_RESET };
    snprintf(reset.u.reset.token, sizeof reset.u.reset.token, "%s", token);
    /* cli_net_send_wall queues any control message once live */
    if (cmd == CMD_RESET ? cli_net_send_wall(n, &reset, &err) : cli_net_send_wind(n, &w, &err)) {
        fprintf(stderr, "gale-ctl: %s\n", err.msg);
        goto done;
    }
    /* a refusal is an error message and a close; none within a short while: taken */
    const double settle = mono_s() + 0.5;
    uint32_t connects = st.connects;
    while (mono_s() < settle) {
        cli_net_poll(n);
        usleep(2000);
        st = cli_net_get_stats(n);
        if (st.state != CLI_NET_LIVE || st.connects != connects) {
            break;
        }
    }
    if (st.state != CLI_NET_LIVE) {
        fprintf(stderr, "gale-ctl: %s refused the command: %s\n", cli_net_server_name(n),
                st.last_error[0] ? st.last_error : "connection closed");
        if (w.has_scenario && w.scenario[0] && seen.names[0]) {
            fprintf(stderr, "gale-ctl: the server's scenarios: %s\n", seen.names);
        }
        goto done;
    }
    printf("gale-ctl: %s took the command\n", cli_net_server_name(n));
    status = 0;
done:
    cli_net_destroy(n);
    return status;
}
