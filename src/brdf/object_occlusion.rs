//! The environment's light that an object hides, the object seen as a sphere
//! (shaders/lib/object_occlusion.glsl): the twin of `sphere_cap_irradiance` in
//! shaders/lib/occlusion.glsl.

use super::PI;

/// Snyder 1996 ("Area light sources for real-time graphics"), the sphere's form factor with
/// the horizon: (1/π) ∫ max(n·l, 0) dω over the cap of directions towards a sphere of
/// angular radius α whose centre makes angle θ with the normal, as a fraction of the
/// cosine-weighted hemisphere (so a uniform radiance L over the cap gives irradiance
/// π L F). Wholly above the horizon (θ ≤ π/2 − α) it is cos θ sin²α; wholly below
/// (θ ≥ π/2 + α) 0; between, with h = 1/sin α, x = √(h² − 1) and y = −x cot θ,
/// (cos θ acos y − x sin θ √(1 − y²))/(π h²) + atan(sin θ √(1 − y²), x)/π
/// (the form Lagarde & de Rousiers 2014 give for sphere lights, §4.7.2).
pub fn sphere_cap_irradiance(cos_theta: f64, sin_alpha: f64) -> f64 {
    let (cos_theta, sin_alpha) = (cos_theta.clamp(-1.0, 1.0), sin_alpha.clamp(0.0, 1.0));
    if cos_theta >= sin_alpha {
        return cos_theta * sin_alpha * sin_alpha;
    }
    match sphere_cap_partial_terms(cos_theta, sin_alpha) {
        Some([a, b, c]) => ((a - b + c) / PI).clamp(0.0, 1.0),
        None => 0.0,
    }
}

/// The three terms of the partial branch, cos θ acos y sin²α, x sin θ √(1 − y²) sin²α and
/// atan(sin θ √(1 − y²), x), whose sum over π is the form factor; `None` where the cap is
/// not cut by the horizon (on clamped arguments, as `sphere_cap_irradiance` takes them).
/// Where little of the cap is above the horizon, the first and last cancel.
pub fn sphere_cap_partial_terms(cos_theta: f64, sin_alpha: f64) -> Option<[f64; 3]> {
    if cos_theta >= sin_alpha || cos_theta <= -sin_alpha {
        return None;
    }
    let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
    let x = (1.0 - sin_alpha * sin_alpha).sqrt() / sin_alpha;
    // −x cot θ; sin θ > 0 here (|cos θ| < sin α ≤ 1).
    let y = (-x * cos_theta / sin_theta).clamp(-1.0, 1.0);
    let s = (1.0 - y * y).sqrt();
    let sin2 = sin_alpha * sin_alpha;
    Some([cos_theta * y.acos() * sin2, x * sin_theta * s * sin2, (sin_theta * s).atan2(x)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::quadrature::gauss_legendre;

    /// (1/π) ∫ max(n·l, 0) dω over the cap by Gauss-Legendre: l at angle ψ from the
    /// centre's direction w = (sin θ, 0, cos θ) and azimuth φ about it has
    /// n·l = cos θ cos ψ + sin θ sin ψ cos φ, positive for |φ| < φ_max(ψ); ψ is split where
    /// φ_max stops being π (θ + ψ = π/2) or becomes 0 (θ − ψ = π/2), so that every panel's
    /// integrand is smooth.
    fn cap_quadrature(theta: f64, alpha: f64) -> f64 {
        let rule = gauss_legendre(24);
        let mut edges = vec![0.0, alpha];
        for b in [PI / 2.0 - theta, theta - PI / 2.0] {
            if b > 0.0 && b < alpha {
                edges.push(b);
            }
        }
        edges.sort_by(f64::total_cmp);
        let panels = 16;
        let mut sum = 0.0;
        for pair in edges.windows(2) {
            let width = (pair[1] - pair[0]) / panels as f64;
            for p in 0..panels {
                let lo = pair[0] + width * p as f64;
                for &(u, wu) in &rule {
                    let psi = lo + width * 0.5 * (u + 1.0);
                    let (a, k) = (theta.cos() * psi.cos(), theta.sin() * psi.sin());
                    let phi_max = if k <= 0.0 {
                        if a > 0.0 { PI } else { 0.0 }
                    } else {
                        (-a / k).clamp(-1.0, 1.0).acos()
                    };
                    let inner: f64 = rule
                        .iter()
                        .map(|&(v, wv)| wv * phi_max * (a + k * (phi_max * v).cos()))
                        .sum();
                    sum += wu * width * 0.5 * psi.sin() * inner;
                }
            }
        }
        sum / PI
    }

    #[test]
    fn matches_the_integral_over_the_cap() {
        for alpha_deg in [0.5, 5.0, 20.0, 45.0, 70.0, 89.0, 90.0] {
            let alpha = f64::to_radians(alpha_deg);
            for k in 0..=36 {
                let theta = PI * k as f64 / 36.0;
                let exact = cap_quadrature(theta, alpha);
                let closed = sphere_cap_irradiance(theta.cos(), alpha.sin());
                assert!(
                    (exact - closed).abs() < 1e-9,
                    "α {alpha_deg}°, θ {}°: closed form {closed}, quadrature {exact}",
                    5 * k
                );
            }
        }
    }

    #[test]
    fn a_hemisphere_cap_is_half_the_horizon_plus_its_tilt() {
        // α = 90°: the cap is the hemisphere about w, of which (1 + cos θ)/2 is above n's horizon.
        for cos_theta in [-0.9, -0.3, 0.0, 0.4, 1.0] {
            let f = sphere_cap_irradiance(cos_theta, 1.0);
            assert!((f - (1.0 + cos_theta) / 2.0).abs() < 1e-12, "{cos_theta}: {f}");
        }
        assert_eq!(sphere_cap_irradiance(0.5, 0.0), 0.0);
    }
}
