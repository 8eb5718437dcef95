// Shading of one surface point: the material's models put together, for point lights
// (environment.glsl integrates them over an environment). Shared by the forward pass and
// compute test harnesses (so no derivatives here: compute shaders have none); the f64
// twins are in src/brdf/shading.rs.
#ifndef ARGIL_SHADING_GLSL
#define ARGIL_SHADING_GLSL
#include "brdf.glsl"
#include "material.glsl"
#include "subsurface.glsl"

// Values of the models' specialization constants: `as u32` of the Rust enums in
// src/brdf/shading.rs.
const uint DIFFUSE_LAMBERT = 0u;
const uint DIFFUSE_OREN_NAYAR = 1u;
const uint DIFFUSE_EON = 2u;
const uint DIFFUSE_NONE = 3u;
const uint SPECULAR_COOK_TORRANCE = 0u;
const uint SPECULAR_TORRANCE_SPARROW = 1u;
const uint SPECULAR_BLINN_PHONG = 2u;
const uint SPECULAR_NONE = 3u;

struct ShadingModels {
    uint diffuse;
    uint specular;
    uint distribution;
    uint geometry;
    uint subsurface;
};

// A light closer than 1e-4 to a surface point would give unbounded irradiance.
const float MIN_LIGHT_DISTANCE2 = 1e-8;
// Below this squared length an interpolated normal has no direction.
const float MIN_NORMAL_LENGTH2 = 1e-12;

// d at unit length, or 0 where it has no direction (MIN_NORMAL_LENGTH2).
vec3 unit_or_zero(vec3 d) {
    float len2 = dot(d, d);
    return len2 > MIN_NORMAL_LENGTH2 ? d * inversesqrt(len2) : vec3(0.0);
}
// Smallest n·v of a shading normal after it is turned towards the viewer.
const float MIN_SHADING_N_DOT_V = 1e-3;

// Irradiance per unit intensity on a plane from a point light `height` above it at squared
// distance distance2 (the inverse-square law with Lambert's cosine): cos θ / d² =
// height / d³; 0 where the light is not above the plane.
float plane_point_irradiance(float height, float distance2) {
    if (height <= 0.0) return 0.0;
    return height * inversesqrt(distance2) / distance2;
}

// A visible point's shading normal cannot face away from the eye: one that does (normal
// maps, interpolated normals at silhouettes) is turned towards v, continuously, until
// n·v = m = MIN_SHADING_N_DOT_V before normalisation; after it, for unit n and v,
// n·v ≥ m/√(1 + m²) (at n·v = 0). The bent n + v·(m − n·v) is computed as
// s + v·(m − |s|²/2), s = n + v, 1 + n·v = |s|²/2: as v → −n, fp32 n·v rounds 1 + n·v,
// and with it the bent normal, which is only m long there (a component was 4e-2 off at
// n·v = −1 + 3e-7); n + v is exact there (Sterbenz), and |s|²/2 as good as s.
vec3 view_facing_normal(vec3 n, vec3 v) {
    float n_dot_v = dot(n, v);
    if (n_dot_v >= MIN_SHADING_N_DOT_V) return n;
    vec3 s = n + v;
    return normalize(s + v * (MIN_SHADING_N_DOT_V - 0.5 * dot(s, s)));
}

// Chiang, Li & Burley 2019 ("Taming the Shadow Terminator"): the shadowing of a bumped
// surface whose shading normal n_s leans away from its geometric normal n_g,
// G = min(1, (n_g·l)/((n_s·l)(n_g·n_s))), smoothed as −G³ + G² + G; 0 below n_g's horizon.
float shadow_terminator(float ng_dot_l, float ns_dot_l, float ng_dot_ns) {
    if (ng_dot_l <= 0.0 || ns_dot_l <= 0.0) return 0.0;
    float g = min(ng_dot_l / (ns_dot_l * max(ng_dot_ns, MIN_N_DOT_V)), 1.0);
    return g * (1.0 + g * (1.0 - g));
}

// The diffuse lobe f_d (without the cosine), albedo included.
vec3 diffuse_lobe(uint model, Material m, vec3 n, vec3 v, vec3 l, float n_dot_v, float n_dot_l) {
    if (model == DIFFUSE_LAMBERT) return diffuse_color(m) * diffuse_lambert();
    if (model == DIFFUSE_OREN_NAYAR) return diffuse_color(m) * diffuse_oren_nayar(m.diffuse_roughness, n, v, l);
    if (model == DIFFUSE_EON) return diffuse_eon(diffuse_color(m), m.diffuse_roughness, n_dot_v, n_dot_l, dot(v, l));
    return vec3(0.0);
}

// The specular lobe f_s (without the cosine), tinted by the material's specular colour.
vec3 specular_lobe(ShadingModels models, Material m, vec3 n, vec3 v, vec3 l, float n_dot_v, float n_dot_l) {
    if (models.specular == SPECULAR_NONE) return vec3(0.0);
    float alpha = clamp_alpha(m.roughness * m.roughness);
    vec3 h = safe_half_vector(v, l, n);
    vec3 n_cross_h = cross(n, h);
    float n_dot_h = max(dot(n, h), 0.0);
    float len2 = dot(n_cross_h, n_cross_h);
    float v_dot_h = max(dot(v, h), 0.0);
    vec3 f0 = specular_f0(m);
    vec3 f;
    if (models.specular == SPECULAR_COOK_TORRANCE) {
        f = spec_cook_torrance(alpha, n_dot_v, n_dot_l, n_dot_h, len2, f0, v_dot_h,
                               int(models.distribution), int(models.geometry));
    } else if (models.specular == SPECULAR_TORRANCE_SPARROW) {
        f = spec_torrance_sparrow(alpha, n_dot_v, n_dot_l, n_dot_h, len2, f0, v_dot_h);
    } else {
        f = spec_blinn_phong(alpha, n_dot_h, len2, f0, v_dot_h);
    }
    return m.specular_color.rgb * f;
}

// Whether the subsurface model moves diffuse light across the terminator
// (subsurface_transfer) rather than adding a term.
bool subsurface_redistributes(uint model) {
    return model == SUBSURFACE_ENERGY_CONSERVING_WRAP || model == SUBSURFACE_PRE_INTEGRATED;
}

// Whether the subsurface term lights anything: only it reaches below the horizon.
bool subsurface_lights(ShadingModels models, Material m) {
    if (models.subsurface == SUBSURFACE_SEED) return m.wrap_color.a > 0.0;
    return subsurface_redistributes(models.subsurface) && models.diffuse != DIFFUSE_NONE;
}

// The reach of a redistributing model per channel: w · scatter_color for the
// energy-conserving wrap, t = σκ with σ = scatter_radius · scatter_color for the
// pre-integrated model, κ the surface's curvature (concave counts as flat).
vec3 subsurface_reach(uint model, Material m, float curvature) {
    if (model == SUBSURFACE_ENERGY_CONSERVING_WRAP) return m.wrap * m.scatter.rgb;
    return m.scatter.rgb * (m.scatter.a * max(curvature, 0.0));
}

// The subsurface term, per unit irradiance: the report's wrap (eq. 18, colour ×
// intensity/π × s) for SUBSURFACE_SEED, or ρ/π (K − max(0, n·l)) for the models that move
// light across the terminator.
vec3 subsurface_cos(ShadingModels models, Material m, float n_dot_l, float curvature) {
    if (!subsurface_lights(models, m)) return vec3(0.0);
    if (models.subsurface == SUBSURFACE_SEED) {
        return m.wrap_color.rgb * (m.wrap_color.a / PI) * wrap_seed(n_dot_l, m.wrap, m.wrap_width);
    }
    vec3 transfer = subsurface_transfer(models.subsurface, n_dot_l,
                                        subsurface_reach(models.subsurface, m, curvature));
    return diffuse_color(m) / PI * (transfer - max(n_dot_l, 0.0));
}

// `lit` (the lobes plus the subsurface term), clamped at 0 for the models that take light
// away: where the lobes are shadowed or below Lambert, less may be left than they move.
// A NaN is kept (max(NaN, 0) may be either), so that checks still see it.
vec3 with_subsurface(ShadingModels models, vec3 lit) {
    if (!subsurface_redistributes(models.subsurface)) return lit;
    return mix(lit, vec3(0.0), lessThan(lit, vec3(0.0)));
}

// Reflected radiance per unit irradiance E⊥ arriving along l, for shading normal n
// (already facing the viewer) on a surface of geometric normal n_geometric and curvature
// `curvature`: f(n, v, l)(n·l) times the terminator shadowing, plus the subsurface term,
// which lights where n·l ≤ 0 too.
vec3 brdf_cos(ShadingModels models, Material m, vec3 n, vec3 n_geometric, vec3 v, vec3 l, float curvature) {
    float n_dot_l = dot(n, l);
    vec3 subsurface = subsurface_cos(models, m, n_dot_l, curvature);
    if (n_dot_l <= 0.0) return subsurface;
    float n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    vec3 f = diffuse_lobe(models.diffuse, m, n, v, l, n_dot_v, n_dot_l)
           + specular_lobe(models, m, n, v, l, n_dot_v, n_dot_l);
    float shadowing = shadow_terminator(dot(n_geometric, l), n_dot_l, dot(n_geometric, n));
    return with_subsurface(models, f * (n_dot_l * shadowing) + subsurface);
}

// The report's composition, for comparison (`horizon = "seed"`): i = d + s (seed eq. 3)
// with d the diffuse lobe times n·l and s the specular BRDF of eq. 11 without a cosine,
// hard-coded to 0 where n·l ≤ 0 (the report's fix of its figure 5a); the subsurface term
// is added as in brdf_cos. Where n·l → 0⁺ the specular term stays finite and non-zero, so
// the cutoff is a visible line (figure 5b).
vec3 brdf_cos_seed(ShadingModels models, Material m, vec3 n, vec3 v, vec3 l, float curvature) {
    float n_dot_l = dot(n, l);
    vec3 subsurface = subsurface_cos(models, m, n_dot_l, curvature);
    if (n_dot_l <= 0.0) return subsurface;
    float n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    vec3 lobes = diffuse_lobe(models.diffuse, m, n, v, l, n_dot_v, n_dot_l) * n_dot_l
               + specular_lobe(models, m, n, v, l, n_dot_v, n_dot_l);
    return with_subsurface(models, lobes + subsurface);
}

#endif
