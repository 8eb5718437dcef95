// Normal mapping (seed §3.2, eqs. 13–16): decoding tangent-space normals, blending a detail
// map over a surface map, and the tangent frame. f64 twins in src/brdf/normal_mapping.rs.
#ifndef ARGIL_NORMAL_MAPPING_GLSL
#define ARGIL_NORMAL_MAPPING_GLSL

// Values of the DETAIL_BLEND specialization constant: `as u32` of DetailBlend.
const uint DETAIL_BLEND_RNM = 0u;
const uint DETAIL_BLEND_UDN = 1u;
const uint DETAIL_BLEND_WHITEOUT = 2u;
const uint DETAIL_BLEND_SEED = 3u;
// A tangent-space normal's z is kept at least this large, so that decoding a texel with
// z ≤ 0 (filtering, compression) never flips the normal below the surface.
const float MIN_TANGENT_Z = 1e-3;
// Below this sin² of the angle between a vertex tangent and the normal, the tangent is
// degenerate: fp32 leaves T − N(N·T) an error of ~2^-23·|T|, its direction one of
// ~2^-23/sin θ, and at sin θ = 1e-2 that is 1e-5.
const float MIN_TANGENT_SIN2 = 1e-4;

// A tangent-space unit normal from an RGB texel in [0, 1] (OpenGL convention, +y = +v;
// `green_down` flips y for DirectX maps), its slope scaled by `strength`.
vec3 decode_normal(vec3 texel, bool green_down, float strength) {
    vec3 n = texel * 2.0 - 1.0;
    n.y = green_down ? -n.y : n.y;
    n.xy *= strength;
    n.z = max(n.z, MIN_TANGENT_Z);
    return normalize(n);
}

// Reoriented Normal Mapping (Barré-Brisebois & Hill 2012): the detail normal rotated by the
// rotation that takes +z to the base normal. Their t·(t·u)/t.z − u, t = base + (0, 0, 1),
// with its z written as base·u: their t.z·(t·u)/t.z − u.z carries the rounding of
// base.z + 1 (6e-8), 6e-4 of a grazing base's z (1e-4 at strength 8).
vec3 blend_rnm(vec3 base, vec3 detail) {
    vec3 u = detail * vec3(-1.0, -1.0, 1.0);
    float z = dot(base, u);
    float k = (z + u.z) / (base.z + 1.0);
    return normalize(vec3(base.xy * k + detail.xy, z));
}

// UDN blending (Barré-Brisebois & Hill 2012): slopes added, the base's z kept.
vec3 blend_udn(vec3 base, vec3 detail) {
    return normalize(vec3(base.xy + detail.xy, base.z));
}

// Whiteout blending (Barré-Brisebois & Hill 2012): slopes added, z multiplied.
vec3 blend_whiteout(vec3 base, vec3 detail) {
    return normalize(vec3(base.xy + detail.xy, base.z * detail.z));
}

// The report's eq. 16, n = (v1 + v2)·(1, 1, 0.5), on decoded normals, then normalised
// (the report's version works on encoded texels and leaves n unnormalised).
vec3 blend_seed(vec3 base, vec3 detail) {
    return normalize((base + detail) * vec3(1.0, 1.0, 0.5));
}

vec3 blend_detail(uint mode, vec3 base, vec3 detail) {
    if (mode == DETAIL_BLEND_UDN) return blend_udn(base, detail);
    if (mode == DETAIL_BLEND_WHITEOUT) return blend_whiteout(base, detail);
    if (mode == DETAIL_BLEND_SEED) return blend_seed(base, detail);
    return blend_rnm(base, detail);
}

// A tangent-space normal in world space through the TBN frame (seed eqs. 13–15): T
// re-orthogonalised against N (interpolation bends it), B = w·(N × T) with the
// handedness w of mirrored UVs. A degenerate T (zero, or within MIN_TANGENT_SIN2 of N, at
// any length) leaves the normal N.
vec3 tangent_to_world(vec3 n_tangent_space, vec3 normal, vec4 tangent) {
    vec3 t = tangent.xyz - normal * dot(normal, tangent.xyz);
    float t2 = dot(t, t);
    if (t2 <= MIN_TANGENT_SIN2 * dot(tangent.xyz, tangent.xyz)) return normal;
    t *= inversesqrt(t2);
    vec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * cross(normal, t);
    return normalize(t * n_tangent_space.x + b * n_tangent_space.y + normal * n_tangent_space.z);
}

#endif
