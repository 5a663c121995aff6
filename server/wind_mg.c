/* Pressure Poisson solve (Oliapuram & Kumar 2010 eq. 9) by geometric multigrid on the
 * cell-centred MAC pressure: V-cycles of red-black Gauss-Seidel, full coarsening while
 * the grid has z layers left, then x-y only; warm-started from the previous step.
 *
 * Why multigrid and not the paper's Jacobi: on 256x256x16 a Jacobi sweep costs 0.71 ms on
 * this machine, 4 sweeps leave 96 % of the error and even 20,000 leave 28 % (the slowest
 * mode needs ~92,000 sweeps per decade; REFERENCE.md "Pressure solve"). Red-black SOR
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
    return (size_t)l->nx * (size_t)l->ny * (size_t)l->nz >= WIND_PAR_MIN ? w->d.threads : 1;
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
        for (int a = 0; a < 3; a++) {
            l->wd[a] = calloc((size_t)n[a], sizeof(int));
        }
        w->n_levels++;
        if (!l->p || !l->b || !l->ax || !l->ay || !l->az || !l->diag || !l->idiag ||
            !l->rowsum || !l->wd[0] || !l->wd[1] || !l->wd[2]) {
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
    w->scratch = calloc((size_t)w->d.threads * (size_t)(w->nx + 2), sizeof(float));
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
    for (int i = 0; i < nx; i++) {
        float nb = ax[i] * p[i - 1] + ax[i + 1] * p[i + 1] + ay[i] * p[i - sy] +
                   ay[i + sy] * p[i + sy] + az[i] * p[i - sz] + az[i + sz] * p[i + sz];
        out[i] = want_resid ? b[i] - (dg[i] * p[i] - nb) : b[i] + nb;
    }
}

static float *row_scratch(const wind_grid *w)
{
    return w->scratch + (size_t)omp_get_thread_num() * (size_t)(w->nx + 2);
}

/* One red-black Gauss-Seidel sweep. Each colour reads only the other colour, so the
 * result does not depend on the thread partition. A row's numerators are computed for
 * every cell (vectorised) and only the current colour's are stored. */
static void smooth(const wind_grid *w, wind_level *l)
{
    const int nx = l->nx, ny = l->ny, nz = l->nz, rows = ny * nz;
    for (int colour = 0; colour < 2; colour++) {
#pragma omp parallel for schedule(static) num_threads(level_threads(w, l))
        for (int r = 0; r < rows; r++) {
            int j = r % ny, k = r / ny;
            size_t c0 = wind_idx(l->sy, l->sz, 0, j, k);
            float *t = row_scratch(w);
            row_stencil(nx, l->sy, l->sz, l->p + c0, l->b + c0, l->ax + c0, l->ay + c0,
                        l->az + c0, l->diag + c0, 0, t);
            float *p = l->p + c0;
            const float *id = l->idiag + c0;
            for (int i = (colour + j + k) & 1; i < nx; i += 2) {
                p[i] = t[i] * id[i];
            }
        }
    }
}

/* Computes the residual of level l, restricts it to level l+1's b (the sum over the
 * children: a coarse row is the sum of its children's rows in flux form) and returns
 * ||r||_2 of level l. */
static double residual_restrict(const wind_grid *w, wind_level *f, wind_level *c)
{
    if (!c) {
        const int ny = f->ny, rows = f->ny * f->nz;
#pragma omp parallel for schedule(static) num_threads(level_threads(w, f))
        for (int r = 0; r < rows; r++) {
            int j = r % ny, k = r / ny;
            size_t c0 = wind_idx(f->sy, f->sz, 0, j, k);
            float *t = row_scratch(w);
            row_stencil(f->nx, f->sy, f->sz, f->p + c0, f->b + c0, f->ax + c0, f->ay + c0,
                        f->az + c0, f->diag + c0, 1, t);
            double s = 0.0;
            for (int i = 0; i < f->nx; i++) {
                s += (double)(t[i] * t[i]);
            }
            f->rowsum[r] = s;
        }
        return sqrt(wind_sum_rows(f->rowsum, rows));
    }
    const int *rf = f->r;
    const int cny = c->ny, crows = c->ny * c->nz, cnx = c->nx;
#pragma omp parallel for schedule(static) num_threads(level_threads(w, f))
    for (int r = 0; r < crows; r++) {
        int J = r % cny, K = r / cny;
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
                row_stencil(f->nx, f->sy, f->sz, f->p + c0, f->b + c0, f->ax + c0, f->ay + c0,
                            f->az + c0, f->diag + c0, 1, t);
                float rs = 0.0f;
                for (int i = 0; i < f->nx; i++) {
                    rs += t[i] * t[i];
                }
                s += (double)rs;
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
    return sqrt(wind_sum_rows(c->rowsum, crows));
}

/* Adds the coarse correction to level f: linear interpolation from the coarse cell and
 * its neighbour on the fine cell's side along each axis where the coarse cell has two
 * children (weight 1/4 each, the rest on the cell itself); across closed faces the cell's
 * own value stands in for the neighbour (Neumann). */
static void prolong_add(const wind_grid *w, wind_level *f, const wind_level *c)
{
    const int *rf = f->r;
    const int ny = f->ny, rows = f->ny * f->nz;
    const ptrdiff_t csy = c->sy, csz = c->sz;
#pragma omp parallel for schedule(static) num_threads(level_threads(w, f))
    for (int r = 0; r < rows; r++) {
        int j = r % ny, k = r / ny;
        int J = j / rf[1], K = k / rf[2];
        size_t f0 = wind_idx(f->sy, f->sz, 0, j, k);
        ptrdiff_t dy = rf[1] == 2 && c->wd[1][J] > f->wd[1][j] ? ((j & 1) ? csy : -csy) : 0;
        ptrdiff_t dz = rf[2] == 2 && c->wd[2][K] > f->wd[2][k] ? ((k & 1) ? csz : -csz) : 0;
        for (int i = 0; i < f->nx; i++) {
            size_t fc = f0 + (size_t)i;
            if (f->idiag[fc] == 0.0f) {
                continue;
            }
            int I = i / rf[0];
            size_t cc = wind_idx(c->sy, c->sz, I, J, K);
            const float e0 = c->p[cc];
            float e = e0;
            if (rf[0] == 2 && c->wd[0][I] > f->wd[0][i]) {
                ptrdiff_t dx = (i & 1) ? 1 : -1;
                float a = c->ax[(i & 1) ? cc + 1 : cc];
                e += 0.25f * ((a > 0.0f ? c->p[(ptrdiff_t)cc + dx] : e0) - e0);
            }
            if (dy) {
                float a = c->ay[dy > 0 ? cc + (size_t)csy : cc];
                e += 0.25f * ((a > 0.0f ? c->p[(ptrdiff_t)cc + dy] : e0) - e0);
            }
            if (dz) {
                float a = c->az[dz > 0 ? cc + (size_t)csz : cc];
                e += 0.25f * ((a > 0.0f ? c->p[(ptrdiff_t)cc + dz] : e0) - e0);
            }
            f->p[fc] += e;
        }
    }
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
