/* Test helper: gale programs run as child processes, their stderr and stdout into a log
 * under the build tree. */
#ifndef GALE_TEST_PROC_FIXTURE_H
#define GALE_TEST_PROC_FIXTURE_H

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mono.h"

/* Starts argv with stderr (and stdout) into log. */
static inline pid_t proc_spawn(char *const argv[], const char *log)
{
    pid_t pid = fork();
    if (pid == 0) {
        FILE *f = freopen(log, "w", stderr);
        if (!f || dup2(fileno(stderr), 1) < 0) {
            _exit(126);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    return pid;
}

/* Count of lines of log containing needle (0 without the file). */
static inline int proc_log_count(const char *log, const char *needle)
{
    FILE *f = fopen(log, "r");
    if (!f) {
        return 0;
    }
    char line[1024];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        n += strstr(line, needle) != NULL;
    }
    fclose(f);
    return n;
}

/* Whether log holds count lines containing needle within timeout_s. */
static inline bool proc_wait_log(const char *log, const char *needle, int count, double timeout_s)
{
    double until = mono_s() + timeout_s;
    while (mono_s() < until) {
        if (proc_log_count(log, needle) >= count) {
            return true;
        }
        usleep(50000);
    }
    return false;
}

/* Waits for pid; its exit status (128 + signal when killed), or -1 on timeout (then kills
 * it). */
static inline int proc_wait_exit(pid_t pid, double timeout_s)
{
    double until = mono_s() + timeout_s;
    int st;
    while (mono_s() < until) {
        if (waitpid(pid, &st, WNOHANG) == pid) {
            return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        usleep(20000);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    return -1;
}

/* The last lines of log on stderr, for a failing check. */
static inline void proc_dump(const char *log)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "tail -n 20 '%s' >&2", log);
    if (system(cmd) != 0) {
        fprintf(stderr, "(no log %s)\n", log);
    }
}

#endif
