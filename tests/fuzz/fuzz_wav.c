/* Fuzz target for the WAV reader (client/audio/wav_stats.h: gale-wav-stats reads any file
 * it is given): every input is parsed as a file; a parse that succeeds gives frames that
 * lie inside the input, and measuring them must not crash. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "wav_stats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* a copy with no slack after it, so ASan sees any read past size */
    uint8_t *b = malloc(size ? size : 1);
    if (!b) {
        return 0;
    }
    memcpy(b, data, size);
    wav_pcm w;
    if (wav_pcm_parse(b, size, "fuzz", &w, NULL) == 0) {
        if ((size_t)w.frames * (size_t)w.channels * 2u > size) {
            abort();
        }
        if (w.frames < 48000) {
            wav_stats st = wav_stats_of(&w, 0, 0);
            (void)st;
        }
        wav_pcm_free(&w);
    }
    free(b);
    return 0;
}
