/* The kiosk token gate without sockets (its loopback side is test_server_kiosk.c): the
 * constant-time compare is a correct string equality; a wrong token delays that address
 * 0.25 s, doubling per failure up to 30 s, refused unchecked meanwhile; a right token
 * resets it; other addresses are not held; the table forgets its oldest address. */
#include "check.h"
#include "kiosk_gate.h"

#include <stdlib.h>

static kiosk_gate g; /* ~22 KB: each test starts it afresh with kiosk_gate_init */

static void test_token_eq(void)
{
    CHECK(kiosk_gate_token_eq("sesame", "sesame"));
    CHECK(kiosk_gate_token_eq("", ""));
    CHECK(!kiosk_gate_token_eq("", "sesame"));
    CHECK(!kiosk_gate_token_eq("sesame", ""));
    CHECK(!kiosk_gate_token_eq("sesam", "sesame"));   /* a prefix */
    CHECK(!kiosk_gate_token_eq("sesame!", "sesame")); /* longer */
    CHECK(!kiosk_gate_token_eq("Sesame", "sesame"));  /* first byte */
    CHECK(!kiosk_gate_token_eq("sesamE", "sesame"));  /* last byte */
    CHECK(!kiosk_gate_token_eq("sesame", "sesam"));
    /* every single-bit change of every byte of a full-length token */
    char want[CTL_MAX_TOKEN], given[CTL_MAX_TOKEN];
    for (int i = 0; i < (int)CTL_MAX_TOKEN - 1; i++) {
        want[i] = (char)('!' + (i * 7) % 90);
    }
    want[CTL_MAX_TOKEN - 1] = 0;
    memcpy(given, want, sizeof given);
    CHECK(kiosk_gate_token_eq(given, want));
    int missed = 0;
    for (int i = 0; i < (int)CTL_MAX_TOKEN - 1; i++) {
        for (int b = 0; b < 8; b++) {
            given[i] = (char)(want[i] ^ (1 << b));
            missed += kiosk_gate_token_eq(given, want);
            given[i] = want[i];
        }
    }
    CHECK(missed == 0);
    /* tokens longer than a hello may carry never match, not even themselves */
    char huge[2 * CTL_MAX_TOKEN];
    memset(huge, 'x', sizeof huge - 1);
    huge[sizeof huge - 1] = 0;
    CHECK(!kiosk_gate_token_eq(huge, huge));
    CHECK(!kiosk_gate_token_eq(want, huge));
    /* bytes above 0x7f compare as bytes */
    CHECK(kiosk_gate_token_eq("\xc3\xa9t\xc3\xa9", "\xc3\xa9t\xc3\xa9"));
    CHECK(!kiosk_gate_token_eq("\xc3\xa9t\xc3\xa8", "\xc3\xa9t\xc3\xa9"));
}

static void test_delay_doubles(void)
{
    kiosk_gate_init(&g);
    const char *a = "10.0.0.1";
    uint64_t now = 1000000, wait = 0;
    uint64_t want_delay = KIOSK_GATE_DELAY0_US;
    for (int k = 0; k < 12; k++) {
        CHECK(kiosk_gate_check(&g, a, "guess", "sesame", now, &wait) == KIOSK_GATE_WRONG);
        CHECK(wait == want_delay);
        /* during the delay, even the right token is refused unchecked */
        CHECK(kiosk_gate_check(&g, a, "sesame", "sesame", now + wait - 1, NULL) == KIOSK_GATE_WAIT);
        CHECK(kiosk_gate_check(&g, a, "guess", "sesame", now + 1, &wait) == KIOSK_GATE_WAIT);
        CHECK(wait == want_delay - 1);
        now += want_delay;
        want_delay = want_delay * 2 < KIOSK_GATE_DELAY_MAX_US ? want_delay * 2
                                                              : KIOSK_GATE_DELAY_MAX_US;
    }
    CHECK(want_delay == KIOSK_GATE_DELAY_MAX_US); /* 0.25 s · 2^11 > 30 s: capped */
    CHECK(atomic_load(&g.failures) == 12);
    CHECK(atomic_load(&g.delayed) == 24);
    /* another address is not held */
    CHECK(kiosk_gate_check(&g, "10.0.0.2", "sesame", "sesame", now - 1, &wait) == KIOSK_GATE_PASS);
    CHECK(wait == 0);
    /* once the delay is over the right token passes and the address starts afresh */
    CHECK(kiosk_gate_check(&g, a, "sesame", "sesame", now, NULL) == KIOSK_GATE_PASS);
    CHECK(kiosk_gate_check(&g, a, "guess", "sesame", now, &wait) == KIOSK_GATE_WRONG);
    CHECK(wait == KIOSK_GATE_DELAY0_US);
    /* kiosks disabled: every token is wrong, "" included */
    CHECK(kiosk_gate_check(&g, "10.0.0.3", "", "", now, &wait) == KIOSK_GATE_WRONG);
    CHECK(wait == KIOSK_GATE_DELAY0_US);
    CHECK(kiosk_gate_check(&g, "10.0.0.4", "gale-kiosk", "", now, NULL) == KIOSK_GATE_WRONG);
    kiosk_gate_count_failure(&g);
    CHECK(atomic_load(&g.failures) == 16);
}

static void test_table_bounded(void)
{
    kiosk_gate_init(&g);
    char addr[32];
    /* the first address fails three times, each as soon as it may: held until 1.75 s */
    uint64_t now = 0;
    for (int k = 0; k < 3; k++) {
        uint64_t wait = 0;
        CHECK(kiosk_gate_check(&g, "192.168.0.1", "x", "sesame", now, &wait) == KIOSK_GATE_WRONG);
        now += k < 2 ? wait : 0;
    }
    CHECK(now == 750000);
    /* KIOSK_GATE_ADDRS - 1 others fill the table; it still holds the first */
    for (int k = 1; k < KIOSK_GATE_ADDRS; k++) {
        snprintf(addr, sizeof addr, "10.1.%d.%d", k / 256, k % 256);
        CHECK(kiosk_gate_check(&g, addr, "x", "sesame", now + (uint64_t)k, NULL) ==
              KIOSK_GATE_WRONG);
    }
    now = 1000000;
    CHECK(kiosk_gate_check(&g, "192.168.0.1", "x", "sesame", now, NULL) == KIOSK_GATE_WAIT);
    /* one more address evicts the oldest (the first): it starts afresh */
    CHECK(kiosk_gate_check(&g, "10.2.0.0", "x", "sesame", now + 1000, NULL) == KIOSK_GATE_WRONG);
    uint64_t wait = 0;
    CHECK(kiosk_gate_check(&g, "192.168.0.1", "x", "sesame", now + 2000, &wait) ==
          KIOSK_GATE_WRONG);
    CHECK(wait == KIOSK_GATE_DELAY0_US);
    /* and the newest are still held */
    CHECK(kiosk_gate_check(&g, "10.2.0.0", "sesame", "sesame", now + 3000, NULL) ==
          KIOSK_GATE_WAIT);
    /* a missing or empty address is an address of its own, not a free slot */
    CHECK(kiosk_gate_check(&g, "", "x", "sesame", now, NULL) == KIOSK_GATE_WRONG);
    CHECK(kiosk_gate_check(&g, NULL, "sesame", "sesame", now + 1, NULL) == KIOSK_GATE_WAIT);
}

static void test_metrics(void)
{
    kiosk_gate_init(&g);
    metric_reg r = { 0 };
    CHECK(kiosk_gate_register(&g, &r, NULL) == 0);
    kiosk_gate_check(&g, "a", "x", "y", 0, NULL);
    kiosk_gate_check(&g, "a", "x", "y", 1, NULL);
    size_t len = 0;
    char *page = metric_reg_render(&r, &len);
    CHECK(page != NULL);
    if (page) {
        CHECK_STR_HAS(page, "# TYPE gale_kiosk_auth_failures_total counter");
        CHECK_STR_HAS(page, "\ngale_kiosk_auth_failures_total 1\n");
        CHECK_STR_HAS(page, "\ngale_kiosk_auth_delayed_total 1\n");
    }
    free(page);
}

int main(void)
{
    RUN(test_token_eq);
    RUN(test_delay_doubles);
    RUN(test_table_bounded);
    RUN(test_metrics);
    return check_report();
}
