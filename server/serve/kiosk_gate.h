/* The kiosk token check (server/SERVER.md "Kiosk tokens"): a constant-time compare, and a
 * per-address delay after wrong tokens that doubles per failure up to a cap, so guessing
 * costs time; its counters as /metrics rows. Single-threaded (the lws service thread);
 * the counters are readable from any thread. */
#ifndef GALE_KIOSK_GATE_H
#define GALE_KIOSK_GATE_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "err.h"
#include "metric.h"
#include "wire_limits.h"

#define KIOSK_GATE_ADDRS 256             /* addresses remembered; the oldest goes first */
#define KIOSK_GATE_DELAY0_US 250000u     /* delay after the first wrong token [µs] */
#define KIOSK_GATE_DELAY_MAX_US 30000000u /* the delay doubles per failure up to this [µs] */
#define KIOSK_GATE_ADDR_MAX 64           /* bytes of a peer address kept, NUL included */

/* One address that sent wrong tokens since its last right one. */
typedef struct kiosk_gate_entry {
    char addr[KIOSK_GATE_ADDR_MAX]; /* "" = free slot */
    uint32_t failures;              /* wrong tokens in a row */
    uint64_t until_us;              /* before this, its kiosk hellos are refused unchecked */
    uint64_t last_us;               /* its latest wrong token (eviction order) */
} kiosk_gate_entry;

typedef struct kiosk_gate {
    kiosk_gate_entry e[KIOSK_GATE_ADDRS];
    atomic_ullong failures;         /* wrong tokens checked (hellos and wind commands) */
    atomic_ullong delayed;          /* hellos refused unchecked during their address's delay */
} kiosk_gate;

typedef enum kiosk_gate_verdict {
    KIOSK_GATE_PASS,  /* the token is right: the address starts afresh */
    KIOSK_GATE_WRONG, /* checked and wrong (or kiosks are disabled): the delay grows */
    KIOSK_GATE_WAIT,  /* not checked: the address is still waiting out its delay */
} kiosk_gate_verdict;

/* An empty gate (every slot free, counters zero). */
void kiosk_gate_init(kiosk_gate *g);

/* True when the NUL-terminated strings given and want are equal. Its time does not depend
 * on where they differ nor on want's length: it always looks at CTL_MAX_TOKEN positions
 * (a string longer than that never matches). */
bool kiosk_gate_token_eq(const char *given, const char *want);

/* A kiosk hello from addr (NUL-terminated; longer ones are cut to KIOSK_GATE_ADDR_MAX - 1
 * bytes) carrying token `given`, against the server's token `want` ("" = kiosks disabled:
 * every token is wrong), at now_us on a monotonic clock. WAIT while the address's delay
 * runs (the token is not looked at; counted in delayed). WRONG records the failure: the
 * address's next hello waits KIOSK_GATE_DELAY0_US × 2^(failures − 1), at most
 * KIOSK_GATE_DELAY_MAX_US (a full table forgets its oldest address); counted in failures.
 * PASS forgets the address. *wait_us (may be NULL) gets the time left before the address
 * may try again (0 on PASS). */
kiosk_gate_verdict kiosk_gate_check(kiosk_gate *g, const char *addr, const char *given,
                                    const char *want, uint64_t now_us, uint64_t *wait_us);

/* Counts a wrong token that no address delay follows (a wind command's: that connection
 * already proved it holds the token). */
void kiosk_gate_count_failure(kiosk_gate *g);

/* Adds gale_kiosk_auth_failures_total and gale_kiosk_auth_delayed_total to r; g is
 * borrowed for r's life. Fails only when r is full (metric_reg_add). */
int kiosk_gate_register(kiosk_gate *g, metric_reg *r, gale_err *err);

#endif
