/* gale test harness: CHECK, CHECK_NEAR (prints both values and the tolerance), RUN.
 * A test file defines its checks as static functions and calls them with RUN from main,
 * then returns check_report(). */
#ifndef GALE_CHECK_H
#define GALE_CHECK_H

#include <math.h>
#include <stdio.h>
#include <string.h>

static int check_failures;
static int check_count;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        check_count++;                                                                   \
        if (!(cond)) {                                                                   \
            check_failures++;                                                            \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);     \
        }                                                                                \
    } while (0)

/* |a - b| <= tol; NaN on either side fails. */
#define CHECK_NEAR(a, b, tol)                                                            \
    do {                                                                                 \
        double check_a_ = (double)(a), check_b_ = (double)(b), check_t_ = (double)(tol); \
        check_count++;                                                                   \
        if (!(fabs(check_a_ - check_b_) <= check_t_)) {                                  \
            check_failures++;                                                            \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.10g, %s = %.10g, "         \
                            "|diff| = %.3g > tol %.3g\n",                                \
                    __FILE__, __LINE__, #a, check_a_, #b, check_b_,                      \
                    fabs(check_a_ - check_b_), check_t_);                                \
        }                                                                                \
    } while (0)

/* The string s contains the substring sub (for exact error texts). */
#define CHECK_STR_HAS(s, sub)                                                            \
    do {                                                                                 \
        check_count++;                                                                   \
        if (!strstr((s), (sub))) {                                                       \
            check_failures++;                                                            \
            fprintf(stderr, "%s:%d: CHECK_STR_HAS failed: \"%s\" lacks \"%s\"\n",         \
                    __FILE__, __LINE__, (s), (sub));                                     \
        }                                                                                \
    } while (0)

#define RUN(fn)                                                                          \
    do {                                                                                 \
        int check_before_ = check_failures;                                             \
        fn();                                                                            \
        fprintf(stderr, "%-48s %s\n", #fn, check_failures == check_before_ ? "ok" : "FAIL"); \
    } while (0)

static inline int check_report(void)
{
    fprintf(stderr, "%d checks, %d failed\n", check_count, check_failures);
    return check_failures ? 1 : 0;
}

#endif
