// The impostor's vertex stage in the page (web/render_imp.js compiles it before
// shaders/bill.frag, whose inputs it writes): shaders/bill.vert's quad, turned about the
// vertical toward the eye, leaning with the crown's sway in the tree's lowest modes
// (web/imp_sway.js swayOffset: min(max(z, 0) / z_c, 3) Σ_k q̃_k c_k, turned by the
// tree's yaw and scaled with it). q is read as the skeleton pass reads it
// (shaders/skel.frag modal_q): blended from the snapshot ring, or the float path's q.
// A fallen tree (the entry's third component >= 1: web/render_list.js impFall) lies along
// its fall and does not sway, as shaders/bill.vert draws it (common.glsl bill_fallen).
import { LOD_IMPOSTOR_MODES } from './lod_policy.js';
import { IMP_SWAY_MAX } from './imp_sway.js';

export const IMP_VERT_NAME = 'web/imp_shader.js (impostor vertex stage)';

export const IMP_VERT = `
uniform GALE_BUF u_list;  // per impostor: tree, share of its leaves left, fall, fade
uniform GALE_BUF u_trees;
uniform int u_base;
uniform vec3 u_bsize;     // half width, height, bottom of the impostor [m, tree frame]
uniform vec3 u_sway[${LOD_IMPOSTOR_MODES}];   // c_k, the crown's sway per unit q_k [m, tree frame]
uniform float u_zc;       // the crown's height z_c [m, tree frame]
uniform vec2 u_imp_ab[${LOD_IMPOSTOR_MODES}]; // a_k, b_k of q̃_k = a_k atan(b_k q_k) (b = 0: q)
uniform int u_qstride;
uniform int u_qtrees;     // trees whose q the page holds (the others stand at rest)
#ifdef GALE_Q_RING
uniform highp isampler2DArray u_qring;
uniform ivec4 u_qlayer;
uniform vec4 u_qw[${LOD_IMPOSTOR_MODES}];
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
uniform GALE_BUF u_q;
float modal_q(int i, int m)
{
    return buf_fetch(u_q, i).x;
}
#endif
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
    if (tree < u_qtrees) {
        for (int k = 0; k < ${LOD_IMPOSTOR_MODES}; k++) {
            float q = modal_q(tree * u_qstride + k, k);
            vec2 ab = u_imp_ab[k];
            sway += (ab.y != 0.0 ? ab.x * atan(ab.y * q) : q) * u_sway[k];
        }
        sway *= min(max(z, 0.0) / max(u_zc, 1e-3), ${IMP_SWAY_MAX.toFixed(1)});
    }
    v_wpos = t0.xyz + t1.x * (right * ((s * 2.0 - 1.0) * u_bsize.x) + vec3(0.0, 0.0, z) +
                              rot_z(t0.w) * sway);
    v_uv = vec2(s, t);
    v_fade = e.w;
    v_leaf = e.y;
    v_tree = tree;
    gl_Position = u_viewproj * vec4(v_wpos, 1.0);
}
`;
