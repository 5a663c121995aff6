/* Randomized bracketed L-system tree generator (Oliapuram & Kumar 2010 section 1.4).
 * Phase 1 expands the grammar F = G [R1 F] ... [Rk F] [F] into stems (one G each: a
 * curved axis with length and radii shrinking with depth, a random twist about the
 * axis); phase 2 cuts every stem into elements and emits nodes parents-first. Each stem
 * draws from its own random stream keyed by its place in the grammar, so changing the
 * depth or the segment length keeps every stem that remains where it was. */
#include "lsystem.h"
#include "hash.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LS_PI  3.14159265358979323846
#define LS_DEG (LS_PI / 180.0)
/* control pieces per stem axis: the curve is fixed by these, not by the segmentation */
#define LS_KNOTS 8
/* elements shorter than this fraction of the trunk hurt FEM conditioning */
#define LS_MIN_SEG_FRAC 0.02
/* stems and nodes beyond which a request is refused (10^6 nodes ~ 40 MB of skeleton) */
#define LS_MAX_STEMS 200000
#define LS_MAX_NODES 1000000
/* thinnest radius emitted [m]: a 2 mm twig; thinner ones would be numerically void */
#define LS_MIN_RADIUS 0.002

typedef struct ls_stem {
    int parent;                 /* stem index, -1 for the trunk */
    int depth;                  /* 0 trunk */
    double t;                   /* attachment as a fraction of the parent's length */
    double len;                 /* arc length [m] */
    double r0, r1;              /* base and tip radius [m] */
    double pt[LS_KNOTS + 1][3]; /* axis knots, equal arc length apart */
    double dir[LS_KNOTS][3];    /* unit direction of each piece */
    double nrm[LS_KNOTS][3];    /* unit normal of each piece (parallel-transported) */
    uint64_t key;               /* random stream of this stem */
} ls_stem;

typedef struct ls_stems {
    ls_stem *s;
    int n, cap;
    const char *where; /* for messages: ls_where() of the parameters */
    int depth;         /* levels being expanded, for messages */
} ls_stems;

/* First word of every message: the species file the parameters came from. */
static const char *ls_where(const lsystem_params *p)
{
    return p->where[0] ? p->where : "lsystem";
}

/* uniform in [0, 1) with 53 random bits */
static double ls_uniform(uint64_t *state)
{
    return (double)(hash64_splitmix(state) >> 11) * (1.0 / 9007199254740992.0);
}

/* uniform in [-1, 1) */
static double ls_signed(uint64_t *state)
{
    return 2.0 * ls_uniform(state) - 1.0;
}

static uint64_t ls_child_key(uint64_t parent_key, int child)
{
    uint64_t st = parent_key ^ (0xd1b54a32d192ed03ull * (uint64_t)(child + 1));
    return hash64_splitmix(&st);
}

static double ls_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void ls_cross(const double a[3], const double b[3], double out[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

static int ls_normalize(double v[3])
{
    double l = sqrt(ls_dot(v, v));
    if (!(l > 1e-12)) {
        return -1;
    }
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
    return 0;
}

/* Rodrigues: rotates v about unit axis k by angle a. */
static void ls_rotate(double v[3], const double k[3], double a)
{
    double c = cos(a), s = sin(a), kv[3];
    ls_cross(k, v, kv);
    double kd = ls_dot(k, v) * (1.0 - c);
    for (int i = 0; i < 3; i++) {
        v[i] = v[i] * c + kv[i] * s + k[i] * kd;
    }
}

/* Turns direction d (and its normal n, kept perpendicular) toward the unit target by
 * at most angle a, never past it. */
static void ls_turn_toward(double d[3], double n[3], const double target[3], double a)
{
    double axis[3];
    ls_cross(d, target, axis);
    double s = sqrt(ls_dot(axis, axis));
    if (s < 1e-9) {
        return;
    }
    double between = atan2(s, ls_dot(d, target));
    if (a > between) {
        a = between;
    }
    if (a < -between) {
        a = -between;
    }
    axis[0] /= s;
    axis[1] /= s;
    axis[2] /= s;
    ls_rotate(d, axis, a);
    ls_rotate(n, axis, a);
}

/* Re-orthonormalises n against unit d (parallel transport of the frame). */
static void ls_fix_normal(const double d[3], double n[3])
{
    double k = ls_dot(n, d);
    for (int i = 0; i < 3; i++) {
        n[i] -= k * d[i];
    }
    if (ls_normalize(n) != 0) {
        double alt[3] = { 1.0, 0.0, 0.0 };
        if (fabs(d[0]) > 0.9) {
            alt[0] = 0.0;
            alt[1] = 1.0;
        }
        k = ls_dot(alt, d);
        for (int i = 0; i < 3; i++) {
            n[i] = alt[i] - k * d[i];
        }
        ls_normalize(n);
    }
}

/* Lays the axis of stem s from base point, start direction d and normal n: LS_KNOTS
 * equal pieces, each turned by the bend toward ±z (or toward `side` for the trunk
 * curve) and a random wobble about a random perpendicular. */
static void ls_grow_axis(ls_stem *s, const double base[3], const double d0[3], const double n0[3],
                         double bend_rad, const double bend_target[3], double wobble_rad,
                         uint64_t *rng)
{
    double d[3] = { d0[0], d0[1], d0[2] };
    double n[3] = { n0[0], n0[1], n0[2] };
    double piece = s->len / LS_KNOTS;
    memcpy(s->pt[0], base, sizeof s->pt[0]);
    for (int k = 0; k < LS_KNOTS; k++) {
        if (k > 0) {
            double step = fabs(bend_rad) / LS_KNOTS;
            ls_turn_toward(d, n, bend_target, step);
            if (wobble_rad > 0.0) {
                double b[3], axis[3];
                ls_cross(d, n, b);
                double phi = LS_PI * ls_signed(rng);
                for (int i = 0; i < 3; i++) {
                    axis[i] = cos(phi) * n[i] + sin(phi) * b[i];
                }
                ls_rotate(d, axis, wobble_rad * ls_signed(rng) / sqrt((double)LS_KNOTS));
            }
            ls_normalize(d);
            ls_fix_normal(d, n);
        }
        memcpy(s->dir[k], d, sizeof s->dir[k]);
        memcpy(s->nrm[k], n, sizeof s->nrm[k]);
        for (int i = 0; i < 3; i++) {
            s->pt[k + 1][i] = s->pt[k][i] + piece * d[i];
        }
    }
}

/* Point of the axis at fraction t of its length. */
static void ls_axis_at(const ls_stem *s, double t, double out[3])
{
    double u = t * LS_KNOTS;
    int k = (int)floor(u);
    if (k < 0) {
        k = 0;
    }
    if (k > LS_KNOTS - 1) {
        k = LS_KNOTS - 1;
    }
    double f = u - k;
    for (int i = 0; i < 3; i++) {
        out[i] = s->pt[k][i] + f * (s->pt[k + 1][i] - s->pt[k][i]);
    }
}

static int ls_piece_at(double t)
{
    int k = (int)floor(t * LS_KNOTS);
    return k < 0 ? 0 : (k > LS_KNOTS - 1 ? LS_KNOTS - 1 : k);
}

static ls_stem *ls_push(ls_stems *st, gale_err *err)
{
    if (st->n == st->cap) {
        if (st->cap >= LS_MAX_STEMS) {
            gale_errf(err, GALE_E_RANGE,
                      "%s: generator.depth: %d levels grow more than %d stems: expected fewer "
                      "(lower depth, whorls, per_whorl or tip_children)",
                      st->where, st->depth, LS_MAX_STEMS);
            return NULL;
        }
        int cap = st->cap ? 2 * st->cap : 256;
        if (cap > LS_MAX_STEMS) {
            cap = LS_MAX_STEMS;
        }
        ls_stem *s = realloc(st->s, (size_t)cap * sizeof *s);
        if (!s) {
            gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %d stems", st->where, cap);
            return NULL;
        }
        st->s = s;
        st->cap = cap;
    }
    ls_stem *s = &st->s[st->n++];
    memset(s, 0, sizeof *s);
    return s;
}

/* Adds one child of stem pi at fraction t, angle `ang` from the parent axis, azimuth
 * phi about it; returns 0, or <0 on error. Children too short are not grown. */
static int ls_add_child(ls_stems *st, int pi, int child_no, double t, double ang, double phi,
                        double len, const lsystem_rule *r, double min_len, double wobble_rad,
                        gale_err *err)
{
    if (len < min_len) {
        return GALE_OK;
    }
    ls_stem *c = ls_push(st, err);
    if (!c) {
        return err ? err->code : GALE_E_NOMEM;
    }
    const ls_stem *p = &st->s[pi]; /* after ls_push: the array may have moved */
    c->parent = pi;
    c->depth = p->depth + 1;
    c->t = t;
    c->len = len;
    c->key = ls_child_key(p->key, child_no);
    double pr = p->r0 + (p->r1 - p->r0) * t;
    c->r0 = fmax(pr * r->radius_ratio, LS_MIN_RADIUS);
    c->r1 = fmax(c->r0 * r->taper, LS_MIN_RADIUS);
    int k = ls_piece_at(t);
    const double *T = p->dir[k], *N = p->nrm[k];
    double B[3], d[3], n[3], base[3];
    ls_cross(T, N, B);
    for (int i = 0; i < 3; i++) {
        double side = cos(phi) * N[i] + sin(phi) * B[i];
        d[i] = cos(ang) * T[i] + sin(ang) * side;
        n[i] = T[i];
    }
    ls_normalize(d);
    ls_fix_normal(d, n);
    ls_axis_at(p, t, base);
    uint64_t rng = c->key;
    double up[3] = { 0.0, 0.0, r->bend_deg >= 0.0 ? 1.0 : -1.0 };
    ls_grow_axis(c, base, d, n, r->bend_deg * LS_DEG, up, wobble_rad, &rng);
    return GALE_OK;
}

/* Phase 1: expands the grammar to `depth` levels. */
static int ls_expand(const lsystem_params *p, int depth, ls_stems *st, gale_err *err)
{
    double min_len = LS_MIN_SEG_FRAC * p->trunk_length_m;
    double wobble = p->wobble_deg * LS_DEG;
    st->where = ls_where(p);
    st->depth = depth;
    ls_stem *tr = ls_push(st, err);
    if (!tr) {
        return err ? err->code : GALE_E_NOMEM;
    }
    tr->parent = -1;
    tr->len = p->trunk_length_m;
    tr->r0 = p->trunk_radius_m;
    tr->r1 = fmax(p->trunk_radius_m * p->trunk_taper, LS_MIN_RADIUS);
    uint64_t seed_state = p->seed;
    tr->key = hash64_splitmix(&seed_state);
    {
        uint64_t rng = tr->key;
        double side_az = 2.0 * LS_PI * ls_uniform(&rng);
        double side[3] = { cos(side_az), sin(side_az), 0.0 };
        double base[3] = { 0.0, 0.0, 0.0 }, d[3] = { 0.0, 0.0, 1.0 }, n[3] = { 1.0, 0.0, 0.0 };
        ls_grow_axis(tr, base, d, n, p->trunk_bend_deg * LS_DEG, side, wobble * 0.5, &rng);
    }
    for (int si = 0; si < st->n; si++) {
        if (st->s[si].depth >= depth) {
            continue;
        }
        const lsystem_rule *r = st->s[si].depth == 0 ? &p->trunk : &p->branch;
        uint64_t rng = st->s[si].key ^ 0x5851f42d4c957f2dull;
        double plen = st->s[si].len;
        double az0 = 2.0 * LS_PI * ls_uniform(&rng);
        int child_no = 0;
        for (int w = 0; w < r->whorls; w++) {
            double f = r->whorls > 1 ? (double)w / (r->whorls - 1) : 0.5;
            double spacing = r->whorls > 1 ? (r->end - r->start) / (r->whorls - 1) : 0.0;
            double t = r->start + (r->end - r->start) * f + 0.25 * spacing * ls_signed(&rng);
            t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
            double az =
                az0 + w * p->twist_deg * LS_DEG + p->twist_jitter_deg * LS_DEG * ls_signed(&rng);
            double lmul = 1.0 + (r->length_top - 1.0) * f;
            for (int c = 0; c < r->per_whorl; c++) {
                double ang = (r->angle_deg + r->angle_jitter_deg * ls_signed(&rng)) * LS_DEG;
                double phi = az + 2.0 * LS_PI * c / r->per_whorl +
                             0.3 * LS_PI / r->per_whorl * ls_signed(&rng);
                double len =
                    plen * r->length_ratio * lmul * (1.0 + r->length_jitter * ls_signed(&rng));
                int grow = ls_uniform(&rng) >= r->prune_prob;
                if (grow) {
                    int rc =
                        ls_add_child(st, si, child_no, t, ang, phi, len, r, min_len, wobble, err);
                    if (rc != 0) {
                        return rc;
                    }
                }
                child_no++;
            }
        }
        double taz = az0 + p->twist_deg * LS_DEG * r->whorls;
        for (int c = 0; c < r->tip_children; c++) {
            double ang = (r->tip_angle_deg + r->angle_jitter_deg * ls_signed(&rng)) * LS_DEG;
            double phi = taz + 2.0 * LS_PI * c / r->tip_children +
                         0.3 * LS_PI / r->tip_children * ls_signed(&rng);
            double len = plen * r->length_ratio * (1.0 + r->length_jitter * ls_signed(&rng));
            int grow = ls_uniform(&rng) >= r->prune_prob;
            if (grow) {
                int rc =
                    ls_add_child(st, si, child_no, 1.0, ang, phi, len, r, min_len, wobble, err);
                if (rc != 0) {
                    return rc;
                }
            }
            child_no++;
        }
        if (r->tip_continue) {
            double ang = 0.3 * r->angle_jitter_deg * LS_DEG * ls_uniform(&rng);
            double phi = 2.0 * LS_PI * ls_uniform(&rng);
            double len = plen * r->continue_ratio * (1.0 + r->length_jitter * ls_signed(&rng));
            int rc = ls_add_child(st, si, child_no, 1.0, ang, phi, len, r, min_len, wobble, err);
            if (rc != 0) {
                return rc;
            }
        }
    }
    return GALE_OK;
}

static int ls_segments(const ls_stem *s, double seg)
{
    double k = floor(s->len / seg); /* never shorter than seg, unless the stem is */
    return k < 1.0 ? 1 : (k > 100000.0 ? 100000 : (int)k);
}

static long ls_count(const ls_stems *st, double seg)
{
    long n = 1;
    for (int i = 0; i < st->n; i++) {
        n += ls_segments(&st->s[i], seg);
    }
    return n;
}

/* Phase 2: cuts each stem into elements of about `seg` and emits nodes parents-first.
 * The node count is known before anything is allocated; past the limit the message names
 * the key that set the segment length (target_nodes when given, else segment_m). */
static int ls_emit(const lsystem_params *p, const ls_stems *st, double seg, skeleton *out,
                   gale_err *err)
{
    long total = ls_count(st, seg);
    if (total > LS_MAX_NODES && p->target_nodes > 0) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: generator.target_nodes: %ld nodes at the closest segment length: "
                         "expected at most %d",
                         st->where, total, LS_MAX_NODES);
    }
    if (total > LS_MAX_NODES) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: generator.segment_m: %ld nodes with %.3g m elements: expected at "
                         "most %d (longer segment_m, or set target_nodes)",
                         st->where, total, seg, LS_MAX_NODES);
    }
    int rc = skeleton_alloc(out, (int)total, err);
    if (rc != 0) {
        return rc;
    }
    int *first = malloc((size_t)st->n * sizeof *first); /* first node of each stem */
    int *nseg = malloc((size_t)st->n * sizeof *nseg);
    int *base = malloc((size_t)st->n * sizeof *base); /* node each stem grows from */
    if (!first || !nseg || !base) {
        free(first);
        free(nseg);
        free(base);
        skeleton_fini(out);
        return gale_errf(err, GALE_E_NOMEM, "%s: out of memory for %d stems", st->where,
                         st->n);
    }
    out->parent[0] = -1;
    out->radius[0] = (float)st->s[0].r0;
    out->order[0] = 0;
    int next = 1;
    for (int si = 0; si < st->n; si++) {
        const ls_stem *s = &st->s[si];
        nseg[si] = ls_segments(s, seg);
        double shift[3] = { 0.0, 0.0, 0.0 };
        if (s->parent < 0) {
            base[si] = 0;
        } else {
            int pi = s->parent;
            int j = (int)floor(s->t * nseg[pi] + 0.5);
            base[si] = j == 0 ? base[pi] : first[pi] + j - 1;
            for (int i = 0; i < 3; i++) {
                shift[i] = (double)out->pos[3 * base[si] + i] - s->pt[0][i];
            }
        }
        first[si] = next;
        for (int j = 1; j <= nseg[si]; j++) {
            double t = (double)j / nseg[si], p3[3];
            ls_axis_at(s, t, p3);
            int id = next++;
            out->parent[id] = j == 1 ? base[si] : id - 1;
            for (int i = 0; i < 3; i++) {
                out->pos[3 * id + i] = (float)(p3[i] + shift[i]);
            }
            out->radius[id] = (float)(s->r0 + (s->r1 - s->r0) * t);
            out->order[id] = s->depth;
        }
    }
    free(first);
    free(nseg);
    free(base);
    return GALE_OK;
}

/* Raises radii to the tip floor and, with e > 0, to the pipe model (Leonardo's rule as
 * measured by Eloy 2011, Phys. Rev. Lett. 107, 258101: r^e = sum of r_child^e, e ~ 2-2.5):
 * R(n) = max(r(n), (sum over children c of R(c)^e)^(1/e)), leaves first. Without it the
 * rules' geometric shrink leaves millimetre twigs whose local modes undercut the whole
 * tree's sway. Nodes come parents-first, so one backward sweep suffices. */
static void ls_pipe(skeleton *s, double tip, double e)
{
    double floor_r = tip > 0.0 ? tip : LS_MIN_RADIUS;
    for (int n = 0; n < s->n; n++) {
        if (s->radius[n] < (float)floor_r) {
            s->radius[n] = (float)floor_r;
        }
    }
    if (!(e > 0.0)) {
        return;
    }
    /* acc[n]: sum of R(c)^e over the children c of n seen so far */
    double *acc = calloc((size_t)s->n, sizeof *acc);
    if (!acc) {
        return; /* the radii stay as the rules gave them: valid, only less sane */
    }
    for (int n = s->n - 1; n >= 0; n--) {
        double r = s->radius[n], rp = acc[n] > 0.0 ? pow(acc[n], 1.0 / e) : 0.0;
        if (rp > r) {
            r = rp;
            s->radius[n] = (float)r;
        }
        if (s->parent[n] >= 0) {
            acc[s->parent[n]] += pow(r, e);
        }
    }
    free(acc);
}

/* name: the rule's key path ("generator.trunk"); where: ls_where(). */
static int ls_check_rule(const lsystem_rule *r, const char *where, const char *name,
                         gale_err *err)
{
    if (r->whorls < 0 || r->whorls > 64 || r->per_whorl < 0 || r->per_whorl > 16 ||
        r->tip_children < 0 || r->tip_children > 32) {
        return gale_errf(
            err, GALE_E_RANGE,
            "%s: %s: whorls 0..64, per_whorl 0..16, tip_children 0..32, got %d, %d, %d", where,
            name, r->whorls, r->per_whorl, r->tip_children);
    }
    if (!(r->start >= 0.0 && r->start <= r->end && r->end <= 1.0)) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: %s: expected 0 <= start <= end <= 1, got %g, %g", where, name,
                         r->start, r->end);
    }
    if (!(r->length_ratio > 0.0 && r->length_ratio <= 2.0) ||
        !(r->radius_ratio > 0.0 && r->radius_ratio <= 1.0) ||
        !(r->taper > 0.0 && r->taper <= 1.0) || !(r->length_top > 0.0 && r->length_top <= 4.0) ||
        !(r->length_jitter >= 0.0 && r->length_jitter <= 0.9) ||
        !(r->prune_prob >= 0.0 && r->prune_prob <= 1.0) ||
        !(r->continue_ratio >= 0.0 && r->continue_ratio <= 2.0) || !isfinite(r->angle_deg) ||
        !isfinite(r->tip_angle_deg) || !isfinite(r->angle_jitter_deg) || !isfinite(r->bend_deg)) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: %s: a ratio, taper, jitter or angle is out of range", where,
                         name);
    }
    if (r->tip_continue && !(r->continue_ratio > 0.0)) {
        return gale_errf(err, GALE_E_RANGE, "%s: %s: tip_continue needs continue_ratio > 0",
                         where, name);
    }
    return GALE_OK;
}

lsystem_params lsystem_params_default(void)
{
    lsystem_params p;
    memset(&p, 0, sizeof p);
    p.seed = 1;
    p.depth = 4;
    p.trunk_length_m = 6.0;
    p.trunk_radius_m = 0.3;
    p.trunk_taper = 0.5;
    p.segment_m = 0.0;
    p.twist_deg = 137.5;
    p.twist_jitter_deg = 20.0;
    p.wobble_deg = 10.0;
    p.trunk = (lsystem_rule){ .whorls = 3,
                              .per_whorl = 1,
                              .start = 0.45,
                              .end = 0.85,
                              .angle_deg = 50.0,
                              .tip_children = 3,
                              .tip_angle_deg = 30.0,
                              .angle_jitter_deg = 10.0,
                              .length_ratio = 0.7,
                              .length_top = 0.8,
                              .length_jitter = 0.15,
                              .radius_ratio = 0.55,
                              .taper = 0.4,
                              .bend_deg = 10.0 };
    p.branch = (lsystem_rule){ .whorls = 2,
                               .per_whorl = 1,
                               .start = 0.35,
                               .end = 0.8,
                               .angle_deg = 45.0,
                               .tip_children = 2,
                               .tip_angle_deg = 25.0,
                               .angle_jitter_deg = 12.0,
                               .length_ratio = 0.62,
                               .length_top = 0.9,
                               .length_jitter = 0.15,
                               .radius_ratio = 0.6,
                               .taper = 0.45,
                               .bend_deg = 5.0,
                               .prune_prob = 0.05 };
    return p;
}

int lsystem_generate(const lsystem_params *p, skeleton *out, gale_err *err)
{
    memset(out, 0, sizeof *out);
    const char *where = ls_where(p);
    if (p->depth < 0 || p->depth > 10) {
        return gale_errf(err, GALE_E_RANGE, "%s: generator.depth: expected 0..10, got %d", where,
                         p->depth);
    }
    if (!(p->trunk_length_m > 0.0 && p->trunk_length_m <= 200.0) ||
        !(p->trunk_radius_m > 0.0 && p->trunk_radius_m <= 10.0)) {
        return gale_errf(
            err, GALE_E_RANGE,
            "%s: generator.trunk_length_m, trunk_radius_m: expected (0, 200] m and (0, 10] m, "
            "got %g, %g",
            where, p->trunk_length_m, p->trunk_radius_m);
    }
    if (!(p->trunk_taper > 0.0 && p->trunk_taper <= 1.0) || !(p->segment_m >= 0.0) ||
        !isfinite(p->segment_m) || !isfinite(p->trunk_bend_deg) || !isfinite(p->twist_deg) ||
        !isfinite(p->twist_jitter_deg) || !(p->wobble_deg >= 0.0 && p->wobble_deg <= 90.0) ||
        !(p->tip_radius_m >= 0.0 && p->tip_radius_m <= 1.0) ||
        !(p->pipe_exponent == 0.0 || (p->pipe_exponent >= 1.5 && p->pipe_exponent <= 4.0))) {
        return gale_errf(err, GALE_E_RANGE,
                         "%s: generator: trunk_taper (0, 1], segment_m >= 0, wobble 0..90 deg, "
                         "tip_radius_m 0..1, pipe_exponent 0 or 1.5..4 expected",
                         where);
    }
    if (p->target_nodes < 0 || p->target_nodes > LS_MAX_NODES) {
        return gale_errf(err, GALE_E_RANGE, "%s: generator.target_nodes: expected 0..%d, got %d",
                         where, LS_MAX_NODES, p->target_nodes);
    }
    int rc = ls_check_rule(&p->trunk, where, "generator.trunk", err);
    if (rc == 0) {
        rc = ls_check_rule(&p->branch, where, "generator.branch", err);
    }
    if (rc != 0) {
        return rc;
    }
    double min_seg = LS_MIN_SEG_FRAC * p->trunk_length_m;
    double seg = p->segment_m > 0.0 ? p->segment_m : p->trunk_length_m / 10.0;
    if (seg < min_seg) {
        seg = min_seg;
    }
    ls_stems st = { 0 };
    int depth = p->depth;
    rc = ls_expand(p, depth, &st, err);
    if (rc == 0 && p->target_nodes > 0) {
        long target = p->target_nodes;
        /* too few nodes even at the shortest segment: grow deeper; too many with one
         * segment per stem: prune levels. Moves in one direction only. */
        int dir = 0;
        for (;;) {
            long lo = 1 + st.n, hi = ls_count(&st, min_seg);
            int want = target < lo && depth > 0 ? -1 : (target > hi && depth < 10 ? 1 : 0);
            if (want == 0 || (dir != 0 && want != dir)) {
                break;
            }
            ls_stems more = { 0 };
            gale_err e2 = { 0 };
            if (ls_expand(p, depth + want, &more, &e2) != 0 ||
                (want > 0 && (more.n == st.n || 1 + more.n > 2 * target))) {
                free(more.s);
                break; /* deeper adds nothing or overshoots: keep the closest we have */
            }
            free(st.s);
            st = more;
            depth += want;
            dir = want;
        }
        /* node count falls as the segment grows: bisect on log(seg) */
        double a = min_seg, b = 2.0 * p->trunk_length_m;
        if (ls_count(&st, a) <= target) {
            seg = a;
        } else {
            for (int it = 0; it < 60; it++) {
                double m = sqrt(a * b);
                if (ls_count(&st, m) > target) {
                    a = m;
                } else {
                    b = m;
                }
            }
            long na = ls_count(&st, a), nb = ls_count(&st, b);
            seg = labs(na - target) < labs(nb - target) ? a : b;
        }
    }
    if (rc == 0) {
        rc = ls_emit(p, &st, seg, out, err);
    }
    if (rc == 0) {
        ls_pipe(out, p->tip_radius_m, p->pipe_exponent);
    }
    free(st.s);
    return rc;
}
