// The kiosk panel's wind dial and compass ring as SVG, drawn as gale-client draws them
// (client/kiosk/kiosk_ui_draw.c draw_dial, draw_compass; sizes in thousandths of the
// screen height as kiosk_ui.c's layout, so the page's dial is the native one): the dial's
// bands in their colours, the band holding the wind lit and its label in the accent, a
// white needle at the server's wind, a knob under the finger, the figures in the middle;
// the compass ring with an arrow across it pointing where the wind blows and a knob on the
// side it comes from. Both are sliders a finger drags (and keys move); they call
// onSet(value, final) a few times a second while dragged and once, final, on release.
import * as S from './kiosk_scale.js';
import { kt, kioskLang } from './kiosk_text.js';
import { unitSustained, UNIT } from './hud_text.js';
import { kmhFirst } from './lang.js';

const NS = 'http://www.w3.org/2000/svg';
const R1 = 132, R0 = 86; // kiosk_ui.c DIAL_R1, DIAL_R0
const COMP_R = 85;
const SEND_EVERY_MS = 250; // a few values a second while dragged (PROTOCOL.md)

function el(parent, tag, attrs = {}) {
    const e = document.createElementNS(NS, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    parent.append(e);
    return e;
}
const pt = (r, a) => [r * Math.sin(a), -r * Math.cos(a)];
const f1 = (v) => v.toFixed(1);

// a ring sector from angle a0 to a1 [rad, clockwise from up] between radii r0 and r1
function sectorPath(r0, r1, a0, a1) {
    const [x0, y0] = pt(r1, a0), [x1, y1] = pt(r1, a1), [x2, y2] = pt(r0, a1), [x3, y3] = pt(r0, a0);
    const big = a1 - a0 > Math.PI ? 1 : 0;
    return `M${f1(x0)} ${f1(y0)}A${r1} ${r1} 0 ${big} 1 ${f1(x1)} ${f1(y1)}L${f1(x2)} ${f1(y2)}` +
        `A${r0} ${r0} 0 ${big} 0 ${f1(x3)} ${f1(y3)}Z`;
}

function text(parent, x, y, size, cls, anchor = 'middle') {
    return el(parent, 'text', { x: f1(x), y: f1(y), 'font-size': size, class: cls, 'text-anchor': anchor });
}

// A slider drawn in an <svg>: pointer drags through pick(x, y, dragging) (the value at a
// point of the viewBox, null off the control), keys through key(ev).
class SvgSlider {
    constructor(svg, onSet) {
        this.svg = svg;
        this.onSet = onSet;
        this.dragging = false;
        this.sentAt = -Infinity;
        this.sentValue = null;
        this.timer = null;
        this.keyAt = -Infinity; // when a key last set the value, and to what
        this.keyValue = 0;
        svg.setAttribute('tabindex', '0');
        svg.setAttribute('role', 'slider');
        svg.addEventListener('pointerdown', (e) => this.down(e));
        svg.addEventListener('pointermove', (e) => this.move(e));
        svg.addEventListener('pointerup', (e) => this.up(e));
        svg.addEventListener('pointercancel', (e) => this.up(e));
        svg.addEventListener('keydown', (e) => this.key(e));
    }

    local(e) {
        const m = this.svg.getScreenCTM();
        if (!m) return null;
        const p = new DOMPoint(e.clientX, e.clientY).matrixTransform(m.inverse());
        return [p.x, p.y];
    }

    down(e) {
        const p = this.local(e);
        const v = p && this.pick(p[0], p[1], false);
        if (v === null || v === undefined) return;
        e.preventDefault();
        this.svg.setPointerCapture(e.pointerId);
        this.dragging = true;
        this.value = v;
        this.send(false);
        this.draw();
    }

    move(e) {
        if (!this.dragging) return;
        const p = this.local(e);
        if (!p) return;
        this.value = this.pick(p[0], p[1], true);
        this.send(false);
        this.draw();
    }

    up(e) {
        if (!this.dragging) return;
        const p = this.local(e);
        if (p && e.type === 'pointerup') this.value = this.pick(p[0], p[1], true);
        this.dragging = false;
        this.send(true);
        this.draw();
    }

    // while dragged a value every SEND_EVERY_MS (the latest when the time comes); the last
    // on release
    send(final) {
        clearTimeout(this.timer);
        const now = performance.now();
        if (final && this.value === this.sentValue && now - this.sentAt < 2000) return; // (a tap: sent on touching)
        if (final || now - this.sentAt >= SEND_EVERY_MS) {
            this.sentAt = now;
            this.sentValue = this.value;
            this.onSet(this.value, final);
        } else {
            this.timer = setTimeout(() => this.send(false), SEND_EVERY_MS - (now - this.sentAt));
        }
    }

    setByKey(v) {
        this.keyAt = performance.now();
        this.keyValue = v;
        this.value = v;
        this.send(true);
        this.draw();
    }
}

export class WindDial extends SvgSlider {
    // svg: an empty <svg>; onSet(speed_ms, final)
    constructor(svg, onSet) {
        super(svg, onSet);
        svg.setAttribute('viewBox', '-304 -177 608 300');
        svg.setAttribute('aria-valuemin', '0');
        svg.setAttribute('aria-valuemax', String(S.DIAL_MAX_MS));
        this.wind = null; // the server's sustained wind [m/s], null before any WEATHER
        this.held = false; // a kiosk's dial holds it (WEATHER DIAL)
        this.value = 0;
        el(svg, 'circle', { r: R1 + 6, class: 'dial-disc' });
        this.bands = [];
        this.labels = [];
        for (let b = 0; b < S.BANDS; b++) {
            this.bands.push(el(svg, 'path', { fill: S.css(S.BAND_RGB[b]), class: 'dial-band', 'data-band': b }));
            this.labels.push(text(svg, 0, 0, 23, 'dial-label'));
        }
        this.needle = el(svg, 'line', { class: 'dial-needle', 'stroke-width': 8 });
        this.knobRim = el(svg, 'circle', { r: 0.5 * (R1 - R0) + 6, class: 'dial-knob-rim' });
        this.knob = el(svg, 'circle', { r: 0.5 * (R1 - R0), class: 'dial-knob' });
        this.title = text(svg, 0, -50, 19, 'dial-dim');
        this.num = text(svg, 0, 12, 43, 'dial-num');
        this.kmh = text(svg, 0, 42, 19, 'dial-dim');
        this.mph = text(svg, 0, 64, 19, 'dial-dim');
        this.hint = text(svg, 0, R1 * 0.84 + 4, 21, 'dial-hint');
        this.draw();
    }

    // the streamed WEATHER's wind and DIAL flag
    show(windMs, held) {
        this.wind = windMs;
        this.held = held;
        if (!this.dragging) this.value = windMs;
        this.draw();
    }

    // the dial's value at (x, y): on its ring (and a little beyond), or null; dragged into
    // the gap below the dial it stays at the end the finger came from, so crossing the
    // bottom does not flip calm and Category 5 (kiosk_ui.c drag)
    pick(x, y, dragging) {
        const d = Math.hypot(x, y);
        let a = Math.atan2(x, -y);
        if (!dragging && (d < 0.45 * R0 || d > R1 + 35 || Math.abs(a) > 0.5 * S.DIAL_SWEEP_RAD + 0.2)) return null;
        if (Math.abs(a) > 0.5 * S.DIAL_SWEEP_RAD && dragging) {
            a = this.value > 0.5 * S.DIAL_MAX_MS ? S.DIAL_SWEEP_RAD : -S.DIAL_SWEEP_RAD;
        }
        return S.dialSpeed(a);
    }

    key(e) {
        // from the value the last key set while keys are pressed (WEATHER follows the
        // server's ramp, seconds behind), else from the wind shown
        const v = this.dragging ? this.value : performance.now() - this.keyAt < 3000 ? this.keyValue : (this.wind ?? 0);
        const step = { ArrowUp: 1, ArrowRight: 1, ArrowDown: -1, ArrowLeft: -1, PageUp: 5, PageDown: -5 }[e.key];
        if (step !== undefined) this.setByKey(Math.min(Math.max(Math.round(v) + step, 0), S.DIAL_MAX_MS));
        else if (e.key === 'Home') this.setByKey(0);
        else if (e.key === 'End') this.setByKey(S.DIAL_MAX_MS);
        else return;
        e.preventDefault();
    }

    draw() {
        const known = this.wind !== null || this.dragging;
        const v = this.dragging ? this.value : (this.wind ?? 0);
        const cur = S.bandOf(v);
        for (let b = 0; b < S.BANDS; b++) {
            const a0 = S.dialAngle(S.BAND_LOWER_MS[b]);
            const a1 = b + 1 < S.BANDS ? S.dialAngle(S.BAND_LOWER_MS[b + 1]) : 0.5 * S.DIAL_SWEEP_RAD;
            const on = b === cur && known;
            this.bands[b].setAttribute('d', sectorPath(R0, on ? R1 + 8 : R1, a0 + 0.006, a1 - 0.006));
            this.bands[b].setAttribute('fill-opacity', on ? '1' : String(S.BAND_DIM_ALPHA));
            this.bands[b].classList.toggle('on', on);
            // the band's name outside the ring, anchored to the side it is on
            const am = 0.5 * (a0 + a1), s = Math.sin(am), c = Math.cos(am), px = on ? 25.8 : 23;
            const [lx, ly] = pt(R1 + 16, am);
            const t = this.labels[b];
            t.textContent = kt(S.BAND_KEYS[b]);
            t.setAttribute('x', f1(lx));
            t.setAttribute('y', f1(c > 0.3 ? ly - 4 : c < -0.3 ? ly + 0.8 * px : ly + 0.35 * px));
            t.setAttribute('text-anchor', s > 0.3 ? 'start' : s < -0.3 ? 'end' : 'middle');
            t.setAttribute('font-size', px);
            t.setAttribute('class', on ? 'dial-label on' : 'dial-label');
        }
        // the streamed wind: a white needle across the ring
        this.needle.style.display = this.wind === null ? 'none' : '';
        if (this.wind !== null) {
            const a = S.dialAngle(this.wind), [x0, y0] = pt(R0 - 10, a), [x1, y1] = pt(R1 + 10, a);
            Object.entries({ x1: f1(x0), y1: f1(y0), x2: f1(x1), y2: f1(y1) }).forEach(([k, val]) => this.needle.setAttribute(k, val));
            this.needle.dataset.angle = String(a);
        }
        // the finger's value: a knob on the ring
        for (const k of [this.knobRim, this.knob]) k.style.display = this.dragging ? '' : 'none';
        if (this.dragging) {
            const [x, y] = pt(0.5 * (R0 + R1), S.dialAngle(this.value));
            for (const k of [this.knobRim, this.knob]) {
                k.setAttribute('cx', f1(x));
                k.setAttribute('cy', f1(y));
            }
        }
        // the language's first unit large, its second and m/s small, each kept inside the
        // range of the class the lit band names (client/kiosk/kiosk_ui_draw.c, hud_units.c)
        const cls = S.ssClass(v), first = kmhFirst(kioskLang());
        const mph = unitSustained(v, UNIT.MPH, cls), kmh = unitSustained(v, UNIT.KMH, cls), r = unitSustained(v, UNIT.MS, cls);
        this.title.textContent = kt(this.dragging ? 'dial.letgo' : 'dial.title');
        this.title.setAttribute('class', this.dragging ? 'dial-accent' : 'dial-dim');
        this.num.textContent = known ? (first ? kt('dial.kmh', kmh) : kt('dial.mph', mph)) : kt('dial.unknown');
        this.num.setAttribute('class', this.dragging ? 'dial-num dial-accent' : 'dial-num');
        // "230 km/h" is wider than "64 m/s": the figure shrinks to stay inside the ring
        // (kiosk_ui_draw.c's rule)
        this.num.setAttribute('font-size', String(Math.min(43, 43 * 6 / Math.max(6, this.num.textContent.length))));
        this.kmh.textContent = known ? (first ? kt('dial.mph', mph) : kt('dial.kmh', kmh)) : '';
        this.mph.textContent = known ? kt('dial.ms', r) : '';
        this.hint.textContent = kt(this.held ? 'dial.held' : 'dial.drag');
        this.hint.setAttribute('class', this.held ? 'dial-hint dial-accent' : 'dial-hint');
        this.svg.setAttribute('aria-label', kt('dial.title'));
        this.svg.setAttribute('aria-valuenow', String(r));
        this.svg.setAttribute('aria-valuetext', kt('dial.value', known ? this.num.textContent : kt('dial.unknown'), kt(S.BAND_KEYS[cur])));
        this.svg.dataset.band = String(cur);
    }
}

export class CompassRing extends SvgSlider {
    // svg: an empty <svg>; onSet(from_deg, final), where the wind comes from, clockwise
    // from north
    constructor(svg, onSet) {
        super(svg, onSet);
        svg.setAttribute('viewBox', '-105 -140 210 245');
        svg.setAttribute('aria-valuemin', '0');
        svg.setAttribute('aria-valuemax', '359');
        this.from = null;
        this.value = 0;
        this.title = text(svg, 0, -COMP_R - 18, 23, 'comp-title');
        el(svg, 'circle', { r: COMP_R, class: 'dial-disc' });
        el(svg, 'circle', { r: 0.87 * COMP_R, class: 'comp-ring', 'stroke-width': 0.26 * COMP_R, fill: 'none' });
        this.arrow = el(svg, 'g', { class: 'comp-arrow' });
        el(this.arrow, 'line', { x1: 0, y1: f1(-0.6 * COMP_R), x2: 0, y2: f1(0.45 * COMP_R), 'stroke-width': 18 });
        el(this.arrow, 'path', { d: `M0 ${f1(0.72 * COMP_R)}L${f1(0.22 * COMP_R)} ${f1(0.4 * COMP_R)}L${f1(-0.22 * COMP_R)} ${f1(0.4 * COMP_R)}Z` });
        this.knob = el(svg, 'circle', { r: 0.145 * COMP_R, class: 'comp-knob', 'stroke-width': 0.05 * COMP_R, fill: 'none' });
        this.points = ['N', 'E', 'S', 'W'].map((p, i) => {
            const [x, y] = pt(0.87 * COMP_R, i * Math.PI / 2);
            const t = text(svg, x, y + 0.35 * 24, 24, 'comp-point');
            t.dataset.point = p;
            return t;
        });
        this.draw();
    }

    show(fromDeg) {
        this.from = fromDeg;
        if (!this.dragging) this.value = fromDeg;
        this.draw();
    }

    // the ring is a compass seen from above, north up: the finger marks where the wind
    // comes from (kiosk_ui.c bearing_deg)
    pick(x, y, dragging) {
        if (!dragging && Math.hypot(x, y) > COMP_R + 20) return null;
        let b = Math.atan2(x, -y) * 57.29578;
        b = (b + 360) % 360;
        return b >= 360 ? 0 : b;
    }

    key(e) {
        const v = this.dragging ? this.value : performance.now() - this.keyAt < 3000 ? this.keyValue : (this.from ?? 0);
        const step = { ArrowUp: 15, ArrowRight: 15, ArrowDown: -15, ArrowLeft: -15, PageUp: 45, PageDown: -45 }[e.key];
        if (step === undefined) return;
        e.preventDefault();
        this.setByKey((((Math.round(v / 15) * 15 + step) % 360) + 360) % 360);
    }

    draw() {
        const known = this.from !== null || this.dragging;
        const from = this.dragging ? this.value : (this.from ?? 0);
        // the arrow points where the wind blows; its tail and the knob sit on the side it
        // comes from
        this.arrow.style.display = known ? '' : 'none';
        this.knob.style.display = known ? '' : 'none';
        this.arrow.setAttribute('transform', `rotate(${f1(from)})`);
        this.arrow.setAttribute('class', this.dragging ? 'comp-arrow dial-accent' : 'comp-arrow');
        const [kx, ky] = pt(0.87 * COMP_R, from * Math.PI / 180);
        this.knob.setAttribute('cx', f1(kx));
        this.knob.setAttribute('cy', f1(ky));
        const point = kt(S.compassKey(from));
        // the points' letters in the page's language (O for the west in Spanish)
        for (const t of this.points) t.textContent = kt(`compass.${t.dataset.point}`);
        this.title.textContent = kt('compass.title', point);
        this.title.setAttribute('class', this.dragging ? 'comp-title dial-accent' : 'comp-title');
        this.svg.setAttribute('aria-label', kt('compass.label'));
        this.svg.setAttribute('aria-valuenow', String(Math.round(from) % 360));
        this.svg.setAttribute('aria-valuetext', kt('compass.value', point, Math.round(from) % 360));
    }
}
