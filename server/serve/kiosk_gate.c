/* The kiosk token check: see kiosk_gate.h. The table is a flat array searched by address
 * (256 entries, touched only by kiosk hellos), so a wrong token costs one scan. */
#include "kiosk_gate.h"

#include <stdio.h>
#include <string.h>

void kiosk_gate_init(kiosk_gate *g)
{
    memset(g->e, 0, sizeof g->e);
    atomic_init(&g->failures, 0);
    atomic_init(&g->delayed, 0);
}

bool kiosk_gate_token_eq(const char *given, const char *want)
{
    /* Each string's index stops at its NUL, which then compares with the other's bytes:
     * no early exit and no branch on the bytes, so the time says nothing about how much
     * of want a guess got right or how long want is. */
    const unsigned char *a = (const unsigned char *)given, *b = (const unsigned char *)want;
    size_t i = 0, j = 0;
    unsigned diff = 0;
    for (size_t k = 0; k < CTL_MAX_TOKEN; k++) {
        unsigned ca = a[i], cb = b[j];
        diff |= ca ^ cb;
        i += ca != 0;
        j += cb != 0;
    }
    return (diff | a[i] | b[j]) == 0;
}

static uint64_t delay_us(uint32_t failures)
{
    uint64_t d = KIOSK_GATE_DELAY0_US;
    for (uint32_t k = 1; k < failures && d < KIOSK_GATE_DELAY_MAX_US; k++) {
        d *= 2;
    }
    return d < KIOSK_GATE_DELAY_MAX_US ? d : KIOSK_GATE_DELAY_MAX_US;
}

static kiosk_gate_entry *find(kiosk_gate *g, const char *addr)
{
    for (int k = 0; k < KIOSK_GATE_ADDRS; k++) {
        if (g->e[k].addr[0] && !strcmp(g->e[k].addr, addr)) {
            return &g->e[k];
        }
    }
    return NULL;
}

/* A slot for addr: a free one, else the one whose last wrong token is oldest. */
static kiosk_gate_entry *take(kiosk_gate *g, const char *addr)
{
    kiosk_gate_entry *best = &g->e[0];
    for (int k = 0; k < KIOSK_GATE_ADDRS; k++) {
        if (!g->e[k].addr[0]) {
            best = &g->e[k];
            break;
        }
        if (g->e[k].last_us < best->last_us) {
            best = &g->e[k];
        }
    }
    memset(best, 0, sizeof *best);
    snprintf(best->addr, sizeof best->addr, "%s", addr);
    return best;
}

kiosk_gate_verdict kiosk_gate_check(kiosk_gate *g, const char *addr, const char *given,
                                    const char *want, uint64_t now_us, uint64_t *wait_us)
{
    char key[KIOSK_GATE_ADDR_MAX];
    /* "" marks a free slot: an address the peer lookup left empty still gets one */
    snprintf(key, sizeof key, "%s", addr && addr[0] ? addr : "?");
    kiosk_gate_entry *e = find(g, key);
    if (e && now_us < e->until_us) {
        atomic_fetch_add(&g->delayed, 1);
        if (wait_us) {
            *wait_us = e->until_us - now_us;
        }
        return KIOSK_GATE_WAIT;
    }
    bool ok = kiosk_gate_token_eq(given, want);
    if (ok && want[0]) {
        if (e) {
            memset(e, 0, sizeof *e);
        }
        if (wait_us) {
            *wait_us = 0;
        }
        return KIOSK_GATE_PASS;
    }
    atomic_fetch_add(&g->failures, 1);
    if (!e) {
        e = take(g, key);
    }
    e->failures += e->failures < UINT32_MAX;
    e->last_us = now_us;
    e->until_us = now_us + delay_us(e->failures);
    if (wait_us) {
        *wait_us = e->until_us - now_us;
    }
    return KIOSK_GATE_WRONG;
}

void kiosk_gate_count_failure(kiosk_gate *g)
{
    atomic_fetch_add(&g->failures, 1);
}

/* --- metrics ---------------------------------------------------------------------------- */

static const metric_row gate_rows[] = {
    { "gale_kiosk_auth_failures_total", NULL,
      "Wrong kiosk tokens checked (kiosk hellos and wind commands).", METRIC_COUNTER, 0 },
    { "gale_kiosk_auth_delayed_total", NULL,
      "Kiosk hellos refused unchecked while their address waited out its delay.",
      METRIC_COUNTER, 0 },
};

static void gate_fill(void *ctx, double *v)
{
    kiosk_gate *g = ctx;
    v[0] = (double)atomic_load(&g->failures);
    v[1] = (double)atomic_load(&g->delayed);
}

int kiosk_gate_register(kiosk_gate *g, metric_reg *r, gale_err *err)
{
    return metric_reg_add(r, gate_rows, (int)(sizeof gate_rows / sizeof gate_rows[0]),
                          gate_fill, g, err);
}
