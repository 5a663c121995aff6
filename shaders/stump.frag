// Stump: bark below, pale splintered wood at the break (the colour of a broken branch's stub,
// tree.frag), streaked along the grain; what stays below the ground plane is not drawn.
in vec3 v_wpos;
in vec3 v_nrm;
in vec3 v_local;
flat in vec3 v_bark;
flat in float v_top_m;
flat in float v_cap;
out vec4 o_col;
void main()
{
    if (v_wpos.z < 0.0) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    if (dot(n, u_eye - v_wpos) < 0.0) {
        n = -n; // the walls are seen from either side
    }
    float ang = atan(v_local.y, v_local.x);
    float furrow = 0.5 + 0.5 * sin(ang * 9.0 + sin(v_local.z * 7.0) * 1.5);
    vec3 bark = v_bark * (0.72 + 0.22 * furrow);
    bark *= mix(0.7, 1.0, clamp(v_local.z / 1.5, 0.0, 1.0));
    float grain = hash01(uint((ang + 4.0) * 40.0) * 2654435761u);
    vec3 wood = vec3(0.80, 0.68, 0.48) * (0.85 + 0.25 * grain);
    // the bark side turns to torn wood over the last few cm below the break
    float pale = max(v_cap, smoothstep(v_top_m - 0.12, v_top_m - 0.02, v_local.z));
    vec3 c = light(mix(bark, wood, pale), n, v_wpos, 0.05, 12.0);
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
