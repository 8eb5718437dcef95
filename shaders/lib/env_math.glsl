// Environment lighting math without resources: cube and equirectangular directions,
// spherical harmonics, and the sampling strategies with their pdfs. Shared by the forward
// pass and the precomputation compute shaders; every function has an f64 twin of the same
// name in src/brdf/environment.rs.
#ifndef ARGIL_ENV_MATH_GLSL
#define ARGIL_ENV_MATH_GLSL
#include "brdf.glsl"

const float TWO_PI = 2.0 * PI;
// 2^-32: maps a 32-bit radical inverse to [0, 1).
const float RADICAL_INVERSE_SCALE = 2.3283064365386963e-10;

// ---- Directions ----

// The point (a, b) in [−1, 1]² on cube face `face` (+x, −x, +y, −y, +z, −z) of the cube
// of half-side 1: the inverse of Vulkan's cube map face selection (spec "Cube Map Face
// Selection", s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2), so a = 2s − 1 and b = 2t − 1.
// Its major component is ±1 exactly: the ray through it per unit major-axis distance.
vec3 cube_face_point(uint face, vec2 ab) {
    float a = ab.x;
    float b = ab.y;
    vec3 d;
    if (face == 0u) d = vec3(1.0, -b, -a);
    else if (face == 1u) d = vec3(-1.0, -b, a);
    else if (face == 2u) d = vec3(a, 1.0, b);
    else if (face == 3u) d = vec3(a, -1.0, -b);
    else if (face == 4u) d = vec3(a, -b, 1.0);
    else d = vec3(-a, -b, -1.0);
    return d;
}

// The unit direction through (a, b) on cube face `face` (cube_face_point).
vec3 cube_direction(uint face, vec2 ab) {
    return normalize(cube_face_point(face, ab));
}

// +1 or −1 per component, +1 at zero: the octahedral fold's quadrant.
vec2 sign_not_zero(vec2 p) {
    return vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
}

// Where split sum reads direction d in an octahedral map (Engelhardt & Dachsbacher 2008)
// `side` texels across: d's point p in [−1, 1]², the octahedron |x| + |y| + |z| = 1
// projected onto z = 0 with its lower half folded out over the square's corners, inside
// a border of one texel (octahedral_direction).
vec2 octahedral_uv(vec3 d, float side) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0) p = (1.0 - abs(p.yx)) * sign_not_zero(p);
    return ((p + 1.0) * (0.5 * (side - 2.0)) + 1.0) / side;
}

// The unit direction of point p of an octahedral map, octahedral_uv's inverse. A point
// past the square's edge, a border texel's, is read as its neighbour across the edge, the
// point mirrored about the edge's midpoint (the edge's halves are one edge of the
// octahedron), so that bilinear lookups cross the fold as if it were not there.
vec3 octahedral_direction(vec2 p) {
    if (abs(p.x) > 1.0) p = vec2(sign_not_zero(p).x * (2.0 - abs(p.x)), -p.y);
    if (abs(p.y) > 1.0) p = vec2(-p.x, sign_not_zero(p).y * (2.0 - abs(p.y)));
    vec3 d = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * sign_not_zero(d.xy);
    return normalize(d);
}

// The point of an octahedral map `side` texels across, a border of one included, at the
// centre of texel `texel`: the border texels' half a texel past the square's edges.
vec2 octahedral_texel_point(vec2 texel, float side) {
    return (texel - 0.5) * (2.0 / (side - 2.0)) - 1.0;
}

// Where direction d of the upper hemisphere (y ≥ 0) falls in [0, 1]²: the octahedral map's
// upper half (Engelhardt & Dachsbacher 2008), |x| + |z| ≤ 1 on the plane y = 0, turned by
// 45° to fill the square, whose edge is the horizon.
vec2 hemisphere_uv(vec3 d) {
    vec2 p = d.xz / (abs(d.x) + abs(d.y) + abs(d.z));
    return vec2(p.x + p.y, p.x - p.y) * 0.5 + 0.5;
}

// The unit direction at point uv of [0, 1]²: hemisphere_uv's inverse.
vec3 hemisphere_direction(vec2 uv) {
    vec2 s = uv * 2.0 - 1.0;
    vec2 p = vec2(s.x + s.y, s.x - s.y) * 0.5;
    return normalize(vec3(p.x, 1.0 - abs(p.x) - abs(p.y), p.y));
}

// The solid angle of triangle (a, b, c) seen from the origin, given its triple product
// a·(b×c) (Van Oosterom & Strackee 1983): 2 atan2(a·(b×c), |a||b||c| + (a·b)|c| + (a·c)|b|
// + (b·c)|a|).
float triangle_solid_angle(vec3 a, vec3 b, vec3 c, float triple) {
    float la = length(a);
    float lb = length(b);
    float lc = length(c);
    return 2.0 * atan(triple, la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
}

// The exact solid angle of texel (x, y) of a cube face of size² texels, the face being
// [−1, 1]² at unit distance: its two triangles. Their triple product is the texel's area,
// exact in fp32 like its corners, so nothing cancels (unlike the difference of atan terms
// of the rectangle formula, which loses a 512² texel to rounding).
float cube_texel_solid_angle(uvec2 texel, uint size) {
    vec2 lo = vec2(texel) / float(size) * 2.0 - 1.0;
    vec2 hi = vec2(texel + 1u) / float(size) * 2.0 - 1.0;
    vec3 a = vec3(lo, 1.0);
    vec3 b = vec3(hi.x, lo.y, 1.0);
    vec3 c = vec3(hi, 1.0);
    vec3 d = vec3(lo.x, hi.y, 1.0);
    float area = (hi.x - lo.x) * (hi.y - lo.y);
    return triangle_solid_angle(a, b, c, area) + triangle_solid_angle(a, c, d, area);
}

// Equirectangular (u, v) of unit d: u = 0.5 looks along −z and grows towards +x, v = 0
// is +y (the top row). Straight up or down, where atan2 is undefined, u = 0.5.
vec2 equirect_uv(vec3 d) {
    float horizontal2 = d.x * d.x + d.z * d.z;
    float u = horizontal2 > 0.0 ? 0.5 + atan(d.x, -d.z) / TWO_PI : 0.5;
    return vec2(u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// The direction of equirectangular (u, v): the inverse of equirect_uv.
vec3 equirect_direction(vec2 uv) {
    float theta = uv.y * PI;
    float phi = (uv.x - 0.5) * TWO_PI;
    return vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// d rotated about +y by the angle whose (cos, sin) is cs: (x c + z s, y, −x s + z c).
vec3 rotate_y(vec3 d, vec2 cs) {
    return vec3(d.x * cs.x + d.z * cs.y, d.y, -d.x * cs.y + d.z * cs.x);
}

// The report's eq. 17: uv = n(2(n·v)) − v, normalised; the mirror direction of v.
vec3 seed_reflection(vec3 n, vec3 v) {
    return normalize(n * (2.0 * dot(n, v)) - v);
}

// The mean angle from n of a specular lobe F0 A + B, given the angles θ_A and θ_B of its
// parts' mean directions (the BRDF tables' z and w): the energy-weighted mean, taking
// `f0_a` = F0 A and `b` = B. Where a rough lobe's mass lies off-specular, towards n, this
// is where its prefiltered radiance is read.
float lobe_mean_angle(float f0_a, float b, float theta_a, float theta_b) {
    float energy = f0_a + b;
    return energy > 0.0 ? (f0_a * theta_a + b * theta_b) / energy : 0.0;
}

// The direction at angle θ from n towards the mirror direction of v, in the plane of
// incidence; n where v is n and that plane undefined (the tables' θ is 0 there).
vec3 lobe_direction(vec3 n, vec3 v, float theta) {
    vec3 towards_mirror = n * dot(n, v) - v;
    float len = length(towards_mirror);
    if (len < 1e-6) return n;
    return n * cos(theta) + towards_mirror * (sin(theta) / len);
}

// The prefiltered cube's mip for a lobe of α: mip k ≥ 1 holds α = 2^(k − last), an octave
// apart, so the trilinear blend mixes lobes at most twice apart in α (even steps in
// roughness mixed lobes four times apart, whose blend is too peaked under a sun); mip 0
// holds the mirror, blended linearly in α up to mip 1.
float prefiltered_lod(float alpha, float last_level) {
    float first = exp2(1.0 - last_level);
    return alpha < first ? alpha / first : last_level + log2(alpha);
}

// A GGX lobe of α lighting a disc of angular radius θ as one direction: the lobe's l has
// variance 2α² across each axis near its peak and the disc θ²/4, so α'² = α² + θ²/8.
float sun_alpha(float alpha, float angular_radius) {
    return sqrt(alpha * alpha + angular_radius * angular_radius / 8.0);
}

// Most lookups of one lobe; twin PREFILTERED_MAX_TAPS in src/brdf/environment.rs.
const uint PREFILTERED_MAX_TAPS = 8u;

// The prefiltered cube holds isotropic lobes (n = v = r), but dω_l = 4 (v·h) dω_h (Walter
// et al. 2007, eq. 14): seen at n·v, a GGX lobe is n·v times as narrow across the plane of
// incidence as along it. The split sum reads it as lookups spaced evenly along the plane,
// isotropic lobes of α·width, whose mean has the lobe's variances: across 2(α n·v)², along
// 2α² (GGX's core as Beckmann's, twice its slopes' α²/2), or 4α² n·v below n·v = ½, where
// the horizon clips the lobe. As few lookups as keep neighbours within 2√2 α·width, two
// of a lookup's standard deviations, so that they read as one lobe; past
// PREFILTERED_MAX_TAPS they widen instead. Returns (lookups, width, spacing), the spacing
// per unit α, a multiple of a unit vector along the plane added to the lobe's direction.
vec3 prefiltered_taps(float n_dot_v) {
    float mu = clamp(n_dot_v, 1e-4, 1.0);
    // Variances over 2α².
    float along = min(1.0, 2.0 * mu);
    float across = mu * mu;
    float taps = clamp(ceil(sqrt(max(3.0 * along / across - 2.0, 1.0))), 1.0, float(PREFILTERED_MAX_TAPS));
    float widest = 3.0 * along / (taps * taps + 2.0);
    // along − across, factored so that nothing cancels near n·v = 1.
    float spare = mu >= 0.5 ? (1.0 - mu) * (1.0 + mu) : mu * (2.0 - mu);
    float spacing2 = across < widest ? 24.0 * along / (taps * taps + 2.0) : 24.0 * spare / max(taps * taps - 1.0, 1.0);
    return vec3(taps, sqrt(max(across, widest)), taps > 1.0 ? sqrt(spacing2) : 0.0);
}

// An orthonormal frame (t, b, n) around unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited"): frame * local takes n-space (n = +z) to world.
mat3 tangent_frame(vec3 n) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b = n.x * n.y * a;
    vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 bt = vec3(b, s + n.y * n.y * a, -n.y);
    return mat3(t, bt, n);
}

// ---- Spherical harmonics (real, bands 0–2) ----

// Funk–Hecke coefficients Â_l = 2π ∫ k(μ) P_l(μ) dμ of the clamped cosine k = max(μ, 0)/π:
// irradiance over π (Ramamoorthi & Hanrahan 2001, eq. 8, divided by π).
const vec3 SH_IRRADIANCE_OVER_PI = vec3(1.0, 2.0 / 3.0, 0.25);

// Y_lm(d) in the order (0,0), (1,−1), (1,0), (1,1), (2,−2), (2,−1), (2,0), (2,1), (2,2)
// (Ramamoorthi & Hanrahan 2001, eq. 3).
void sh_basis(vec3 d, out float y[9]) {
    y[0] = 0.28209479177387814;
    y[1] = 0.4886025119029199 * d.y;
    y[2] = 0.4886025119029199 * d.z;
    y[3] = 0.4886025119029199 * d.x;
    y[4] = 1.0925484305920792 * d.x * d.y;
    y[5] = 1.0925484305920792 * d.y * d.z;
    y[6] = 0.31539156525252005 * (3.0 * d.z * d.z - 1.0);
    y[7] = 1.0925484305920792 * d.x * d.z;
    y[8] = 0.5462742152960396 * (d.x * d.x - d.y * d.y);
}

// ∫ L(l) k(d·l) dl for radiance L with SH coefficients c and a zonal kernel k whose
// Funk–Hecke coefficients per band are `kernel` (Ramamoorthi & Hanrahan 2001, eq. 7).
vec3 sh_convolve(vec4 c[9], vec3 d, vec3 kernel) {
    float y[9];
    sh_basis(d, y);
    vec3 sum = c[0].rgb * (kernel.x * y[0]);
    for (int i = 1; i < 4; ++i) sum += c[i].rgb * (kernel.y * y[i]);
    for (int i = 4; i < 9; ++i) sum += c[i].rgb * (kernel.z * y[i]);
    return sum;
}

// Funk–Hecke coefficients 2π ∫ s(μ) P_l(μ) dμ of the report's wrap term s (eq. 18, as
// wrap_seed). s is one cubic in μ on [−w₁, w₂(1 + w₁) − w₁] (the rising smoothstep) and
// one on the next w₂(1 + w₁) (the falling one), 0 elsewhere: 3-point Gauss-Legendre per
// piece integrates s P_l (degree ≤ 5) exactly.
vec3 wrap_sh_kernel(float w1, float w2) {
    float wa = clamp(w1, 0.0, 1.0);
    float wb = max(w2, MIN_WRAP_WIDTH);
    float edges[3] = float[3](-wa, wb * (1.0 + wa) - wa, 2.0 * wb * (1.0 + wa) - wa);
    const float nodes[3] = float[3](-0.7745966692414834, 0.0, 0.7745966692414834);
    const float weights[3] = float[3](5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0);
    vec3 k = vec3(0.0);
    for (int piece = 0; piece < 2; ++piece) {
        float lo = clamp(edges[piece], -1.0, 1.0);
        float hi = clamp(edges[piece + 1], -1.0, 1.0);
        float mid = 0.5 * (lo + hi);
        float half_width = 0.5 * (hi - lo);
        for (int i = 0; i < 3; ++i) {
            float mu = mid + half_width * nodes[i];
            float s = weights[i] * half_width * wrap_seed(mu, w1, w2);
            k += s * vec3(1.0, mu, 0.5 * (3.0 * mu * mu - 1.0));
        }
    }
    return TWO_PI * k;
}

// ---- Sampling, in n-space (n = +z) ----

// Point i of the n-point Hammersley set: ((i + ½)/n, radical inverse of i in base 2).
vec2 hammersley(uint i, uint n) {
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * RADICAL_INVERSE_SCALE);
}

// The R2 sequence's steps 1/g and 1/g² (g the plastic number, x³ = x + 1) in 0.32 fixed
// point (Roberts 2018, "The Unreasonable Effectiveness of Quasirandom Sequences").
const uvec2 R2_STEP = uvec2(3242174889u, 2447445414u);

// Point k of the R2 sequence, frac(k/g, k/g²), exact mod 1 in fixed point; 0 at k = 0.
vec2 r2(uint k) {
    return vec2(k * R2_STEP) * RADICAL_INVERSE_SCALE;
}

// Cosine-weighted hemisphere (Malley's method); pdf = n·l/π.
vec3 sample_cosine(vec2 u) {
    float r = sqrt(u.x);
    float phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u.x, 0.0)));
}

float pdf_cosine(float n_dot_l) {
    return max(n_dot_l, 0.0) / PI;
}

// Uniform on the sphere; pdf = 1/(4π).
vec3 sample_uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(1.0 - z * z, 0.0));
    float phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

const float PDF_UNIFORM_SPHERE = 0.25 / PI;

// A GGX microfacet normal h distributed as the visible normals seen from v (v.z > 0),
// by Dupuy & Benyoub 2023 ("Sampling Visible GGX Normals with Spherical Caps"): a
// uniform point on the spherical cap of the stretched hemisphere, offset by v.
vec3 sample_ggx_vndf(vec3 v, float alpha, vec2 u) {
    vec3 vs = normalize(vec3(v.xy * alpha, v.z));
    float phi = TWO_PI * u.x;
    float z = (1.0 - u.y) * (1.0 + vs.z) - vs.z;
    float r = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    vec3 h = vec3(r * cos(phi), r * sin(phi), z) + vs;
    return normalize(vec3(h.xy * alpha, h.z));
}

// The pdf of l = reflect(−v, h) for h from sample_ggx_vndf: D_v(h)/(4 v·h) =
// G1(v) D(h)/(4 n·v) (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", eq. 17).
float pdf_ggx_vndf(float alpha, float n_dot_v, float n_dot_h, float n_cross_h_len2) {
    float nv = max(n_dot_v, MIN_N_DOT_V);
    return g1_smith_ggx(alpha, nv) * d_ggx(alpha, n_dot_h, n_cross_h_len2) / (4.0 * nv);
}

// Filtered importance sampling (Colbert & Křivánek 2007, GPU Gems 3 ch. 20, eq. 13
// without its +1 bias): the mip whose texel solid angle matches a sample's share
// 1/(N p) of the sphere. `n_pdf` is N times the sample's pdf; `texel_solid_angle` is
// that of an average level-0 texel, 4π/(6 w²). (Measuring the texel at the sample's
// direction instead, smaller towards a face's corners, made sampled reflection depend
// more on where a map's features fall on the cube, not less.)
float filtered_lod(float n_pdf, float texel_solid_angle) {
    return max(0.5 * log2(1.0 / (max(n_pdf, 1e-30) * texel_solid_angle)), 0.0);
}

// Samples per strategy (cosine, GGX VNDF, uniform sphere, the environment's luminance)
// out of `total`: a quarter for the wrap term when it lights (it is the only lobe reaching
// below the horizon), three quarters of the rest for the environment when it is sampled
// (a sun or a studio's boxes are where the light is, even for a glossy lobe), the rest
// split between the lobes present. Every strategy with samples covers the upper hemisphere, so
// the multi-sample balance heuristic stays unbiased for any total ≥ 1.
uvec4 strategy_counts(uint total, bool diffuse, bool specular, bool wrap, bool environment) {
    if (!diffuse && !specular) return uvec4(0u, 0u, wrap ? total : 0u, 0u);
    uint n_wrap = wrap ? max(total / 4u, 1u) : 0u;
    uint rest = total - min(n_wrap, total);
    uint n_environment = environment ? 3u * rest / 4u : 0u;
    rest -= n_environment;
    uint n_specular = specular ? (diffuse ? rest / 2u : rest) : 0u;
    return uvec4(rest - n_specular, n_specular, n_wrap, n_environment);
}

#endif
