// Node positions from the modal state in the strong-wind form (Diener 2008 section 5.2):
// x = rest + Σ c_i (q̃_i v_i + q̃_i² w_i), q̃_i = a_i atan(b_i q_i) (b_i = 0: q̃_i = q_i);
// c_i fades the last mode in or out as the LOD mode count changes. The GLSL twin of
// asset_corr_qt / asset_reconstruct (protocol/asset.h), held to it by tests/test_render.c.
uniform samplerBuffer u_vw;   // [(m n_nodes + node) 2 + {0: v, 1: w}]
uniform samplerBuffer u_node; // rest xyz, parent
uniform samplerBuffer u_q;    // [tree stride + m]
uniform int u_qstride;
uniform int u_nodes;
uniform vec2 u_ab[64];        // a_i, b_i
flat in int v_tree;
flat in float v_modes;
out vec4 o_pos;
void main()
{
    int node = int(gl_FragCoord.x);
    vec3 x = texelFetch(u_node, node).xyz;
    int nm = int(ceil(v_modes));
    int qb = v_tree * u_qstride;
    for (int m = 0; m < nm; m++) {
        float q = texelFetch(u_q, qb + m).x;
        float qt = u_ab[m].y != 0.0 ? u_ab[m].x * atan(u_ab[m].y * q) : q;
        float c = clamp(v_modes - float(m), 0.0, 1.0);
        int t = (m * u_nodes + node) * 2;
        x += c * (qt * texelFetch(u_vw, t).xyz + qt * qt * texelFetch(u_vw, t + 1).xyz);
    }
    o_pos = vec4(x, 1.0);
}
