//! BRDF models of the clay material, in f64.
//!
//! Each function is the twin of the function of the same name in
//! `shaders/lib/brdf.glsl` (or `tonemap.glsl`): same arguments in the same
//! order, same guards, evaluated in f64. The shaders render with the GLSL
//! versions; tests and `argil verify` check these twins against reference
//! integrals. Directions are unit vectors in any frame; dot products are
//! passed as scalars wherever the GLSL function takes scalars.

pub mod antialiasing;
pub mod bounce;
pub mod diffuse;
pub mod energy;
pub mod distribution;
pub mod environment;
pub mod fresnel;
pub mod geometry;
pub mod luminance_distribution;
pub mod normal_mapping;
pub mod object_occlusion;
pub mod occlusion;
pub mod quadrature;
pub mod shading;
pub mod shadow;
pub mod specular;
pub mod subsurface;
pub mod tonemap;
pub mod wrap;

#[cfg(test)]
mod tests;

/// A direction or colour.
pub type Vec3 = [f64; 3];

pub const PI: f64 = std::f64::consts::PI;

/// Smallest microfacet roughness α. Measured: fp32 `d_ggx` through |n×h|² stays within
/// 3.4e-7 of f64 down to α = 1e-9, so precision does not bound α; the fp16 target does:
/// the normal-incidence Cook-Torrance peak 1/(4πα²) reaches `FP16_MAX` at α = 1.10e-3,
/// and 0.002025 (0.045², Filament's) keeps it at 1.94e4, 3.4x below.
pub const MIN_ALPHA: f64 = 0.002025;
/// Largest α: roughness = √α ≤ 1, and Blinn-Phong's exponent 2/α² − 2 is negative above it.
pub const MAX_ALPHA: f64 = 1.0;
/// Cosines are clamped up to this where they divide (Smith Λ, 1/(4 n·v n·l), tan θ):
/// a normal-mapped n·v ≤ 0 still shades, and 1/cos stays ≤ 1e4 (Filament's value).
pub const MIN_N_DOT_V: f64 = 1e-4;
/// Largest finite fp16: D·G/(4 n·v n·l) is clamped to it, so with F ≤ 1 a specular lobe
/// never puts Inf in an RGBA16F target.
pub const FP16_MAX: f64 = 65504.0;
/// |v+l|² below which v+l is fp32 rounding noise (direction error > 0.6%): h falls back to n.
pub const MIN_HALF_LEN2: f64 = 1e-10;

/// Clamps a microfacet roughness to [`MIN_ALPHA`, `MAX_ALPHA`].
pub fn clamp_alpha(alpha: f64) -> f64 {
    alpha.clamp(MIN_ALPHA, MAX_ALPHA)
}

pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Normalised v + l (seed eq. 5), or n when v ≈ −l leaves no meaningful half vector.
pub fn safe_half_vector(v: Vec3, l: Vec3, n: Vec3) -> Vec3 {
    let h = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
    let len2 = dot(h, h);
    if len2 < MIN_HALF_LEN2 {
        return n;
    }
    let inv = 1.0 / len2.sqrt();
    [h[0] * inv, h[1] * inv, h[2] * inv]
}
