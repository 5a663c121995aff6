/* The closed card: while the exhibit's opening hours keep it closed (the server's
 * schedule message, protocol/PROTOCOL.md "schedule") the last picture stays, dimmed, under
 * a card that says when it opens, in the language shown (configs/lang closed.card). */
#include <stdio.h>

#include "client.h"

void client_closed_on_schedule(client *c, const ctl_schedule *s)
{
    c->closed = !s->open;
    /* the card shows hours and minutes: a visitor reads "09:30", not "09:30:00" */
    snprintf(c->opens_at, sizeof c->opens_at, "%.5s", s->open ? "" : s->next_change);
    fprintf(stderr, "gale-client: exhibit %s%s%s\n", s->open ? "open" : "closed",
            s->next_change[0] ? (s->open ? " until " : ", opens at ") : "", s->next_change);
}

void client_closed_draw(client *c, int fb_w, int fb_h)
{
    if (!c->closed || !c->hud) {
        return;
    }
    char card[HUD_LINE_CHARS];
    if (c->opens_at[0]) {
        lang_format(card, sizeof card, c->lang, L_CLOSED_CARD, c->opens_at);
    } else {
        snprintf(card, sizeof card, "%s", lang_text(c->lang, L_CLOSED_CARD_NO_TIME));
    }
    hud_draw_veil(c->hud, card, fb_w, fb_h);
    if (c->hud_lines < HUD_MAX_LINES) {
        /* for scripts reading the headless HUD text */
        snprintf(c->hud_text[c->hud_lines++], HUD_LINE_CHARS, "%s", card);
    }
}
