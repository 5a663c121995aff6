/* The 3-s gust tracker of weather_gust.h. */
#include "weather_gust.h"

#include <math.h>

void weather_gust_init(weather_gust *g)
{
    *g = (weather_gust){ .sec = -1 };
}

/* Closes the second being filled: its mean joins the last three, and when three are held
 * their mean joins the ring of 3-s means. */
static void close_second(weather_gust *g)
{
    float mean = g->n ? (float)(g->sum / g->n) : 0.0f;
    g->last3[0] = g->last3[1];
    g->last3[1] = g->last3[2];
    g->last3[2] = mean;
    if (g->n_last3 < 3) {
        g->n_last3++;
    }
    if (g->n_last3 == 3) {
        g->mean3[g->head] = (g->last3[0] + g->last3[1] + g->last3[2]) / 3.0f;
        g->head = (g->head + 1) % WEATHER_GUST_WINDOW_S;
        if (g->n_mean3 < WEATHER_GUST_WINDOW_S) {
            g->n_mean3++;
        }
    }
    g->sum = 0.0;
    g->n = 0;
}

void weather_gust_add(weather_gust *g, double t_s, float speed_ms)
{
    if (!(t_s >= 0.0) || !isfinite(speed_ms)) {
        return;
    }
    long sec = (long)floor(t_s);
    if (sec < g->sec) {
        weather_gust_init(g);
    }
    if (g->sec < 0) {
        g->sec = sec;
    }
    /* seconds with no sample (a stalled loop) close empty only up to the window */
    for (int k = 0; g->sec < sec && k <= WEATHER_GUST_WINDOW_S; k++) {
        close_second(g);
        g->sec++;
    }
    g->sec = sec;
    g->sum += speed_ms > 0.0f ? (double)speed_ms : 0.0;
    g->n++;
}

float weather_gust_ms(const weather_gust *g, float floor_ms)
{
    return weather_gust_ms_last(g, floor_ms, WEATHER_GUST_WINDOW_S);
}

float weather_gust_ms_last(const weather_gust *g, float floor_ms, int window_s)
{
    int w = window_s < 1 ? 1 : window_s > WEATHER_GUST_WINDOW_S ? WEATHER_GUST_WINDOW_S : window_s;
    int n = w < g->n_mean3 ? w : g->n_mean3;
    float m = floor_ms;
    for (int i = 0; i < n; i++) {
        /* the newest mean is the one before head */
        int k = (g->head - 1 - i + 2 * WEATHER_GUST_WINDOW_S) % WEATHER_GUST_WINDOW_S;
        m = g->mean3[k] > m ? g->mean3[k] : m;
    }
    return m;
}
