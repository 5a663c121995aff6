/* The fixed-step loop on the simulation thread (server/SERVER.md "Loop"): scenario →
 * inflow, one tick, leaf seeds gathered, a snapshot every ticks_per_snap ticks, the
 * simulation's metrics, and the overrun policy (step_clock.h): a late tick is counted and
 * logged but never skipped, so simulated time stays exact. */
#include "srv_int.h"
#include "sim_team.h"
#include "step_clock.h"
#include "svc_notify.h"

#include <stdio.h>

/* A pressure solve that ran out of its iteration budget: one line at most every
 * SRV_SOLVE_LOG_S seconds, saying how many such solves there were since the last. */
static void log_unconverged(srv *s, uint32_t tick, const tick_stats *ts)
{
    const double now_s = mono_s();
    s->slog_n++;
    if (now_s < s->slog_next_s) {
        return;
    }
    fprintf(stderr,
            "gale-server: tick %u: wind pressure solve ran out of its budget (%d iterations, "
            "residual %.3g, target %.3g); %llu out of budget since the last such line\n",
            tick, ts->wind_iters, ts->wind_residual, 1.0 / (double)s->d.wind->div_reduction,
            s->slog_n);
    s->slog_next_s = now_s + SRV_SOLVE_LOG_S;
    s->slog_n = 0;
}

void *srv_loop(void *arg)
{
    srv *s = arg;
    sim_metrics *mt = &s->simm;
    const double dt = 1.0 / s->d.sc->tick_hz;
    const uint64_t period_ns = (uint64_t)(dt * 1e9);
    const int rt_priority = s->d.sc->tick_rt_priority;
    if (rt_priority > 0) {
        gale_err e;
        if (sim_team_set_priority(s->d.sc->tick_threads, rt_priority, &e)) {
            fprintf(stderr, "gale-server: %s; they run at the fair scheduler's priority\n",
                    e.msg);
        } else {
            fprintf(stderr, "gale-server: %d tick threads at SCHED_FIFO priority %d\n",
                    s->d.sc->tick_threads, rt_priority);
        }
    }
    step_clock clock;
    step_clock_init(&clock, period_ns);
    /* systemd's watchdog is pinged from here, so a wedged simulation trips it (SERVER.md
     * "Debian service"): four pings per interval */
    const uint64_t wd_us = svc_watchdog_us() / 4u;
    uint64_t wd_next_us = 0;
    bool idled = false;
    while (!atomic_load(&s->stop)) {
        if (wd_us && mono_us() >= wd_next_us) {
            svc_notify("WATCHDOG=1");
            wd_next_us = mono_us() + wd_us;
        }
        if (!srv_ops_open(s->ops)) {
            /* closed by the opening hours (SERVER.md "Opening hours"): no tick, no
             * snapshot; the loop naps, waking for the watchdog and the opening */
            idled = true;
            const struct timespec nap = { 0, SRV_CLOSED_NAP_MS * 1000000L };
            nanosleep(&nap, NULL);
            continue;
        }
        if (idled) {
            /* the clock starts over: the closed time is no backlog to catch up */
            step_clock_init(&clock, period_ns);
            idled = false;
        }
        uint32_t tick = tick_now(s->tick);
        scenario_state st;
        pthread_mutex_lock(&s->scen_lock);
        if ((s->dial_owner || s->picked) && s->d.kiosk_idle_s > 0 &&
            mono_s() - s->dial_last_s > s->d.kiosk_idle_s) {
            /* attract: nobody touched the kiosk for its idle time */
            srv_release_dial_locked(s, "idle");
            srv_playlist_resume_locked(s, tick * dt);
        }
        if (s->scen) {
            scenario_eval(s->scen, tick * dt, &st);
            if (srv_playlist_poll_locked(s, tick * dt, &st) && s->scen) {
                scenario_eval(s->scen, tick * dt, &st);
            }
        }
        scenario *scen = s->scen;
        bool wx_reset = s->wx_reset_due;
        s->wx_reset_due = false;
        if (s->wx_reset_after_ramp && !(s->scen && st.ramping)) {
            /* the ramp's winds are the jump's, not the new minute's */
            wx_reset = true;
            s->wx_reset_after_ramp = false;
        }
        pthread_mutex_unlock(&s->scen_lock);
        if (scen != s->balls_scen) {
            /* the running scenario's force balls (a switch takes effect here) */
            const wind_ball *balls = NULL;
            int nb = scen ? scenario_balls(scen, &balls) : 0;
            tick_set_balls(s->tick, balls, nb);
            s->balls_scen = scen;
        }
        if (wx_reset) {
            weather_gust_init(&s->wx_gust);
        }
        s->sim_scen = scen;
        if (scen) {
            tick_set_inflow(s->tick, &st.inflow);
            srv_weather_sample(s, tick, dt, &st);
        } else {
            srv_weather_sample(s, tick, dt, NULL);
        }
        tick_stats ts;
        gale_err e;
        bool snap = (tick + 1) % (uint32_t)s->ticks_per_snap == 0;
        if (tick_step(s->tick, snap ? s->qbuf[s->cur] : NULL, &ts, &e)) {
            fprintf(stderr, "gale-server: %s: stopping the simulation\n", e.msg);
            net_stop(s->net);
            break;
        }
        if (ts.wind_unconverged) {
            log_unconverged(s, tick, &ts);
        }
        const leaf_seed *ls;
        int nl = tick_leaves(s->tick, &ls);
        for (int i = 0; i < nl && s->n_leaves < WIRE_MAX_LEAVES; i++) {
            s->leaves[s->n_leaves++] = (wire_leaf){ .instance = ls[i].instance,
                                                    .slot = (uint16_t)ls[i].slot,
                                                    .spawn_tick = ls[i].spawn_tick,
                                                    .seed = ls[i].variation };
        }
        srv_damage_gather(s);
        double publish_ms = -1.0;
        if (snap) {
            const double p0 = mono_ms();
            srv_publish(s, tick + 1);
            publish_ms = mono_ms() - p0;
            sim_metrics_publish(mt, publish_ms);
        }
        const uint64_t now_ns = mono_ns();
        uint64_t ns = sim_metrics_tick(mt, tick + 1, &ts);
        const step_verdict v = step_clock_end(&clock, now_ns, ns);
        if (v.overrun) {
            /* The tick is still run (ticks are never skipped, simulated time stays exact);
             * the loop catches up back to back (step_clock.h). */
            unsigned long long k = sim_metrics_overrun(mt);
            time_t sec = time(NULL);
            if (sec != s->olog_sec) {
                s->olog_sec = sec;
                s->olog_n = 0;
            }
            if (s->olog_n++ < SRV_OVERRUN_LOG_PER_S) {
                char where[320], steal[96] = "";
                sim_metrics_describe(where, sizeof where, &ts, publish_ms);
                double steal_ms, span_s;
                if (host_steal_recent(&s->steal, mono_s(), &steal_ms, &span_s) == 0) {
                    snprintf(steal, sizeof steal, "; the host took %.0f ms of the machine's "
                             "CPUs in the last %.1f s", steal_ms, span_s);
                }
                fprintf(stderr,
                        "gale-server: tick %u overran: work %.2f ms of a %.2f ms budget (%s), "
                        "finished %.2f ms after the next tick was due; %llu overruns%s\n",
                        tick, ts.ms, dt * 1e3, where, (double)v.late_ns * 1e-6, k, steal);
            }
        }
        host_steal_advance(&s->steal, mono_s());
        if (v.wait) {
            const struct timespec due = { .tv_sec = (time_t)(clock.due_ns / 1000000000u),
                                          .tv_nsec = (long)(clock.due_ns % 1000000000u) };
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, NULL);
        }
    }
    return NULL;
}
