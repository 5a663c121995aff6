// Root plates of uprooted trees: the disc of soil and roots a tree lifts out of the ground
// as it tips over its root plate (ForestGALES' uprooting; Nicoll et al. 2006), drawn in the
// tree's frame so it turns with the stem (common.glsl tree_frame). Built from gl_VertexID:
// a top fan (the turf), a bottom fan and the side band (soil), PLATE_SEG segments with a
// ragged rim hashed per tree.
uniform GALE_BUF u_trees;  // per tree: pos xyz, yaw; scale, species, fall, azimuth
uniform GALE_BUF u_plates; // tree index per instance
out vec3 v_wpos;
out vec3 v_nrm;
out vec3 v_local;
flat out float v_top;

const int PLATE_SEG = 24;
const float PLATE_R_M = 2.1;     // radius at unit scale [m]
const float PLATE_DEPTH_M = 0.6; // soil held in the roots [m]

vec3 rim(int tree, int i, float z)
{
    int k = i % PLATE_SEG;
    float a = 6.2831853 * float(k) / float(PLATE_SEG);
    float r = PLATE_R_M * (0.78 + 0.34 * hash01(uint(tree) * 131u + uint(k) * 7u + 3u));
    // the bottom is narrower: roots taper into the soil
    r *= z < 0.0 ? 0.7 : 1.0;
    return vec3(r * cos(a), r * sin(a), z);
}

void main()
{
    int tree = int(buf_fetch(u_plates, gl_InstanceID).x);
    int id = gl_VertexID;
    int fan = 3 * PLATE_SEG;
    vec3 p, n;
    v_top = 0.0;
    if (id < 2 * fan) {
        bool top = id < fan;
        int j = top ? id : id - fan;
        int i = j / 3, c = j % 3;
        float z = top ? 0.0 : -PLATE_DEPTH_M;
        p = c == 0 ? vec3(0.0, 0.0, z) : rim(tree, i + c - 1, z);
        n = vec3(0.0, 0.0, top ? 1.0 : -1.0);
        v_top = top ? 1.0 : 0.0;
    } else {
        int j = id - 2 * fan;
        int i = j / 6, c = j % 6;
        int seg = (c == 1 || c == 2 || c == 4) ? i + 1 : i;
        bool up = c == 0 || c == 1 || c == 4;
        p = rim(tree, seg, up ? 0.0 : -PLATE_DEPTH_M);
        n = normalize(vec3(p.xy, 0.0));
    }
    vec4 t0 = buf_fetch(u_trees, tree * 2), t1 = buf_fetch(u_trees, tree * 2 + 1);
    mat3 rz = tree_frame(t0.w, tree_fall(t1.z), t1.w);
    v_local = p;
    v_wpos = t0.xyz + rz * (p * t1.x);
    v_nrm = rz * n;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
