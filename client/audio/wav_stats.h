/* What a WAV of the client's sound measures: its level (RMS and peak, dBFS), its spectral
 * centroid (the power-weighted mean frequency of its average spectrum, Hann windows of
 * WAV_STATS_FFT samples, half overlapped, over 20 Hz..20 kHz: how bright it is), the
 * frequency of its spectrum's peak, and where a sound sets in. For the tests and
 * gale-wav-stats. */
#ifndef GALE_WAV_STATS_H
#define GALE_WAV_STATS_H

#include <stdint.h>

#include "err.h"

#define WAV_STATS_FFT 8192

typedef struct wav_pcm {
    int16_t *s; /* owned: interleaved */
    uint32_t frames;
    int channels, rate_hz;
} wav_pcm;

typedef struct wav_stats {
    double seconds;
    double rms_dbfs, peak_dbfs;
    int peak;             /* largest |sample| */
    double centroid_hz;
    double peak_hz;       /* the average spectrum's largest bin (20 Hz..20 kHz) */
    double low_share, mid_share, high_share; /* of the power: < 250 Hz, to 2 kHz, above */
    double env_min_dbfs, env_max_dbfs;       /* quietest and loudest 100 ms (RMS) */
} wav_stats;

/* Reads a 16-bit PCM WAV (the chunks it does not know skipped). 0, or GALE_E_IO /
 * GALE_E_FORMAT with err naming the file and what is wrong. */
int wav_pcm_load(const char *path, wav_pcm *w, gale_err *err);
/* The same from n bytes at b (name: for the messages); a data chunk longer than the
 * bytes left gives the frames that are there. */
int wav_pcm_parse(const uint8_t *b, size_t n, const char *name, wav_pcm *w, gale_err *err);
void wav_pcm_free(wav_pcm *w);

/* The measures of frames [from, to) (to 0: to the end) of w, channels averaged. */
wav_stats wav_stats_of(const wav_pcm *w, uint32_t from, uint32_t to);

/* The average power spectrum of frames [from, to) into p[WAV_STATS_FFT / 2 + 1] (bin k at
 * k · rate / WAV_STATS_FFT Hz). */
void wav_stats_spectrum(const wav_pcm *w, uint32_t from, uint32_t to, double *p);

/* The first instant [s] at or after from_s where the RMS of the signal's first difference
 * (a high-pass rising 6 dB an octave: where a click stands out of the wind) over 2 ms
 * windows rises by rise_db above its median over the 200 ms before from_s; a negative
 * value when none does before to_s. */
double wav_stats_onset_s(const wav_pcm *w, double from_s, double to_s, double rise_db);

#endif
