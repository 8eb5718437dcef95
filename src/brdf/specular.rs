//! Specular lobes: BRDF values f (without the cosine) for a given F0.

use super::distribution::{d_beckmann, d_ggx};
use super::fresnel::f_schlick;
use super::geometry::{
    g2_smith_correlated_beckmann, g2_smith_correlated_ggx, g2_smith_separable_beckmann, g2_smith_separable_ggx,
    g2_v_cavity,
};
use super::{clamp_alpha, Vec3, FP16_MAX, MIN_N_DOT_V, PI};
use serde::{Deserialize, Serialize};

/// Normal distribution of `spec_cook_torrance`; the value is the GLSL `int distribution`
/// and a shader specialization constant: never renumber.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Distribution {
    #[default]
    Ggx = 0,
    Beckmann = 1,
}

/// Smith masking-shadowing of `spec_cook_torrance`; the value is the GLSL `int geometry`
/// and a shader specialization constant: never renumber.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Geometry {
    #[default]
    SmithCorrelated = 0,
    SmithSeparable = 1,
}

/// Cook & Torrance 1982, seed eq. 11 without F: D·G/(4 n·v n·l), G the Smith G2 matching D,
/// clamped to `FP16_MAX`; for callers that apply Fresnel themselves (F ≤ 1 keeps the cap).
pub fn spec_cook_torrance_df(
    alpha: f64,
    n_dot_v: f64,
    n_dot_l: f64,
    n_dot_h: f64,
    n_cross_h_len2: f64,
    distribution: Distribution,
    geometry: Geometry,
) -> f64 {
    let nv = n_dot_v.clamp(MIN_N_DOT_V, 1.0);
    let nl = n_dot_l.clamp(MIN_N_DOT_V, 1.0);
    let d_g = match distribution {
        Distribution::Ggx => {
            d_ggx(alpha, n_dot_h, n_cross_h_len2)
                * match geometry {
                    Geometry::SmithCorrelated => g2_smith_correlated_ggx(alpha, nv, nl),
                    Geometry::SmithSeparable => g2_smith_separable_ggx(alpha, nv, nl),
                }
        }
        Distribution::Beckmann => {
            d_beckmann(alpha, n_dot_h, n_cross_h_len2)
                * match geometry {
                    Geometry::SmithCorrelated => g2_smith_correlated_beckmann(alpha, nv, nl),
                    Geometry::SmithSeparable => g2_smith_separable_beckmann(alpha, nv, nl),
                }
        }
    };
    (d_g / (4.0 * nv * nl)).min(FP16_MAX)
}

/// Cook & Torrance 1982, seed eq. 11: D·G·F/(4 n·v n·l), G the Smith G2 matching D;
/// F times `spec_cook_torrance_df`.
#[allow(clippy::too_many_arguments)]
pub fn spec_cook_torrance(
    alpha: f64,
    n_dot_v: f64,
    n_dot_l: f64,
    n_dot_h: f64,
    n_cross_h_len2: f64,
    f0: Vec3,
    v_dot_h: f64,
    distribution: Distribution,
    geometry: Geometry,
) -> Vec3 {
    let df = spec_cook_torrance_df(alpha, n_dot_v, n_dot_l, n_dot_h, n_cross_h_len2, distribution, geometry);
    f_schlick(f0, v_dot_h).map(|f| f * df)
}

/// Torrance & Sparrow 1967 (seed eq. 10 corrected): Beckmann D, V-cavity G, F over
/// 4 n·v n·l, because eq. 10's 4π(n·ωr) does not integrate D's projected area to 1.
/// D·G/(4 n·v n·l) is clamped to `FP16_MAX` before F.
pub fn spec_torrance_sparrow(
    alpha: f64,
    n_dot_v: f64,
    n_dot_l: f64,
    n_dot_h: f64,
    n_cross_h_len2: f64,
    f0: Vec3,
    v_dot_h: f64,
) -> Vec3 {
    let nv = n_dot_v.clamp(MIN_N_DOT_V, 1.0);
    let nl = n_dot_l.clamp(MIN_N_DOT_V, 1.0);
    let d_g = d_beckmann(alpha, n_dot_h, n_cross_h_len2) * g2_v_cavity(n_dot_h, nv, nl, v_dot_h);
    let df = (d_g / (4.0 * nv * nl)).min(FP16_MAX);
    f_schlick(f0, v_dot_h).map(|f| f * df)
}

/// Largest |n×h|² whose ln(n·h) `log_n_dot_h` takes as ½ ln(1 − |n×h|²): the GLSL twin's
/// `SIN2_SERIES_MAX` (n·h > 0.866 for unit n, h).
const SIN2_SERIES_MAX: f64 = 0.25;

/// 2 atanh(u) = ln((1 + u)/(1 − u)); the GLSL twin sums its series to u⁹.
pub fn two_atanh(u: f64) -> f64 {
    2.0 * u.atanh()
}

/// ln x for x clamped to (0, 1]. The GLSL twin sums the atanh series near 1, where fp32 log2
/// is only absolutely precise; f64's ln is relatively precise there already.
pub fn log_near_one(x: f64) -> f64 {
    x.clamp(f64::MIN_POSITIVE, 1.0).ln()
}

/// ln(n·h) = ½ ln(1 − s²), s² = |n×h|², for (n·h)ⁿ: below `SIN2_SERIES_MAX` from s², as
/// 2 atanh(−s²/(2 − s²)), otherwise (also for s² ≥ 1, non-unit inputs) `log_near_one(n·h)`,
/// the branches of the GLSL twin, which needs s² because fp32 n·h is rounded near 1.
pub fn log_n_dot_h(n_dot_h: f64, n_cross_h_len2: f64) -> f64 {
    let s2 = n_cross_h_len2.max(0.0);
    if s2 < SIN2_SERIES_MAX {
        0.5 * two_atanh(-s2 / (2.0 - s2))
    } else {
        log_near_one(n_dot_h)
    }
}

/// Blinn 1977 (seed eq. 5) normalised: (n+8)/(8π) (n·h)ⁿ F(v·h), n = 2/α² − 2, (n·h)ⁿ via |n×h|².
/// Peaks at 1.94e4 for `MIN_ALPHA`, so it needs no cap.
pub fn spec_blinn_phong(alpha: f64, n_dot_h: f64, n_cross_h_len2: f64, f0: Vec3, v_dot_h: f64) -> Vec3 {
    if n_dot_h <= 0.0 {
        return [0.0; 3];
    }
    let a = clamp_alpha(alpha);
    let n = 2.0 / (a * a) - 2.0;
    let lobe = (n + 8.0) / (8.0 * PI) * (n * log_n_dot_h(n_dot_h, n_cross_h_len2)).exp();
    f_schlick(f0, v_dot_h).map(|f| f * lobe)
}
