//! Startup: wall time from process start to the first finished frame, in its parts. A
//! child `argil render --timings` records its steps; the bench runs it three times on the
//! default scene ([`KINDS`]): with empty caches (cold: argil's disk cache and Mesa's shader
//! cache), with argil's cache empty and Mesa's as the cold start left it (the driver has
//! compiled these shaders before, as after any earlier run of this build), and with the
//! caches the cold start filled (warm).

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use ash::vk;
use serde::{Deserialize, Serialize};

use crate::atomic::{write_bytes, Existing};
use crate::scratch::Scratch;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    pub name: String,
    pub ms: f64,
}

/// The kinds of start, in the order a run makes them, and what each one's caches hold.
pub const KINDS: [(&str, &str); 3] = [
    ("cold", "empty argil and Mesa caches"),
    ("argil cold", "an empty argil cache, Mesa's as the cold start left it"),
    ("warm", "the caches the cold start filled"),
];

/// One start of each of [`KINDS`].
pub type Run = [Startup; KINDS.len()];

/// One start: its steps in order, the work other threads did beside them, and from process
/// start to the first frame (read back) and to that frame written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Startup {
    /// Which of [`KINDS`] it is, when the bench measured it.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub kind: String,
    pub steps: Vec<Step>,
    /// Wall time of work on other threads, which the steps do not count.
    #[serde(default)]
    pub beside: Vec<Step>,
    /// 0 in records written before it was kept.
    #[serde(default)]
    pub first_frame_ms: f64,
    pub total_ms: f64,
}

/// Records the steps of a start as they happen.
pub struct Recorder {
    process_start: Instant,
    steps: Vec<Step>,
    beside: Vec<Step>,
    first_frame: Duration,
}

impl Recorder {
    pub fn new(process_start: Instant) -> Self {
        Self {
            process_start,
            steps: Vec::new(),
            beside: Vec::new(),
            first_frame: Duration::ZERO,
        }
    }

    /// Runs `work` as step `name`.
    pub fn step<T>(&mut self, name: &str, work: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = work();
        self.record(name, start.elapsed());
        result
    }

    pub fn record(&mut self, name: &str, time: Duration) {
        self.steps.push(step(name, time));
    }

    /// Records `time` of work `name` that other threads did beside the steps.
    pub fn record_beside(&mut self, name: &str, time: Duration) {
        self.beside.push(step(name, time));
    }

    /// The first frame is finished now.
    pub fn first_frame(&mut self) {
        self.first_frame = self.process_start.elapsed();
    }

    /// The start so far, as JSON written atomically to `path`.
    pub fn write(&self, path: &Path, existing: Existing) -> Result<()> {
        let startup = Startup {
            kind: String::new(),
            steps: self.steps.clone(),
            beside: self.beside.clone(),
            first_frame_ms: self.first_frame.as_secs_f64() * 1e3,
            total_ms: self.process_start.elapsed().as_secs_f64() * 1e3,
        };
        write_bytes(path, existing, serde_json::to_string_pretty(&startup)?.as_bytes())
    }
}

fn step(name: &str, time: Duration) -> Step {
    Step {
        name: name.to_owned(),
        ms: time.as_secs_f64() * 1e3,
    }
}

/// `runs` runs of the starts of [`KINDS`] of the default scene at `extent` on device
/// `device_index`, each run from empty caches of its own.
pub fn measure(device_index: usize, extent: vk::Extent2D, runs: u32) -> Result<Vec<Run>> {
    (0..runs).map(|_| measure_run(device_index, extent)).collect()
}

/// A start of each of [`KINDS`], in order: the cold one fills the caches that the others
/// read.
fn measure_run(device_index: usize, extent: vk::Extent2D) -> Result<Run> {
    let dir = Scratch::new("startup")?;
    let exe = std::env::current_exe().context("cannot find the argil executable")?;
    let start = |kind: usize, argil_cache: &str| -> Result<Startup> {
        let run = KINDS[kind].0.replace(' ', "-");
        let timings = dir.join(format!("{run}.json"));
        let output = Command::new(&exe)
            .args(["--device", &device_index.to_string(), "render", "--out"])
            .arg(dir.join(format!("{run}.exr")))
            .args([
                "--width",
                &extent.width.to_string(),
                "--height",
                &extent.height.to_string(),
            ])
            .arg("--timings")
            .arg(&timings)
            .env("ARGIL_CACHE_DIR", dir.join(argil_cache))
            .env("MESA_SHADER_CACHE_DIR", dir.join("mesa-cache"))
            .output()
            .context("cannot start argil render")?;
        if !output.status.success() {
            bail!(
                "argil render failed: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            );
        }
        let bytes = std::fs::read(&timings).with_context(|| format!("cannot read {}", timings.display()))?;
        let start: Startup =
            serde_json::from_slice(&bytes).with_context(|| format!("{}: not a startup record", timings.display()))?;
        Ok(Startup {
            kind: KINDS[kind].0.to_owned(),
            ..start
        })
    };
    Ok([
        start(0, "argil-cache")?,
        start(1, "argil-cache-empty")?,
        start(2, "argil-cache")?,
    ])
}

/// Of `runs`, the start of each kind whose time to the first frame is the median (the
/// lower of the middle two of an even count): whole starts, so that their steps add up as
/// they happened.
pub fn median(runs: &[Run]) -> Result<Run> {
    if runs.is_empty() {
        bail!("no startup was measured");
    }
    Ok(std::array::from_fn(|kind| {
        let mut starts: Vec<&Startup> = runs.iter().map(|run| &run[kind]).collect();
        starts.sort_by(|a, b| a.first_frame_ms.total_cmp(&b.first_frame_ms));
        starts[(starts.len() - 1) / 2].clone()
    }))
}

/// The table of the median start of each kind of `runs` on `host`, a row per step, and
/// every run's time to the first frame.
pub fn markdown(extent: vk::Extent2D, host: &str, runs: &[Run]) -> Result<String> {
    let medians = median(runs)?;
    let kinds: Vec<String> = KINDS.iter().map(|(kind, caches)| format!("{kind} ({caches})")).collect();
    let mut text = format!(
        "Start of `argil render` of the default scene at {}×{} to an EXR on {host}: wall milliseconds per step, \
         {}; the median of {} starts of each by the time to the first frame.\n\n\
         | step | {} |\n|{}\n",
        extent.width,
        extent.height,
        kinds.join(", "),
        runs.len(),
        KINDS.map(|(kind, _)| format!("{kind} ms")).join(" | "),
        " --- |".repeat(KINDS.len() + 1),
    );
    let row = |name: &str, ms: &mut dyn Iterator<Item = f64>, bold: bool| {
        let cells: Vec<String> = ms.map(|ms| if bold { format!("**{ms:.1}**") } else { format!("{ms:.1}") }).collect();
        format!("| {name} | {} |\n", cells.join(" | "))
    };
    for (i, step) in medians[0].steps.iter().enumerate() {
        text += &row(&step.name, &mut medians.iter().map(|m| m.steps.get(i).map_or(f64::NAN, |s| s.ms)), false);
    }
    text += &row("**process start to first frame**", &mut medians.iter().map(|m| m.first_frame_ms), true);
    text += &row("**process start to frame written**", &mut medians.iter().map(|m| m.total_ms), true);
    for (i, step) in medians[0].beside.iter().enumerate() {
        let name = format!("*beside the steps, on other threads:* {}", step.name);
        text += &row(&name, &mut medians.iter().map(|m| m.beside.get(i).map_or(f64::NAN, |s| s.ms)), false);
    }
    let first_frames = |kind: usize| {
        let times: Vec<String> = runs.iter().map(|run| format!("{:.1}", run[kind].first_frame_ms)).collect();
        format!("{} {} ms", KINDS[kind].0, times.join(", "))
    };
    let every: Vec<String> = (0..KINDS.len()).map(first_frames).collect();
    text += &format!("\nProcess start to the first frame, each run in order: {}.\n", every.join("; "));
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start(first_frame_ms: f64) -> Startup {
        Startup {
            steps: vec![step("first frame and readback", Duration::from_secs_f64(first_frame_ms / 1e3))],
            first_frame_ms,
            total_ms: first_frame_ms + 1.0,
            ..Startup::default()
        }
    }

    /// The median start of each kind is a whole run's, the lower middle one of an even count.
    #[test]
    fn the_median_starts_are_whole_runs() {
        let runs = |times: &[(f64, f64, f64)]| -> Vec<Run> {
            times.iter().map(|&(cold, argil_cold, warm)| [start(cold), start(argil_cold), start(warm)]).collect()
        };
        let medians = |times: &[(f64, f64, f64)]| median(&runs(times)).expect("a median").map(|s| s.first_frame_ms);
        assert_eq!(medians(&[(1500.0, 900.0, 450.0)]), [1500.0, 900.0, 450.0]);
        let three = [(1600.0, 800.0, 440.0), (1400.0, 1000.0, 460.0), (1500.0, 900.0, 450.0)];
        assert_eq!(medians(&three), [1500.0, 900.0, 450.0]);
        assert_eq!(medians(&[(4.0, 1.0, 1.0), (1.0, 4.0, 4.0), (3.0, 2.0, 2.0), (2.0, 3.0, 3.0)]), [2.0; 3]);
        assert!(median(&[]).is_err());
        let [cold, ..] = median(&runs(&three)).expect("a median");
        assert_eq!(cold.total_ms, 1501.0, "the median run's own steps and totals");
        let table = markdown(vk::Extent2D { width: 16, height: 9 }, "h", &runs(&three[..2])).expect("a table");
        assert!(table.contains("| step | cold ms | argil cold ms | warm ms |\n| --- | --- | --- | --- |"), "{table}");
        assert!(table.contains("| first frame and readback | 1400.0 | 800.0 | 440.0 |"), "the steps: {table}");
        assert!(table.contains("| **process start to first frame** | **1400.0** | **800.0** | **440.0** |"), "{table}");
        assert!(table.contains("cold 1600.0, 1400.0 ms; argil cold 800.0, 1000.0 ms; warm 440.0, 460.0 ms"), "{table}");
        assert!(table.contains("to an EXR on h:"), "the host: {table}");
    }
}
