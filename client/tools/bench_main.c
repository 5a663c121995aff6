/* gale-bench-client: the client-side benchmarks, each printing figures as JSON: the
 * client CPU per frame and the renderer's frame time; the server side has gale-bench. */
#include <stdio.h>
#include <string.h>

int bench_client(int argc, char **argv);
int bench_render(int argc, char **argv);

typedef struct bench_cmd {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *what;
} bench_cmd;

static const bench_cmd bench_cmds[] = {
    { "client", bench_client, "client CPU per frame: receive, decode, upload (JSON)" },
    { "render", bench_render, "frame time of gale_render, headless (JSON)" },
};

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-bench-client COMMAND [options]   (COMMAND --help for its options)\n");
    for (size_t i = 0; i < sizeof bench_cmds / sizeof bench_cmds[0]; i++) {
        fprintf(f, "  %-8s %s\n", bench_cmds[i].name, bench_cmds[i].what);
    }
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
