// The stream follows the camera: the frustum drawn turned into the server's view
// (PROTOCOL.md `view`, a cone from the eye: view_select), sent when the camera has moved
// enough, at most a few times a second, and once more when it stops, so that the server
// streams the trees in view (far ones with few modes) and not the whole scene.
import { invert } from './view_math.js';
import { VIEW_MIN_INTERVAL_S, VIEW_MOVE_M, VIEW_TURN_DEG, VIEW_SETTLE_S } from './lod_policy.js';

const FOV_MAX_DEG = 179; // PROTOCOL.md: fov_deg in [1, 179]
const FOV_MIN_DEG = 1;
const COORD_MAX_M = 1e6;

// The cone about a frustum (column-major view and view-projection matrices): its apex the
// eye (the view's origin), its axis the mean of the rays through the far corners, its
// half angle the widest of those rays from the axis, so that it holds the whole frustum
// (for a symmetric one, atan √(tan²(hfov / 2) + tan²(vfov / 2))). Returns { eye, dir, fov_deg }.
export function frustumCone(view, viewproj) {
    // the eye: −Rᵀ t of the rigid view
    const eye = [0, 1, 2].map((c) => -(view[4 * c] * view[12] + view[4 * c + 1] * view[13] + view[4 * c + 2] * view[14]));
    const inv = invert(viewproj), rays = [];
    for (const [x, y] of [[-1, -1], [1, -1], [-1, 1], [1, 1]]) {
        const p = [0, 1, 2, 3].map((r) => inv[r] * x + inv[4 + r] * y + inv[8 + r] + inv[12 + r]);
        const v = [p[0] / p[3] - eye[0], p[1] / p[3] - eye[1], p[2] / p[3] - eye[2]], l = Math.hypot(...v);
        rays.push(v.map((a) => a / l));
    }
    const sum = [0, 1, 2].map((k) => rays.reduce((a, r) => a + r[k], 0)), l = Math.hypot(...sum);
    const dir = sum.map((a) => a / l);
    let half = 0;
    for (const r of rays) half = Math.max(half, Math.acos(Math.min(1, r[0] * dir[0] + r[1] * dir[1] + r[2] * dir[2])));
    return { eye, dir, fov_deg: 2 * half * 180 / Math.PI };
}

// The view message's object for cone c with draw distance far_m and LOD distance lod_m,
// within PROTOCOL.md's bounds, numbers to a millimetre or a thousandth.
export function frustumView(c, far_m, lod_m) {
    const r = (x, k) => Math.round(x * k) / k;
    return { kind: 'frustum', eye: c.eye.map((x) => r(Math.max(-COORD_MAX_M, Math.min(COORD_MAX_M, x)), 1000)), dir: c.dir.map((x) => r(x, 1e6)),
        fov_deg: r(Math.max(FOV_MIN_DEG, Math.min(FOV_MAX_DEG, c.fov_deg + 0.01)), 100), far_m: r(Math.max(1, far_m), 10), lod_m: r(Math.max(0, lod_m), 10) };
}

// Sends a view (send(msg) -> whether it went) when the view moved by more than the
// policy's thresholds, at most once per VIEW_MIN_INTERVAL_S, and once VIEW_SETTLE_S after it
// last moved when what was sent differs at all from where it stopped.
export class ViewSender {
    constructor(send) {
        this.send = send;
        this.sent = null; // the view the server has (sent, or in the hello)
        this.sent_s = -Infinity;
        this.lastKey = null; // the view of the last update
        this.moved_s = -Infinity;
        this.count = 0;
    }

    // A new connection: the hello carried view (or none).
    reset(view) {
        this.sent = view || null;
        this.sent_s = -Infinity;
    }

    static differs(a, b, move_m, turn_deg) {
        if (!a || !b) return true;
        const d = Math.hypot(a.eye[0] - b.eye[0], a.eye[1] - b.eye[1], a.eye[2] - b.eye[2]);
        const cos = a.dir[0] * b.dir[0] + a.dir[1] * b.dir[1] + a.dir[2] * b.dir[2];
        return d > move_m || Math.acos(Math.min(1, cos)) * 180 / Math.PI > turn_deg || Math.abs(a.fov_deg - b.fov_deg) > turn_deg
            || Math.abs(a.far_m - b.far_m) > 0.2 * b.far_m || Math.abs(a.lod_m - b.lod_m) > 0.2 * b.lod_m;
    }

    // The view now (frustumView) at page time now_s; returns whether one was sent.
    update(view, now_s) {
        const key = JSON.stringify(view);
        if (key !== this.lastKey) this.moved_s = now_s;
        this.lastKey = key;
        const due = ViewSender.differs(view, this.sent, VIEW_MOVE_M, VIEW_TURN_DEG)
            || (now_s - this.moved_s >= VIEW_SETTLE_S && key !== JSON.stringify(this.sent));
        if (!due || now_s - this.sent_s < VIEW_MIN_INTERVAL_S) return false;
        if (!this.send({ type: 'view', view })) return false;
        this.sent = view;
        this.sent_s = now_s;
        this.count++;
        return true;
    }
}
