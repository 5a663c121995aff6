// Far trees as impostors (Singh section 2, Oliapuram LOD): a quad turned about the
// vertical toward the camera, textured with the species' impostor rendered at rest, and
// leaning with the tree's lowest modes so a far forest sways: a vertex at height z moves
// by (z / z_c) Σ_k q̃_k c_k (a quad's two rows can only shear: the lean that puts the
// crown's middle where the modes put it), c_k the crown's mean translation per unit q_k, z_c its height
// (client/render/render_species.c impostor_sway; the page's impostors bend the same) and
// q̃_k = a_k atan(b_k q_k) the pose's saturated coordinate (Diener 2008 eq. 16).
//
// A fallen tree (snapped or uprooted, the list entry's third component f >= 1: f - 1 =
// azimuth in 1/256 turns + fall angle / π, render_bill_fall) lies along its fall: the
// quad's up axis turns from the vertical towards the azimuth by the angle about the
// tree's base (a snapped tree's break height is not seen this far), its right axis goes
// from the camera-facing one (standing) to the horizontal across the fall (lying) as the
// angle goes to π/2, made square to the up axis, and a lying quad is lifted off the
// ground by half its half width; it does not sway.
uniform GALE_BUF u_list;  // per billboard: tree, share of its leaves left, fall, fade
uniform GALE_BUF u_trees;
uniform GALE_BUF u_q;     // [tree stride + m]
uniform int u_qstride;
uniform int u_base;
uniform vec3 u_bsize;         // half width, height, bottom of the impostor [m, tree frame]
uniform vec3 u_sway[2];       // c_k [m per unit q, tree frame]
uniform float u_crown_z;      // z_c [m, tree frame]
uniform vec2 u_ab[2];         // a_k, b_k of q̃_k (b = 0: q̃ = q)
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
    float z = u_bsize.z + t * u_bsize.y;
    if (e.z >= 1.0) {
        v_wpos = t0.xyz + t1.x * bill_fallen(e.z, right, s * 2.0 - 1.0, z, u_bsize.x);
        v_uv = vec2(s, t);
        v_fade = e.w;
        v_leaf = e.y;
        v_tree = tree;
        gl_Position = u_viewproj * vec4(v_wpos, 1.0);
        return;
    }
    vec3 sway = vec3(0.0);
    for (int k = 0; k < 2 && k < u_qstride; k++) {
        float q = buf_fetch(u_q, tree * u_qstride + k).x;
        sway += (u_ab[k].y != 0.0 ? u_ab[k].x * atan(u_ab[k].y * q) : q) * u_sway[k];
    }
    float bend = min(max(z, 0.0) / u_crown_z, 3.0);
    v_wpos = t0.xyz + t1.x * (right * ((s * 2.0 - 1.0) * u_bsize.x) + vec3(0.0, 0.0, z) +
                              bend * (rot_z(t0.w) * sway));
    v_uv = vec2(s, t);
    v_fade = e.w;
    v_leaf = e.y;
    v_tree = tree;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
