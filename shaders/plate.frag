// Root plate: turf on top, dark soil with root streaks below and around; what stays below
// the ground plane is not drawn (the ground is the sky pass's, without depth).
in vec3 v_wpos;
in vec3 v_nrm;
in vec3 v_local;
flat in float v_top;
out vec4 o_col;
void main()
{
    if (v_wpos.z < 0.0) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    float ang = atan(v_local.y, v_local.x);
    float roots = smoothstep(0.55, 0.95, abs(sin(ang * 11.0 + length(v_local.xy) * 3.0)));
    vec3 soil = mix(vec3(0.42, 0.31, 0.20), vec3(0.56, 0.44, 0.30), roots);
    vec3 albedo = v_top > 0.5 ? u_ground_col * 0.85 : soil;
    vec3 c = light(albedo, n, v_wpos, 0.02, 8.0); // outward normals of a closed solid
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
