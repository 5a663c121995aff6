/* The 3-s gust a weather report names (WMO No. 8, part I, 5.8.3: the gust is the highest
 * 3-s running mean of the wind speed; here over the last 60 s): speed samples go into
 * one-second bins, each completed second closes a 3-s mean, and the highest of the last 60
 * such means is the gust. Fixed size, no allocation. */
#ifndef GALE_WEATHER_GUST_H
#define GALE_WEATHER_GUST_H

#define WEATHER_GUST_WINDOW_S 60 /* the gust is the peak 3-s mean of this many seconds */

typedef struct weather_gust {
    long sec;                 /* the whole second being filled; -1 before any sample */
    double sum;               /* of samples in it */
    int n;
    float last3[3];           /* means of the last three completed seconds */
    int n_last3;
    float mean3[WEATHER_GUST_WINDOW_S]; /* 3-s means, one per completed second, a ring */
    int n_mean3, head;
} weather_gust;

void weather_gust_init(weather_gust *g);
/* One speed sample [m/s] at time t_s [s, never decreasing; an earlier t_s starts over]. */
void weather_gust_add(weather_gust *g, double t_s, float speed_ms);
/* The gust [m/s]: the highest 3-s mean of the window, at least floor_ms (the sustained
 * wind, which a gust never undercuts); floor_ms alone before three seconds have passed. */
float weather_gust_ms(const weather_gust *g, float floor_ms);
/* The same over the last window_s 3-s means only (clamped to [1, WEATHER_GUST_WINDOW_S]):
 * a replay at N storm seconds per second spans the gust's 60 storm seconds in 60/N. */
float weather_gust_ms_last(const weather_gust *g, float floor_ms, int window_s);

#endif
