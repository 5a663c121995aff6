/* What the listener (the camera) has near it to hear: each species' diameter classes (from
 * its asset: metres of branch in each class, needles from its tufts, leaves), and over the
 * scene's trees within SOUND_NEAR_M of the camera's ground point, those summed with the
 * inverse square of the distance (sound_near_weight) and what the storm left of them: a
 * fallen tree's crown lies still, a stripped one keeps its level's share of leaves. */
#ifndef GALE_SOUND_LISTENER_H
#define GALE_SOUND_LISTENER_H

#include <stdint.h>

#include "asset.h"
#include "ctl.h"
#include "damage_view.h"
#include "sound_mix.h"

typedef struct sound_species {
    float class_len_m[SOUND_CLASSES]; /* metres of each diameter class at unit scale */
    float leaves;                     /* broad leaves and leaflets (rustle) */
} sound_species;

/* The class of diameter d_m: the nearest on a log scale, clamped to the ends. */
int sound_class_of(float d_m);

/* A species' profile from its asset (borrowed). */
void sound_species_profile(const asset *a, sound_species *out);

/* Sums the n trees (their species' profiles prof[inst[t].species], n_species of them)
 * near eye_xy into s's class_len_m, leaves_w and kept; dmg may be NULL (nothing broken)
 * or hold dmg->n_trees ≥ n. The other fields of s are left. */
void sound_listen(const float eye_xy[2], const ctl_instance *inst, uint32_t n,
                  const sound_species *prof, uint32_t n_species, const damage_view *dmg,
                  sound_scene *s);

#endif
