/* Tests of the error buffer: formatting, truncation, NULL tolerance. */
#include "check.h"
#include "err.h"

static void test_format(void)
{
    gale_err e;
    gale_err_clear(&e);
    int rc = gale_errf(&e, GALE_E_RANGE, "%s:%d: %s: expected > 0, got %g", "a.json", 3,
                       "species.E", -1.0);
    CHECK(rc == GALE_E_RANGE);
    CHECK(e.code == GALE_E_RANGE);
    CHECK(strcmp(e.msg, "a.json:3: species.E: expected > 0, got -1") == 0);
    CHECK(strcmp(gale_err_name(e.code), "range") == 0);
}

static void test_truncate_and_null(void)
{
    gale_err e;
    char big[1000];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    gale_errf(&e, GALE_E_IO, "%s", big);
    CHECK(strlen(e.msg) == sizeof e.msg - 1);
    CHECK(gale_errf(NULL, GALE_E_IO, "nothing") == GALE_E_IO);
    gale_err_clear(NULL);
}

int main(void)
{
    RUN(test_format);
    RUN(test_truncate_and_null);
    return check_report();
}
