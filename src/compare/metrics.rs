//! The figures of `argil compare`, from two images in memory (definitions in [`super::HELP`]).

use anyhow::{ensure, Context, Result};
use serde::Serialize;

use crate::brdf::tonemap::{display_srgb8, luminance};

/// PSNR's peak: linear radiance 1, display white at exposure 1 (HDR images have no maximum).
pub const PSNR_PEAK: f64 = 1.0;
/// The relative error's floor as a fraction of B's mean covered luminance: near-black pixels,
/// where a Monte Carlo reference is mostly noise, do not dominate the tail, and the figures
/// do not change when both images are scaled.
pub const REL_ERR_FLOOR: f64 = 1e-2;
/// ꟻLIP's default observer: 67 pixels per degree, a 24" 4K monitor seen from 0.7 m.
pub const FLIP_PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;
/// Heat-map colour of the pixels left out for NaN/Inf: green, which magma never shows.
const NON_FINITE_COLOUR: [u8; 3] = [0, 255, 0];

/// An RGBA32F image: linear radiance and coverage, row-major from the top left.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba32 {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 4]>,
}

/// Mean and nearest-rank percentiles of a per-pixel figure; NaN (JSON null) when undefined.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Distribution {
    pub mean: f64,
    pub p95: f64,
    pub p99: f64,
}

impl Distribution {
    fn of(mut values: Vec<f64>) -> Self {
        if values.is_empty() {
            return Self {
                mean: f64::NAN,
                p95: f64::NAN,
                p99: f64::NAN,
            };
        }
        values.sort_unstable_by(f64::total_cmp);
        Self {
            mean: values.iter().sum::<f64>() / values.len() as f64,
            p95: nearest_rank(&values, 0.95),
            p99: nearest_rank(&values, 0.99),
        }
    }
}

/// The nearest-rank percentile p of sorted, non-empty values: the smallest value with at
/// least p·n values at or below it.
pub fn nearest_rank(sorted: &[f64], p: f64) -> f64 {
    sorted[((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1]
}

/// Every figure of a comparison; the JSON report holds them under these names.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Metrics {
    pub width: usize,
    pub height: usize,
    /// Pixels measured: alpha of B > 0, and no NaN/Inf in A or B.
    pub covered_pixels: usize,
    /// Pixels of A with a NaN or Inf in any channel, RGBA, anywhere in the image.
    pub non_finite_a: usize,
    pub non_finite_b: usize,
    /// Σ(a−b)² / Σb² over covered pixels and RGB channels.
    pub rel_mse: f64,
    /// Mean of (a−b)² over covered pixels and RGB channels.
    pub mse: f64,
    /// 10·log₁₀(peak² / mse).
    pub psnr_db: f64,
    pub psnr_peak: f64,
    /// |Y(a) − Y(b)| / max(Y(b), floor) per covered pixel, Y the Rec. 709 luminance.
    pub rel_err: Distribution,
    /// [`REL_ERR_FLOOR`] × the mean covered Y(b).
    pub rel_err_floor: f64,
    /// ꟻLIP of A against B after argil's display transform, over covered pixels.
    pub flip: Distribution,
    pub flip_pixels_per_degree: f32,
}

/// The figures, and the ꟻLIP heat map: magma over covered pixels, black elsewhere, green
/// where a NaN/Inf left a pixel out.
pub struct Comparison {
    pub metrics: Metrics,
    pub heat_map: image::RgbImage,
}

/// Compares `a` with the reference `b` (same size).
pub fn compare(a: &Rgba32, b: &Rgba32) -> Result<Comparison> {
    ensure!(
        (a.width, a.height) == (b.width, b.height),
        "images of different sizes: {}x{} and {}x{}",
        a.width,
        a.height,
        b.width,
        b.height
    );
    for image in [a, b] {
        ensure!(
            image.pixels.len() == image.width * image.height,
            "{} pixels for {}x{}",
            image.pixels.len(),
            image.width,
            image.height
        );
    }
    let (width, height) = (
        u32::try_from(a.width).context("image too wide")?,
        u32::try_from(a.height).context("image too tall")?,
    );
    let finite = |p: &[f32; 4]| p.iter().all(|v| v.is_finite());
    let both_finite: Vec<bool> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(pa, pb)| finite(pa) && finite(pb))
        .collect();
    let covered: Vec<usize> = (0..b.pixels.len())
        .filter(|&i| both_finite[i] && b.pixels[i][3] > 0.0)
        .collect();

    let (mut sum_d2, mut sum_b2) = (0.0, 0.0);
    for &i in &covered {
        let (pa, pb) = (rgb(&a.pixels[i]), rgb(&b.pixels[i]));
        for c in 0..3 {
            sum_d2 += (pa[c] - pb[c]).powi(2);
            sum_b2 += pb[c].powi(2);
        }
    }
    let mse = sum_d2 / (3 * covered.len()) as f64;

    let luminance = |p: &[f32; 4]| luminance(rgb(p));
    let mean_b_luminance = covered.iter().map(|&i| luminance(&b.pixels[i])).sum::<f64>() / covered.len() as f64;
    let (floor, rel_err) = if mean_b_luminance > 0.0 {
        let floor = REL_ERR_FLOOR * mean_b_luminance;
        let errors = covered.iter().map(|&i| {
            let yb = luminance(&b.pixels[i]);
            (luminance(&a.pixels[i]) - yb).abs() / yb.max(floor)
        });
        (floor, errors.collect())
    } else {
        // B is black: no floor, and no relative error, is meaningful.
        (f64::NAN, Vec::new())
    };

    let error_map = flip_error_map(a, b, &both_finite, width, height);
    let flip = covered.iter().map(|&i| f64::from(error_map[i])).collect();
    let heat_map = heat_map(&error_map, &covered, &both_finite, width, height)?;

    Ok(Comparison {
        metrics: Metrics {
            width: a.width,
            height: a.height,
            covered_pixels: covered.len(),
            non_finite_a: a.pixels.iter().filter(|p| !finite(p)).count(),
            non_finite_b: b.pixels.iter().filter(|p| !finite(p)).count(),
            rel_mse: sum_d2 / sum_b2,
            mse,
            psnr_db: 10.0 * (PSNR_PEAK * PSNR_PEAK / mse).log10(),
            psnr_peak: PSNR_PEAK,
            rel_err: Distribution::of(rel_err),
            rel_err_floor: floor,
            flip: Distribution::of(flip),
            flip_pixels_per_degree: FLIP_PIXELS_PER_DEGREE,
        },
        heat_map,
    })
}

fn rgb(p: &[f32; 4]) -> [f64; 3] {
    [p[0], p[1], p[2]].map(f64::from)
}

/// ꟻLIP of `a` against the reference `b` per pixel, both through the same display transform.
/// A pixel with NaN/Inf in either image is black in both, so that it shows no difference to
/// its neighbours' ꟻLIP filters either.
fn flip_error_map(a: &Rgba32, b: &Rgba32, both_finite: &[bool], width: u32, height: u32) -> Vec<f32> {
    let display = |image: &Rgba32| -> Vec<u8> {
        image
            .pixels
            .iter()
            .zip(both_finite)
            .flat_map(|(p, &ok)| {
                let linear = if ok {
                    [p[0], p[1], p[2]].map(f64::from)
                } else {
                    [0.0; 3]
                };
                display_srgb8(linear)
            })
            .collect()
    };
    nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(width, height, &display(b)),
        nv_flip::FlipImageRgb8::with_data(width, height, &display(a)),
        FLIP_PIXELS_PER_DEGREE,
    )
    .to_vec()
}

/// The error map in magma on the covered pixels, magma's 0 elsewhere, NaN/Inf pixels marked.
fn heat_map(
    error_map: &[f32],
    covered: &[usize],
    both_finite: &[bool],
    width: u32,
    height: u32,
) -> Result<image::RgbImage> {
    let mut shown = vec![0.0f32; error_map.len()];
    for &i in covered {
        shown[i] = error_map[i];
    }
    let mut rgb = nv_flip::FlipImageFloat::with_data(width, height, &shown)
        .apply_color_lut(&nv_flip::magma_lut())
        .to_vec();
    for (pixel, &ok) in rgb.chunks_exact_mut(3).zip(both_finite) {
        if !ok {
            pixel.copy_from_slice(&NON_FINITE_COLOUR);
        }
    }
    image::RgbImage::from_raw(width, height, rgb).context("ꟻLIP heat map has the wrong size")
}
