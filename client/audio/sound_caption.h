/* Sound captions: what the visitor would hear, as a line of text, for those who cannot hear
 * it ("[wind howling] [tree snaps]"). One table of keys into the visitor's texts
 * (configs/lang, lang.h), which the page holds in the same order (web/sound_policy.js
 * SOUND_CAPTIONS). */
#ifndef GALE_SOUND_CAPTION_H
#define GALE_SOUND_CAPTION_H

#include <stddef.h>

enum sound_caption_key {
    SOUND_CAP_WIND_WHISPERING = 0, /* sound.wind_whispering */
    SOUND_CAP_WIND_BLOWING,        /* sound.wind_blowing */
    SOUND_CAP_WIND_ROARING,        /* sound.wind_roaring */
    SOUND_CAP_WIND_HOWLING,        /* sound.wind_howling */
    SOUND_CAP_LEAVES_RUSTLING,     /* sound.leaves_rustling */
    SOUND_CAP_TWIGS_WHISTLING,     /* sound.twigs_whistling */
    SOUND_CAP_BRANCH_CRACKS,       /* sound.branch_cracks */
    SOUND_CAP_TREE_SNAPS,          /* sound.tree_snaps */
    SOUND_CAP_TREE_UPROOTED,       /* sound.tree_uprooted */
    SOUND_CAPS
};

/* The key ("sound.wind_howling") of k and its text in a language (lang.h: "[wind
 * howling]"); NULL outside the table. */
const char *sound_caption_key(int k);
const char *sound_caption_text(int lang, int k);

/* What is heard now, most telling first, at most 4 keys into out: a one-shot heard less
 * than SOUND_CAPTION_EVENT_S ago (event: SOUND_EV_*, or -1 for none), the wind by its
 * speed at the listener (nothing below SOUND_BED_U_MIN_MS), the leaves when they click
 * SOUND_CAPTION_RUSTLE_HZ a second, the twigs when a class sings
 * SOUND_CAPTION_WHISTLE_DB. Returns how many. */
int sound_caption_pick(float u_ms, float rustle_hz, float loudest_tone_db, int event, int out[4]);

/* The picked captions' texts in a language joined by a space into buf (cap bytes); returns
 * buf. */
char *sound_caption_line(int lang, const int *keys, int n, char *buf, size_t cap);

#endif
