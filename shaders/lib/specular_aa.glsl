// Specular anti-aliasing of normal-mapped detail (Tokuyoshi & Kaplanyan 2019, "Improved
// Geometric Specular Antialiasing", eq. 13, as Filament's normalFiltering applies it): a
// shading normal that turns quickly across the screen puts many facets' highlights into
// one pixel, which a single shading sample aliases; the GGX lobe is widened to cover them,
// α'² = α² + min(2σ²(|∂n/∂x|² + |∂n/∂y|²), κ), σ² = 1/(2π) the variance of the pixel's
// filter kernel and κ = 0.18 the paper's clamp of the widening. f64 twin:
// src/brdf/antialiasing.rs.
#ifndef ARGIL_SPECULAR_AA_GLSL
#define ARGIL_SPECULAR_AA_GLSL

const float SPECULAR_AA_KERNEL_VARIANCE = 0.15915494;
const float SPECULAR_AA_MAX_WIDENING = 0.18;

// The perceptual roughness (α = roughness²) of the lobe widened by `normal_change2`,
// |∂n/∂x|² + |∂n/∂y|² of the shading normal; at most 1.
float specular_aa_roughness(float roughness, float normal_change2) {
    float r2 = roughness * roughness;
    float widening = min(2.0 * SPECULAR_AA_KERNEL_VARIANCE * normal_change2, SPECULAR_AA_MAX_WIDENING);
    return sqrt(sqrt(min(r2 * r2 + widening, 1.0)));
}

#endif
