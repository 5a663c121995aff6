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
import { CELL_TREES, CELL_MIN_M } from './lod_policy.js';

const MAX_CELLS = 1 << 16; // the grid's cells at most (a cell test is cheap; 65,536 are not)

// The six planes (a, b, c, d; inside where a x + b y + c z + d >= 0) of the frustum of a
// column-major view-projection matrix (Gribb and Hartmann): left, right, bottom, top,
// near, far.
export function frustumPlanes(m, out = new Float64Array(24)) {
    const row = (i) => [m[i], m[4 + i], m[8 + i], m[12 + i]];
    const r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const planes = [[r3, r0, 1], [r3, r0, -1], [r3, r1, 1], [r3, r1, -1], [r3, r2, 1], [r3, r2, -1]];
    planes.forEach(([a, b, s], p) => {
        const v = [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]];
        const n = Math.hypot(v[0], v[1], v[2]) || 1;
        for (let k = 0; k < 4; k++) out[4 * p + k] = v[k] / n;
    });
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

export class CellGrid {
    // rows: the welcome's instances [species, x, y, z, yaw, scale]; height_m[t]: tree t's height.
    constructor(rows, height_m) {
        const n = rows.length;
        this.n = n;
        this.x = new Float32Array(n);
        this.y = new Float32Array(n);
        this.z = new Float32Array(n);
        this.h = new Float32Array(n);
        let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity, hmax = 0;
        for (let t = 0; t < n; t++) {
            const r = rows[t];
            this.x[t] = r[1];
            this.y[t] = r[2];
            this.z[t] = r[3];
            this.h[t] = height_m[t] > 0 ? height_m[t] : 0;
            x0 = Math.min(x0, r[1]); x1 = Math.max(x1, r[1]);
            y0 = Math.min(y0, r[2]); y1 = Math.max(y1, r[2]);
            hmax = Math.max(hmax, this.h[t]);
        }
        if (!n) x0 = y0 = x1 = y1 = 0;
        this.hmax_m = hmax;
        // about CELL_TREES trees a cell over the trees' extent
        const w = x1 - x0, d = y1 - y0;
        let cell = Math.max(CELL_MIN_M, Math.sqrt(Math.max(w * d, 1) * CELL_TREES / Math.max(n, 1)));
        while (Math.ceil(w / cell + 1e-9) * Math.ceil(d / cell + 1e-9) > MAX_CELLS) cell *= 1.25;
        const nx = Math.max(1, Math.ceil(w / cell + 1e-9)), ny = Math.max(1, Math.ceil(d / cell + 1e-9));
        Object.assign(this, { cell_m: cell, nx, ny, x0, y0 });
        // counting sort of the trees by cell: start[c]..start[c + 1] in trees
        const cellOf = new Int32Array(n), start = new Int32Array(nx * ny + 1);
        const zlo = new Float32Array(nx * ny).fill(Infinity), zhi = new Float32Array(nx * ny).fill(-Infinity);
        for (let t = 0; t < n; t++) {
            const cx = Math.min(nx - 1, Math.floor((this.x[t] - x0) / cell)), cy = Math.min(ny - 1, Math.floor((this.y[t] - y0) / cell));
            const c = cy * nx + cx;
            cellOf[t] = c;
            start[c + 1]++;
            zlo[c] = Math.min(zlo[c], this.z[t]);
            zhi[c] = Math.max(zhi[c], this.z[t]);
        }
        for (let c = 0; c < nx * ny; c++) start[c + 1] += start[c];
        const fill = start.slice(0, nx * ny), trees = new Int32Array(n);
        for (let t = 0; t < n; t++) trees[fill[cellOf[t]]++] = t;
        this.start = start;
        this.trees = trees;
        // each cell's box [x0, y0, z0, x1, y1, z1]: its extent and its trees' bases, the
        // tallest tree's height about them
        this.box = new Float32Array(nx * ny * 6);
        for (let c = 0; c < nx * ny; c++) {
            const cx = c % nx, cy = (c - cx) / nx, b = 6 * c;
            this.box[b] = x0 + cx * cell - hmax;
            this.box[b + 1] = y0 + cy * cell - hmax;
            this.box[b + 2] = (start[c + 1] > start[c] ? zlo[c] : 0) - hmax;
            this.box[b + 3] = x0 + (cx + 1) * cell + hmax;
            this.box[b + 4] = y0 + (cy + 1) * cell + hmax;
            this.box[b + 5] = (start[c + 1] > start[c] ? zhi[c] : 0) + hmax;
        }
        this.out = { n: 0, trees: new Int32Array(n), dist: new Float32Array(n), cells_tested: 0, cells_in_view: 0 };
    }

    // The trees in view of view-projection viewproj from eye within far_m, into this.out
    // (trees[0..n), their distances dist[0..n)), in cell order; reused each call.
    gather(viewproj, eye, far_m) {
        const pl = this.planes = frustumPlanes(viewproj, this.planes);
        const o = this.out, B = this.box, ex = eye[0], ey = eye[1], ez = eye[2], far2 = far_m * far_m;
        let n = 0, tested = 0, seen = 0;
        for (let c = 0; c < this.nx * this.ny; c++) {
            const a = this.start[c], e = this.start[c + 1];
            if (a === e) continue;
            tested++;
            const b = 6 * c;
            // the box's nearest point to the eye beyond far_m: none of its trees is near enough
            const dx = Math.max(B[b] - ex, 0, ex - B[b + 3]), dy = Math.max(B[b + 1] - ey, 0, ey - B[b + 4]), dz = Math.max(B[b + 2] - ez, 0, ez - B[b + 5]);
            if (dx * dx + dy * dy + dz * dz > far2) continue;
            const k = boxInFrustum(pl, B[b], B[b + 1], B[b + 2], B[b + 3], B[b + 4], B[b + 5]);
            if (k < 0) continue;
            seen++;
            for (let i = a; i < e; i++) {
                const t = this.trees[i], x = this.x[t], y = this.y[t], z = this.z[t], h = this.h[t];
                const mx = x - ex, my = y - ey, mz = z + 0.5 * h - ez, d2 = mx * mx + my * my + mz * mz;
                if (d2 > far2) continue;
                if (k === 0 && boxInFrustum(pl, x - h, y - h, z - h, x + h, y + h, z + h) < 0) continue;
                o.trees[n] = t;
                o.dist[n++] = Math.sqrt(d2);
            }
        }
        o.n = n;
        o.cells_tested = tested;
        o.cells_in_view = seen;
        return o;
    }
}
