/* Leaf stripping by gusts (PHYSICS.md "Storm damage"): Hurricane Hugo's field data has
 * defoliation begin near 60 km/h gusts, rise fast to about 130 km/h and not worsen above
 * it. A crown's leaf area relaxes towards the level its strongest gusts leave. */
#ifndef GALE_DAMAGE_STRIP_H
#define GALE_DAMAGE_STRIP_H

#define DAMAGE_STRIP_START_MS (60.0f / 3.6f) /* no stripping below this gust [m/s] */
#define DAMAGE_STRIP_FULL_MS (130.0f / 3.6f) /* the plateau from this gust on [m/s] */
#define DAMAGE_STRIP_TAU_S 10.0f             /* time for a crown to lose 63 % of the
                                                area its gusts take [s] */

/* Leaf area fraction a gust of gust_ms leaves on a crown: 1 below the start, then a
 * smoothstep down to 1 - strip_max at the plateau. */
float damage_strip_target(float gust_ms, float strip_max);

/* The relaxation over a step of dt_s: exp(-dt_s / DAMAGE_STRIP_TAU_S). */
float damage_strip_decay(float dt_s);

/* Leaf area after a step of decay = damage_strip_decay(dt_s) more under gust_ms, from leaf
 * (0..1): it never grows back (only a heal restores it). */
float damage_strip_step(float leaf, float gust_ms, float strip_max, float decay);

#endif
