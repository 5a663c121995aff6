/* gale-client's kiosk panel (client/kiosk/kiosk_ui.c, kiosk_ui_msg.c, caption.c) as one JSON
 * object, for tests/web/test_kiosk_js.mjs to hold web/kiosk_scale.js and web/kiosk_text.js to:
 * the dial's bands, labels, sweep and top, its angle at speeds through every band and back,
 * the replay speeds, the messages a sequence of touches sends, the scenario WEATHER names
 * lit for a list of names, the caption of every class and force, the compass points. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "caption.h"
#include "lang.h"
#include "ctl.h"
#include "hud.h"
#include "kiosk_ui.h"
#include "wind_scale.h"

/* s as a JSON string (the texts here are printable UTF-8 without quotes or backslashes
 * but for what is escaped) */
static void str(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') {
            putchar('\\');
        }
        putchar(*s);
    }
    putchar('"');
}

static void message(kiosk_ui *ui, int act, float value, int index)
{
    kiosk_ui_action a = { .act = act, .value = value, .index = index };
    ctl_msg m;
    int rc = kiosk_ui_message(ui, &a, "t", &m);
    const ctl_wind *w = &m.u.wind;
    printf("{\"act\":%d,\"value\":%.9g,\"index\":%d,\"rc\":%d,\"type\":%d", act, (double)value, index,
           rc, m.type == CTL_RESET ? 1 : 0);
    if (m.type == CTL_WIND) {
        if (w->has_speed) {
            printf(",\"speed_ms\":%.9g", (double)w->speed_ms);
        }
        if (w->has_dir) {
            printf(",\"dir_deg\":%.9g", (double)w->dir_deg);
        }
        if (w->has_scenario) {
            printf(",\"scenario\":");
            str(w->scenario);
        }
    }
    printf("}");
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        int help = strcmp(argv[1], "--help") == 0;
        fprintf(help ? stdout : stderr,
                "usage: gale-web-kiosk-table\n"
                "  prints gale-client's kiosk panel (dial bands, angles, messages, lit\n"
                "  scenario, captions, compass points) as one JSON object\n");
        return help ? 0 : 2;
    }
    printf("{\"DIAL_MAX_MS\":%.9g,\"DIAL_SWEEP_RAD\":%.9g,\"BANDS\":%d,", (double)KIOSK_UI_DIAL_MAX_MS,
           (double)KIOSK_UI_DIAL_SWEEP_RAD, KIOSK_UI_BANDS);
    printf("\"BAND_LOWER_MS\":[");
    for (int b = 0; b <= KIOSK_UI_BANDS; b++) {
        printf("%s%.9g", b ? "," : "", (double)kiosk_ui_band_lower_ms(b));
    }
    printf("],\"band_labels\":[");
    for (int b = 0; b < KIOSK_UI_BANDS; b++) {
        printf("%s", b ? "," : "");
        str(kiosk_ui_band_label(b));
    }
    printf("],\"REPLAY_SPEEDS\":[");
    for (int i = 0; i < KIOSK_UI_SPEEDS; i++) {
        printf("%s%.9g", i ? "," : "", (double)kiosk_ui_speed_x(i));
    }
    /* every band's edges, a point inside each, the ends and beyond */
    printf("],\"angles\":[");
    int first = 1;
    for (int b = 0; b <= KIOSK_UI_BANDS; b++) {
        float lo = kiosk_ui_band_lower_ms(b);
        const float v[4] = { lo, nextafterf(lo, -1.0f), lo + 0.37f, lo - 0.01f };
        for (int k = 0; k < 4; k++) {
            printf("%s[%.9g,%.9g,%d]", first ? "" : ",", (double)v[k],
                   (double)kiosk_ui_dial_angle(v[k]), kiosk_ui_band(v[k]));
            first = 0;
        }
    }
    const float more[] = { -5.0f, 0.0f, 60.0f, 90.0f, 200.0f, NAN };
    for (size_t k = 0; k < sizeof more / sizeof more[0]; k++) {
        if (isnan(more[k])) {
            printf(",[null,%.9g,%d]", (double)kiosk_ui_dial_angle(more[k]), kiosk_ui_band(0.0f));
        } else {
            printf(",[%.9g,%.9g,%d]", (double)more[k], (double)kiosk_ui_dial_angle(more[k]),
                   kiosk_ui_band(more[k]));
        }
    }
    printf("],\"speeds\":[");
    for (int i = 0; i <= 80; i++) {
        float a = -2.6f + 0.065f * (float)i;
        printf("%s[%.9g,%.9g]", i ? "," : "", (double)a, (double)kiosk_ui_dial_speed(a));
    }
    /* a visitor's touches in turn, and what each sends */
    printf("],\"messages\":[");
    kiosk_ui ui;
    kiosk_ui_init(&ui);
    kiosk_ui_set_scenario(&ui, 0, "gusty", "Gusty afternoon", false);
    kiosk_ui_set_scenario(&ui, 1, "andrew1992", "Andrew 1992", true);
    kiosk_ui_set_scenario_count(&ui, 2);
    message(&ui, KIOSK_UI_ACT_SPEED, 60.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_DIR, 315.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_SPEED, 120.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_DIR, 271.5f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_SCENARIO, 0.0f, 1);
    printf(",");
    message(&ui, KIOSK_UI_ACT_DIR, 0.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_DIR, 270.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_SPEED, 12.5f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_RESET, 0.0f, 0);
    printf(",");
    message(&ui, KIOSK_UI_ACT_SPEED, 33.0f, 0);
    /* the scenario lit for WEATHER names (no DIAL flag: the C lights by the name alone) */
    printf("],\"scenarios\":[[\"gusty\",\"Gusty afternoon\"],[\"andrew1992\",\"Andrew 1992\"],"
           "[\"cat1\",\"Category 1 (steady)\"],[\"cat3-synthetic\",\"\"]],\"running\":[");
    static const char *const names[] = { "Gusty afternoon", "gusty", "ANDREW 1992", "Andrew-1992",
                                         "andrew", "Category 1 (steady)", "category1steady",
                                         "cat3synthetic", "", "  ", "Calm" };
    kiosk_ui_set_scenario(&ui, 2, "cat1", "Category 1 (steady)", false);
    kiosk_ui_set_scenario(&ui, 3, "cat3-synthetic", "", true);
    kiosk_ui_set_scenario_count(&ui, 4);
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        wire_weather w = { .sustained_ms = 5.0f };
        snprintf(w.name, sizeof w.name, "%s", names[k]);
        kiosk_ui_set_weather(&ui, &w);
        printf("%s[", k ? "," : "");
        str(names[k]);
        printf(",%d]", ui.running);
    }
    /* the caption of every class and force gale-client shows, in every language */
    printf("],\"captions\":[");
    for (int l = 0; l < LANG_COUNT; l++) {
        for (int ss = 0; ss < WIND_SCALE_SS_COUNT; ss++) {
            for (int b = 0; b <= 12; b++) {
                printf("%s[\"%s\",%d,%d,", l || ss || b ? "," : "", lang_code(l), ss, b);
                str(caption_for(l, ss, b));
                printf("]");
            }
        }
    }
    printf("],\"compass\":[");
    for (int l = 0; l < LANG_COUNT; l++) {
        for (int i = 0; i < 73; i++) {
            float d = -7.0f + 5.125f * (float)i;
            printf("%s[\"%s\",%.9g,", l || i ? "," : "", lang_code(l), (double)d);
            str(hud_compass_text(l, d));
            printf("]");
        }
    }
    printf("],\"band_names\":[");
    for (int l = 0; l < LANG_COUNT; l++) {
        for (int b = 0; b < KIOSK_UI_BANDS; b++) {
            printf("%s[\"%s\",%d,", l || b ? "," : "", lang_code(l), b);
            str(kiosk_ui_band_name(l, b));
            printf("]");
        }
    }
    printf("]}\n");
    return 0;
}
