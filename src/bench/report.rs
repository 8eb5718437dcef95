//! The bench's rows and the files written from them: `results.csv`, `results.json`,
//! `results.md`, each written atomically.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use ash::vk;
use serde::{Deserialize, Serialize};

use super::plan::{Configuration, FLOOR, REPORT};
use super::plot::plot;
use super::references::CachedReference;
use super::{Floor, Timing};
use crate::atomic::{write_bytes, Existing};
use crate::compare::metrics::Metrics;
use crate::render::PASS_NAMES;

/// Where and when a run was made.
pub struct Provenance {
    pub device: String,
    pub driver: String,
    /// The CPU and its threads ([`super::host`]).
    pub host: String,
    pub date: String,
    pub commit: String,
}

/// The error of a frame against one reference, and that reference's own noise.
#[derive(Clone, Debug, Serialize, Deserialize)]
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

/// One scene × configuration × resolution. Milliseconds; ratios are the configuration's
/// medians (and p95) over the floor's ([`Floor`]: the floor frames of the scene's rows at
/// this size that draw its own meshes, in the run).
#[derive(Clone, Debug, Serialize, Deserialize)]
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
    /// Median GPU milliseconds of the floor frames' forward pass (the run's at this size).
    pub floor_forward_ms_median: f64,
    /// Forward pass against the floor's forward pass: what shading costs.
    pub forward_ratio_to_floor: f64,
    pub forward_ratio_to_floor_p95: f64,
    /// The whole frame (every pass) against the floor's whole frame.
    pub gpu_ratio_to_floor: f64,
    /// Median CPU milliseconds the process spent on a frame (every thread): on a software
    /// device, the rendering's work.
    pub work_ms_median: f64,
    /// That work against the floor frames': on a software device, the ratio that other
    /// load on the machine leaves alone.
    pub work_ratio_to_floor: f64,
    /// Against the `full` and `shadows` references, at their size.
    pub error_full: Error,
    pub error_shadows: Error,
    pub error_width: usize,
    pub error_height: usize,
    pub device: String,
    pub driver: String,
    /// Empty in rows written before it was kept.
    #[serde(default)]
    pub host: String,
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
        floor: &Floor,
        full: (&Metrics, &CachedReference),
        shadows: (&Metrics, &CachedReference),
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
            floor_forward_ms_median: floor.forward,
            forward_ratio_to_floor: timing.passes[0].median / floor.forward,
            forward_ratio_to_floor_p95: timing.passes[0].p95 / floor.forward,
            gpu_ratio_to_floor: timing.gpu_total.median / floor.gpu,
            work_ms_median: timing.work.median,
            work_ratio_to_floor: timing.work.median / floor.work,
            error_full: Error::new(full.0, full.1),
            error_shadows: Error::new(shadows.0, shadows.1),
            error_width: full.0.width,
            error_height: full.0.height,
            device: provenance.device.clone(),
            driver: provenance.driver.clone(),
            host: provenance.host.clone(),
            date: provenance.date.clone(),
            commit: provenance.commit.clone(),
        }
    }

    /// The row as one line of progress.
    pub fn line(&self) -> String {
        format!(
            "{} {} {}x{}: GPU {:.2} ms (p95 {:.2}), forward {:.1}× the floor (work {:.1}×), CPU {:.2} ms, ꟻLIP full {:.4} shadows {:.4}",
            self.scene,
            self.configuration,
            self.width,
            self.height,
            self.gpu_ms_median,
            self.gpu_ms_p95,
            self.forward_ratio_to_floor,
            self.work_ratio_to_floor,
            self.cpu_ms_median,
            self.error_full.flip_mean,
            self.error_shadows.flip_mean
        )
    }
}

/// The rows of `dir/results.json`; none if there is no such file.
pub fn read(dir: &Path) -> Result<Vec<Row>> {
    let path = dir.join("results.json");
    match std::fs::read(&path) {
        Ok(bytes) => serde_json::from_slice(&bytes)
            .with_context(|| format!("{}: not the bench's results (rerun without --only)", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(e).with_context(|| format!("cannot read {}", path.display())),
    }
}

/// `old` with each row of `new` in place of the row of the same scene, configuration and
/// size, or after the last row of its scene (at the end for a new scene). Rows of `old`
/// that are not `planned` (a configuration the bench no longer has) are dropped, so that
/// the results describe only what this build measures.
pub fn merged(old: Vec<Row>, new: Vec<Row>, planned: impl Fn(&Row) -> bool) -> Vec<Row> {
    let mut old: Vec<Row> = old.into_iter().filter(|r| planned(r)).collect();
    for row in new {
        let same = |r: &Row| {
            r.scene == row.scene
                && r.configuration == row.configuration
                && (r.width, r.height) == (row.width, row.height)
        };
        if let Some(i) = old.iter().position(same) {
            old[i] = row;
        } else {
            let at = old
                .iter()
                .rposition(|r| r.scene == row.scene)
                .map_or(old.len(), |i| i + 1);
            old.insert(at, row);
        }
    }
    old
}

/// A row's scene, configuration and size.
pub type RowKey = (String, String, u32, u32);

/// A run's results folder, written again after each group of rows, so that a run that
/// stops (Ctrl-C, a lost device) leaves what it measured beside the rows it did not reach.
pub struct Results {
    dir: PathBuf,
    /// The rows in the folder when the run began.
    earlier: Vec<Row>,
    rows: Vec<Row>,
    /// Each planned row's place: the plan's order of scenes, configurations and sizes,
    /// whichever order the rows were measured or merged in.
    order: HashMap<RowKey, usize>,
    /// `--only`: the run measures some rows and keeps the others.
    only: bool,
    /// `--quick`: it plans fewer rows, so it keeps every earlier row it merges with.
    quick: bool,
}

impl Results {
    pub fn new(dir: &Path, earlier: Vec<Row>, order: HashMap<RowKey, usize>, only: bool, quick: bool) -> Self {
        Self {
            dir: dir.to_path_buf(),
            earlier,
            rows: Vec::new(),
            order,
            only,
            quick,
        }
    }

    /// Adds `rows` and writes the folder: the earlier rows with these in their places.
    pub fn add(&mut self, rows: Vec<Row>) -> Result<()> {
        self.rows.extend(rows);
        write(&self.dir, &self.merged(true))
    }

    /// Writes the folder once the run is over: with `--only`, the earlier rows beside the
    /// new ones, but for those of configurations a whole run no longer makes; after a whole
    /// run, its rows alone.
    pub fn finish(self) -> Result<()> {
        let rows = self.merged(self.only);
        if rows.is_empty() {
            return Ok(());
        }
        write(&self.dir, &rows)
    }

    fn merged(&self, keep_earlier: bool) -> Vec<Row> {
        let place = |r: &Row| self.order.get(&(r.scene.clone(), r.configuration.clone(), r.width, r.height));
        let mut rows = if keep_earlier {
            merged(self.earlier.clone(), self.rows.clone(), |r| self.quick || place(r).is_some())
        } else {
            self.rows.clone()
        };
        // A quick run's earlier rows, which it did not plan, stay after its own.
        rows.sort_by_cached_key(|r| place(r).copied().unwrap_or(usize::MAX));
        rows
    }
}

/// Writes `results.csv`, `results.json`, `results.md` and a `plot-SCENE.png` per scene
/// (each configuration at its first size) into `dir`.
pub fn write(dir: &Path, rows: &[Row]) -> Result<()> {
    let json = serde_json::to_string_pretty(rows)?;
    write_bytes(&dir.join("results.csv"), Existing::Replace, csv(rows).as_bytes())?;
    write_bytes(&dir.join("results.json"), Existing::Replace, json.as_bytes())?;
    write_bytes(&dir.join("results.md"), Existing::Replace, markdown(rows).as_bytes())?;
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
        "work_ms_median",
        "work_ratio_to_floor",
        "flip_full",
        "rel_mse_full",
        "flip_shadows",
        "rel_mse_shadows",
        "reference_noise_full",
        "reference_noise_shadows",
        "error_width",
        "error_height",
        "device",
        "driver",
        "host",
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
            r.work_ms_median.to_string(),
            r.work_ratio_to_floor.to_string(),
            r.error_full.flip_mean.to_string(),
            r.error_full.rel_mse.to_string(),
            r.error_shadows.flip_mean.to_string(),
            r.error_shadows.rel_mse.to_string(),
            r.error_full.reference_noise.to_string(),
            r.error_shadows.reference_noise.to_string(),
            r.error_width.to_string(),
            r.error_height.to_string(),
            csv_field(&r.device),
            csv_field(&r.driver),
            csv_field(&r.host),
            csv_field(&r.date),
            csv_field(&r.commit),
        ]);
        text += &(fields.join(",") + "\n");
    }
    text
}

/// A row's host, or what rows written before the host was kept say instead.
fn host_or_unrecorded(host: &str) -> String {
    if host.is_empty() { "host not recorded" } else { host }.to_owned()
}

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The table of every row, with where and at which commits its rows were measured (an
/// `--only` run replaces some rows and keeps the others) and each scene's references.
pub fn markdown(rows: &[Row]) -> String {
    let mut text = String::new();
    if !rows.is_empty() {
        let devices = distinct(rows, |r| format!("{}, driver {}", r.device, r.driver)).join("; ");
        let commits = distinct(rows, |r| r.commit.clone())
            .iter()
            .map(|commit| {
                let at = || rows.iter().filter(|r| &r.commit == commit);
                let dates = distinct(at(), |r| r.date.get(..10).unwrap_or(&r.date).to_owned()).join(", ");
                let hosts = distinct(at(), |r| host_or_unrecorded(&r.host)).join("; ");
                let count = at().count();
                format!("{commit} ({count} row{}, {dates}, {hosts})", if count == 1 { "" } else { "s" })
            })
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            text,
            "Measured on {devices}. Rows per commit: {commits} (each row's commit and time are in \
             results.csv). On a software device the host's CPU is the device: compare milliseconds \
             between rows of one host, ratios to the floor across hosts. GPU and CPU milliseconds per \
             frame: median (p95) of the row's steady frames; × floor: the forward pass's median against \
             the trivial-shader floor's, the median of the floor frames drawn between the frames of the \
             scene's rows at that size that draw its own meshes, in the run; × floor (work): the same \
             ratio of the CPU time the process spent (on a software device the rendering's work, which \
             other load on the machine does not stretch). Error against the scene's `full` and `shadows` references, at their size:\n"
        );
        text += "| scene | size | `full` reference | `shadows` reference |\n| --- | --- | --- | --- |\n";
        for scene in distinct(rows, |r| r.scene.clone()) {
            if let Some(r) = rows.iter().find(|r| r.scene == scene) {
                let reference = |e: &Error| format!("{} spp, noise {:.2}%", e.reference_spp, e.reference_noise * 100.0);
                let _ = writeln!(
                    text,
                    "| {scene} | {}×{} | {} | {} |",
                    r.error_width,
                    r.error_height,
                    reference(&r.error_full),
                    reference(&r.error_shadows)
                );
            }
        }
        text.push('\n');
    }
    text += "| scene | configuration | size | frames | GPU ms | forward ms | CPU ms | × floor | × floor (work) | ꟻLIP full | rel. MSE full | ꟻLIP shadows | rel. MSE shadows |\n";
    text += "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for r in rows {
        let name = if r.report {
            format!("**{}**", r.configuration)
        } else {
            r.configuration.clone()
        };
        let _ = writeln!(
            text,
            "| {} | {name} | {}×{} | {} | {:.2} ({:.2}) | {:.2} | {:.2} ({:.2}) | {:.1} | {:.1} | {:.4} | {:.2e} | {:.4} | {:.2e} |",
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
            r.work_ratio_to_floor,
            r.error_full.flip_mean,
            r.error_full.rel_mse,
            r.error_shadows.flip_mean,
            r.error_shadows.rel_mse,
        );
    }
    text
}

/// The values `key` takes over `rows`, each once, in the order they first appear.
fn distinct<'a>(rows: impl IntoIterator<Item = &'a Row>, key: impl Fn(&Row) -> String) -> Vec<String> {
    let mut values: Vec<String> = Vec::new();
    for value in rows.into_iter().map(key) {
        if !values.contains(&value) {
            values.push(value);
        }
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(scene: &str, configuration: &str, width: u32, gpu_ms: f64) -> Row {
        let error = Error {
            flip_mean: 0.1,
            rel_mse: 0.01,
            reference_noise: 0.01,
            reference_spp: 16,
        };
        Row {
            scene: scene.to_owned(),
            configuration: configuration.to_owned(),
            report: false,
            width,
            height: width / 2,
            frames: 10,
            gpu_ms_median: gpu_ms,
            gpu_ms_p95: gpu_ms,
            pass_ms_median: vec![gpu_ms; PASS_NAMES.len()],
            cpu_ms_median: gpu_ms,
            cpu_ms_p95: gpu_ms,
            floor_forward_ms_median: 1.0,
            forward_ratio_to_floor: gpu_ms,
            forward_ratio_to_floor_p95: gpu_ms,
            gpu_ratio_to_floor: gpu_ms,
            work_ms_median: gpu_ms,
            work_ratio_to_floor: gpu_ms,
            error_full: error.clone(),
            error_shadows: error,
            error_width: 32,
            error_height: 16,
            device: "d".to_owned(),
            driver: "v".to_owned(),
            host: "h".to_owned(),
            date: "2026-12-01".to_owned(),
            commit: "c".to_owned(),
        }
    }

    #[test]
    fn merged_rows_replace_their_namesakes_join_their_scene_and_drop_the_unplanned() {
        let old = vec![
            row("a", "x", 64, 1.0),
            row("a", "y", 64, 2.0),
            row("a", "gone", 64, 2.5),
            row("b", "x", 64, 3.0),
        ];
        let new = vec![
            row("a", "y", 64, 20.0),
            row("a", "y", 128, 21.0),
            row("c", "x", 64, 30.0),
        ];
        let merged: Vec<(String, String, u32, f64)> = merged(old, new, |r| r.configuration != "gone")
            .into_iter()
            .map(|r| (r.scene, r.configuration, r.width, r.gpu_ms_median))
            .collect();
        let expected = [
            ("a", "x", 64, 1.0),
            ("a", "y", 64, 20.0),
            ("a", "y", 128, 21.0),
            ("b", "x", 64, 3.0),
            ("c", "x", 64, 30.0),
        ];
        let expected: Vec<(String, String, u32, f64)> = expected
            .iter()
            .map(|&(s, c, w, t)| (s.to_owned(), c.to_owned(), w, t))
            .collect();
        assert_eq!(merged, expected);
    }

    /// While a run goes on, the folder holds the earlier rows with the new ones in their
    /// places; a whole run's end leaves its rows alone, an `--only` run's the merge.
    #[test]
    fn results_are_written_after_each_group_and_replaced_by_a_whole_run() {
        let dir = std::env::temp_dir().join(format!("argil-bench-results-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let keys = [("a", "x"), ("a", "y"), ("b", "x")];
        let order: HashMap<RowKey, usize> =
            keys.iter().enumerate().map(|(i, &(s, c))| ((s.to_owned(), c.to_owned(), 64, 32), i)).collect();
        let earlier = || vec![row("b", "x", 64, 3.0), row("a", "x", 64, 1.0), row("a", "gone", 64, 9.0)];
        let on_disk = || -> Vec<(String, String, f64)> {
            read(&dir).unwrap().into_iter().map(|r| (r.scene, r.configuration, r.gpu_ms_median)).collect()
        };
        let named = |rows: &[(&str, &str, f64)]| -> Vec<(String, String, f64)> {
            rows.iter().map(|&(s, c, t)| (s.to_owned(), c.to_owned(), t)).collect()
        };
        for only in [false, true] {
            let mut results = Results::new(&dir, earlier(), order.clone(), only, false);
            results.add(vec![row("a", "y", 64, 20.0)]).unwrap();
            assert_eq!(on_disk(), named(&[("a", "x", 1.0), ("a", "y", 20.0), ("b", "x", 3.0)]));
            results.add(vec![row("b", "x", 64, 30.0)]).unwrap();
            assert_eq!(on_disk(), named(&[("a", "x", 1.0), ("a", "y", 20.0), ("b", "x", 30.0)]));
            results.finish().unwrap();
            let after = if only {
                named(&[("a", "x", 1.0), ("a", "y", 20.0), ("b", "x", 30.0)])
            } else {
                named(&[("a", "y", 20.0), ("b", "x", 30.0)])
            };
            assert_eq!(on_disk(), after, "--only: {only}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn rows_read_back_as_written() {
        let dir = std::env::temp_dir().join(format!("argil-bench-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(read(&dir).unwrap().is_empty(), "no results yet");
        // A value whose shortest decimal a fast parser reads back one ulp off: an `--only`
        // run rewrites the kept rows, which must not change.
        let awkward = 10.161857999999999;
        write(&dir, &[row("a", "x", 64, awkward)]).unwrap();
        let back = read(&dir).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!(back[0].gpu_ms_median.to_bits(), f64::to_bits(awkward));
    }

    /// Rows kept from an earlier run keep their commit and host: the header names every
    /// commit with its rows and hosts, and each scene's references.
    #[test]
    fn the_table_names_every_commit_and_each_scenes_references() {
        let mut later = row("b", "x", 64, 3.0);
        later.commit = "d".to_owned();
        later.date = "2026-12-02T10:00:00Z".to_owned();
        later.error_full.reference_spp = 99;
        let mut unrecorded = row("a", "y", 64, 2.0);
        unrecorded.host.clear();
        let text = markdown(&[row("a", "x", 64, 1.0), unrecorded, later]);
        let header = text.lines().next().unwrap();
        assert!(
            header.contains("c (2 rows, 2026-12-01, h; host not recorded), d (1 row, 2026-12-02, h)"),
            "{header}"
        );
        assert!(text.contains("| a | 32×16 | 16 spp, noise 1.00% | 16 spp, noise 1.00% |"), "{text}");
        assert!(text.contains("| b | 32×16 | 99 spp, noise 1.00% | 16 spp, noise 1.00% |"), "{text}");
    }

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
