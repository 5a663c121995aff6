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

// A far impostor reads a small mip, whose alpha is its texels' mean coverage: a crown
// covering a third of its box reads 0.3 there, and the alpha test would erase every tree
// of a forest seen from afar (the 2 km landscape from the aerial camera drew none). Alpha
// grows with the mip level the sampler takes, 0.25 a level (Golus 2017, "Anti-aliased
// alpha test: the esoteric alpha to coverage"), from the fourth level down (a tree under
// 64 px high): nearer, where the impostor fades in against the posed tree, its edges
// stay as they were (tests/test_render.c's dolly, within 3 % coverage a step).
float coverage(vec4 c)
{
    vec2 px = v_uv * vec2(textureSize(u_imp, 0));
    vec2 dx = dFdx(px), dy = dFdy(px);
    float mip = 0.5 * log2(max(max(dot(dx, dx), dot(dy, dy)), 1e-8));
    return c.a * (1.0 + 0.25 * max(mip - 3.0, 0.0));
}

void main()
{
    vec4 c = texture(u_imp, v_uv);
    if (coverage(c) < 0.5 || !dither_keep(v_fade)) {
        discard;
    }
    if (v_leaf < 1.0) {
        uvec2 cell = uvec2(v_uv * vec2(64.0, 128.0));
        if (hash01(cell.x * 73856093u ^ cell.y * 19349663u ^ uint(v_tree) * 83492791u) >= v_leaf) {
            c = texture(u_imp_wood, v_uv);
            if (coverage(c) < 0.5) {
                discard;
            }
        }
    }
    o_col = vec4(fog_apply(c.rgb / c.a, v_wpos), 1.0);
}
