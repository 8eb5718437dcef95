//! Anti-aliasing's formulas, twins of `shaders/lib/msaa_resolve.glsl` and
//! `shaders/lib/specular_aa.glsl`.

use super::{dot, Vec3};

/// Rec. 709 luma weights of linear RGB.
pub const REC709_LUMA: Vec3 = [0.2126, 0.7152, 0.0722];

/// Karis 2014 ("High Quality Temporal Supersampling"): a sample's weight 1/(1 + luma) in
/// the resolve of a multisampled HDR frame, negative luma counting as 0.
pub fn resolve_weight(radiance: Vec3) -> f64 {
    1.0 / (1.0 + dot(radiance, REC709_LUMA).max(0.0))
}

/// The resolve of one pixel's samples as msaa_resolve.frag computes it: Σ w c / Σ w.
pub fn resolve(samples: &[Vec3]) -> Vec3 {
    let mut weighted = [0.0; 3];
    let mut weights = 0.0;
    for s in samples {
        let w = resolve_weight(*s);
        for (sum, c) in weighted.iter_mut().zip(s) {
            *sum += c * w;
        }
        weights += w;
    }
    weighted.map(|c| c / weights)
}

/// σ² of Tokuyoshi & Kaplanyan's pixel filter kernel, 1/(2π).
pub const SPECULAR_AA_KERNEL_VARIANCE: f64 = 0.159_154_94;
/// κ, their clamp of the widening of α².
pub const SPECULAR_AA_MAX_WIDENING: f64 = 0.18;

/// Tokuyoshi & Kaplanyan 2019 ("Improved Geometric Specular Antialiasing", eq. 13): the
/// perceptual roughness whose α'² = α² + min(2σ² `normal_change2`, κ), at most 1, where
/// α = roughness² and `normal_change2` = |∂n/∂x|² + |∂n/∂y|².
pub fn specular_aa_roughness(roughness: f64, normal_change2: f64) -> f64 {
    let alpha2 = roughness.powi(4);
    let widening = (2.0 * SPECULAR_AA_KERNEL_VARIANCE * normal_change2).min(SPECULAR_AA_MAX_WIDENING);
    (alpha2 + widening).min(1.0).sqrt().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weighted_resolve_never_brightens_and_keeps_flat_pixels() {
        // A flat pixel resolves to itself.
        let c = [0.3, 2.0, 7.0];
        let r = resolve(&[c; 4]);
        assert!(r.iter().zip(c).all(|(a, b)| (a - b).abs() < 1e-15));
        // Weights fall as luma rises: the weighted mean is at most the plain mean.
        let samples = [[0.0; 3], [1.0; 3], [10.0; 3], [0.5, 0.2, 0.1]];
        let mean: f64 = samples.iter().map(|s| dot(*s, REC709_LUMA)).sum::<f64>() / 4.0;
        assert!(dot(resolve(&samples), REC709_LUMA) <= mean);
        // White (luma 1) on black at half coverage: w = 1/2 and 1, so 1/3, not 1/2.
        let half = resolve(&[[1.0; 3], [1.0; 3], [0.0; 3], [0.0; 3]]);
        assert!((half[0] - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn specular_aa_widens_only_where_the_normal_turns() {
        assert_eq!(specular_aa_roughness(0.3, 0.0), 0.3);
        let widened = specular_aa_roughness(0.3, 0.1);
        let expected = (0.3f64.powi(4) + 2.0 * SPECULAR_AA_KERNEL_VARIANCE * 0.1).powf(0.25);
        assert!((widened - expected).abs() < 1e-15);
        // The widening is clamped at κ, and α at 1.
        let clamped = (0.3f64.powi(4) + SPECULAR_AA_MAX_WIDENING).powf(0.25);
        assert!((specular_aa_roughness(0.3, 1e6) - clamped).abs() < 1e-15);
        assert_eq!(specular_aa_roughness(1.0, 1e6), 1.0);
    }
}
