/* Plot raster: lines cover the pixels they pass through with anti-aliased edges, shapes
 * clip at the borders, the colour map's ends, PNG output and its I/O error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "plot.h"

static const uint8_t white[3] = { 255, 255, 255 }, black[3] = { 0, 0, 0 };

static const uint8_t *px(const plot *p, int x, int y)
{
    return p->rgb + 3 * ((size_t)y * (size_t)p->w + (size_t)x);
}

static void test_line(void)
{
    plot p;
    gale_err err = { 0 };
    CHECK(plot_init(&p, 64, 32, white, &err) == 0);
    CHECK(px(&p, 10, 10)[0] == 255);
    plot_line(&p, 4.0f, 16.5f, 60.0f, 16.5f, 3.0f, black);
    CHECK(px(&p, 30, 16)[0] == 0);  /* on the line: full coverage */
    CHECK(px(&p, 30, 5)[0] == 255); /* far away: untouched */
    /* edge pixel partly covered: strictly between the two colours */
    plot_line(&p, 4.0f, 8.0f, 60.0f, 8.0f, 1.0f, black);
    CHECK(px(&p, 30, 7)[0] > 0 && px(&p, 30, 7)[0] < 255);
    /* far off the image, NaN: nothing happens, nothing crashes */
    plot_line(&p, -1e6f, -1e6f, 1e6f, -1e6f, 2.0f, black);
    plot_line(&p, NAN, 0.0f, 5.0f, 5.0f, 2.0f, black);
    CHECK(px(&p, 0, 0)[0] == 255);
    plot_fini(&p);
    CHECK(p.rgb == NULL);
    plot_fini(NULL);
}

static void test_rect_arrow_text(void)
{
    plot p;
    gale_err err = { 0 };
    CHECK(plot_init(&p, 40, 40, white, &err) == 0);
    plot_rect(&p, -10, -10, 5, 5, black);
    CHECK(px(&p, 0, 0)[0] == 0 && px(&p, 4, 4)[0] == 0 && px(&p, 5, 5)[0] == 255);
    plot_rect(&p, 35, 35, 100, 100, black);
    CHECK(px(&p, 39, 39)[0] == 0);
    plot_arrow(&p, 10.0f, 20.0f, 30.0f, 20.0f, 1.5f, black);
    CHECK(px(&p, 20, 19)[0] < 128 || px(&p, 20, 20)[0] < 128);
    /* a barb sits behind the head, off the shaft */
    int barb = 0;
    for (int y = 14; y < 19; y++) {
        for (int x = 22; x < 30; x++) {
            barb += px(&p, x, y)[0] < 200;
        }
    }
    CHECK(barb > 0);
    plot_fini(&p);

    CHECK(plot_init(&p, 80, 20, white, &err) == 0);
    plot_text(&p, 2, 2, 1, "Hz 42", black);
    int ink = 0;
    for (int i = 0; i < 80 * 20; i++) {
        ink += p.rgb[3 * i] == 0;
    }
    CHECK(ink > 10);
    plot_text(&p, 1000, 1000, 3, "off image", black); /* clipped */
    plot_fini(&p);
}

static void test_colormap(void)
{
    uint8_t a[3], b[3], c[3];
    plot_colormap(0.0f, a);
    plot_colormap(1.0f, b);
    plot_colormap(-5.0f, c);
    CHECK(a[0] == 68 && a[1] == 1 && a[2] == 84);
    CHECK(b[0] == 253 && b[1] == 231 && b[2] == 37);
    CHECK(memcmp(a, c, 3) == 0);
    /* lightness grows along the map */
    int prev = -1, mono = 1;
    for (int i = 0; i <= 20; i++) {
        uint8_t m[3];
        plot_colormap((float)i / 20.0f, m);
        int l = 2 * m[0] + 5 * m[1] + m[2];
        mono &= l > prev;
        prev = l;
    }
    CHECK(mono);
}

static void test_png(void)
{
    plot p;
    gale_err err = { 0 };
    CHECK(plot_init(&p, 16, 8, white, &err) == 0);
    char path[] = "test_plot_out.png";
    CHECK(plot_write_png(&p, path, &err) == 0);
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    if (f) {
        unsigned char sig[8] = { 0 };
        CHECK(fread(sig, 1, 8, f) == 8);
        CHECK(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
        fclose(f);
    }
    remove(path);
    CHECK(plot_write_png(&p, "/nonexistent/dir/x.png", &err) == GALE_E_IO);
    CHECK_STR_HAS(err.msg, "/nonexistent/dir/x.png");
    plot_fini(&p);
    CHECK(plot_init(&p, 0, 10, white, &err) == GALE_E_RANGE);
    CHECK(plot_init(&p, 100000, 10, white, &err) == GALE_E_RANGE);
}

int main(void)
{
    RUN(test_line);
    RUN(test_rect_arrow_text);
    RUN(test_colormap);
    RUN(test_png);
    return check_report();
}
