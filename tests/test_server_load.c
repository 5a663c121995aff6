/* gale-load against the in-process loopback server: 20 real connections for 3 s, every
 * frame decoded, the JSON report read back; and its refusals (non-loopback host, bad
 * counts). */
#include "check.h"
#include "server_fixture.h"

#include <cjson/cJSON.h>
#include <stdlib.h>
#include <sys/wait.h>

static int run(const char *args, char *out, size_t cap)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "%s %s 2>&1", GALE_LOAD_EXE, args);
    FILE *p = popen(cmd, "r");
    if (!p) {
        return -1;
    }
    size_t n = fread(out, 1, cap - 1, p);
    out[n] = 0;
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static double num(const cJSON *o, const char *k)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, k);
    return cJSON_IsNumber(v) ? v->valuedouble : -1;
}

static void test_load_run(void)
{
    char args[256], out[8192];
    snprintf(args, sizeof args, "--url ws://127.0.0.1:%d --clients 20 --seconds 3 --json",
             srv_port(S));
    int rc = run(args, out, sizeof out);
    fprintf(stderr, "  %s", out);
    CHECK(rc == 0);
    cJSON *j = cJSON_Parse(out);
    CHECK(j != NULL);
    if (!j) {
        return;
    }
    CHECK(num(j, "connected") == 20);
    CHECK(num(j, "welcomed") == 20);
    CHECK(num(j, "decode_errors") == 0);
    CHECK(num(j, "disconnects") == 0);
    CHECK(num(j, "keyframes") >= 20);
    /* every client got its keyframe and deltas after it (counts, not a rate: the rate
       belongs to gale-bench and deploy/bench-load.sh) */
    CHECK(num(j, "state_frames") > num(j, "keyframes"));
    CHECK(num(j, "sequence_gaps") == 0);
    const cJSON *lat = cJSON_GetObjectItemCaseSensitive(j, "latency_ms");
    CHECK(lat && num(lat, "samples") == num(j, "state_frames"));
    CHECK(lat && num(lat, "p50") <= num(lat, "p99") && num(lat, "p99") <= num(lat, "max") + 0.01);
    cJSON_Delete(j);
    CHECK(srv_metrics(S)->clients[NET_ROLE_LOAD] == 0); /* all gone again */
}

static void test_load_refusals(void)
{
    char out[2048];
    CHECK(run("--url ws://10.1.2.3:80 --clients 1 --seconds 1", out, sizeof out) == 2);
    CHECK_STR_HAS(out, "expected loopback");
    CHECK(run("--url ws://127.0.0.1:80 --clients 0 --seconds 1", out, sizeof out) == 2);
    CHECK_STR_HAS(out, "--clients: expected 1..5000");
    CHECK(run("--url http://127.0.0.1:80 --clients 1 --seconds 1", out, sizeof out) == 2);
    CHECK_STR_HAS(out, "expected ws://HOST:PORT");
    CHECK(run("--url ws://127.0.0.1:80 --clients 1 --seconds 99999", out, sizeof out) == 2);
}

int main(void)
{
    if (start_server()) {
        return 1;
    }
    RUN(test_load_run);
    RUN(test_load_refusals);
    stop_server();
    return check_report();
}
