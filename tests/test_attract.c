/* Attract mode's clock (client/kiosk/attract.c): it starts once after the idle time without
 * input (default 90 s), a touch during it wakes the kiosk (and is reported, so it is not
 * taken as a control), input while awake keeps it awake, and its cards take turns. */
#include "attract.h"
#include "check.h"

static void test_idle_and_wake(void)
{
    attract a;
    attract_init(&a, 0.0, 100.0);
    CHECK_NEAR(a.idle_s, 90.0, 0.0);
    CHECK(!attract_tick(&a, 189.9));
    CHECK(!a.active);
    CHECK(attract_tick(&a, 190.0)); /* starts after 90 s idle */
    CHECK(a.active);
    CHECK(!attract_tick(&a, 200.0)); /* once */
    CHECK(attract_input(&a, 201.0)); /* a click wakes it */
    CHECK(!a.active);
    CHECK(!attract_input(&a, 202.0)); /* awake: a click is a control */
    CHECK(!attract_tick(&a, 291.9));
    CHECK(attract_tick(&a, 292.0));
}

static void test_input_keeps_awake(void)
{
    attract a;
    attract_init(&a, 10.0, 0.0);
    for (int t = 5; t < 100; t += 5) {
        CHECK(!attract_input(&a, t));
        CHECK(!attract_tick(&a, t + 4.9));
    }
    CHECK(attract_tick(&a, 110.0));
}

/* The cards in turn from when attract mode began: the invitation, then the water card, each
 * ATTRACT_CARD_S; none while awake. */
static void test_cards(void)
{
    attract a;
    attract_init(&a, 90.0, 0.0);
    CHECK(attract_card(&a, 50.0) == -1);
    CHECK(attract_tick(&a, 90.0));
    CHECK(attract_card(&a, 90.0) == ATTRACT_CARD_TOUCH);
    CHECK(attract_card(&a, 90.0 + ATTRACT_CARD_S - 0.01) == ATTRACT_CARD_TOUCH);
    CHECK(attract_card(&a, 90.0 + ATTRACT_CARD_S) == ATTRACT_CARD_WATER);
    CHECK(attract_card(&a, 90.0 + 2.0 * ATTRACT_CARD_S + 0.5) == ATTRACT_CARD_TOUCH);
    CHECK(attract_card(&a, 90.0 + 7.0 * ATTRACT_CARD_S + 0.5) == ATTRACT_CARD_WATER);
    CHECK(attract_input(&a, 200.0));
    CHECK(attract_card(&a, 200.0) == -1);
}

int main(void)
{
    RUN(test_idle_and_wake);
    RUN(test_input_keeps_awake);
    RUN(test_cards);
    return check_report();
}
