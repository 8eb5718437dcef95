// The weight of one sample in the resolve of a multisampled HDR frame (Karis 2014, "High
// Quality Temporal Supersampling"): w = 1/(1 + luma), the tone map c/(1 + luma) averaged
// and inverted, written as the mean Σ w c / Σ w (src/render/msaa.rs says why). Luma is
// Rec. 709's; negative luma (debug views' signed values) counts as 0, so weights stay in
// (0, 1]. f64 twin: src/brdf/antialiasing.rs.
#ifndef ARGIL_MSAA_RESOLVE_GLSL
#define ARGIL_MSAA_RESOLVE_GLSL

const vec3 REC709_LUMA = vec3(0.2126, 0.7152, 0.0722);

float resolve_weight(vec3 radiance) {
    return 1.0 / (1.0 + max(dot(radiance, REC709_LUMA), 0.0));
}

#endif
