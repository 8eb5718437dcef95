//! The bench's rows and the files written from them: `results.csv`, `results.json`,
//! `results.md`, each written atomically.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use ash::vk;
use serde::Serialize;

use super::plan::{Configuration, FLOOR, REPORT};
use super::plot::plot;
use super::references::CachedReference;
use super::Timing;
use crate::atomic::write_bytes;
use crate::compare::metrics::Metrics;
use crate::render::PASS_NAMES;

/// Where and when a run was made.
pub struct Provenance {
    pub device: String,
    pub driver: String,
    pub date: String,
    pub commit: String,
}

/// The error of a frame against one reference, and that reference's own noise.
#[derive(Clone, Debug, Serialize)]
pub struct Error {
    pub flip_mean: f64,
    pub rel_mse: f64,
    pub reference_noise: f64,
    pub reference_spp: u32,
}

impl Error {
    fn new(metrics: &Metrics, reference: &CachedReference) -> Self {
        Self {
            flip_mean: metrics.flip.mean,
            rel_mse: metrics.rel_mse,
            reference_noise: reference.noise,
            reference_spp: reference.samples,
        }
    }
}

/// One scene × configuration × resolution. Milliseconds; ratios are medians over pairs of
/// frames, each of the configuration against a floor frame drawn just before it.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub scene: String,
    pub configuration: String,
    /// The report's composition (reflection, horizon and subsurface `seed`).
    pub report: bool,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub gpu_ms_median: f64,
    pub gpu_ms_p95: f64,
    /// Median GPU milliseconds of each pass of [`PASS_NAMES`].
    pub pass_ms_median: Vec<f64>,
    pub cpu_ms_median: f64,
    pub cpu_ms_p95: f64,
    /// Median GPU milliseconds of the floor frames' forward pass.
    pub floor_forward_ms_median: f64,
    /// Forward pass against the floor's forward pass: what shading costs.
    pub forward_ratio_to_floor: f64,
    pub forward_ratio_to_floor_p95: f64,
    /// The whole frame (every pass) against the floor's whole frame.
    pub gpu_ratio_to_floor: f64,
    /// Against the `full` and `direct` references, at their size.
    pub error_full: Error,
    pub error_direct: Error,
    pub error_width: usize,
    pub error_height: usize,
    pub device: String,
    pub driver: String,
    pub date: String,
    pub commit: String,
}

impl Row {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        scene: &str,
        configuration: &Configuration,
        extent: vk::Extent2D,
        timing: &Timing,
        full: (&Metrics, &CachedReference),
        direct: (&Metrics, &CachedReference),
        provenance: &Provenance,
    ) -> Self {
        Self {
            scene: scene.to_owned(),
            configuration: configuration.name.clone(),
            report: configuration.name == REPORT,
            width: extent.width,
            height: extent.height,
            frames: timing.frames,
            gpu_ms_median: timing.gpu_total.median,
            gpu_ms_p95: timing.gpu_total.p95,
            pass_ms_median: timing.passes.iter().map(|p| p.median).collect(),
            cpu_ms_median: timing.cpu.median,
            cpu_ms_p95: timing.cpu.p95,
            floor_forward_ms_median: timing.floor_forward.median,
            forward_ratio_to_floor: timing.forward_ratio.median,
            forward_ratio_to_floor_p95: timing.forward_ratio.p95,
            gpu_ratio_to_floor: timing.gpu_ratio.median,
            error_full: Error::new(full.0, full.1),
            error_direct: Error::new(direct.0, direct.1),
            error_width: full.0.width,
            error_height: full.0.height,
            device: provenance.device.clone(),
            driver: provenance.driver.clone(),
            date: provenance.date.clone(),
            commit: provenance.commit.clone(),
        }
    }

    /// The row as one line of progress.
    pub fn line(&self) -> String {
        format!(
            "{} {} {}x{}: GPU {:.2} ms (p95 {:.2}), forward {:.1}× the floor, CPU {:.2} ms, ꟻLIP full {:.4} direct {:.4}",
            self.scene,
            self.configuration,
            self.width,
            self.height,
            self.gpu_ms_median,
            self.gpu_ms_p95,
            self.forward_ratio_to_floor,
            self.cpu_ms_median,
            self.error_full.flip_mean,
            self.error_direct.flip_mean
        )
    }
}

/// Writes `results.csv`, `results.json`, `results.md` and a `plot-SCENE.png` per scene
/// (each configuration at its first size) into `dir`.
pub fn write(dir: &Path, rows: &[Row]) -> Result<()> {
    write_bytes(&dir.join("results.csv"), csv(rows).as_bytes())?;
    write_bytes(
        &dir.join("results.json"),
        serde_json::to_string_pretty(rows)?.as_bytes(),
    )?;
    write_bytes(&dir.join("results.md"), markdown(rows).as_bytes())?;
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    for scene in scenes {
        let mut shown: Vec<&Row> = Vec::new();
        for r in rows.iter().filter(|r| r.scene == scene && r.configuration != FLOOR) {
            if !shown.iter().any(|s| s.configuration == r.configuration) {
                shown.push(r);
            }
        }
        if let Some(first) = shown.first() {
            let title = format!("{scene} scene, {}×{}, {}", first.width, first.height, first.device);
            plot(&dir.join(format!("plot-{scene}.png")), &title, &shown)?;
        }
    }
    Ok(())
}

fn csv(rows: &[Row]) -> String {
    let mut header = vec![
        "scene",
        "configuration",
        "width",
        "height",
        "frames",
        "gpu_ms_median",
        "gpu_ms_p95",
    ];
    let pass_columns: Vec<String> = PASS_NAMES.iter().map(|p| format!("{p}_ms_median")).collect();
    header.extend(pass_columns.iter().map(String::as_str));
    header.extend([
        "cpu_ms_median",
        "cpu_ms_p95",
        "floor_forward_ms_median",
        "forward_ratio_to_floor",
        "forward_ratio_to_floor_p95",
        "gpu_ratio_to_floor",
        "flip_full",
        "rel_mse_full",
        "flip_direct",
        "rel_mse_direct",
        "reference_noise_full",
        "reference_noise_direct",
        "error_width",
        "error_height",
        "device",
        "driver",
        "date",
        "commit",
    ]);
    let mut text = header.join(",") + "\n";
    for r in rows {
        let mut fields = vec![
            csv_field(&r.scene),
            csv_field(&r.configuration),
            r.width.to_string(),
            r.height.to_string(),
            r.frames.to_string(),
            r.gpu_ms_median.to_string(),
            r.gpu_ms_p95.to_string(),
        ];
        fields.extend(r.pass_ms_median.iter().map(f64::to_string));
        fields.extend([
            r.cpu_ms_median.to_string(),
            r.cpu_ms_p95.to_string(),
            r.floor_forward_ms_median.to_string(),
            r.forward_ratio_to_floor.to_string(),
            r.forward_ratio_to_floor_p95.to_string(),
            r.gpu_ratio_to_floor.to_string(),
            r.error_full.flip_mean.to_string(),
            r.error_full.rel_mse.to_string(),
            r.error_direct.flip_mean.to_string(),
            r.error_direct.rel_mse.to_string(),
            r.error_full.reference_noise.to_string(),
            r.error_direct.reference_noise.to_string(),
            r.error_width.to_string(),
            r.error_height.to_string(),
            csv_field(&r.device),
            csv_field(&r.driver),
            csv_field(&r.date),
            csv_field(&r.commit),
        ]);
        text += &(fields.join(",") + "\n");
    }
    text
}

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The table of every row, with where it was measured and the references' noise.
pub fn markdown(rows: &[Row]) -> String {
    let mut text = String::new();
    if let Some(first) = rows.first() {
        let _ = writeln!(
            text,
            "Measured on {} ({}), commit {}, {}. GPU and CPU milliseconds per frame: median (p95) \
             of the row's steady frames; × floor: the forward pass against the trivial-shader floor's \
             in the frame drawn just before, median of the pairs. Error at {}×{} against the `full` reference ({} spp, noise {:.2}%) and the `direct` one ({} spp, \
             noise {:.2}%).\n",
            first.device,
            first.driver,
            first.commit,
            first.date,
            first.error_width,
            first.error_height,
            first.error_full.reference_spp,
            first.error_full.reference_noise * 100.0,
            first.error_direct.reference_spp,
            first.error_direct.reference_noise * 100.0,
        );
    }
    text += "| scene | configuration | size | frames | GPU ms | forward ms | CPU ms | × floor | ꟻLIP full | rel. MSE full | ꟻLIP direct | rel. MSE direct |\n";
    text += "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for r in rows {
        let name = if r.report {
            format!("**{}**", r.configuration)
        } else {
            r.configuration.clone()
        };
        let _ = writeln!(
            text,
            "| {} | {name} | {}×{} | {} | {:.2} ({:.2}) | {:.2} | {:.2} ({:.2}) | {:.1} | {:.4} | {:.2e} | {:.4} | {:.2e} |",
            r.scene,
            r.width,
            r.height,
            r.frames,
            r.gpu_ms_median,
            r.gpu_ms_p95,
            r.pass_ms_median[0],
            r.cpu_ms_median,
            r.cpu_ms_p95,
            r.forward_ratio_to_floor,
            r.error_full.flip_mean,
            r.error_full.rel_mse,
            r.error_direct.flip_mean,
            r.error_direct.rel_mse,
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::csv_field;

    #[test]
    fn csv_fields_are_quoted_only_when_needed() {
        assert_eq!(
            csv_field("llvmpipe (LLVM 19.1.7, 256 bits)"),
            "\"llvmpipe (LLVM 19.1.7, 256 bits)\""
        );
        assert_eq!(csv_field("say \"hi\", x"), "\"say \"\"hi\"\", x\"");
        assert_eq!(csv_field("split-sum"), "split-sum");
    }
}
