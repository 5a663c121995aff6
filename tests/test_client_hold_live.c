/* gale-client holding fewer trees than a scene has (client/CLIENT.md "Reduced view";
 * tests/data/slow_client_scene.json: 300 palms) against the real gale-server, with
 * --max-trees 100: it runs its frames and exits 0, says so once on stderr and on the
 * HUD, holds and draws the 100 trees nearest the scene's centre and the server streams
 * those alone, all checked against a count of the test's own from the welcome's trees;
 * a server restarted mid-stream brings the same scene, and the client the same trees and
 * circle, on the same run, not said again. */
#include <math.h>

#include "check.h"
#include "ctl.h"
#include "kiosk_fixture.h"

#define SCENE      "slow_client_scene.json"
#define HOLD_TREES 100

/* What the test finds from the welcome on its own: the scene's centre, the distance of
 * the HOLD_TREES-th nearest tree and of the next. */
static struct {
    uint32_t n;
    double cx, cy, r_held_m, r_next_m;
} want;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The welcome's trees over a raw connection of the test's own: 0 or -1. */
static int count_from_welcome(void)
{
    wsraw c = { .fd = -1 };
    if (wsraw_open(&c, kf_port, 0)) {
        return -1;
    }
    wsraw_text(&c, "{\"type\": \"hello\", \"protocol\": 1, \"role\": \"viewer\"}");
    uint8_t *m = NULL;
    size_t len = 0;
    int op = wsraw_recv(&c, &m, &len, 30000);
    ctl_msg msg = { 0 };
    int rc =
        op == 1 ? ctl_decode((const char *)m, len, CTL_MAX_SERVER_BYTES, &msg, NULL, NULL) : -1;
    free(m);
    wsraw_close(&c);
    if (rc != 0 || msg.type != CTL_WELCOME) {
        ctl_msg_fini(&msg);
        return -1;
    }
    const ctl_welcome *w = &msg.u.welcome;
    want.n = w->n_instances;
    double sx = 0.0, sy = 0.0;
    for (uint32_t t = 0; t < w->n_instances; t++) {
        sx += (double)w->instances[t].pos[0];
        sy += (double)w->instances[t].pos[1];
    }
    want.cx = sx / w->n_instances;
    want.cy = sy / w->n_instances;
    double *d = malloc(w->n_instances * sizeof *d);
    for (uint32_t t = 0; t < w->n_instances; t++) {
        d[t] = hypot((double)w->instances[t].pos[0] - want.cx,
                     (double)w->instances[t].pos[1] - want.cy);
    }
    qsort(d, w->n_instances, sizeof *d, cmp_double);
    want.r_held_m = d[HOLD_TREES - 1];
    want.r_next_m = d[HOLD_TREES];
    free(d);
    ctl_msg_fini(&msg);
    return 0;
}

static pid_t start_client(const char *name, const char *frames, const char *lang, char *log,
                          size_t cap)
{
    char url[64], cache[300], shot[300];
    snprintf(log, cap, "%s/%s.log", kf_dir, name);
    snprintf(url, sizeof url, "ws://127.0.0.1:%d", kf_port);
    snprintf(cache, sizeof cache, "%s/cache", kf_dir);
    snprintf(shot, sizeof shot, "%s/%s.png", kf_dir, name);
    unlink(log); /* a log of an earlier run is not this one's */
    char *argv[] = { GALE_CLIENT_EXE, "--url",        url,       "--headless",  "--frames",
                     (char *)frames,  "--size",       "320x180", "--max-trees", "100",
                     "--lang",        (char *)lang,   "--wait",  "150",         "--cache",
                     cache,           "--screenshot", shot,      NULL };
    return proc_spawn(argv, log);
}

/* The number after `after` on the last line holding it, NAN if none. */
static double log_number(const char *log, const char *after)
{
    FILE *f = fopen(log, "r");
    char line[2048];
    double v = NAN;
    while (f && fgets(line, sizeof line, f)) {
        const char *p = strstr(line, after);
        if (p) {
            v = atof(p + strlen(after));
        }
    }
    if (f) {
        fclose(f);
    }
    return v;
}

static double metric(const char *name)
{
    char *body = NULL, key[128];
    double v = -1.0;
    snprintf(key, sizeof key, "\n%s ", name);
    if (wsraw_http_get(kf_port, "/metrics", &body) == 200 && body && strstr(body, key)) {
        v = atof(strstr(body, key) + strlen(key));
    }
    free(body);
    return v;
}

/* What the client's log says of the trees it holds, against the test's count. */
static void check_held(const char *log)
{
    char said[160];
    snprintf(said, sizeof said,
             "the scene has %u trees, more than this client holds "
             "(--max-trees 100): holding the 100 nearest",
             want.n);
    CHECK(proc_log_count(log, said) == 1);
    /* the point is the scene's centre, the radius the 100th tree's */
    FILE *f = fopen(log, "r");
    char line[2048];
    double cx = NAN, cy = NAN, r = NAN;
    while (f && fgets(line, sizeof line, f)) {
        const char *p = strstr(line, "holding the 100 nearest (");
        if (p) {
            sscanf(p, "holding the 100 nearest (%lf, %lf), within %lf m", &cx, &cy, &r);
        }
    }
    if (f) {
        fclose(f);
    }
    CHECK_NEAR(cx, want.cx, 0.0051);
    CHECK_NEAR(cy, want.cy, 0.0051);
    CHECK_NEAR(r, want.r_held_m, 0.0051); /* printed to the centimetre */
    /* the client holds and draws those trees alone, and the server streams them alone */
    CHECK(log_number(log, "trees held ") == HOLD_TREES);
    CHECK(log_number(log, "trees a snapshot ") == HOLD_TREES);
    CHECK(log_number(log, "tree-count mismatches ") == 0);
    CHECK(proc_log_count(log, "; trying ") == 0);
}

static void test_holds_nearest(void)
{
    char log[300];
    double views0 = metric("gale_view_snapshots_total");
    pid_t pid = start_client("held", "30", "en", log, sizeof log);
    int status = proc_wait_exit(pid, 300.0);
    CHECK(status == 0);
    check_held(log);
    CHECK(log_number(log, "views sent ") == 1);
    /* what the renderer held: trees at each level and culled add up to the trees held */
    double full = log_number(log, "trees_full "), thin = log_number(log, "trees_thin ");
    double imp = log_number(log, "impostors "), culled = log_number(log, "culled ");
    CHECK(full + thin + imp + culled == HOLD_TREES);
    CHECK(full > 0);
    char hud[96];
    snprintf(hud, sizeof hud, "hud: Reduced view: the 100 nearest of %u trees", want.n);
    CHECK(proc_log_count(log, hud) >= 1);
    /* the server streamed a view of its own for it */
    CHECK(views0 >= 0.0 && metric("gale_view_snapshots_total") > views0);
    if (check_failures) {
        proc_dump(log);
    }
}

/* The server restarts on its port: the client reconnects to the same scene, holds the
 * same trees and asks for the same circle again, without saying it twice. */
static void test_reconnect_same(void)
{
    char log[300], port[16];
    pid_t pid = start_client("again", "1000000", "ht", log, sizeof log);
    CHECK(proc_wait_log(log, "receiving state", 1, 200.0));
    snprintf(port, sizeof port, "%d", kf_port);
    kf_stop_server();
    CHECK(proc_wait_log(log, "connection lost", 1, 30.0));
    const char *extra[] = { "--port", port, NULL };
    CHECK(kf_start_server(SCENE, extra) == 0);
    CHECK(proc_wait_log(log, "receiving state", 2, 200.0));
    sleep(3); /* the circle sent again and the stream following it */
    kill(pid, SIGTERM);
    CHECK(proc_wait_exit(pid, 60.0) == 0);
    CHECK(proc_log_count(log, "welcome as viewer") == 2);
    CHECK(log_number(log, "connects ") == 2);
    CHECK(log_number(log, "views sent ") == 2);
    check_held(log);
    char hud[96];
    snprintf(hud, sizeof hud, "hud: Vi redui: 100 pyebwa ki pi pre yo sou %u", want.n);
    CHECK(proc_log_count(log, hud) >= 1);
    if (check_failures) {
        proc_dump(log);
    }
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        /* CI runs the suite under xvfb-run (deploy/test.sh): no display there is a broken
           setup, not a reason to pass */
        if (getenv("CI")) {
            fprintf(stderr, "test_client_hold_live: CI is set but there is no DISPLAY\n");
            return 1;
        }
        fprintf(stderr, "test_client_hold_live: no DISPLAY (run under xvfb-run); skipped\n");
        return 77;
    }
    kf_init("client_hold_live");
    signal(SIGPIPE, SIG_IGN);
    if (kf_start_server(SCENE, NULL) != 0) {
        fprintf(stderr, "gale-server did not start\n");
        return 1;
    }
    if (count_from_welcome() != 0) {
        fprintf(stderr, "test_client_hold_live: no welcome read\n");
        kf_stop_server();
        return 1;
    }
    fprintf(stderr,
            "scene: %u trees, centre (%.3f, %.3f), the 100th nearest %.3f m, the next "
            "%.3f m\n",
            want.n, want.cx, want.cy, want.r_held_m, want.r_next_m);
    /* the count is only a count where the 100th and 101st are apart */
    CHECK(want.n > HOLD_TREES && want.r_next_m > want.r_held_m + 0.01);
    RUN(test_holds_nearest);
    RUN(test_reconnect_same);
    kf_stop_server();
    return check_report();
}
