/* What the listener has near it (sound_listener.h). */
#include <math.h>

#include "sound_listener.h"

int sound_class_of(float d_m)
{
    int best = 0;
    float bd = INFINITY, ld = logf(fmaxf(d_m, 1e-6f));
    for (int k = 0; k < SOUND_CLASSES; k++) {
        float e = fabsf(ld - logf(sound_class_d_m[k]));
        if (e < bd) {
            bd = e;
            best = k;
        }
    }
    return best;
}

void sound_species_profile(const asset *a, sound_species *out)
{
    *out = (sound_species){ 0 };
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        int p = a->parent[i];
        if (p < 0) {
            continue;
        }
        const float *x = &a->rest[3 * i], *y = &a->rest[3 * p];
        float len = sqrtf((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                          (x[2] - y[2]) * (x[2] - y[2]));
        out->class_len_m[sound_class_of(2.0f * a->radius[i])] += len;
    }
    for (uint32_t j = 0; j < a->n_leaves; j++) {
        if (a->leaf_shape == 2) {
            out->class_len_m[sound_class_of(SOUND_NEEDLE_D_M)] +=
                SOUND_NEEDLES_PER_TUFT * a->leaf_size[j];
        } else {
            out->leaves += 1.0f;
        }
    }
}

void sound_listen(const float eye_xy[2], const ctl_instance *inst, uint32_t n,
                  const sound_species *prof, uint32_t n_species, const damage_view *dmg,
                  sound_scene *s)
{
    float len[SOUND_CLASSES] = { 0 }, leaves = 0.0f, leaves_all = 0.0f;
    for (uint32_t t = 0; t < n; t++) {
        const ctl_instance *in = &inst[t];
        if (in->species >= n_species) {
            continue;
        }
        float dx = in->pos[0] - eye_xy[0], dy = in->pos[1] - eye_xy[1];
        float w = sound_near_weight(sqrtf(dx * dx + dy * dy));
        if (w == 0.0f) {
            continue;
        }
        const sound_species *p = &prof[in->species];
        float kept = 1.0f, sc = in->scale > 0.0f ? in->scale : 1.0f;
        if (dmg && t < dmg->n_trees) {
            kept = dmg->tree[t].fallen ? 0.0f
                                       : (float)dmg->tree[t].level / (float)WIRE_DAMAGE_LEVELS;
        }
        /* a lying tree is out of the wind: it neither sings nor rustles */
        float stand = dmg && t < dmg->n_trees && dmg->tree[t].fallen ? 0.0f : 1.0f;
        for (int k = 0; k < SOUND_CLASSES; k++) {
            /* needles go with the leaves a stripped crown loses */
            len[k] += w * sc * p->class_len_m[k] * stand * (k == 0 ? kept : 1.0f);
        }
        leaves_all += w * p->leaves;
        leaves += w * p->leaves * kept;
    }
    for (int k = 0; k < SOUND_CLASSES; k++) {
        s->class_len_m[k] = len[k];
    }
    s->leaves_w = leaves_all;
    s->kept = leaves_all > 0.0f ? leaves / leaves_all : 1.0f;
}
