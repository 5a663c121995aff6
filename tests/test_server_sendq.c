/* Send queue: newest wins, oldest dropped first, every reference released exactly once,
 * drop streak resets on pop, bounded capacity. */
#include "check.h"
#include "sendq.h"

static int released[64];

static void rel(void *item, void *ctx)
{
    (void)ctx;
    released[(int)(intptr_t)item]++;
}

static void test_order_and_drops(void)
{
    memset(released, 0, sizeof released);
    sendq q;
    CHECK(sendq_init(&q, 4, rel, NULL, NULL) == 0);
    CHECK(sendq_pop(&q) == NULL);
    for (intptr_t i = 1; i <= 10; i++) {
        sendq_push(&q, (void *)i);
    }
    CHECK(q.count == 4);
    CHECK(q.dropped == 6);
    CHECK(q.drop_streak == 6);
    for (int i = 1; i <= 6; i++) {
        CHECK(released[i] == 1); /* the six oldest went, once each */
    }
    CHECK((intptr_t)sendq_pop(&q) == 7); /* oldest survivor first */
    CHECK(q.drop_streak == 0);
    CHECK((intptr_t)sendq_pop(&q) == 8);
    sendq_push(&q, (void *)11);
    CHECK((intptr_t)sendq_pop(&q) == 9);
    CHECK((intptr_t)sendq_pop(&q) == 10);
    CHECK((intptr_t)sendq_pop(&q) == 11);
    CHECK(sendq_pop(&q) == NULL);
    sendq_push(&q, (void *)12);
    sendq_push(&q, (void *)13);
    sendq_fini(&q); /* queued items released at fini */
    CHECK(released[12] == 1 && released[13] == 1);
    CHECK(released[7] == 0 && released[11] == 0); /* popped items belong to the caller */
    sendq_fini(&q);                               /* no-op */
}

static void test_bad_cap(void)
{
    sendq q;
    gale_err e;
    CHECK(sendq_init(&q, 0, NULL, NULL, &e) == GALE_E_ARG);
    CHECK_STR_HAS(e.msg, "expected 1..65536, got 0");
    CHECK(sendq_init(&q, 1, NULL, NULL, &e) == 0);
    sendq_push(&q, (void *)1);
    sendq_push(&q, (void *)2);
    CHECK(q.count == 1 && (intptr_t)sendq_pop(&q) == 2);
    sendq_fini(&q);
}

int main(void)
{
    RUN(test_order_and_drops);
    RUN(test_bad_cap);
    return check_report();
}
