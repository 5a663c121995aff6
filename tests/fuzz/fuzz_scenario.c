/* Fuzz target: arbitrary bytes as a scenario file. Must never crash; a scenario that loads
 * is evaluated over a replay (including kiosk overrides) and every output must be finite. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "hurdat.h"
#include "scenario.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gale_err err = { 0 };
    scenario *s = scenario_parse("fuzz.json", (const char *)data, size, &err);
    if (s) {
        scenario_state st;
        double dur = scenario_duration_s(s);
        double step = dur > 0.0 ? dur / 50.0 : 0.5;
        for (int i = 0; i <= 60; i++) {
            if (i == 20) {
                scenario_set_category(s, SAFFIR_CAT3, NULL);
            } else if (i == 30) {
                scenario_set_direction(s, 90.0, NULL);
            } else if (i == 40) {
                scenario_clear_override(s);
            }
            scenario_eval(s, i * step, &st);
            if (!isfinite(st.sustained_ms) || !isfinite(st.gust_ms) || !isfinite(st.dir_from_deg) ||
                !isfinite(st.pressure_hpa) || !isfinite(st.inflow.gust[0]) ||
                !isfinite(st.inflow.dir_rad)) {
                abort();
            }
        }
        scenario_destroy(s);
    }
    /* the same bytes as HURDAT2 text */
    hurdat_file f;
    if (hurdat_parse(&f, "fuzz.txt", (const char *)data, size, &err) == 0) {
        /* every row's pressure, filled where it is missing (gale-hurdat), finite */
        for (int k = 0; k < f.n_storms; k++) {
            for (int i = 0; i < f.storms[k].n_rows; i++) {
                double p = 0.0;
                if (hurdat_pressure_at(&f.storms[k], i, 1013.0, &p) >= 0 && !isfinite(p)) {
                    abort();
                }
            }
        }
        hurdat_fini(&f);
    }
    return 0;
}
