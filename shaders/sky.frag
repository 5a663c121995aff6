// Sky gradient with the sun, and the ground plane z = 0 found by intersecting the view ray
// (grass colour with large-scale patches, lit, fogged); writes depth for the ground.
uniform mat4 u_inv_viewproj;
in vec2 v_ndc;
out vec4 o_col;
void main()
{
    vec4 a = u_inv_viewproj * vec4(v_ndc, -1.0, 1.0);
    vec4 b = u_inv_viewproj * vec4(v_ndc, 1.0, 1.0);
    vec3 p0 = a.xyz / a.w, p1 = b.xyz / b.w;
    vec3 dir = normalize(p1 - p0);
    if (dir.z < -1e-5 && p0.z > 0.0) {
        float t = -p0.z / dir.z;
        vec3 g = p0 + dir * t;
        vec4 clip = u_viewproj * vec4(g, 1.0);
        float depth = clip.z / clip.w * 0.5 + 0.5;
        if (depth < 1.0) {
            vec2 c = g.xy;
            float n1 = sin(c.x * 0.11 + sin(c.y * 0.07) * 2.0) * sin(c.y * 0.13 + sin(c.x * 0.05));
            float n2 = sin(c.x * 0.9 + sin(c.y * 0.6)) * sin(c.y * 1.1 + sin(c.x * 0.4));
            // fine detail fades with distance so it does not alias
            float near = clamp(1.0 - t / 60.0, 0.0, 1.0);
            vec3 albedo = u_ground_col * (0.85 + 0.18 * n1 + 0.08 * n2 * near);
            vec3 col = light(albedo, vec3(0.0, 0.0, 1.0), g, 0.02, 8.0);
            o_col = vec4(fog_apply(col, g), 1.0);
            gl_FragDepth = depth;
            return;
        }
    }
    o_col = vec4(sky_color(dir), 1.0);
    gl_FragDepth = 1.0;
}
