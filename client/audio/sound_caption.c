/* Sound captions (sound_caption.h): the table and which of it is heard. */
#include <stdio.h>

#include "sound_caption.h"
#include "lang.h"
#include "sound_policy.h"

static const char *const keys[SOUND_CAPS] = {
    "sound.wind_whispering", "sound.wind_blowing",   "sound.wind_roaring",
    "sound.wind_howling",    "sound.leaves_rustling", "sound.twigs_whistling",
    "sound.branch_cracks",   "sound.tree_snaps",     "sound.tree_uprooted",
};

const char *sound_caption_key(int k)
{
    return k >= 0 && k < SOUND_CAPS ? keys[k] : NULL;
}

const char *sound_caption_text(int lang, int k)
{
    return k >= 0 && k < SOUND_CAPS ? lang_text(lang, lang_key_find(keys[k])) : NULL;
}

int sound_caption_pick(float u_ms, float rustle_hz, float loudest_tone_db, int event, int out[4])
{
    int n = 0;
    if (event == SOUND_EV_CRACK) {
        out[n++] = SOUND_CAP_BRANCH_CRACKS;
    } else if (event == SOUND_EV_SNAP) {
        out[n++] = SOUND_CAP_TREE_SNAPS;
    } else if (event == SOUND_EV_UPROOT) {
        out[n++] = SOUND_CAP_TREE_UPROOTED;
    }
    if (u_ms >= SOUND_BED_U_MIN_MS) {
        out[n++] = u_ms >= SOUND_CAPTION_HOWL_MS    ? SOUND_CAP_WIND_HOWLING
                   : u_ms >= SOUND_CAPTION_ROAR_MS  ? SOUND_CAP_WIND_ROARING
                   : u_ms < SOUND_CAPTION_WHISPER_MS ? SOUND_CAP_WIND_WHISPERING
                                                     : SOUND_CAP_WIND_BLOWING;
    }
    if (rustle_hz >= SOUND_CAPTION_RUSTLE_HZ) {
        out[n++] = SOUND_CAP_LEAVES_RUSTLING;
    }
    if (loudest_tone_db >= SOUND_CAPTION_WHISTLE_DB) {
        out[n++] = SOUND_CAP_TWIGS_WHISTLING;
    }
    return n;
}

char *sound_caption_line(int lang, const int *k, int n, char *buf, size_t cap)
{
    size_t at = 0;
    if (cap) {
        buf[0] = '\0';
    }
    for (int i = 0; i < n && at < cap; i++) {
        const char *t = sound_caption_text(lang, k[i]);
        int w = snprintf(buf + at, cap - at, "%s%s", i ? " " : "", t ? t : "");
        at += w > 0 ? (size_t)w : 0;
    }
    return buf;
}
