//! `argil compare`: how far a linear-radiance EXR is from a reference of the same size.
//!
//! - [`input`]: reading EXRs and their `argil.*` attributes, every failure an [`InputError`].
//! - [`metrics`]: the figures, from images in memory.
//!
//! The definitions are in [`HELP`], which `argil compare --help` prints.

pub mod input;
pub mod metrics;

#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Serialize;

use crate::atomic::{write_bytes, Existing};
use crate::error::InputError;
use input::read_exr;
use metrics::{compare, Metrics};

/// The long help of `argil compare`: what each figure is, exactly.
pub const HELP: &str = "\
Compares two linear-radiance EXRs of the same size: A (a real-time render, `argil render
--out a.exr`, or a reference) against B, the reference. Prints one line; --json writes
every figure and the `argil.*` header attributes of both files.

Covered pixels: alpha of B > 0 (edge pixels count fully). A pixel with NaN or Inf in any
channel of A or B is left out of every figure; `nan/inf A/B` counts such pixels in each
whole image. Over the covered pixels:
  rel-mse  Σ(a−b)² / Σb² over pixels and RGB channels, no ε (A = k·B gives (k−1)²).
  psnr     10·log10(1 / mse), mse = mean of (a−b)² over pixels and RGB channels; peak 1,
           display white at exposure 1.
  rel-err  per pixel |Y(a) − Y(b)| / max(Y(b), floor), Y = 0.2126 R + 0.7152 G + 0.0722 B
           (linear Rec. 709), floor = 0.01 × mean Y(b) (in the JSON); mean, p95, p99.
  flip     ꟻLIP (NVIDIA's implementation, 67 pixels per degree) of A against B, both through
           argil's display transform (exposure 1, Khronos PBR Neutral, sRGB, 8 bits), on the
           whole image; mean, p95, p99 of its error map over the covered pixels.
Percentiles are nearest-rank. In the JSON, null is a figure that is undefined (B black)
or infinite (psnr of equal images).

--out writes the ꟻLIP heat map: magma on covered pixels, black elsewhere, green at NaN/Inf.
Exit code 2: bad input (a file missing, unreadable, not an EXR; sizes differ; nothing
covered), bad arguments, or an output that exists without --overwrite or whose folder is
missing or unwritable; nothing is written. Exit code 1: any other failure.";

/// What to compare and where the results go.
pub struct Options {
    pub a: PathBuf,
    pub b: PathBuf,
    /// The ꟻLIP heat map, a PNG.
    pub out: Option<PathBuf>,
    /// The report as JSON.
    pub json: Option<PathBuf>,
    /// What `out` and `json` do with a file at their paths (`--overwrite`).
    pub outputs: Existing,
}

/// The figures and what the EXR headers say about how each image was made.
#[derive(Debug, Serialize)]
pub struct Report {
    pub a: String,
    pub b: String,
    #[serde(flatten)]
    pub metrics: Metrics,
    pub a_attributes: BTreeMap<String, serde_json::Value>,
    pub b_attributes: BTreeMap<String, serde_json::Value>,
}

impl Report {
    /// The one line printed to the terminal.
    pub fn line(&self) -> String {
        let m = &self.metrics;
        format!(
            "flip {} (p95 {}, p99 {})  rel-mse {}  psnr {} dB  rel-err mean {} p95 {} p99 {}  nan/inf {}/{}  covered {} px",
            figure(m.flip.mean),
            figure(m.flip.p95),
            figure(m.flip.p99),
            figure(m.rel_mse),
            figure(m.psnr_db),
            figure(m.rel_err.mean),
            figure(m.rel_err.p95),
            figure(m.rel_err.p99),
            m.non_finite_a,
            m.non_finite_b,
            m.covered_pixels
        )
    }
}

/// Three significant digits, in scientific notation outside [10⁻³, 10⁵).
fn figure(x: f64) -> String {
    if x.is_nan() {
        return "n/a".to_owned();
    }
    if x.is_infinite() || x == 0.0 {
        return format!("{x}");
    }
    let scientific = format!("{x:.2e}");
    // The exponent after rounding to three digits: 0.09999 is 1.00e-1, printed 0.100.
    let exponent: i32 = scientific
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    if (-3..5).contains(&exponent) {
        let decimals = (2 - exponent).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        scientific
    }
}

/// Compares `options.a` with the reference `options.b` and writes the requested files.
pub fn run(options: &Options) -> Result<Report> {
    check_outputs(options)?;
    let a = read_exr(&options.a)?;
    let b = read_exr(&options.b)?;
    let size = |image: &metrics::Rgba32| (image.width, image.height);
    if size(&a.image) != size(&b.image) {
        return Err(InputError(format!(
            "{} is {}x{} but {} is {}x{}: the images must have the same size",
            options.a.display(),
            a.image.width,
            a.image.height,
            options.b.display(),
            b.image.width,
            b.image.height
        ))
        .into());
    }
    let comparison = compare(&a.image, &b.image)?;
    if comparison.metrics.covered_pixels == 0 {
        return Err(InputError::file(
            &options.b,
            "no pixel has alpha > 0 and finite values in both images: nothing to compare",
        )
        .into());
    }
    let report = Report {
        a: options.a.display().to_string(),
        b: options.b.display().to_string(),
        metrics: comparison.metrics,
        a_attributes: a.attributes,
        b_attributes: b.attributes,
    };
    if let Some(out) = &options.out {
        let mut png = Cursor::new(Vec::new());
        comparison
            .heat_map
            .write_to(&mut png, image::ImageFormat::Png)
            .context("cannot encode the heat map")?;
        write_bytes(out, options.outputs, png.get_ref())?;
    }
    if let Some(json) = &options.json {
        let mut text = serde_json::to_string_pretty(&report).context("cannot encode the JSON report")?;
        text.push('\n');
        write_bytes(json, options.outputs, text.as_bytes())?;
    }
    Ok(report)
}

/// Refuses outputs that would overwrite an input or each other, before anything is read.
fn check_outputs(options: &Options) -> Result<(), InputError> {
    if let Some(out) = &options.out {
        let is_png = out.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !is_png {
            return Err(InputError::file(out, "--out must end in .png (the heat map is a PNG)"));
        }
    }
    let outputs = [&options.out, &options.json].into_iter().flatten();
    for (i, output) in outputs.clone().enumerate() {
        let mut others = [&options.a, &options.b].into_iter().chain(outputs.clone().skip(i + 1));
        if let Some(other) = others.find(|other| same_file(output, other)) {
            return Err(InputError::file(
                output,
                format_args!("would overwrite {}", other.display()),
            ));
        }
    }
    Ok(())
}

/// Whether two paths name one file, existing or not.
fn same_file(x: &Path, y: &Path) -> bool {
    x == y || matches!((resolved(x), resolved(y)), (Some(p), Some(q)) if p == q)
}

/// `path` absolute with links resolved; for a file not written yet, through its folder.
fn resolved(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok().or_else(|| {
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        Some(std::fs::canonicalize(folder).ok()?.join(path.file_name()?))
    })
}
