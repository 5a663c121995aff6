// Falling leaves (Vazquez 2008 sections 3-4): every leaf follows the one shared path
// (u_path: row 0 positions, row 1 orientations) from its own starting sample, rotated
// about the vertical and scaled in x/y by its seed, with path reuse at continuity points,
// drift by the wind sampled at release, a soft start from its orientation on the tree and
// a soft landing flat on the ground, where it stays. Same evaluation as falling_path.c.
layout(location = 0) in vec4 a_start;  // release point xyz [m], release time [s]
layout(location = 1) in vec4 a_var;    // yaw, sx, sy, start sample
layout(location = 2) in vec4 a_drift;  // drift xy [m/s], landing time after release [s], seed
layout(location = 3) in vec4 a_q0;     // orientation on the tree
layout(location = 4) in vec4 a_look;   // rgb, size [m]
layout(location = 5) in float a_shape;
uniform sampler2D u_path;
uniform int u_npath;
uniform float u_pdt;
uniform int u_ncont;
uniform int u_cont[8];
uniform float u_aspects[3];
out vec3 v_wpos;
out vec3 v_nrm;
out vec2 v_uv;
flat out vec3 v_col;
flat out int v_shape;

vec4 qmul(vec4 a, vec4 b)
{
    return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

vec3 qrot(vec4 q, vec3 v)
{
    vec3 t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

vec4 qslerp(vec4 a, vec4 b, float t)
{
    if (dot(a, b) < 0.0) {
        b = -b;
    }
    return normalize(mix(a, b, t)); // nlerp: short arcs only
}

vec3 ppos(int i)
{
    return texelFetch(u_path, ivec2(i, 0), 0).xyz;
}

void main()
{
    float tau = u_time - a_start.w;
    v_shape = int(a_shape);
    v_col = a_look.rgb;
    if (tau < 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // not released yet: outside the clip volume
        v_wpos = vec3(0.0);
        v_nrm = vec3(0.0, 0.0, 1.0);
        v_uv = vec2(0.0);
        return;
    }
    float t_land = a_drift.z;
    float te = min(tau, t_land);
    int start = int(a_var.w);
    float f = float(start) + te / u_pdt;
    vec3 off = -ppos(start);
    float last = float(u_npath - 1);
    uint seed = floatBitsToUint(a_drift.w);
    for (int j = 0; j < 64 && f >= last; j++) {
        int c = u_cont[int(hash_u(seed + uint(j)) % uint(u_ncont))];
        off += ppos(u_npath - 1) - ppos(c - 1);
        f = f - last + float(c - 1);
    }
    f = min(f, last);
    int i0 = int(f);
    int i1 = min(i0 + 1, u_npath - 1);
    float ft = f - float(i0);
    vec3 d = off + mix(ppos(i0), ppos(i1), ft);
    vec4 q = normalize(mix(texelFetch(u_path, ivec2(i0, 1), 0), texelFetch(u_path, ivec2(i1, 1), 0), ft));
    float yaw = a_var.x;
    vec2 hd = vec2(d.x * a_var.y, d.y * a_var.z);
    vec3 pos = a_start.xyz + vec3(cos(yaw) * hd.x - sin(yaw) * hd.y,
                                  sin(yaw) * hd.x + cos(yaw) * hd.y, d.z);
    pos.xy += a_drift.xy * te;
    q = qmul(vec4(0.0, 0.0, sin(0.5 * yaw), cos(0.5 * yaw)), q);
    // soft start: turn from the orientation on the tree to the path's (section 3.5)
    q = qslerp(a_q0, q, smoothstep(0.0, 0.6, tau));
    // soft landing: settle flat, keeping the heading
    vec4 flat_q = vec4(0.0, 0.0, sin(0.5 * yaw), cos(0.5 * yaw));
    float land = smoothstep(t_land - 0.5, t_land, tau);
    q = qslerp(q, flat_q, land);
    pos.z = max(pos.z, 0.0) + 0.004 + 0.004 * hash01(seed + 99u);
    int id = gl_VertexID;
    float s = (id == 1 || id == 2 || id == 4) ? 1.0 : 0.0;
    float t = (id == 2 || id == 4 || id == 5) ? 0.5 : -0.5;
    float len = a_look.w;
    float asp = u_aspects[clamp(v_shape, 0, 2)];
    // the blade's centre follows the path
    vec3 local = vec3((s - 0.5) * len, t * len * asp, 0.0);
    v_wpos = pos + qrot(q, local);
    v_nrm = qrot(q, vec3(0.0, 0.0, 1.0));
    v_uv = vec2(s, t * 2.0);
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
