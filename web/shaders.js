// The shaders of shaders/, as served by gale-server at /shaders/, compiled for WebGL2:
// the same sources the native client compiles, each stage given its own preamble here
// ("#version 300 es" and default precisions) where client/render/render_shader.c gives
// "#version 330 core". common.glsl reads GL_ES to pick 2D textures for buffer data.
export const PREAMBLE = '#version 300 es\nprecision highp float;\nprecision highp int;\n' +
    'precision highp sampler2D;\nprecision highp sampler3D;\n';

const cache = new Map();
async function text(base, name) {
    const url = `${base}/shaders/${name}`;
    if (!cache.has(url)) {
        cache.set(url, fetch(url, { cache: 'no-store' }).then((r) => {
            if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
            return r.text();
        }));
    }
    return cache.get(url);
}

function compile(gl, stage, name, common, body, defines) {
    const head = PREAMBLE + (stage === gl.VERTEX_SHADER ? '#define GALE_VERT 1\n' : '#define GALE_FRAG 1\n') + defines;
    const sh = gl.createShader(stage);
    gl.shaderSource(sh, head + common + '\n#line 1\n' + body);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) {
        const log = gl.getShaderInfoLog(sh);
        gl.deleteShader(sh);
        throw new Error(`${name.includes('/') ? name : `shaders/${name}`} (after common.glsl): ${log}`);
    }
    return sh;
}

// Program `name` from shaders/name.vert and .frag; uniform locations in prog.u. defines:
// lines after the preamble (e.g. '#define GALE_Q_RING 1\n', shaders/skel.frag). vert: a
// vertex stage of the page's own in place of shaders/name.vert, its name and source
// (web/imp_shader.js: the impostor's sway before shaders/bill.frag).
export async function loadProgram(gl, name, base = '', defines = '', vert = null) {
    const [common, vs, fs] = await Promise.all([text(base, 'common.glsl'), vert ? vert.source : text(base, `${name}.vert`), text(base, `${name}.frag`)]);
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, vert ? vert.name : `${name}.vert`, common, vs, defines));
    gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, `${name}.frag`, common, fs, defines));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
        throw new Error(`shaders/${name}: link: ${gl.getProgramInfoLog(p)}`);
    }
    const u = {};
    const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; i++) {
        const info = gl.getActiveUniform(p, i);
        const key = info.name.replace(/\[0\]$/, '');
        u[key] = gl.getUniformLocation(p, info.name);
    }
    return { id: p, u, name };
}

// Every program of shaders/ (the list the native client links, client/render/render.c).
export const PROGRAMS = ['skel', 'tree', 'leaf', 'fall', 'sky', 'bill', 'house', 'rain', 'plate', 'stump'];
