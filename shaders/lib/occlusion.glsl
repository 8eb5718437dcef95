// Ambient occlusion of the environment's light: GTAO's slice integral and multi-bounce
// fit, and the specular occlusion derived from the visibility; the micro-shadowing of a
// light by the occlusion map's visibility. Pure functions, shared by
// shaders/gtao.comp, the forward pass and the verify harness; the f64 twins are in
// src/brdf/occlusion.rs.
#ifndef ARGIL_OCCLUSION_GLSL
#define ARGIL_OCCLUSION_GLSL

// Jimenez et al. 2016 eq. 7: ∫ cos(θ − γ) |sin θ| dθ over [h0, h1], h0 ≤ 0 ≤ h1.
float gtao_slice_visibility(float h0, float h1, float gamma) {
    float base = cos(gamma);
    float s = sin(gamma);
    // The integrand is ≥ 0 on the clamped horizons; rounding of the closed form is not.
    return max(0.25 * (-cos(2.0 * h0 - gamma) + base + 2.0 * h0 * s)
             + 0.25 * (-cos(2.0 * h1 - gamma) + base + 2.0 * h1 * s), 0.0);
}

// Jimenez et al. 2016 eq. 10, held in [x, 1] (the cubic is 1e-4 over 1 at x = 1).
vec3 gtao_multi_bounce(float x, vec3 albedo) {
    vec3 a = 2.0404 * albedo - 0.3324;
    vec3 b = -4.7951 * albedo + 0.6417;
    vec3 c = 2.7552 * albedo + 0.6903;
    return min(max(vec3(x), ((a * x + b) * x + c) * x), vec3(1.0));
}

// Lagarde & de Rousiers 2014 eq. 41, α = roughness² held in [0, 1] (exponent > 0).
float specular_occlusion(float n_dot_v, float x, float alpha) {
    float exponent = exp2(-16.0 * clamp(alpha, 0.0, 1.0) - 1.0);
    return clamp(pow(max(n_dot_v, 0.0) + x, exponent) - 1.0 + x, 0.0, 1.0);
}

// Micro-shadowing (Filament, after Chan 2018 "Material advances in Call of Duty: WWII"):
// the map's visibility ao read as a cone of cos² = 1 − ao around n, so a light at n·l is
// weighted saturate(n·l / √(1 − ao))². ao ≥ 1 (no cavity, an infinite aperture) leaves the
// light as it is, past the terminator too, so a map of 1 is no map.
float micro_shadowing(float n_dot_l, float ao) {
    float closed = 1.0 - ao;
    if (closed <= 0.0) return 1.0;
    float s = clamp(n_dot_l * inversesqrt(closed), 0.0, 1.0);
    return s * s;
}

// Snyder 1996, the sphere's form factor with the horizon: (1/π) ∫ max(n·l, 0) dω over the
// cap towards a sphere of angular radius α whose centre is at angle θ from the normal
// (src/brdf/object_occlusion.rs derives the branches).
float sphere_cap_irradiance(float cos_theta, float sin_alpha) {
    const float INV_PI = 0.318309886183791;
    cos_theta = clamp(cos_theta, -1.0, 1.0);
    sin_alpha = clamp(sin_alpha, 0.0, 1.0);
    if (cos_theta >= sin_alpha) return cos_theta * sin_alpha * sin_alpha;
    if (cos_theta <= -sin_alpha) return 0.0;
    float sin_theta = sqrt(1.0 - cos_theta * cos_theta);
    float x = sqrt(1.0 - sin_alpha * sin_alpha) / sin_alpha;
    float y = clamp(-x * cos_theta / sin_theta, -1.0, 1.0);
    float s = sqrt(1.0 - y * y);
    float f = (cos_theta * acos(y) - x * sin_theta * s) * sin_alpha * sin_alpha * INV_PI + atan(sin_theta * s, x) * INV_PI;
    return clamp(f, 0.0, 1.0);
}

#endif
