//! The χ² test of a sampling routine against its pdf, as pbrt-v4's `bsdfs_test.cpp` and
//! Mitsuba 3's chi2 tests do: a histogram of samples over the sphere, binned in (cos θ, φ)
//! (equal-area cells), against the pdf integrated over each cell; cells with fewer than 5
//! expected samples are pooled. The p-value of the statistic (Wilson–Hilferty's normal
//! approximation of χ²) must not reject the pdf at 1e-4; the seed is fixed, so a pass
//! stays a pass.

use std::f64::consts::PI;

use glam::DVec3;

use crate::brdf::geometry::erf;
use crate::rng::Rng;

const COS_BINS: usize = 24;
const PHI_BINS: usize = 48;
/// Midpoint quadrature points per cell side when integrating the pdf.
const SUBDIVISIONS: usize = 32;
const SAMPLES: usize = 500_000;

pub fn direction(cos: f64, phi: f64) -> DVec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

fn cell(d: DVec3) -> usize {
    let c = (((d.z + 1.0) * 0.5 * COS_BINS as f64) as usize).min(COS_BINS - 1);
    let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
    let p = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    c * PHI_BINS + p
}

/// P(χ²_k ≥ x) by Wilson & Hilferty 1931.
fn chi2_p_value(x: f64, k: f64) -> f64 {
    let z = ((x / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    0.5 * (1.0 - erf(z / std::f64::consts::SQRT_2))
}

/// Draws `SAMPLES` directions (None counts as a sample that returned nothing) and tests
/// them against `pdf`; returns the integral of the pdf over the sphere.
pub fn chi2(name: &str, mut sample: impl FnMut(&mut Rng) -> Option<DVec3>, pdf: impl Fn(DVec3) -> f64) -> f64 {
    let mut rng = Rng::new(0x5eed);
    let mut observed = vec![0.0; COS_BINS * PHI_BINS];
    for _ in 0..SAMPLES {
        if let Some(d) = sample(&mut rng) {
            assert!(d.is_finite() && (d.length() - 1.0).abs() < 1e-9, "{name}: sample {d}");
            observed[cell(d)] += 1.0;
        }
    }
    let mut expected = vec![0.0; COS_BINS * PHI_BINS];
    let (dc, dp) = (2.0 / COS_BINS as f64, 2.0 * PI / PHI_BINS as f64);
    let sub = SUBDIVISIONS as f64;
    for (i, e) in expected.iter_mut().enumerate() {
        let (c0, p0) = (-1.0 + (i / PHI_BINS) as f64 * dc, (i % PHI_BINS) as f64 * dp);
        for a in 0..SUBDIVISIONS {
            for b in 0..SUBDIVISIONS {
                let d = direction(c0 + (a as f64 + 0.5) / sub * dc, p0 + (b as f64 + 0.5) / sub * dp);
                *e += pdf(d);
            }
        }
        *e *= dc * dp / (sub * sub);
    }
    let integral: f64 = expected.iter().sum();
    // Pool the sparse cells, then compare.
    let (mut statistic, mut cells, mut pooled_o, mut pooled_e) = (0.0, 0usize, 0.0, 0.0);
    for (o, e) in observed.iter().zip(&expected) {
        let e = e * SAMPLES as f64;
        if e < 5.0 {
            pooled_o += o;
            pooled_e += e;
        } else {
            statistic += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pooled_e >= 5.0 {
        statistic += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
        cells += 1;
    } else {
        assert!(
            pooled_o < 5.0 + 5.0 * pooled_e,
            "{name}: {pooled_o} samples where the pdf expects {pooled_e}"
        );
    }
    let p = chi2_p_value(statistic, (cells - 1) as f64);
    if p <= 1e-4 {
        for (i, (o, e)) in observed.iter().zip(&expected).enumerate() {
            let e = e * SAMPLES as f64;
            if e >= 5.0 && (o - e).abs() > 3.0 * e.sqrt() {
                eprintln!(
                    "{name}: cell cos {} phi {}: observed {o} expected {e:.1}",
                    i / PHI_BINS,
                    i % PHI_BINS
                );
            }
        }
    }
    assert!(p > 1e-4, "{name}: χ² {statistic:.1} over {cells} cells, p = {p:.2e}");
    integral
}
