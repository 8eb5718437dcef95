//! Display transform: Khronos PBR Neutral tone mapping and the sRGB encoding.

use super::Vec3;

/// PBR Neutral's K_s = 0.8 − F₉₀ with F₉₀ = 0.04: compression starts at this peak.
pub const START_COMPRESSION: f64 = 0.8 - 0.04;
/// PBR Neutral's K_d: speed of the desaturation of compressed highlights.
pub const DESATURATION: f64 = 0.15;

/// Khronos PBR Neutral tone mapper (Khronos 2024); negative input is clamped to 0.
pub fn tonemap_pbr_neutral(color: Vec3) -> Vec3 {
    let c = color.map(|x| x.max(0.0));
    let x = c[0].min(c[1]).min(c[2]);
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c.map(|v| v - offset);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < START_COMPRESSION {
        return c;
    }
    // Rearranged as in the GLSL, where 1 − 1/(1 + x) and peak − new_peak cancel in fp32.
    let d = 1.0 - START_COMPRESSION;
    let q = peak - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (q + d);
    let k = DESATURATION * q * (q / (q + d));
    let g = k / (k + 1.0);
    c.map(|v| v * new_peak / peak * (1.0 - g) + new_peak * g)
}

/// sRGB EOTF, IEC 61966-2-1 (as Vulkan decodes `_SRGB` formats): E/12.92 up to 0.04045,
/// else ((E + 0.055)/1.055)^2.4; E in [0, 1].
pub fn srgb_eotf(encoded: f64) -> f64 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB OETF, IEC 61966-2-1: 12.92 L below 0.0031308, else 1.055 L^(1/2.4) − 0.055; L in [0, 1].
pub fn srgb_oetf(linear: f64) -> f64 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// `srgb_oetf` per channel (GLSL's vec3 overload).
pub fn srgb_oetf_rgb(linear: Vec3) -> Vec3 {
    linear.map(srgb_oetf)
}

/// Linear Rec. 709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B.
pub fn luminance(c: Vec3) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// The display transform of `tonemap.frag` for an 8-bit sRGB image: PBR Neutral (negative
/// input clamped), the sRGB OETF, rounded. Exposure is the caller's to apply first.
pub fn display_srgb8(linear: Vec3) -> [u8; 3] {
    srgb_oetf_rgb(tonemap_pbr_neutral(linear)).map(|c| (c * 255.0).round() as u8)
}
