/* Saffir–Simpson classes from the 1-minute sustained wind, both sides of every threshold
 * (knots per server/PHYSICS.md "Hurricanes"), and the Beaufort classes below tropical-storm force. */
#include "check.h"
#include "saffir.h"

#define KT(k) ((k)*SAFFIR_MS_PER_KT)

static void test_thresholds(void)
{
    /* the last whole knot of each class and the first of the next */
    static const int edge[] = { 33, 63, 82, 95, 112, 136 };
    for (int i = 0; i < 6; i++) {
        CHECK(saffir_classify(KT(edge[i])) == (saffir_class)i);
        CHECK(saffir_classify(KT(edge[i] + 1)) == (saffir_class)(i + 1));
        /* rounding to the nearest knot: .49 stays, .5 goes up */
        CHECK(saffir_classify(KT(edge[i] + 0.49)) == (saffir_class)i);
        CHECK(saffir_classify(KT(edge[i] + 0.5)) == (saffir_class)(i + 1));
        /* saffir_lower_ms is that boundary */
        double lo = saffir_lower_ms((saffir_class)(i + 1));
        CHECK(saffir_classify(lo * 1.0001) == (saffir_class)(i + 1));
        CHECK(saffir_classify(lo * 0.9999) == (saffir_class)i);
    }
    /* the m/s column of the table */
    CHECK(saffir_classify(17.0) == SAFFIR_TD);
    CHECK(saffir_classify(18.0) == SAFFIR_TS);
    CHECK(saffir_classify(32.0) == SAFFIR_TS);
    CHECK(saffir_classify(33.0) == SAFFIR_CAT1);
    CHECK(saffir_classify(42.0) == SAFFIR_CAT1);
    CHECK(saffir_classify(43.0) == SAFFIR_CAT2);
    CHECK(saffir_classify(49.0) == SAFFIR_CAT2);
    CHECK(saffir_classify(50.0) == SAFFIR_CAT3);
    /* the table's 58 m/s sits on the Cat 3/4 line: 112.74 kt rounds to 113 (Cat 4) */
    CHECK(saffir_classify(57.8) == SAFFIR_CAT3);
    CHECK(saffir_classify(58.0) == SAFFIR_CAT4);
    CHECK(saffir_classify(70.0) == SAFFIR_CAT4);
    CHECK(saffir_classify(71.0) == SAFFIR_CAT5);
    /* Andrew's 145 kt and Charley's 130 kt at landfall */
    CHECK(saffir_classify(KT(145)) == SAFFIR_CAT5);
    CHECK(saffir_classify(KT(130)) == SAFFIR_CAT4);
    /* junk in: calm */
    CHECK(saffir_classify(-3.0) == SAFFIR_TD);
    CHECK(saffir_classify(NAN) == SAFFIR_TD);
    CHECK(saffir_classify(1e9) == SAFFIR_CAT5);
}

static void test_names(void)
{
    CHECK_STR_HAS(saffir_name(SAFFIR_TD), "tropical depression");
    CHECK_STR_HAS(saffir_name(SAFFIR_CAT3), "Category 3");
    CHECK_STR_HAS(saffir_short(SAFFIR_CAT5), "Cat 5");
    CHECK_STR_HAS(saffir_name((saffir_class)7), "?");
    CHECK_STR_HAS(saffir_name((saffir_class)-1), "?");
    for (int c = 0; c < SAFFIR_COUNT; c++) {
        /* the representative wind falls in its own class */
        CHECK(saffir_classify(saffir_representative_ms((saffir_class)c)) == (saffir_class)c);
    }
    CHECK(saffir_representative_ms((saffir_class)9) < 0.0);
}

static void test_beaufort(void)
{
    CHECK(saffir_beaufort(0.0) == 0);
    CHECK(saffir_beaufort(0.2) == 0);
    CHECK(saffir_beaufort(0.3) == 1);
    CHECK(saffir_beaufort(3.3) == 2);
    CHECK(saffir_beaufort(3.4) == 3);
    CHECK(saffir_beaufort(10.7) == 5);
    CHECK(saffir_beaufort(10.8) == 6);
    CHECK(saffir_beaufort(32.6) == 11);
    CHECK(saffir_beaufort(32.7) == 12);
    CHECK_STR_HAS(saffir_beaufort_name(4), "moderate breeze");
    CHECK_STR_HAS(saffir_beaufort_name(12), "hurricane force");
    CHECK_STR_HAS(saffir_beaufort_name(13), "?");
}

int main(void)
{
    RUN(test_thresholds);
    RUN(test_names);
    RUN(test_beaufort);
    return check_report();
}
