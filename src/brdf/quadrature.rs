//! Hemisphere quadrature for checking the models: normalisation, furnace tests, albedo.
//!
//! Microfacet integrals are taken over half vectors h = (sin θ cos φ, sin θ sin φ, cos θ)
//! around the normal n = +z, where every microfacet lobe peaks at θ = 0: Gauss-Legendre
//! panels in θ, graded geometrically towards 0, resolve lobes down to `MIN_ALPHA`. The region
//! of valid φ at each θ (k cos φ > r) is integrated by Gauss-Legendre on [−φmax, φmax], and
//! θ panels are split where that region changes shape, so integrands are smooth per panel.
//! Diffuse lobes are integrated over l instead (`diffuse_albedo`), split at their kinks.

use super::{dot, Vec3, PI};

/// Gauss-Legendre order of `d_normalisation` and `weak_white_furnace`.
pub const QUADRATURE_ORDER: usize = 32;
/// Panels reach down to θ = π/2 · 2⁻²⁰ ≈ 1.5e-6 rad, far inside the narrowest lobe.
const GRADED_PANELS: i32 = 20;
/// θ samples scanned for where the φ region appears, becomes full or vanishes.
const BREAKPOINT_SCAN: usize = 4096;
/// Bisection steps locating such a θ: 2⁻⁶⁰ of a scan interval, below f64 resolution.
const BISECTION_STEPS: u32 = 60;

/// Gauss-Legendre nodes and weights on [−1, 1], by Newton iteration on Pₙ.
pub fn gauss_legendre(order: usize) -> Vec<(f64, f64)> {
    let n = order.max(1);
    let nf = n as f64;
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            derivative = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / derivative;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        rule.push((x, 2.0 / ((1.0 - x * x) * derivative * derivative)));
    }
    rule
}

/// Half-angle φ of the region k cos φ > r (k ≥ 0): 0 when empty, π when full.
fn phi_max(k: f64, r: f64) -> f64 {
    if r >= k {
        0.0
    } else if r <= -k {
        PI
    } else {
        (r / k).acos()
    }
}

/// Panel edges in θ: geometric towards 0, plus where r(θ) = ±k(θ).
fn theta_edges(region: &impl Fn(f64) -> (f64, f64)) -> Vec<f64> {
    let mut edges: Vec<f64> = (0..=GRADED_PANELS).map(|i| 0.5 * PI * 0.5f64.powi(i)).collect();
    edges.push(0.0);
    for sign in [-1.0, 1.0] {
        let f = |theta: f64| {
            let (k, r) = region(theta);
            r + sign * k
        };
        let at = |j: usize| 0.5 * PI * (j as f64 + 0.5) / BREAKPOINT_SCAN as f64;
        for j in 0..BREAKPOINT_SCAN - 1 {
            let (mut lo, mut hi) = (at(j), at(j + 1));
            let f_lo = f(lo);
            if (f_lo < 0.0) == (f(hi) < 0.0) {
                continue;
            }
            for _ in 0..BISECTION_STEPS {
                let mid = 0.5 * (lo + hi);
                if (f(mid) < 0.0) == (f_lo < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            edges.push(0.5 * (lo + hi));
        }
    }
    edges.sort_by(f64::total_cmp);
    edges.dedup_by(|a, b| (*a - *b).abs() < 1e-15);
    edges
}

/// ∫ g(h, |n×h|²) dω over half vectors of the upper hemisphere with k(θ) cos φ > r(θ),
/// where `region(θ)` returns (k, r).
fn integrate_half_vectors(order: usize, region: impl Fn(f64) -> (f64, f64), g: impl Fn(Vec3, f64) -> f64) -> f64 {
    let rule = gauss_legendre(order);
    let edges = theta_edges(&region);
    let mut total = 0.0;
    for panel in edges.windows(2) {
        let (mid, half) = (0.5 * (panel[0] + panel[1]), 0.5 * (panel[1] - panel[0]));
        for &(x, w) in &rule {
            let theta = mid + half * x;
            let (k, r) = region(theta);
            let phi_max = phi_max(k, r);
            if phi_max == 0.0 {
                continue;
            }
            let (sin, cos) = theta.sin_cos();
            let ring: f64 = rule
                .iter()
                .map(|&(y, u)| {
                    let (sin_phi, cos_phi) = (phi_max * y).sin_cos();
                    u * g([sin * cos_phi, sin * sin_phi, cos], sin * sin)
                })
                .sum();
            total += w * half * sin * phi_max * ring;
        }
    }
    total
}

/// ∫ D(h) (n·h) dω over the hemisphere, 1 for a normalised D(alpha, n·h, |n×h|²).
pub fn d_normalisation(d: impl Fn(f64, f64, f64) -> f64, alpha: f64) -> f64 {
    // D is isotropic: the φ integral is 2π.
    let rule = gauss_legendre(QUADRATURE_ORDER);
    let edges = theta_edges(&|_| (0.0, -1.0));
    let mut total = 0.0;
    for panel in edges.windows(2) {
        let (mid, half) = (0.5 * (panel[0] + panel[1]), 0.5 * (panel[1] - panel[0]));
        for &(x, w) in &rule {
            let (sin, cos) = (mid + half * x).sin_cos();
            total += w * half * d(alpha, cos, sin * sin) * cos * sin;
        }
    }
    2.0 * PI * total
}

/// Weak white furnace (Heitz 2014): ∫ D(h) G1(o, h)/(4 |cos θo|) dωi over the whole sphere
/// of ωi, 1 when G1(alpha, n·o) is the Smith masking of D(alpha, n·h, |n×h|²).
/// Taken over h with dωi = 4 (o·h) dωh; θo < π/2.
pub fn weak_white_furnace(
    d: impl Fn(f64, f64, f64) -> f64,
    g1: impl Fn(f64, f64) -> f64,
    alpha: f64,
    theta_o: f64,
) -> f64 {
    weak_white_furnace_microfacet(d, |alpha, o, _| g1(alpha, o[2]), alpha, theta_o)
}

/// `weak_white_furnace` for a masking function of the microfacet normal too,
/// G1(alpha, o, h), like the V-cavity's min(1, 2 (n·h)(n·o)/(o·h)).
pub fn weak_white_furnace_microfacet(
    d: impl Fn(f64, f64, f64) -> f64,
    g1: impl Fn(f64, Vec3, Vec3) -> f64,
    alpha: f64,
    theta_o: f64,
) -> f64 {
    let (sin_o, cos_o) = theta_o.sin_cos();
    let o = [sin_o, 0.0, cos_o];
    // o·h > 0 ⇔ sin θo sin θ cos φ > −cos θo cos θ.
    let region = |theta: f64| (sin_o * theta.sin(), -cos_o * theta.cos());
    integrate_half_vectors(QUADRATURE_ORDER, region, |h, sin2| {
        d(alpha, h[2], sin2) * g1(alpha, o, h) * dot(o, h) / cos_o
    })
}

/// Directional albedo ∫ f(v, l) (n·l) dωl over the upper hemisphere for n = +z and
/// v = (√(1 − μ²), 0, μ); `brdf(v, l)` returns f. Suited to lobes peaked around the mirror
/// direction (microfacet, Blinn-Phong): it integrates over h. `order` is the Gauss-Legendre
/// order per θ panel and in φ.
pub fn directional_albedo(brdf: impl Fn(Vec3, Vec3) -> f64, n_dot_v: f64, order: usize) -> f64 {
    let mu = n_dot_v.clamp(0.0, 1.0);
    let sin_v = (1.0 - mu * mu).sqrt();
    let v = [sin_v, 0.0, mu];
    // l = 2(v·h)h − v has n·l = 2(v·h) cos θ − μ > 0 ⇔ sin θv sin θ cos φ > μ/(2 cos θ) − μ cos θ.
    let region = |theta: f64| {
        let (sin, cos) = theta.sin_cos();
        (sin_v * sin, mu / (2.0 * cos) - mu * cos)
    };
    integrate_half_vectors(order, region, |h, _| {
        let v_dot_h = dot(v, h);
        let l = [
            2.0 * v_dot_h * h[0] - v[0],
            2.0 * v_dot_h * h[1] - v[1],
            2.0 * v_dot_h * h[2] - v[2],
        ];
        // dωl = 4 (v·h) dωh.
        brdf(v, l) * l[2].max(0.0) * 4.0 * v_dot_h
    })
}

/// Directional albedo like `directional_albedo`, integrated over l for smooth lobes: panels
/// split at θl = θv and φl = ±π/2, where Oren-Nayar and EON have kinks, converge fast.
pub fn diffuse_albedo(brdf: impl Fn(Vec3, Vec3) -> f64, n_dot_v: f64, order: usize) -> f64 {
    let rule = gauss_legendre(order);
    let mu = n_dot_v.clamp(0.0, 1.0);
    let theta_v = mu.acos();
    let v = [theta_v.sin(), 0.0, mu];
    let theta_edges = [0.0, theta_v, 0.5 * PI];
    let phi_edges = [-PI, -0.5 * PI, 0.0, 0.5 * PI, PI];
    let mut total = 0.0;
    for t in theta_edges.windows(2) {
        let (t_mid, t_half) = (0.5 * (t[0] + t[1]), 0.5 * (t[1] - t[0]));
        for &(x, w) in &rule {
            let (sin, cos) = (t_mid + t_half * x).sin_cos();
            for p in phi_edges.windows(2) {
                let (p_mid, p_half) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
                for &(y, u) in &rule {
                    let (sin_phi, cos_phi) = (p_mid + p_half * y).sin_cos();
                    let l = [sin * cos_phi, sin * sin_phi, cos];
                    total += w * t_half * u * p_half * brdf(v, l) * cos * sin;
                }
            }
        }
    }
    total
}
