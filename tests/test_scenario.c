/* Scenarios: the shipped files load; a steady wind's conventions; the hurricane at the
 * scene against the Holland profile (surface and land reduction, inflow angle, both
 * hemispheres, forward-motion asymmetry); replays of Andrew and Charley (the wind rises,
 * the eye is calm, the direction reverses); time compression; kiosk overrides ramp;
 * determinism; bad files with their exact messages. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "holland.h"
#include "scenario.h"

#define CONFIGS GALE_SOURCE_DIR "/configs/scenarios/"

static scenario *parse(const char *json)
{
    gale_err err = { 0 };
    scenario *s = scenario_parse("t.json", json, strlen(json), &err);
    if (!s) {
        fprintf(stderr, "unexpected error: %s\n", err.msg);
    }
    return s;
}

/* Smallest angle between two directions [deg], in [0, 180]. */
static double angle_between(double a, double b)
{
    double d = fmod(fabs(a - b), 360.0);
    return d > 180.0 ? 360.0 - d : d;
}

static void test_shipped_files(void)
{
    scenario *s;
    static const char *const files[] = { "calm",         "breeze",      "gusty",         "storm",
                                         "andrew1992",   "charley2004", "cat3-synthetic", "cat1",
                                         "cat2",         "cat3",        "cat4",           "cat5",
                                         "laborday1935", "camille1969", "hugo1989",
                                         "katrina2005",  "wilma2005",   "ike2008",
                                         "harvey2017",   "irma2017",    "maria2017",
                                         "michael2018",  "laura2020",   "ida2021",
                                         "ian2022" };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, CONFIGS "%s.json", files[i]);
        gale_err err = { 0 };
        s = scenario_load(path, &err);
        CHECK(s != NULL);
        if (!s) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        scenario_state st;
        scenario_eval(s, 1.0, &st);
        CHECK(isfinite(st.sustained_ms) && st.sustained_ms >= 0.0);
        CHECK(st.inflow.z0_m > 0.0f);
        scenario_destroy(s);
    }
    /* gusty.json carries two force balls */
    s = scenario_load(CONFIGS "gusty.json", NULL);
    const wind_ball *balls = NULL;
    CHECK(s && scenario_balls(s, &balls) == 2);
    if (s && balls) {
        CHECK_NEAR(balls[1].center[1], -20.0, 0.0);
        CHECK_NEAR(balls[1].radius_m, 12.0, 0.0);
        CHECK_NEAR(balls[1].force[2], 0.5, 0.0);
        CHECK_NEAR(balls[1].jitter_m, 10.0, 0.0);
    }
    scenario_destroy(s);
    /* the steady ones classify as their names say */
    s = scenario_load(CONFIGS "breeze.json", NULL);
    scenario_state st;
    scenario_eval(s, 0.0, &st);
    CHECK(st.beaufort == 3);
    scenario_destroy(s);
    s = scenario_load(CONFIGS "storm.json", NULL);
    scenario_eval(s, 0.0, &st);
    CHECK(st.category == SAFFIR_TS);
    CHECK(st.beaufort >= 10);
    scenario_destroy(s);
    /* the kiosk's Category buttons: each mean wind inside its Saffir-Simpson band */
    for (int c = 1; c <= 5; c++) {
        char path[512];
        snprintf(path, sizeof path, CONFIGS "cat%d.json", c);
        s = scenario_load(path, NULL);
        CHECK(s != NULL);
        if (!s) {
            continue;
        }
        scenario_eval(s, 0.0, &st);
        CHECK(st.category == (saffir_class)(SAFFIR_CAT1 + c - 1));
        CHECK(saffir_classify(scenario_steady_ms(s)) == (saffir_class)(SAFFIR_CAT1 + c - 1));
        char title[32];
        snprintf(title, sizeof title, "Category %d (steady)", c);
        CHECK(!strcmp(scenario_name(s), title));
        scenario_destroy(s);
    }
}

static void test_steady(void)
{
    scenario *s = parse("{\"kind\":\"steady\",\"seed\":9,\"z0_m\":0.5,\"zmin_m\":4,"
                        "\"steady\":{\"u10_ms\":10,\"dir_from_deg\":270},"
                        "\"gust\":{\"enabled\":false}}");
    if (!s) {
        CHECK(0);
        return;
    }
    scenario_state st;
    scenario_eval(s, 3.0, &st);
    /* from the west = toward +x (east): dir_rad 0 */
    CHECK_NEAR(st.inflow.dir_rad, 0.0, 1e-6);
    CHECK_NEAR(st.inflow.u10_ms, 10.0, 1e-6);
    CHECK_NEAR(st.inflow.z0_m, 0.5, 1e-6);
    CHECK_NEAR(st.inflow.zmin_m, 4.0, 1e-6);
    CHECK_NEAR(st.inflow.gust[0] + st.inflow.gust[1] + st.inflow.gust[2], 0.0, 0.0);
    CHECK_NEAR(st.dir_from_deg, 270.0, 1e-9);
    CHECK_NEAR(st.gust_ms, 10.0, 1e-9);
    CHECK(st.distance_km < 0.0);
    CHECK(st.storm_category == -1);
    CHECK(scenario_get_kind(s) == SCENARIO_STEADY);
    CHECK(scenario_duration_s(s) == 0.0);
    CHECK_STR_HAS(scenario_name(s), "t.json");
    scenario_destroy(s);
    /* from the north = toward −y: dir_rad −π/2 */
    s = parse("{\"steady\":{\"u10_ms\":5,\"dir_from_deg\":0}}");
    scenario_eval(s, 0.0, &st);
    CHECK_NEAR(st.inflow.dir_rad, -M_PI / 2.0, 1e-6);
    CHECK_NEAR(st.dir_from_deg, 0.0, 1e-9);
    CHECK_NEAR(st.turbulence_intensity, 1.0 / log(10.0 / 0.3), 1e-9);
    scenario_destroy(s);
}

/* A storm parked (two equal track points) with its centre at (x_km, y_km) from the scene. */
static scenario *parked(double x_km, double y_km, double lat, const char *extra)
{
    char buf[1024];
    snprintf(buf, sizeof buf,
             "{\"kind\":\"hurricane\",\"gust\":{\"enabled\":false},\"hurricane\":{"
             "\"site\":{\"lat_deg\":%g},\"ambient_hpa\":1013%s,\"track\":["
             "{\"t_min\":0,\"x_km\":%g,\"y_km\":%g,\"p_hpa\":922,\"rmax_km\":18.5,"
             "\"vmax_ms\":74.6},"
             "{\"t_min\":60,\"x_km\":%g,\"y_km\":%g,\"p_hpa\":922,\"rmax_km\":18.5,"
             "\"vmax_ms\":74.6}]}}",
             lat, extra, x_km, y_km, x_km, y_km);
    return parse(buf);
}

static void test_vortex_at_scene(void)
{
    /* centre 37 km east of the scene, northern hemisphere, over land */
    scenario *s = parked(37.0, 0.0, 25.5, "");
    if (!s) {
        CHECK(0);
        return;
    }
    scenario_state st;
    scenario_eval(s, 0.0, &st);
    holland_vortex v = { .pc_pa = 92200.0,
                         .pn_pa = 101300.0,
                         .rmax_m = 18500.0,
                         .rho = 1.15,
                         .f = holland_coriolis(25.5) };
    v.b = holland_b(74.6 / 0.9, v.pn_pa - v.pc_pa, v.rho);
    CHECK_NEAR(v.b, 2.36, 0.01);
    /* PHYSICS.md: surface = 0.9 × gradient, × 0.8 over land */
    CHECK_NEAR(st.sustained_ms, 0.9 * 0.8 * holland_gradient_wind(&v, 37000.0), 1e-6);
    CHECK_NEAR(st.pressure_hpa, holland_pressure(&v, 37000.0) / 100.0, 1e-9);
    CHECK_NEAR(st.distance_km, 37.0, 1e-9);
    CHECK(st.storm_category == SAFFIR_CAT5);
    /* counter-clockwise: west of the centre the wind blows from the north, turned 20°
     * toward the centre → from 340° */
    CHECK_NEAR(st.dir_from_deg, 340.0, 1e-6);
    scenario_destroy(s);

    /* over water: only the 0.9 */
    s = parked(37.0, 0.0, 25.5, "");
    scenario_destroy(s);
    s = parse("{\"kind\":\"hurricane\",\"gust\":{\"enabled\":false},\"hurricane\":{"
              "\"site\":{\"lat_deg\":25.5,\"over_land\":false},\"inflow_angle_deg\":0,"
              "\"track\":[{\"t_min\":0,\"x_km\":0,\"y_km\":-37,\"p_hpa\":922,"
              "\"rmax_km\":18.5,\"vmax_ms\":74.6},{\"t_min\":60,\"x_km\":0,\"y_km\":-37,"
              "\"p_hpa\":922,\"rmax_km\":18.5,\"vmax_ms\":74.6}]}}");
    scenario_eval(s, 0.0, &st);
    CHECK_NEAR(st.sustained_ms, 0.9 * holland_gradient_wind(&v, 37000.0), 1e-6);
    /* north of the centre, no inflow angle: blows toward the west, from 90° */
    CHECK_NEAR(st.dir_from_deg, 90.0, 1e-6);
    scenario_destroy(s);

    /* southern hemisphere: clockwise, so west of the centre the wind comes from the
     * south, turned 20° inward → from 200° */
    s = parked(37.0, 0.0, -25.5, "");
    scenario_eval(s, 0.0, &st);
    CHECK_NEAR(st.dir_from_deg, 200.0, 1e-6);
    scenario_destroy(s);

    /* the eye: centre 2 km away is calm; the pressure is near the central pressure */
    s = parked(2.0, 0.0, 25.5, "");
    scenario_eval(s, 0.0, &st);
    CHECK_NEAR(st.sustained_ms, 0.0, 0.01);
    CHECK_NEAR(st.pressure_hpa, 922.0, 0.01);
    scenario_destroy(s);
}

/* Peak speed at the scene as a storm moving north at vt m/s passes with its centre at
 * x_km (negative: west of the scene, which is then right of track). */
static double pass_peak(double x_km, double vt, double asym)
{
    char buf[1024];
    double y0 = -vt * 3600.0 / 1000.0 * 2.0, y1 = -y0;
    snprintf(buf, sizeof buf,
             "{\"kind\":\"hurricane\",\"gust\":{\"enabled\":false},\"hurricane\":{"
             "\"site\":{\"lat_deg\":25},\"asymmetry\":%g,\"track\":["
             "{\"t_min\":-120,\"x_km\":%g,\"y_km\":%g,\"p_hpa\":950,\"rmax_km\":20,"
             "\"vmax_ms\":55},{\"t_min\":120,\"x_km\":%g,\"y_km\":%g,\"p_hpa\":950,"
             "\"rmax_km\":20,\"vmax_ms\":55}]}}",
             asym, x_km, y0, x_km, y1);
    scenario *s = parse(buf);
    if (!s) {
        return NAN;
    }
    double best = 0.0;
    scenario_state st;
    for (double t = 0.0; t <= 240.0 * 60.0; t += 10.0) {
        scenario_eval(s, t, &st);
        if (st.sustained_ms > best) {
            best = st.sustained_ms;
        }
    }
    scenario_destroy(s);
    return best;
}

static void test_asymmetry(void)
{
    /* centre passing 20 km (= Rmax) west vs east of the scene at V_t = 8 m/s: the right
     * side is stronger by about 2 × 0.5 V_t = 8 m/s (the inflow angle makes the motion
     * vector not quite parallel to the wind, so allow ±1.5 m/s) */
    double right = pass_peak(-20.0, 8.0, 0.5), left = pass_peak(20.0, 8.0, 0.5);
    CHECK_NEAR(right - left, 8.0, 1.5);
    /* no asymmetry: mirror images */
    CHECK_NEAR(pass_peak(-20.0, 8.0, 0.0), pass_peak(20.0, 8.0, 0.0), 1e-6);
}

typedef struct replay_summary {
    double peak1, t_peak1, dir1; /* first eyewall: speed, time [s], direction */
    double peak2, t_peak2, dir2; /* second eyewall */
    double eye_min;              /* slowest wind between the two peaks */
    double start_speed, min_pressure;
    double duration;
} replay_summary;

static int replay(const char *file, replay_summary *r)
{
    gale_err err = { 0 };
    scenario *s = scenario_load(file, &err);
    if (!s) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    memset(r, 0, sizeof *r);
    r->duration = scenario_duration_s(s);
    int n = (int)(r->duration / 0.1) + 1;
    double *spd = malloc((size_t)n * sizeof *spd), *dir = malloc((size_t)n * sizeof *dir);
    double *dist = malloc((size_t)n * sizeof *dist);
    if (!spd || !dir || !dist || n < 2) {
        free(spd);
        free(dir);
        free(dist);
        scenario_destroy(s);
        return -1;
    }
    for (int i = 0; i < n; i++) {
        spd[i] = dir[i] = dist[i] = 0.0;
    }
    r->min_pressure = 1e9;
    int i_near = 0;
    for (int i = 0; i < n; i++) {
        scenario_state st;
        scenario_eval(s, i * 0.1, &st);
        spd[i] = st.sustained_ms;
        dir[i] = st.dir_from_deg;
        dist[i] = st.distance_km;
        if (st.pressure_hpa < r->min_pressure) {
            r->min_pressure = st.pressure_hpa;
        }
        if (dist[i] < dist[i_near]) {
            i_near = i;
        }
    }
    r->start_speed = spd[0];
    int i1 = 0, i2 = n - 1;
    for (int i = 0; i < i_near; i++) {
        if (spd[i] > spd[i1]) {
            i1 = i;
        }
    }
    for (int i = n - 1; i > i_near; i--) {
        if (spd[i] > spd[i2]) {
            i2 = i;
        }
    }
    r->peak1 = spd[i1];
    r->t_peak1 = i1 * 0.1;
    r->dir1 = dir[i1];
    r->peak2 = spd[i2];
    r->t_peak2 = i2 * 0.1;
    r->dir2 = dir[i2];
    r->eye_min = 1e9;
    for (int i = i1; i <= i2; i++) {
        if (spd[i] < r->eye_min) {
            r->eye_min = spd[i];
        }
    }
    free(spd);
    free(dir);
    free(dist);
    scenario_destroy(s);
    return 0;
}

static void test_replay_andrew(void)
{
    replay_summary r;
    if (replay(CONFIGS "andrew1992.json", &r) < 0) {
        CHECK(0);
        return;
    }
    fprintf(stderr,
            "andrew: %.0f s, start %.1f m/s, eyewall %.1f m/s at %.0f s from %.0f°, eye %.2f "
            "m/s, eyewall %.1f m/s at %.0f s from %.0f°, %.1f hPa\n",
            r.duration, r.start_speed, r.peak1, r.t_peak1, r.dir1, r.eye_min, r.peak2, r.t_peak2,
            r.dir2, r.min_pressure);
    /* the wind rises: the eyewall at least 4× the opening wind, major hurricane force
     * (Category 3+) even after the land reduction */
    CHECK(r.peak1 > 4.0 * r.start_speed);
    CHECK(saffir_classify(r.peak1) >= SAFFIR_CAT3);
    CHECK(saffir_classify(r.peak2) >= SAFFIR_CAT3);
    /* the calm eye */
    CHECK(r.eye_min < 0.05 * r.peak1);
    /* the reversal: the back eyewall blows from the opposite side */
    CHECK(angle_between(r.dir1, r.dir2) >= 120.0);
    /* the central pressure is felt in the eye (922–926 hPa on the track) */
    CHECK(r.min_pressure < 930.0);
    /* time compression: a replay of minutes, not hours */
    CHECK(r.duration > 120.0 && r.duration < 900.0);
}

static void test_replay_charley(void)
{
    replay_summary r;
    if (replay(CONFIGS "charley2004.json", &r) < 0) {
        CHECK(0);
        return;
    }
    fprintf(stderr,
            "charley: %.0f s, start %.1f m/s, eyewall %.1f m/s from %.0f°, eye %.2f m/s, "
            "eyewall %.1f m/s from %.0f°, %.1f hPa\n",
            r.duration, r.start_speed, r.peak1, r.dir1, r.eye_min, r.peak2, r.dir2, r.min_pressure);
    CHECK(r.peak1 > 4.0 * r.start_speed);
    CHECK(saffir_classify(r.peak1) >= SAFFIR_CAT2);
    CHECK(r.eye_min < 0.1 * r.peak1);
    CHECK(angle_between(r.dir1, r.dir2) >= 120.0);
    CHECK(r.duration > 120.0 && r.duration < 900.0);
}

/* The storm library (configs/scenarios/README.md's table, from gale-wind --timeline): each
 * replay lasts 5-8 minutes, the wind at the site rises to an eyewall, falls to the calm of
 * the eye (within 6 km of the site) at about the landfall row's pressure and returns from
 * the other side; the eyewalls' peaks are the table's to 0.3 m/s (it samples each second). */
static void test_replay_library(void)
{
    static const struct {
        const char *file;
        double peak1, peak2, p_hpa; /* README figures; the landfall row's pressure */
    } lib[] = {
        { "laborday1935", 65.1, 66.4, 892 }, { "camille1969", 60.5, 61.2, 900 },
        { "hugo1989", 46.8, 45.3, 934 },     { "katrina2005", 45.2, 45.6, 920 },
        { "wilma2005", 40.5, 40.8, 950 },    { "ike2008", 37.0, 37.4, 950 },
        { "harvey2017", 46.0, 43.0, 937 },   { "irma2017", 46.7, 47.1, 931 },
        { "maria2017", 55.3, 50.5, 920 },    { "michael2018", 55.7, 58.0, 919 },
        { "laura2020", 51.7, 50.8, 939 },    { "ida2021", 52.5, 53.1, 931 },
        { "ian2022", 54.8, 48.8, 941 },
    };
    for (size_t i = 0; i < sizeof lib / sizeof lib[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, CONFIGS "%s.json", lib[i].file);
        replay_summary r;
        if (replay(path, &r) < 0) {
            CHECK(0);
            continue;
        }
        fprintf(stderr,
                "%-13s %.0f s, start %.1f, eyewall %.1f from %.0f°, eye %.2f, eyewall %.1f from "
                "%.0f°, %.1f hPa\n",
                lib[i].file, r.duration, r.start_speed, r.peak1, r.dir1, r.eye_min, r.peak2,
                r.dir2, r.min_pressure);
        CHECK(r.duration >= 300.0 && r.duration <= 480.0);
        CHECK(fabs(r.peak1 - lib[i].peak1) < 0.3 && fabs(r.peak2 - lib[i].peak2) < 0.3);
        CHECK(r.peak1 > 1.4 * r.start_speed);
        CHECK(r.eye_min < 0.1 * r.peak1);
        CHECK(angle_between(r.dir1, r.dir2) >= 120.0);
        CHECK(r.min_pressure < lib[i].p_hpa + 5.0);
    }
}

static void test_time_compression(void)
{
    scenario *s = scenario_load(CONFIGS "andrew1992.json", NULL);
    if (!s) {
        CHECK(0);
        return;
    }
    /* start −160 min, end +175 min, time_scale 50: 335 × 60 / 50 s */
    CHECK_NEAR(scenario_duration_s(s), 335.0 * 60.0 / 50.0, 1e-9);
    scenario_state st;
    scenario_eval(s, 60.0, &st);
    CHECK_NEAR(st.storm_min, -160.0 + 60.0 * 50.0 / 60.0, 1e-9);
    CHECK_STR_HAS(st.clock_utc, "1992-08-24 07:15Z");
    CHECK(!st.finished);
    scenario_eval(s, 1e4, &st);
    CHECK(st.finished);
    CHECK_NEAR(st.storm_min, 175.0, 1e-9);
    /* a restart at server time 1000 s begins the replay again */
    scenario_restart(s, 1000.0);
    scenario_eval(s, 1000.0, &st);
    CHECK_NEAR(st.storm_min, -160.0, 1e-9);
    CHECK(!st.finished);
    scenario_destroy(s);
}

static void test_overrides(void)
{
    scenario *s = parse("{\"seed\":3,\"dial_rate_ms2\":4,"
                        "\"steady\":{\"u10_ms\":5,\"dir_from_deg\":270},"
                        "\"gust\":{\"enabled\":false}}");
    if (!s) {
        CHECK(0);
        return;
    }
    scenario_state st;
    gale_err err = { 0 };
    scenario_eval(s, 0.0, &st);
    CHECK(scenario_set_category(s, SAFFIR_CAT3, &err) == 0);
    double target = saffir_representative_ms(SAFFIR_CAT3);
    /* ramps at 4 m/s per second: never a jump */
    double prev = 5.0;
    for (double t = 0.1; t < 30.0; t += 0.1) {
        scenario_eval(s, t, &st);
        CHECK(st.sustained_ms - prev <= 4.0 * 0.1 + 1e-9);
        CHECK(st.override_active);
        prev = st.sustained_ms;
    }
    CHECK_NEAR(st.sustained_ms, target, 1e-9);
    CHECK(st.category == SAFFIR_CAT3);
    CHECK_STR_HAS(st.category_name, "Category 3");
    /* direction hold: from the south */
    CHECK(scenario_set_direction(s, 180.0, &err) == 0);
    for (double t = 30.0; t < 60.0; t += 0.1) {
        scenario_eval(s, t, &st);
    }
    CHECK_NEAR(st.dir_from_deg, 180.0, 1e-6);
    CHECK_NEAR(st.sustained_ms, target, 1e-6);
    /* cleared: back to the scripted 5 m/s from the west, ramped */
    scenario_clear_override(s);
    scenario_eval(s, 60.1, &st);
    CHECK(st.sustained_ms > 40.0);
    CHECK(!st.override_active);
    for (double t = 60.2; t < 120.0; t += 0.1) {
        scenario_eval(s, t, &st);
    }
    CHECK_NEAR(st.sustained_ms, 5.0, 1e-9);
    CHECK_NEAR(st.dir_from_deg, 270.0, 1e-9);
    /* bad kiosk values: exact messages, nothing changes */
    CHECK(scenario_set_dial(s, 120.0, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "scenario t.json: dial: expected a sustained wind in [0, 90] m/s, "
                           "got 120");
    CHECK(scenario_set_dial(s, NAN, &err) == GALE_E_RANGE);
    CHECK(scenario_set_category(s, (saffir_class)7, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "scenario t.json: category: expected a class in [0, 6], got 7");
    CHECK(scenario_set_direction(s, -1.0, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "scenario t.json: direction: expected degrees in [0, 360], got -1");
    scenario_eval(s, 120.1, &st);
    CHECK(!st.override_active);
    scenario_destroy(s);
}

static void test_determinism(void)
{
    scenario *a = scenario_load(CONFIGS "gusty.json", NULL);
    scenario *b = scenario_load(CONFIGS "gusty.json", NULL);
    scenario *c = parse("{\"seed\":4,\"steady\":{\"u10_ms\":11,\"dir_from_deg\":270},"
                        "\"gust\":{\"intensity\":0.35,\"length_m\":40}}");
    if (!a || !b || !c) {
        CHECK(0);
        scenario_destroy(a);
        scenario_destroy(b);
        scenario_destroy(c);
        return;
    }
    int same = 1, differ = 0;
    static scenario_state first[101];
    for (int i = 0; i < 600; i++) {
        scenario_state sa, sb, sc;
        scenario_eval(a, i / 60.0, &sa);
        scenario_eval(b, i / 60.0, &sb);
        scenario_eval(c, i / 60.0, &sc);
        same &= memcmp(&sa.inflow, &sb.inflow, sizeof sa.inflow) == 0;
        differ |= sa.inflow.gust[0] != sc.inflow.gust[0];
        if (i <= 100) {
            first[i] = sa;
        }
    }
    CHECK(same);
    CHECK(differ);
    /* going back in time replays the gusts a produced the first time over the same
       seconds, not the ones that would follow t = 10 s */
    int replayed = 1, moved = 0;
    for (int i = 0; i <= 100; i++) {
        scenario_state s1;
        scenario_eval(a, i / 60.0, &s1);
        replayed &= memcmp(&s1.inflow, &first[i].inflow, sizeof s1.inflow) == 0;
        moved |= first[i].inflow.gust[0] != first[0].inflow.gust[0];
    }
    CHECK(replayed);
    CHECK(moved); /* the gusts vary over those seconds, so the comparison means something */
    scenario_destroy(a);
    scenario_destroy(b);
    scenario_destroy(c);
}

static void expect_bad(const char *json, const char *msg)
{
    gale_err err = { 0 };
    scenario *s = scenario_parse("bad.json", json, strlen(json), &err);
    CHECK(s == NULL);
    CHECK(err.code < 0);
    if (!strstr(err.msg, msg)) {
        fprintf(stderr, "  json: %s\n  got:  %s\n", json, err.msg);
    }
    CHECK_STR_HAS(err.msg, msg);
    scenario_destroy(s);
}

#define PT(t, p) \
    "{\"t_min\":" #t ",\"x_km\":0,\"y_km\":0,\"p_hpa\":" #p ",\"rmax_km\":20,\"vmax_ms\":50}"
#define HUR(body) "{\"kind\":\"hurricane\",\"hurricane\":{\"site\":{\"lat_deg\":25}," body "}}"

/* A replay's pause holds its storm clock, play runs it from there; a jump while paused
 * moves the held minute; the start set at load time (gale-server --start-min,
 * --replay-speed) is where a restart goes, at that speed. */
static void test_pause_and_start(void)
{
    scenario *s = scenario_load(CONFIGS "andrew1992.json", NULL);
    CHECK(s != NULL);
    if (!s) {
        return;
    }
    scenario_state st;
    scenario_eval(s, 10.0, &st);
    const double at10 = st.storm_min; /* -160 + 10 s x 50 / 60 */
    CHECK_NEAR(at10, -160.0 + 500.0 / 60.0, 1e-9);
    CHECK(!st.paused);
    CHECK(scenario_replay_pause(s, 10.0, true, NULL) == 0);
    scenario_eval(s, 20.0, &st);
    CHECK(st.paused && st.storm_min == at10);
    CHECK(scenario_replay_set(s, 20.0, true, -100.0, false, 0.0, NULL) == 0);
    scenario_eval(s, 25.0, &st);
    CHECK(st.paused && st.storm_min == -100.0);
    CHECK(scenario_replay_pause(s, 25.0, false, NULL) == 0);
    scenario_eval(s, 31.0, &st);
    CHECK(!st.paused);
    CHECK_NEAR(st.storm_min, -100.0 + 6.0 * 50.0 / 60.0, 1e-9);
    /* the configured start: minute -30 at x10; a kiosk's speed does not outlive a restart */
    CHECK(scenario_set_start(s, 40.0, true, -30.0, true, 10.0, NULL) == 0);
    scenario_eval(s, 46.0, &st);
    CHECK_NEAR(st.storm_min, -30.0 + 1.0, 1e-9);
    CHECK(scenario_replay_set(s, 46.0, false, 0.0, true, 100.0, NULL) == 0);
    CHECK(scenario_replay_pause(s, 46.0, true, NULL) == 0);
    scenario_restart(s, 50.0);
    scenario_eval(s, 56.0, &st);
    CHECK(!st.paused);
    CHECK_NEAR(st.replay_speed, 10.0, 0.0);
    CHECK_NEAR(st.storm_min, -30.0 + 1.0, 1e-9);
    scenario_destroy(s);
    /* a steady scenario has no clock to hold */
    s = scenario_load(CONFIGS "gusty.json", NULL);
    gale_err e = { 0 };
    CHECK(s && scenario_replay_pause(s, 0.0, true, &e) == GALE_E_STATE);
    CHECK_STR_HAS(e.msg, "not a hurricane replay");
    CHECK(s && scenario_set_start(s, 0.0, true, 0.0, false, 0.0, NULL) == GALE_E_STATE);
    scenario_destroy(s);
}

/* A start from rest and a jump into a storm's core move the wind at the dial's rate
 * (scenario_ramp_from): |Δu| ≤ rate·dt on every eval until the scripted wind is reached,
 * then the scripted wind exactly. */
static void test_ramps(void)
{
    scenario *s = parse("{\"kind\":\"steady\",\"dial_rate_ms2\":5,"
                        "\"steady\":{\"u10_ms\":40,\"dir_from_deg\":270},"
                        "\"gust\":{\"enabled\":false}}");
    if (!s) {
        CHECK(0);
        return;
    }
    scenario_state st;
    scenario_restart(s, 10.0);
    scenario_ramp_from(s, 0.0, 0.0);
    int ramping = 0;
    for (int k = 0; k <= 40; k++) {
        const double t = 0.25 * k;
        scenario_eval(s, 10.0 + t, &st);
        const double want = 5.0 * t < 40.0 ? 5.0 * t : 40.0;
        CHECK_NEAR(st.sustained_ms, want, 1e-6);
        ramping += st.ramping;
    }
    CHECK(ramping == 32); /* 40 m/s at 5 m/s² is 8 s: the evals before it ramp */
    CHECK(!st.ramping);
    double w[2];
    scenario_last_wind(s, w);
    CHECK_NEAR(w[0], 40.0, 1e-6);
    CHECK_NEAR(w[1], 0.0, 1e-6);
    scenario_destroy(s);

    /* Andrew: from the eyewall, a jump into the eye falls at 4 m/s per second */
    s = scenario_load(CONFIGS "andrew1992.json", NULL);
    if (!s) {
        CHECK(0);
        return;
    }
    scenario_replay_set(s, 0.0, true, -18.0, true, 1.0, NULL);
    scenario_eval(s, 0.0, &st);
    scenario_eval(s, 0.1, &st);
    const double eyewall = st.sustained_ms;
    CHECK(eyewall > 45.0);
    scenario_replay_set(s, 0.1, true, 20.0, false, 0.0, NULL);
    double prev = eyewall;
    for (int k = 1; k <= 200 && st.sustained_ms > 10.0; k++) {
        scenario_eval(s, 0.1 + 0.1 * k, &st);
        CHECK(prev - st.sustained_ms <= 0.4 + 1e-6);
        prev = st.sustained_ms;
    }
    CHECK(st.sustained_ms <= 10.0); /* reached within 20 s */
    scenario_destroy(s);
}

static void test_bad_files(void)
{
    expect_bad("{\"steady\":{\"u10_ms\":5},\"colour\":1}", "bad.json: colour: unknown key");
    expect_bad("{\"steady\":{\"u10_ms\":5,\"speed\":1}}", "bad.json: steady.speed: unknown key");
    expect_bad("{\"steady\":{\"u10_ms\":\"fast\"}}",
               "bad.json: steady.u10_ms: expected a number, got a string");
    expect_bad("{\"steady\":{\"u10_ms\":95}}",
               "bad.json: steady.u10_ms: expected a number in [0, 90], got 95");
    expect_bad("{\"steady\":{\"dir_from_deg\":90}}",
               "bad.json: steady.u10_ms: required key missing");
    expect_bad("{\"kind\":\"steady\"}", "bad.json: steady: required key missing");
    expect_bad("{\"steady\":[]}", "bad.json: steady: expected an object, got an array");
    expect_bad("{\"kind\":\"tornado\"}",
               "bad.json: kind: expected \"steady\" or \"hurricane\", got \"tornado\"");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"seed\":1.5}",
               "bad.json: seed: expected an integer in [0, 9007199254740991], got 1.5");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"hurricane\":{}}",
               "bad.json: hurricane: not used by kind \"steady\"");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"gust\":{\"intensity\":2}}",
               "bad.json: gust.intensity: expected a number in [0, 1], got 2");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"gust\":{\"enabled\":1}}",
               "bad.json: gust.enabled: expected a boolean, got a number");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"balls\":[{\"center\":[0,0],\"radius_m\":1,"
               "\"force\":[0,0,0]}]}",
               "bad.json: balls[0].center");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"balls\":[{\"center\":[0,0,1],\"radius_m\":0,"
               "\"force\":[0,0,0]}]}",
               "bad.json: balls[0].radius_m: expected a number in [0.1, 10000], got 0");
    expect_bad("{\"steady\":{\"u10_ms\":5},\"z0_m\":0}",
               "bad.json: z0_m: expected a number in [0.001, 3], got 0");
    expect_bad("{\"kind\":\"hurricane\"}", "bad.json: hurricane: required key missing");
    expect_bad(HUR("\"track\":[" PT(0, 950) "]"),
               "bad.json: hurricane.track: expected 2 to 256 track points, got 1");
    expect_bad(HUR("\"track\":[" PT(0, 950) "," PT(0, 950) "]"),
               "bad.json: hurricane.track[1].t_min: expected a time after track[0] (0 min), "
               "got 0");
    expect_bad(HUR("\"track\":[" PT(0, 950) "," PT(60, 1020) "]"),
               "bad.json: hurricane.track[1].p_hpa: expected a central pressure below "
               "ambient_hpa (1013), got 1020");
    expect_bad(HUR("\"track\":[" PT(0, 950) "," PT(60, 840) "]"),
               "bad.json: hurricane.track[1].p_hpa: expected a number in [850, 1050], got 840");
    expect_bad(HUR("\"track\":[" PT(0, 950) ",{\"t_min\":60,\"lat_deg\":25,\"lon_deg\":-80,"
                                            "\"p_hpa\":950,\"rmax_km\":20,\"vmax_ms\":50}]"),
               "bad.json: hurricane.track[1]: expected x_km/y_km like track[0], got "
               "lat_deg/lon_deg");
    expect_bad(HUR("\"track\":[{\"t_min\":0,\"lat_deg\":25,\"x_km\":1,\"p_hpa\":950,"
                   "\"rmax_km\":20,\"vmax_ms\":50}," PT(60, 950) "]"),
               "bad.json: hurricane.track[0]: expected lat_deg/lon_deg or x_km/y_km, got both");
    expect_bad(HUR("\"track\":[" PT(0, 950) ",{\"t_min\":60,\"x_km\":0,\"y_km\":0,"
                                            "\"p_hpa\":950,\"rmax_km\":20}]"),
               "bad.json: hurricane.track[1].vmax_ms: required key missing");
    expect_bad(HUR("\"ref_utc\":\"24 Aug 1992\",\"track\":[" PT(0, 950) "," PT(60, 950) "]"),
               "bad.json: hurricane.ref_utc: expected a UTC time like \"1992-08-24T09:05Z\", "
               "got \"24 Aug 1992\"");
    expect_bad(HUR("\"start_min\":-10,\"track\":[" PT(0, 950) "," PT(60, 950) "]"),
               "bad.json: hurricane.start_min: expected a number in [0, 60], got -10");
    expect_bad(HUR("\"start_min\":30,\"end_min\":30,\"track\":[" PT(0, 950) "," PT(60, 950) "]"),
               "bad.json: hurricane.end_min: expected a time after start_min (30), got 30");
    expect_bad(HUR("\"time_scale\":0.5,\"track\":[" PT(0, 950) "," PT(60, 950) "]"),
               "bad.json: hurricane.time_scale: expected a number in [1, 10000], got 0.5");
    expect_bad(HUR("\"eye\":1,\"track\":[" PT(0, 950) "," PT(60, 950) "]"),
               "bad.json: hurricane.eye: unknown key");
    expect_bad("{\"kind\":\"hurricane\",\"hurricane\":{\"site\":{\"lat_deg\":95},\"track\":[]}}",
               "bad.json: hurricane.site.lat_deg: expected a number in [-70, 70], got 95");
    expect_bad("{\"kind\":\"hurricane\",\"hurricane\":{\"site\":{\"lat_deg\":25},\"track\":["
               "{\"t_min\":0,\"lat_deg\":25,\"lon_deg\":-80,\"p_hpa\":950,\"rmax_km\":20,"
               "\"vmax_ms\":50},{\"t_min\":60,\"lat_deg\":25,\"lon_deg\":-81,\"p_hpa\":950,"
               "\"rmax_km\":20,\"vmax_ms\":50}]}}",
               "bad.json: hurricane.site.lon_deg: required key missing");
    expect_bad("{\"steady\":{\"u10_ms\":5},}", "bad.json:1:24: invalid JSON");
    expect_bad("[1]", "bad.json: expected a JSON object at the top, got an array");
    expect_bad("{\"steady\":{\"u10_ms\":5}}\n{\"steady\":{\"u10_ms\":50}}",
               "bad.json:2:1: trailing bytes after the JSON object: expected the end of the file");
    expect_bad("{\"steady\":{\"u10_ms\":5}} ]", "bad.json:1:25: trailing bytes after the JSON "
                                                  "object: expected the end of the file");
    /* a missing file names the path */
    gale_err err = { 0 };
    CHECK(scenario_load("/nonexistent/x.json", &err) == NULL);
    CHECK_STR_HAS(err.msg, "/nonexistent/x.json: cannot open");
    /* embedded in a larger document, the key path carries the prefix */
    cfg_doc d;
    const char *scene = "{\"wind\":{\"steady\":{\"u10_ms\":-1}}}";
    CHECK(cfg_parse(&d, "scene.json", scene, strlen(scene), &err) == 0);
    CHECK(scenario_create(&d, cJSON_GetObjectItemCaseSensitive(d.root, "wind"), "scene.wind",
                          &err) == NULL);
    CHECK_STR_HAS(err.msg,
                  "scene.json: scene.wind.steady.u10_ms: expected a number in [0, 90], got -1");
    cfg_fini(&d);
}

int main(void)
{
    RUN(test_shipped_files);
    RUN(test_steady);
    RUN(test_vortex_at_scene);
    RUN(test_asymmetry);
    RUN(test_replay_andrew);
    RUN(test_replay_charley);
    RUN(test_replay_library);
    RUN(test_time_compression);
    RUN(test_overrides);
    RUN(test_determinism);
    RUN(test_pause_and_start);
    RUN(test_ramps);
    RUN(test_bad_files);
    return check_report();
}
