/* The subcommands of gale-bench (one per bench_<name>.c) and what they share. */
#ifndef GALE_BENCH_H
#define GALE_BENCH_H

int bench_bake(int argc, char **argv);
int bench_wind(int argc, char **argv);
int bench_modal(int argc, char **argv);
int bench_wire(int argc, char **argv);

/* Answers an argument a subcommand does not take: "--help"/"-h" print usage on stdout and
 * give exit status 0, anything else prints it on stderr and gives 2. */
int bench_usage(const char *arg, const char *usage);

#endif
