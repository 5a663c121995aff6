/* The kiosk's camera presets (cameras that show the trees): street level beside
 * a row of palms, a garden oak close up, roof height, aerial; and a slow tour through
 * them for attract mode. Each is placed from the welcome's instances and species names,
 * so it fits any scene; a scene without palms or oaks uses the tree nearest its centre. */
#ifndef GALE_CAMERA_PRESET_H
#define GALE_CAMERA_PRESET_H

#include <stdint.h>

#include "camera.h"
#include "ctl.h"

enum camera_preset {
    CAMERA_PRESET_STREET = 0, /* eye 1.7 m up beside the palms nearest the centre */
    CAMERA_PRESET_GARDEN,     /* an oak close up, crown filling the view */
    CAMERA_PRESET_ROOF,       /* roof height (about 12 m) over the block */
    CAMERA_PRESET_AERIAL,     /* the whole scene from above */
    CAMERA_PRESET_TOUR,       /* each of the above in turn, slowly turning */
    CAMERA_PRESET_COUNT
};

#define CAMERA_TOUR_STOP_S 20.0 /* seconds at each preset of the tour */

/* Preset of a name ("street", "garden", "roof", "aerial", "tour"), -1 for another. */
int camera_preset_find(const char *name);
const char *camera_preset_name(int preset);
/* "street|garden|roof|aerial|tour" for usage lines. */
const char *camera_preset_names(void);

/* Places c at preset (TOUR: its first stop) over the scene. */
void camera_preset_apply(camera *c, int preset, const ctl_instance *inst, uint32_t n_inst,
                         const ctl_species *species, uint32_t n_species);
/* The tour at time t_s [s] since it began: the stop of that time, turning slowly (one
 * degree a second) about its target. */
void camera_preset_tour(camera *c, double t_s, const ctl_instance *inst, uint32_t n_inst,
                        const ctl_species *species, uint32_t n_species);

/* A side view of tree `tree` of inst[] falling towards fall_az_rad (its top's heading,
 * PROTOCOL.md "DAMAGE"): looking across the fall at the middle of the arc its stem sweeps,
 * from whichever side has fewer trees in the way, near enough that a tree of height_m fills
 * the view standing and lying. Returns how many trees stand in the way (within 4 m of the
 * sight line); out of range: c unchanged, UINT32_MAX. */
uint32_t camera_preset_fall(camera *c, const ctl_instance *inst, uint32_t n_inst,
                            uint32_t tree, float height_m, float fall_az_rad);

#endif
