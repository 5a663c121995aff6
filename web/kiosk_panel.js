// The kiosk panel's scenario buttons and replay row (client/kiosk/kiosk_ui.c): a button per
// welcome scenario in two groups, steady winds and storm replays, each a grid of as many
// columns as its width holds and a fixed number of rows, paged when the list is longer (a
// storm library of a few dozen replays stays usable: the last cell of a page turns the
// pages, and the running scenario's page comes up by itself); the running one lit as
// WEATHER names it (web/kiosk_scale.js runningIndex); the replay controls only while a
// replay runs, with where the storm is against its landfall.
import { REPLAY_SPEEDS } from './kiosk_scale.js';
import { kt, scenarioText } from './kiosk_text.js';

const MIN_BUTTON_REM = 7.4; // two lines of "Category 1 (steady)" fit
const GAP_REM = 0.4;

export class ScenarioGroup {
    // box: the group's element, holding a title and an empty .grid; rows(): how many rows
    // it shows now; onPick(scenario)
    constructor(box, rows, onPick) {
        this.box = box;
        this.grid = box.querySelector('.grid');
        this.rows = rows;
        this.onPick = onPick;
        this.items = []; // { sc, index }: index into the welcome's list
        this.page = 0;
        this.lit = -1;
    }

    set(items) {
        this.items = items;
        this.page = 0;
        this.layout();
    }

    // the buttons again in the page's language, on the page shown
    relabel() {
        this.layout();
    }

    // columns from the grid's width; a page of cols × rows cells, the last one the pager's
    // when the list needs more than one page
    perPage() {
        const rem = parseFloat(getComputedStyle(document.documentElement).fontSize) || 16;
        const w = this.grid.clientWidth || this.box.clientWidth;
        const cols = Math.max(1, Math.floor((w + GAP_REM * rem) / ((MIN_BUTTON_REM + GAP_REM) * rem)));
        this.cols = cols;
        const cells = cols * this.rows();
        return this.items.length > cells ? Math.max(1, cells - 1) : cells;
    }

    pages() {
        return Math.max(1, Math.ceil(this.items.length / this.perPage()));
    }

    layout() {
        this.box.hidden = this.items.length === 0;
        const per = this.perPage(), pages = Math.max(1, Math.ceil(this.items.length / per));
        this.page = Math.min(Math.max(this.page, 0), pages - 1);
        this.grid.style.gridTemplateColumns = `repeat(${this.cols}, minmax(0, 1fr))`;
        this.grid.textContent = '';
        for (const { sc, index } of this.items.slice(this.page * per, (this.page + 1) * per)) {
            const b = document.createElement('button');
            b.type = 'button';
            b.className = 'scen';
            b.textContent = scenarioText(sc.title || sc.name);
            b.dataset.name = sc.name;
            b.dataset.index = String(index);
            b.setAttribute('aria-pressed', String(index === this.lit));
            b.addEventListener('click', () => this.onPick(sc));
            this.grid.append(b);
        }
        if (pages > 1) {
            const cell = document.createElement('div');
            cell.className = 'pager';
            const prev = document.createElement('button'), next = document.createElement('button');
            const at = document.createElement('span');
            prev.type = next.type = 'button';
            prev.className = 'page-prev';
            next.className = 'page-next';
            prev.textContent = '◀';
            next.textContent = '▶';
            prev.setAttribute('aria-label', kt('page.prev'));
            next.setAttribute('aria-label', kt('page.next'));
            at.textContent = kt('page.of', this.page + 1, pages);
            at.className = 'page-at';
            prev.addEventListener('click', () => { this.page = (this.page + pages - 1) % pages; this.layout(); });
            next.addEventListener('click', () => { this.page = (this.page + 1) % pages; this.layout(); });
            cell.append(prev, at, next);
            this.grid.append(cell);
        }
    }

    // the welcome index running now (-1 none): lit, and its page shown
    light(index) {
        if (index === this.lit) return;
        this.lit = index;
        const k = this.items.findIndex((it) => it.index === index);
        if (k >= 0) {
            const page = Math.floor(k / this.perPage());
            if (page !== this.page) {
                this.page = page;
                this.layout();
                return;
            }
        }
        for (const b of this.grid.querySelectorAll('button.scen')) b.setAttribute('aria-pressed', String(Number(b.dataset.index) === index));
    }
}

const pad2 = (n) => String(n).padStart(2, '0');
const mmss = (s) => `${Math.trunc(s / 60)}:${pad2(Math.trunc(s) % 60)}`;

// "1 h 20 min" of minutes
function span(min) {
    const m = Math.round(Math.abs(min));
    return m >= 60 ? kt('replay.hm', Math.floor(m / 60), pad2(m % 60)) : kt('replay.min', m);
}

// Where a replay's storm is (WEATHER storm_min: storm time from the track's reference,
// landfall in the shipped replays) and how far the replay is (replay_pos_s, replay_len_s).
export function replayWhere(w) {
    const m = w.storm_min;
    const at = Math.abs(m) < 0.5 ? kt('replay.at') : m < 0 ? kt('replay.before', span(m)) : kt('replay.after', span(m));
    const len = w.replay_len_s;
    const pos = w.flags & 4 ? kt('replay.ended')
        : len > 0 ? kt('replay.pos', mmss(w.replay_pos_s), mmss(len)) : kt('replay.loop', mmss(w.replay_pos_s));
    return { at, pos, share: len > 0 ? Math.min(Math.max(w.replay_pos_s / len, 0), 1) : null };
}

// the ×N buttons' speeds, for kiosk.html's row
export { REPLAY_SPEEDS };
