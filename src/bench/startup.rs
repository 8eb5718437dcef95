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

/// A cold and a warm start of the default scene at `extent` on device `device_index`.
pub fn measure(device_index: usize, extent: vk::Extent2D) -> Result<[Startup; 2]> {
    let dir = Scratch::new("startup")?;
    let exe = std::env::current_exe().context("cannot find the argil executable")?;
    let start = |run: &str| -> Result<Startup> {
        let timings = dir.join(format!("{run}.json"));
        let output = Command::new(&exe)
            .args(["--device", &device_index.to_string(), "render", "--out"])
            .arg(dir.join("frame.exr"))
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

/// The table of a cold and a warm start, a row per step.
pub fn markdown(extent: vk::Extent2D, [cold, warm]: &[Startup; 2]) -> String {
    let mut text = format!(
        "Start of `argil render` of the default scene at {}×{} to an EXR: wall milliseconds per step, \
         cold (empty argil and Mesa caches) and warm (the caches the cold start filled).\n\n\
         | step | cold ms | warm ms |\n| --- | --- | --- |\n",
        extent.width, extent.height
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
    text
}
