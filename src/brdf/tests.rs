//! Checks of the models against `shared/reference/brdf-oracles.md` and of their guards.

use super::diffuse::{
    diffuse_eon, diffuse_eon_exact, diffuse_lambert, diffuse_oren_nayar, e_fon_approx, e_fon_exact, EON_EPSILON,
};
use super::distribution::{d_beckmann, d_ggx};
use super::fresnel::{f_schlick, f_schlick_scalar};
use super::geometry::{
    erf_series, erfc_fraction, g1_smith_ggx, g2_smith_correlated_beckmann, g2_smith_correlated_ggx,
    g2_smith_separable_beckmann, g2_smith_separable_ggx, g2_v_cavity, lambda_beckmann, lambda_beckmann_exact,
    lambda_ggx,
};
use super::quadrature::{d_normalisation, diffuse_albedo, directional_albedo, gauss_legendre, weak_white_furnace};
use super::specular::{
    spec_blinn_phong, spec_cook_torrance, spec_cook_torrance_df, spec_torrance_sparrow, Distribution, Geometry,
};
use super::tonemap::{srgb_oetf, srgb_oetf_rgb, tonemap_pbr_neutral};
use super::wrap::{wrap_energy_conserving, wrap_seed};
use super::{cross, dot, safe_half_vector, Vec3, FP16_MAX, MIN_ALPHA, PI};

const N: Vec3 = [0.0, 0.0, 1.0];
const WHITE: Vec3 = [1.0; 3];
const ALBEDO_ORDER: usize = 24;
const DIFFUSE_ORDER: usize = 16;

fn dir(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    [st * cp, st * sp, ct]
}

/// (n·h, |n×h|², v·h) for n = +z.
fn half_terms(v: Vec3, l: Vec3) -> (f64, f64, f64) {
    let h = safe_half_vector(v, l, N);
    let c = cross(N, h);
    (dot(N, h), dot(c, c), dot(v, h))
}

fn cook_torrance(d: Distribution, g: Geometry, alpha: f64, f0: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let (nh, nxh, vh) = half_terms(v, l);
    spec_cook_torrance(alpha, v[2], l[2], nh, nxh, f0, vh, d, g)
}

fn torrance_sparrow(alpha: f64, f0: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let (nh, nxh, vh) = half_terms(v, l);
    spec_torrance_sparrow(alpha, v[2], l[2], nh, nxh, f0, vh)
}

fn blinn_phong(alpha: f64, f0: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let (nh, nxh, vh) = half_terms(v, l);
    spec_blinn_phong(alpha, nh, nxh, f0, vh)
}

fn eon(rho: Vec3, r: f64, v: Vec3, l: Vec3) -> Vec3 {
    diffuse_eon(rho, r, v[2], l[2], dot(v, l))
}

/// Every BRDF of the library as f(v, l) for n = +z, with a name for messages.
/// A BRDF f(v, l) for n = +z.
type Brdf = Box<dyn Fn(Vec3, Vec3) -> Vec3>;

fn all_brdfs() -> Vec<(String, Brdf)> {
    let f0 = [0.04, 0.5, 1.0];
    let mut models: Vec<(String, Brdf)> = vec![
        ("lambert".into(), Box::new(|_, _| [diffuse_lambert(); 3])),
        (
            "oren-nayar".into(),
            Box::new(|v, l| [diffuse_oren_nayar(0.5, N, v, l); 3]),
        ),
        ("eon".into(), Box::new(|v, l| eon([0.9, 0.5, 0.1], 0.7, v, l))),
        (
            "torrance-sparrow".into(),
            Box::new(move |v, l| torrance_sparrow(0.3, f0, v, l)),
        ),
        ("blinn-phong".into(), Box::new(move |v, l| blinn_phong(0.3, f0, v, l))),
    ];
    for d in [Distribution::Ggx, Distribution::Beckmann] {
        for g in [Geometry::SmithCorrelated, Geometry::SmithSeparable] {
            models.push((
                format!("cook-torrance {d:?} {g:?}"),
                Box::new(move |v, l| cook_torrance(d, g, 0.3, f0, v, l)),
            ));
        }
    }
    models
}

#[test]
fn d_integrates_to_one() {
    let mut worst: f64 = 0.0;
    for alpha in [0.002025, 0.007921, 0.05, 0.2, 0.5, 1.0] {
        for (name, d) in [("ggx", d_ggx as fn(f64, f64, f64) -> f64), ("beckmann", d_beckmann)] {
            let integral = d_normalisation(d, alpha);
            assert!(
                (integral - 1.0).abs() < 1e-6,
                "{name} α {alpha}: ∫D(n·h)dω = {integral}"
            );
            worst = worst.max((integral - 1.0).abs());
        }
    }
    println!("∫D(n·h)dω: max |error| {worst:.1e}");
}

#[test]
fn weak_white_furnace_with_exact_lambda() {
    let g1_beckmann = |alpha, mu| 1.0 / (1.0 + lambda_beckmann_exact(alpha, mu));
    let mut worst: f64 = 0.0;
    for alpha in [0.002025, 0.05, 0.2, 0.5, 1.0] {
        for theta_deg in [0.0f64, 45.0, 80.0, 89.0] {
            let theta = theta_deg.to_radians();
            let ggx = weak_white_furnace(d_ggx, g1_smith_ggx, alpha, theta);
            let beckmann = weak_white_furnace(d_beckmann, g1_beckmann, alpha, theta);
            for (name, value) in [("ggx", ggx), ("beckmann", beckmann)] {
                assert!(
                    (value - 1.0).abs() < 1e-4,
                    "{name} α {alpha} θo {theta_deg}°: furnace {value}"
                );
                worst = worst.max((value - 1.0).abs());
            }
        }
    }
    println!("weak white furnace: max |error| {worst:.1e}");
}

#[test]
fn erf_matches_reference_values() {
    let sqrt_pi = PI.sqrt();
    for (x, erf) in [
        (0.1, 0.1124629160182849),
        (0.5, 0.5204998778130465),
        (1.0, 0.8427007929497149),
        (2.0, 0.9953222650189527),
        (2.9, 0.9999589021219005),
    ] {
        assert!((erf_series(x) - erf).abs() < 1e-13, "erf({x})");
    }
    for (x, erfc) in [(3.0f64, 2.209049699858544e-5), (5.0, 1.537_459_794_428_035e-12)] {
        let value = (-x * x).exp() / sqrt_pi * erfc_fraction(x);
        assert!((value / erfc - 1.0).abs() < 1e-13, "erfc({x})");
    }
}

#[test]
fn walter_beckmann_fit_error_matches_oracle() {
    // G1 depends on a = μ/(α sin θ) only: sweeping μ at α = 1 covers every a.
    let worst = (1..100_000)
        .map(|i| {
            let mu = i as f64 / 100_000.0;
            let fit = 1.0 / (1.0 + lambda_beckmann(1.0, mu));
            let exact = 1.0 / (1.0 + lambda_beckmann_exact(1.0, mu));
            (fit - exact).abs()
        })
        .fold(0.0, f64::max);
    println!("Walter Beckmann G1 fit: max abs error {worst:.2e}");
    assert!((worst - 3.1e-3).abs() < 1e-4, "max abs error {worst}");
}

#[test]
fn lambda_ggx_matches_seed_g1() {
    for alpha in [MIN_ALPHA, 0.1, 0.5, 1.0] {
        for mu in [1e-4, 0.01, 0.3, 0.7, 0.999, 1.0] {
            let from_lambda = 1.0 / (1.0 + lambda_ggx(alpha, mu));
            assert!((from_lambda - g1_smith_ggx(alpha, mu)).abs() < 1e-14);
        }
    }
}

#[test]
fn ggx_correlated_albedo_matches_table() {
    let table = [
        (0.05, [0.997296, 0.992716, 0.911347]),
        (0.2, [0.94766, 0.895235, 0.891266]),
        (0.5, [0.687852, 0.69825, 0.860105]),
        (0.8, [0.427005, 0.540134, 0.800495]),
        (1.0, [0.306855, 0.450693, 0.76021]),
    ];
    let mut worst: f64 = 0.0;
    for (alpha, row) in table {
        for (mu, expected) in [1.0, 0.5, 0.1].into_iter().zip(row) {
            let brdf = |v, l| cook_torrance(Distribution::Ggx, Geometry::SmithCorrelated, alpha, WHITE, v, l)[0];
            let albedo = directional_albedo(brdf, mu, ALBEDO_ORDER);
            assert!(
                (albedo - expected).abs() < 1e-3,
                "α {alpha} μo {mu}: E = {albedo}, table {expected}"
            );
            worst = worst.max((albedo - expected).abs());
        }
    }
    println!("GGX albedo table: max |error| {worst:.1e}");
}

#[test]
fn oren_nayar_energy_matches_oracle() {
    let table = [
        (0.25, [0.920, 0.975, 1.006]),
        (0.5, [0.784, 0.883, 0.939]),
        (1.0, [0.624, 0.747, 0.816]),
    ];
    for (sigma, row) in table {
        for (mu, expected) in [1.0, 0.5, 0.1].into_iter().zip(row) {
            let albedo = diffuse_albedo(|v, l| diffuse_oren_nayar(sigma, N, v, l), mu, DIFFUSE_ORDER);
            println!("Oren-Nayar σ {sigma} μo {mu}: E = {albedo:.5}");
            assert!((albedo - expected).abs() < 1e-3, "σ {sigma} μo {mu}: E = {albedo}");
        }
    }
    let grazing = diffuse_albedo(|v, l| diffuse_oren_nayar(0.25, N, v, l), 0.1, DIFFUSE_ORDER);
    assert!(grazing > 1.0, "qualitative Oren-Nayar gains energy: {grazing}");
}

#[test]
fn blinn_phong_albedo_matches_oracle() {
    for (exponent, expected) in [(1.0f64, 1.024), (10.0, 1.075), (100.0, 1.018), (1000.0, 1.002)] {
        let alpha = (2.0 / (exponent + 2.0)).sqrt();
        let albedo = directional_albedo(|v, l| blinn_phong(alpha, WHITE, v, l)[0], 1.0, ALBEDO_ORDER);
        println!("Blinn-Phong n {exponent}: albedo {albedo:.5}");
        assert!((albedo - expected).abs() < 1e-3, "n {exponent}: {albedo}");
    }
}

#[test]
fn eon_preserves_energy() {
    let mut worst_fit: f64 = 0.0;
    for r in [0.0, 0.25, 0.5, 1.0] {
        for mu in [1.0, 0.5, 0.1, 0.01] {
            let fit = diffuse_albedo(|v, l| eon(WHITE, r, v, l)[0], mu, DIFFUSE_ORDER);
            let exact = diffuse_albedo(
                |v, l| diffuse_eon_exact(WHITE, r, v[2], l[2], dot(v, l))[0],
                mu,
                DIFFUSE_ORDER,
            );
            // The paper: white EON reflects exactly 1 with the closed-form E_FON (up to its ε).
            assert!(
                (exact - 1.0).abs() < 2.0 * EON_EPSILON,
                "r {r} μo {mu}: exact E {exact}"
            );
            println!("EON r {r} μo {mu}: E {fit:.6} (fit), {exact:.12} (closed form)");
            // The E_FON fit costs at most 2.7e-4 (it exceeds 1 by up to 1.3e-4, at μo = 0.1).
            assert!((fit - 1.0).abs() < 5e-4, "r {r} μo {mu}: E {fit}");
            worst_fit = worst_fit.max((fit - 1.0).abs());
        }
    }
    println!("EON white albedo with the E_FON fit: max |E − 1| {worst_fit:.1e}");
    for mu in [0.05, 0.3, 0.6, 0.9, 1.0] {
        for r in [0.1, 0.5, 1.0] {
            assert!((e_fon_approx(mu, r) - e_fon_exact(mu, r)).abs() < 1e-3);
        }
    }
}

#[test]
fn schlick_error_against_exact_dielectric_fresnel() {
    // Unpolarised Fresnel reflectance of a dielectric of η = 1.5 (F0 = 0.04).
    let exact = |cos_i: f64| {
        let eta = 1.5;
        let cos_t = (1.0 - (1.0 - cos_i * cos_i) / (eta * eta)).sqrt();
        let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
        0.5 * (rs * rs + rp * rp)
    };
    let worst = (0..=10_000)
        .map(|i| {
            let c = i as f64 / 10_000.0;
            (f_schlick_scalar(0.04, c) - exact(c)).abs()
        })
        .fold(0.0, f64::max);
    println!("Schlick vs exact Fresnel, η 1.5: max abs error {worst:.4}");
    assert!((worst - 0.0357).abs() < 5e-4, "{worst}");
}

#[test]
fn energy_conserving_wrap_integrates_to_lambert() {
    // ∫ over the sphere of a function of μ = n·l is 2π ∫ dμ; both wraps are linear above μ = −w.
    let rule = gauss_legendre(8);
    let integral = |f: &dyn Fn(f64) -> f64, w: f64| -> f64 {
        let (mid, half) = (0.5 * (1.0 - w), 0.5 * (1.0 + w));
        2.0 * PI * rule.iter().map(|&(x, u)| u * half * f(mid + half * x)).sum::<f64>()
    };
    for w in [0.0, 0.25, 0.5, 1.0] {
        let conserving = integral(&|mu| wrap_energy_conserving(mu, w), w);
        assert!((conserving - PI).abs() < 1e-12, "w {w}: {conserving}");
        let plain = integral(&|mu: f64| ((mu + w) / (1.0 + w)).clamp(0.0, 1.0), w);
        assert!((plain - (1.0 + w) * PI).abs() < 1e-12, "w {w}: {plain}");
    }
}

#[test]
fn wrap_seed_is_a_band_at_the_terminator() {
    // x = w₂ is the top of the band, x = 0 and x ≥ 2w₂ are outside it.
    let (w1, w2) = (0.5, 0.2);
    let n_dot_l_at = |x: f64| x * (1.0 + w1) - w1;
    assert!((wrap_seed(n_dot_l_at(w2), w1, w2) - 1.0).abs() < 1e-12);
    assert_eq!(wrap_seed(n_dot_l_at(0.0), w1, w2), 0.0);
    assert_eq!(wrap_seed(n_dot_l_at(2.0 * w2), w1, w2), 0.0);
    assert_eq!(wrap_seed(1.0, w1, w2), 0.0);
}

#[test]
fn brdfs_are_reciprocal() {
    let mut directions = Vec::new();
    for theta in [0.0, 5.0, 30.0, 60.0, 85.0, 89.9] {
        for phi in [0.0, 40.0, 90.0, 170.0, 250.0] {
            directions.push(dir(theta, phi));
        }
    }
    for (name, f) in all_brdfs() {
        for &v in &directions {
            for &l in &directions {
                let (a, b) = (f(v, l), f(l, v));
                for c in 0..3 {
                    let tolerance = 1e-12 * a[c].abs().max(1.0);
                    assert!((a[c] - b[c]).abs() <= tolerance, "{name}: {a:?} vs {b:?}");
                }
            }
        }
    }
}

#[test]
fn stress_inputs_are_finite_and_non_negative() {
    let cosines = [-1.0, -1e-3, 0.0, 1e-310, 1e-7, 1e-4, 0.5, 1.0 - 1e-16, 1.0, 1.5];
    let alphas = [0.0, 1e-310, 1e-4, 0.002025, 0.5, 1.0, 1.5, 1e6];
    let ok = |x: f64| (0.0..=FP16_MAX).contains(&x);
    let f0 = [0.0, 0.04, 1.0];
    for &alpha in &alphas {
        for &a in &cosines {
            for &b in &cosines {
                let values = [
                    d_ggx(alpha, a, b),
                    d_beckmann(alpha, a, b),
                    d_ggx(alpha, a, 1.0 - a * a),
                    d_beckmann(alpha, a, 1.0 - a * a),
                    lambda_ggx(alpha, a),
                    lambda_beckmann(alpha, a),
                    lambda_beckmann_exact(alpha, a),
                    g1_smith_ggx(alpha, a),
                    g2_smith_separable_ggx(alpha, a, b),
                    g2_smith_correlated_ggx(alpha, a, b),
                    g2_smith_separable_beckmann(alpha, a, b),
                    g2_smith_correlated_beckmann(alpha, a, b),
                    g2_v_cavity(a, b, a, b),
                    f_schlick_scalar(0.04, a),
                    wrap_seed(a, alpha, b),
                    wrap_energy_conserving(a, alpha),
                    e_fon_approx(a, alpha),
                ];
                // D may exceed fp16 before the lobe's cap; it is bounded by 1/(π MIN_ALPHA²).
                for (i, x) in values.into_iter().enumerate() {
                    let bound = if i < 4 {
                        1.0 / (PI * MIN_ALPHA * MIN_ALPHA)
                    } else {
                        FP16_MAX
                    };
                    assert!(
                        x.is_finite() && (0.0..=bound).contains(&x),
                        "#{i} α {alpha} {a} {b}: {x}"
                    );
                }
                for &c in &cosines {
                    for &d in &cosines {
                        let mut lobes = vec![
                            spec_torrance_sparrow(alpha, a, b, c, d, f0, a),
                            spec_blinn_phong(alpha, c, d, f0, a),
                            diffuse_eon(f0, alpha, a, b, c),
                        ];
                        for dist in [Distribution::Ggx, Distribution::Beckmann] {
                            for geo in [Geometry::SmithCorrelated, Geometry::SmithSeparable] {
                                lobes.push(spec_cook_torrance(alpha, a, b, c, d, f0, a, dist, geo));
                                let df = spec_cook_torrance_df(alpha, a, b, c, d, dist, geo);
                                lobes.push([df; 3]);
                            }
                        }
                        for lobe in lobes {
                            assert!(lobe.into_iter().all(ok), "α {alpha} {a} {b} {c} {d}: {lobe:?}");
                        }
                    }
                }
            }
        }
    }
    // Geometric configurations: v = l, v = −l, grazing, at and below the horizon.
    let views = [
        N,
        dir(89.99, 0.0),
        dir(90.0, 0.0),
        dir(90.06, 0.0),
        dir(30.0, 10.0),
        [0.0, 0.0, -1.0],
    ];
    for &v in &views {
        for l in [v, v.map(|x| -x), dir(45.0, 180.0), N] {
            for alpha in alphas {
                let mut values: Vec<f64> = all_brdfs().into_iter().flat_map(|(_, f)| f(v, l)).collect();
                values.push(diffuse_oren_nayar(alpha, N, v, l));
                values.extend(cook_torrance(
                    Distribution::Ggx,
                    Geometry::SmithSeparable,
                    alpha,
                    f0,
                    v,
                    l,
                ));
                values.extend(torrance_sparrow(alpha, f0, v, l));
                values.extend(blinn_phong(alpha, f0, v, l));
                assert!(values.into_iter().all(ok), "v {v:?} l {l:?} α {alpha}");
            }
        }
    }
    assert_eq!(safe_half_vector(views[4], views[4].map(|x| -x), N), N);
    assert!(f_schlick(f0, -3.0).into_iter().all(ok));
}

/// D_GGX in fp32 as a shader evaluates it, from the 1 − (n·h)² or the |n×h|² form.
fn d_ggx_f32(alpha: f32, n_dot_h: f32, n_cross_h_len2: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = n_dot_h * n_dot_h * a2 + n_cross_h_len2;
    a2 / (std::f32::consts::PI * d * d)
}

/// Max and median relative error of fp32 D_GGX over half vectors within 4α of n.
fn ggx_f32_error(alpha: f64, cancelling: bool) -> (f64, f64) {
    let mut errors: Vec<f64> = (0..4000)
        .map(|i| {
            let theta = 4.0 * alpha * i as f64 / 4000.0;
            // h as an fp32 shader would hold it; the reference sees the same rounded vector.
            let (hx, hz) = (theta.sin() as f32, theta.cos() as f32);
            let (c, s) = (f64::from(hz), f64::from(hx));
            let tan2 = s * s / (c * c);
            let exact = alpha * alpha / (PI * c.powi(4) * (alpha * alpha + tan2).powi(2));
            let sin2 = if cancelling { 1.0 - hz * hz } else { hx * hx };
            let value = f64::from(d_ggx_f32(alpha as f32, hz, sin2));
            (value / exact - 1.0).abs()
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    (errors[errors.len() - 1], errors[errors.len() / 2])
}

#[test]
fn ggx_cross_product_form_keeps_fp32_precision() {
    let (cross_max, _) = ggx_f32_error(MIN_ALPHA, false);
    let (cancel_max, cancel_median) = ggx_f32_error(MIN_ALPHA, true);
    println!(
        "fp32 D_GGX at α {MIN_ALPHA}: |n×h|² max {cross_max:.1e}; 1 − (n·h)² median {cancel_median:.1e}, max {cancel_max:.1e}"
    );
    assert!(cross_max < 1e-6, "{cross_max}");
    assert!(
        cancel_max > 1e-2 && cancel_median > 1e-4,
        "{cancel_max} {cancel_median}"
    );
}

#[test]
fn min_alpha_is_set_by_the_fp16_target() {
    // Precision does not limit α: the |n×h|² form stays accurate far below MIN_ALPHA.
    for alpha in [1e-4, 1e-6, 1e-9] {
        let (max, _) = ggx_f32_error(alpha, false);
        assert!(max < 1e-6, "α {alpha}: {max}");
    }
    // The normal-incidence Cook-Torrance peak 1/(4πα²) (F = 1) must fit fp16.
    let peak = |alpha: f64| 1.0 / (4.0 * PI * alpha * alpha);
    let at_min = cook_torrance(Distribution::Ggx, Geometry::SmithCorrelated, MIN_ALPHA, WHITE, N, N)[0];
    assert!((at_min / peak(MIN_ALPHA) - 1.0).abs() < 1e-12);
    assert!(peak(MIN_ALPHA) < FP16_MAX / 3.0);
    assert!((peak(1.102e-3) / FP16_MAX - 1.0).abs() < 1e-3);
}

#[test]
fn lambert_albedo_is_one() {
    for mu in [1.0, 0.5, 0.1, 0.001] {
        let over_h = directional_albedo(|_, _| diffuse_lambert(), mu, ALBEDO_ORDER);
        let over_l = diffuse_albedo(|_, _| diffuse_lambert(), mu, DIFFUSE_ORDER);
        println!("Lambert μo {mu}: E {over_h:.9} over h, {over_l:.12} over l");
        assert!((over_h - 1.0).abs() < 1e-5, "μo {mu}: {over_h}");
        assert!((over_l - 1.0).abs() < 1e-12, "μo {mu}: {over_l}");
    }
}

#[test]
fn tonemap_and_srgb() {
    // Below the compression start, PBR Neutral only subtracts its toe offset.
    let low = tonemap_pbr_neutral([0.5, 0.3, 0.2]);
    for (out, inp) in low.into_iter().zip([0.5, 0.3, 0.2]) {
        assert!((out - (inp - 0.04)).abs() < 1e-15);
    }
    let toe = tonemap_pbr_neutral([0.05, 0.5, 0.5]);
    assert!((toe[0] - 6.25 * 0.05 * 0.05).abs() < 1e-15);
    for x in [0.8, 1.0, 10.0, 1e4, 1e30] {
        let out = tonemap_pbr_neutral([x, x * 0.5, 0.1]);
        assert!(out.into_iter().all(|c| (0.0..=1.0).contains(&c)), "{x}: {out:?}");
    }
    assert!(tonemap_pbr_neutral([1e30; 3])[0] > 0.999);
    assert_eq!(tonemap_pbr_neutral([-1e30; 3]), [0.0; 3]);
    assert!((srgb_oetf(0.5) - 0.735_356_983_052_449_5).abs() < 1e-12);
    assert!((srgb_oetf(0.0031308) - 12.92 * 0.0031308).abs() < 1e-12);
    assert!((1.055 * 0.0031308f64.powf(1.0 / 2.4) - 0.055 - 12.92 * 0.0031308).abs() < 1e-7);
    let clamped = srgb_oetf_rgb([-1.0, 0.0, 2.0]);
    assert!(clamped[0] == 0.0 && clamped[1] == 0.0 && (clamped[2] - 1.0).abs() < 1e-15);
}
