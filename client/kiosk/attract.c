/* Attract mode's clock (attract.h). */
#include "attract.h"

#include <math.h>

void attract_init(attract *a, double idle_s, double now_s)
{
    a->idle_s = idle_s > 0.0 ? idle_s : ATTRACT_DEFAULT_IDLE_S;
    a->last_input_s = now_s;
    a->active = false;
}

bool attract_tick(attract *a, double now_s)
{
    if (a->active || now_s - a->last_input_s < a->idle_s) {
        return false;
    }
    a->active = true;
    return true;
}

bool attract_input(attract *a, double now_s)
{
    a->last_input_s = now_s;
    if (!a->active) {
        return false;
    }
    a->active = false;
    return true;
}

int attract_card(const attract *a, double now_s)
{
    if (!a->active) {
        return -1;
    }
    double shown_s = fmax(now_s - a->last_input_s - a->idle_s, 0.0);
    return (int)fmod(floor(shown_s / ATTRACT_CARD_S), (double)ATTRACT_CARDS);
}
