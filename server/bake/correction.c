/* Diener 2008 section 5.2: length-preserving poses per mode and the least-squares fit of
 * eq. 16-17. With a = 1/b the scale of q̃ is fixed (a only rescales v and w), so the fit is
 * a 1D search over b; for each b, v and w follow from a 2x2 normal system shared by all
 * nodes, and the residual from the sample Gram matrix G = U U^T. Modes are fitted in
 * parallel (OpenMP), each independent of the others. */
#include "correction.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

void corr_result_fini(corr_result *r)
{
    if (!r) {
        return;
    }
    free(r->v), free(r->w), free(r->a), free(r->b), free(r->q_amp);
    memset(r, 0, sizeof *r);
}

/* u[3 n] = length-preserving pose of one mode at q, minus rest: each segment p -> i is the
 * rest segment rotated by q (θ_p + θ_i)/2, the mean node rotation over the element, given
 * here as unit axis ax[3 i] and magnitude mag[i] (Rodrigues' formula). */
static void pose(const double *rest, const int *parent, int n, const double *ax,
                 const double *mag, double q, double *u)
{
    u[0] = u[1] = u[2] = 0.0;
    for (int i = 1; i < n; i++) {
        const int p = parent[i];
        const double seg[3] = { rest[3 * i] - rest[3 * p], rest[3 * i + 1] - rest[3 * p + 1],
                                rest[3 * i + 2] - rest[3 * p + 2] };
        const double th = q * mag[i];
        double d[3] = { 0, 0, 0 };
        if (th != 0.0) {
            const double *k = ax + 3 * i, s = sin(th), c1 = 1.0 - cos(th);
            const double kx[3] = { k[1] * seg[2] - k[2] * seg[1], k[2] * seg[0] - k[0] * seg[2],
                                   k[0] * seg[1] - k[1] * seg[0] };
            const double kd = k[0] * seg[0] + k[1] * seg[1] + k[2] * seg[2];
            for (int j = 0; j < 3; j++) {
                d[j] = kx[j] * s + (k[j] * kd - seg[j]) * c1;
            }
        }
        for (int k = 0; k < 3; k++) {
            u[3 * i + k] = u[3 * p + k] + d[k];
        }
    }
}

/* Max relative branch-length error of displaced positions rest + u. */
static double length_error(const double *rest, const int *parent, int n, const double *u)
{
    double worst = 0.0;
    for (int i = 1; i < n; i++) {
        const int p = parent[i];
        double l0 = 0, l1 = 0;
        for (int k = 0; k < 3; k++) {
            const double s0 = rest[3 * i + k] - rest[3 * p + k];
            const double s1 = s0 + u[3 * i + k] - u[3 * p + k];
            l0 += s0 * s0;
            l1 += s1 * s1;
        }
        const double e = fabs(sqrt(l1 / l0) - 1.0);
        if (e > worst) {
            worst = e;
        }
    }
    return worst;
}

static double qt(double b, double q)
{
    return b > 0.0 ? atan(b * q) / b : q;
}

/* Fit residual Σ|U - X c|² for the given b, from G = U U^T (S x S, upper). On return
 * coef[4] = (X^T X)^{-1} (row-major 2x2) when wanted. */
static double fit_residual(const double *g, const double *qs, int ns, double b, double coef[4])
{
    double x1[64], x2[64];
    double s11 = 0, s12 = 0, s22 = 0;
    for (int k = 0; k < ns; k++) {
        x1[k] = qt(b, qs[k]);
        x2[k] = x1[k] * x1[k];
        s11 += x1[k] * x1[k], s12 += x1[k] * x2[k], s22 += x2[k] * x2[k];
    }
    const double det = s11 * s22 - s12 * s12;
    const double i11 = s22 / det, i12 = -s12 / det, i22 = s11 / det;
    if (coef) {
        coef[0] = i11, coef[1] = i12, coef[2] = i12, coef[3] = i22;
    }
    /* tr(P G), P = X (X^T X)^{-1} X^T: Σ_ab inv_ab (X_a^T G X_b) */
    double a11 = 0, a12 = 0, a22 = 0, tr = 0;
    for (int k = 0; k < ns; k++) {
        tr += g[k * ns + k];
        for (int l = 0; l < ns; l++) {
            const double gkl = k <= l ? g[k * ns + l] : g[l * ns + k];
            a11 += x1[k] * gkl * x1[l];
            a12 += x1[k] * gkl * x2[l];
            a22 += x2[k] * gkl * x2[l];
        }
    }
    return tr - (i11 * a11 + 2 * i12 * a12 + i22 * a22);
}

/* Fits mode m (writes r->v, w, a, b, q_amp of that mode only) and returns its branch-
 * length errors: errs = {linear, corrected, pose}. Scratch: u[ns 3n], ev[3n], ax[3n],
 * mag[n]. */
static void fit_mode(const double *rest, const int *parent, int n, const double *phi,
                     const double *phi_rot, const corr_desc *dp, int m, corr_result *r,
                     double *u, double *ev, double *ax, double *mag, double errs[3])
{
    const corr_desc cd = *dp;
    const int ns = cd.n_samples, nc = 3 * n;
    double g[63 * 63];
    errs[0] = errs[1] = errs[2] = 0.0;
    const double *ph = phi + (size_t)m * nc, *rot = phi_rot + (size_t)m * nc;
    double rmax = 0.0;
    for (int i = 0; i < n; i++) {
        const double *t = rot + 3 * i;
        rmax = fmax(rmax, sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
    }
    const double qa = rmax > 0.0 ? cd.amp_rot_rad / rmax : 1.0, qf = cd.fit_range * qa;
    r->q_amp[m] = qa;
    mag[0] = 0.0;
    for (int i = 1; i < n; i++) {
        const int p = parent[i];
        double t[3], tn = 0.0;
        for (int k = 0; k < 3; k++) {
            t[k] = 0.5 * (rot[3 * p + k] + rot[3 * i + k]);
            tn += t[k] * t[k];
        }
        tn = sqrt(tn);
        mag[i] = tn;
        for (int k = 0; k < 3; k++) {
            ax[3 * i + k] = tn > 0.0 ? t[k] / tn : 0.0;
        }
    }
    double qs[63];
    for (int k = 0; k < ns; k++) {
        qs[k] = qf * (2.0 * k / (ns - 1) - 1.0);
        pose(rest, parent, n, ax, mag, qs[k], u + (size_t)k * nc);
    }
    /* G = U U^T (upper triangle) */
    for (int k = 0; k < ns; k++) {
        for (int l = k; l < ns; l++) {
            const double *uk = u + (size_t)k * nc, *ul = u + (size_t)l * nc;
            double acc = 0.0;
            for (int c = 0; c < nc; c++) {
                acc += uk[c] * ul[c];
            }
            g[k * ns + l] = acc;
        }
    }
    /* coarse log scan of b q_f in [0.02, 20], then golden section around the best */
    double best_b = 0.0, best = fit_residual(g, qs, ns, 0.0, NULL);
    const int scan = 24;
    int bi = -1;
    for (int k = 0; k < scan; k++) {
        const double b = 0.02 * pow(1000.0, (double)k / (scan - 1)) / qf;
        const double res = fit_residual(g, qs, ns, b, NULL);
        if (res < best) {
            best = res, best_b = b, bi = k;
        }
    }
    if (bi >= 0) {
        double lo = log(0.02 * pow(1000.0, (double)(bi - 1) / (scan - 1)) / qf);
        double hi = log(0.02 * pow(1000.0, (double)(bi + 1) / (scan - 1)) / qf);
        const double gr = 0.5 * (sqrt(5.0) - 1.0);
        double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
        double f1 = fit_residual(g, qs, ns, exp(x1), NULL);
        double f2 = fit_residual(g, qs, ns, exp(x2), NULL);
        for (int it = 0; it < 40; it++) {
            if (f1 < f2) {
                hi = x2, x2 = x1, f2 = f1, x1 = hi - gr * (hi - lo);
                f1 = fit_residual(g, qs, ns, exp(x1), NULL);
            } else {
                lo = x1, x1 = x2, f1 = f2, x2 = lo + gr * (hi - lo);
                f2 = fit_residual(g, qs, ns, exp(x2), NULL);
            }
        }
        const double bg = exp(0.5 * (lo + hi));
        if (fit_residual(g, qs, ns, bg, NULL) < best) {
            best_b = bg;
        }
    }
    /* b = 0 is the q̃ = q limit; keep b > 0 for the reconstruction form a atan(b q) */
    if (best_b <= 0.0) {
        best_b = 1e-6 / qf;
    }
    double inv[4];
    fit_residual(g, qs, ns, best_b, inv);
    r->b[m] = best_b, r->a[m] = 1.0 / best_b;
    /* [v; w] = (X^T X)^{-1} X^T U */
    double *v = r->v + (size_t)m * nc, *w = r->w + (size_t)m * nc;
    for (int k = 0; k < ns; k++) {
        const double x1 = qt(best_b, qs[k]), x2 = x1 * x1;
        const double cv = inv[0] * x1 + inv[1] * x2, cw = inv[2] * x1 + inv[3] * x2;
        const double *uk = u + (size_t)k * nc;
        for (int c = 0; c < nc; c++) {
            v[c] += cv * uk[c];
            w[c] += cw * uk[c];
        }
    }
    /* errors at the stated amplitude: q = ±q_a, ±q_a/2 */
    const double qe[4] = { -qa, -0.5 * qa, 0.5 * qa, qa };
    for (int k = 0; k < 4; k++) {
        for (int c = 0; c < nc; c++) {
            ev[c] = qe[k] * ph[c];
        }
        errs[0] = fmax(errs[0], length_error(rest, parent, n, ev));
        const double x1 = qt(best_b, qe[k]);
        for (int c = 0; c < nc; c++) {
            ev[c] = x1 * v[c] + x1 * x1 * w[c];
        }
        errs[1] = fmax(errs[1], length_error(rest, parent, n, ev));
        if (k == 0 || k == 3) {
            pose(rest, parent, n, ax, mag, qe[k], ev);
            errs[2] = fmax(errs[2], length_error(rest, parent, n, ev));
        }
    }
}

int corr_fit(const double *rest, const int *parent, int n_nodes, const double *phi,
             const double *phi_rot, int n_modes, const corr_desc *d, corr_result *r,
             gale_err *err)
{
    memset(r, 0, sizeof *r);
    corr_desc cd = d ? *d : (corr_desc){ 0 };
    if (cd.amp_rot_rad <= 0.0) {
        cd.amp_rot_rad = 0.35;
    }
    if (cd.fit_range <= 0.0) {
        cd.fit_range = 2.0;
    }
    if (cd.n_samples <= 0) {
        cd.n_samples = 9;
    }
    if (cd.n_samples < 5 || cd.n_samples > 63 || cd.n_samples % 2 == 0) {
        return gale_errf(err, GALE_E_RANGE, "correction: n_samples %d, expected odd in 5..63",
                         cd.n_samples);
    }
    const int n = n_nodes, nm = n_modes, ns = cd.n_samples, nc = 3 * n;
    r->n_modes = nm, r->n_nodes = n, r->amp_rot_rad = cd.amp_rot_rad;
    r->v = calloc((size_t)nm * nc, sizeof *r->v);
    r->w = calloc((size_t)nm * nc, sizeof *r->w);
    r->a = calloc((size_t)nm, sizeof *r->a);
    r->b = calloc((size_t)nm, sizeof *r->b);
    r->q_amp = calloc((size_t)nm, sizeof *r->q_amp);
    /* modes are independent: one per thread, each with its own scratch */
    const int nt = omp_get_max_threads();
    double *u = malloc((size_t)nt * ns * nc * sizeof *u); /* samples x coords */
    double *ev = malloc((size_t)nt * nc * sizeof *ev);
    double *ax = malloc((size_t)nt * nc * sizeof *ax), *mag = malloc((size_t)nt * n * sizeof *mag);
    double *errs = calloc((size_t)nm * 3, sizeof *errs);
    if (!r->v || !r->w || !r->a || !r->b || !r->q_amp || !u || !ev || !ax || !mag || !errs) {
        free(u), free(ev), free(ax), free(mag), free(errs);
        corr_result_fini(r);
        return gale_errf(err, GALE_E_NOMEM, "correction: out of memory for %d nodes", n);
    }
#pragma omp parallel for schedule(dynamic) num_threads(nt)
    for (int m = 0; m < nm; m++) {
        const int t = omp_get_thread_num();
        fit_mode(rest, parent, n, phi, phi_rot, &cd, m, r, u + (size_t)t * ns * nc,
                 ev + (size_t)t * nc, ax + (size_t)t * nc, mag + (size_t)t * n, errs + 3 * m);
    }
    for (int m = 0; m < nm; m++) {
        r->err_linear = fmax(r->err_linear, errs[3 * m]);
        r->err_corrected = fmax(r->err_corrected, errs[3 * m + 1]);
        r->err_pose = fmax(r->err_pose, errs[3 * m + 2]);
    }
    free(u), free(ev), free(ax), free(mag), free(errs);
    return GALE_OK;
}
