//! Masking-shadowing: Smith Λ for each distribution, G1, G2, and the V-cavity G.

use super::{clamp_alpha, MIN_N_DOT_V};

/// Walter et al. 2007's Beckmann fit sets G1 = 1 from a = 1/(α tan θ) ≥ 1.6.
pub const BECKMANN_FIT_MAX_A: f64 = 1.6;
/// Beyond this a, erfc is evaluated by its continued fraction instead of 1 − erf's series.
const ERFC_SERIES_MAX: f64 = 3.0;
/// Continued-fraction depth: converged to f64 precision for a ≥ `ERFC_SERIES_MAX`.
const ERFC_FRACTION_DEPTH: u32 = 120;

/// Smith Λ of GGX (Heitz 2014): (√(1 + α² tan²θ) − 1)/2, written x/(2(1 + √(1+x)))
/// so it does not cancel for small α tan θ. Below-horizon cosines are masked by G, not here.
pub fn lambda_ggx(alpha: f64, n_dot_x: f64) -> f64 {
    let a = clamp_alpha(alpha);
    let mu = n_dot_x.clamp(MIN_N_DOT_V, 1.0);
    let mu2 = mu * mu;
    let x = a * a * (1.0 - mu2) / mu2;
    x / (2.0 * (1.0 + (1.0 + x).sqrt()))
}

/// Smith Λ of Beckmann by Walter et al. 2007's rational fit of G1, a = 1/(α tan θ).
/// The fit exceeds G1 = 1 by 6e-5 just below a = 1.6, so Λ is clamped at 0.
pub fn lambda_beckmann(alpha: f64, n_dot_x: f64) -> f64 {
    let al = clamp_alpha(alpha);
    let mu = n_dot_x.clamp(MIN_N_DOT_V, 1.0);
    let sin = (1.0 - mu * mu).sqrt();
    if mu >= BECKMANN_FIT_MAX_A * al * sin {
        return 0.0;
    }
    let a = mu / (al * sin);
    ((1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)).max(0.0)
}

/// Exact Smith Λ of Beckmann (Heitz 2014): (erf(a) − 1)/2 + e^(−a²)/(2a√π).
pub fn lambda_beckmann_exact(alpha: f64, n_dot_x: f64) -> f64 {
    let al = clamp_alpha(alpha);
    let mu = n_dot_x.clamp(MIN_N_DOT_V, 1.0);
    let sin = (1.0 - mu * mu).sqrt();
    if sin == 0.0 {
        return 0.0;
    }
    let a = mu / (al * sin);
    let sqrt_pi = std::f64::consts::PI.sqrt();
    let gauss = (-a * a).exp();
    if a < ERFC_SERIES_MAX {
        0.5 * (gauss / (a * sqrt_pi) - (1.0 - erf_series(a)))
    } else {
        // erfc(a) = e^(−a²)/√π · K(a): factoring e^(−a²)/√π avoids the cancellation.
        0.5 * gauss / sqrt_pi * (1.0 / a - erfc_fraction(a))
    }
}

/// erf(x) in f64: its series below |x| = 3, `1 − e^(−x²)/√π · K(x)` beyond.
pub fn erf(x: f64) -> f64 {
    let a = x.abs();
    let e = if a < ERFC_SERIES_MAX {
        erf_series(a)
    } else {
        1.0 - (-a * a).exp() / std::f64::consts::PI.sqrt() * erfc_fraction(a)
    };
    e.copysign(x)
}

/// erf by its Maclaurin series 2/√π Σ (−1)ⁿ x²ⁿ⁺¹/(n!(2n+1)); used for |x| < 3.
pub(super) fn erf_series(x: f64) -> f64 {
    let x2 = x * x;
    let mut term = x; // (−1)ⁿ x²ⁿ⁺¹/n!
    let mut sum = x;
    let mut n = 0.0;
    while term.abs() > 1e-18 * sum.abs() {
        n += 1.0;
        term *= -x2 / n;
        sum += term / (2.0 * n + 1.0);
    }
    2.0 / std::f64::consts::PI.sqrt() * sum
}

/// K(x) = √π e^(x²) erfc(x) by Laplace's continued fraction 1/(x + ½/(x + 1/(x + 3/2/(x + …)))).
pub(super) fn erfc_fraction(x: f64) -> f64 {
    let mut t = x;
    for k in (1..=ERFC_FRACTION_DEPTH).rev() {
        t = x + 0.5 * f64::from(k) / t;
    }
    1.0 / t
}

/// Smith G1 of GGX, seed eq. 8: 2(n·x)/(n·x + √(α² + (1 − α²)(n·x)²)); 0 below the horizon.
pub fn g1_smith_ggx(alpha: f64, n_dot_x: f64) -> f64 {
    let a = clamp_alpha(alpha);
    let a2 = a * a;
    let mu = n_dot_x.clamp(0.0, 1.0);
    2.0 * mu / (mu + (a2 + (1.0 - a2) * mu * mu).sqrt())
}

/// Separable Smith G2 = G1(v) G1(l) (seed's G, eq. 8), GGX.
pub fn g2_smith_separable_ggx(alpha: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    g1_smith_ggx(alpha, n_dot_v) * g1_smith_ggx(alpha, n_dot_l)
}

/// Height-correlated Smith G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014), GGX.
pub fn g2_smith_correlated_ggx(alpha: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    if n_dot_v <= 0.0 || n_dot_l <= 0.0 {
        return 0.0;
    }
    1.0 / (1.0 + lambda_ggx(alpha, n_dot_v) + lambda_ggx(alpha, n_dot_l))
}

/// Separable Smith G2 = 1/((1 + Λ(v))(1 + Λ(l))) (Heitz 2014), Beckmann (Walter fit).
pub fn g2_smith_separable_beckmann(alpha: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    if n_dot_v <= 0.0 || n_dot_l <= 0.0 {
        return 0.0;
    }
    1.0 / ((1.0 + lambda_beckmann(alpha, n_dot_v)) * (1.0 + lambda_beckmann(alpha, n_dot_l)))
}

/// Height-correlated Smith G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014), Beckmann (Walter fit).
pub fn g2_smith_correlated_beckmann(alpha: f64, n_dot_v: f64, n_dot_l: f64) -> f64 {
    if n_dot_v <= 0.0 || n_dot_l <= 0.0 {
        return 0.0;
    }
    1.0 / (1.0 + lambda_beckmann(alpha, n_dot_v) + lambda_beckmann(alpha, n_dot_l))
}

/// V-cavity G of Torrance & Sparrow 1967 / Cook & Torrance 1982:
/// min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)), written without dividing by a tiny v·h.
pub fn g2_v_cavity(n_dot_h: f64, n_dot_v: f64, n_dot_l: f64, v_dot_h: f64) -> f64 {
    let g = 2.0 * n_dot_h.clamp(0.0, 1.0) * n_dot_v.min(n_dot_l).clamp(0.0, 1.0);
    let v_dot_h = v_dot_h.clamp(0.0, 1.0);
    if v_dot_h > g {
        g / v_dot_h
    } else {
        1.0
    }
}
