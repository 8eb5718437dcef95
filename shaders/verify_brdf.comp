#version 460
// `argil verify`'s harness: evaluates one function of brdf.glsl, tonemap.glsl,
// msaa_resolve.glsl, specular_aa.glsl, occlusion.glsl, env_math.glsl, normal_mapping.glsl
// or shading.glsl, chosen by the FUNCTION specialization constant, on every input tuple.
// src/verify/functions.rs and terms.rs evaluate the f64 twins on the same f32 tuples; the
// meaning of a tuple's vec4s per function is documented there and below.
#include "brdf.glsl"
#include "tonemap.glsl"
#include "normal_mapping.glsl"
#include "shading.glsl"
#include "msaa_resolve.glsl"
#include "specular_aa.glsl"
#include "occlusion.glsl"
#include "env_math.glsl"

layout(local_size_x = 64) in;

// Values of src/verify/functions.rs's `Function`; below FIRST_MODEL, a term's index in
// src/verify/terms.rs's TERMS.
layout(constant_id = 0) const uint FUNCTION = 0u;
// From here on, BRDF models of directions: f(n, v, l) and f(n, l, v) are both written.
const uint FIRST_MODEL = 36u;
const uint LAMBERT = 36u;
const uint OREN_NAYAR = 37u;
const uint EON = 38u;
const uint BLINN_PHONG = 39u;
const uint TORRANCE_SPARROW = 40u;
const uint COOK_TORRANCE_GGX_SEPARABLE = 41u;
const uint COOK_TORRANCE_GGX_CORRELATED = 42u;
const uint COOK_TORRANCE_BECKMANN_SEPARABLE = 43u;
const uint COOK_TORRANCE_BECKMANN_CORRELATED = 44u;
// From here on, unit vectors of normal_mapping.glsl, shading.glsl and env_math.glsl.
const uint FIRST_NORMAL = 48u;
const uint DECODE_NORMAL = 48u;
const uint BLEND_RNM = 49u;
const uint BLEND_UDN = 50u;
const uint BLEND_WHITEOUT = 51u;
const uint BLEND_SEED = 52u;
const uint TANGENT_TO_WORLD = 53u;
const uint VIEW_FACING_NORMAL = 54u;
const uint OCTAHEDRAL_DIRECTION = 55u;
// From here on, brdf_cos of shading.glsl: FUNCTION = FIRST_SHADING + 256 horizon +
// 64 subsurface + 16 diffuse + 4 specular + 2 distribution + geometry, the models'
// specialization constant values; horizon 1 is brdf_cos_seed.
const uint FIRST_SHADING = 64u;

// Terms: a holds the scalar arguments, d a colour argument.
// Models: a = (n, α / σ / r), b = (v, 0), c = (l, 0), d = (F0 or ρ, 0).
// Unit vectors: the vector arguments in a, b, c (tangent: all of c), scalars in a.w, b.x; points in a.xy.
// brdf_cos: a = (n_geometric, roughness), b = (v, f0), c = (l, diffuse_roughness),
// d = (base_color, wrap_intensity), e = (specular_color, wrap), f = (wrap_color, wrap_width),
// g = (scatter_color, curvature), h = (metallic, 0, 0, 0), with scatter_radius 1 (only σκ
// counts).
struct Tuple {
    vec4 a;
    vec4 b;
    vec4 c;
    vec4 d;
    vec4 e;
    vec4 f;
    vec4 g;
    vec4 h;
};

layout(std430, set = 0, binding = 0) readonly buffer Inputs {
    Tuple tuples[];
};
// Two per tuple: the value, and for models the value with v and l exchanged.
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {
    vec4 results[];
};
layout(push_constant) uniform Push {
    uint count;
} push;

// A scalar or colour term of the library: case k calls TERMS[k] of src/verify/terms.rs,
// which names its arguments (scalars in a, a colour in d), one line a term.
vec4 term(Tuple t) {
    vec4 a = t.a;
    switch (FUNCTION) {
    case 0u: return vec4(d_ggx(a.x, a.y, a.z));
    case 1u: return vec4(d_beckmann(a.x, a.y, a.z));
    case 2u: return vec4(lambda_ggx(a.x, a.y));
    case 3u: return vec4(lambda_beckmann(a.x, a.y));
    case 4u: return vec4(g1_smith_ggx(a.x, a.y));
    case 5u: return vec4(g2_smith_separable_ggx(a.x, a.y, a.z));
    case 6u: return vec4(g2_smith_correlated_ggx(a.x, a.y, a.z));
    case 7u: return vec4(g2_smith_separable_beckmann(a.x, a.y, a.z));
    case 8u: return vec4(g2_smith_correlated_beckmann(a.x, a.y, a.z));
    case 9u: return vec4(g2_v_cavity(a.x, a.y, a.z, a.w));
    case 10u: return vec4(f_schlick(t.d.rgb, a.x), f_schlick_scalar(t.d.r, a.x));
    case 11u: return vec4(e_fon_approx(a.x, a.y));
    case 12u: return vec4(tonemap_pbr_neutral(t.d.rgb), 0.0);
    case 13u: return vec4(srgb_oetf(t.d.rgb), srgb_oetf(t.d.r));
    case 14u: return vec4(wrap_seed(a.x, a.y, a.z));
    case 15u: return vec4(wrap_energy_conserving(a.x, a.y));
    case 16u: return vec4(spec_blinn_phong(a.x, a.y, a.z, t.d.rgb, a.w), 0.0);
    case 17u: return vec4(shadow_terminator(a.x, a.y, a.z));
    case 18u: return vec4(preintegrated_d(a.x, a.y), preintegrated_kernel(a.y));
    case 19u: return vec4(wrap_energy_conserving_sh_kernel(a.x), 0.0);
    case 20u: return vec4(resolve_weight(t.d.rgb));
    case 21u: return vec4(specular_aa_roughness(a.x, a.y));
    case 22u: return vec4(gtao_slice_visibility(a.x, a.y, a.z));
    case 23u: return vec4(gtao_multi_bounce(a.x, t.d.rgb), 0.0);
    case 24u: return vec4(specular_occlusion(a.x, a.y, a.z));
    case 25u: return vec4(plane_point_irradiance(a.x, a.y));
    case 26u: return vec4(specular_energy_compensation(a.x, t.d.rgb), 0.0);
    case 27u: return vec4(sphere_cap_irradiance(a.x, a.y));
    case 28u: return vec4(micro_shadowing(a.x, a.y));
    case 29u: return vec4(prefiltered_taps(a.x), 0.0);
    case 30u: return vec4(prefiltered_lod(a.x, a.y));
    case 31u: return vec4(sun_alpha(a.x, a.y));
    case 32u: return vec4(octahedral_uv(a.xyz, a.w), 0.0, 0.0);
    }
    return vec4(0.0);
}

// A BRDF model f(n, v, l) (no cosine), its arguments derived from the directions as a
// renderer derives them; p is α (specular), σ (Oren-Nayar) or r (EON).
vec3 model(vec3 n, vec3 v, vec3 l, float p, vec3 colour) {
    vec3 h = safe_half_vector(v, l, n);
    vec3 n_cross_h = cross(n, h);
    float nxh2 = dot(n_cross_h, n_cross_h);
    float nv = dot(n, v);
    float nl = dot(n, l);
    float nh = dot(n, h);
    float vh = dot(v, h);
    switch (FUNCTION) {
    case LAMBERT: // diffuse_lambert()
        return vec3(diffuse_lambert());
    case OREN_NAYAR: // diffuse_oren_nayar(σ, n, v, l)
        return vec3(diffuse_oren_nayar(p, n, v, l));
    case EON: // diffuse_eon(ρ, r, n·v, n·l, v·l)
        return diffuse_eon(colour, p, nv, nl, dot(v, l));
    case BLINN_PHONG: // spec_blinn_phong(α, n·h, |n×h|², F0, v·h)
        return spec_blinn_phong(p, nh, nxh2, colour, vh);
    case TORRANCE_SPARROW: // spec_torrance_sparrow(α, n·v, n·l, n·h, |n×h|², F0, v·h)
        return spec_torrance_sparrow(p, nv, nl, nh, nxh2, colour, vh);
    case COOK_TORRANCE_GGX_SEPARABLE: // spec_cook_torrance(…, GGX, separable Smith)
        return spec_cook_torrance(p, nv, nl, nh, nxh2, colour, vh, DISTRIBUTION_GGX, GEOMETRY_SMITH_SEPARABLE);
    case COOK_TORRANCE_GGX_CORRELATED: // spec_cook_torrance(…, GGX, height-correlated Smith)
        return spec_cook_torrance(p, nv, nl, nh, nxh2, colour, vh, DISTRIBUTION_GGX, GEOMETRY_SMITH_CORRELATED);
    case COOK_TORRANCE_BECKMANN_SEPARABLE: // spec_cook_torrance(…, Beckmann, separable Smith)
        return spec_cook_torrance(p, nv, nl, nh, nxh2, colour, vh, DISTRIBUTION_BECKMANN, GEOMETRY_SMITH_SEPARABLE);
    case COOK_TORRANCE_BECKMANN_CORRELATED: // spec_cook_torrance(…, Beckmann, height-correlated Smith)
        return spec_cook_torrance(p, nv, nl, nh, nxh2, colour, vh, DISTRIBUTION_BECKMANN, GEOMETRY_SMITH_CORRELATED);
    }
    return vec3(0.0);
}

// A function of normal_mapping.glsl or shading.glsl whose value is a unit vector.
vec3 unit_vector(Tuple t) {
    switch (FUNCTION) {
    case DECODE_NORMAL: // decode_normal(texel, green_down, strength): a = (texel, strength), b.x = green_down
        return decode_normal(t.a.xyz, t.b.x != 0.0, t.a.w);
    case BLEND_RNM: // blend_rnm(base, detail): a = base, b = detail
        return blend_rnm(t.a.xyz, t.b.xyz);
    case BLEND_UDN: // blend_udn(base, detail)
        return blend_udn(t.a.xyz, t.b.xyz);
    case BLEND_WHITEOUT: // blend_whiteout(base, detail)
        return blend_whiteout(t.a.xyz, t.b.xyz);
    case BLEND_SEED: // blend_seed(base, detail)
        return blend_seed(t.a.xyz, t.b.xyz);
    case TANGENT_TO_WORLD: // tangent_to_world(n_ts, normal, tangent): a = n_ts, b = normal, c = tangent
        return tangent_to_world(t.a.xyz, t.b.xyz, t.c);
    case VIEW_FACING_NORMAL: // view_facing_normal(n, v): a = n, b = v
        return view_facing_normal(t.a.xyz, t.b.xyz);
    case OCTAHEDRAL_DIRECTION: // octahedral_direction(p): a.xy = p
        return octahedral_direction(t.a.xy);
    }
    return vec3(0.0);
}

// brdf_cos (or brdf_cos_seed) with shading normal +z, the frame where n × h is exact in fp32
// as for the models (n_geometric leans away from it instead), and the models FUNCTION
// encodes.
vec3 shading(Tuple t) {
    uint code = FUNCTION - FIRST_SHADING;
    ShadingModels models = ShadingModels((code >> 4) & 3u, (code >> 2) & 3u, (code >> 1) & 1u, code & 1u,
                                         (code >> 6) & 3u);
    // No maps and no flags: brdf_cos does not read them.
    Material m = material_zero();
    m.base_color = vec4(t.d.rgb, 1.0);
    m.specular_color = vec4(t.e.rgb, 1.0);
    m.wrap_color = vec4(t.f.rgb, t.d.w);
    m.scatter = vec4(t.g.rgb, 1.0);
    m.roughness = t.a.w;
    m.f0 = t.b.w;
    m.diffuse_roughness = t.c.w;
    m.wrap = t.e.w;
    m.wrap_width = t.f.w;
    m.metallic = t.h.x;
    if ((code >> 8) == 1u) return brdf_cos_seed(models, m, vec3(0.0, 0.0, 1.0), t.b.xyz, t.c.xyz, t.g.w);
    return brdf_cos(models, m, vec3(0.0, 0.0, 1.0), t.a.xyz, t.b.xyz, t.c.xyz, t.g.w);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    Tuple t = tuples[i];
    vec4 swapped = vec4(0.0);
    if (FUNCTION >= FIRST_SHADING) {
        results[2 * i] = vec4(shading(t), 0.0);
    } else if (FUNCTION >= FIRST_NORMAL) {
        results[2 * i] = vec4(unit_vector(t), 0.0);
    } else if (FUNCTION >= FIRST_MODEL) {
        results[2 * i] = vec4(model(t.a.xyz, t.b.xyz, t.c.xyz, t.a.w, t.d.rgb), 0.0);
        swapped = vec4(model(t.a.xyz, t.c.xyz, t.b.xyz, t.a.w, t.d.rgb), 0.0);
    } else {
        results[2 * i] = term(t);
    }
    results[2 * i + 1] = swapped;
}
