// Node positions from the modal state in the length-true form (PHYSICS.md "Length-true
// pose"), in two passes over the same rows. u_pass 0: each node's posed segment
// R(Θ) (s + e), Θ = Σ c_i q̃_i v_i, e = Σ c_i q̃_i w_i, s the rest segment from its parent
// (the root writes its rest position), q̃_i = a_i atan(b_i q_i) (b_i = 0: q̃_i = q_i);
// c_i fades the last mode in or out as the LOD mode count changes. u_pass 1: a node's
// position, the sum of the posed segments from it up to the root (u_skel holds pass 0).
// The GLSL twin of asset_corr_qt / asset_reconstruct (protocol/asset_pose.c), held to it
// by tests/test_render.c.
// Storm damage: .w of a pass-0 texel is 0 at a node listed in the tree's cut list (a
// branch broken off there) and 1 elsewhere; pass 1 reads every texel up to the root anyway,
// so the minimum along the way costs nothing: a node stays attached (.w 1) when no node
// from it to the root is cut. A debris piece (keep-only) inverts it: only the sub-tree of
// its listed node is drawn. The GLSL twin of damage_cut_mask (client/motion/damage_cut.c), held
// to it by tests/test_render_damage.c.
uniform GALE_BUF u_vw;   // [(m n_nodes + node) 2 + {0: v, 1: w}]
uniform GALE_BUF u_node; // rest xyz, parent
#ifdef GALE_Q_RING
// The browser blends the interpolation here (web/render_skel.js, web/jitter.js): each
// snapshot's quantised values Q [tree stride + m] are a layer of u_qring, uploaded once,
// and q = Σ_k u_qw[m][k] Q_k over the (up to four) snapshots of u_qlayer, u_qw the
// Hermite weight of snapshot k times its step of mode m for this species (PROTOCOL.md
// "Quantisation of q"): the sum client/playout/jitter.c jitter_sample forms on the CPU.
uniform highp isampler2DArray u_qring;
uniform ivec4 u_qlayer;
uniform vec4 u_qw[64];
float modal_q(int i, int m)
{
    int w = textureSize(u_qring, 0).x;
    ivec2 at = ivec2(i % w, i / w);
    vec4 q = vec4(float(texelFetch(u_qring, ivec3(at, u_qlayer.x), 0).x),
                  float(texelFetch(u_qring, ivec3(at, u_qlayer.y), 0).x),
                  float(texelFetch(u_qring, ivec3(at, u_qlayer.z), 0).x),
                  float(texelFetch(u_qring, ivec3(at, u_qlayer.w), 0).x));
    return dot(u_qw[m], q);
}
#else
uniform GALE_BUF u_q;    // [tree stride + m], interpolated and dequantised
float modal_q(int i, int m)
{
    return buf_fetch(u_q, i).x;
}
#endif
uniform sampler2D u_skel;     // pass 1: the posed segments of pass 0
uniform int u_qstride;
uniform int u_nodes;
uniform int u_pass;
uniform vec2 u_ab[64];        // a_i, b_i
uniform GALE_BUF u_cutn; // cut node indices, per tree ascending
flat in int v_tree;
flat in float v_modes;
flat in ivec3 v_cut;
out vec4 o_pos;

vec3 posed_segment(vec3 th, vec3 s)
{
    float t2 = dot(th, th);
    // sin t / t and (1 - cos t) / t² by their series where the closed forms lose digits
    float sa, ca;
    if (t2 < 1e-4) {
        sa = 1.0 - t2 / 6.0;
        ca = 0.5 - t2 / 24.0;
    } else {
        float t = sqrt(t2);
        sa = sin(t) / t;
        ca = (1.0 - cos(t)) / t2;
    }
    vec3 c = cross(th, s);
    return s + sa * c + ca * cross(th, c);
}

void main()
{
    int node = int(gl_FragCoord.x);
    int row = int(gl_FragCoord.y);
    vec4 rn = buf_fetch(u_node, node);
    if (u_pass == 1) {
        vec3 x = vec3(0.0);
        float kept = 1.0;
        int j = node;
        for (int guard = 0; guard < u_nodes && j >= 0; guard++) {
            vec4 sg = texelFetch(u_skel, ivec2(j, row), 0);
            x += sg.xyz;
            kept = min(kept, sg.w);
            j = int(buf_fetch(u_node, j).w);
        }
        o_pos = vec4(x, v_cut.z != 0 ? 1.0 - kept : kept);
        return;
    }
    float whole = 1.0;
    for (int k = 0; k < v_cut.y; k++) {
        if (int(buf_fetch(u_cutn, v_cut.x + k).x) == node) {
            whole = 0.0;
            break;
        }
    }
    int p = int(rn.w);
    if (p < 0) {
        o_pos = vec4(rn.xyz, whole);
        return;
    }
    vec3 s = rn.xyz - buf_fetch(u_node, p).xyz;
    vec3 th = vec3(0.0);
    int nm = int(ceil(v_modes));
    int qb = v_tree * u_qstride;
    for (int m = 0; m < nm; m++) {
        float q = modal_q(qb + m, m);
        float qt = u_ab[m].y != 0.0 ? u_ab[m].x * atan(u_ab[m].y * q) : q;
        float c = clamp(v_modes - float(m), 0.0, 1.0) * qt;
        int t = (m * u_nodes + node) * 2;
        th += c * buf_fetch(u_vw, t).xyz;
        s += c * buf_fetch(u_vw, t + 1).xyz;
    }
    o_pos = vec4(posed_segment(th, s), whole);
}
