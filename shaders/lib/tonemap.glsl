// Display transform (GLSL 4.60): Khronos PBR Neutral tone mapping and the sRGB encoding.
// #include from a shader that declares #version 460 and GL_GOOGLE_include_directive.
// Every function has an f64 twin in src/brdf/tonemap.rs.

#ifndef ARGIL_TONEMAP_GLSL
#define ARGIL_TONEMAP_GLSL

// PBR Neutral's K_s = 0.8 − F₉₀ with F₉₀ = 0.04: compression starts at this peak.
const float START_COMPRESSION = 0.8 - 0.04;
// PBR Neutral's K_d: speed of the desaturation of compressed highlights.
const float DESATURATION = 0.15;

// Khronos PBR Neutral tone mapper (Khronos 2024); negative input is clamped to 0.
vec3 tonemap_pbr_neutral(vec3 color) {
    vec3 c = max(color, vec3(0.0));
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < START_COMPRESSION) {
        return c;
    }
    // Khronos' new_peak = 1 − d²/(peak − K_s + d) and g = 1 − 1/(K_d (peak − new_peak) + 1),
    // rearranged so nothing cancels just above the compression start: with q = peak − K_s,
    // peak − new_peak = q²/(q + d) and g = k/(k + 1), k = K_d (peak − new_peak).
    const float d = 1.0 - START_COMPRESSION;
    float q = peak - START_COMPRESSION;
    float new_peak = 1.0 - d * d / (q + d);
    float k = DESATURATION * q * (q / (q + d));
    float g = k / (k + 1.0);
    return mix(c * (new_peak / peak), vec3(new_peak), g);
}

// sRGB OETF, IEC 61966-2-1: 12.92 L below 0.0031308, else 1.055 L^(1/2.4) − 0.055; L in [0, 1].
float srgb_oetf(float linear) {
    float l = clamp(linear, 0.0, 1.0);
    return l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1.0 / 2.4) - 0.055;
}

// srgb_oetf per channel (twin: srgb_oetf_rgb).
vec3 srgb_oetf(vec3 linear) {
    return vec3(srgb_oetf(linear.r), srgb_oetf(linear.g), srgb_oetf(linear.b));
}

#endif // ARGIL_TONEMAP_GLSL
