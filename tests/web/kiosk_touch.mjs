// A finger on the kiosk page's panel (web/kiosk_dial.js), for the kiosk browser tests: a drag
// along the wind dial's ring to a speed, a drag on the compass ring to a bearing, each point
// found from the control's own drawing (its SVG's screen transform) and web/kiosk_scale.js's
// angle of a speed, as gale-client's --touch finds kiosk_ui_dial_point.
import { dialAngle } from '../../web/kiosk_scale.js';

const DIAL_RING = 109; // between the dial's inner and outer radius (kiosk_ui.c 86, 132)
const COMPASS_RING = 74; // on the compass's ring (0.87 of its radius 85)

// the page pixel of the point at radius r and angle a [rad, clockwise from up] of svg #id
export function ringPoint(page, id, r, a) {
    return page.evaluate(([id, r, a]) => {
        const svg = document.getElementById(id), m = svg.getScreenCTM();
        const p = new DOMPoint(r * Math.sin(a), -r * Math.cos(a)).matrixTransform(m);
        return [p.x, p.y];
    }, [id, r, a]);
}

// Presses the dial at speed `from` (m/s), drags along the ring to `to` in steps over about
// ms milliseconds, lets go.
export async function dialTo(page, to, { from = null, steps = 10, ms = 800 } = {}) {
    const a1 = dialAngle(to);
    const a0 = from === null ? a1 : dialAngle(from);
    const p0 = await ringPoint(page, 'dial', DIAL_RING, a0);
    await page.mouse.move(p0[0], p0[1]);
    await page.mouse.down();
    for (let k = 1; k <= steps; k++) {
        const p = await ringPoint(page, 'dial', DIAL_RING, a0 + (a1 - a0) * k / steps);
        await page.mouse.move(p[0], p[1]);
        await new Promise((r) => setTimeout(r, ms / steps));
    }
    await page.mouse.up();
}

// Touches the compass ring at the bearing the wind should come from (degrees clockwise
// from north) and lets go.
export async function compassTo(page, bearingDeg) {
    const p = await ringPoint(page, 'compass', COMPASS_RING, bearingDeg * Math.PI / 180);
    await page.mouse.move(p[0], p[1]);
    await page.mouse.down();
    await page.mouse.up();
}
