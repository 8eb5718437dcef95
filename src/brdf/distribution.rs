//! Microfacet normal distributions D(h), normalised so that ∫ D (n·h) dω = 1.

use super::{clamp_alpha, PI};

/// exp(−x) is treated as 0 beyond this: D is then below 1e-31 of its peak.
pub const BECKMANN_MAX_EXPONENT: f64 = 80.0;

/// GGX / Trowbridge-Reitz, seed eq. 7 rewritten as α²/(π((n·h)²α² + |n×h|²)²) so the
/// highlight keeps its precision (1 − (n·h)² cancels near n·h = 1).
pub fn d_ggx(alpha: f64, n_dot_h: f64, n_cross_h_len2: f64) -> f64 {
    if n_dot_h <= 0.0 {
        return 0.0;
    }
    let a = clamp_alpha(alpha);
    let a2 = a * a;
    let c = n_dot_h.min(1.0);
    // For unit n, h the denominator is ≥ α²; the max only tames inconsistent inputs.
    let d = (c * c * a2 + n_cross_h_len2.max(0.0)).max(a2);
    let k = a / d;
    k * k / PI
}

/// Beckmann, seed eq. 6 corrected to tan²θh = |n×h|²/(n·h)²:
/// exp(−tan²θh/α²)/(πα² cos⁴θh), with 1/cos⁴θh = (1 + tan²θh)².
pub fn d_beckmann(alpha: f64, n_dot_h: f64, n_cross_h_len2: f64) -> f64 {
    let a = clamp_alpha(alpha);
    let a2 = a * a;
    let c = n_dot_h.clamp(0.0, 1.0);
    let c2 = c * c;
    let s2 = n_cross_h_len2.max(0.0);
    // Also catches n·h ≤ 0 (c2 = 0) without dividing.
    if s2 >= BECKMANN_MAX_EXPONENT * a2 * c2 {
        return 0.0;
    }
    let tan2 = s2 / c2;
    let sec2 = 1.0 + tan2;
    (-tan2 / a2).exp() * sec2 * sec2 / (PI * a2)
}
