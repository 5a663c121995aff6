/* gale-server: arguments, scene config, species assets, wind grid and scenario, then the
 * server (srv.h) until SIGINT/SIGTERM; teardown. After the lws minimal-ws-server main:
 * everything else lives in its module. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sys/resource.h>

#include "scen_lib.h"
#include "scenario.h"
#include "scene.h"
#include "link_server.h"
#include "ops_hours.h"
#include "species_cache.h"
#include "srv.h"
#include "svc_notify.h"
#include "wind.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-server [--config FILE.json] [--port N] [--iface ADDR] [--cache DIR]\n"
               "                   [--kiosk-token-file FILE] [--max-connections N]\n"
               "                   [--hello-timeout S] [--no-bundle] [--nats URL] [--check]\n"
               "                   [--scenario FILE [--start-min M] [--replay-speed X]]\n"
               "                   [--kiosk-idle S] [--hours SPEC] [--state-file FILE]\n"
               "                   [--tls-cert FILE --tls-key FILE]\n"
               "  --config FILE  scene config (default: the embedded town block,\n"
               "                 configs/scenes/default.json)\n"
               "  --port N       listen port, 0 for any free one (default 8080)\n"
               "  --iface ADDR   listen address (default 127.0.0.1: this machine only;\n"
               "                 all or 0.0.0.0: every interface)\n"
               "  --cache DIR    baked species assets (default $XDG_CACHE_HOME/gale-server\n"
               "                 or ~/.cache/gale-server)\n"
               "  --kiosk-token-file FILE\n"
               "                 the kiosk token: the file's first line (over\n"
               "                 $" SCENE_KIOSK_TOKEN_ENV " over the config's kiosk_token;\n"
               "                 none of them: kiosks are refused)\n"
               "  --max-connections N  WebSocket connections served, more get close 4010\n"
               "                 (default 2048; lowered to what the open-file limit allows)\n"
               "  --hello-timeout S  seconds a connection may take to say hello before it\n"
               "                 is closed with 4009 (default 5)\n"
               "  --no-bundle    send a snapshot's leaves, wind, damage and weather frames\n"
               "                 as messages of their own instead of inside its BUNDLE\n"
               "  --nats URL     also publish every snapshot once on NATS (nats://HOST:PORT,\n"
               "                 comma-separated for a cluster) for gale-relay edges, and\n"
               "                 answer their clients' control messages\n"
               "  --check        validate the config, bake or load the species, and exit\n"
               "  --scenario FILE  run this scenario file (configs/scenarios/) instead of the\n"
               "                 config's scenario or playlist, e.g.\n"
               "                 configs/scenarios/andrew1992.json (kiosks may still pick\n"
               "                 any file of the scenarios folder)\n"
               "  --start-min M  a replay starts at storm minute M (0: the track's reference,\n"
               "                 landfall for the shipped replays) instead of the file's\n"
               "  --replay-speed X  a replay runs X storm seconds per second (1..10000)\n"
               "  --kiosk-idle S  release a kiosk's dial S seconds after its last command\n"
               "                 (default 300; a disconnect releases it at once); a kiosk\n"
               "                 session of the usage counters ends as long after its last\n"
               "                 interaction\n"
               "  --hours SPEC   opening hours in the machine's local time (TZ), e.g.\n"
               "                 09:30-17:00 or \"mon-fri 09:30-17:00; sat,sun 10:00-18:00;\n"
               "                 tue closed\" (seconds optional: HH:MM:SS); outside them\n"
               "                 clients show the closed card and the simulation idles\n"
               "                 (default: always open)\n"
               "  --state-file FILE  keep the usage counters in FILE (loaded at start,\n"
               "                 written every 60 s and at shutdown; default: not kept)\n"
               "  --tls-cert FILE  serve https and wss with this PEM certificate (chain)\n"
               "  --tls-key FILE  and this PEM private key (both or neither)\n");
}

/* The wind grid behind tick.h's tick_wind. */
static void w_inflow(void *ctx, const wind_inflow *in)
{
    wind_set_inflow(ctx, in);
}

static int w_step(void *ctx, float dt_s, wind_step_stats *st)
{
    return wind_step(ctx, dt_s, st);
}

static void w_sample(void *ctx, int n, const float *p, float *v)
{
    wind_sample_many(ctx, n, p, v);
}

static void *w_probe_create(void *ctx, int n, const float *p)
{
    gale_err err;
    wind_probe *pr = wind_probe_create(ctx, n, p, &err);
    if (!pr) {
        fprintf(stderr, "gale-server: %s: sampling every crown every tick instead\n", err.msg);
    }
    return pr;
}

static void w_probe_destroy(void *probe)
{
    wind_probe_destroy(probe);
}

static void w_probe_sample(void *ctx, const void *probe, int i0, int i1, float *v)
{
    wind_probe_sample(ctx, probe, i0, i1, v);
}

static void w_add_subgrid(void *ctx, int n, const float *p, float *v)
{
    wind_add_subgrid(ctx, n, p, v);
}

static int w_coarse(void *ctx, int factor, float *out, int capacity, int dims[3])
{
    return wind_coarse(ctx, factor, out, capacity, dims);
}

static int w_publish(void *ctx)
{
    return wind_publish(ctx);
}

static void w_subgrid_inflow(void *ctx, const wind_inflow *in)
{
    wind_set_subgrid_inflow(ctx, in);
}

static void w_ball(void *ctx, const wind_ball *b)
{
    wind_add_ball(ctx, b);
}

/* The open-file limit: the soft limit raised to the hard one (capped where lws would size
 * a table by it), so the connection limit is what the operator asked for where the system
 * allows it (the network sizes the limit from what this leaves). */
static void raise_nofile(void)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl)) {
        return;
    }
    rlim_t want = rl.rlim_max;
    if (want == RLIM_INFINITY || want > (rlim_t)1 << 20) {
        want = (rlim_t)1 << 20;
    }
    if (rl.rlim_cur == RLIM_INFINITY || rl.rlim_cur >= want) {
        return;
    }
    rl.rlim_cur = want;
    if (setrlimit(RLIMIT_NOFILE, &rl)) {
        fprintf(stderr, "gale-server: cannot raise the open-file limit to %llu: %s\n",
                (unsigned long long)want, strerror(errno));
    }
}

/* SIGINT/SIGTERM: the handler only writes the signal number to a pipe (async-signal
 * safe, and whichever thread the kernel picks, the BLAS pool's included); a waiting
 * thread reads it and stops the server from ordinary code. */
static int sig_pipe[2] = { -1, -1 };

static void on_signal(int sig)
{
    unsigned char b = (unsigned char)sig;
    ssize_t n = write(sig_pipe[1], &b, 1);
    (void)n;
}

static void *wait_signal(void *arg)
{
    srv *s = arg;
    unsigned char b = 0;
    while (read(sig_pipe[0], &b, 1) < 0 && errno == EINTR) {
    }
    if (b == SIGINT || b == SIGTERM) {
        fprintf(stderr, "gale-server: %s: shutting down\n", b == SIGINT ? "SIGINT" : "SIGTERM");
        srv_stop(s);
    }
    return NULL;
}

/* The OpenMP threads wait passively (sleep in the kernel) between parallel regions
 * unless the environment says otherwise: libgomp's default spins for a while after each
 * region, and on a machine with as many cores as tick threads the spinning thread takes
 * the core the service thread, the wind step or the other tick thread needs (SERVER.md
 * "The tick at 100 000 trees": a wind step 20 times slower). libgomp reads the variable
 * once, as it loads, before main; so the server sets it and runs itself again, by the
 * path /proc/self/exe points to, so that the process keeps its name (ps, top, pkill and
 * systemd see "gale-server", not "exe"); by /proc/self/exe itself where that path is
 * gone (the binary replaced under a running service). Where both fail it runs on with
 * libgomp's default. */
static void omp_wait_passive(char **argv)
{
    if (getenv("OMP_WAIT_POLICY") || setenv("OMP_WAIT_POLICY", "passive", 1)) {
        return;
    }
    char path[4096];
    const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
    if (n > 0) {
        path[n] = 0;
        execv(path, argv);
    }
    execv("/proc/self/exe", argv);
    fprintf(stderr, "gale-server: cannot run again with OMP_WAIT_POLICY=passive (%s): "
                    "OpenMP threads spin between regions\n", strerror(errno));
}

int main(int argc, char **argv)
{
    omp_wait_passive(argv);
    if (pipe(sig_pipe) != 0) {
        fprintf(stderr, "gale-server: pipe: %s\n", strerror(errno));
        return 1;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    const char *config = NULL, *iface = "127.0.0.1", *cache = NULL, *token_file = NULL;
    long port = 8080, max_conn = 0;
    double hello_s = 0;
    int check = 0;
    bool no_bundle = false;
    const char *nats_url = NULL;
    link_server *link = NULL;
    /* the scenario and its replay start and speed, set at load time */
    const char *scen_file = NULL;
    double start_min = 0, replay_speed = 0, kiosk_idle_s = 0;
    bool has_start = false;
    ops_hours hours = { 0 };
    const char *state_file = NULL, *tls_cert = NULL, *tls_key = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--config") && v) {
            config = v;
            i++;
        } else if (!strcmp(a, "--port") && v) {
            char *end;
            port = strtol(v, &end, 10);
            if (*end || port < 0 || port > 65535) {
                fprintf(stderr, "gale-server: --port: expected 0..65535, got \"%s\"\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--iface") && v) {
            iface = !strcmp(v, "all") || !strcmp(v, "0.0.0.0") ? NULL : v;
            i++;
        } else if (!strcmp(a, "--kiosk-token-file") && v) {
            token_file = v;
            i++;
        } else if (!strcmp(a, "--cache") && v) {
            cache = v;
            i++;
        } else if (!strcmp(a, "--max-connections") && v) {
            char *end;
            max_conn = strtol(v, &end, 10);
            if (*end || end == v || max_conn < 1 || max_conn > 1000000) {
                fprintf(stderr,
                        "gale-server: --max-connections: expected 1..1000000, got \"%s\"\n", v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--hello-timeout") && v) {
            char *end;
            hello_s = strtod(v, &end);
            if (*end || end == v || !(hello_s >= 0.01 && hello_s <= 3600)) {
                fprintf(stderr,
                        "gale-server: --hello-timeout: expected seconds in [0.01, 3600], got "
                        "\"%s\"\n",
                        v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--hours") && v) {
            gale_err he;
            if (ops_hours_parse(v, &hours, &he)) {
                fprintf(stderr, "gale-server: --%s\n", he.msg);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--state-file") && v) {
            state_file = v;
            i++;
        } else if (!strcmp(a, "--tls-cert") && v) {
            tls_cert = v;
            i++;
        } else if (!strcmp(a, "--tls-key") && v) {
            tls_key = v;
            i++;
        } else if (!strcmp(a, "--nats") && v) {
            nats_url = v;
            i++;
        } else if (!strcmp(a, "--no-bundle")) {
            no_bundle = true;
        } else if (!strcmp(a, "--scenario") && v) {
            scen_file = v;
            i++;
        } else if ((!strcmp(a, "--start-min") || !strcmp(a, "--replay-speed") ||
                    !strcmp(a, "--kiosk-idle")) && v) {
            char *end;
            double x = strtod(v, &end);
            bool ok = !*end && end != v && isfinite(x);
            if (!strcmp(a, "--start-min")) {
                ok = ok && fabs(x) <= 1e5;
                start_min = x;
                has_start = true;
            } else if (!strcmp(a, "--replay-speed")) {
                ok = ok && x >= 1 && x <= 10000;
                replay_speed = x;
            } else {
                ok = ok && x >= 1 && x <= 1e6;
                kiosk_idle_s = x;
            }
            if (!ok) {
                fprintf(stderr, "gale-server: %s: expected %s, got \"%s\"\n", a,
                        !strcmp(a, "--start-min")      ? "a storm minute within +-1e5"
                        : !strcmp(a, "--replay-speed") ? "1..10000"
                                                       : "seconds in [1, 1e6]",
                        v);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--check")) {
            check = 1;
        } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else {
            fprintf(stderr, "gale-server: unknown or incomplete argument \"%s\"\n", a);
            usage(stderr);
            return 2;
        }
    }
    if (!tls_cert != !tls_key) {
        fprintf(stderr, "gale-server: %s: expected --tls-cert and --tls-key together, got only "
                "the %s\n", tls_cert ? "--tls-key" : "--tls-cert", tls_cert ? "certificate" : "key");
        return 2;
    }
    for (int k = 0; k < 2; k++) {
        const char *f = k ? tls_key : tls_cert;
        if (f && access(f, R_OK)) {
            fprintf(stderr, "gale-server: %s %s: cannot read: %s\n", k ? "--tls-key" : "--tls-cert",
                    f, strerror(errno));
            return 1;
        }
    }
    char cache_dir[512];
    if (cache) {
        snprintf(cache_dir, sizeof cache_dir, "%s", cache);
    } else if (getenv("XDG_CACHE_HOME") && getenv("XDG_CACHE_HOME")[0]) {
        snprintf(cache_dir, sizeof cache_dir, "%s/gale-server", getenv("XDG_CACHE_HOME"));
    } else if (getenv("HOME") && getenv("HOME")[0]) {
        snprintf(cache_dir, sizeof cache_dir, "%s/.cache/gale-server", getenv("HOME"));
    } else {
        snprintf(cache_dir, sizeof cache_dir, "/tmp/gale-server-cache");
    }

    gale_err err;
    gale_err_clear(&err);
    scene sc;
    int rc = config ? scene_load(&sc, config, &err) : scene_load_default(&sc, getenv("GALE_SHARE"), &err);
    if (rc) {
        /* a bad config: say why and refuse to start (Redis FATAL CONFIG) */
        fprintf(stderr, "gale-server: bad config: %s\n", err.msg);
        return 1;
    }
    char token_from[600];
    if (scene_kiosk_token_resolve(&sc, token_file, getenv(SCENE_KIOSK_TOKEN_ENV), token_from,
                                  sizeof token_from, &err)) {
        fprintf(stderr, "gale-server: kiosk token: %s\n", err.msg);
        scene_fini(&sc);
        return 1;
    }
    if (token_from[0]) {
        fprintf(stderr, "gale-server: kiosks enabled: token from %s\n", token_from);
    } else {
        fprintf(stderr, "gale-server: kiosks disabled: no kiosk token set (give one with "
                        "--kiosk-token-file FILE, $" SCENE_KIOSK_TOKEN_ENV " or the config's "
                        "kiosk_token)\n");
    }
    int status = 1;
    species_entry ent[SCENE_MAX_SPECIES];
    srv_species sp[SCENE_MAX_SPECIES];
    memset(ent, 0, sizeof ent);
    scenario *scen = NULL;
    scen_lib lib;
    memset(&lib, 0, sizeof lib);
    wind_grid *grid = NULL;
    srv *s = NULL;
    for (int i = 0; i < sc.n_species; i++) {
        if (species_cache_get(sc.species[i].file, sc.species[i].modes, cache_dir, &ent[i], &err)) {
            fprintf(stderr, "gale-server: species[%d] %s: %s\n", i, sc.species[i].name, err.msg);
            goto done;
        }
        const asset *a = &ent[i].a;
        fprintf(stderr,
                "gale-server: species %s: %u nodes, %u modes, %.2f..%.2f Hz, %u leaves; %s in "
                "%.2f s (%s)\n",
                sc.species[i].name, a->n_nodes, a->n_modes,
                (double)a->omega[0] / 6.283185307179586,
                (double)a->omega[a->n_modes - 1] / 6.283185307179586, a->n_leaves,
                ent[i].baked ? "baked" : "loaded", ent[i].seconds, ent[i].path);
        sp[i] = (srv_species){ .modal = { .n_modes = a->n_modes,
                                          .omega = a->omega,
                                          .gamma = a->gamma,
                                          .wind_basis = a->wind_basis,
                                          .height_m = a->height_m,
                                          .n_leaves = a->n_leaves,
                                          .drag = ent[i].drag,
                                          .damage = &ent[i].damage },
                               .qstep = ent[i].qstep,
                               .asset_bytes = ent[i].bytes,
                               .asset_len = ent[i].len };
        snprintf(sp[i].hash, sizeof sp[i].hash, "%s", ent[i].hash);
    }
    /* every scenario of the scenarios folder, for kiosks' picks and the playlist */
    char scen_dir[SCENE_PATH_MAX + 32];
    scene_scenarios_dir(&sc, getenv("GALE_SHARE"), scen_dir, sizeof scen_dir);
    if (scen_lib_load(&lib, scen_dir, &err)) {
        fprintf(stderr, "gale-server: bad scenario: %s\n", err.msg);
        goto done;
    }
    fprintf(stderr, "gale-server: %d scenarios in %s\n", lib.n, lib.dir[0] ? lib.dir : scen_dir);
    scenario *pl[SCENE_MAX_PLAYLIST];
    int n_pl = 0;
    if (!scen_file && scen_lib_playlist(&lib, &sc, pl, &n_pl, &err)) {
        fprintf(stderr, "gale-server: bad config: %s\n", err.msg);
        goto done;
    }
    if (n_pl > 0) {
        fprintf(stderr, "gale-server: playlist of %d, from %s\n", n_pl, scenario_name(pl[0]));
    }
    if (scen_file || sc.scenario[0]) {
        scen = scenario_load(scen_file ? scen_file : sc.scenario, &err);
        if (!scen) {
            fprintf(stderr, "gale-server: bad %s: %s\n", scen_file ? "--scenario" : "config: scenario",
                    err.msg);
            goto done;
        }
        if ((has_start || replay_speed > 0) &&
            scenario_set_start(scen, 0.0, has_start, start_min, replay_speed > 0, replay_speed,
                                &err)) {
            fprintf(stderr, "gale-server: --start-min / --replay-speed: %s\n", err.msg);
            goto done;
        }
        fprintf(stderr, "gale-server: scenario %s (%s)\n", scenario_name(scen),
                scen_file ? scen_file : sc.scenario);
    } else if (has_start || replay_speed > 0) {
        fprintf(stderr, "gale-server: --start-min / --replay-speed: no scenario to replay\n");
        goto done;
    }
    tick_wind tw = { 0 };
    if (sc.grid_on) {
        grid = wind_create(&(wind_desc){ .nx = sc.grid[0],
                                         .ny = sc.grid[1],
                                         .nz = sc.grid[2],
                                         .cell_m = sc.cell_m,
                                         .origin = { sc.origin[0], sc.origin[1], sc.origin[2] },
                                         .seed = sc.leaf_seed + 1,
                                         .threads = sc.wind_threads,
                                         .subgrid_profile = sc.wind_subgrid ? 1 : 0,
                                         .obstacles = sc.obstacles,
                                         .n_obstacles = sc.n_obstacles },
                           &err);
        if (!grid) {
            fprintf(stderr, "gale-server: wind grid: %s\n", err.msg);
            goto done;
        }
        wind_desc wd = wind_get_desc(grid);
        tw = (tick_wind){ .ctx = grid, .set_inflow = w_inflow, .step = w_step,
                          .sample_many = w_sample, .coarse = w_coarse,
                          .probe_create = w_probe_create, .probe_destroy = w_probe_destroy,
                          .probe_sample = w_probe_sample, .add_subgrid = w_add_subgrid,
                          .publish = w_publish, .set_subgrid_inflow = w_subgrid_inflow,
                          .add_ball = w_ball, .max_iterations = wd.max_iterations,
                          .div_reduction = wd.div_reduction };
    }
    if (check) {
        fprintf(stderr, "gale-server: %s: config ok: %d trees, %d species\n",
                config ? config : "<embedded default>", sc.n_trees, sc.n_species);
        status = 0;
        goto done;
    }

    raise_nofile();
    if (nats_url && !(link = link_server_create(nats_url, &err))) {
        fprintf(stderr, "gale-server: %s\n", err.msg);
        goto done;
    }
    s = srv_create(&(srv_desc){ .sc = &sc, .species = sp, .scen = scen, .lib = &lib,
                                .wind = sc.grid_on ? &tw : NULL,
                                .port = port ? (int)port : -1, .iface = iface,
                                .max_clients = (int)max_conn,
                                .kiosk_idle_s = kiosk_idle_s,
                                .hello_timeout_ms = hello_s > 0 ? (int)(hello_s * 1000 + 0.5) : 0,
                                .separate_extras = no_bundle,
                                .published = link ? link_server_publish : NULL,
                                .published_user = link,
                                .hours = hours,
                                .state_file = state_file,
                                .tls_cert = tls_cert,
                                .tls_key = tls_key },
                   &err);
    if (!s) {
        fprintf(stderr, "gale-server: %s\n", err.msg);
        goto done;
    }
    if (link && link_server_attach(link, s, &err)) {
        fprintf(stderr, "gale-server: %s\n", err.msg);
        goto done;
    }
    if (link) {
        fprintf(stderr, "gale-server: publishing on NATS %s\n", nats_url);
    }
    net_limits lim = srv_net_limits(s);
    if (lim.max_clients < lim.requested) {
        fprintf(stderr,
                "gale-server: connection limit %d, lowered from %d: the open-file limit "
                "(RLIMIT_NOFILE %ld) leaves room for no more\n",
                lim.max_clients, lim.requested, lim.nofile);
    } else {
        fprintf(stderr, "gale-server: connection limit %d (RLIMIT_NOFILE %ld)\n",
                lim.max_clients, lim.nofile);
    }
    pthread_t sig_thread;
    if (pthread_create(&sig_thread, NULL, wait_signal, s)) {
        fprintf(stderr, "gale-server: cannot start the signal thread\n");
        goto done;
    }
    /* where it listens, on stderr beside the other start-up lines; the stdout line below
     * is the one scripts read the port from */
    if (iface) {
        fprintf(stderr, "gale-server: listening on %s port %d%s\n", iface, srv_port(s),
                !strcmp(iface, "127.0.0.1") ? " (this machine only; --iface all serves every "
                                              "interface)"
                                            : "");
    } else {
        fprintf(stderr, "gale-server: listening on every interface, port %d\n", srv_port(s));
    }
    printf("gale-server: listening on port %d\n", srv_port(s));
    fflush(stdout);
    char status_line[160];
    snprintf(status_line, sizeof status_line, "READY=1\nSTATUS=scene %s, %d trees, port %d%s",
             sc.name, sc.n_trees, srv_port(s), link ? ", publishing on NATS" : "");
    svc_notify(status_line);
    rc = srv_run(s);
    svc_notify("STOPPING=1\nSTATUS=stopping");
    on_signal(0); /* wakes the waiter when the server stopped on its own */
    pthread_join(sig_thread, NULL);
    sim_metrics *sm = srv_sim_metrics(s);
    net_metrics *m = srv_metrics(s);
    fprintf(stderr,
            "gale-server: stopped after %llu ticks (%llu overruns, max tick %.2f ms), %llu "
            "snapshots, %llu frames sent, %llu dropped for slow clients, %llu bad messages\n",
            (unsigned long long)atomic_load(&sm->ticks),
            (unsigned long long)atomic_load(&sm->overruns),
            (double)atomic_load(&sm->tick_ns_max) * 1e-6,
            (unsigned long long)atomic_load(&m->snapshots),
            (unsigned long long)atomic_load(&m->frames_sent),
            (unsigned long long)atomic_load(&m->frames_dropped),
            (unsigned long long)atomic_load(&m->bad_messages));
    status = rc ? 1 : 0;
done:
    link_server_destroy(link); /* before the server its handlers call */
    srv_destroy(s);
    wind_destroy(grid);
    scenario_destroy(scen);
    scen_lib_fini(&lib);
    for (int i = 0; i < sc.n_species; i++) {
        species_entry_fini(&ent[i]);
    }
    scene_fini(&sc);
    return status;
}
