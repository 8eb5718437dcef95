//! Ambient occlusion of the environment's light in f64: the twins of
//! `shaders/lib/occlusion.glsl` (GTAO's slice integral and multi-bounce fit, and the
//! specular occlusion derived from it, and the micro-shadowing of lights by the occlusion
//! map).

/// GTAO's inner integral over one slice (Jimenez et al. 2016, "Practical Realtime
/// Strategies for Accurate Indirect Occlusion", eq. 7): ∫ cos(θ − γ) |sin θ| dθ from the
/// horizon angle `h0` ≤ 0 to `h1` ≥ 0, angles from the view direction in the slice's
/// plane, γ the angle of the normal projected into it. 1 for γ = 0 and open horizons ±π/2.
pub fn gtao_slice_visibility(h0: f64, h1: f64, gamma: f64) -> f64 {
    let arc = |h: f64| 0.25 * (-(2.0 * h - gamma).cos() + gamma.cos() + 2.0 * h * gamma.sin());
    // The integrand is ≥ 0 on the clamped horizons; rounding of the closed form is not.
    (arc(h0) + arc(h1)).max(0.0)
}

/// GTAO's multi-bounce fit (Jimenez et al. 2016, eq. 10): the visibility `x` raised by the
/// light that bounces between surfaces of albedo ρ, per channel. The cubic exceeds 1 by up
/// to 1e-4 at x = 1 (a fit error), so it is held in [x, 1].
pub fn gtao_multi_bounce(x: f64, albedo: [f64; 3]) -> [f64; 3] {
    albedo.map(|rho| {
        let a = 2.0404 * rho - 0.3324;
        let b = -4.7951 * rho + 0.6417;
        let c = 2.7552 * rho + 0.6903;
        (((a * x + b) * x + c) * x).max(x).min(1.0)
    })
}

/// Specular occlusion from the ambient visibility (Lagarde & de Rousiers 2014, "Moving
/// Frostbite to PBR", eq. 41): (n·v + x)^(2^(−16α − 1)) − 1 + x in [0, 1], α = roughness².
/// 1 where x = 1; α is held in [0, 1], so the exponent stays > 0 in fp32.
pub fn specular_occlusion(n_dot_v: f64, x: f64, alpha: f64) -> f64 {
    let exponent = (-16.0 * alpha.clamp(0.0, 1.0) - 1.0).exp2();
    ((n_dot_v.max(0.0) + x).powf(exponent) - 1.0 + x).clamp(0.0, 1.0)
}

/// Micro-shadowing (Filament, after Chan 2018, "Material advances in Call of Duty: WWII"):
/// the occlusion map's visibility `ao` taken as a cone around the normal of cos² = 1 − ao
/// (aperture 1/√(1 − ao)), a light at `n_dot_l` weighted saturate(n·l · aperture)². At
/// ao ≥ 1 the aperture is infinite and the light is left as it is (1, past the terminator
/// too: a map of 1 is no map); at ao = 0, (n·l)².
pub fn micro_shadowing(n_dot_l: f64, ao: f64) -> f64 {
    let closed = 1.0 - ao;
    if closed <= 0.0 {
        return 1.0;
    }
    let s = (n_dot_l / closed.sqrt()).clamp(0.0, 1.0);
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// The closed form is the integral it names, by the midpoint rule.
    #[test]
    fn slice_visibility_is_the_cosine_weighted_arc() {
        for (h0, h1, gamma) in [
            (-FRAC_PI_2, FRAC_PI_2, 0.0),
            (-0.3, 1.2, 0.4),
            (-1.5, 0.2, -0.9),
            (-0.7, 0.0, 0.0),
        ] {
            let n = 200_000;
            let dt = (h1 - h0) / n as f64;
            let quadrature: f64 = (0..n)
                .map(|i| {
                    let t = h0 + (i as f64 + 0.5) * dt;
                    (t - gamma).cos() * t.sin().abs() * dt
                })
                .sum();
            let closed = gtao_slice_visibility(h0, h1, gamma);
            assert!(
                (closed - quadrature).abs() < 1e-9,
                "{h0} {h1} {gamma}: {closed} against {quadrature}"
            );
        }
        assert!((gtao_slice_visibility(-FRAC_PI_2, FRAC_PI_2, 0.0) - 1.0).abs() < 1e-15);
    }

    /// Open sky stays open for every albedo and roughness; the bounce raises what is
    /// occluded more the whiter the surfaces, and never above 1.
    #[test]
    fn nothing_occluded_stays_one_and_bounces_raise_visibility() {
        for rho in [0.0, 0.3, 0.8, 1.0] {
            assert_eq!(gtao_multi_bounce(1.0, [rho; 3]), [1.0; 3]);
            let dark = gtao_multi_bounce(0.5, [0.1; 3])[0];
            let bright = gtao_multi_bounce(0.5, [rho; 3])[0];
            assert!((0.5..=1.0).contains(&bright));
            if rho > 0.1 {
                assert!(bright > dark);
            }
        }
        for alpha in [0.002, 0.1, 0.5, 1.0] {
            for n_dot_v in [0.0, 0.3, 1.0] {
                assert_eq!(specular_occlusion(n_dot_v, 1.0, alpha), 1.0);
                let so = specular_occlusion(n_dot_v, 0.4, alpha);
                assert!((0.0..=1.0).contains(&so));
            }
        }
    }

    /// Micro-shadowing is (n·l)² with nothing open, 1 where the light is inside the open
    /// cone, grows with n·l and ao, and tends to 1 as ao → 1, where it is exactly 1.
    #[test]
    fn micro_shadowing_opens_with_visibility() {
        for n_dot_l in [0.0, 0.1, 0.5, 1.0] {
            assert_eq!(micro_shadowing(n_dot_l, 0.0), n_dot_l * n_dot_l);
            assert_eq!(micro_shadowing(n_dot_l, 1.0), 1.0);
        }
        assert_eq!(micro_shadowing(-0.2, 0.5), 0.0);
        // cos² of the cone is 1 − ao: at ao = 0.75 the light is unshadowed above n·l = 0.5.
        assert_eq!(micro_shadowing(0.6, 0.75), 1.0);
        assert!((micro_shadowing(0.25, 0.75) - 0.25).abs() < 1e-15);
        assert!((micro_shadowing(0.3, 1.0 - 1e-12) - 1.0).abs() < 1e-15);
        let mut previous = 0.0;
        for i in 0..=100 {
            let ao = f64::from(i) / 100.0;
            let value = micro_shadowing(0.3, ao);
            assert!(value >= previous && value <= micro_shadowing(0.4, ao), "{ao}");
            previous = value;
        }
    }
}
