/* gale-bench: benchmarks that print figures as JSON. One subcommand per subsystem;
 * each lives in its own bench_<name>.c. */
#include <stdio.h>
#include <string.h>

/* Subcommands are weak so the program links while a subsystem is absent. */
int bench_bake(int argc, char **argv) __attribute__((weak));
int bench_wind(int argc, char **argv) __attribute__((weak));
int bench_modal(int argc, char **argv) __attribute__((weak));
int bench_wire(int argc, char **argv) __attribute__((weak));
int bench_client(int argc, char **argv) __attribute__((weak));
int bench_render(int argc, char **argv) __attribute__((weak));

typedef struct bench_cmd {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *what;
} bench_cmd;

int main(int argc, char **argv)
{
    const bench_cmd cmds[] = {
        { "bake", bench_bake, "bake time and peak memory for generated trees (JSON)" },
        { "wind", bench_wind, "wind solver ms/step, divergence reduction, bandwidth (JSON)" },
        { "modal", bench_modal, "per-tick modal update of many trees (JSON)" },
        { "wire", bench_wire, "state stream bytes per tree and node error, gusty run (JSON)" },
        { "client", bench_client, "client CPU per frame: receive, decode, upload (JSON)" },
        { "render", bench_render, "frame time of gale_render, headless (JSON)" },
    };
    const int n = (int)(sizeof cmds / sizeof cmds[0]);
    if (argc >= 2) {
        for (int i = 0; i < n; i++) {
            if (strcmp(argv[1], cmds[i].name) == 0 && cmds[i].fn) {
                return cmds[i].fn(argc - 1, argv + 1);
            }
        }
    }
    fprintf(stderr, "usage: gale-bench COMMAND [options]   (COMMAND --help for its options)\n");
    for (int i = 0; i < n; i++) {
        if (cmds[i].fn) {
            fprintf(stderr, "  %-8s %s\n", cmds[i].name, cmds[i].what);
        }
    }
    return 2;
}
