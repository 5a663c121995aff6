// The frame-time governor of the page, gale-client's (client/render/governor.c; the table of
// tests/web/test_governor_js.mjs holds the two to each other): each step down draws FULL's
// and THIN's distances closer by GOVERNOR_LOD_FACTOR and the scene's resolution lower by
// GOVERNOR_RES_STEP (to GOVERNOR_RES_MIN); it steps down while the smoothed frame time is
// well over its target, back up while well under, and waits longer before a step up than
// a step down, so it settles rather than flip-flops. A software renderer (SwiftShader,
// llvmpipe) starts a few steps down.
export const GOVERNOR_MAX_STEP = 6;
export const GOVERNOR_SOFTWARE_STEP = 3;
export const GOVERNOR_LOD_FACTOR = 0.75;
export const GOVERNOR_RES_STEP = 0.1;
export const GOVERNOR_RES_MIN = 0.5;
export const GOVERNOR_DOWN_OVER = 1.15;
export const GOVERNOR_UP_UNDER = 0.6;
export const GOVERNOR_DOWN_HOLD_S = 1.0;
export const GOVERNOR_UP_HOLD_S = 4.0;
export const GOVERNOR_SMOOTH = 0.1;
export const GOVERNOR_MIN_FRAMES = 8;

export class Governor {
    // target_ms 0 turns it off (the step stays 0); software: start at GOVERNOR_SOFTWARE_STEP.
    constructor(target_ms, software, now_s) {
        this.target_ms = target_ms > 0 ? target_ms : 0;
        this.step = this.target_ms > 0 && software ? GOVERNOR_SOFTWARE_STEP : 0;
        this.smooth_ms = 0;
        this.frames = 0;
        this.hold_until_s = now_s + GOVERNOR_DOWN_HOLD_S;
        this.changes = 0;
    }

    // Takes one frame's time; true when the step changed.
    frame(frame_ms, now_s) {
        if (!(this.target_ms > 0) || !(frame_ms >= 0) || !Number.isFinite(frame_ms)) return false;
        this.smooth_ms = this.smooth_ms > 0 ? (1 - GOVERNOR_SMOOTH) * this.smooth_ms + GOVERNOR_SMOOTH * frame_ms : frame_ms;
        this.frames++;
        if (now_s < this.hold_until_s || this.frames < GOVERNOR_MIN_FRAMES) return false;
        if (this.smooth_ms > GOVERNOR_DOWN_OVER * this.target_ms && this.step < GOVERNOR_MAX_STEP) {
            this.step++;
            this.hold_until_s = now_s + GOVERNOR_DOWN_HOLD_S;
        } else if (this.smooth_ms < GOVERNOR_UP_UNDER * this.target_ms && this.step > 0) {
            this.step--;
            this.hold_until_s = now_s + GOVERNOR_UP_HOLD_S;
        } else {
            return false;
        }
        // the frames before the change say nothing of the new step's cost
        this.smooth_ms = 0;
        this.frames = 0;
        this.changes++;
        return true;
    }

    // The scale of FULL's and THIN's distances at this step: GOVERNOR_LOD_FACTOR^step.
    lodScale() {
        return Math.fround(Math.pow(GOVERNOR_LOD_FACTOR, this.step));
    }

    // The scene's resolution scale at this step.
    resScale() {
        return Math.max(GOVERNOR_RES_MIN, 1 - GOVERNOR_RES_STEP * this.step);
    }
}

// Whether a renderer string names a software renderer.
export function softwareRenderer(name) {
    return /llvmpipe|softpipe|SwiftShader/.test(name || '');
}
