// Wind-driven rain as screen-space streaks (render_rain.c): columns along the slant
// u = x + slant y (the wind across the view over the drops' fall speed), a hashed share of
// them carrying dashes that fall with time; each layer nearer (wider, longer, faster).
// Spray: a mist band hugging the horizon (the view ray's height), streaked in azimuth and
// drifting with the wind.
uniform vec4 u_rain; // density 0..1, slant dx/dy, layers 1..3, pixels per 720 rows
uniform vec2 u_spray; // strength 0..1, drift [rad/s]
// the camera's subject on screen [px] (xy), the radius about it [px] over which the
// streaks thin (z), and the share of them kept off it (w; 0: none)
uniform vec4 u_rain_clear;
uniform mat4 u_inv_viewproj;
in vec2 v_ndc;
out vec4 o_col;
void main()
{
    vec2 p = gl_FragCoord.xy;
    float a = 0.0;
    // the foreground volume around the subject: the near layers (k 1, 2: wider, faster)
    // thin out there, the far one less, so the trees read through the rain
    float clear = 0.0;
    if (u_rain_clear.w > 0.0) {
        clear = u_rain_clear.w * (1.0 - smoothstep(0.5, 1.0, length(p - u_rain_clear.xy) /
                                                             u_rain_clear.z));
    }
    int n = int(u_rain.z);
    for (int k = 0; k < 3; k++) {
        if (k >= n) {
            break;
        }
        float scale = (1.0 + 0.7 * float(k)) * u_rain.w;
        float col_w = 9.0 * scale;
        float u = p.x + u_rain.y * p.y;
        float c = floor(u / col_w);
        uint h = hash_u(uint(int(c) + 1048576) * 0x9E3779B1u + uint(k) * 0x85EBCA77u);
        float r0 = float(h & 0xffffu) * (1.0 / 65536.0);
        float r1 = float(h >> 16u) * (1.0 / 65536.0);
        float density = u_rain.x * (1.0 - clear * (k == 0 ? 0.5 : 1.0));
        if (r0 >= density) {
            continue; // this column is dry
        }
        // the streak's line inside its column, about one pixel wide per layer scale
        float x = (fract(u / col_w) - 0.2 - 0.6 * r1) * col_w;
        float line = 1.0 - smoothstep(0.35 * scale, 0.35 * scale + 0.8, abs(x));
        float len = 34.0 * scale;
        float y = (p.y + u_time * 1100.0 * scale * (0.8 + 0.4 * r1)) / (len * 3.0) + r1 * 11.0;
        float dash = smoothstep(0.0, 0.08, fract(y)) * (1.0 - smoothstep(0.26, 0.34, fract(y)));
        a = max(a, line * dash * (0.30 + 0.08 * float(k)));
    }
    if (u_spray.x > 0.0) {
        vec4 n0 = u_inv_viewproj * vec4(v_ndc, -1.0, 1.0);
        vec4 f0 = u_inv_viewproj * vec4(v_ndc, 1.0, 1.0);
        vec3 dir = normalize(f0.xyz / f0.w - n0.xyz / n0.w);
        float az = atan(dir.y, dir.x) + u_time * u_spray.y;
        float band = exp(-abs(dir.z) * 9.0);
        float streak = 0.6 + 0.4 * sin(az * 23.0 + sin(az * 7.0) * 2.0) * sin(az * 61.0 - u_time);
        float s = u_spray.x * 0.55 * band * streak * (1.0 - 0.5 * clear);
        a = 1.0 - (1.0 - a) * (1.0 - s);
    }
    if (a <= 0.004) {
        discard;
    }
    o_col = vec4(0.80, 0.82, 0.86, a);
}
