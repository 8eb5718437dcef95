//! Diffuse lobes. Lambert and Oren-Nayar are linear in the albedo and return f per unit
//! albedo; EON is not linear in it and takes the albedo ρ.

use super::{dot, Vec3, MIN_N_DOT_V, PI};

/// |v_t|²|l_t|² below which φ is undefined (one direction along n, where sin a tan b is 0).
pub const MIN_TANGENT_LEN2: f64 = 1e-12;
/// EON's 1/2 − 2/(3π) (Portsmouth, Kutz & Hill 2025): FON's A = 1/(1 + c₁ r).
pub const EON_CONSTANT_1: f64 = 0.5 - 2.0 / (3.0 * PI);
/// EON's 2/3 − 28/(15π): FON's average albedo is A (1 + c₂ r).
pub const EON_CONSTANT_2: f64 = 2.0 / 3.0 - 28.0 / (15.0 * PI);
/// EON's ε: keeps 1 − E > 0 where E_FON = 1 (r = 0), where the multiple-scattering lobe vanishes.
pub const EON_EPSILON: f64 = 1e-7;

/// Lambert, seed eq. 4: 1/π per unit albedo.
pub fn diffuse_lambert() -> f64 {
    1.0 / PI
}

/// Qualitative Oren-Nayar, seed eq. 12 with a = max(θi, θr), b = min(θi, θr) as angles:
/// (A + B max(0, cos(φi − φr)) sin a tan b)/π per unit albedo, σ in radians. sin a and
/// tan b come from the tangent-plane projections (|v_t| = sin θr) rather than acos/tan,
/// which lose precision near the normal in fp32.
pub fn diffuse_oren_nayar(sigma: f64, n: Vec3, v: Vec3, l: Vec3) -> f64 {
    let s2 = sigma * sigma;
    let a_coef = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let b_coef = 0.45 * s2 / (s2 + 0.09);
    let n_dot_v = dot(n, v);
    let n_dot_l = dot(n, l);
    let v_t = [v[0] - n[0] * n_dot_v, v[1] - n[1] * n_dot_v, v[2] - n[2] * n_dot_v];
    let l_t = [l[0] - n[0] * n_dot_l, l[1] - n[1] * n_dot_l, l[2] - n[2] * n_dot_l];
    let (v_t2, l_t2) = (dot(v_t, v_t), dot(l_t, l_t));
    let len2 = v_t2 * l_t2;
    let cos_phi = if len2 > MIN_TANGENT_LEN2 {
        (dot(v_t, l_t) / len2.sqrt()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (sin_r, sin_i) = (v_t2.sqrt().min(1.0), l_t2.sqrt().min(1.0));
    let (cos_r, cos_i) = (n_dot_v.clamp(MIN_N_DOT_V, 1.0), n_dot_l.clamp(MIN_N_DOT_V, 1.0));
    // The larger angle has the larger sine, the smaller angle the larger cosine.
    let sin_a = sin_r.max(sin_i);
    let tan_b = sin_r.min(sin_i) / cos_r.max(cos_i);
    (a_coef + b_coef * cos_phi * sin_a * tan_b) / PI
}

/// EON's polynomial fit of the FON directional albedo E_FON(μ) (Portsmouth et al. 2025).
pub fn e_fon_approx(mu: f64, r: f64) -> f64 {
    let m = 1.0 - mu.clamp(0.0, 1.0);
    let r = r.clamp(0.0, 1.0);
    let g_over_pi = m * (0.0571085289 + m * (0.491881867 + m * (-0.332181442 + m * 0.0714429953)));
    (1.0 + r * g_over_pi) / (1.0 + EON_CONSTANT_1 * r)
}

/// FON directional albedo in closed form (Portsmouth et al. 2025):
/// A + B/π (sin θ(θ − sin θ cos θ) + 2/3 (tan θ (1 − sin³θ) − sin θ)).
pub fn e_fon_exact(mu: f64, r: f64) -> f64 {
    let mu = mu.clamp(MIN_N_DOT_V, 1.0);
    let r = r.clamp(0.0, 1.0);
    let a = 1.0 / (1.0 + EON_CONSTANT_1 * r);
    let b = r * a;
    let si = (1.0 - mu * mu).sqrt();
    let g = si * (mu.acos() - si * mu) + 2.0 / 3.0 * ((si / mu) * (1.0 - si * si * si) - si);
    a + b / PI * g
}

/// Energy-preserving Oren-Nayar (EON, Portsmouth, Kutz & Hill 2025, as in OpenPBR), with the
/// E_FON fit: FON single scattering ρ/π A (1 + r s/t) plus the multiple-scattering lobe
/// ρ_ms/π (1 − E(μo))(1 − E(μi))/(1 − Ē). r is the roughness in [0, 1].
pub fn diffuse_eon(rho: Vec3, r: f64, n_dot_v: f64, n_dot_l: f64, v_dot_l: f64) -> Vec3 {
    eon(rho, r, n_dot_v, n_dot_l, v_dot_l, e_fon_approx)
}

/// `diffuse_eon` with the closed-form E_FON, which makes it exactly energy-preserving.
pub fn diffuse_eon_exact(rho: Vec3, r: f64, n_dot_v: f64, n_dot_l: f64, v_dot_l: f64) -> Vec3 {
    eon(rho, r, n_dot_v, n_dot_l, v_dot_l, e_fon_exact)
}

fn eon(rho: Vec3, r: f64, n_dot_v: f64, n_dot_l: f64, v_dot_l: f64, e_fon: fn(f64, f64) -> f64) -> Vec3 {
    let r = r.clamp(0.0, 1.0);
    let mu_o = n_dot_v.clamp(MIN_N_DOT_V, 1.0);
    let mu_i = n_dot_l.clamp(MIN_N_DOT_V, 1.0);
    // FON's s = cos φ sin θi sin θo and t = max(μi, μo) where s > 0.
    let s = v_dot_l - mu_i * mu_o;
    let s_over_t = if s > 0.0 { s / mu_i.max(mu_o) } else { s };
    let a = 1.0 / (1.0 + EON_CONSTANT_1 * r);
    let single = a * (1.0 + r * s_over_t) / PI;
    let e_avg = eon_average_albedo(r);
    let multi = (1.0 - e_fon(mu_o, r)).max(EON_EPSILON) * (1.0 - e_fon(mu_i, r)).max(EON_EPSILON)
        / (PI * (1.0 - e_avg).max(EON_EPSILON));
    rho.map(|c| {
        let c = c.clamp(0.0, 1.0);
        (c * single + eon_multiple_albedo(c, e_avg) * multi).max(0.0)
    })
}

/// EON's average FON albedo Ē = A (1 + c₂ r), r in [0, 1].
pub fn eon_average_albedo(r: f64) -> f64 {
    let r = r.clamp(0.0, 1.0);
    let a = 1.0 / (1.0 + EON_CONSTANT_1 * r);
    a * (1.0 + EON_CONSTANT_2 * r)
}

/// EON's multiple-scattering albedo ρ_ms = ρ² Ē/(1 − ρ(1 − Ē)), ρ clamped to [0, 1].
pub fn eon_multiple_albedo(rho: f64, e_avg: f64) -> f64 {
    let c = rho.clamp(0.0, 1.0);
    c * c * e_avg / (1.0 - c * (1.0 - e_avg))
}

/// The directional albedo of `diffuse_eon`, ρ E(μ) + ρ_ms (1 − E(μ)) with the E_FON fit
/// (Portsmouth et al. 2025: single scattering reflects E, the multiple-scattering lobe
/// 1 − E of ρ_ms): the radiance it reflects of a unit uniform environment.
pub fn diffuse_eon_albedo(rho: Vec3, r: f64, n_dot_v: f64) -> Vec3 {
    let e = e_fon_approx(n_dot_v, r);
    let e_avg = eon_average_albedo(r);
    rho.map(|c| {
        let c = c.clamp(0.0, 1.0);
        c * e + eon_multiple_albedo(c, e_avg) * (1.0 - e)
    })
}
