// Bark: species colour with procedural furrows, lit by sun and sky, fogged.
uniform vec3 u_bark;
in vec3 v_wpos;
in vec3 v_nrm;
in vec3 v_local;
in float v_kept;
in float v_cut;
flat in float v_fade;
flat in int v_tree;
out vec4 o_col;
void main()
{
    if (v_kept < 0.5 || !dither_keep(v_fade)) {
        discard;
    }
    float ang = atan(v_local.y, v_local.x);
    // a snapped stem's fallen part ends at the ragged break the stump's top shares
    float cut = v_cut;
    if (cut < 100.0) { // only a snapped tree pays for the hash
        cut -= stump_jag_m(v_tree, int(floor((ang / 6.2831853 + 0.5) * float(STUMP_SEG))));
    }
    if (cut < 0.0) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    float furrow = 0.5 + 0.5 * sin(ang * 9.0 + sin(v_local.z * 7.0) * 1.5);
    float grain = hash01(uint(v_local.z * 40.0) * 2654435761u ^ uint((ang + 4.0) * 12.0));
    vec3 albedo = u_bark * (0.72 + 0.22 * furrow + 0.12 * grain);
    // darker near the ground where soil and moss collect
    albedo *= mix(0.7, 1.0, clamp(v_wpos.z / 1.5, 0.0, 1.0));
    // the last stretch before a break (v_kept falls from 1 to 0.5 across the broken
    // segment, on the tree and on its piece): pale splintered wood
    albedo = mix(albedo, vec3(0.78, 0.66, 0.46), smoothstep(0.85, 0.6, v_kept));
    albedo = mix(albedo, vec3(0.80, 0.68, 0.48), smoothstep(0.25, 0.0, cut));
    vec3 c = light(albedo, n, v_wpos, 0.08, 16.0);
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
