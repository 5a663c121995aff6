// The viewer page (/): the whole scene, an orbit camera, the HUD. ?max_trees=N draws only
// the N trees nearest the camera (a slow GPU; the benchmark), all are still decoded;
// ?hold_trees=N (every page's, web/app.js) holds at most N trees: a reduced view past it.
import { App } from './app.js';

const q = new URLSearchParams(location.search);
new App({ role: 'viewer', maxTrees: Number(q.get('max_trees')) || 0 }).start();
