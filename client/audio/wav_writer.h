/* A WAV file of 16-bit PCM (RIFF/WAVE, one "fmt " and one "data" chunk, little-endian),
 * written as samples come; the sizes are filled in at close. */
#ifndef GALE_WAV_WRITER_H
#define GALE_WAV_WRITER_H

#include <stdint.h>
#include <stdio.h>

#include "err.h"

typedef struct wav_writer {
    FILE *f; /* owned */
    int channels, rate_hz;
    uint64_t frames;
} wav_writer;

/* Opens path for writing and writes the header. 0, or GALE_E_IO with err set. */
int wav_writer_open(wav_writer *w, const char *path, int channels, int rate_hz, gale_err *err);
/* Appends n frames of interleaved samples. 0, or GALE_E_IO. */
int wav_writer_write(wav_writer *w, const int16_t *s, uint32_t n, gale_err *err);
/* Fills in the sizes and closes (a writer never opened is a no-op). 0, or GALE_E_IO. */
int wav_writer_close(wav_writer *w, gale_err *err);

#endif
