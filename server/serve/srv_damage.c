/* Storm damage on the wire, on the sim thread (PROTOCOL.md "DAMAGE", "FOREST"): each
 * tick's events are gathered and go out with the next snapshot; every snapshot also
 * carries the whole damage state (the broken branches as DAMAGE, the trees as FOREST),
 * which the network sends only to a connection that gets that snapshot's keyframe (a late
 * joiner, a resync), so it sees the same broken forest. */
#include "srv_int.h"

void srv_damage_gather(srv *s)
{
    const damage_sim *d = tick_damage(s->tick);
    if (!d) {
        return;
    }
    unsigned long long heals = atomic_load(&tick_damage_counts(s->tick)->heals);
    if (heals != s->dmg_heals) {
        /* everything before the heal is void: the next snapshot carries the state */
        s->dmg_heals = heals;
        s->dmg_full_due = true;
        s->n_dmg_ev = 0;
    }
    const wire_damage *ev;
    int n = damage_events(d, &ev);
    for (int i = 0; i < n; i++) {
        if (s->n_dmg_ev < WIRE_MAX_DAMAGE) {
            s->dmg_ev[s->n_dmg_ev++] = ev[i];
        } else {
            /* the frame is full: the whole state goes instead */
            s->dmg_full_due = true;
        }
    }
}

int srv_damage_encode(srv *s, const wire_header *h, net_snap *p, gale_err *e)
{
    const damage_sim *d = tick_damage(s->tick);
    if (!d) {
        return GALE_OK;
    }
    /* the whole state: the branches in a DAMAGE frame (the first WIRE_MAX_DAMAGE: PROTOCOL.md
     * "Limits"), every tree's fall and level in a FOREST after it */
    uint32_t n = damage_branches(d, s->dmg_state, WIRE_MAX_DAMAGE);
    if (n > WIRE_MAX_DAMAGE) {
        n = WIRE_MAX_DAMAGE;
    }
    int rc = wire_encode_damage(h, true, s->dmg_state, n, p->extra[SRV_EXTRA_DAMAGE_STATE],
                                p->extra_cap, &p->extra_len[SRV_EXTRA_DAMAGE_STATE], e);
    p->extra_key_only |= 1u << SRV_EXTRA_DAMAGE_STATE;
    uint32_t first = 0, n_fall = 0;
    const uint32_t count = damage_forest(d, s->forest_state, s->forest_fall, &first, &n_fall);
    if (!rc) {
        rc = wire_encode_forest(h, first, count, s->forest_state, s->forest_fall, n_fall,
                                p->extra[SRV_EXTRA_FOREST], p->extra_cap,
                                &p->extra_len[SRV_EXTRA_FOREST], e);
    }
    if (!s->dmg_full_due) {
        p->extra_key_only |= 1u << SRV_EXTRA_FOREST; /* else everyone's, with the heal */
    }
    if (!rc && s->dmg_full_due) {
        rc = wire_encode_damage(h, true, s->dmg_state, n, p->extra[SRV_EXTRA_DAMAGE],
                                p->extra_cap, &p->extra_len[SRV_EXTRA_DAMAGE], e);
    } else if (!rc && s->n_dmg_ev) {
        rc = wire_encode_damage(h, false, s->dmg_ev, s->n_dmg_ev, p->extra[SRV_EXTRA_DAMAGE],
                                p->extra_cap, &p->extra_len[SRV_EXTRA_DAMAGE], e);
    }
    if (!rc) {
        s->dmg_full_due = false;
        s->n_dmg_ev = 0;
    }
    return rc;
}

void srv_heal(srv *s)
{
    tick_request_heal(s->tick);
}
