// Shared by every gale_render shader (prepended after the #version line, and in the
// browser after "#version 300 es" and its precision lines): scene
// uniforms, sky colour, fog, lighting (Singh section 2.4: diffuse + specular with the
// skinned normal, plus sky ambient), small helpers.
uniform mat4 u_viewproj;
uniform vec3 u_eye;
uniform vec3 u_sun_dir;     // unit, towards the sun
uniform vec3 u_sun_col;
uniform vec3 u_sky_zenith;
uniform vec3 u_sky_horizon;
uniform vec3 u_ground_col;
uniform float u_fog_dist;   // [m]
uniform float u_time;       // [s]
uniform sampler3D u_wind;   // coarse wind [m/s], world
uniform vec3 u_wind_origin; // grid corner [m]
uniform vec3 u_wind_extent; // grid size [m]; 0 = uniform wind only
uniform vec3 u_wind_uniform;
// The trees kept readable in a storm (storm_fx.h): x wetness 0..1, y distance of the
// camera's subject [m] (0: none), z the calm fog distance [m], w share of the storm's extra
// fog kept off the subject (storm_fx.subject_clear). All 0 in the calm look.
uniform vec4 u_storm;

// Data indexed by one integer (per node, tree, leaf, mode): a buffer texture in GLSL 3.30;
// GLSL ES 3.00 has none, so the browser client (web/render_data.js) keeps the same texels
// row by row in a 2D texture. Declared GALE_BUF, read with buf_fetch.
#ifdef GL_ES
#define GALE_BUF highp sampler2D
vec4 buf_fetch(highp sampler2D s, int i)
{
    int w = textureSize(s, 0).x;
    return texelFetch(s, ivec2(i % w, i / w), 0);
}
#else
#define GALE_BUF samplerBuffer
vec4 buf_fetch(samplerBuffer s, int i)
{
    return texelFetch(s, i);
}
#endif

vec3 sky_color(vec3 dir)
{
    float h = clamp(dir.z, -1.0, 1.0);
    vec3 c = mix(u_sky_horizon, u_sky_zenith, pow(max(h, 0.0), 0.55));
    if (h < 0.0) {
        c = mix(u_sky_horizon, u_ground_col * 0.8 + u_sky_horizon * 0.2, min(-h * 6.0, 1.0));
    }
    float s = max(dot(dir, u_sun_dir), 0.0);
    c += u_sun_col * (pow(s, 900.0) * 6.0 + pow(s, 12.0) * 0.18);
    return c;
}

vec3 fog_apply(vec3 c, vec3 wpos)
{
    vec3 d = wpos - u_eye;
    float dist = length(d);
    // exponential-squared fog, thicker near the ground
    float tau = pow(dist / u_fog_dist, 1.6);
    if (u_storm.w > 0.0 && u_storm.y > 0.0) {
        // the storm's fog by distance beyond the subject: up to it mostly the calm fog,
        // the whole storm fog from twice its distance on (tau grows with dist throughout:
        // the calm depth is the smaller, and its share falls with dist)
        float keep = u_storm.w * (1.0 - smoothstep(u_storm.y, 2.0 * u_storm.y, dist));
        tau = mix(tau, pow(dist / u_storm.z, 1.6), keep);
    }
    float f = 1.0 - exp(-tau);
    vec3 fc = sky_color(normalize(vec3(d.xy, max(d.z, 0.0) * 0.3)));
    return mix(c, fc, clamp(f, 0.0, 1.0));
}

vec3 light(vec3 albedo, vec3 n, vec3 wpos, float spec_k, float shininess)
{
    vec3 v = normalize(u_eye - wpos);
    float ndl = dot(n, u_sun_dir);
    vec3 hv = normalize(u_sun_dir + v);
    float spec = ndl > 0.0 ? pow(max(dot(n, hv), 0.0), shininess) * spec_k : 0.0;
    vec3 amb = mix(u_ground_col * 0.9, u_sky_zenith, 0.5 + 0.5 * n.z) * 0.55;
    if (u_storm.x > 0.0) {
        // wet: a water film darkens what it covers (light trapped in the film by total
        // internal reflection, Lekner & Dorf, Appl. Opt. 27, 1988) and reflects the sky
        // (Schlick's Fresnel for water, F0 = 0.02) as sharply as the surface is glossy
        // (spec_k: leaves and bark, hardly grass): crowns darker than the grey sky
        // behind them, their leaves' edges catching its light
        albedo *= 1.0 - 0.3 * u_storm.x;
        float fr = 0.02 + 0.98 * pow(1.0 - abs(dot(n, v)), 5.0);
        float gloss = min(spec_k * 8.0, 1.0);
        vec3 sheen = sky_color(reflect(-v, n)) * fr * 0.5 * gloss * u_storm.x;
        return albedo * (amb + u_sun_col * max(ndl, 0.0)) + u_sun_col * spec + sheen;
    }
    return albedo * (amb + u_sun_col * max(ndl, 0.0)) + u_sun_col * spec;
}

vec3 wind_at(vec3 wpos)
{
    if (u_wind_extent.x <= 0.0) {
        return u_wind_uniform;
    }
    vec3 t = (wpos - u_wind_origin) / u_wind_extent;
    t.z = clamp(t.z, 0.0, 1.0); // a slice or a low grid applies at every height
    if (any(lessThan(t, vec3(0.0))) || any(greaterThan(t, vec3(1.0)))) {
        return u_wind_uniform;
    }
    return texture(u_wind, t).xyz;
}

// hash_mix32 of protocol/hash.h, bit for bit (the C side draws the same per-tree values)
uint hash_u(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

float hash01(uint x)
{
    return float(hash_u(x) >> 8) * (1.0 / 16777216.0);
}

// rotation taking unit a to unit b (minimal arc)
mat3 rot_between(vec3 a, vec3 b)
{
    vec3 v = cross(a, b);
    float c = dot(a, b);
    if (c < -0.9999) {
        return mat3(-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0);
    }
    mat3 vx = mat3(0.0, v.z, -v.y, -v.z, 0.0, v.x, v.y, -v.x, 0.0);
    return mat3(1.0) + vx + vx * vx * (1.0 / (1.0 + c));
}

#ifdef GALE_FRAG
// screen-door dither for LOD transitions: f > 0 keeps a fraction f of the pixels,
// f < 0 keeps the complementary 1 - |f|... fraction |f| of the others
bool dither_keep(float f)
{
    if (f >= 1.0) {
        return true;
    }
    uvec2 p = uvec2(gl_FragCoord.xy);
    float r = hash01(p.x * 73856093u ^ p.y * 19349663u);
    return f >= 0.0 ? r < f : r >= 1.0 + f;
}
#endif

mat3 rot_z(float a)
{
    float c = cos(a), s = sin(a);
    return mat3(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
}

// Storm damage in u_trees slot 1 .z: the fall angle (0..π: a tumbling debris piece turns
// upside down) plus 4 x the leaf levels lost, plus 256 on a snapped tree
// (render_tree_code, client/render/render_internal.h).
float tree_fall(float z)
{
    return z - 4.0 * floor(z * 0.25);
}
bool tree_snapped(float z)
{
    return z >= 256.0;
}

// tip_fall_break_m (client/motion/tip_fall.c), the same bits: the height [m, tree frame] where a
// snapped stem breaks; the stump stands below it (stump.vert), the rest tips about it.
const float STUMP_MIN_M = 0.5;
const float STUMP_SPAN_M = 1.0;
float stump_break_m(int tree)
{
    return STUMP_MIN_M + STUMP_SPAN_M * hash01(uint(tree) * 2246822519u + 374761393u);
}
// The ragged edge of the break: height above or below stump_break_m [m] in segment k of
// STUMP_SEG around the stem; the stump's top and the fallen butt share it, so they fit.
const int STUMP_SEG = 12;
float stump_jag_m(int tree, int k)
{
    float u = hash01(uint(tree) * 977u + uint(k % STUMP_SEG) * 131u + 11u);
    return (k % 2 == 0 ? 0.10 : -0.06) + 0.14 * (u - 0.5);
}
// The fall's pivot [m up the stem]: the break on a snapped tree, else the base.
float tree_pivot_m(int tree, float z)
{
    return tree_snapped(z) ? stump_break_m(tree) : 0.0;
}

// wire_damage_leaf_kept (protocol/wire.h), the same bits: whether a leaf slot of a tree
// stays on a crown with `level` of 32 left.
bool leaf_kept(uint tree, uint slot, float z)
{
    uint level = 32u - uint(floor(mod(z, 256.0) * 0.25));
    uint r = hash_u(slot * 0x9E3779B1u + 0x7F4A7C15u) +
             hash_u(tree * 0x85EBCA77u + 0x165667B1u);
    return level >= 32u || r < (level << 27u);
}

// A tree's frame: yaw about z, then tipped over its root by `fall` towards azimuth `az`
// (storm damage: a fallen tree lies; u_trees slot 1 .z (tree_fall), .w).
mat3 tree_frame(float yaw, float fall, float az)
{
    vec3 k = vec3(-sin(az), cos(az), 0.0); // axis across the fall, top goes towards az
    float c = cos(fall), s = sin(fall);
    mat3 kx = mat3(0.0, k.z, -k.y, -k.z, 0.0, k.x, k.y, -k.x, 0.0);
    return (mat3(1.0) + s * kx + (1.0 - c) * kx * kx) * rot_z(yaw);
}

// A corner of a fallen tree's impostor quad (shaders/bill.vert; the page's
// web/imp_shader.js), relative to the tree's base [m, unit scale]: f the list entry's fall
// (1 + azimuth in 1/256 turns + fall angle / π, render_bill_fall), right the camera-facing
// axis of a standing one, x -1..1 across the quad, z its height up the quad [m], hw its
// half width [m]. The up axis tips towards the azimuth by the angle about the base; the
// right axis goes from right (standing) to the horizontal across the fall (lying) by
// angle / (π/2), square to the up axis; a lying quad is lifted by hw / 2 off the ground.
vec3 bill_fallen(float f, vec3 right, float x, float z, float hw)
{
    float g = f - 1.0, k = floor(g);
    float ang = (g - k) * 3.14159265, az = k * (6.28318531 / 256.0);
    vec2 d = vec2(cos(az), sin(az));
    vec3 up = vec3(sin(ang) * d, cos(ang));
    vec3 across = vec3(-d.y, d.x, 0.0);
    across = dot(across, right) < 0.0 ? -across : across;
    float w = clamp(ang / 1.57079633, 0.0, 1.0);
    vec3 r = mix(right, across, w);
    r = normalize(r - dot(r, up) * up);
    return r * (x * hw) + up * z + vec3(0.0, 0.0, 0.5 * hw * w);
}

// A point p of the tree frame [m, unit scale] in the world: turned by rz (tree_frame)
// about the pivot piv_m up the stem (tree_pivot_m; rz's yaw keeps the stem axis), scaled
// by `scale`, placed at `pos`.
vec3 tree_point(vec3 p, mat3 rz, float piv_m, vec3 pos, float scale)
{
    vec3 k = vec3(0.0, 0.0, piv_m);
    return pos + scale * (k + rz * (p - k));
}
