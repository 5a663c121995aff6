// Impostor texel: rgb is the tree's albedo-lit colour at rest, a its coverage.
uniform sampler2D u_imp;
in vec2 v_uv;
in vec3 v_wpos;
flat in float v_fade;
out vec4 o_col;
void main()
{
    vec4 c = texture(u_imp, v_uv);
    if (c.a < 0.5 || !dither_keep(v_fade)) {
        discard;
    }
    o_col = vec4(fog_apply(c.rgb / c.a, v_wpos), 1.0);
}
