//! Wrap lighting, the seed's subsurface-scattering approximation.

/// Smallest wrap width w₂: keeps eq. 18's smoothstep edges apart.
pub const MIN_WRAP_WIDTH: f64 = 1e-4;

/// Hermite smoothstep that, like HLSL's and unlike GLSL's, accepts edge0 > edge1
/// (eq. 18 relies on it); the edges must differ.
pub fn hermite_step(edge0: f64, edge1: f64, x: f64) -> f64 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Seed eq. 18 (Fernando 2004): x = max(0, (n·l + w₁)/(1 + w₁)),
/// s = smoothstep(0, w₂, x) smoothstep(2w₂, w₂, x); w₁ in [0, 1], w₂ ≥ `MIN_WRAP_WIDTH`.
pub fn wrap_seed(n_dot_l: f64, w1: f64, w2: f64) -> f64 {
    let w1 = w1.clamp(0.0, 1.0);
    let w2 = w2.max(MIN_WRAP_WIDTH);
    let x = ((n_dot_l + w1) / (1.0 + w1)).max(0.0);
    hermite_step(0.0, w2, x) * hermite_step(2.0 * w2, w2, x)
}

/// Energy-conserving wrap, a replacement for max(0, n·l): saturate((n·l + w)/(1 + w)²),
/// whose integral over the sphere is π (Lambert's) for every w in [0, 1].
pub fn wrap_energy_conserving(n_dot_l: f64, w: f64) -> f64 {
    let w = w.clamp(0.0, 1.0);
    ((n_dot_l + w) / ((1.0 + w) * (1.0 + w))).clamp(0.0, 1.0)
}
