/* WAV writer (wav_writer.h): the canonical 44-byte header of PCM WAVE. */
#include <string.h>

#include "wav_writer.h"

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static void put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static void header(uint8_t h[44], int ch, int rate, uint32_t data_bytes)
{
    memcpy(h, "RIFF", 4);
    put32(h + 4, 36u + data_bytes);
    memcpy(h + 8, "WAVEfmt ", 8);
    put32(h + 16, 16);
    put16(h + 20, 1); /* PCM */
    put16(h + 22, (uint16_t)ch);
    put32(h + 24, (uint32_t)rate);
    put32(h + 28, (uint32_t)(rate * ch * 2));
    put16(h + 32, (uint16_t)(ch * 2));
    put16(h + 34, 16);
    memcpy(h + 36, "data", 4);
    put32(h + 40, data_bytes);
}

int wav_writer_open(wav_writer *w, const char *path, int channels, int rate_hz, gale_err *err)
{
    *w = (wav_writer){ .channels = channels, .rate_hz = rate_hz };
    w->f = fopen(path, "wb");
    uint8_t h[44];
    header(h, channels, rate_hz, 0);
    if (!w->f || fwrite(h, 1, sizeof h, w->f) != sizeof h) {
        if (w->f) {
            fclose(w->f);
            w->f = NULL;
        }
        return gale_errf(err, GALE_E_IO, "%s: cannot write", path);
    }
    return 0;
}

int wav_writer_write(wav_writer *w, const int16_t *s, uint32_t n, gale_err *err)
{
    uint8_t buf[4096];
    size_t total = (size_t)n * (size_t)w->channels, done = 0;
    while (done < total) {
        size_t k = 0;
        for (; k < sizeof buf / 2 && done < total; k++, done++) {
            put16(buf + 2 * k, (uint16_t)s[done]); /* little-endian on any host */
        }
        if (fwrite(buf, 2, k, w->f) != k) {
            return gale_errf(err, GALE_E_IO, "wav: write failed after %llu frames",
                             (unsigned long long)w->frames);
        }
    }
    w->frames += n;
    return 0;
}

int wav_writer_close(wav_writer *w, gale_err *err)
{
    if (!w->f) {
        return 0;
    }
    uint64_t bytes = w->frames * (uint64_t)w->channels * 2u;
    uint8_t h[44];
    header(h, w->channels, w->rate_hz, bytes > 0xffffffd0u ? 0xffffffd0u : (uint32_t)bytes);
    int bad = fseek(w->f, 0, SEEK_SET) != 0 || fwrite(h, 1, sizeof h, w->f) != sizeof h;
    bad |= fclose(w->f) != 0;
    w->f = NULL;
    return bad ? gale_errf(err, GALE_E_IO, "wav: cannot finish the file") : 0;
}
