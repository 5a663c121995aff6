/* Pressure Poisson solve (Oliapuram & Kumar 2010 eq. 9) by geometric multigrid on the
 * cell-centred MAC pressure: V-cycles of red-black Gauss-Seidel, full coarsening while
 * the grid has z layers left, then x-y only; warm-started from the previous step.
 *
 * Why multigrid and not the paper's Jacobi: on 256x256x16 a Jacobi sweep costs 0.71 ms on
 * this machine, 4 sweeps leave 96 % of the error and even 20,000 leave 28 % (the slowest
 * mode needs ~92,000 sweeps per decade; PHYSICS.md "Pressure solve"). Red-black SOR
 * needs ~970 sweeps and plain CG ~550 iterations for a 1e-2 residual; a V-cycle gains
 * about a decade per cycle independently of the grid size, so the 100x divergence
 * reduction costs 1-3 cycles, and fewer from a warm start in steady wind. MGPCG would
 * reach tighter residuals per cycle but costs a CG pass on top of each V-cycle; the
 * 1e-2 target is met by plain V-cycles in float. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "wind_int.h"

/* Smoothing sweeps before / after the coarse correction on coarse levels, after it on the
 * finest level (whose pre-smoothing is the previous cycle's post-smoothing). */
#define MG_PRE 2
#define MG_POST 2
#define MG_FINE_POST 2
#define MG_COARSEST_SWEEPS 40
/* Multigrid levels with fewer cells than this run on one thread, outside any OpenMP
 * region: a level is swept about ten times per cycle, and below this size (the 64x64x4
 * level of the reference grid: 0.09 ms alone, 0.15 ms split) the forks and barriers cost
 * more than the second core saves. */
#define MG_PAR_MIN 32768

double wind_sum_rows(const double *rows, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        s += rows[i];
    }
    return s;
}

static int level_threads(const wind_grid *w, const wind_level *l)
{
    return (size_t)l->nx * (size_t)l->ny * (size_t)l->nz >= MG_PAR_MIN ? w->d.threads : 1;
}

int wind_mg_alloc(wind_grid *w, gale_err *err)
{
    int n[3] = { w->nx, w->ny, w->nz };
    w->n_levels = 0;
    for (;;) {
        wind_level *l = &w->lv[w->n_levels];
        l->nx = n[0];
        l->ny = n[1];
        l->nz = n[2];
        l->sy = n[0] + 2;
        l->sz = l->sy * (n[1] + 2);
        l->count = (size_t)l->sz * (size_t)(n[2] + 2);
        l->p = calloc(l->count, sizeof(float));
        l->b = calloc(l->count, sizeof(float));
        l->ax = calloc(l->count, sizeof(float));
        l->ay = calloc(l->count, sizeof(float));
        l->az = calloc(l->count, sizeof(float));
        l->diag = calloc(l->count, sizeof(float));
        l->idiag = calloc(l->count, sizeof(float));
        l->rowsum = calloc((size_t)n[1] * (size_t)n[2], sizeof(double));
        l->rowg = calloc((size_t)WIND_ROWG * (size_t)n[1] * (size_t)n[2], sizeof(float));
        for (int a = 0; a < 3; a++) {
            l->wd[a] = calloc((size_t)n[a], sizeof(int));
        }
        w->n_levels++;
        if (!l->p || !l->b || !l->ax || !l->ay || !l->az || !l->diag || !l->idiag ||
            !l->rowsum || !l->rowg || !l->wd[0] || !l->wd[1] || !l->wd[2]) {
            return gale_errf(err, GALE_E_NOMEM, "wind: multigrid level %d (%dx%dx%d): out of "
                             "memory", w->n_levels - 1, n[0], n[1], n[2]);
        }
        int any = 0;
        for (int a = 0; a < 3; a++) {
            l->r[a] = n[a] >= 2 ? 2 : 1;
            any |= l->r[a] == 2;
        }
        if (!any || n[0] * n[1] * n[2] <= 8 || w->n_levels == WIND_MAX_LEVELS) {
            l->r[0] = l->r[1] = l->r[2] = 1;
            break;
        }
        for (int a = 0; a < 3; a++) {
            n[a] = (n[a] + l->r[a] - 1) / l->r[a];
        }
    }
    w->scratch = calloc((size_t)w->d.threads * WIND_SCRATCH_ROW(w), sizeof(float));
    if (!w->scratch) {
        return gale_errf(err, GALE_E_NOMEM, "wind: multigrid scratch: out of memory");
    }
    /* widths: 1 on the finest level, the children's sum above */
    for (int a = 0; a < 3; a++) {
        const wind_level *f = &w->lv[0];
        int nf = a == 0 ? f->nx : a == 1 ? f->ny : f->nz;
        for (int i = 0; i < nf; i++) {
            f->wd[a][i] = 1;
        }
        for (int li = 1; li < w->n_levels; li++) {
            const wind_level *fl = &w->lv[li - 1], *cl = &w->lv[li];
            int nfl = a == 0 ? fl->nx : a == 1 ? fl->ny : fl->nz;
            int ncl = a == 0 ? cl->nx : a == 1 ? cl->ny : cl->nz;
            for (int i = 0; i < ncl; i++) {
                int c0 = i * fl->r[a];
                cl->wd[a][i] = fl->wd[a][c0] + (fl->r[a] == 2 && c0 + 1 < nfl ? fl->wd[a][c0 + 1] : 0);
            }
        }
    }
    return 0;
}

void wind_mg_free(wind_grid *w)
{
    for (int i = 0; i < w->n_levels; i++) {
        wind_level *l = &w->lv[i];
        free(l->p);
        free(l->b);
        free(l->ax);
        free(l->ay);
        free(l->az);
        free(l->diag);
        free(l->idiag);
        free(l->rowsum);
        free(l->rowg);
        for (int a = 0; a < 3; a++) {
            free(l->wd[a]);
        }
    }
    w->n_levels = 0;
    free(w->scratch);
    w->scratch = NULL;
}

static size_t lidx(const wind_level *l, int i, int j, int k)
{
    return wind_idx(l->sy, l->sz, i, j, k);
}

/* Level 0 face coefficients: 1 where both cells are fluid, 2 where a fluid cell meets an
 * open border, 0 at solids, the ground, the lid and inflow borders (Neumann). */
static void setup_fine(wind_grid *w)
{
    wind_level *l = &w->lv[0];
    const uint8_t *s = w->solid;
    memset(l->ax, 0, l->count * sizeof(float));
    memset(l->ay, 0, l->count * sizeof(float));
    memset(l->az, 0, l->count * sizeof(float));
    for (int k = 0; k < l->nz; k++) {
        for (int j = 0; j < l->ny; j++) {
            for (int i = 0; i <= l->nx; i++) {
                size_t c = lidx(l, i, j, k);
                int lo = i > 0 && !s[c - 1], hi = i < l->nx && !s[c];
                float a = 0.0f;
                if (i == 0) {
                    a = 2.0f * (float)(hi && w->dirichlet[WIND_SIDE_XLO]);
                } else if (i == l->nx) {
                    a = 2.0f * (float)(lo && w->dirichlet[WIND_SIDE_XHI]);
                } else {
                    a = (float)(lo && hi);
                }
                l->ax[c] = a;
            }
        }
        for (int j = 0; j <= l->ny; j++) {
            for (int i = 0; i < l->nx; i++) {
                size_t c = lidx(l, i, j, k);
                int lo = j > 0 && !s[c - (size_t)l->sy], hi = j < l->ny && !s[c];
                float a = 0.0f;
                if (j == 0) {
                    a = 2.0f * (float)(hi && w->dirichlet[WIND_SIDE_YLO]);
                } else if (j == l->ny) {
                    a = 2.0f * (float)(lo && w->dirichlet[WIND_SIDE_YHI]);
                } else {
                    a = (float)(lo && hi);
                }
                l->ay[c] = a;
            }
        }
    }
    for (int k = 1; k < l->nz; k++) {
        for (int j = 0; j < l->ny; j++) {
            for (int i = 0; i < l->nx; i++) {
                size_t c = lidx(l, i, j, k);
                l->az[c] = (float)(!s[c] && !s[c - (size_t)l->sz]);
            }
        }
    }
}

/* Distance between the centres of cells i - 1 and i along one axis (widths wd, n cells);
 * half the width at the borders. */
static float face_dist(const int *wd, int n, int i)
{
    if (i == 0) {
        return 0.5f * (float)wd[0];
    }
    if (i == n) {
        return 0.5f * (float)wd[n - 1];
    }
    return 0.5f * (float)(wd[i - 1] + wd[i]);
}

/* Coarse face g: the open area of the fine faces that make up the coarse face (each fine
 * g times its centre distance) over the coarse centre distance. */
static void setup_coarse(wind_level *f, wind_level *c)
{
    memset(c->ax, 0, c->count * sizeof(float));
    memset(c->ay, 0, c->count * sizeof(float));
    memset(c->az, 0, c->count * sizeof(float));
    const int *r = f->r;
    for (int K = 0; K <= c->nz; K++) {
        for (int J = 0; J <= c->ny; J++) {
            for (int I = 0; I <= c->nx; I++) {
                int i0 = I * r[0], j0 = J * r[1], k0 = K * r[2];
                int i1 = i0 + r[0] < f->nx ? i0 + r[0] : f->nx;
                int j1 = j0 + r[1] < f->ny ? j0 + r[1] : f->ny;
                int k1 = k0 + r[2] < f->nz ? k0 + r[2] : f->nz;
                int fi = i0 < f->nx ? i0 : f->nx, fj = j0 < f->ny ? j0 : f->ny;
                int fk = k0 < f->nz ? k0 : f->nz;
                size_t cc = lidx(c, I, J, K);
                if (J < c->ny && K < c->nz) {
                    double s = 0.0;
                    float df = face_dist(f->wd[0], f->nx, fi);
                    for (int k = k0; k < k1; k++) {
                        for (int j = j0; j < j1; j++) {
                            s += (double)(f->ax[lidx(f, fi, j, k)] * df);
                        }
                    }
                    c->ax[cc] = (float)s / face_dist(c->wd[0], c->nx, I);
                }
                if (I < c->nx && K < c->nz) {
                    double s = 0.0;
                    float df = face_dist(f->wd[1], f->ny, fj);
                    for (int k = k0; k < k1; k++) {
                        for (int i = i0; i < i1; i++) {
                            s += (double)(f->ay[lidx(f, i, fj, k)] * df);
                        }
                    }
                    c->ay[cc] = (float)s / face_dist(c->wd[1], c->ny, J);
                }
                if (I < c->nx && J < c->ny) {
                    double s = 0.0;
                    float df = face_dist(f->wd[2], f->nz, fk);
                    for (int j = j0; j < j1; j++) {
                        for (int i = i0; i < i1; i++) {
                            s += (double)(f->az[lidx(f, i, j, fk)] * df);
                        }
                    }
                    c->az[cc] = (float)s / face_dist(c->wd[2], c->nz, K);
                }
            }
        }
    }
}

static void setup_diag(wind_level *l)
{
    memset(l->diag, 0, l->count * sizeof(float));
    memset(l->idiag, 0, l->count * sizeof(float));
    size_t sy = (size_t)l->sy, sz = (size_t)l->sz;
    for (int k = 0; k < l->nz; k++) {
        for (int j = 0; j < l->ny; j++) {
            for (int i = 0; i < l->nx; i++) {
                size_t c = lidx(l, i, j, k);
                float d = l->ax[c] + l->ax[c + 1] + l->ay[c] + l->ay[c + sy] + l->az[c] +
                          l->az[c + sz];
                l->diag[c] = d;
                l->idiag[c] = d > 0.0f ? 1.0f / d : 0.0f;
            }
            /* constant-coefficient rows take a kernel that reads only p and b */
            float *g = l->rowg + WIND_ROWG * ((size_t)k * (size_t)l->ny + (size_t)j);
            size_t c1 = lidx(l, 1, j, k);
            g[0] = l->ax[c1];
            g[1] = l->ax[c1 + 1];
            g[2] = l->ay[c1];
            g[3] = l->ay[c1 + sy];
            g[4] = l->az[c1];
            g[5] = l->az[c1 + sz];
            int same = l->nx >= 3 && g[0] > 0.0f && g[1] > 0.0f;
            for (int i = 1; i < l->nx - 1 && same; i++) {
                size_t c = lidx(l, i, j, k);
                same = l->ax[c] == g[0] && l->ax[c + 1] == g[1] && l->ay[c] == g[2] &&
                       l->ay[c + sy] == g[3] && l->az[c] == g[4] && l->az[c + sz] == g[5];
            }
            /* the interior cells' diag and idiag, as computed above */
            g[6] = l->diag[c1];
            g[7] = l->idiag[c1];
            if (!same) {
                g[0] = -1.0f;
            }
            for (int e = 0; e < 2; e++) {
                size_t c = lidx(l, e == 0 ? 0 : l->nx - 1, j, k);
                float *q = g + (e == 0 ? WIND_END0 : WIND_END1);
                q[0] = l->ax[c];
                q[1] = l->ax[c + 1];
                q[2] = l->ay[c];
                q[3] = l->ay[c + sy];
                q[4] = l->az[c];
                q[5] = l->az[c + sz];
                q[6] = l->diag[c];
                q[7] = l->idiag[c];
            }
        }
    }
}

void wind_mg_setup(wind_grid *w)
{
    setup_fine(w);
    setup_diag(&w->lv[0]);
    for (int i = 1; i < w->n_levels; i++) {
        setup_coarse(&w->lv[i - 1], &w->lv[i]);
        setup_diag(&w->lv[i]);
    }
}

/* Stencil of one row into out[0..nx): out = b + sum of g p_nb (the Gauss-Seidel
 * numerator) when want_resid is 0, else the residual b - A p. Contiguous, no branches:
 * vectorises. */
WIND_CLONES static void row_stencil(int nx, ptrdiff_t sy, ptrdiff_t sz, const float *restrict p,
                                    const float *restrict b, const float *restrict ax,
                                    const float *restrict ay, const float *restrict az,
                                    const float *restrict dg, int want_resid,
                                    float *restrict out)
{
    /* the two forms in separate loops: a loop choosing per cell would load dg only in
     * one arm, and without masked loads (AVX2) it would not vectorise */
    if (want_resid) {
        for (int i = 0; i < nx; i++) {
            float nb = ax[i] * p[i - 1] + ax[i + 1] * p[i + 1] + ay[i] * p[i - sy] +
                       ay[i + sy] * p[i + sy] + az[i] * p[i - sz] + az[i + sz] * p[i + sz];
            out[i] = b[i] - (dg[i] * p[i] - nb);
        }
        return;
    }
    for (int i = 0; i < nx; i++) {
        float nb = ax[i] * p[i - 1] + ax[i + 1] * p[i + 1] + ay[i] * p[i - sy] +
                   ay[i + sy] * p[i + sy] + az[i] * p[i - sz] + az[i + sz] * p[i + sz];
        out[i] = b[i] + nb;
    }
}

/* row_stencil for a row whose interior faces have the same six g (x low/high, y low/high,
 * z low/high) in every cell: the same arithmetic in the same order, without reading the
 * coefficient arrays (a third of the traffic). */
WIND_CLONES static void row_stencil_const(int nx, ptrdiff_t sy, ptrdiff_t sz,
                                          const float *restrict p, const float *restrict b,
                                          const float *restrict g, float dg, int want_resid,
                                          float *restrict out)
{
    const float g0 = g[0], g1 = g[1], g2 = g[2], g3 = g[3], g4 = g[4], g5 = g[5];
    for (int i = 0; i < nx; i++) {
        float nb = g0 * p[i - 1] + g1 * p[i + 1] + g2 * p[i - sy] + g3 * p[i + sy] +
                   g4 * p[i - sz] + g5 * p[i + sz];
        out[i] = want_resid ? b[i] - (dg * p[i] - nb) : b[i] + nb;
    }
}

/* One cell of row_stencil from a row's end entry q (six g, diag; wind_level.rowg), for
 * the ends of constant rows: the same arithmetic in the same order. */
static inline float cell_stencil(ptrdiff_t sy, ptrdiff_t sz, const float *p, const float *b,
                                 const float *q, int want_resid)
{
    float nb = q[0] * p[-1] + q[1] * p[1] + q[2] * p[-sy] + q[3] * p[sy] + q[4] * p[-sz] +
               q[5] * p[sz];
    return want_resid ? b[0] - (q[6] * p[0] - nb) : b[0] + nb;
}

/* Stencil of row r (first cell c0) of level l into out, by the constant-coefficient
 * kernel where the row allows it. */
static void row_eval(const wind_level *l, int r, size_t c0, int want_resid, float *out)
{
    const float *g = l->rowg + WIND_ROWG * (size_t)r;
    const float *p = l->p + c0, *b = l->b + c0;
    if (g[0] < 0.0f) {
        row_stencil(l->nx, l->sy, l->sz, p, b, l->ax + c0, l->ay + c0, l->az + c0,
                    l->diag + c0, want_resid, out);
        return;
    }
    const size_t e = (size_t)l->nx - 1;
    out[0] = cell_stencil(l->sy, l->sz, p, b, g + WIND_END0, want_resid);
    row_stencil_const(l->nx - 2, l->sy, l->sz, p + 1, b + 1, g, g[6], want_resid,
                      out + 1);
    out[e] = cell_stencil(l->sy, l->sz, p + e, b + e, g + WIND_END1, want_resid);
}

static float *row_scratch(const wind_grid *w)
{
    return w->scratch + (size_t)omp_get_thread_num() * WIND_SCRATCH_ROW(w);
}

/* Gauss-Seidel update of every second cell of a constant-coefficient row: cells 0, 2, ..
 * of p (2 cnt - 1 at most), whose neighbours are all of the other colour. The same
 * arithmetic in the same order as row_stencil; vectorises with interleaved loads. */
WIND_CLONES static void rb_row_const(int cnt, ptrdiff_t sy, ptrdiff_t sz, float *restrict p,
                                     const float *restrict b, const float *restrict g, float id)
{
    const float g0 = g[0], g1 = g[1], g2 = g[2], g3 = g[3], g4 = g[4], g5 = g[5];
    for (int m = 0; m < cnt; m++) {
        ptrdiff_t i = 2 * (ptrdiff_t)m;
        float nb = g0 * p[i - 1] + g1 * p[i + 1] + g2 * p[i - sy] + g3 * p[i + sy] +
                   g4 * p[i - sz] + g5 * p[i + sz];
        p[i] = (b[i] + nb) * id;
    }
}

/* One red-black Gauss-Seidel sweep. Each colour reads only the other colour, so the
 * result does not depend on the thread partition. Constant-coefficient rows update their
 * interior cells of the colour directly; other rows compute every cell's numerator
 * (vectorised) and store the current colour's. */
static void smooth_row(const wind_grid *w, wind_level *l, int colour, int r)
{
    const int nx = l->nx, ny = l->ny;
    int j = r % ny, k = r / ny;
    size_t c0 = wind_idx(l->sy, l->sz, 0, j, k);
    float *p = l->p + c0;
    const float *g = l->rowg + WIND_ROWG * (size_t)r;
    int first = (colour + j + k) & 1;
    if (g[0] < 0.0f) {
        const float *id = l->idiag + c0;
        float *t = row_scratch(w);
        row_stencil(nx, l->sy, l->sz, p, l->b + c0, l->ax + c0, l->ay + c0, l->az + c0,
                    l->diag + c0, 0, t);
        for (int i = first; i < nx; i += 2) {
            p[i] = t[i] * id[i];
        }
        return;
    }
    /* the end cells from the row's end entries, the interior by the constant kernel */
    const int ends[2] = { 0, nx - 1 };
    for (int e = 0; e < 2; e++) {
        int i = ends[e];
        if (((i + first) & 1) == 0) {
            const float *q = g + (e == 0 ? WIND_END0 : WIND_END1);
            p[i] = cell_stencil(l->sy, l->sz, p + i, l->b + c0 + (size_t)i, q, 0) * q[7];
        }
    }
    int i1 = first == 1 ? 1 : 2; /* first interior cell of this colour */
    int cnt = (nx - 2 - i1 + 2) / 2;
    if (cnt > 0) {
        rb_row_const(cnt, l->sy, l->sz, p + i1, l->b + c0 + (size_t)i1, g, g[7]);
    }
}

/* One red-black Gauss-Seidel sweep. Each colour reads only the other colour, so the
 * result does not depend on the thread partition. Constant-coefficient rows update their
 * interior cells of the colour directly; other rows compute every cell's numerator
 * (vectorised) and store the current colour's. Levels too small to split run without an
 * OpenMP region at all: even a one-thread region costs over a microsecond, and the
 * coarsest levels are swept dozens of times per cycle. */
static void smooth(const wind_grid *w, wind_level *l)
{
    const int rows = l->ny * l->nz, nt = level_threads(w, l);
    if (nt == 1) {
        for (int colour = 0; colour < 2; colour++) {
            for (int r = 0; r < rows; r++) {
                smooth_row(w, l, colour, r);
            }
        }
        return;
    }
    /* one parallel region, the barrier of the first loop between the colours */
#pragma omp parallel num_threads(nt)
    for (int colour = 0; colour < 2; colour++) {
#pragma omp for schedule(static)
        for (int r = 0; r < rows; r++) {
            smooth_row(w, l, colour, r);
        }
    }
}

/* Sum of squares of a residual row, reassociated into vector lanes (a norm for the
 * stopping test: the order is fixed per build, so runs stay reproducible). */
WIND_CLONES static float row_sq(int n, const float *restrict t)
{
    float s = 0.0f;
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < n; i++) {
        s += t[i] * t[i];
    }
    return s;
}

/* A per-row kernel of a level pass: fine level f, coarse level c (may be NULL), row r. */
typedef void (*level_row_fn)(const wind_grid *w, wind_level *f, wind_level *c, int r);

/* Runs fn over rows [0, rows) on nt threads; with one thread, outside any OpenMP region
 * (see smooth). Rows are independent, so the split does not change the result. */
static void for_each_row(const wind_grid *w, int nt, int rows, level_row_fn fn, wind_level *f,
                         wind_level *c)
{
    if (nt == 1) {
        for (int r = 0; r < rows; r++) {
            fn(w, f, c, r);
        }
        return;
    }
#pragma omp parallel for schedule(static) num_threads(nt)
    for (int r = 0; r < rows; r++) {
        fn(w, f, c, r);
    }
}

/* Residual of fine row r into f->rowsum[r] (its sum of squares); c is unused (the
 * signature of level_row_fn). */
static void residual_row(const wind_grid *w, wind_level *f, wind_level *c, int r)
{
    (void)c;
    int j = r % f->ny, k = r / f->ny;
    size_t c0 = wind_idx(f->sy, f->sz, 0, j, k);
    float *t = row_scratch(w);
    row_eval(f, r, c0, 1, t);
    f->rowsum[r] = (double)row_sq(f->nx, t);
}

/* Coarse row r of level c's b: the sum of its children's residuals; c->rowsum[r] gets the
 * children's sum of squares. */
static void restrict_row(const wind_grid *w, wind_level *f, wind_level *c, int r)
{
    const int *rf = f->r;
    const int cnx = c->nx;
    int J = r % c->ny, K = r / c->ny;
    int j0 = J * rf[1], k0 = K * rf[2];
    int j1 = j0 + rf[1] < f->ny ? j0 + rf[1] : f->ny;
    int k1 = k0 + rf[2] < f->nz ? k0 + rf[2] : f->nz;
    float *cb = c->b + wind_idx(c->sy, c->sz, 0, J, K);
    float *t = row_scratch(w);
    double s = 0.0;
    for (int I = 0; I < cnx; I++) {
        cb[I] = 0.0f;
    }
    for (int k = k0; k < k1; k++) {
        for (int j = j0; j < j1; j++) {
            size_t c0 = wind_idx(f->sy, f->sz, 0, j, k);
            row_eval(f, k * f->ny + j, c0, 1, t);
            s += (double)row_sq(f->nx, t);
            if (rf[0] == 2) {
                for (int I = 0; I < f->nx / 2; I++) {
                    cb[I] += t[2 * I] + t[2 * I + 1];
                }
                if (f->nx & 1) {
                    cb[cnx - 1] += t[f->nx - 1];
                }
            } else {
                for (int I = 0; I < cnx; I++) {
                    cb[I] += t[I];
                }
            }
        }
    }
    c->rowsum[r] = s;
}

/* Computes the residual of level l, restricts it to level l+1's b (the sum over the
 * children: a coarse row is the sum of its children's rows in flux form) and returns
 * ||r||_2 of level l. */
static double residual_restrict(const wind_grid *w, wind_level *f, wind_level *c)
{
    const int nt = level_threads(w, f);
    if (!c) {
        const int rows = f->ny * f->nz;
        for_each_row(w, nt, rows, residual_row, f, NULL);
        return sqrt(wind_sum_rows(f->rowsum, rows));
    }
    const int crows = c->ny * c->nz;
    for_each_row(w, nt, crows, restrict_row, f, c);
    return sqrt(wind_sum_rows(c->rowsum, crows));
}

/* Fine row of the prolongation where x is coarsened by two: each coarse cell I feeds fine
 * cells 2I and 2I + 1. base already holds the y and z terms per coarse cell. */
WIND_CLONES static void prolong_row_x2(int n_pairs, const float *restrict e,
                                       const float *restrict axc, const float *restrict base,
                                       const float *restrict fid, float *restrict fp)
{
    for (int I = 0; I < n_pairs; I++) {
        float e0 = e[I];
        float lo = wind_select(axc[I] > 0.0f, e[I - 1], e0);
        float hi = wind_select(axc[I + 1] > 0.0f, e[I + 1], e0);
        float m0 = fid[2 * I] != 0.0f ? 1.0f : 0.0f, m1 = fid[2 * I + 1] != 0.0f ? 1.0f : 0.0f;
        fp[2 * I] += m0 * (base[I] + 0.25f * (lo - e0));
        fp[2 * I + 1] += m1 * (base[I] + 0.25f * (hi - e0));
    }
}

/* The y and z terms of a fine row's correction per coarse cell: e plus a quarter of the
 * difference to the neighbour at offset dy (dz) across an open face, nothing across a
 * closed one or where the axis is not coarsened (offset 0: the neighbour is the cell). */
WIND_CLONES static void prolong_base(int n, const float *restrict e, ptrdiff_t dy, ptrdiff_t dz,
                                     const float *restrict fy, const float *restrict fz,
                                     float *restrict base)
{
    for (int I = 0; I < n; I++) {
        float e0 = e[I], t = 0.0f;
        t += 0.25f * (wind_select(fy[I] > 0.0f, e[I + dy], e0) - e0);
        t += 0.25f * (wind_select(fz[I] > 0.0f, e[I + dz], e0) - e0);
        base[I] = e0 + t;
    }
}

/* Adds the coarse correction to fine row r of level f: linear interpolation from the
 * coarse cell and its neighbour on the fine cell's side along each axis where the coarse
 * cell has two children (weight 1/4 each, the rest on the cell itself); across closed
 * faces the cell's own value stands in for the neighbour (Neumann). Closed fine cells get
 * nothing. */
static void prolong_row(const wind_grid *w, wind_level *f, wind_level *c, int r)
{
    const int *rf = f->r;
    const int ny = f->ny;
    const ptrdiff_t csy = c->sy, csz = c->sz;
    int j = r % ny, k = r / ny;
    int J = j / rf[1], K = k / rf[2];
    size_t f0 = wind_idx(f->sy, f->sz, 0, j, k);
    size_t c0 = wind_idx(c->sy, c->sz, 0, J, K);
    ptrdiff_t dy = rf[1] == 2 && c->wd[1][J] > f->wd[1][j] ? ((j & 1) ? csy : -csy) : 0;
    ptrdiff_t dz = rf[2] == 2 && c->wd[2][K] > f->wd[2][k] ? ((k & 1) ? csz : -csz) : 0;
    /* y and z terms per coarse cell of this row, into the scratch row */
    float *base = row_scratch(w);
    const float *e = c->p + c0;
    const float *fy = c->ay + c0 + (dy > 0 ? csy : 0), *fz = c->az + c0 + (dz > 0 ? csz : 0);
    prolong_base(c->nx, e, dy, dz, fy, fz, base);
    float *fp = f->p + f0;
    const float *fid = f->idiag + f0;
    int done = 0;
    if (rf[0] == 2) {
        done = 2 * (f->nx / 2);
        prolong_row_x2(f->nx / 2, e, c->ax + c0, base, fid, fp);
    }
    /* x not coarsened, or the single child of an odd row's last coarse cell */
    for (int i = done; i < f->nx; i++) {
        if (fid[i] != 0.0f) {
            fp[i] += base[i / rf[0]];
        }
    }
}

static void prolong_add(const wind_grid *w, wind_level *f, wind_level *c)
{
    for_each_row(w, level_threads(w, f), f->ny * f->nz, prolong_row, f, c);
}

static void vcycle(const wind_grid *w, int li)
{
    wind_level *l = (wind_level *)&w->lv[li];
    memset(l->p, 0, l->count * sizeof(float));
    if (li == w->n_levels - 1) {
        for (int s = 0; s < MG_COARSEST_SWEEPS; s++) {
            smooth(w, l);
        }
        return;
    }
    wind_level *c = (wind_level *)&w->lv[li + 1];
    for (int s = 0; s < MG_PRE; s++) {
        smooth(w, l);
    }
    residual_restrict(w, l, c);
    vcycle(w, li + 1);
    prolong_add(w, l, c);
    for (int s = 0; s < MG_POST; s++) {
        smooth(w, l);
    }
}

int wind_mg_solve(wind_grid *w, double tol, int max_it, double *r_final)
{
    wind_level *f = &w->lv[0];
    wind_level *c = w->n_levels > 1 ? &w->lv[1] : NULL;
    double r = residual_restrict(w, f, c);
    int it = 0;
    while (r > tol && it < max_it && isfinite(r)) {
        if (c) {
            vcycle(w, 1);
            prolong_add(w, f, c);
        }
        for (int s = 0; s < MG_FINE_POST; s++) {
            smooth(w, f);
        }
        r = residual_restrict(w, f, c);
        it++;
    }
    *r_final = r;
    return it;
}
