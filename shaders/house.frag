// Houses: plaster walls with a row of windows per 3 m storey, a darker tiled roof; lit by
// the same sun and sky and fogged like the trees (common.glsl light, fog_apply).
uniform vec3 u_wall;    // plaster albedo
uniform vec3 u_roof;    // roof tile albedo
uniform vec3 u_window;  // glass albedo
in vec3 v_wpos;
in vec3 v_nrm;
in vec4 v_attr;
flat in float v_mat;
out vec4 o_col;
void main()
{
    vec3 n = normalize(v_nrm);
    float u = v_attr.x, v = v_attr.y, wall_h = v_attr.z, half_w = v_attr.w;
    vec3 albedo;
    float spec = 0.03;
    if (v_mat > 0.5) {
        // tile courses every 0.3 m down the slope, each course darker at its lower edge
        float course = fract(v / 0.3);
        float row = floor(v / 0.3);
        float tile = hash01(uint(row) * 2654435761u ^ uint(floor(u / 0.25 + 4096.0)));
        albedo = u_roof * (0.78 + 0.22 * smoothstep(0.0, 0.35, course) + 0.08 * (tile - 0.5));
        spec = 0.06;
    } else {
        // plaster, a little darker near the ground (splash) and under the eaves
        float grime = mix(0.82, 1.0, clamp(v / 0.8, 0.0, 1.0));
        albedo = u_wall * grime * (0.96 + 0.04 * hash01(uint(v * 9.0) * 747796405u ^ uint(u * 9.0 + 4096.0)));
        // windows: 1.1 m wide, centred in 3 m bays, 1.0..2.1 m above each storey's floor,
        // only where the whole window fits below the eaves and inside the face
        float storey = floor(v / 3.0);
        float vs = v - storey * 3.0;
        float bay = u - 3.0 * floor(u / 3.0 + 0.5);  // from the nearest bay centre
        bool fits = storey * 3.0 + 2.3 <= wall_h && abs(u - bay) + 0.85 <= half_w;
        if (fits && vs > 1.0 && vs < 2.1 && abs(bay) < 0.55) {
            bool frame = vs < 1.08 || vs > 2.02 || abs(bay) > 0.47 || abs(bay) < 0.03;
            albedo = frame ? u_wall * 1.05 : u_window;
            spec = frame ? 0.03 : 0.5;
        }
    }
    vec3 c = light(albedo, n, v_wpos, spec, 40.0);
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
