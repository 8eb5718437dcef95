#version 460
// `argil verify`'s harness: evaluates one function of brdf.glsl / tonemap.glsl, chosen by the
// FUNCTION specialization constant, on every input tuple. src/verify/functions.rs evaluates
// the f64 twins on the same f32 tuples; the meaning of a tuple's four vec4 per function is
// documented there and next to each case below.
#include "brdf.glsl"
#include "tonemap.glsl"

layout(local_size_x = 64) in;

// Values of src/verify/functions.rs's `Function`.
layout(constant_id = 0) const uint FUNCTION = 0u;
const uint D_GGX = 0u;
const uint D_BECKMANN = 1u;
const uint LAMBDA_GGX = 2u;
const uint LAMBDA_BECKMANN = 3u;
const uint G1_SMITH_GGX = 4u;
const uint G2_SMITH_SEPARABLE_GGX = 5u;
const uint G2_SMITH_CORRELATED_GGX = 6u;
const uint G2_SMITH_SEPARABLE_BECKMANN = 7u;
const uint G2_SMITH_CORRELATED_BECKMANN = 8u;
const uint G2_V_CAVITY = 9u;
const uint F_SCHLICK = 10u;
const uint E_FON_APPROX = 11u;
const uint TONEMAP_PBR_NEUTRAL = 12u;
const uint SRGB_OETF = 13u;
const uint WRAP_SEED = 14u;
const uint WRAP_ENERGY_CONSERVING = 15u;
const uint SPEC_BLINN_PHONG = 16u;
// From here on, BRDF models of directions: f(n, v, l) and f(n, l, v) are both written.
const uint FIRST_MODEL = 32u;
const uint LAMBERT = 32u;
const uint OREN_NAYAR = 33u;
const uint EON = 34u;
const uint BLINN_PHONG = 35u;
const uint TORRANCE_SPARROW = 36u;
const uint COOK_TORRANCE_GGX_SEPARABLE = 37u;
const uint COOK_TORRANCE_GGX_CORRELATED = 38u;
const uint COOK_TORRANCE_BECKMANN_SEPARABLE = 39u;
const uint COOK_TORRANCE_BECKMANN_CORRELATED = 40u;

// Terms: a holds the scalar arguments, d a colour argument.
// Models: a = (n, α / σ / r), b = (v, 0), c = (l, 0), d = (F0 or ρ, 0).
struct Tuple {
    vec4 a;
    vec4 b;
    vec4 c;
    vec4 d;
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

// A scalar or colour term of the library.
vec4 term(Tuple t) {
    vec4 a = t.a;
    switch (FUNCTION) {
    case D_GGX: // d_ggx(α, n·h, |n×h|²)
        return vec4(d_ggx(a.x, a.y, a.z));
    case D_BECKMANN: // d_beckmann(α, n·h, |n×h|²)
        return vec4(d_beckmann(a.x, a.y, a.z));
    case LAMBDA_GGX: // lambda_ggx(α, n·x)
        return vec4(lambda_ggx(a.x, a.y));
    case LAMBDA_BECKMANN: // lambda_beckmann(α, n·x)
        return vec4(lambda_beckmann(a.x, a.y));
    case G1_SMITH_GGX: // g1_smith_ggx(α, n·x)
        return vec4(g1_smith_ggx(a.x, a.y));
    case G2_SMITH_SEPARABLE_GGX: // g2_smith_separable_ggx(α, n·v, n·l)
        return vec4(g2_smith_separable_ggx(a.x, a.y, a.z));
    case G2_SMITH_CORRELATED_GGX: // g2_smith_correlated_ggx(α, n·v, n·l)
        return vec4(g2_smith_correlated_ggx(a.x, a.y, a.z));
    case G2_SMITH_SEPARABLE_BECKMANN: // g2_smith_separable_beckmann(α, n·v, n·l)
        return vec4(g2_smith_separable_beckmann(a.x, a.y, a.z));
    case G2_SMITH_CORRELATED_BECKMANN: // g2_smith_correlated_beckmann(α, n·v, n·l)
        return vec4(g2_smith_correlated_beckmann(a.x, a.y, a.z));
    case G2_V_CAVITY: // g2_v_cavity(n·h, n·v, n·l, v·h)
        return vec4(g2_v_cavity(a.x, a.y, a.z, a.w));
    case F_SCHLICK: // f_schlick(F0, v·h) in rgb, f_schlick_scalar(F0.r, v·h) in w
        return vec4(f_schlick(t.d.rgb, a.x), f_schlick_scalar(t.d.r, a.x));
    case E_FON_APPROX: // e_fon_approx(μ, r)
        return vec4(e_fon_approx(a.x, a.y));
    case TONEMAP_PBR_NEUTRAL: // tonemap_pbr_neutral(colour)
        return vec4(tonemap_pbr_neutral(t.d.rgb), 0.0);
    case SRGB_OETF: // srgb_oetf(vec3 colour) in rgb, srgb_oetf(float colour.r) in w
        return vec4(srgb_oetf(t.d.rgb), srgb_oetf(t.d.r));
    case WRAP_SEED: // wrap_seed(n·l, w₁, w₂)
        return vec4(wrap_seed(a.x, a.y, a.z));
    case WRAP_ENERGY_CONSERVING: // wrap_energy_conserving(n·l, w)
        return vec4(wrap_energy_conserving(a.x, a.y));
    case SPEC_BLINN_PHONG: // spec_blinn_phong(α, n·h, F0, v·h) on given n·h (models derive it)
        return vec4(spec_blinn_phong(a.x, a.y, t.d.rgb, a.z), 0.0);
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
    case BLINN_PHONG: // spec_blinn_phong(α, n·h, F0, v·h)
        return spec_blinn_phong(p, nh, colour, vh);
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

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    Tuple t = tuples[i];
    if (FUNCTION >= FIRST_MODEL) {
        results[2 * i] = vec4(model(t.a.xyz, t.b.xyz, t.c.xyz, t.a.w, t.d.rgb), 0.0);
        results[2 * i + 1] = vec4(model(t.a.xyz, t.c.xyz, t.b.xyz, t.a.w, t.d.rgb), 0.0);
    } else {
        results[2 * i] = term(t);
        results[2 * i + 1] = vec4(0.0);
    }
}
