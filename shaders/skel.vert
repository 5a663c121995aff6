// Skeleton pass (Diener 2008 section 5.1, matrix U of figure 5): one row of the skeleton
// texture per visible tree, one texel per node; this draws the row's quad.
uniform samplerBuffer u_list; // per entry: tree, row, modes used (fractional), fade
uniform int u_base;
uniform int u_nodes;
uniform vec2 u_target;        // skeleton texture size [texels]
flat out int v_tree;
flat out float v_modes;
void main()
{
    vec4 e = texelFetch(u_list, u_base + gl_InstanceID);
    int id = gl_VertexID;
    float cx = (id == 1 || id == 2 || id == 4) ? 1.0 : 0.0;
    float cy = (id == 2 || id == 4 || id == 5) ? 1.0 : 0.0;
    vec2 p = vec2(cx * float(u_nodes), e.y + cy) / u_target * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
    v_tree = int(e.x);
    v_modes = e.z;
}
