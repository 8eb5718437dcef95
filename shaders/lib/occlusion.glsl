// Ambient occlusion of the environment's light: GTAO's slice integral and multi-bounce
// fit, and the specular occlusion derived from the visibility. Pure functions, shared by
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

#endif
