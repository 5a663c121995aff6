/* The time the host took this machine's CPUs from it (steal, as the kernel reports it on
 * /proc/stat's cpu line), so an overrun's log line can say whether the machine itself lost
 * its CPUs around it: under a hypervisor a tick can take three times its usual work with
 * nothing else running in the machine. */
#ifndef GALE_HOST_STEAL_H
#define GALE_HOST_STEAL_H

#include <stddef.h>

/* The steal of all CPUs together [ms] from the text of /proc/stat, whose first line is
 * "cpu  user nice system idle iowait irq softirq steal ..." in ticks of ticks_per_s.
 * Returns 0, or -1 when the text has no such line with a steal field. */
int host_steal_parse(const char *text, size_t len, long ticks_per_s, double *ms);

/* The same, read from /proc/stat now. Returns 0, or -1 where it cannot be read. */
int host_steal_read(double *ms);

/* The steal of the last 1-2 s (/proc/stat counts it in 10 ms ticks, so a shorter span
 * says little): a reading taken once a second and the one before it, through one
 * descriptor of /proc/stat kept open (read again from its start each time), so the
 * process's descriptors do not come and go with the readings. */
typedef struct host_steal_window {
    int fd;         /* /proc/stat, or -1: off */
    double ms[2];   /* [1] the last reading, [0] the one before; < 0: none */
    double at_s[2]; /* when they were taken (mono_s) */
} host_steal_window;

/* Opens /proc/stat and takes the first reading at now_s. Returns -1, the window off
 * (fd -1), where it cannot be read. */
int host_steal_open(host_steal_window *w, double now_s);
/* Closes the descriptor; the window is off after. A window off already is left so. */
void host_steal_close(host_steal_window *w);
/* Takes a reading when the last is a second old or more (call it as often as wanted). */
void host_steal_advance(host_steal_window *w, double now_s);
/* The steal now since the older reading [ms] and how long ago that was [s]. Returns -1
 * where the window is off or has no reading. */
int host_steal_recent(const host_steal_window *w, double now_s, double *ms, double *span_s);

#endif
