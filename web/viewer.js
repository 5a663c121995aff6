// The viewer page (/): the whole scene, an orbit camera, the HUD. ?max_trees=N draws only
// the N trees nearest the camera (a slow GPU; the benchmark), all are still decoded.
import { App } from './app.js';

const q = new URLSearchParams(location.search);
new App({ role: 'viewer', maxTrees: Number(q.get('max_trees')) || 0 }).start();
