//! `argil bench --soak FRAMES RENDERS`: a long run in one process, looking for leaks.
//! FRAMES frames of the default scene go through the per-frame path (uniforms, recording,
//! submitting, waiting) into one kept target, as the viewer draws them; then RENDERS
//! renders each reload the scene from its file (alternating two versions of it), upload
//! it, draw it and read it back, as `argil render` does, and drop it. Host memory (RSS) and
//! gpu-allocator's allocated bytes are sampled at intervals and must be flat once the
//! first tenth of each phase has warmed the driver's caches up; at the end no GPU
//! allocation may be left and the validation layer must have reported nothing.
//!
//! `argil bench --soak-viewer FRAMES` does the same for the viewer itself, in a window:
//! a child `argil view` runs the scripted session of [`ViewerSoak`] (an orbiting camera,
//! a material edit that switches pipelines, the panel drawn every frame, swapchain
//! presents) and logs its memory, which must be flat once the first tenth and the first
//! two edits (the first's new pipeline grows the driver's memory once) are past; the
//! validation layer's report of objects still alive when the device is destroyed is part
//! of what it must not print.

use std::path::PathBuf;
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use ash::vk;
use serde::{Deserialize, Serialize};

use crate::atomic::Existing;
use crate::scratch::Scratch;
use crate::render::{OffscreenTarget, Renderer};
use crate::scene::{Scene, DEFAULT_SCENE_TOML};
use crate::vk::Device;

/// Host memory a phase may gain after its warm-up: a leak of 1 KiB a frame over 9,000
/// frames exceeds it, while malloc's arenas and the driver's pools move RSS by a few MiB.
pub const MAX_RSS_GROWTH: u64 = 8 << 20;
/// Samples per phase.
pub const SAMPLES: u64 = 10;
const FRAME: vk::Extent2D = vk::Extent2D {
    width: 320,
    height: 180,
};
const RENDER: vk::Extent2D = vk::Extent2D { width: 160, height: 90 };
/// The viewer's window: the panel (320 px) and a 160×270 view, small enough for 10,000
/// frames on a software driver in minutes; leaks follow the code paths, not the pixels.
const WINDOW: vk::Extent2D = vk::Extent2D {
    width: 480,
    height: 270,
};

/// Memory at one point of the run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Sample {
    step: u64,
    seconds: f64,
    rss: Option<u64>,
    gpu_allocated: u64,
    gpu_blocks: u64,
}

/// Resident host memory, from /proc (Linux); `None` elsewhere.
fn rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

pub fn sample(device: &Device, step: u64, start: &Instant) -> Sample {
    let report = device.allocator().generate_report();
    Sample {
        step,
        seconds: start.elapsed().as_secs_f64(),
        rss: rss_bytes(),
        gpu_allocated: report.total_allocated_bytes,
        gpu_blocks: report.total_capacity_bytes,
    }
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1 << 20)
}

/// Prints `phase`'s samples and returns what is not flat about them: host memory grown by
/// more than [`MAX_RSS_GROWTH`], or any change of the GPU's allocated bytes, from the first
/// sample at step `warmed_up` or later (the first sample is taken after the warm-up tenth)
/// to the last.
fn judge(phase: &str, samples: &[Sample], warmed_up: u64) -> Vec<String> {
    for s in samples {
        println!(
            "{phase} {:>6}  {:>8.1} s  rss {:>8}  gpu allocated {:>8.2} MiB in blocks of {:>8.2} MiB",
            s.step,
            s.seconds,
            s.rss.map_or_else(|| "n/a".to_owned(), |r| format!("{:.1} MiB", mib(r))),
            mib(s.gpu_allocated),
            mib(s.gpu_blocks)
        );
    }
    let mut problems = Vec::new();
    let judged = samples.iter().position(|s| s.step >= warmed_up).map_or(&[][..], |at| &samples[at..]);
    let (Some(first), Some(last)) = (judged.first(), judged.last()) else {
        println!("{phase}: no sample after step {warmed_up}, where its warm-up ends: nothing judged");
        return problems;
    };
    if let (Some(a), Some(b)) = (first.rss, last.rss) {
        let growth = b.saturating_sub(a);
        println!(
            "{phase}: rss {:+.2} MiB from step {} to {}",
            mib(growth),
            first.step,
            last.step
        );
        if growth > MAX_RSS_GROWTH {
            problems.push(format!(
                "{phase}: host memory grew by {:.1} MiB (at most {:.0} MiB)",
                mib(growth),
                mib(MAX_RSS_GROWTH)
            ));
        }
    }
    // Between frames nothing of a frame is allocated, so the bytes are the same exactly.
    if let Some(s) = judged.iter().find(|s| s.gpu_allocated != first.gpu_allocated) {
        problems.push(format!(
            "{phase}: GPU memory allocated went from {} bytes at step {} to {} at step {}",
            first.gpu_allocated, first.step, s.gpu_allocated, s.step
        ));
    }
    problems
}

/// The default scene's text with its first object's material changed, so a reload is
/// a different scene.
fn variant(toml: &str, index: u64) -> String {
    let colour = if index % 2 == 0 {
        "[0.12, 0.24, 0.55]"
    } else {
        "[0.55, 0.24, 0.12]"
    };
    toml.replace("base_color = [0.12, 0.24, 0.55]", &format!("base_color = {colour}"))
}

/// Runs the soak on `device`; fails if memory is not flat, a GPU allocation is left or the
/// validation layer reported an error.
pub fn run(device: &Arc<Device>, frames: u64, renders: u64) -> Result<()> {
    let start = Instant::now();
    let mut problems = Vec::new();
    let baseline = device.allocator().generate_report().allocations.len();
    {
        let mut renderer = Renderer::new(device.clone(), 1)?;
        let scene = Scene::default_scene();
        let gpu = renderer.upload(&scene)?;
        let offscreen = OffscreenTarget::new(device, FRAME)?;
        let every = (frames / SAMPLES).max(1);
        let mut samples = Vec::new();
        for frame in 1..=frames {
            renderer.draw_offscreen(&scene, &gpu, &offscreen, 1.0)?;
            if frame % every == 0 {
                samples.push(sample(device, frame, &start));
            }
        }
        problems.extend(judge("frames", &samples, 0));

        let scratch = Scratch::new("soak")?;
        let path = scratch.join("soak-scene.toml");
        let every = (renders / SAMPLES).max(1);
        let mut samples = Vec::new();
        for render in 1..=renders {
            crate::atomic::write_bytes(&path, Existing::Replace, variant(DEFAULT_SCENE_TOML, render).as_bytes())?;
            let reloaded = Scene::load(&path)?;
            let gpu = renderer.upload(&reloaded)?;
            renderer.render_offscreen(&reloaded, &gpu, RENDER, 1.0)?;
            drop(gpu);
            if render % every == 0 {
                samples.push(sample(device, render, &start));
            }
        }
        problems.extend(judge("renders", &samples, 0));
    }
    device.wait_idle()?;
    let left = device.allocator().generate_report().allocations.len();
    println!(
        "soak: {frames} frames and {renders} renders in {:.0} s; GPU allocations left: {}",
        start.elapsed().as_secs_f64(),
        left - baseline.min(left)
    );
    if left > baseline {
        problems.push(format!("{} GPU allocation(s) were not freed", left - baseline));
    }
    if let Some(report) = device.validation() {
        println!(
            "soak: validation layer: {} error(s), {} warning(s)",
            report.error_count(),
            report.warning_count()
        );
        if report.error_count() + report.warning_count() > 0 {
            problems.push("the validation layer reported messages".to_owned());
        }
    }
    if !problems.is_empty() {
        bail!("the soak found leaks: {}", problems.join("; "));
    }
    Ok(())
}

/// Runs the viewer's soak in a child `argil view` on this display; fails if its memory is
/// not flat, it failed, or the validation layer printed anything (leaked objects are
/// reported when its device is destroyed). `device` is the child's `--device`, if given.
pub fn run_viewer(frames: u64, device: Option<&str>) -> Result<()> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(crate::error::InputError(
            "--soak-viewer needs a display; without one run it under Xvfb: xvfb-run -a argil bench --soak-viewer N"
                .to_owned(),
        )
        .into());
    }
    let scratch = Scratch::new("soak-viewer")?;
    let log: PathBuf = scratch.join("viewer-soak.json");
    let exe = std::env::current_exe().context("cannot find the argil executable")?;
    let mut child = Command::new(exe);
    child.arg("--validation");
    if let Some(d) = device {
        child.args(["--device", d]);
    }
    let (w, h) = (WINDOW.width.to_string(), WINDOW.height.to_string());
    child
        .args([
            "view",
            "--frames",
            &frames.to_string(),
            "--width",
            &w,
            "--height",
            &h,
            "--soak-log",
        ])
        .arg(&log);
    let start = Instant::now();
    let output = child.output().context("cannot start the viewer")?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    let mut problems = Vec::new();
    if !output.status.success() {
        problems.push(format!("the viewer failed ({}): {}", output.status, stderr.trim()));
    }
    let text = std::fs::read_to_string(&log).with_context(|| format!("the viewer wrote no {}", log.display()))?;
    let samples: Vec<Sample> = serde_json::from_str(&text).with_context(|| format!("cannot read {}", log.display()))?;
    problems.extend(judge("viewer", &samples, crate::viewer::soak_warmed_up(frames)));
    let messages = stderr
        .lines()
        .filter(|l| l.starts_with(crate::vk::instance::VALIDATION_PREFIX))
        .count();
    println!(
        "soak: {frames} viewer frames in {:.0} s; validation messages: {messages}",
        start.elapsed().as_secs_f64()
    );
    if messages > 0 {
        problems.push(format!("the validation layer printed {messages} message(s)"));
    }
    if !problems.is_empty() {
        bail!("the viewer soak found problems: {}", problems.join("; "));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_differ_from_each_other_and_parse() {
        assert_ne!(variant(DEFAULT_SCENE_TOML, 0), variant(DEFAULT_SCENE_TOML, 1));
        for i in 0..2 {
            Scene::from_toml(&variant(DEFAULT_SCENE_TOML, i), "soak", std::path::Path::new("")).unwrap();
        }
    }

    #[test]
    fn a_growing_allocation_is_reported() {
        let at = |step, rss, gpu| Sample {
            step,
            seconds: 0.0,
            rss: Some(rss),
            gpu_allocated: gpu,
            gpu_blocks: 0,
        };
        assert!(judge("t", &[at(1, 100 << 20, 5), at(2, 101 << 20, 5)], 0).is_empty());
        assert_eq!(judge("t", &[at(1, 100 << 20, 5), at(2, 120 << 20, 5)], 0).len(), 1);
        assert_eq!(judge("t", &[at(1, 100 << 20, 5), at(2, 100 << 20, 6)], 0).len(), 1);
        // Growth before the warm-up's end is not judged; after it, it is.
        let stepped = [at(1, 100 << 20, 5), at(2, 120 << 20, 5), at(3, 121 << 20, 5)];
        assert_eq!(judge("t", &stepped, 0).len(), 1);
        assert!(judge("t", &stepped, 2).is_empty());
        assert_eq!(judge("t", &[at(1, 100 << 20, 5), at(2, 120 << 20, 5), at(3, 140 << 20, 5)], 2).len(), 1);
    }
}
