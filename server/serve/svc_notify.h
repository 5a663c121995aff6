/* systemd's service notification protocol (sd_notify(3), systemd.service Type=notify and
 * WatchdogSec=) without libsystemd: one datagram to $NOTIFY_SOCKET. Outside systemd
 * (no $NOTIFY_SOCKET) every call does nothing. server/SERVER.md "Debian service". */
#ifndef GALE_SVC_NOTIFY_H
#define GALE_SVC_NOTIFY_H

#include <stdint.h>

/* Sends state ("READY=1\nSTATUS=...", "STOPPING=1", "WATCHDOG=1"): 0 sent, 1 no
 * $NOTIFY_SOCKET, -1 it could not be sent. Any thread. */
int svc_notify(const char *state);

/* The watchdog interval systemd asks for ($WATCHDOG_USEC, when $WATCHDOG_PID is unset or
 * this process) [us]; 0 without one. */
uint64_t svc_watchdog_us(void);

#endif
