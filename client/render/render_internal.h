/* gale_render internals shared by its files: render.c (create, destroy, frame, readback),
 * render_gpu.c (buffers, targets, common uniforms), render_shader.c (run-time shader
 * loading), render_species.c, render_scene.c (instances, q, houses), render_wind.c (the
 * coarse wind), render_fall.c (falling leaves), render_rain.c (storm rain and spray). Not part
 * of the public API. */
#ifndef GALE_RENDER_INTERNAL_H
#define GALE_RENDER_INTERNAL_H

#include <epoxy/gl.h>

#include <stdbool.h>
#include <stdint.h>

#include "err.h"
#include "falling_path.h"
#include "gl_ctx.h"
#include "render.h"
#include "render_cull.h"
#include "storm_fx.h"
#include "wire.h"
#include "wire_limits.h"

/* Modes per species: the wire's limit; shaders/skel.frag declares u_ab[64] to match. */
#define RENDER_MAX_MODES 64u
_Static_assert(RENDER_MAX_MODES == WIRE_MAX_MODES,
               "render: RENDER_MAX_MODES (u_ab[] in shaders/skel.frag) must equal WIRE_MAX_MODES");

#define RENDER_IMP_W 256 /* billboard impostor texture [px] */
#define RENDER_IMP_H 512

/* Texture units, fixed for every program. */
enum {
    RU_SKEL = 0,  /* skeleton texture: node positions per visible tree */
    RU_NODE = 1,  /* species rest positions + parents (buffer) */
    RU_LIST = 2,  /* per-frame draw list (buffer) */
    RU_TREES = 3, /* instance transforms (buffer) */
    RU_VW = 4,    /* species corrected mode shapes v, w (buffer) */
    RU_Q = 5,     /* modal state of every tree (buffer) */
    RU_LEAF = 6,  /* species leaf slots (buffer) */
    RU_WIND = 7,  /* coarse wind (3D) */
    RU_PATH = 8,  /* falling-leaf path */
    RU_IMP = 9,   /* billboard impostor */
    RU_CUT = 10,  /* per tree slot: first, count of its cut nodes, keep-only (buffer) */
    RU_CUTN = 11, /* cut node indices (buffer) */
    RU_PLATE = 12, /* trees drawn with a root plate this frame (buffer) */
    RU_STUMP = 13, /* stumps of snapped trees drawn this frame (buffer) */
    RU_IMP_WOOD = 14, /* billboard impostor of the wood alone */
};

/* Groups of the per-frame draw list, per species. */
/* a species' draw groups: skeleton rows, bark by mesh LOD, every leaf, the thinned leaves
 * (lod_policy.h THIN), impostors */
enum { G_SKEL = 0, G_MESH = 1, G_LEAF = G_MESH + ASSET_MAX_LODS, G_LEAF_THIN, G_BILL, G_COUNT };

/* A linked program and every uniform location any gale program uses, looked up once at
 * link time (-1 where this program lacks the uniform; glUniform* ignores -1). */
typedef struct render_prog {
    GLuint id;
    /* common.glsl */
    GLint u_viewproj, u_eye, u_sun_dir, u_sun_col, u_sky_zenith, u_sky_horizon, u_ground_col;
    GLint u_fog_dist, u_time, u_wind_origin, u_wind_extent, u_wind_uniform;
    /* skel */
    GLint u_base, u_nodes, u_target, u_qstride, u_ab, u_pass;
    /* tree, leaf */
    GLint u_bark, u_nleaves, u_leaf_total, u_leaf_grow, u_aspect, u_crown, u_leafcol, u_shape;
    /* sky, house, bill */
    GLint u_inv_viewproj, u_wall, u_roof, u_window, u_bsize, u_sway, u_crown_z;
    /* fall */
    GLint u_npath, u_pdt, u_ncont, u_cont, u_aspects;
    /* rain */
    GLint u_rain, u_spray;
    GLint u_storm, u_rain_clear; /* the trees kept readable in a storm (common.glsl, rain) */
} render_prog;

typedef struct rs_buf {
    GLuint buf, tex; /* a buffer and its buffer texture */
    size_t bytes;
} rs_buf;

typedef struct rs_species {
    uint32_t n_nodes, n_modes, n_leaves, n_lods, leaf_shape;
    uint32_t lod_first[ASSET_MAX_LODS], lod_count[ASSET_MAX_LODS];
    float height, crown_r, bark[3], leaf_rgb[3];
    float ab[2 * RENDER_MAX_MODES]; /* a_i, b_i interleaved, the layout of skel.frag's u_ab */
    GLuint vao, vbo, ibo, imp_tex, imp_wood_tex; /* impostors: whole tree, wood alone */
    rs_buf vw, node, leaf;
    float bill[3]; /* half width, height, bottom [m] */
    /* the impostor's sway (shaders/bill.vert): the crown's mean translation per unit q of
     * its lowest modes, weighted by leaves [m], and the crown's height [m] */
    float imp_sway[LOD_IMPOSTOR_MODES][3], imp_crown_z;
    uint32_t leaves_thin; /* leaves drawn at THIN: n_leaves × lod_leaf_share[LOD_THIN] */
    float stem_r_m, stem_taper; /* stem radius at the base [m] and its change per metre up */
    /* CPU copies for releasing falling leaves (one node per leaf, never per frame) */
    float *rest, *corr_v, *corr_w, *leaf_offset, *leaf_normal, *leaf_size;
    float corr_a[RENDER_MAX_MODES], corr_b[RENDER_MAX_MODES];
    uint32_t *leaf_node;
    int32_t *parent; /* [n_nodes], -1 at the root: the pose walks up it */
} rs_species;

/* What culling needs of a species on the GPU. */
static inline render_cull_species render_cull_species_of(const rs_species *s)
{
    return (render_cull_species){ .height_m = s->height,
                                  .crown_r_m = s->crown_r,
                                  .n_modes = s->n_modes,
                                  .n_lods = s->n_lods };
}

/* one falling-leaf record, the vertex layout of shaders/fall.vert */
typedef struct rs_fall {
    float start[4], var[4], drift[4], q0[4], look[4], shape;
} rs_fall;

struct render {
    gl_ctx ctx;
    render_desc desc;
    char shader_dir[512];
    int w, h;
    GLuint fbo, fbo_col, fbo_depth; /* offscreen target (headless) */
    /* the scene at a lower resolution (render_set_res_scale), scaled up onto the target */
    float res_scale;
    GLuint low_fbo, low_col, low_depth;
    int low_w, low_h;
    GLuint vao_empty;
    render_prog p_skel, p_tree, p_leaf, p_fall, p_sky, p_bill, p_house, p_rain, p_plate;
    render_prog p_stump;
    storm_fx fx; /* sky, light, fog and rain of the weather (render_set_storm) */
    GLuint house_vao, house_vbo; /* houses: world-space triangles (render_house_mesh) */
    uint32_t house_verts;

    rs_species sp[RENDER_MAX_SPECIES];
    uint32_t n_species;

    uint32_t n_trees, cap_trees; /* cap_trees + 1 slots: the last is a rest-pose slot; then
                                    RENDER_MAX_DEBRIS debris slots (render_slots) */
    render_instance *inst;
    rs_buf trees;
    float *q_stage;
    uint32_t q_stride;
    rs_buf q;
    float *list; /* 4 floats per entry */
    uint32_t list_cap;
    rs_buf list_buf;
    /* scratch per visible tree, indexed like vis: its skeleton row, LOD group flags, LOD
       and distance */
    uint32_t *tree_row, *tree_group;
    uint32_t rows_used; /* skeleton rows this frame */
    render_cells cells;              /* the scene's trees in cells (render_set_instances) */
    float lod_scale;                 /* × the LOD distances (render_set_lod_scale) */
    float budget_scale;              /* the last frame's scale under its budget */
    render_tree_lod *tree_lod;
    float *tree_dist;
    uint32_t *vis;                   /* scratch: the frame's trees in view (draw order k) */
    uint32_t lod_hist[RENDER_MAX_SPECIES * RENDER_LOD_BINS]; /* render_lod_budget's */
    uint32_t felled_hist[RENDER_LOD_BINS]; /* and its felled trees' (root plates, stumps) */
    uint32_t grp_base[RENDER_MAX_SPECIES][G_COUNT], grp_n[RENDER_MAX_SPECIES][G_COUNT];

    /* storm damage drawn by the skeleton pass (render_damage.c, shaders/skel.frag) */
    uint64_t *broken;   /* (tree << 32 | node), ascending: branches broken off */
    uint32_t n_broken, cap_broken;
    render_debris debris[RENDER_MAX_DEBRIS];
    uint32_t n_debris;
    rs_buf cut, cutn;   /* per slot: first, count, keep-only; node indices */
    bool cut_dirty;
    float *plates;      /* [cap_trees] uprooted trees drawn in full this frame */
    uint32_t n_plates;
    rs_buf plate_buf;
    float *stumps;      /* [8 cap_trees] snapped trees drawn in full this frame: tree, stem
                           radius, taper, 0; bark rgb, 0 (shaders/stump.vert) */
    uint32_t n_stumps;
    rs_buf stump_buf;
    float *leaf_attached; /* [cap_trees] share of a tree's leaf slots on no broken branch */

    GLuint skel_tex, skel_fbo;
    GLuint seg_tex, seg_fbo; /* the skeleton pass's posed segments (shaders/skel.frag) */
    int skel_w, skel_h;

    GLuint wind_tex;
    float wind_uniform[3], wind_origin[3], wind_extent[3], wind_cell[3];
    uint32_t wind_n[3];
    float *wind_v;

    falling_path path; /* built on the CPU before any GPU state */
    GLuint path_tex;
    rs_fall *ring;
    uint32_t ring_cap, ring_head, ring_count, dirty_lo, dirty_hi;
    GLuint fall_vao, fall_vbo;
    double t_base;
    bool t_base_set;

    float view[16], proj[16], viewproj[16], eye[3];
    /* the camera's subject (render_camera.subject_m): world point and distance [m], 0 none */
    float subject[3], subject_m;
    render_stats stats;
};

/* Blade length / width of the three leaf shapes (asset leaf_shape 0..2). */
extern const float render_leaf_aspect[3];

/* ---- render_shader.c ---- */

/* Compiles and links shaders/<name>.vert + <name>.frag (each preceded by common.glsl)
 * from dir, binds the sampler uniforms to their units and fills *p with the program and
 * its uniform locations. 0, or negative GALE_E_* with err set (file:line of the compiler
 * message); p->id is 0 then. The caller deletes p->id. */
int render_program_load(const char *dir, const char *name, render_prog *p, gale_err *err);

/* ---- render_gpu.c ---- */

/* A buffer texture of `bytes` (at least 16) initialised from data (may be NULL). */
void render_buf_create(rs_buf *b, GLenum fmt, const void *data, size_t bytes);
/* Replaces the first `bytes` of b (growing it when larger), orphaning the old storage. */
void render_buf_upload(rs_buf *b, GLenum fmt, const void *data, size_t bytes);
/* Deletes b's buffer and texture and zeroes it; a zero b is a no-op. */
void render_buf_free(rs_buf *b);
void render_bind_buf(int unit, const rs_buf *b);
void render_bind_tex(int unit, GLenum target, GLuint tex);

/* (Re)creates the offscreen framebuffer at r->w x r->h (headless only; windowed is a
 * no-op). GALE_E_STATE when incomplete. */
int render_target_create(render *r, gale_err *err);
/* Binds the frame's target (window or offscreen) and its viewport. */
void render_target_bind(render *r);
/* Binds what the scene is drawn into: the target, or at res_scale < 1 the lower-resolution
 * one (made or remade to size). render_scene_present then scales it onto the target. */
int render_scene_bind(render *r, gale_err *err);
void render_scene_present(render *r);
/* Grows the skeleton texture to at least width x rows texels. GALE_E_RANGE past
 * GL_MAX_TEXTURE_SIZE, GALE_E_STATE when RGBA32F is not renderable. */
int render_skel_ensure(render *r, int width, int rows, gale_err *err);
/* Uses p and sets the scene uniforms every program shares (common.glsl). */
void render_set_common(render *r, const render_prog *p, float time_rel, float fog_dist);
/* t [s] relative to a base fixed at the first call (floats keep their precision). */
double render_rel_time(render *r, double t);

/* ---- render_scene.c ---- */

/* Instance slots: the scene's cap_trees, the rest-pose slot, the debris slots. */
static inline uint32_t render_slots(const render *r)
{
    return r->cap_trees + 1 + RENDER_MAX_DEBRIS;
}
/* Slot of the k-th drawn tree: scene trees first, then the debris pieces. */
static inline uint32_t render_slot_at(const render *r, uint32_t k)
{
    return k < r->n_trees ? k : r->cap_trees + 1 + (k - r->n_trees);
}

/* Whether slot i holds a snapped tree: a scene tree fallen and not uprooted (PROTOCOL.md
 * "DAMAGE": SNAP and UPROOT are the fallen kinds); it tips about its break and leaves a
 * stump (tip_fall_break_m). Debris slots never: a piece turns about its own frame. */
static inline bool render_slot_snapped(const render *r, uint32_t i)
{
    return i < r->cap_trees && r->inst[i].fall_rad > 0.0f && r->inst[i].uprooted == 0;
}
/* What slot i's impostor keeps of its crown's leaves: stripped levels and broken branches. */
static inline float render_bill_leaf_share(const render *r, uint32_t i)
{
    return (1.0f - (float)r->inst[i].leaf_lost / (float)WIRE_DAMAGE_LEVELS) *
           (i < r->cap_trees ? r->leaf_attached[i] : 1.0f);
}
/* Slot i's fall as its impostor list entry's third component holds it (shaders/bill.vert):
 * 0 for a standing tree; for a tipped one (fallen, snapped or uprooted: fall_rad > 0)
 * 1 + its fall azimuth in 1/256 turns (0..255) + its fall angle (0..π/2) / π, so that the
 * impostor lies along its fall as the posed tree does. */
static inline float render_bill_fall(const render *r, uint32_t i)
{
    return render_bill_fall_code(r->inst[i].fall_rad, r->inst[i].fall_az_rad);
}
/* Scene tree t's entries of r->cells.bill_leaf and bill_fall, after its damage or leaves
 * changed. */
void render_bill_leaf_set(render *r, uint32_t t);

/* u_trees slot 1 .z of slot i (shaders/common.glsl tree_fall, tree_snapped, leaf_kept): the
 * fall angle (0..π) plus 4 x the leaf levels lost, plus 256 on a snapped tree. */
static inline float render_tree_code(const render *r, uint32_t i)
{
    const render_instance *in = &r->inst[i];
    return in->fall_rad + 4.0f * (float)in->leaf_lost + (render_slot_snapped(r, i) ? 256.0f : 0.0f);
}

/* (Re)allocates the per-tree arrays for cap trees plus the rest-pose slot. GALE_E_NOMEM. */
int render_trees_alloc(render *r, uint32_t cap, gale_err *err);
/* Uploads every instance transform (and the rest slot) to the trees buffer. */
void render_trees_upload(render *r);

/* ---- render_damage.c ---- */

/* Uploads the per-slot cut lists (broken branches, debris pieces) when they changed. */
void render_damage_upload(render *r);
/* Draws the root plates of r->plates (shaders/plate.*); expects the target bound. */
void render_plates_draw(render *r, float time_rel);
/* Draws the stumps of r->stumps (shaders/stump.*); expects the target bound. */
void render_stumps_draw(render *r, float time_rel);

/* ---- render_wind.c ---- */

/* The coarse wind [m/s] at world point p: the grid cell holding it (heights clamped into
 * the grid), else the uniform wind. */
void render_wind_at(const render *r, const float p[3], float out[3]);

/* ---- render_species.c ---- */

/* Frees one species' GPU objects and CPU copies and zeroes it. */
void render_species_free(rs_species *s);
/* Rebuilds n skeletons of list entries [base, base + n) into the skeleton texture. */
void render_draw_skeleton(render *r, const rs_species *s, uint32_t base, uint32_t n);
/* Draws n trees of mesh LOD lod; expects render_set_common(r, &r->p_tree, ...). */
void render_draw_tree(render *r, const rs_species *s, uint32_t lod, uint32_t base, uint32_t n);
/* Draws the leaves of n trees; expects render_set_common(r, &r->p_leaf, ...). */
void render_draw_leaves(render *r, const rs_species *s, uint32_t base, uint32_t n, bool thin);

/* ---- render_fall.c ---- */

/* Uploads the already built r->path as a texture and creates the ring of
 * r->desc.max_falling records with its vertex buffer. GALE_E_NOMEM. */
int render_fall_gpu_create(render *r, gale_err *err);
/* Uploads new ring records and draws falling and landed leaves; expects the target bound. */
void render_fall_draw(render *r, float time_rel);

/* ---- render_rain.c ---- */

/* Draws r->fx's rain streaks and spray over the frame (nothing when it has none); expects the
 * target bound. */
void render_rain_draw(render *r, float time_rel);

#endif
