/* gale_render: create, destroy, the frame and readback. Per frame the CPU only walks
 * trees (render_cull.c: cull, LOD; one draw-list upload, one q upload); nodes are rebuilt
 * on the GPU into a skeleton texture (Diener 2008 section 5.1, figure 5) that skins meshes
 * and carries leaves (render_species.c); falling leaves follow one shared path (Vazquez
 * 2008 sections 3-4, render_fall.c). */
#include "render_internal.h"
#include "mono.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <cglm/cglm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

#include "render_cull.h"
#include "wire.h"

render *render_create(const render_desc *desc, gale_err *err)
{
    render *r = calloc(1, sizeof *r);
    if (!r) {
        gale_errf(err, GALE_E_NOMEM, "render: out of memory");
        return NULL;
    }
    r->desc = desc ? *desc : (render_desc){ 0 };
    render_desc *d = &r->desc;
    if (d->width == 0) {
        d->width = 1280;
    }
    if (d->height == 0) {
        d->height = 720;
    }
    if (d->max_trees == 0) {
        d->max_trees = 8192;
    }
    if (d->max_falling == 0) {
        d->max_falling = 16384;
    }
    if (d->lod_mode_dist == 0.0f) {
        d->lod_mode_dist = 40.0f;
    }
    if (d->fog_dist == 0.0f) {
        d->fog_dist = 450.0f;
    }
    if (d->width < 1 || d->height < 1 || d->width > 16384 || d->height > 16384 ||
        d->max_trees > RENDER_MAX_TREES || d->max_falling > (1u << 22) || !(d->lod_mode_dist > 0.0f) ||
        !(d->fog_dist > 0.0f)) {
        gale_errf(err, GALE_E_ARG,
                  "render_create: size %dx%d (1..16384), max_trees %u, "
                  "max_falling %u (<= 4M), LOD and fog distances > 0",
                  d->width, d->height, d->max_trees, d->max_falling);
        free(r);
        return NULL;
    }
    const char *sd = d->shader_dir ? d->shader_dir : getenv("GALE_SHADER_DIR");
    snprintf(r->shader_dir, sizeof r->shader_dir, "%s", sd ? sd : GALE_SOURCE_DIR "/shaders");
    d->shader_dir = NULL;
    d->title = NULL;
    r->w = d->width;
    r->h = d->height;
    r->lod_scale = 1.0f;
    r->budget_scale = 1.0f;
    r->res_scale = 1.0f;
    storm_fx_calm(&r->fx);
    /* the shared falling path: a CPU simulation, done before any GPU state exists */
    if (falling_path_build(&r->path, NULL, err) < 0) {
        free(r);
        return NULL;
    }
    if (gl_ctx_create(&r->ctx, r->w, r->h, d->headless, d->vsync,
                      desc && desc->title ? desc->title : "gale", err) < 0) {
        free(r);
        return NULL;
    }
    if (render_target_create(r, err) < 0) {
        goto fail;
    }
    glGenVertexArrays(1, &r->vao_empty);
    struct {
        render_prog *p;
        const char *name;
    } progs[] = { { &r->p_skel, "skel" },  { &r->p_tree, "tree" }, { &r->p_leaf, "leaf" },
                  { &r->p_fall, "fall" },  { &r->p_sky, "sky" },   { &r->p_bill, "bill" },
                  { &r->p_house, "house" }, { &r->p_rain, "rain" }, { &r->p_plate, "plate" },
                  { &r->p_stump, "stump" } };
    for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
        if (render_program_load(r->shader_dir, progs[i].name, progs[i].p, err) < 0) {
            goto fail;
        }
    }
    r->q_stride = 1;
    if (render_trees_alloc(r, d->max_trees, err) < 0) {
        goto fail;
    }
    render_buf_create(&r->trees, GL_RGBA32F, NULL, (size_t)(d->max_trees + 1) * 8 * sizeof(float));
    render_trees_upload(r);
    render_buf_create(&r->q, GL_R32F, NULL, 0);
    render_buf_create(&r->list_buf, GL_RGBA32F, NULL, (size_t)r->list_cap * 4 * sizeof(float));
    render_buf_create(&r->cut, GL_RGBA32F, NULL, (size_t)render_slots(r) * 4 * sizeof(float));
    render_buf_create(&r->cutn, GL_R32F, NULL, 0);
    render_buf_create(&r->plate_buf, GL_R32F, NULL, 0);
    render_buf_create(&r->stump_buf, GL_RGBA32F, NULL, 0);
    r->cut_dirty = true;
    render_damage_upload(r);
    if (render_skel_ensure(r, 64, 64, err) < 0) {
        goto fail;
    }
    /* wind: a 1x1x1 texture until a grid arrives */
    glGenTextures(1, &r->wind_tex);
    glBindTexture(GL_TEXTURE_3D, r->wind_tex);
    float zero[4] = { 0 };
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, 1, 1, 1, 0, GL_RGBA, GL_FLOAT, zero);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (render_fall_gpu_create(r, err) < 0) {
        goto fail;
    }
    return r;
fail:
    render_destroy(r);
    return NULL;
}

void render_destroy(render *r)
{
    if (!r) {
        return;
    }
    if (r->ctx.kind == GL_CTX_WINDOW || r->ctx.egl_context || r->ctx.window) {
        for (uint32_t i = 0; i < r->n_species; i++) {
            render_species_free(&r->sp[i]);
        }
        GLuint progs[] = { r->p_skel.id, r->p_tree.id,  r->p_leaf.id, r->p_fall.id, r->p_sky.id,
                           r->p_bill.id, r->p_house.id, r->p_rain.id, r->p_plate.id,
                           r->p_stump.id };
        for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
            if (progs[i]) {
                glDeleteProgram(progs[i]);
            }
        }
        render_buf_free(&r->trees);
        render_buf_free(&r->q);
        render_buf_free(&r->list_buf);
        render_buf_free(&r->cut);
        render_buf_free(&r->cutn);
        render_buf_free(&r->plate_buf);
        render_buf_free(&r->stump_buf);
        GLuint texs[] = { r->skel_tex, r->seg_tex, r->wind_tex, r->path_tex, r->fbo_col };
        for (size_t i = 0; i < sizeof texs / sizeof texs[0]; i++) {
            if (texs[i]) {
                glDeleteTextures(1, &texs[i]);
            }
        }
        GLuint fbos[] = { r->skel_fbo, r->seg_fbo, r->fbo };
        for (size_t i = 0; i < sizeof fbos / sizeof fbos[0]; i++) {
            if (fbos[i]) {
                glDeleteFramebuffers(1, &fbos[i]);
            }
        }
        if (r->fbo_depth) {
            glDeleteRenderbuffers(1, &r->fbo_depth);
        }
        if (r->low_fbo) {
            glDeleteFramebuffers(1, &r->low_fbo);
            glDeleteTextures(1, &r->low_col);
            glDeleteRenderbuffers(1, &r->low_depth);
        }
        if (r->fall_vao) {
            glDeleteVertexArrays(1, &r->fall_vao);
            glDeleteBuffers(1, &r->fall_vbo);
        }
        if (r->vao_empty) {
            glDeleteVertexArrays(1, &r->vao_empty);
        }
        if (r->house_vao) {
            glDeleteVertexArrays(1, &r->house_vao);
            glDeleteBuffers(1, &r->house_vbo);
        }
    }
    gl_ctx_destroy(&r->ctx);
    free(r->inst);
    free(r->q_stage);
    free(r->list);
    free(r->tree_row);
    free(r->tree_group);
    render_cells_free(&r->cells);
    free(r->tree_lod);
    free(r->tree_dist);
    free(r->vis);
    free(r->wind_v);
    free(r->ring);
    free(r->broken);
    free(r->plates);
    free(r->stumps);
    free(r->leaf_attached);
    free(r);
}

struct GLFWwindow *render_window(render *r)
{
    return r && r->ctx.kind == GL_CTX_WINDOW ? r->ctx.window : NULL;
}

static void camera_matrices(render *r, const render_camera *cam)
{
    mat4 view, proj, vp;
    if (cam->matrices) {
        memcpy(view, cam->view, sizeof view);
        memcpy(proj, cam->proj, sizeof proj);
        mat4 inv;
        glm_mat4_inv(view, inv);
        r->eye[0] = inv[3][0];
        r->eye[1] = inv[3][1];
        r->eye[2] = inv[3][2];
    } else {
        vec3 up = { cam->up[0], cam->up[1], cam->up[2] };
        if (up[0] == 0.0f && up[1] == 0.0f && up[2] == 0.0f) {
            up[2] = 1.0f;
        }
        vec3 eye = { cam->eye[0], cam->eye[1], cam->eye[2] };
        vec3 tgt = { cam->target[0], cam->target[1], cam->target[2] };
        glm_lookat(eye, tgt, up, view);
        float fov = cam->fov_y_deg > 0.0f ? cam->fov_y_deg : 50.0f;
        float zn = cam->z_near > 0.0f ? cam->z_near : 0.3f;
        float zf = cam->z_far > 0.0f ? cam->z_far : 4500.0f;
        glm_perspective(glm_rad(fov), (float)r->w / (float)r->h, zn, zf, proj);
        memcpy(r->eye, cam->eye, sizeof r->eye);
    }
    /* the subject lies subject_m along the view axis: -(row 2 of the view matrix) */
    r->subject_m = cam->subject_m > 0.0f && isfinite(cam->subject_m) ? cam->subject_m : 0.0f;
    for (int k = 0; k < 3; k++) {
        r->subject[k] = r->eye[k] - r->subject_m * view[k][2];
    }
    glm_mat4_mul(proj, view, vp);
    memcpy(r->view, view, sizeof view);
    memcpy(r->proj, proj, sizeof proj);
    memcpy(r->viewproj, vp, sizeof vp);
}

/* What a tree of species s costs at each level (render_lod_budget): every leaf and its bark
 * at each mesh LOD, the coarsest mesh and the thinned leaves, an impostor. */
static render_lod_cost species_cost(const rs_species *s)
{
    render_lod_cost c = { .n_lods = s->n_lods, .impostor = 2.0f, .nodes = (float)s->n_nodes };
    c.full_leaves = 2.0f * (float)s->n_leaves;
    for (uint32_t l = 0; l < s->n_lods; l++) {
        c.mesh[l] = (float)(s->lod_count[l] / 3u);
    }
    c.thin = c.mesh[s->n_lods - 1] + 2.0f * (float)s->leaves_thin;
    return c;
}

/* A piece no impostor draws: a debris piece (slot past the trees). A tipped or snapped
 * tree is an impostor past THIN as a standing one is, laid along its fall (its entry's
 * render_bill_fall, shaders/bill.vert). */
static bool stays_posed(const render *r, uint32_t k)
{
    return k >= r->n_trees;
}

/* Cull (render_cull.c), fit the frame's budget and choose each tree's LOD (render_lod.c),
 * and fill the draw list grouped by species and kind. */
static void build_lists(render *r)
{
    float planes[6][4];
    render_cull_planes(r->viewproj, planes);
    memset(r->grp_n, 0, sizeof r->grp_n);
    r->n_plates = 0;
    r->n_stumps = 0;
    /* the cells first: the trees of a cell wholly outside are culled with it, never
       visited; one of a cell wholly inside needs no test of its own */
    render_cells *cells = &r->cells;
    for (uint32_t c = 0; c < cells->n_cells; c++) {
        cells->where[c] = (uint8_t)render_cell_test(&cells->cell[c], planes);
    }
    /* pass 0: what is in view (r->vis, cell by cell, then the debris pieces), how far, in
       the budget's histogram. A cell wholly in view, all of it past THIN's reach at the
       largest scale this frame may take and inside the impostors', is drawn as impostors
       whole (cells->bulk), its trees never visited one by one: at 100,000 trees most of a
       landscape. Its trees count in the histogram at the cell's nearest distance, whose
       bin's near edge is past THIN too, so the budget sees the cost it would tree by tree. */
    memset(r->lod_hist, 0, (size_t)r->n_species * RENDER_LOD_BINS * sizeof r->lod_hist[0]);
    memset(r->felled_hist, 0, sizeof r->felled_hist);
    const uint32_t n_drawn = r->n_trees + r->n_debris;
    /* the governor's scale caps the budget's, which grows back a step a frame */
    const float max_scale = fminf(r->lod_scale, r->budget_scale * LOD_GROW_PER_FRAME);
    const float thin_reach_m = lod_outer_m[LOD_THIN] * fmaxf(max_scale, 1e-3f);
    uint32_t n_vis = 0, n_bulk = 0, bulk_trees = 0;
    uint32_t bulk_per_species[RENDER_MAX_SPECIES] = { 0 };
    for (uint32_t c = 0; c <= cells->n_cells; c++) {
        const bool debris = c == cells->n_cells;
        if (!debris && cells->where[c] == RENDER_CELL_OUT) {
            continue;
        }
        const bool inside = !debris && cells->where[c] == RENDER_CELL_IN;
        if (inside) {
            const render_cell *cl = &cells->cell[c];
            float near2 = 0.0f, far2 = 0.0f;
            for (int a = 0; a < 3; a++) {
                float dn = fmaxf(fmaxf(cl->lo[a] - r->eye[a], r->eye[a] - cl->hi[a]), 0.0f);
                float df = fmaxf(fabsf(cl->lo[a] - r->eye[a]), fabsf(cl->hi[a] - r->eye[a]));
                near2 += dn * dn;
                far2 += df * df;
            }
            const uint32_t b = render_lod_bin(sqrtf(near2));
            if (b < RENDER_LOD_BINS && render_lod_bin_near_m(b) >= thin_reach_m &&
                sqrtf(far2) < lod_outer_m[LOD_IMPOSTOR]) {
                cells->bulk[n_bulk++] = c;
                for (uint32_t at = cl->first; at < cl->first + cl->count; at++) {
                    const uint32_t sp = cells->species[at];
                    bulk_per_species[sp]++;
                    r->lod_hist[sp * RENDER_LOD_BINS + b]++;
                }
                bulk_trees += cl->count;
                continue;
            }
        }
        const uint32_t first = debris ? r->n_trees : 0;
        const uint32_t count = debris ? r->n_debris : cells->cell[c].count;
        for (uint32_t t = 0; t < count; t++) {
            uint32_t k, species;
            float dist_m;
            if (debris) {
                k = first + t;
                const render_instance *in = &r->inst[render_slot_at(r, k)];
                const render_cull_species cs = render_cull_species_of(&r->sp[in->species]);
                species = in->species;
                if (!render_cull_visible(planes, r->eye, in, &cs, &dist_m)) {
                    continue;
                }
            } else {
                const uint32_t at = cells->cell[c].first + t;
                k = cells->tree[at];
                species = cells->species[at];
                if (!render_cull_sphere_visible(inside ? NULL : planes, r->eye,
                                                cells->sphere[at], cells->sphere[at][3],
                                                &dist_m)) {
                    continue;
                }
            }
            uint32_t b = render_lod_bin(dist_m);
            if (b < RENDER_LOD_BINS) {
                r->lod_hist[species * RENDER_LOD_BINS + b]++;
                /* a felled tree (its impostor's fall code set) may draw a plate or stump */
                r->felled_hist[b] += !debris && cells->bill_fall[cells->cell[c].first + t] != 0.0f;
            }
            r->tree_dist[n_vis] = dist_m;
            r->vis[n_vis++] = k;
        }
    }
    r->stats.trees_culled = n_drawn - n_vis - bulk_trees;
    render_lod_cost cost[RENDER_MAX_SPECIES];
    for (uint32_t s = 0; s < r->n_species; s++) {
        cost[s] = species_cost(&r->sp[s]);
    }
    /* the budget is the whole frame's: the houses and the falling leaves come off it first */
    const double other_tris = (double)(r->house_verts / 3u) + 2.0 * (double)r->ring_count;
    r->budget_scale = render_lod_budget(r->lod_hist, r->felled_hist, cost, r->n_species,
                                        max_scale, fmax(LOD_BUDGET_TRIANGLES - other_tris, 0.0),
                                        LOD_BUDGET_NODES);
    r->stats.lod_scale = r->budget_scale;
    const render_lod_desc ld = { .mode_dist_m = r->desc.lod_mode_dist * r->budget_scale,
                                 .scale = r->budget_scale };
    /* pass 1: classify and count */
    uint32_t rows = 0;
    for (uint32_t v = 0; v < n_vis; v++) {
        const uint32_t k = r->vis[v], i = render_slot_at(r, k);
        const render_instance *in = &r->inst[i];
        const rs_species *s = &r->sp[in->species];
        const render_cull_species cs = render_cull_species_of(s);
        render_tree_lod *const tlp = &r->tree_lod[v];
        render_lod_pick_into(r->tree_dist[v], &cs, &ld, stays_posed(r, k), tlp);
        if (k >= r->n_trees) {
            tlp->n_modes = 0.0f; /* a debris piece: its rest pose needs no modes */
        }
        const render_tree_lod tl = *tlp;
        r->tree_group[v] = tl.flags;
        if (!tl.flags) {
            r->stats.trees_culled++;
            continue;
        }
        if ((tl.flags & RENDER_LOD_FULL) && k < r->n_trees && in->uprooted != 0 &&
            in->fall_rad > 0.02f) {
            r->plates[r->n_plates++] = (float)i;
        }
        if ((tl.flags & RENDER_LOD_FULL) && k < r->n_trees && render_slot_snapped(r, i)) {
            float *e = &r->stumps[8 * r->n_stumps++];
            e[0] = (float)i;
            e[1] = s->stem_r_m;
            e[2] = s->stem_taper;
            e[3] = 0.0f;
            memcpy(&e[4], s->bark, sizeof s->bark);
            e[7] = 0.0f;
        }
        uint32_t *gn = r->grp_n[in->species];
        if (tl.flags & RENDER_LOD_FULL) {
            r->tree_row[v] = rows++;
            gn[G_SKEL]++;
            gn[G_LEAF] += tl.thin_t < 1.0f;
            gn[G_LEAF_THIN] += tl.thin_t > 0.0f;
            gn[G_MESH + tl.mesh_lod]++;
            gn[G_MESH + tl.mesh_lod + 1] += tl.mesh_fade > 0.0f;
            r->stats.trees_full++;
            r->stats.trees_thin += tl.level == LOD_THIN || (tl.level == LOD_IMPOSTOR);
        }
        if (tl.flags & RENDER_LOD_BILLBOARD) {
            gn[G_BILL]++;
            r->stats.trees_billboard++;
        }
    }
    for (uint32_t s = 0; s < r->n_species; s++) {
        r->grp_n[s][G_BILL] += bulk_per_species[s];
    }
    r->stats.trees_billboard += bulk_trees;
    uint32_t off = 0;
    for (uint32_t s = 0; s < r->n_species; s++) {
        for (int g = 0; g < G_COUNT; g++) {
            r->grp_base[s][g] = off;
            off += r->grp_n[s][g];
            r->grp_n[s][g] = 0;
        }
    }
    /* pass 2: fill. Each fade draws both levels, complementary pixels of one dither: the
       finer with keep share 1 - t, the coarser with -t (shaders/common.glsl dither_keep). */
    for (uint32_t v = 0; v < n_vis; v++) {
        const uint32_t i = render_slot_at(r, r->vis[v]);
        uint32_t fl = r->tree_group[v];
        if (!fl) {
            continue;
        }
        uint32_t sp = r->inst[i].species;
        const render_tree_lod *tl = &r->tree_lod[v];
        const float tb = tl->bill_t, tt = tl->thin_t;
        float row = (float)r->tree_row[v];
#define PUT(g, a, b, c, d)                                                 \
    do {                                                                   \
        float *e = &r->list[4 * (r->grp_base[sp][g] + r->grp_n[sp][g]++)]; \
        e[0] = (a);                                                        \
        e[1] = (b);                                                        \
        e[2] = (c);                                                        \
        e[3] = (d);                                                        \
    } while (0)
        if (fl & RENDER_LOD_FULL) {
            float keep = 1.0f - tb; /* fading out toward the impostor */
            PUT(G_SKEL, (float)i, row, tl->n_modes, 1.0f);
            if (tt < 1.0f) {
                PUT(G_LEAF, (float)i, row, 0.0f, tt > 0.0f ? 1.0f - tt : keep);
            }
            if (tt > 0.0f) {
                PUT(G_LEAF_THIN, (float)i, row, 0.0f, tt < 1.0f ? -tt : keep);
            }
            uint32_t k = tl->mesh_lod;
            float mf = tl->mesh_fade;
            if (mf > 0.0f) {
                PUT(G_MESH + (int)k, (float)i, row, 0.0f, 1.0f - mf);
                PUT(G_MESH + (int)k + 1, (float)i, row, 0.0f, -mf);
            } else {
                PUT(G_MESH + (int)k, (float)i, row, 0.0f, keep);
            }
        }
        if (fl & RENDER_LOD_BILLBOARD) {
            PUT(G_BILL, (float)i, render_bill_leaf_share(r, i), render_bill_fall(r, i),
                (fl & RENDER_LOD_FULL) ? -tb : 1.0f);
        }
    }
    /* the cells drawn as impostors whole: their trees, standing or lying, in order */
    for (uint32_t n = 0; n < n_bulk; n++) {
        const render_cell *cl = &cells->cell[cells->bulk[n]];
        for (uint32_t at = cl->first; at < cl->first + cl->count; at++) {
            const uint32_t sp = cells->species[at];
            PUT(G_BILL, (float)cells->tree[at], cells->bill_leaf[at], cells->bill_fall[at], 1.0f);
        }
    }
#undef PUT
    render_buf_upload(&r->list_buf, GL_RGBA32F, r->list, (size_t)off * 4 * sizeof(float));
    r->rows_used = rows;
}

int render_frame(render *r, const render_camera *cam, double time_s, gale_err *err)
{
    memset(&r->stats, 0, sizeof r->stats);
    float t = (float)render_rel_time(r, time_s);
    camera_matrices(r, cam);
    /* one upload of every tree's q (the rest slot at cap_trees is uploaded when used) */
    if (r->n_trees > 0) {
        render_buf_upload(&r->q, GL_R32F, r->q_stage,
                          (size_t)r->n_trees * r->q_stride * sizeof(float));
    }
    render_damage_upload(r);
    const double cull_t0_s = mono_s();
    build_lists(r);
    r->stats.cull_ms = (mono_s() - cull_t0_s) * 1e3;
    uint32_t rows = r->rows_used;
    int maxw = 1;
    for (uint32_t s = 0; s < r->n_species; s++) {
        maxw = (int)r->sp[s].n_nodes > maxw ? (int)r->sp[s].n_nodes : maxw;
    }
    int rc = render_skel_ensure(r, maxw, rows > 0 ? (int)rows : 1, err);
    if (rc < 0) {
        return rc;
    }
    for (uint32_t s = 0; s < r->n_species; s++) {
        render_draw_skeleton(r, &r->sp[s], r->grp_base[s][G_SKEL], r->grp_n[s][G_SKEL]);
    }

    rc = render_scene_bind(r, err);
    if (rc < 0) {
        return rc;
    }
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    /* sky and ground */
    glDepthFunc(GL_ALWAYS);
    render_set_common(r, &r->p_sky, t, r->desc.fog_dist);
    mat4 inv, vp;
    memcpy(vp, r->viewproj, sizeof vp);
    glm_mat4_inv(vp, inv);
    glUniformMatrix4fv(r->p_sky.u_inv_viewproj, 1, GL_FALSE, (float *)inv);
    glBindVertexArray(r->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    r->stats.draw_calls++;
    glDepthFunc(GL_LESS);
    /* houses (both faces drawn: the mesh is closed, and thin boxes stay visible) */
    if (r->house_verts > 0) {
        render_set_common(r, &r->p_house, t, r->desc.fog_dist);
        glUniform3f(r->p_house.u_wall, 0.92f, 0.82f, 0.64f);
        glUniform3f(r->p_house.u_roof, 0.52f, 0.22f, 0.15f);
        glUniform3f(r->p_house.u_window, 0.14f, 0.18f, 0.24f);
        glBindVertexArray(r->house_vao);
        glDrawArrays(GL_TRIANGLES, 0, (GLsizei)r->house_verts);
        r->stats.draw_calls++;
        r->stats.triangles += r->house_verts / 3u;
    }
    /* trunks and branches */
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    render_set_common(r, &r->p_tree, t, r->desc.fog_dist);
    for (uint32_t s = 0; s < r->n_species; s++) {
        for (uint32_t l = 0; l < r->sp[s].n_lods; l++) {
            render_draw_tree(r, &r->sp[s], l, r->grp_base[s][G_MESH + l], r->grp_n[s][G_MESH + l]);
        }
    }
    glDisable(GL_CULL_FACE);
    render_plates_draw(r, t);
    render_stumps_draw(r, t);
    render_set_common(r, &r->p_leaf, t, r->desc.fog_dist);
    for (uint32_t s = 0; s < r->n_species; s++) {
        render_draw_leaves(r, &r->sp[s], r->grp_base[s][G_LEAF], r->grp_n[s][G_LEAF], false);
        render_draw_leaves(r, &r->sp[s], r->grp_base[s][G_LEAF_THIN], r->grp_n[s][G_LEAF_THIN],
                           true);
    }
    /* impostors, swaying with each tree's lowest modes */
    render_set_common(r, &r->p_bill, t, r->desc.fog_dist);
    render_bind_buf(RU_LIST, &r->list_buf);
    render_bind_buf(RU_TREES, &r->trees);
    render_bind_buf(RU_Q, &r->q);
    glUniform1i(r->p_bill.u_qstride, (GLint)r->q_stride);
    for (uint32_t s = 0; s < r->n_species; s++) {
        uint32_t n = r->grp_n[s][G_BILL];
        if (n == 0) {
            continue;
        }
        glUniform1i(r->p_bill.u_base, (GLint)r->grp_base[s][G_BILL]);
        glUniform3fv(r->p_bill.u_bsize, 1, r->sp[s].bill);
        glUniform3fv(r->p_bill.u_sway, LOD_IMPOSTOR_MODES, &r->sp[s].imp_sway[0][0]);
        glUniform1f(r->p_bill.u_crown_z, r->sp[s].imp_crown_z);
        glUniform2fv(r->p_bill.u_ab, LOD_IMPOSTOR_MODES, r->sp[s].ab);
        render_bind_tex(RU_IMP, GL_TEXTURE_2D, r->sp[s].imp_tex);
        render_bind_tex(RU_IMP_WOOD, GL_TEXTURE_2D, r->sp[s].imp_wood_tex);
        glBindVertexArray(r->vao_empty);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, (GLsizei)n);
        r->stats.draw_calls++;
        r->stats.triangles += 2u * (uint64_t)n;
    }
    /* falling and landed leaves */
    render_fall_draw(r, t);
    render_rain_draw(r, t);
    glBindVertexArray(0);
    render_scene_present(r);
    /* leave the target bound for overlays */
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render_frame: OpenGL error 0x%x", (unsigned)e);
    }
    return 0;
}

void render_present(render *r)
{
    if (r->ctx.kind == GL_CTX_WINDOW) {
        glfwSwapBuffers(r->ctx.window);
    } else {
        glFinish();
    }
}

int render_resize(render *r, int width, int height, gale_err *err)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return gale_errf(err, GALE_E_ARG, "render_resize: %dx%d (1..16384)", width, height);
    }
    r->w = width;
    r->h = height;
    return render_target_create(r, err);
}

void render_set_res_scale(render *r, float scale)
{
    r->res_scale = scale >= 0.25f && scale <= 1.0f ? scale : 1.0f;
}

void render_set_fog_dist(render *r, float fog_m)
{
    if (fog_m > 0.0f && isfinite(fog_m)) {
        r->desc.fog_dist = fog_m;
    }
}

void render_set_lod_scale(render *r, float scale)
{
    r->lod_scale = scale > 0.0f && isfinite(scale) ? scale : 1.0f;
}

void render_last_view(const render *r, float viewproj[16], float eye[3], float *full_m)
{
    memcpy(viewproj, r->viewproj, 16 * sizeof(float));
    memcpy(eye, r->eye, 3 * sizeof(float));
    *full_m = lod_outer_m[LOD_FULL] * r->budget_scale;
}

void render_size(const render *r, int *width, int *height)
{
    *width = r->w;
    *height = r->h;
}

int render_read_rgb(render *r, uint8_t *rgb, gale_err *err)
{
    render_target_bind(r);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (r->ctx.kind == GL_CTX_WINDOW) {
        glReadBuffer(GL_BACK);
    }
    glReadPixels(0, 0, r->w, r->h, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    /* bottom-up to top-down, in place */
    size_t row = (size_t)r->w * 3;
    for (int y = 0; y < r->h / 2; y++) {
        uint8_t *a = rgb + (size_t)y * row, *b = rgb + (size_t)(r->h - 1 - y) * row;
        for (size_t k = 0; k < row; k++) {
            uint8_t t = a[k];
            a[k] = b[k];
            b[k] = t;
        }
    }
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render_read_rgb: OpenGL error 0x%x", (unsigned)e);
    }
    return 0;
}

int render_write_png(render *r, const char *path, gale_err *err)
{
    size_t n = (size_t)r->w * (size_t)r->h * 3;
    uint8_t *rgb = malloc(n);
    if (!rgb) {
        return gale_errf(err, GALE_E_NOMEM, "render_write_png: out of memory");
    }
    int rc = render_read_rgb(r, rgb, err);
    if (rc == 0 && !stbi_write_png(path, r->w, r->h, 3, rgb, r->w * 3)) {
        rc = gale_errf(err, GALE_E_IO, "%s: cannot write PNG", path);
    }
    free(rgb);
    return rc;
}

/* Rebuilds slot `slot`'s skeleton (all modes; none for a debris piece) and reads it back:
 * px[4 n_nodes], xyz the node position, w whether it is drawn (shaders/skel.frag). */
static int skeleton_readback(render *r, uint32_t slot, float *px, gale_err *err)
{
    const rs_species *s = &r->sp[r->inst[slot].species];
    render_buf_upload(&r->q, GL_R32F, r->q_stage,
                      (size_t)(r->cap_trees + 1) * r->q_stride * sizeof(float));
    render_damage_upload(r);
    float modes = slot > r->cap_trees ? 0.0f : (float)s->n_modes;
    float ent[4] = { (float)slot, 0.0f, modes, 1.0f };
    render_buf_upload(&r->list_buf, GL_RGBA32F, ent, sizeof ent);
    int rc = render_skel_ensure(r, (int)s->n_nodes, 1, err);
    if (rc < 0) {
        return rc;
    }
    render_draw_skeleton(r, s, 0, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, r->skel_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, (GLsizei)s->n_nodes, 1, GL_RGBA, GL_FLOAT, px);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        return gale_errf(err, GALE_E_STATE, "render: skeleton readback: OpenGL error 0x%x",
                         (unsigned)e);
    }
    return 0;
}

int render_read_skeleton(render *r, uint32_t tree, float *out, gale_err *err)
{
    if (tree >= r->n_trees) {
        return gale_errf(err, GALE_E_RANGE, "render_read_skeleton: tree %u of %u", tree,
                         r->n_trees);
    }
    const rs_species *s = &r->sp[r->inst[tree].species];
    float *px = malloc((size_t)s->n_nodes * 4 * sizeof(float));
    if (!px) {
        return gale_errf(err, GALE_E_NOMEM, "render_read_skeleton: out of memory");
    }
    int rc = skeleton_readback(r, tree, px, err);
    for (uint32_t i = 0; rc == 0 && i < s->n_nodes; i++) {
        memcpy(&out[3 * i], &px[4 * i], 3 * sizeof(float));
    }
    free(px);
    return rc;
}

int render_read_attached(render *r, uint32_t k, uint8_t *out, gale_err *err)
{
    if (k >= r->n_trees + r->n_debris) {
        return gale_errf(err, GALE_E_RANGE, "render_read_attached: %u of %u trees + %u debris",
                         k, r->n_trees, r->n_debris);
    }
    const uint32_t slot = render_slot_at(r, k);
    const rs_species *s = &r->sp[r->inst[slot].species];
    float *px = malloc((size_t)s->n_nodes * 4 * sizeof(float));
    if (!px) {
        return gale_errf(err, GALE_E_NOMEM, "render_read_attached: out of memory");
    }
    int rc = skeleton_readback(r, slot, px, err);
    for (uint32_t i = 0; rc == 0 && i < s->n_nodes; i++) {
        out[i] = px[4 * i + 3] > 0.5f;
    }
    free(px);
    return rc;
}

void render_set_storm(render *r, const storm_fx *fx)
{
    if (fx) {
        r->fx = *fx;
    } else {
        storm_fx_calm(&r->fx);
    }
}

render_stats render_get_stats(const render *r)
{
    return r->stats;
}
