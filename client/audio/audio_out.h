/* The sound device: ALSA's "default" PCM (through PipeWire or PulseAudio where the desktop
 * runs one, straight to the card where it does not) fed from a mixer by a thread of its
 * own, 5 ms a period, about 20 ms queued. Where there is no device (a headless machine,
 * no sound card, no server) it is the null device: nothing is played, one log line says
 * why, and the client runs on. */
#ifndef GALE_AUDIO_OUT_H
#define GALE_AUDIO_OUT_H

#include <stdbool.h>
#include <stdint.h>

#include "sound_mix.h"

typedef struct audio_out audio_out;

/* Opens the device (device: an ALSA PCM name, NULL for "default") and starts the thread
 * rendering m (borrowed: it must outlive the audio_out). Never fails for want of a device:
 * then the null device, and *why says so. NULL only without memory. */
audio_out *audio_out_open(sound_mix *m, const char *device, char *why, int why_cap);

/* Stops the thread, drains nothing, closes the device (NULL is a no-op). */
void audio_out_close(audio_out *o);

/* Whether sound reaches a device (false: the null device). */
bool audio_out_live(const audio_out *o);

/* The output device's name: "null" for the null device, else the PCM's and its card's
 * (e.g. "default: HDA Intel PCH"). The string lives as long as o. */
const char *audio_device_name(const audio_out *o);

/* When mixer frame `frame` leaves the speaker [s, CLOCK_MONOTONIC]: from the frames
 * written and the device's queue at the last period. NaN before the first period or on
 * the null device. */
double audio_out_play_time_s(audio_out *o, uint64_t frame);

#endif
