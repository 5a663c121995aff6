/* Drawable geometry of a tree: a tube around every element with rings at the nodes,
 * skinned to the element's two nodes (Singh, section 2.1: vertex weighting, weight =
 * position along the element), coarser LODs that share the finest vertices, and leaf
 * slots on terminal nodes (Oliapuram & Kumar 2010 section 1.4: leaves where a recursion
 * ends). Ring frames are parallel-transported from the root, so tubes do not twist. */
#include "mesh.h"
#include "hash.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MESH_PI 3.14159265358979323846
/* Sides of a ring at LOD 0; LOD 1 and 2 use every other vertex (4 sides). */
#define MESH_SIDES 8
#define MESH_LODS  3
/* LOD 1 drops elements thinner than this fraction of the root radius, LOD 2 this one;
 * an element whose parent element is dropped is dropped too. */
#define MESH_LOD1_RADIUS 0.08
#define MESH_LOD2_RADIUS 0.2

typedef struct mesh_vec {
    double x, y, z;
} mesh_vec;

static mesh_vec mv_sub(const float *a, const float *b)
{
    return (mesh_vec){ (double)a[0] - (double)b[0], (double)a[1] - (double)b[1],
                       (double)a[2] - (double)b[2] };
}

static double mv_dot(mesh_vec a, mesh_vec b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static mesh_vec mv_cross(mesh_vec a, mesh_vec b)
{
    return (mesh_vec){ a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}

static mesh_vec mv_scale(mesh_vec a, double s)
{
    return (mesh_vec){ a.x * s, a.y * s, a.z * s };
}

static mesh_vec mv_add(mesh_vec a, mesh_vec b)
{
    return (mesh_vec){ a.x + b.x, a.y + b.y, a.z + b.z };
}

static mesh_vec mv_unit(mesh_vec a, mesh_vec fallback)
{
    double l = sqrt(mv_dot(a, a));
    return l > 1e-12 ? mv_scale(a, 1.0 / l) : fallback;
}

/* A unit vector perpendicular to unit d, as close to n as possible. */
static mesh_vec mv_perp(mesh_vec d, mesh_vec n)
{
    mesh_vec p = mv_add(n, mv_scale(d, -mv_dot(n, d)));
    double l = sqrt(mv_dot(p, p));
    if (l > 1e-6) {
        return mv_scale(p, 1.0 / l);
    }
    mesh_vec alt = fabs(d.x) < 0.9 ? (mesh_vec){ 1, 0, 0 } : (mesh_vec){ 0, 1, 0 };
    return mv_unit(mv_add(alt, mv_scale(d, -mv_dot(alt, d))), (mesh_vec){ 0, 0, 1 });
}

static double mesh_uniform(uint64_t *s)
{
    return (double)(hash64_splitmix(s) >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct mesh_work {
    int *cont;           /* [n] continuation child of each node, -1 if none */
    int *nchild;         /* [n] */
    mesh_vec *axis;      /* [n] ring axis at each node */
    mesh_vec *frame;     /* [n] ring reference normal at each node */
    int *ring;           /* [n] first vertex of the node's ring */
    int *start_ring;     /* [n] first vertex of the ring element (parent -> i) starts at */
    unsigned char *keep; /* [n * MESH_LODS] element (parent -> i) drawn at LOD l */
} mesh_work;

static void mesh_work_free(mesh_work *w)
{
    free(w->cont);
    free(w->nchild);
    free(w->axis);
    free(w->frame);
    free(w->ring);
    free(w->start_ring);
    free(w->keep);
}

static void put_ring(asset *a, uint32_t v0, const float *centre, double r, mesh_vec axis,
                     mesh_vec ref, uint32_t bone0, uint32_t bone1, float weight)
{
    /* cos and sin of 2 pi k / 8 */
    static const double ck[MESH_SIDES] = { 1.0,  0.70710678118654752,  0.0, -0.70710678118654752,
                                           -1.0, -0.70710678118654752, 0.0, 0.70710678118654752 };
    mesh_vec b = mv_cross(axis, ref);
    for (uint32_t k = 0; k < MESH_SIDES; k++) {
        double c = ck[k], sn = ck[(k + MESH_SIDES - MESH_SIDES / 4) % MESH_SIDES];
        mesh_vec n = mv_add(mv_scale(ref, c), mv_scale(b, sn));
        uint32_t v = v0 + k;
        a->mesh_pos[3 * v + 0] = (float)((double)centre[0] + r * n.x);
        a->mesh_pos[3 * v + 1] = (float)((double)centre[1] + r * n.y);
        a->mesh_pos[3 * v + 2] = (float)((double)centre[2] + r * n.z);
        a->mesh_normal[3 * v + 0] = (float)n.x;
        a->mesh_normal[3 * v + 1] = (float)n.y;
        a->mesh_normal[3 * v + 2] = (float)n.z;
        a->mesh_bone[2 * v + 0] = bone0;
        a->mesh_bone[2 * v + 1] = bone1;
        a->mesh_weight[v] = weight;
    }
}

int mesh_build(const skeleton *s, const species *sp, asset *a, gale_err *err)
{
    int n = s->n;
    if (n < 1 || !s->parent || !s->pos || !s->radius) {
        return gale_errf(err, GALE_E_ARG, "mesh: empty skeleton");
    }
    mesh_work w;
    memset(&w, 0, sizeof w);
    size_t nn = (size_t)n;
    w.cont = malloc(nn * sizeof *w.cont);
    w.nchild = calloc(nn, sizeof *w.nchild);
    w.axis = malloc(nn * sizeof *w.axis);
    w.frame = malloc(nn * sizeof *w.frame);
    w.ring = malloc(nn * sizeof *w.ring);
    w.start_ring = malloc(nn * sizeof *w.start_ring);
    w.keep = calloc(nn * MESH_LODS, 1);
    if (!w.cont || !w.nchild || !w.axis || !w.frame || !w.ring || !w.start_ring || !w.keep) {
        mesh_work_free(&w);
        return gale_errf(err, GALE_E_NOMEM, "mesh: out of memory for %d nodes", n);
    }
    /* continuation child: the child whose element best continues the incoming direction
     * (vertical at the root), preferring one of the same branch order */
    for (int i = 0; i < n; i++) {
        w.cont[i] = -1;
    }
    double *best = malloc(nn * sizeof *best);
    if (!best) {
        mesh_work_free(&w);
        return gale_errf(err, GALE_E_NOMEM, "mesh: out of memory for %d nodes", n);
    }
    for (int i = 1; i < n; i++) {
        int p = s->parent[i];
        if (p < 0 || p >= i) {
            free(best);
            mesh_work_free(&w);
            return gale_errf(err, GALE_E_ARG, "mesh: node %d: parent %d is not an earlier node", i,
                             p);
        }
        w.nchild[p]++;
        mesh_vec in = p == 0 ? (mesh_vec){ 0, 0, 1 }
                             : mv_unit(mv_sub(&s->pos[3 * p], &s->pos[3 * s->parent[p]]),
                                       (mesh_vec){ 0, 0, 1 });
        mesh_vec out = mv_unit(mv_sub(&s->pos[3 * i], &s->pos[3 * p]), in);
        double score = mv_dot(in, out) + (s->order && s->order[i] == s->order[p] ? 2.0 : 0.0);
        if (w.cont[p] < 0 || score > best[p]) {
            w.cont[p] = i;
            best[p] = score;
        }
    }
    free(best);
    /* ring axes and parallel-transported frames, parents first */
    for (int i = 0; i < n; i++) {
        int p = s->parent[i];
        mesh_vec in = { 0, 0, 1 };
        if (p >= 0) {
            in = mv_unit(mv_sub(&s->pos[3 * i], &s->pos[3 * p]), in);
        }
        mesh_vec ax = in;
        if (w.cont[i] >= 0) {
            mesh_vec out = mv_unit(mv_sub(&s->pos[3 * w.cont[i]], &s->pos[3 * i]), in);
            ax = p >= 0 ? mv_unit(mv_add(in, out), out) : out;
        }
        w.axis[i] = ax;
        w.frame[i] = mv_perp(ax, p >= 0 ? w.frame[p] : (mesh_vec){ 1, 0, 0 });
    }
    /* LOD membership of each element (parent -> i) */
    double r0 = s->radius[0];
    for (int i = 1; i < n; i++) {
        int p = s->parent[i];
        /* the thinner end decides: a twig leaving a thick limb is judged by its own size */
        double re = fmin((double)s->radius[i], (double)s->radius[p]);
        for (int l = 0; l < MESH_LODS; l++) {
            double thr = l == 0 ? 0.0 : (l == 1 ? MESH_LOD1_RADIUS : MESH_LOD2_RADIUS) * r0;
            int parent_kept = p == 0 || w.keep[(size_t)p * MESH_LODS + (size_t)l];
            w.keep[(size_t)i * MESH_LODS + (size_t)l] = (unsigned char)(re >= thr && parent_kept);
        }
    }
    /* vertices: a ring at every node, plus a start ring for every element that leaves
     * its parent sideways (not the continuation) */
    size_t nverts = 0;
    if (n > 1) {
        for (int i = 0; i < n; i++) {
            w.ring[i] = (int)nverts;
            nverts += MESH_SIDES;
        }
        for (int i = 1; i < n; i++) {
            int p = s->parent[i];
            if (w.cont[p] == i) {
                w.start_ring[i] = w.ring[p];
            } else {
                w.start_ring[i] = (int)nverts;
                nverts += MESH_SIDES;
            }
        }
    }
    size_t nelem = nn - 1, nidx = 0;
    size_t per_lod[MESH_LODS] = { 0, 0, 0 };
    for (int l = 0; l < MESH_LODS; l++) {
        int sides = l == 0 ? MESH_SIDES : MESH_SIDES / 2;
        for (int i = 1; i < n; i++) {
            per_lod[l] += w.keep[(size_t)i * MESH_LODS + (size_t)l] ? (size_t)(6 * sides) : 0;
        }
        nidx += per_lod[l];
    }
    /* the asset format's limits (ASSET.md): 2^22 vertices, 2^24 indices */
    if (nverts > 4194304u || nidx > 16777216u) {
        mesh_work_free(&w);
        return gale_errf(err, GALE_E_RANGE,
                         "mesh: %zu vertices, %zu indices for %zu elements: too many", nverts, nidx,
                         nelem);
    }
    /* leaves: on terminal nodes */
    size_t nleaves = 0;
    int per_tip = sp->leaves_per_tip > 0 ? sp->leaves_per_tip : 0;
    for (int i = 1; i < n; i++) {
        nleaves += w.nchild[i] == 0 ? (size_t)per_tip : 0;
    }
    a->mesh_pos = malloc((nverts ? nverts : 1) * 3 * sizeof(float));
    a->mesh_normal = malloc((nverts ? nverts : 1) * 3 * sizeof(float));
    a->mesh_bone = malloc((nverts ? nverts : 1) * 2 * sizeof(uint32_t));
    a->mesh_weight = malloc((nverts ? nverts : 1) * sizeof(float));
    a->mesh_index = malloc((nidx ? nidx : 1) * sizeof(uint32_t));
    a->leaf_node = malloc((nleaves ? nleaves : 1) * sizeof(uint32_t));
    a->leaf_offset = malloc((nleaves ? nleaves : 1) * 3 * sizeof(float));
    a->leaf_normal = malloc((nleaves ? nleaves : 1) * 3 * sizeof(float));
    a->leaf_size = malloc((nleaves ? nleaves : 1) * sizeof(float));
    if (!a->mesh_pos || !a->mesh_normal || !a->mesh_bone || !a->mesh_weight || !a->mesh_index ||
        !a->leaf_node || !a->leaf_offset || !a->leaf_normal || !a->leaf_size) {
        mesh_work_free(&w);
        free(a->mesh_pos);
        free(a->mesh_normal);
        free(a->mesh_bone);
        free(a->mesh_weight);
        free(a->mesh_index);
        free(a->leaf_node);
        free(a->leaf_offset);
        free(a->leaf_normal);
        free(a->leaf_size);
        a->mesh_pos = a->mesh_normal = a->mesh_weight = a->leaf_offset = a->leaf_normal =
            a->leaf_size = NULL;
        a->mesh_bone = a->mesh_index = a->leaf_node = NULL;
        return gale_errf(err, GALE_E_NOMEM, "mesh: out of memory for %zu vertices", nverts);
    }
    /* rings: at node i the vertices follow node i (element parent -> i at its end, weight
     * 1); a side start ring sits at the parent with weight 0 */
    if (n > 1) {
        for (int i = 0; i < n; i++) {
            int p = s->parent[i];
            uint32_t b0 = (uint32_t)(p >= 0 ? p : 0);
            uint32_t b1 = (uint32_t)(p >= 0 ? i : (w.cont[0] >= 0 ? w.cont[0] : 0));
            put_ring(a, (uint32_t)w.ring[i], &s->pos[3 * i], s->radius[i], w.axis[i], w.frame[i],
                     b0, b1, p >= 0 ? 1.0f : 0.0f);
        }
        for (int i = 1; i < n; i++) {
            int p = s->parent[i];
            if (w.cont[p] == i) {
                continue;
            }
            mesh_vec ax = mv_unit(mv_sub(&s->pos[3 * i], &s->pos[3 * p]), w.axis[p]);
            mesh_vec ref = mv_perp(ax, w.frame[i]);
            put_ring(a, (uint32_t)w.start_ring[i], &s->pos[3 * p], s->radius[i], ax, ref,
                     (uint32_t)p, (uint32_t)i, 0.0f);
        }
    }
    /* indices, LOD by LOD: two triangles per side, wound outward */
    size_t at = 0;
    for (int l = 0; l < MESH_LODS; l++) {
        a->lod_first[l] = (uint32_t)at;
        int step = l == 0 ? 1 : 2;
        for (int i = 1; i < n; i++) {
            if (!w.keep[(size_t)i * MESH_LODS + (size_t)l]) {
                continue;
            }
            uint32_t s0 = (uint32_t)w.start_ring[i], e0 = (uint32_t)w.ring[i];
            for (int k = 0; k < MESH_SIDES; k += step) {
                uint32_t k0 = (uint32_t)k, k1 = (uint32_t)((k + step) % MESH_SIDES);
                a->mesh_index[at++] = s0 + k0;
                a->mesh_index[at++] = s0 + k1;
                a->mesh_index[at++] = e0 + k0;
                a->mesh_index[at++] = s0 + k1;
                a->mesh_index[at++] = e0 + k1;
                a->mesh_index[at++] = e0 + k0;
            }
        }
        a->lod_count[l] = (uint32_t)(at - a->lod_first[l]);
    }
    for (int l = MESH_LODS; l < ASSET_MAX_LODS; l++) {
        a->lod_first[l] = 0;
        a->lod_count[l] = 0;
    }
    a->n_verts = (uint32_t)nverts;
    a->n_indices = (uint32_t)at;
    a->n_lods = at > 0 ? MESH_LODS : 0;
    if (at == 0) {
        memset(a->lod_first, 0, sizeof a->lod_first);
        memset(a->lod_count, 0, sizeof a->lod_count);
    }

    /* leaf slots: around each tip, azimuths spread evenly about the twig with a random
     * start, blade normals tilted from straight up by up to leaf_spread_deg */
    size_t li = 0;
    double spread = (double)sp->leaf_spread_deg * MESH_PI / 180.0;
    double size = sp->leaf_size_m > 0.0f ? (double)sp->leaf_size_m : 0.1;
    for (int i = 1; i < n && per_tip > 0; i++) {
        if (w.nchild[i] != 0) {
            continue;
        }
        uint64_t rng = sp->gen.seed ^ (0x2545f4914f6cdd1dull * (uint64_t)(i + 1));
        mesh_vec d = w.axis[i], ref = w.frame[i], b = mv_cross(d, ref);
        double az0 = 2.0 * MESH_PI * mesh_uniform(&rng);
        for (int k = 0; k < per_tip; k++) {
            double az = az0 + 2.0 * MESH_PI * k / per_tip;
            mesh_vec side = mv_add(mv_scale(ref, cos(az)), mv_scale(b, sin(az)));
            double sz = size * (0.8 + 0.4 * mesh_uniform(&rng));
            /* the blade's base sits at the tip, its centre half a blade out and forward */
            mesh_vec off =
                mv_scale(mv_unit(mv_add(mv_scale(side, 0.8), mv_scale(d, 0.6)), d), 0.5 * sz);
            double tilt = spread * mesh_uniform(&rng), tilt_az = 2.0 * MESH_PI * mesh_uniform(&rng);
            mesh_vec nrm = { sin(tilt) * cos(tilt_az), sin(tilt) * sin(tilt_az), cos(tilt) };
            a->leaf_node[li] = (uint32_t)i;
            a->leaf_offset[3 * li + 0] = (float)off.x;
            a->leaf_offset[3 * li + 1] = (float)off.y;
            a->leaf_offset[3 * li + 2] = (float)off.z;
            a->leaf_normal[3 * li + 0] = (float)nrm.x;
            a->leaf_normal[3 * li + 1] = (float)nrm.y;
            a->leaf_normal[3 * li + 2] = (float)nrm.z;
            a->leaf_size[li] = (float)sz;
            li++;
        }
    }
    a->n_leaves = (uint32_t)li;
    memcpy(a->bark_rgb, sp->bark_rgb, sizeof a->bark_rgb);
    memcpy(a->leaf_rgb, sp->leaf_rgb, sizeof a->leaf_rgb);
    a->leaf_shape = (uint32_t)(sp->leaf_shape >= 0 && sp->leaf_shape <= 2 ? sp->leaf_shape : 0);
    mesh_work_free(&w);
    return GALE_OK;
}
