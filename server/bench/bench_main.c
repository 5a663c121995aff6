/* gale-bench: the server-side benchmarks, each printing figures as JSON. One subcommand
 * per subsystem, each in its own bench_<name>.c; the client side has gale-bench-client. */
#include "bench.h"

#include <stdio.h>
#include <string.h>

typedef struct bench_cmd {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *what;
} bench_cmd;

static const bench_cmd bench_cmds[] = {
    { "bake", bench_bake, "bake time and peak memory for generated trees (JSON)" },
    { "wind", bench_wind, "wind solver ms/step, divergence reduction, bandwidth (JSON)" },
    { "modal", bench_modal, "per-tick modal update of many trees, bandwidth (JSON)" },
    { "wire", bench_wire, "state stream bytes per tree and node error, gusty run (JSON)" },
    { "views", bench_views, "per-client view streams: selection and encode per snapshot (JSON)" },
    { "ef", bench_ef, "wind at the first branch, uproot and snap per species vs the EF scale (JSON)" },
};

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-bench COMMAND [options]   (COMMAND --help for its options)\n");
    for (size_t i = 0; i < sizeof bench_cmds / sizeof bench_cmds[0]; i++) {
        fprintf(f, "  %-8s %s\n", bench_cmds[i].name, bench_cmds[i].what);
    }
}

int bench_usage(const char *arg, const char *usage)
{
    const int help = strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0;
    fputs(usage, help ? stdout : stderr);
    return help ? 0 : 2;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; argc >= 2 && i < sizeof bench_cmds / sizeof bench_cmds[0]; i++) {
        if (strcmp(argv[1], bench_cmds[i].name) == 0) {
            return bench_cmds[i].fn(argc - 1, argv + 1);
        }
    }
    usage(stderr);
    return 2;
}
