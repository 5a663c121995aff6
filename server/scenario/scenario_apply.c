/* Applies a scenario to the wind grid (kept apart from scenario.c so programs that only
 * evaluate scenarios need not link the solver). */
#include "scenario.h"
#include "scenario_int.h"

void scenario_apply(scenario *s, wind_grid *w, double t_s, scenario_state *out)
{
    scenario_state st;
    if (!out) {
        out = &st;
    }
    scenario_eval(s, t_s, out);
    wind_set_inflow(w, &out->inflow);
    for (int i = 0; i < s->n_balls; i++) {
        wind_add_ball(w, &s->balls[i]);
    }
}
