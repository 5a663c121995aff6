/* Draws the kiosk's touch panel (kiosk_ui.h) over the bound framebuffer with the HUD's
 * batch of shapes and text (hud.h); a GL 3.3 context must be current. */
#ifndef GALE_KIOSK_UI_DRAW_H
#define GALE_KIOSK_UI_DRAW_H

#include "hud.h"
#include "kiosk_ui.h"

/* The panel as laid out for ui->fb_w × ui->fb_h (kiosk_ui_layout), the pressed control lit.
 * No allocation. */
void kiosk_ui_draw(hud *h, const kiosk_ui *ui);

#endif
