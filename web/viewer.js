// The viewer page (/): the whole scene, an orbit camera, the HUD.
import { App } from './app.js';

new App({ role: 'viewer' }).start();
