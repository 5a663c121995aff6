// Trunk and branch tubes skinned on the GPU from the reconstructed skeleton (Singh
// section 2.1, eq. 1: v' = Σ w_i M_i v with two bones); each bone is the node's position and
// the rotation of its incoming segment, so normals turn with the wood.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in ivec2 a_bone;
layout(location = 3) in float a_w;
uniform sampler2D u_skel;
uniform GALE_BUF u_node;
uniform GALE_BUF u_list;
uniform GALE_BUF u_trees; // per tree: pos xyz, yaw; scale, species
uniform int u_base;
out vec3 v_wpos;
out vec3 v_nrm;
out vec3 v_local;
out float v_kept;
out float v_cut;
flat out float v_fade;
flat out int v_tree;

// kept: 1 while the node hangs on the tree (skel.frag .w), 0 on a broken-off sub-tree
void bone(int j, int row, out vec3 x, out vec3 rest, out mat3 r, out float kept)
{
    vec4 nj = buf_fetch(u_node, j);
    rest = nj.xyz;
    vec4 xj = texelFetch(u_skel, ivec2(j, row), 0);
    x = xj.xyz;
    kept = xj.w;
    int p = int(nj.w);
    if (p < 0) {
        r = mat3(1.0);
        return;
    }
    vec3 xp = texelFetch(u_skel, ivec2(p, row), 0).xyz;
    vec3 rp = buf_fetch(u_node, p).xyz;
    r = rot_between(normalize(rest - rp), normalize(x - xp));
}

void main()
{
    vec4 e = buf_fetch(u_list, u_base + gl_InstanceID);
    int tree = int(e.x), row = int(e.y);
    vec3 x0, x1, r0, r1;
    mat3 m0, m1;
    float k0, k1;
    bone(a_bone.x, row, x0, r0, m0, k0);
    bone(a_bone.y, row, x1, r1, m1, k1);
    // a tube segment across the break keeps the half at the tree: a splintered stub
    v_kept = min(k0, k1);
    vec3 p = (1.0 - a_w) * (x0 + m0 * (a_pos - r0)) + a_w * (x1 + m1 * (a_pos - r1));
    vec3 n = (1.0 - a_w) * (m0 * a_nrm) + a_w * (m1 * a_nrm);
    vec4 t0 = buf_fetch(u_trees, tree * 2), t1 = buf_fetch(u_trees, tree * 2 + 1);
    mat3 rz = tree_frame(t0.w, tree_fall(t1.z), t1.w);
    // a snapped tree tips about its break; the wood below it is the stump's (stump.vert)
    float piv = tree_pivot_m(tree, t1.z);
    v_wpos = tree_point(p, rz, piv, t0.xyz, t1.x);
    v_cut = piv > 0.0 ? p.z - piv : 1e3;
    v_tree = tree;
    v_nrm = rz * n;
    v_local = a_pos;
    v_fade = e.w;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
