// Bark: species colour with procedural furrows, lit by sun and sky, fogged.
uniform vec3 u_bark;
in vec3 v_wpos;
in vec3 v_nrm;
in vec3 v_local;
in float v_kept;
flat in float v_fade;
out vec4 o_col;
void main()
{
    if (v_kept < 0.5 || !dither_keep(v_fade)) {
        discard;
    }
    vec3 n = normalize(v_nrm);
    float ang = atan(v_local.y, v_local.x);
    float furrow = 0.5 + 0.5 * sin(ang * 9.0 + sin(v_local.z * 7.0) * 1.5);
    float grain = hash01(uint(v_local.z * 40.0) * 2654435761u ^ uint((ang + 4.0) * 12.0));
    vec3 albedo = u_bark * (0.72 + 0.22 * furrow + 0.12 * grain);
    // darker near the ground where soil and moss collect
    albedo *= mix(0.7, 1.0, clamp(v_wpos.z / 1.5, 0.0, 1.0));
    // the last stretch before a break (v_kept falls from 1 to 0.5 across the broken
    // segment, on the tree and on its piece): pale splintered wood
    albedo = mix(albedo, vec3(0.78, 0.66, 0.46), smoothstep(0.85, 0.6, v_kept));
    vec3 c = light(albedo, n, v_wpos, 0.08, 16.0);
    o_col = vec4(fog_apply(c, v_wpos), 1.0);
}
