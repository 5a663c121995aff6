/* http_hdr: Range values against a body length (RFC 7233 §2.1 examples, clamping,
 * suffixes, unsatisfiable, several ranges, invalid syntax) and entity-tag lists for
 * If-None-Match (weak comparison) and If-Range (strong). */
#include "check.h"
#include "http_hdr.h"

/* Parses v against len; checks the kind and, for ONE, the span. */
static void range_is(const char *v, uint64_t len, http_hdr_range_kind want, uint64_t first,
                     uint64_t last)
{
    uint64_t a = 7, b = 7;
    http_hdr_range_kind k = http_hdr_range(v, v ? strlen(v) : 0, len, &a, &b);
    if (k != want || (k == HTTP_HDR_RANGE_ONE && (a != first || b != last)) ||
        (k != HTTP_HDR_RANGE_ONE && (a || b))) {
        fprintf(stderr, "range \"%s\" of %llu: kind %d [%llu, %llu], expected %d [%llu, %llu]\n",
                v ? v : "(null)", (unsigned long long)len, (int)k, (unsigned long long)a,
                (unsigned long long)b, (int)want, (unsigned long long)first,
                (unsigned long long)last);
    }
    CHECK(k == want);
    if (want == HTTP_HDR_RANGE_ONE) {
        CHECK(a == first && b == last);
    } else {
        CHECK(a == 0 && b == 0);
    }
}

static void test_range_one(void)
{
    /* RFC 7233 §2.1 examples, a representation of 10000 bytes */
    range_is("bytes=0-499", 10000, HTTP_HDR_RANGE_ONE, 0, 499);
    range_is("bytes=500-999", 10000, HTTP_HDR_RANGE_ONE, 500, 999);
    range_is("bytes=-500", 10000, HTTP_HDR_RANGE_ONE, 9500, 9999);
    range_is("bytes=9500-", 10000, HTTP_HDR_RANGE_ONE, 9500, 9999);
    range_is("bytes=0-0", 10000, HTTP_HDR_RANGE_ONE, 0, 0);
    range_is("bytes=-1", 10000, HTTP_HDR_RANGE_ONE, 9999, 9999);
    /* clamping: a last position past the end, a suffix longer than the body */
    range_is("bytes=5-20000", 10000, HTTP_HDR_RANGE_ONE, 5, 9999);
    range_is("bytes=9999-99999999999999999999999", 10000, HTTP_HDR_RANGE_ONE, 9999, 9999);
    range_is("bytes=-20000", 10000, HTTP_HDR_RANGE_ONE, 0, 9999);
    range_is("bytes=-99999999999999999999999", 10000, HTTP_HDR_RANGE_ONE, 0, 9999);
    range_is("bytes=0-", 1, HTTP_HDR_RANGE_ONE, 0, 0);
    /* unit case, spaces around the element, empty list elements */
    range_is("Bytes=1-2", 10, HTTP_HDR_RANGE_ONE, 1, 2);
    range_is("BYTES= 1-2 ", 10, HTTP_HDR_RANGE_ONE, 1, 2);
    range_is("bytes=,\t1-2 ,, ", 10, HTTP_HDR_RANGE_ONE, 1, 2);
    range_is("bytes=007-008", 10, HTTP_HDR_RANGE_ONE, 7, 8);
}

static void test_range_unsatisfiable(void)
{
    range_is("bytes=10000-", 10000, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
    range_is("bytes=10000-10005", 10000, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
    range_is("bytes=99999999999999999999999-", 10000, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
    range_is("bytes=-0", 10000, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
    range_is("bytes=0-", 0, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
    range_is("bytes=-5", 0, HTTP_HDR_RANGE_UNSATISFIABLE, 0, 0);
}

static void test_range_multi(void)
{
    range_is("bytes=0-0,-1", 10000, HTTP_HDR_RANGE_MULTI, 0, 0);
    range_is("bytes=500-600, 601-999", 10000, HTTP_HDR_RANGE_MULTI, 0, 0);
    range_is("bytes=10000-,20000-", 10000, HTTP_HDR_RANGE_MULTI, 0, 0);
    /* one bad element spoils the set */
    range_is("bytes=0-1,x", 10000, HTTP_HDR_RANGE_NONE, 0, 0);
}

static void test_range_none(void)
{
    range_is(NULL, 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=,", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("items=0-1", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes =0-1", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=5-2", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=-", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=1", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=1-2-3", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=+1-2", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=1 -2", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=0x1-2", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    range_is("bytes=--1", 10, HTTP_HDR_RANGE_NONE, 0, 0);
    /* the length bounds the read: "bytes=1-2" cut to "bytes=1-" */
    uint64_t a, b;
    CHECK(http_hdr_range("bytes=1-2", 8, 10, &a, &b) == HTTP_HDR_RANGE_ONE && a == 1 && b == 9);
    CHECK(http_hdr_range("bytes=1-2", 7, 10, &a, &b) == HTTP_HDR_RANGE_NONE);
}

static void test_etag(void)
{
    const char *t = "00000000000000aa";
#define M(v, weak) http_hdr_etag_match((v), strlen(v), t, (weak))
    CHECK(M("\"00000000000000aa\"", true));
    CHECK(M("W/\"00000000000000aa\"", true));
    CHECK(M("*", true));
    CHECK(M(" * ", true));
    CHECK(M("\"x\", \"00000000000000aa\"", true));
    CHECK(M("\"x\",W/\"00000000000000aa\" , ", true));
    CHECK(!M("\"x\", \"y\"", true));
    CHECK(!M("\"00000000000000ab\"", true));
    CHECK(!M("\"00000000000000aa", true));
    CHECK(!M("00000000000000aa", true));
    CHECK(!M("\"00000000000000a\"", true));
    CHECK(!M("w/\"00000000000000aa\"", true));
    CHECK(!M("\"x\" \"00000000000000aa\"", true));
    CHECK(!M("\"a b\", \"00000000000000aa\"", true)); /* a space is no etagc */
    CHECK(!M("", true));
    /* If-Range: one strong tag, never W/, *, a list or a date */
    CHECK(M("\"00000000000000aa\"", false));
    CHECK(M(" \"00000000000000aa\" ", false));
    CHECK(!M("W/\"00000000000000aa\"", false));
    CHECK(!M("*", false));
    CHECK(!M("\"x\", \"00000000000000aa\"", false));
    CHECK(!M("\"00000000000000aa\", \"x\"", false));
    CHECK(!M("Tue, 01 Dec 2026 20:00:00 GMT", false));
#undef M
    CHECK(!http_hdr_etag_match(NULL, 0, t, true));
    CHECK(!http_hdr_etag_match("\"00000000000000aa\"", 17, t, true)); /* closing quote cut */
}

int main(void)
{
    RUN(test_range_one);
    RUN(test_range_unsatisfiable);
    RUN(test_range_multi);
    RUN(test_range_none);
    RUN(test_etag);
    return check_report();
}
