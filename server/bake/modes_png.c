/* Mode-shape figure (Diener 2008 figure 4): each panel looks at the tree from the side,
 * across the horizontal direction in which that mode moves most, with the rest skeleton in
 * grey and the mode at +q and -q in colour, reconstructed with eq. 16-17. */
#include "modes_png.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"

enum { PANEL_W = 420, PANEL_H = 520, COLS = 3 };

/* Node positions of mode m alone at q: rest + q̃ v + q̃² w (asset_corr_qt). */
static void deform(const asset *a, uint32_t m, double q, float *out)
{
    const size_t n = a->n_nodes, off = (size_t)m * n * 3;
    const double qt = (double)asset_corr_qt(a->corr_a[m], a->corr_b[m], (float)q);
    for (size_t c = 0; c < 3 * n; c++) {
        out[c] = a->rest[c] + (float)(qt * (double)a->corr_v[off + c] +
                                      qt * qt * (double)a->corr_w[off + c]);
    }
}

/* Draws the skeleton x seen across horizontal direction e. With base != NULL each segment
 * is coloured by how far it moved from the rest pose: base (still) to col (moving by
 * umove or more), so the part of the tree a mode moves stands out. */
static void draw(plot *p, const asset *a, const float *x, const double e[2], double sc,
                 double ox, double oy, const uint8_t col[3], const uint8_t *base, double umove)
{
    for (uint32_t i = 1; i < a->n_nodes; i++) {
        const uint32_t j = (uint32_t)a->parent[i];
        uint8_t c[3] = { col[0], col[1], col[2] };
        if (base) {
            double d = 0.0;
            for (int k = 0; k < 3; k++) {
                const double dk = (double)(x[3 * i + k] - a->rest[3 * i + k]);
                d += dk * dk;
            }
            const double t = fmin(1.0, sqrt(d) / umove);
            for (int k = 0; k < 3; k++) {
                c[k] = (uint8_t)lrint((1.0 - t) * base[k] + t * col[k]);
            }
        }
        const double u0 = e[0] * (double)x[3 * j] + e[1] * (double)x[3 * j + 1];
        const double u1 = e[0] * (double)x[3 * i] + e[1] * (double)x[3 * i + 1];
        double w = (double)(a->radius[i] + a->radius[j]) * sc;
        if (w < 1.0) {
            w = 1.0;
        }
        plot_line(p, (float)(ox + sc * u0), (float)(oy - sc * (double)x[3 * j + 2]),
                  (float)(ox + sc * u1), (float)(oy - sc * (double)x[3 * i + 2]), (float)w, c);
    }
}

int modes_png_write(const asset *a, const char *path, gale_err *err)
{
    const uint32_t nshow = a->n_modes < 6 ? a->n_modes : 6;
    const int rows = (int)((nshow + COLS - 1) / COLS);
    const size_t n = a->n_nodes;
    const uint8_t white[3] = { 255, 255, 255 }, grey[3] = { 175, 175, 175 };
    const uint8_t ink[3] = { 30, 30, 30 };
    plot p;
    int rc = plot_init(&p, PANEL_W * COLS, PANEL_H * (rows > 0 ? rows : 1), white, err);
    if (rc != GALE_OK) {
        return rc;
    }
    float *xp = malloc(n * 3 * sizeof *xp), *xm = malloc(n * 3 * sizeof *xm);
    double *q = calloc(nshow ? nshow : 1, sizeof *q), (*dir)[2] = calloc(nshow ? nshow : 1,
                                                                          sizeof *dir);
    if (!xp || !xm || !q || !dir) {
        rc = gale_errf(err, GALE_E_NOMEM, "%s: out of memory drawing %zu nodes", path, n);
        goto done;
    }
    /* per mode: amplitude and view direction; one scale for all panels */
    double umin = 0, umax = 0, zmax = (double)a->height_m, zmin = 0;
    const double h = a->height_m > 0.0f ? (double)a->height_m : 1.0;
    for (uint32_t m = 0; m < nshow; m++) {
        const float *ph = a->phi + (size_t)m * n * 3;
        double big = 0, sxx = 0, sxy = 0, syy = 0;
        for (size_t i = 0; i < n; i++) {
            const double x = (double)ph[3 * i], y = (double)ph[3 * i + 1], z = (double)ph[3 * i + 2];
            big = fmax(big, sqrt(x * x + y * y + z * z));
            sxx += x * x, sxy += x * y, syy += y * y;
        }
        q[m] = big > 0.0 ? 0.12 * h / big : 0.0;
        /* principal horizontal direction of the motion: the view looks across it */
        const double th = 0.5 * atan2(2.0 * sxy, sxx - syy);
        dir[m][0] = cos(th), dir[m][1] = sin(th);
        for (int s = -1; s <= 1; s += 2) {
            deform(a, m, s * q[m], xp);
            for (size_t i = 0; i < n; i++) {
                const double u = dir[m][0] * (double)xp[3 * i] + dir[m][1] * (double)xp[3 * i + 1];
                umin = fmin(umin, u), umax = fmax(umax, u);
                zmin = fmin(zmin, (double)xp[3 * i + 2]), zmax = fmax(zmax, (double)xp[3 * i + 2]);
            }
        }
        for (size_t i = 0; i < n; i++) {
            const double u = dir[m][0] * (double)a->rest[3 * i] + dir[m][1] * (double)a->rest[3 * i + 1];
            umin = fmin(umin, u), umax = fmax(umax, u);
        }
    }
    const double half_u = fmax(fabs(umin), fabs(umax)) + 1e-6;
    const double sc = fmin((PANEL_W - 40) / (2.0 * half_u), (PANEL_H - 70) / (zmax - zmin + 1e-6));
    for (uint32_t m = 0; m < nshow; m++) {
        const int px = (int)(m % COLS) * PANEL_W, py = (int)(m / COLS) * PANEL_H;
        const double ox = px + PANEL_W / 2.0, oy = py + PANEL_H - 20 + sc * zmin;
        uint8_t col[3], light[3];
        plot_colormap(nshow > 1 ? 0.1f + 0.75f * (float)m / (float)(nshow - 1) : 0.3f, col);
        for (int k = 0; k < 3; k++) {
            light[k] = (uint8_t)(255 - (255 - col[k]) / 2);
        }
        plot_rect(&p, px + 4, (int)oy, px + PANEL_W - 4, (int)oy + 2, ink);
        const double umove = 0.02 * h;
        draw(&p, a, a->rest, dir[m], sc, ox, oy, grey, NULL, 1.0);
        deform(a, m, -q[m], xm);
        draw(&p, a, xm, dir[m], sc, ox, oy, light, grey, umove);
        deform(a, m, q[m], xp);
        draw(&p, a, xp, dir[m], sc, ox, oy, col, grey, umove);
        char title[64];
        snprintf(title, sizeof title, "mode %u  %.2f Hz", m + 1,
                 (double)a->omega[m] / (2.0 * M_PI));
        plot_text(&p, px + 12, py + 12, 2, title, ink);
        if (m % COLS) {
            plot_rect(&p, px, py, px + 1, py + PANEL_H, grey);
        }
        if (m >= COLS) {
            plot_rect(&p, px, py, px + PANEL_W, py + 1, grey);
        }
    }
    rc = plot_write_png(&p, path, err);
done:
    free(xp), free(xm), free(q), free(dir);
    plot_fini(&p);
    return rc;
}
