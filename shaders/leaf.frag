// Leaf blade: procedural outline per species shape (alpha-tested), two-sided lighting
// with light through the blade, per-leaf colour variation, fog.
uniform vec3 u_leafcol;
uniform int u_shape;           // 0 broad leaf, 1 palm leaflet, 2 needle tuft
in vec3 v_wpos;
in vec3 v_nrm;
in vec2 v_uv;                  // s along the blade 0..1, t across -1..1
flat in float v_fade;
flat in float v_var;
flat in float v_ao;
out vec4 o_col;

bool inside(vec2 uv)
{
    float s = uv.x, t = abs(uv.y);
    if (u_shape == 1) {
        return t < pow(max(1.0 - s, 0.0), 0.6) * min(s * 6.0, 1.0);
    }
    if (u_shape == 2) {
        // needles radiating from the base
        vec2 d = vec2(s, uv.y * 0.5);
        float r = length(d);
        float ang = atan(d.y, d.x);
        float k = abs(fract(ang * 4.5 + 0.5) - 0.5);
        return r < 1.0 && k < 0.09 + 0.05 * (1.0 - r);
    }
    // broad leaf: pointed ellipse with a short stalk
    if (s < 0.08) {
        return t < 0.06;
    }
    float u = (s - 0.08) / 0.92;
    return t < pow(sin(3.14159 * u), 0.75) * (1.0 - 0.35 * u);
}

void main()
{
    if (!inside(v_uv) || !dither_keep(v_fade)) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 base = u_leafcol * (0.78 + 0.4 * v_var);
    base.r *= 0.9 + 0.25 * v_var * v_var;
    float rib = u_shape == 0 ? smoothstep(0.06, 0.0, abs(v_uv.y)) * 0.15 : 0.0;
    base *= 1.0 - rib;
    vec3 c = light(base, n, v_wpos, 0.12, 28.0) * v_ao;
    // sunlight through the blade from behind
    float back = max(-dot(n, u_sun_dir), 0.0);
    c += base * vec3(0.9, 1.1, 0.45) * u_sun_col * back * 0.45;
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
