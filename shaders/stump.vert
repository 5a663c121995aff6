// Stumps of snapped trees: the stem from the ground up to its break (stump_break_m), with the
// ragged top the fallen part's butt shares (stump_jag_m, tree.frag). Drawn upright in the
// tree's yawed frame from gl_VertexID: per segment of STUMP_SEG around the stem a tooth of
// wood, its bark side, its splintered top and its two radial walls (seen where a neighbour
// broke lower), 21 vertices each.
uniform GALE_BUF u_trees;  // per tree: pos xyz, yaw; scale, species, fall, azimuth
uniform GALE_BUF u_stumps; // per stump: tree, base radius [m], taper [m/m]; bark rgb
out vec3 v_wpos;
out vec3 v_nrm;
out vec3 v_local;
flat out vec3 v_bark;
flat out float v_top_m;
flat out float v_cap;

const float STUMP_LOW_M = 0.15; // the walls between teeth reach this far below the break

void main()
{
    int inst = gl_InstanceID;
    vec4 s0 = buf_fetch(u_stumps, inst * 2), s1 = buf_fetch(u_stumps, inst * 2 + 1);
    int tree = int(s0.x);
    float h = stump_break_m(tree);
    int k = gl_VertexID / 21, c = gl_VertexID % 21;
    float a0 = -3.1415926 + 6.2831853 * float(k) / float(STUMP_SEG);
    float a1 = a0 + 6.2831853 / float(STUMP_SEG);
    float top = h + stump_jag_m(tree, k);
    // a little wider than the stem's tube so the mesh it replaces stays inside
    float rb = 1.04 * s0.y, rt = 1.04 * max(s0.y + s0.z * top, 0.3 * s0.y);
    vec3 d0 = vec3(cos(a0), sin(a0), 0.0), d1 = vec3(cos(a1), sin(a1), 0.0);
    vec3 p, n;
    v_cap = 0.0;
    if (c < 6) {
        // bark side: a quad from below the ground to the tooth's top
        const int qs[6] = int[6](0, 1, 2, 0, 2, 3);
        int q = qs[c];
        vec3 d = (q == 1 || q == 2) ? d1 : d0;
        bool up = q >= 2;
        p = up ? d * rt + vec3(0.0, 0.0, top) : d * rb * 1.12 + vec3(0.0, 0.0, -0.1);
        n = normalize(d + vec3(0.0, 0.0, (rb - rt) / max(top, 0.1)));
    } else if (c < 9) {
        // the splintered top: a fan from the stem's axis, a little lower in the middle
        int q = c - 6;
        p = q == 0 ? vec3(0.0, 0.0, top - 0.05) : (q == 1 ? d0 : d1) * rt + vec3(0.0, 0.0, top);
        n = vec3(0.0, 0.0, 1.0);
        v_cap = 1.0;
    } else {
        // radial walls at a0 and a1
        int w = (c - 9) / 6, q = (c - 9) % 6;
        const int qs[6] = int[6](0, 1, 2, 0, 2, 3);
        int e = qs[q];
        vec3 d = w == 0 ? d0 : d1;
        float r = (e == 1 || e == 2) ? rt : 0.0;
        float z = e >= 2 ? top : h - STUMP_LOW_M;
        p = d * r + vec3(0.0, 0.0, z);
        n = w == 0 ? vec3(sin(a0), -cos(a0), 0.0) : vec3(-sin(a1), cos(a1), 0.0);
        v_cap = 1.0;
    }
    vec4 t0 = buf_fetch(u_trees, tree * 2), t1 = buf_fetch(u_trees, tree * 2 + 1);
    mat3 rz = rot_z(t0.w);
    v_local = p;
    v_wpos = t0.xyz + rz * (p * t1.x);
    v_nrm = rz * n;
    v_bark = s1.xyz;
    v_top_m = top;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
