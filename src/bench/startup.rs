//! Startup: wall time from process start to the first finished frame, in its parts. A
//! child `argil render --timings` records its steps; the bench runs it twice on the
//! default scene, with empty caches (cold: argil's disk cache and Mesa's shader cache) and
//! again with the caches the first run filled (warm).

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use ash::vk;
use serde::{Deserialize, Serialize};

use crate::atomic::write_bytes;
use crate::scratch::Scratch;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    pub name: String,
    pub ms: f64,
}

/// One start: its steps in order, the work other threads did beside them, and from process
/// start to the first frame (read back) and to that frame written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Startup {
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
    pub fn write(&self, path: &Path) -> Result<()> {
        let startup = Startup {
            steps: self.steps.clone(),
            beside: self.beside.clone(),
            first_frame_ms: self.first_frame.as_secs_f64() * 1e3,
            total_ms: self.process_start.elapsed().as_secs_f64() * 1e3,
        };
        write_bytes(path, serde_json::to_string_pretty(&startup)?.as_bytes())
    }
}

fn step(name: &str, time: Duration) -> Step {
    Step {
        name: name.to_owned(),
        ms: time.as_secs_f64() * 1e3,
    }
}

/// `runs` pairs of a cold and a warm start of the default scene at `extent` on device
/// `device_index`, each pair from empty caches of its own.
pub fn measure(device_index: usize, extent: vk::Extent2D, runs: u32) -> Result<Vec<[Startup; 2]>> {
    (0..runs).map(|_| measure_pair(device_index, extent)).collect()
}

/// A cold and a warm start, the warm one with the caches the cold one filled.
fn measure_pair(device_index: usize, extent: vk::Extent2D) -> Result<[Startup; 2]> {
    let dir = Scratch::new("startup")?;
    let exe = std::env::current_exe().context("cannot find the argil executable")?;
    let start = |run: &str| -> Result<Startup> {
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
            .env("ARGIL_CACHE_DIR", dir.join("argil-cache"))
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
        serde_json::from_slice(&bytes).with_context(|| format!("{}: not a startup record", timings.display()))
    };
    Ok([start("cold")?, start("warm")?])
}

/// Of `runs`, the cold start and the warm start whose times to the first frame are the
/// medians (the lower of the middle two of an even count): whole starts, so that their
/// steps add up as they happened.
pub fn median(runs: &[[Startup; 2]]) -> Result<[Startup; 2]> {
    let median_of = |kind: usize| {
        let mut starts: Vec<&Startup> = runs.iter().map(|pair| &pair[kind]).collect();
        starts.sort_by(|a, b| a.first_frame_ms.total_cmp(&b.first_frame_ms));
        starts.get(starts.len().saturating_sub(1) / 2).map(|s| (*s).clone())
    };
    match (median_of(0), median_of(1)) {
        (Some(cold), Some(warm)) => Ok([cold, warm]),
        _ => bail!("no startup was measured"),
    }
}

/// The table of the median cold and warm starts of `runs` on `host`, a row per step, and
/// every run's time to the first frame.
pub fn markdown(extent: vk::Extent2D, host: &str, runs: &[[Startup; 2]]) -> Result<String> {
    let [cold, warm] = median(runs)?;
    let mut text = format!(
        "Start of `argil render` of the default scene at {}×{} to an EXR on {host}: wall milliseconds per step, \
         cold (empty argil and Mesa caches) and warm (the caches the cold start filled); the median \
         of {} starts of each by the time to the first frame.\n\n\
         | step | cold ms | warm ms |\n| --- | --- | --- |\n",
        extent.width,
        extent.height,
        runs.len()
    );
    for (c, w) in cold.steps.iter().zip(&warm.steps) {
        text += &format!("| {} | {:.1} | {:.1} |\n", c.name, c.ms, w.ms);
    }
    let totals = [
        ("first frame", cold.first_frame_ms, warm.first_frame_ms),
        ("frame written", cold.total_ms, warm.total_ms),
    ];
    for (to, cold, warm) in totals {
        text += &format!("| **process start to {to}** | **{cold:.1}** | **{warm:.1}** |\n");
    }
    for (c, w) in cold.beside.iter().zip(&warm.beside) {
        text += &format!("| *beside the steps, on other threads:* {} | {:.1} | {:.1} |\n", c.name, c.ms, w.ms);
    }
    let first_frames = |kind: usize| {
        let times: Vec<String> = runs.iter().map(|pair| format!("{:.1}", pair[kind].first_frame_ms)).collect();
        times.join(", ")
    };
    text += &format!(
        "\nProcess start to the first frame, each run in order: cold {} ms; warm {} ms.\n",
        first_frames(0),
        first_frames(1)
    );
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
        let runs = |times: &[(f64, f64)]| -> Vec<[Startup; 2]> {
            times.iter().map(|&(cold, warm)| [start(cold), start(warm)]).collect()
        };
        let medians = |times: &[(f64, f64)]| {
            let [cold, warm] = median(&runs(times)).expect("a median");
            (cold.first_frame_ms, warm.first_frame_ms)
        };
        assert_eq!(medians(&[(1500.0, 450.0)]), (1500.0, 450.0));
        assert_eq!(medians(&[(1600.0, 440.0), (1400.0, 460.0), (1500.0, 450.0)]), (1500.0, 450.0));
        assert_eq!(medians(&[(4.0, 1.0), (1.0, 4.0), (3.0, 2.0), (2.0, 3.0)]), (2.0, 2.0));
        assert!(median(&[]).is_err());
        let [cold, _] = median(&runs(&[(1600.0, 440.0), (1400.0, 460.0), (1500.0, 450.0)])).expect("a median");
        assert_eq!(cold.total_ms, 1501.0, "the median run's own steps and totals");
        let table = markdown(vk::Extent2D { width: 16, height: 9 }, "h", &runs(&[(1600.0, 440.0), (1400.0, 460.0)]))
            .expect("a table");
        assert!(table.contains("| **process start to first frame** | **1400.0** | **440.0** |"), "{table}");
        assert!(table.contains("cold 1600.0, 1400.0 ms; warm 440.0, 460.0 ms"), "{table}");
        assert!(table.contains("to an EXR on h:"), "the host: {table}");
    }
}
