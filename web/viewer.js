// The viewer page (/): the whole scene, an orbit camera, the HUD. ?max_trees=N draws only
// the N trees nearest the camera (a slow GPU; the benchmark), all are still decoded;
// ?hold_trees=N (every page's, web/app.js) holds at most N trees: a reduced view past it.
// ?camera=street|garden|roof|aerial starts the orbit at that preset of the kiosk's
// (web/attract.js cameraPreset, gale-client's --camera), so a benchmark or a screenshot of
// the page frames what gale-client's does.
import { App } from './app.js';
import { CAMERA_PRESETS, cameraPreset } from './attract.js';

const q = new URLSearchParams(location.search);
let preset = CAMERA_PRESETS.indexOf(q.get('camera') || '');
const app = new App({
    role: 'viewer',
    maxTrees: Number(q.get('max_trees')) || 0,
    onWelcome(w) {
        // the tour (the last name) is the kiosk's attract loop, not a place to start
        if (preset < 0 || preset >= CAMERA_PRESETS.length - 1) return;
        Object.assign(app.cam, cameraPreset(preset, w.instances, w.species.map((s) => s.name)));
        preset = -1; // the first welcome's: a reconnect keeps where the visitor has turned it
    },
});
app.start();
