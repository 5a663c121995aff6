/* Physical sanity of the shipped species (server/PHYSICS.md "Trees"):
 * each species is generated and baked, then its first modes and its static response to a
 * uniform wind are checked against what real trees do. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake.h"
#include "check.h"
#include "lsystem.h"
#include "species.h"

#define PHYS_PI    3.14159265358979323846
#define PHYS_MODES 24
#define PHYS_DIRS  8 /* wind azimuths tried; the largest response counts */

typedef struct phys_tree {
    species sp;
    asset a;
    int top;     /* top node of the leader: from the root always into the thickest child */
    int trunk;   /* last node of the trunk (branch order 0) */
} phys_tree;

static int phys_bake(const char *name, phys_tree *t)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/configs/species/%s.json", GALE_SOURCE_DIR, name);
    gale_err err;
    memset(&err, 0, sizeof err);
    memset(t, 0, sizeof *t);
    skeleton s;
    memset(&s, 0, sizeof s);
    int rc = species_load(path, &t->sp, &err);
    if (rc == GALE_OK) {
        rc = lsystem_generate(&t->sp.gen, &s, &err);
    }
    bake_desc d;
    memset(&d, 0, sizeof d);
    d.n_modes = PHYS_MODES;
    bake_report rep;
    if (rc == GALE_OK) {
        rc = bake_run(&s, &t->sp, &d, &t->a, &rep, &err);
    }
    if (rc != GALE_OK) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
        skeleton_fini(&s);
        return rc;
    }
    /* the leader: walk up from the root into the thickest child each time */
    int cur = 0;
    t->trunk = 0;
    for (;;) {
        int best = -1;
        for (int i = cur + 1; i < s.n; i++) {
            if (s.parent[i] == cur && (best < 0 || s.radius[i] > s.radius[best])) {
                best = i;
            }
        }
        if (best < 0) {
            break;
        }
        cur = best;
        if (s.order[cur] == 0) {
            t->trunk = cur;
        }
    }
    t->top = cur;
    printf("%s: %d nodes, height %.2f m, %d leaves, f1 %.3f Hz, f2 %.3f Hz, f3 %.3f Hz\n",
           name, s.n, (double)t->a.height_m, (int)t->a.n_leaves,
           (double)t->a.omega[0] / (2.0 * PHYS_PI), (double)t->a.omega[1] / (2.0 * PHYS_PI),
           (double)t->a.omega[2] / (2.0 * PHYS_PI));
    skeleton_fini(&s);
    return GALE_OK;
}

static double phys_norm3(const float *v)
{
    double x = v[0], y = v[1], z = v[2];
    return sqrt(x * x + y * y + z * z);
}

/* |φ_i(node)| / max over nodes |φ_i|: how much of mode i's motion reaches that node */
static double phys_share(const asset *a, int mode, int node)
{
    const float *phi = a->phi + (size_t)mode * a->n_nodes * 3;
    double mx = 0.0;
    for (uint32_t n = 0; n < a->n_nodes; n++) {
        mx = fmax(mx, phys_norm3(phi + 3 * n));
    }
    return mx > 0.0 ? phys_norm3(phi + 3 * (size_t)node) / mx : 0.0;
}

/* Static response to a uniform horizontal wind of `speed` [m/s]: q_i = f_i / ω_i² with
 * f_i = s(|v|) |v| v·p_i, s the species' streamlining (the steady state of
 * q̈ + γq̇ + ω²q = f), reconstructed with the
 * length-true pose. Returns the largest horizontal displacement of the leader's
 * top over PHYS_DIRS azimuths, as a fraction of the height; *max_node gets the largest
 * displacement of any node, same units. */
static double phys_static(const phys_tree *t, double speed, double *max_node)
{
    const asset *a = &t->a;
    float q[PHYS_MODES];
    float *pos = malloc(sizeof(float) * 3 * a->n_nodes);
    if (!pos) {
        return NAN;
    }
    double top = 0.0, any = 0.0;
    for (int k = 0; k < PHYS_DIRS; k++) {
        double az = 2.0 * PHYS_PI * k / PHYS_DIRS;
        double v[3] = { speed * cos(az), speed * sin(az), 0.0 };
        /* the species' streamlining, as the modal force has it (drag_law.h) */
        const double sl = (double)drag_law_scale(&t->sp.drag, (float)speed);
        for (uint32_t i = 0; i < a->n_modes && i < PHYS_MODES; i++) {
            const float *p = a->wind_basis + 3 * i;
            double f = sl * speed * (v[0] * (double)p[0] + v[1] * (double)p[1] + v[2] * (double)p[2]);
            double w = a->omega[i];
            q[i] = (float)(f / (w * w));
        }
        asset_reconstruct(a, q, a->n_modes, pos);
        for (uint32_t n = 0; n < a->n_nodes; n++) {
            float d[3];
            for (int c = 0; c < 3; c++) {
                d[c] = pos[3 * n + c] - a->rest[3 * n + c];
            }
            double dn = phys_norm3(d);
            any = fmax(any, dn);
            if ((int)n == t->top) {
                top = fmax(top, hypot(d[0], d[1]));
            }
        }
    }
    free(pos);
    *max_node = any / (double)a->height_m;
    return top / (double)a->height_m;
}

/* Band checks common to every species. lo20/hi20: top deflection at 20 m/s as a fraction
 * of height; storm, hi_storm: the same at hurricane speed. */
static void phys_check(const char *name, double lo20, double hi20, double storm, double lo_storm,
                       double hi_storm)
{
    phys_tree t;
    CHECK(phys_bake(name, &t) == GALE_OK);
    if (t.a.n_modes < 4) {
        return;
    }
    /* PHYSICS.md "Trees": first natural frequencies of trees are 0.2-2 Hz */
    double f1 = (double)t.a.omega[0] / (2.0 * PHYS_PI);
    CHECK(f1 >= 0.2 && f1 <= 2.0);
    /* the first two modes are the whole-tree sway in two planes: the trunk top and the
     * leader's top carry a share of the motion: in a twig or branch mode the trunk top
     * moves less than 1% of the mode's largest displacement (measured: 0.0-1.0%), in
     * the oak's crown sway ~4% (its trunk ends at 38% H under a crown that bends too),
     * in the pine's and palm's stem sway 65-100%. The pair lies within 15% in frequency */
    for (int m = 0; m < 2; m++) {
        double st = phys_share(&t.a, m, t.trunk), sl = phys_share(&t.a, m, t.top);
        printf("  mode %d: %.3f Hz, trunk top share %.3f, leader top share %.3f\n", m + 1,
               (double)t.a.omega[m] / (2.0 * PHYS_PI), st, sl);
        CHECK(st >= 0.025);
        CHECK(sl >= 0.3);
    }
    CHECK(t.a.omega[1] <= 1.15f * t.a.omega[0]);
    double mx20, mxs;
    double d20 = phys_static(&t, 20.0, &mx20);
    double ds = phys_static(&t, storm, &mxs);
    printf("  static top deflection: %.1f%% H at 20 m/s (any node %.1f%%), %.1f%% H at %.0f m/s "
           "(any node %.1f%%)\n",
           100.0 * d20, 100.0 * mx20, 100.0 * ds, storm, 100.0 * mxs);
    CHECK(d20 >= lo20 && d20 <= hi20);
    CHECK(ds >= lo_storm && ds <= hi_storm);
    /* no node, twig tips included, swings by more than 15% of the height at 20 m/s (the
     * unsane oak this guards against: 84%, its twig clusters flailing) */
    CHECK(mx20 <= 0.15);
    asset_fini(&t.a);
}

/* Oak: a 16 m open-grown hardwood. Field pulling tests and wind-sway records put the
 * stem top of such trees a few % of the height out at 20 m/s; 2-8% H is the band. At
 * 45 m/s (a category 2 hurricane, past the ~42 m/s where trees break), streamlined, it
 * must still stay under 40% H and bend visibly (> 8% H). */
static void test_oak(void)
{
    phys_check("oak", 0.02, 0.08, 45.0, 0.08, 0.40);
}

/* Pine: an 18 m conifer, stiff stem, small crown area: the same 2-8% H at 20 m/s. */
static void test_pine(void)
{
    phys_check("pine", 0.02, 0.08, 45.0, 0.08, 0.40);
}

/* Palm: slender, soft stem (3-5 GPa effective), built to bend: at 20 m/s it leans a few %
 * to ~15% H; at 60 m/s (category 4, the worst case of the 45-60 m/s band) it bends by
 * tens of % of the height (>= 10% H) yet stays under 40% H in the linear+corrected
 * model. */
static void test_palm(void)
{
    phys_check("palm", 0.02, 0.15, 60.0, 0.10, 0.40);
}

/* The oak's radii obey the pipe model it asks for (lsystem.c ls_pipe): every node at
 * least as thick as the tip floor, and r^e >= sum of r_child^e at every node (float
 * rounding: 1e-4 relative); with pipe_exponent 0 the same grammar leaves hundreds of
 * forks thinner than their children call for, so the check can fail. A pipe_exponent outside 0 or 1.5..4 is refused. */
static void test_pipe_radii(void)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/configs/species/oak.json", GALE_SOURCE_DIR);
    species sp;
    gale_err err;
    memset(&err, 0, sizeof err);
    CHECK(species_load(path, &sp, &err) == GALE_OK);
    double e = sp.gen.pipe_exponent, tip = sp.gen.tip_radius_m;
    CHECK(e >= 2.0 && e <= 3.0 && tip >= 0.008);
    for (int pass = 0; pass < 2; pass++) {
        skeleton s;
        CHECK(lsystem_generate(&sp.gen, &s, &err) == GALE_OK);
        double *sum = calloc((size_t)s.n, sizeof *sum);
        CHECK(sum != NULL);
        if (!sum) {
            skeleton_fini(&s);
            return;
        }
        int thin = 0, short_pipe = 0;
        for (int n = 1; n < s.n; n++) {
            sum[s.parent[n]] += pow((double)s.radius[n], e);
        }
        for (int n = 0; n < s.n; n++) {
            thin += (double)s.radius[n] < tip * (1.0 - 1e-6);
            short_pipe += sum[n] > 0.0 && (double)s.radius[n] < pow(sum[n], 1.0 / e) * (1.0 - 1e-4);
        }
        printf("pipe %s: %d nodes, trunk base r %.3f m, %d thinner than %.3f m, %d short of "
               "the pipe rule\n",
               pass == 0 ? "on" : "off", s.n, (double)s.radius[0], thin, tip, short_pipe);
        if (pass == 0) {
            CHECK(thin == 0 && short_pipe == 0);
        } else {
            CHECK(short_pipe > 0); /* the rules alone break the pipe rule */
        }
        free(sum);
        skeleton_fini(&s);
        sp.gen.pipe_exponent = 0.0;
        sp.gen.tip_radius_m = 0.0;
    }
    lsystem_params bad = lsystem_params_default();
    bad.pipe_exponent = 1.0;
    skeleton s;
    CHECK(lsystem_generate(&bad, &s, &err) == GALE_E_RANGE);
    CHECK_STR_HAS(err.msg, "pipe_exponent");
    bad = lsystem_params_default();
    bad.tip_radius_m = -0.01;
    CHECK(lsystem_generate(&bad, &s, &err) == GALE_E_RANGE);
}

int main(void)
{
    RUN(test_pipe_radii);
    RUN(test_oak);
    RUN(test_pine);
    RUN(test_palm);
    return check_report();
}
