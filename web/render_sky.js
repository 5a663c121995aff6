// Sky, light, fog and rain, calm or in the storm's look (web/storm_fx.js): the uniforms
// every pass shares, the sky and ground behind the scene (sky.frag) and the rain streaks
// over the frame (rain.vert/.frag, client/render/render_rain.c). Renderer (web/render_gl.js)
// takes these methods as its own.
import { rainUniforms } from './storm_fx.js';
import { invert } from './view_math.js';
import { RU } from './render_data.js';
import { FOG_MIN_M, fogForScene } from './lod_policy.js';

// The calm fog distance [m] of a scene of instance rows [species, x, y, ...]
// (web/lod_policy.js fogForScene over the trees' bounding box in x, y).
export function sceneFog_m(rows) {
    if (!rows.length) return FOG_MIN_M;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (const r of rows) {
        x0 = Math.min(x0, r[1]);
        x1 = Math.max(x1, r[1]);
        y0 = Math.min(y0, r[2]);
        y1 = Math.max(y1, r[2]);
    }
    return fogForScene([x0, y0], [x1, y1]);
}

export class RendererSky {
    // Program p in use with what every pass reads: view, eye, sun, sky, ground, fog, storm,
    // shader time t and wind.
    setCommon(p, t) {
        const gl = this.gl, u = p.u, fx = this.fx;
        gl.useProgram(p.id);
        gl.uniformMatrix4fv(u.u_viewproj, false, this.viewproj);
        gl.uniform3fv(u.u_eye, this.eye);
        const sun = [0.45, -0.35, 0.62], l = Math.hypot(...sun);
        gl.uniform3fv(u.u_sun_dir, sun.map((x) => x / l));
        gl.uniform3fv(u.u_sun_col, fx.sun_col);
        gl.uniform3fv(u.u_sky_zenith, fx.sky_zenith);
        gl.uniform3fv(u.u_sky_horizon, fx.sky_horizon);
        gl.uniform3fv(u.u_ground_col, fx.ground_col);
        const fog_m = this.fog_m || FOG_MIN_M; // the scene's calm fog (sceneFog_m)
        gl.uniform1f(u.u_fog_dist, fog_m * fx.fog_scale);
        // the storm fog is the calm one times fog_scale; up to the subject it is thinned
        // towards the calm fog (common.glsl fog_apply)
        if (u.u_storm) gl.uniform4f(u.u_storm, fx.wet, this.subject_m, fog_m, fx.subject_clear);
        gl.uniform1f(u.u_time, t);
        gl.uniform3fv(u.u_wind_origin, [0, 0, 0]);
        gl.uniform3fv(u.u_wind_extent, [0, 0, 0]);
        gl.uniform3fv(u.u_wind_uniform, this.windUniform || [0, 0, 0]);
        this.bindTex(RU.WIND, gl.TEXTURE_3D, this.wind);
    }

    // The sky and ground (sky.frag): one full-screen triangle behind the scene.
    drawSky(t) {
        const gl = this.gl;
        gl.depthFunc(gl.ALWAYS);
        this.setCommon(this.p.sky, t);
        gl.uniformMatrix4fv(this.p.sky.u.u_inv_viewproj, false, invert(this.viewproj));
        gl.bindVertexArray(this.vaoEmpty);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        gl.depthFunc(gl.LESS);
    }

    // Rain streaks and spray over the frame (client/render/render_rain.c): one full-screen
    // triangle of rain.frag, blended, after the scene.
    drawRain(t) {
        const gl = this.gl, fx = this.fx, p = this.p.rain;
        if (fx.rain_layers <= 0 || !(fx.rain > 0)) return;
        const v = this.view || new Float32Array(16); // no view matrix: streaks fall straight
        let subject = null;
        if (this.subject_m > 0) {
            // the subject lies subject_m along the view axis: -(row 2 of the view matrix)
            subject = [0, 1, 2].map((k) => this.eye[k] - this.subject_m * v[4 * k + 2]);
        }
        const ru = rainUniforms(fx, v, this.viewproj, subject, this.canvas.width, this.canvas.height);
        this.setCommon(p, t);
        gl.uniform4fv(p.u.u_rain, ru.rain);
        gl.uniform2fv(p.u.u_spray, ru.spray);
        gl.uniform4fv(p.u.u_rain_clear, ru.clear);
        gl.uniformMatrix4fv(p.u.u_inv_viewproj, false, invert(this.viewproj));
        gl.disable(gl.DEPTH_TEST);
        gl.depthMask(false);
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
        gl.bindVertexArray(this.vaoEmpty);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        gl.disable(gl.BLEND);
        gl.depthMask(true);
        gl.enable(gl.DEPTH_TEST);
    }
}
