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

#endif
