/* A slow reader's rate steps: see net_rate.h. */
#include "net_rate.h"

#include <math.h>

size_t net_rate_key_bytes(const net_snap *p)
{
    if (!p->key_len) {
        return 0;
    }
    size_t key = p->key_len;
    for (int x = 0; x < NET_SNAP_MAX_EXTRA; x++) {
        key += (p->extra_key_only >> x & 1u) ? p->extra_len[x] : 0u;
    }
    return key;
}

size_t net_rate_delta_bytes(const net_snap *p)
{
    return p->delta2_len ? p->delta2_len : p->delta1_len;
}

float net_rate_key_per_delta(size_t key_bytes, size_t delta_bytes)
{
    return key_bytes && delta_bytes ? (float)key_bytes / (float)delta_bytes : 0.0f;
}

int net_rate_floor(float key_per_delta, int hz)
{
    int n = key_per_delta > 2.0f ? (key_per_delta < (float)hz ? (int)ceilf(key_per_delta) : hz) : 2;
    return n < hz ? n : hz;
}

int net_rate_take_floor(size_t key_bytes, double take_bytes_s, int hz)
{
    if (!key_bytes || !(take_bytes_s > 0.0)) {
        return 1;
    }
    const double n = ceil((double)key_bytes * (double)hz / take_bytes_s);
    return n < (double)hz ? (int)n : hz;
}

int net_rate_lower(int decim, float key_per_delta, int take_floor, int hz)
{
    const int floor_n = net_rate_floor(key_per_delta, hz);
    int d = 2 * decim > floor_n ? 2 * decim : floor_n;
    d = d > take_floor ? d : take_floor;
    return d < hz ? d : hz;
}

int net_rate_raise(int decim, float key_per_delta, int hz)
{
    const int half = decim / 2;
    return half >= 2 && half >= net_rate_floor(key_per_delta, hz) ? half : 1;
}
