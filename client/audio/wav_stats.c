/* WAV measures (wav_stats.h): a radix-2 FFT of Hann windows, averaged. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wav_stats.h"

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

/* The chunks walked with every length checked against the bytes left. */
int wav_pcm_parse(const uint8_t *b, size_t n, const char *name, wav_pcm *w, gale_err *err)
{
    memset(w, 0, sizeof *w);
    if (n < 12 || memcmp(b, "RIFF", 4) || memcmp(b + 8, "WAVE", 4)) {
        return gale_errf(err, GALE_E_FORMAT, "%s: expected a RIFF WAVE header", name);
    }
    int bits = 0;
    for (size_t at = 12; at + 8 <= n;) {
        const uint8_t *ck = b + at;
        const size_t len = get32(ck + 4), left = n - at - 8;
        if (!memcmp(ck, "fmt ", 4)) {
            if (len < 16 || left < 16) {
                return gale_errf(err, GALE_E_FORMAT, "%s: fmt chunk at byte %zu: expected 16 "
                                 "bytes, got %zu", name, at, len < left ? len : left);
            }
            const uint8_t *fm = ck + 8;
            w->channels = get16(fm + 2);
            w->rate_hz = (int)(get32(fm + 4) & 0x7fffffffu);
            bits = get16(fm + 14);
            /* 8-384 kHz: the measures step in windows of 0.1 s and 2 ms, which need whole
               samples */
            if (get16(fm) != 1 || bits != 16 || w->channels < 1 || w->channels > 8 ||
                w->rate_hz < 8000 || w->rate_hz > 384000) {
                return gale_errf(err, GALE_E_FORMAT, "%s: expected 16-bit PCM of 1..8 channels "
                                 "at 8000..384000 Hz, got format %d, %d bits, %d channels, %d Hz",
                                 name, get16(fm), bits, w->channels, w->rate_hz);
            }
        } else if (!memcmp(ck, "data", 4)) {
            if (!bits) {
                return gale_errf(err, GALE_E_FORMAT, "%s: data chunk at byte %zu before fmt",
                                 name, at);
            }
            const size_t bytes = len < left ? len : left; /* a file cut short: what is there */
            const uint32_t fr = (uint32_t)(bytes / (size_t)(2 * w->channels));
            w->s = malloc((size_t)fr * (size_t)w->channels * 2 + 2);
            if (!w->s) {
                return gale_errf(err, GALE_E_NOMEM, "%s: no memory for %u frames", name, fr);
            }
            const uint8_t *d = ck + 8; /* little-endian on any host */
            for (size_t i = 0; i < (size_t)fr * (size_t)w->channels; i++) {
                w->s[i] = (int16_t)get16(d + 2 * i);
            }
            w->frames = fr;
            return 0;
        }
        if (len > left) {
            break;
        }
        at += 8 + len + (len & 1);
    }
    return gale_errf(err, GALE_E_FORMAT, "%s: no data chunk", name);
}

int wav_pcm_load(const char *path, wav_pcm *w, gale_err *err)
{
    memset(w, 0, sizeof *w);
    FILE *f = fopen(path, "rb");
    if (!f) {
        return gale_errf(err, GALE_E_IO, "%s: cannot open", path);
    }
    uint8_t *buf = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (n == cap) {
            cap = cap ? 2 * cap : 1u << 20;
            uint8_t *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                return gale_errf(err, GALE_E_NOMEM, "%s: no memory to read it", path);
            }
            buf = nb;
        }
        size_t k = fread(buf + n, 1, cap - n, f);
        n += k;
        if (k == 0) {
            break;
        }
    }
    int bad = ferror(f);
    fclose(f);
    int rc = bad ? gale_errf(err, GALE_E_IO, "%s: read failed", path)
                 : wav_pcm_parse(buf, n, path, w, err);
    free(buf);
    return rc;
}

void wav_pcm_free(wav_pcm *w)
{
    free(w->s);
    w->s = NULL;
    w->frames = 0;
}

static double mono(const wav_pcm *w, uint32_t i)
{
    double s = 0.0;
    for (int c = 0; c < w->channels; c++) {
        s += w->s[(size_t)i * (size_t)w->channels + (size_t)c];
    }
    return s / (32768.0 * w->channels);
}

static void fft(double *re, double *im, int n)
{
    for (int i = 1, j = 0; i < n; i++) {
        int bit = n >> 1;
        for (; j & bit; bit >>= 1) {
            j ^= bit;
        }
        j ^= bit;
        if (i < j) {
            double t = re[i];
            re[i] = re[j];
            re[j] = t;
            t = im[i];
            im[i] = im[j];
            im[j] = t;
        }
    }
    for (int len = 2; len <= n; len <<= 1) {
        double a = -2.0 * M_PI / len;
        for (int i = 0; i < n; i += len) {
            for (int k = 0; k < len / 2; k++) {
                double wr = cos(a * k), wi = sin(a * k);
                double xr = re[i + k + len / 2] * wr - im[i + k + len / 2] * wi;
                double xi = re[i + k + len / 2] * wi + im[i + k + len / 2] * wr;
                re[i + k + len / 2] = re[i + k] - xr;
                im[i + k + len / 2] = im[i + k] - xi;
                re[i + k] += xr;
                im[i + k] += xi;
            }
        }
    }
}

void wav_stats_spectrum(const wav_pcm *w, uint32_t from, uint32_t to, double *p)
{
    const int n = WAV_STATS_FFT;
    static double re[WAV_STATS_FFT], im[WAV_STATS_FFT];
    memset(p, 0, sizeof(double) * (size_t)(n / 2 + 1));
    to = to == 0 || to > w->frames ? w->frames : to;
    int windows = 0;
    for (uint32_t at = from; at + (uint32_t)n <= to; at += (uint32_t)n / 2, windows++) {
        for (int i = 0; i < n; i++) {
            re[i] = mono(w, at + (uint32_t)i) * (0.5 - 0.5 * cos(2.0 * M_PI * i / n));
            im[i] = 0.0;
        }
        fft(re, im, n);
        for (int k = 0; k <= n / 2; k++) {
            p[k] += re[k] * re[k] + im[k] * im[k];
        }
    }
    for (int k = 0; windows && k <= n / 2; k++) {
        p[k] /= windows;
    }
}

wav_stats wav_stats_of(const wav_pcm *w, uint32_t from, uint32_t to)
{
    wav_stats st = { .rms_dbfs = -(double)INFINITY, .peak_dbfs = -(double)INFINITY };
    to = to == 0 || to > w->frames ? w->frames : to;
    if (from >= to || !w->rate_hz) {
        return st;
    }
    double ss = 0.0;
    for (uint32_t i = from; i < to; i++) {
        for (int c = 0; c < w->channels; c++) {
            int v = w->s[(size_t)i * (size_t)w->channels + (size_t)c];
            ss += (double)v * v;
            st.peak = abs(v) > st.peak ? abs(v) : st.peak;
        }
    }
    st.seconds = (double)(to - from) / w->rate_hz;
    double rms = sqrt(ss / ((double)(to - from) * w->channels)) / 32768.0;
    st.rms_dbfs = rms > 0.0 ? 20.0 * log10(rms) : -(double)INFINITY;
    st.peak_dbfs = st.peak > 0 ? 20.0 * log10(st.peak / 32768.0) : -(double)INFINITY;
    static double p[WAV_STATS_FFT / 2 + 1];
    wav_stats_spectrum(w, from, to, p);
    double num = 0.0, den = 0.0, best = -1.0;
    for (int k = 1; k <= WAV_STATS_FFT / 2; k++) {
        double f = (double)k * w->rate_hz / WAV_STATS_FFT;
        if (f < 20.0 || f > 20000.0) {
            continue;
        }
        num += f * p[k];
        den += p[k];
        if (p[k] > best) {
            best = p[k];
            st.peak_hz = f;
        }
    }
    st.centroid_hz = den > 0.0 ? num / den : 0.0;
    double band[3] = { 0.0, 0.0, 0.0 };
    for (int k = 1; k <= WAV_STATS_FFT / 2; k++) {
        double f = (double)k * w->rate_hz / WAV_STATS_FFT;
        if (f >= 20.0 && f <= 20000.0) {
            band[f < 250.0 ? 0 : f < 2000.0 ? 1 : 2] += p[k];
        }
    }
    st.low_share = den > 0.0 ? band[0] / den : 0.0;
    st.mid_share = den > 0.0 ? band[1] / den : 0.0;
    st.high_share = den > 0.0 ? band[2] / den : 0.0;
    st.env_min_dbfs = INFINITY;
    st.env_max_dbfs = -INFINITY;
    const uint32_t win = (uint32_t)(0.1 * w->rate_hz);
    for (uint32_t at = from; at + win <= to; at += win) {
        double e = 0.0;
        for (uint32_t i = at; i < at + win; i++) {
            double v = mono(w, i);
            e += v * v;
        }
        double db = e > 0.0 ? 10.0 * log10(e / win) : -200.0;
        st.env_min_dbfs = fmin(st.env_min_dbfs, db);
        st.env_max_dbfs = fmax(st.env_max_dbfs, db);
    }
    return st;
}

/* RMS of the first difference over [at, at + n): a click's broad spectrum stands out of a
 * wind whose power is mostly below 2 kHz (the difference weights each octave 6 dB above
 * the one below it). */
static double window_rms(const wav_pcm *w, uint32_t at, uint32_t n)
{
    double ss = 0.0;
    for (uint32_t i = at > 0 ? at : 1; i < at + n && i < w->frames; i++) {
        double v = mono(w, i) - mono(w, i - 1);
        ss += v * v;
    }
    return sqrt(ss / n);
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double wav_stats_onset_s(const wav_pcm *w, double from_s, double to_s, double rise_db)
{
    const uint32_t n = (uint32_t)(0.002 * w->rate_hz);
    const uint32_t from = (uint32_t)(from_s * w->rate_hz), to = (uint32_t)(to_s * w->rate_hz);
    double before[100];
    int k = 0;
    for (uint32_t at = from > 100 * n ? from - 100 * n : 0; at + n <= from && k < 100; at += n) {
        before[k++] = window_rms(w, at, n);
    }
    qsort(before, (size_t)k, sizeof before[0], cmp_d);
    double base = k ? before[k / 2] : 0.0, thr = fmax(base, 1e-6) * pow(10.0, rise_db / 20.0);
    for (uint32_t at = from; at + n <= to && at + n <= w->frames; at += n / 4) {
        if (window_rms(w, at, n) > thr) {
            return (double)at / w->rate_hz;
        }
    }
    return -1.0;
}
