// Attached leaves: one quad per leaf slot per visible tree, instanced. The leaf follows its
// node (position and segment rotation from the skeleton texture), flutters about its stem
// with a phase and rate from its seed and an amplitude from the local wind, and leans
// downwind in strong wind.
uniform sampler2D u_skel;
uniform GALE_BUF u_node;
uniform GALE_BUF u_list;
uniform GALE_BUF u_trees;
uniform GALE_BUF u_leaf;  // per leaf: offset xyz, node; normal xyz, size
uniform int u_base;
uniform int u_nleaves;         // leaves drawn per tree: every one, or THIN's share
uniform int u_leaf_total;      // the species' leaves
uniform float u_leaf_grow;     // each drawn leaf's size × this
uniform float u_aspect;        // blade width / length for this species' shape
uniform vec2 u_crown;          // crown radius, tree height [m, tree frame]
out vec3 v_wpos;
out vec3 v_nrm;
out vec2 v_uv;
flat out float v_fade;
flat out float v_var;
flat out float v_ao;

void main()
{
    int ent = gl_InstanceID / u_nleaves;
    int slot = gl_InstanceID - ent * u_nleaves;
    // a share of the leaves (lod_policy.h THIN): every (total / drawn)-th, spread over the
    // slots, each grown by u_leaf_grow so the crown covers as much (the page's too)
    int leaf = min(u_leaf_total - 1, int((float(slot) + 0.5) * float(u_leaf_total) / float(u_nleaves)));
    float grow = u_leaf_grow;
    vec4 e = buf_fetch(u_list, u_base + ent);
    int tree = int(e.x), row = int(e.y);
    vec4 l0 = buf_fetch(u_leaf, leaf * 2), l1 = buf_fetch(u_leaf, leaf * 2 + 1);
    int j = int(l0.w);
    vec4 nj = buf_fetch(u_node, j);
    vec4 sj = texelFetch(u_skel, ivec2(j, row), 0);
    vec3 xj = sj.xyz;
    mat3 r = mat3(1.0);
    int p = int(nj.w);
    if (p >= 0) {
        vec3 xp = texelFetch(u_skel, ivec2(p, row), 0).xyz;
        r = rot_between(normalize(nj.xyz - buf_fetch(u_node, p).xyz), normalize(xj - xp));
    }
    vec4 t0 = buf_fetch(u_trees, tree * 2), t1 = buf_fetch(u_trees, tree * 2 + 1);
    mat3 rz = tree_frame(t0.w, tree_fall(t1.z), t1.w);
    if (sj.w < 0.5 || !leaf_kept(uint(tree), uint(leaf), t1.z)) {
        // stripped, or on a broken-off branch: outside the clip volume
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        v_wpos = vec3(0.0);
        v_nrm = vec3(0.0, 0.0, 1.0);
        v_uv = vec2(0.0);
        v_fade = 0.0;
        v_var = 0.0;
        v_ao = 0.0;
        return;
    }
    uint h = hash_u(uint(tree) * 7919u + uint(leaf) * 104729u + 17u);

    vec3 n = l1.xyz;
    vec3 a = l0.xyz - dot(l0.xyz, n) * n;
    if (dot(a, a) < 1e-8) {
        vec3 k = abs(n.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
        a = cross(n, k);
    }
    a = rz * (r * normalize(a));
    n = rz * (r * n);
    vec3 anchor = tree_point(xj + r * l0.xyz, rz, tree_pivot_m(tree, t1.z), t0.xyz, t1.x);

    vec3 w = wind_at(anchor);
    float ws = length(w);
    float rate = 2.0 + 4.0 * hash01(h) + 0.12 * ws;
    float amp = 0.12 + min(0.035 * ws, 0.9);
    float th = amp * sin(6.2831853 * rate * u_time + 6.2831853 * hash01(h + 1u));
    // twist about the stem (Rodrigues, a is unit)
    n = n * cos(th) + cross(a, n) * sin(th) + a * dot(a, n) * (1.0 - cos(th));
    if (ws > 0.3) {
        vec3 a2 = normalize(mix(a, w / ws, min(0.02 * ws, 0.7)));
        n = rot_between(a, a2) * n;
        a = a2;
    }
    vec3 b = normalize(cross(n, a));
    int id = gl_VertexID;
    float s = (id == 1 || id == 2 || id == 4) ? 1.0 : 0.0;
    float t = (id == 2 || id == 4 || id == 5) ? 0.5 : -0.5;
    float len = l1.w * t1.x * grow;
    v_wpos = anchor + a * (s * len) + b * (t * len * u_aspect);
    v_nrm = n;
    v_uv = vec2(s, t * 2.0);
    v_fade = e.w;
    v_var = hash01(h + 2u);
    // leaves deep inside and low in the crown get less sky: cheap ambient occlusion
    vec3 rl = nj.xyz + l0.xyz;
    float outer = clamp(length(rl.xy) / max(u_crown.x, 1e-3), 0.0, 1.0);
    float high = clamp(rl.z / max(u_crown.y, 1e-3), 0.0, 1.0);
    v_ao = mix(0.5, 1.0, clamp(0.55 * outer + 0.6 * high, 0.0, 1.0));
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
