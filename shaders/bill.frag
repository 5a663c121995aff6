// Impostor texel: rgb is the tree's albedo-lit colour at rest, a its coverage. A crown that
// lost leaves (stripped, or branches broken off) keeps that share of its leaf texels, in
// cells of 4 x 4 impostor texels hashed per tree; where one goes, the impostor of the wood
// alone shows what stands behind it, or nothing.
uniform sampler2D u_imp;
uniform sampler2D u_imp_wood;
in vec2 v_uv;
in vec3 v_wpos;
flat in float v_fade;
flat in float v_leaf;
flat in int v_tree;
out vec4 o_col;
void main()
{
    vec4 c = texture(u_imp, v_uv);
    if (c.a < 0.5 || !dither_keep(v_fade)) {
        discard;
    }
    if (v_leaf < 1.0) {
        uvec2 cell = uvec2(v_uv * vec2(64.0, 128.0));
        if (hash01(cell.x * 73856093u ^ cell.y * 19349663u ^ uint(v_tree) * 83492791u) >= v_leaf) {
            c = texture(u_imp_wood, v_uv);
            if (c.a < 0.5) {
                discard;
            }
        }
    }
    o_col = vec4(fog_apply(c.rgb / c.a, v_wpos), 1.0);
}
