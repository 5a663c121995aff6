// Far trees as billboards (Singh section 2, Oliapuram LOD): a quad turned about the
// vertical toward the camera, textured with the species' impostor rendered at rest.
uniform GALE_BUF u_list;  // per billboard: tree, share of its leaves left, 0, fade
uniform GALE_BUF u_trees;
uniform int u_base;
uniform vec3 u_bsize;         // half width, height, bottom of the impostor [m, tree frame]
out vec2 v_uv;
out vec3 v_wpos;
flat out float v_fade;
flat out float v_leaf;
flat out int v_tree;
void main()
{
    vec4 e = buf_fetch(u_list, u_base + gl_InstanceID);
    int tree = int(e.x);
    vec4 t0 = buf_fetch(u_trees, tree * 2), t1 = buf_fetch(u_trees, tree * 2 + 1);
    int id = gl_VertexID;
    float s = (id == 1 || id == 2 || id == 4) ? 1.0 : 0.0;
    float t = (id == 2 || id == 4 || id == 5) ? 1.0 : 0.0;
    vec3 toc = u_eye - t0.xyz;
    vec2 f = normalize(toc.xy + vec2(1e-6, 0.0));
    vec3 right = vec3(-f.y, f.x, 0.0);
    v_wpos = t0.xyz + t1.x * (right * ((s * 2.0 - 1.0) * u_bsize.x) +
                              vec3(0.0, 0.0, u_bsize.z + t * u_bsize.y));
    v_uv = vec2(s, t);
    v_fade = e.w;
    v_leaf = e.y;
    v_tree = tree;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
