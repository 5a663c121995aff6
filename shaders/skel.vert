// Skeleton pass (Diener 2008 section 5.1, matrix U of figure 5): one row of the skeleton
// texture per visible tree, one texel per node; this draws the row's quad.
uniform GALE_BUF u_list; // per entry: tree, row, modes used (fractional), fade
uniform int u_base;
uniform int u_nodes;
uniform vec2 u_target;        // skeleton texture size [texels]
uniform GALE_BUF u_cut;  // per tree: first, count of its cut nodes in u_cutn, keep-only
flat out int v_tree;
flat out float v_modes;
flat out ivec3 v_cut;
void main()
{
    vec4 e = buf_fetch(u_list, u_base + gl_InstanceID);
    int id = gl_VertexID;
    float cx = (id == 1 || id == 2 || id == 4) ? 1.0 : 0.0;
    float cy = (id == 2 || id == 4 || id == 5) ? 1.0 : 0.0;
    vec2 p = vec2(cx * float(u_nodes), e.y + cy) / u_target * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
    v_tree = int(e.x);
    v_modes = e.z;
    v_cut = ivec3(buf_fetch(u_cut, v_tree).xyz);
}
