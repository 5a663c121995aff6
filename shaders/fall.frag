// Falling and landed leaf blades: the attached-leaf look (shape, two-sided light, fog).
in vec3 v_wpos;
in vec3 v_nrm;
in vec2 v_uv;
flat in vec3 v_col;
flat in int v_shape;
out vec4 o_col;

bool inside(vec2 uv)
{
    float s = uv.x, t = abs(uv.y);
    if (v_shape == 1) {
        return t < pow(max(1.0 - s, 0.0), 0.6) * min(s * 6.0, 1.0);
    }
    if (v_shape == 2) {
        vec2 d = vec2(s, uv.y * 0.5);
        float k = abs(fract(atan(d.y, d.x) * 4.5 + 0.5) - 0.5);
        return length(d) < 1.0 && k < 0.12;
    }
    if (s < 0.08) {
        return t < 0.06;
    }
    float u = (s - 0.08) / 0.92;
    return t < pow(sin(3.14159 * u), 0.75) * (1.0 - 0.35 * u);
}

void main()
{
    if (!inside(v_uv)) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    if (!gl_FrontFacing) {
        n = -n;
    }
    vec3 c = light(v_col, n, v_wpos, 0.1, 28.0);
    c += v_col * vec3(0.9, 1.1, 0.45) * u_sun_col * max(-dot(n, u_sun_dir), 0.0) * 0.4;
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
