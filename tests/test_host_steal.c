/* The host's steal time read from /proc/stat (server/serve/host_steal.c): the eighth field
 * of the cpu line in clock ticks, as milliseconds; a text without that line or field is
 * refused; the machine's own /proc/stat reads; the window of the last 1-2 s. */
#include "check.h"
#include "host_steal.h"

#include <string.h>

static void test_parse(void)
{
    const char *stat = "cpu  4705 356 584 3699176 2364 0 39 1234 0 0\n"
                       "cpu0 2000 100 300 1800000 1000 0 20 600 0 0\n"
                       "intr 114930548 113199788 3\n";
    double ms = -1.0;
    CHECK(host_steal_parse(stat, strlen(stat), 100, &ms) == 0);
    CHECK_NEAR(ms, 12340.0, 1e-9); /* 1234 ticks of 10 ms */
    CHECK(host_steal_parse(stat, strlen(stat), 1000, &ms) == 0);
    CHECK_NEAR(ms, 1234.0, 1e-9);
    /* a kernel without the steal field (before 2.6.11), a cpuN line first, no text */
    const char *old = "cpu  4705 356 584 3699176 2364 0 39\ncpu0 1 2 3 4 5 6 7 8\n";
    CHECK(host_steal_parse(old, strlen(old), 100, &ms) == -1);
    const char *cpu0 = strchr(stat, '\n') + 1;
    CHECK(host_steal_parse(cpu0, strlen(cpu0), 100, &ms) == -1);
    CHECK(host_steal_parse("", 0, 100, &ms) == -1);
    CHECK(host_steal_parse(stat, strlen(stat), 0, &ms) == -1);
    /* the line cut short in the buffer: only what is there is read */
    CHECK(host_steal_parse(stat, 30, 100, &ms) == -1);
    const char *bad = "cpu  1 2 3 4 5 6 7 x\n";
    CHECK(host_steal_parse(bad, strlen(bad), 100, &ms) == -1);
}

static void test_read(void)
{
    double ms = -1.0;
    CHECK(host_steal_read(&ms) == 0);
    CHECK(ms >= 0.0);
}

/* The window keeps the last reading and the one before, a reading at most once a
 * second, so the span it reports is 1-2 s once it has run that long. */
static void test_window(void)
{
    host_steal_window w;
    CHECK(host_steal_open(&w, 100.0) == 0);
    CHECK(w.fd >= 0);
    CHECK(w.at_s[0] == 100.0 && w.at_s[1] == 100.0);
    host_steal_advance(&w, 100.5); /* under a second: no reading */
    CHECK(w.at_s[1] == 100.0);
    host_steal_advance(&w, 101.25);
    CHECK(w.at_s[0] == 100.0 && w.at_s[1] == 101.25);
    host_steal_advance(&w, 102.5);
    CHECK(w.at_s[0] == 101.25 && w.at_s[1] == 102.5);
    double ms = -1.0, span_s = 0.0;
    CHECK(host_steal_recent(&w, 103.0, &ms, &span_s) == 0);
    CHECK_NEAR(span_s, 1.75, 1e-12);
    CHECK(ms >= 0.0 && ms >= w.ms[1] - w.ms[0]);
    /* the descriptor read again from its start: the readings never go back */
    CHECK(w.ms[1] >= w.ms[0] && w.ms[0] >= 0.0);
    /* off: nothing to report, nothing read */
    host_steal_close(&w);
    CHECK(w.fd == -1);
    host_steal_advance(&w, 200.0);
    CHECK(w.at_s[1] == 102.5);
    CHECK(host_steal_recent(&w, 200.0, &ms, &span_s) == -1);
    host_steal_close(&w); /* closing an off window again is harmless */
}

int main(void)
{
    RUN(test_parse);
    RUN(test_read);
    RUN(test_window);
    return check_report();
}
