// The trees bucketed into a 2D grid of cells once per welcome, and each frame's trees in
// view gathered cell by cell: a cell's box is tested against the frustum, and only the
// trees of the cells not wholly outside it are looked at, so a frame never walks (nor
// sorts) every tree of a large scene.
//
// A tree's box is the cube of half-side h about its base (h: its height, species height ×
// scale), which holds the tree however it leans, lies or falls; a cell's box is the
// cell's extent widened by the tallest tree's height on every side, which holds every
// box of its trees. A tree is in view when its box is not wholly outside any one of the
// frustum's planes and its middle (base raised by h / 2) is within far_m of the eye; its
// distance is that middle's from the eye.
//
// The trees' positions, heights and species are kept in arrays of the grid's own order (a
// tree's place: by species, within a species cell by cell, then by tree), so that a frame
// reads memory in order, and the caller may keep its per-tree state by place too. A cell
// wholly in view whose trees all lie within a band of distance the caller names (past
// THIN's reach, inside the impostors': web/lod_select.js) may be listed whole, by its
// places, never tree by tree.
import { CELL_TREES, CELL_MIN_M } from './lod_policy.js';

const MAX_CELLS = 1 << 16; // the grid's cells at most (a cell test is cheap; 65,536 are not)
// A cell's nearest and farthest distances are widened by this share so that they hold
// its trees' distances as the per-tree pass rounds them (to float32: 6e-8 of them).
const WHOLE_MARGIN = 1e-6;

// The six planes (a, b, c, d; inside where a x + b y + c z + d >= 0) of the frustum of a
// column-major view-projection matrix (Gribb and Hartmann): left, right, bottom, top,
// near, far.
export function frustumPlanes(m, out = new Float64Array(24)) {
    for (let p = 0; p < 6; p++) {
        const r = p >> 1, s = p & 1 ? -1 : 1;
        const a = m[3] + s * m[r], b = m[7] + s * m[4 + r], c = m[11] + s * m[8 + r], d = m[15] + s * m[12 + r];
        const n = Math.hypot(a, b, c) || 1;
        out[4 * p] = a / n;
        out[4 * p + 1] = b / n;
        out[4 * p + 2] = c / n;
        out[4 * p + 3] = d / n;
    }
    return out;
}

// -1: box [x0, y0, z0]..[x1, y1, z1] wholly outside one plane; 1: wholly inside all; 0: across.
export function boxInFrustum(pl, x0, y0, z0, x1, y1, z1) {
    let inside = 1;
    for (let p = 0; p < 24; p += 4) {
        const a = pl[p], b = pl[p + 1], c = pl[p + 2], d = pl[p + 3];
        // the corner farthest along the plane's normal, and the nearest
        const far = a * (a >= 0 ? x1 : x0) + b * (b >= 0 ? y1 : y0) + c * (c >= 0 ? z1 : z0) + d;
        if (far < 0) return -1;
        const near = a * (a >= 0 ? x0 : x1) + b * (b >= 0 ? y0 : y1) + c * (c >= 0 ? z0 : z1) + d;
        if (near < 0) inside = 0;
    }
    return inside;
}

// -1: box B[b..b + 6) wholly outside one of the planes; else a mask of the planes it lies
// across (0: wholly inside all), so that its trees are tested against those alone.
function cellPlanes(pl, B, b) {
    const x0 = B[b], y0 = B[b + 1], z0 = B[b + 2], x1 = B[b + 3], y1 = B[b + 4], z1 = B[b + 5];
    let across = 0;
    for (let p = 0; p < 6; p++) {
        const a = pl[4 * p], bb = pl[4 * p + 1], c = pl[4 * p + 2], d = pl[4 * p + 3];
        const far = a * (a >= 0 ? x1 : x0) + bb * (bb >= 0 ? y1 : y0) + c * (c >= 0 ? z1 : z0) + d;
        if (far < 0) return -1;
        const near = a * (a >= 0 ? x0 : x1) + bb * (bb >= 0 ? y0 : y1) + c * (c >= 0 ? z0 : z1) + d;
        if (near < 0) across |= 1 << p;
    }
    return across;
}

export class CellGrid {
    // rows: the welcome's instances [species, x, y, z, yaw, scale]; height_m[t]: tree t's height.
    constructor(rows, height_m) {
        const n = rows.length;
        this.n = n;
        let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity, hmax = 0, ns = 1;
        for (let t = 0; t < n; t++) {
            const r = rows[t], h = height_m[t] > 0 ? height_m[t] : 0;
            x0 = Math.min(x0, r[1]); x1 = Math.max(x1, r[1]);
            y0 = Math.min(y0, r[2]); y1 = Math.max(y1, r[2]);
            hmax = Math.max(hmax, Math.fround(h));
            ns = Math.max(ns, r[0] + 1);
        }
        if (!n) x0 = y0 = x1 = y1 = 0;
        this.hmax_m = hmax;
        this.ns = ns; // species ids below it: the places of cell c's species s are run[s nc + c] .. run[s nc + c + 1]
        // about CELL_TREES trees a cell over the trees' extent
        const w = x1 - x0, d = y1 - y0;
        let cell = Math.max(CELL_MIN_M, Math.sqrt(Math.max(w * d, 1) * CELL_TREES / Math.max(n, 1)));
        while (Math.ceil(w / cell + 1e-9) * Math.ceil(d / cell + 1e-9) > MAX_CELLS) cell *= 1.25;
        const nx = Math.max(1, Math.ceil(w / cell + 1e-9)), ny = Math.max(1, Math.ceil(d / cell + 1e-9));
        Object.assign(this, { cell_m: cell, nx, ny, x0, y0 });
        const nc = nx * ny;
        this.nc = nc;
        // counting sort of the trees by species, cell and tree: a species' trees in one run
        // of places, cell by cell, so that the trees of adjacent cells of one species are
        // adjacent too
        const keyOf = new Int32Array(n), run = new Int32Array(ns * nc + 1);
        for (let t = 0; t < n; t++) {
            const r = rows[t];
            const cx = Math.min(nx - 1, Math.floor((Math.fround(r[1]) - x0) / cell)), cy = Math.min(ny - 1, Math.floor((Math.fround(r[2]) - y0) / cell));
            keyOf[t] = r[0] * nc + cy * nx + cx;
            run[keyOf[t] + 1]++;
        }
        for (let k = 0; k < ns * nc; k++) run[k + 1] += run[k];
        const fill = run.slice(0, ns * nc);
        this.run = run;
        this.trees = new Int32Array(n); // the tree at each place
        this.px = new Float32Array(n); // its base [m], by place
        this.py = new Float32Array(n);
        this.pz = new Float32Array(n);
        this.ph = new Float32Array(n); // its height [m]
        this.species = new Uint8Array(n);
        this.cellOf = new Int32Array(n); // its cell
        for (let t = 0; t < n; t++) {
            const r = rows[t], at = fill[keyOf[t]]++;
            this.trees[at] = t;
            this.px[at] = r[1];
            this.py[at] = r[2];
            this.pz[at] = r[3];
            this.ph[at] = height_m[t] > 0 ? height_m[t] : 0;
            this.species[at] = r[0];
        }
        // each cell's box [x0, y0, z0, x1, y1, z1]: its extent and its trees' bases, the
        // tallest tree's height about them; the box of its trees' middles; its trees, and
        // the species among them (bit s, the first 31)
        this.box = new Float64Array(nc * 6);
        this.mid = new Float64Array(nc * 6);
        this.count = new Int32Array(nc);
        this.mask = new Int32Array(nc);
        const M = this.mid;
        for (let c = 0; c < nc; c++) {
            const cx = c % nx, cy = (c - cx) / nx, b = 6 * c;
            let zlo = Infinity, zhi = -Infinity, k = 0;
            M[b] = M[b + 1] = M[b + 2] = Infinity;
            M[b + 3] = M[b + 4] = M[b + 5] = -Infinity;
            for (let s = 0; s < ns; s++) {
                const a = run[s * nc + c], e = run[s * nc + c + 1];
                if (e > a && s < 31) this.mask[c] |= 1 << s;
                k += e - a;
                this.cellOf.fill(c, a, e);
                for (let i = a; i < e; i++) {
                    const z = this.pz[i], mz = z + 0.5 * this.ph[i];
                    zlo = Math.min(zlo, z);
                    zhi = Math.max(zhi, z);
                    M[b] = Math.min(M[b], this.px[i]); M[b + 3] = Math.max(M[b + 3], this.px[i]);
                    M[b + 1] = Math.min(M[b + 1], this.py[i]); M[b + 4] = Math.max(M[b + 4], this.py[i]);
                    M[b + 2] = Math.min(M[b + 2], mz); M[b + 5] = Math.max(M[b + 5], mz);
                }
            }
            this.count[c] = k;
            this.box[b] = x0 + cx * cell - hmax;
            this.box[b + 1] = y0 + cy * cell - hmax;
            this.box[b + 2] = (k ? zlo : 0) - hmax;
            this.box[b + 3] = x0 + (cx + 1) * cell + hmax;
            this.box[b + 4] = y0 + (cy + 1) * cell + hmax;
            this.box[b + 5] = (k ? zhi : 0) + hmax;
        }
        this.planes = new Float64Array(24);
        this.cut = new Float64Array(24); // the planes a cell lies across
        this.out = {
            n: 0, trees: new Int32Array(n), at: new Int32Array(n), dist: new Float32Array(n), cells_tested: 0, cells_in_view: 0,
            // the cells listed whole: their cells, where in the list of trees each falls
            // (before tree `before[k]`), their nearest distance [m], their trees in all; the
            // band they were listed in; the places (run, ns, nc, cellOf: this grid's)
            whole: { n: 0, cell: new Int32Array(nc), before: new Int32Array(nc), near_m: new Float64Array(nc), trees: 0, band: null, run, ns, nc, cellOf: this.cellOf },
        };
    }

    // The trees in view of view-projection viewproj from eye within far_m, into this.out
    // (trees[0..n), their places at[0..n) and distances dist[0..n)), in cell order;
    // reused each call. whole (null: none; web/lod_select.js wholeBand) lists whole a cell
    // wholly in view, no tree of it of a species with drawn[s] 0 (a lying tree is listed
    // as a standing one: its impostor lies, web/render_list.js impFall), whose trees'
    // middles all lie at least near_m (the near edge of the bin of width bin_m its
    // nearest distance falls in) and less than far_m from the eye: into out.whole, none
    // of its trees into trees[].
    gather(viewproj, eye, far_m, whole = null) {
        const pl = frustumPlanes(viewproj, this.planes), cut = this.cut;
        const o = this.out, W = o.whole, B = this.box, M = this.mid, ex = eye[0], ey = eye[1], ez = eye[2], far2 = far_m * far_m;
        const run = this.run, ns = this.ns, nc = this.nc, px = this.px, py = this.py, pz = this.pz, ph = this.ph, trees = this.trees;
        const oTrees = o.trees, oAt = o.at, oDist = o.dist, count = this.count, mask = this.mask;
        // the species not drawn, as the cells' masks hold them
        let hidden = 0;
        if (whole) for (let s = 0; s < ns && s < 31; s++) if (!whole.drawn[s]) hidden |= 1 << s;
        let n = 0, tested = 0, seen = 0, nw = 0, wt = 0;
        for (let c = 0; c < nc; c++) {
            if (!count[c]) continue;
            tested++;
            const b = 6 * c;
            // the box's nearest point to the eye beyond far_m: none of its trees is near enough
            const dx = Math.max(B[b] - ex, 0, ex - B[b + 3]), dy = Math.max(B[b + 1] - ey, 0, ey - B[b + 4]), dz = Math.max(B[b + 2] - ez, 0, ez - B[b + 5]);
            if (dx * dx + dy * dy + dz * dz > far2) continue;
            const across = cellPlanes(pl, B, b);
            if (across < 0) continue;
            seen++;
            if (across === 0 && whole && (mask[c] & hidden) === 0 && (ns <= 31 || this.listable(c, whole.drawn))) {
                // the nearest and farthest of its trees' middles
                const mx = Math.max(M[b] - ex, 0, ex - M[b + 3]), my = Math.max(M[b + 1] - ey, 0, ey - M[b + 4]), mz = Math.max(M[b + 2] - ez, 0, ez - M[b + 5]);
                const fx = Math.max(ex - M[b], M[b + 3] - ex), fy = Math.max(ey - M[b + 1], M[b + 4] - ey), fz = Math.max(ez - M[b + 2], M[b + 5] - ez);
                const near = Math.sqrt(mx * mx + my * my + mz * mz) * (1 - WHOLE_MARGIN), far = Math.sqrt(fx * fx + fy * fy + fz * fz) * (1 + WHOLE_MARGIN);
                if (far < whole.far_m && far <= far_m && Math.floor(near / whole.bin_m) * whole.bin_m >= whole.near_m) {
                    W.cell[nw] = c;
                    W.before[nw] = n;
                    W.near_m[nw++] = near;
                    wt += count[c];
                    continue;
                }
            }
            // the planes the cell lies across, for its trees
            let m = 0;
            for (let p = 0; p < 6; p++) {
                if (!(across & (1 << p))) continue;
                for (let k = 0; k < 4; k++) cut[4 * m + k] = pl[4 * p + k];
                m++;
            }
            for (let r = c; r < ns * nc; r += nc) {
                for (let i = run[r], e = run[r + 1]; i < e; i++) {
                    const x = px[i], y = py[i], z = pz[i], h = ph[i];
                    const mx = x - ex, my = y - ey, mz = z + 0.5 * h - ez, d2 = mx * mx + my * my + mz * mz;
                    if (d2 > far2) continue;
                    let out = false;
                    for (let p = 0; p < 4 * m; p += 4) {
                        // the box's corner farthest along the plane's normal (boxInFrustum)
                        const A = cut[p], Bp = cut[p + 1], C = cut[p + 2];
                        if (A * (A >= 0 ? x + h : x - h) + Bp * (Bp >= 0 ? y + h : y - h) + C * (C >= 0 ? z + h : z - h) + cut[p + 3] < 0) {
                            out = true;
                            break;
                        }
                    }
                    if (out) continue;
                    oTrees[n] = trees[i];
                    oAt[n] = i;
                    oDist[n++] = Math.sqrt(d2);
                }
            }
        }
        o.n = n;
        o.cells_tested = tested;
        o.cells_in_view = seen;
        W.n = nw;
        W.trees = wt;
        W.band = whole;
        return o;
    }

    // Whether cell c holds trees of the drawn species alone (drawn[s]: 1 for a drawn one).
    listable(c, drawn) {
        const run = this.run, ns = this.ns, nc = this.nc;
        for (let s = 0; s < ns; s++) if (run[s * nc + c + 1] > run[s * nc + c] && !drawn[s]) return false;
        return true;
    }
}
