/* gale-wav-stats: the level and brightness of a WAV (gale-client --audio-out's) as JSON:
 * RMS and peak in dBFS, spectral centroid and the spectrum's peak frequency
 * (client/audio/wav_stats.h), over the whole file or a span of it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wav_stats.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: gale-wav-stats FILE.wav [--from S] [--to S] [--onset S]\n"
               "prints {\"file\", \"seconds\", \"rms_dbfs\", \"peak_dbfs\", \"peak\",\n"
               "\"centroid_hz\", \"peak_hz\", the power's \"low_share\" (< 250 Hz),\n"
               "\"mid_share\" (to 2 kHz), \"high_share\", the quietest and loudest 100 ms\n"
               "\"env_min_dbfs\", \"env_max_dbfs\"} of the span [--from, --to) (default the whole\n"
               "file); --onset S adds \"onset_s\": the first instant from S where the 2 ms\n"
               "RMS rises 12 dB over its median of the 200 ms before (-1: none within 1 s)\n");
}

static double num(const char *o, const char *v)
{
    char *end = NULL;
    double x = v ? strtod(v, &end) : (double)NAN;
    if (!v || end == v || *end || !(x >= 0.0)) {
        fprintf(stderr, "gale-wav-stats: %s: expected seconds >= 0, got \"%s\"\n", o, v ? v : "");
        exit(2);
    }
    return x;
}

static void jnum(const char *k, double v, int last)
{
    if (isfinite(v)) {
        printf("\"%s\": %.6g%s", k, v, last ? "" : ", ");
    } else {
        printf("\"%s\": null%s", k, last ? "" : ", ");
    }
}

int main(int argc, char **argv)
{
    const char *path = NULL;
    double from = 0.0, to = 0.0, onset = -1.0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--from")) {
            from = num(argv[i], argv[i + 1]), i++;
        } else if (!strcmp(argv[i], "--to")) {
            to = num(argv[i], argv[i + 1]), i++;
        } else if (!strcmp(argv[i], "--onset")) {
            onset = num(argv[i], argv[i + 1]), i++;
        } else if (argv[i][0] == '-' || path) {
            fprintf(stderr, "gale-wav-stats: unexpected \"%s\" (see --help)\n", argv[i]);
            return 2;
        } else {
            path = argv[i];
        }
    }
    if (!path) {
        usage(stderr);
        return 2;
    }
    wav_pcm w;
    gale_err err = { 0 };
    if (wav_pcm_load(path, &w, &err) != 0) {
        fprintf(stderr, "gale-wav-stats: %s\n", err.msg);
        return 1;
    }
    wav_stats st = wav_stats_of(&w, (uint32_t)(from * w.rate_hz), (uint32_t)(to * w.rate_hz));
    printf("{\"file\": \"%s\", \"rate_hz\": %d, \"channels\": %d, ", path, w.rate_hz, w.channels);
    jnum("seconds", st.seconds, 0);
    jnum("rms_dbfs", st.rms_dbfs, 0);
    jnum("peak_dbfs", st.peak_dbfs, 0);
    jnum("peak", st.peak, 0);
    jnum("centroid_hz", st.centroid_hz, 0);
    jnum("peak_hz", st.peak_hz, 0);
    jnum("low_share", st.low_share, 0);
    jnum("mid_share", st.mid_share, 0);
    jnum("high_share", st.high_share, 0);
    jnum("env_min_dbfs", st.env_min_dbfs, 0);
    jnum("env_max_dbfs", st.env_max_dbfs, onset < 0.0);
    if (onset >= 0.0) {
        jnum("onset_s", wav_stats_onset_s(&w, onset, onset + 1.0, 12.0), 1);
    }
    printf("}\n");
    wav_pcm_free(&w);
    return 0;
}
