//! `argil bench`: run time against error. For each scene × configuration × resolution, the
//! GPU time per pass of steady frames (after a warm-up that absorbs the driver's first-draw
//! shader compile), the CPU time per frame, the GPU time as a ratio to the trivial-shader
//! floor drawn in alternation with it, and the frame's error against the scene's `full` and
//! `direct` references (cached, see [`references`]).
//!
//! - [`plan`]: the scenes and configurations.
//! - [`references`]: the reference cache.
//! - [`report`]: the rows and the CSV, JSON and markdown written from them; [`plot`]: the
//!   plot of time against error.
//! - [`stats`]: median and p95, the stable hash, the date.
//! - [`soak`]: `--soak`, a long run that checks memory stays flat.

pub mod plan;
pub mod plot;
pub mod references;
pub mod report;
pub mod soak;
pub mod stats;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use anyhow::{bail, Context, Result};
use ash::vk;

use crate::compare::metrics::{compare, Rgba32};
use crate::reference::{Stop, Transport};
use crate::render::{OffscreenTarget, Renderer, PASS_NAMES};
use crate::scene::Scene;
use crate::vk::Device;
use plan::BenchScene;
use references::CachedReference;
use report::{Provenance, Row};
use stats::Summary;

pub struct Options {
    /// The small subset: one scene, three configurations, a small frame, tiny references.
    pub quick: bool,
    /// Timed frames per row (after the warm-up).
    pub frames: u32,
    pub warmup: u32,
    /// A row stops timing after this many seconds, once it has [`MIN_FRAMES`].
    pub max_seconds: f64,
    /// Where the results go; by default `bench/results/DEVICE` (`--quick`: the system's
    /// temporary folder).
    pub out: Option<PathBuf>,
    /// Where the references are cached; by default `bench/references` (`--quick`: the
    /// system's temporary folder, as its references are too small to keep).
    pub references: Option<PathBuf>,
}

/// Fewest timed frames a row has, whatever `max_seconds` says.
pub const MIN_FRAMES: u32 = 5;
/// Warm-up frames stop after this long, once there has been one.
const WARMUP_SECONDS: f64 = 2.0;

/// How the error is measured: the size of the frame compared and how long each
/// reference samples.
struct ErrorSpec {
    extent: vk::Extent2D,
    full: Stop,
    direct: Stop,
}

impl ErrorSpec {
    fn new(quick: bool) -> Self {
        if quick {
            Self {
                extent: vk::Extent2D { width: 96, height: 54 },
                full: Stop::Samples(8),
                direct: Stop::Samples(8),
            }
        } else {
            // 320×180 keeps each full-transport reference under a minute on 2 cores.
            Self {
                extent: vk::Extent2D {
                    width: 320,
                    height: 180,
                },
                full: Stop::Noise {
                    target: 0.02,
                    max_samples: 4096,
                },
                direct: Stop::Noise {
                    target: 0.01,
                    max_samples: 4096,
                },
            }
        }
    }
}

/// Runs the bench on `device` and writes its results; returns the folder they are in.
pub fn run(device: &Arc<Device>, options: &Options) -> Result<PathBuf> {
    if device.timestamp_period_ns.is_none() {
        bail!(
            "{} has no GPU timestamps: the bench cannot time passes",
            device.info.name
        );
    }
    let temporary = std::env::temp_dir();
    let out = options.out.clone().unwrap_or_else(|| {
        let root = if options.quick {
            temporary.join("argil-bench-quick")
        } else {
            PathBuf::from("bench/results")
        };
        root.join(file_safe(&device.info.name))
    });
    let reference_dir = options.references.clone().unwrap_or_else(|| {
        if options.quick {
            temporary.join("argil-bench-references")
        } else {
            PathBuf::from("bench/references")
        }
    });
    let provenance = Provenance {
        device: device.info.name.clone(),
        driver: device.info.driver.clone(),
        date: stats::utc_iso8601(SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs())),
        commit: commit(),
    };
    let spec = ErrorSpec::new(options.quick);
    let mut renderer = Renderer::new(device.clone(), 1)?;
    let mut rows = Vec::new();
    for scene in plan::scenes(options.quick)? {
        let refs = [(Transport::Full, spec.full), (Transport::Direct, spec.direct)].map(|(transport, stop)| {
            let settings = references::settings(spec.extent.width, spec.extent.height, transport, stop);
            references::get(&reference_dir, scene.name, &scene.text, &settings)
        });
        let [full, direct] = refs;
        let (full, direct) = (full?, direct?);
        bench_scene(
            &mut renderer,
            &scene,
            options,
            &spec,
            [&full, &direct],
            &provenance,
            &mut rows,
        )?;
    }
    drop(renderer);
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    report::write(&out, &rows)?;
    Ok(out)
}

/// Times and measures every configuration of `scene`.
fn bench_scene(
    renderer: &mut Renderer,
    scene: &BenchScene,
    options: &Options,
    spec: &ErrorSpec,
    refs: [&CachedReference; 2],
    provenance: &Provenance,
    rows: &mut Vec<Row>,
) -> Result<()> {
    for configuration in &scene.configurations {
        let parsed = Scene::from_toml(&configuration.text, &configuration.name, Path::new(""))?;
        let gpu = renderer.upload(&parsed)?;
        renderer.floor = configuration.floor;
        let error_frame = frame(renderer, &parsed, &gpu, spec.extent)?;
        let [full, direct] = refs.map(|r| compare(&error_frame, &r.image).map(|c| c.metrics));
        let (full, direct) = (full?, direct?);
        for &extent in &configuration.resolutions {
            let timing = time(renderer, &parsed, &gpu, extent, configuration.floor, options)?;
            let row = Row::new(
                scene.name,
                configuration,
                extent,
                &timing,
                (&full, refs[0]),
                (&direct, refs[1]),
                provenance,
            );
            eprintln!("{}", row.line());
            rows.push(row);
        }
    }
    renderer.floor = false;
    Ok(())
}

/// One frame at `extent`, read back as linear radiance with coverage in alpha.
fn frame(
    renderer: &mut Renderer,
    scene: &Scene,
    gpu: &crate::render::GpuScene,
    extent: vk::Extent2D,
) -> Result<Rgba32> {
    let frame = renderer.render_offscreen(scene, gpu, extent, 1.0)?;
    Ok(Rgba32 {
        width: frame.width as usize,
        height: frame.height as usize,
        pixels: bytemuck::pod_collect_to_vec::<f32, [f32; 4]>(&frame.hdr),
    })
}

/// The times of one row.
pub struct Timing {
    pub frames: u32,
    /// Per pass of [`PASS_NAMES`].
    pub passes: Vec<Summary>,
    pub gpu_total: Summary,
    pub cpu: Summary,
    /// The forward pass of the floor frames.
    pub floor_forward: Summary,
    /// Per pair of frames, the configuration's forward pass over the floor's, and its
    /// whole frame over the floor's.
    pub forward_ratio: Summary,
    pub gpu_ratio: Summary,
}

/// Renders warm-up frames, then pairs of timed frames into the same target without
/// reading them back: a floor frame, then a frame of the configuration (itself the floor
/// when `floor`). GPU milliseconds per pass from the timestamps, CPU milliseconds of
/// writing the uniforms, recording, submitting and waiting for each frame. Pairing makes
/// the ratios hold when other work on the machine comes and goes during a run.
fn time(
    renderer: &mut Renderer,
    scene: &Scene,
    gpu: &crate::render::GpuScene,
    extent: vk::Extent2D,
    floor: bool,
    options: &Options,
) -> Result<Timing> {
    let offscreen = OffscreenTarget::new(&renderer.device, extent)?;
    let draw = |renderer: &mut Renderer, as_floor: bool| -> Result<(Vec<f64>, f64)> {
        renderer.floor = as_floor;
        let begin = Instant::now();
        let ms = renderer
            .draw_offscreen(scene, gpu, &offscreen, 1.0)?
            .context("the device stopped reporting timestamps")?;
        Ok((ms, begin.elapsed().as_secs_f64() * 1e3))
    };
    // The error frame drawn before has compiled the pipeline already; what is left to warm
    // up (caches, the new target) takes a frame, so slow rows stop after one.
    let warming = Instant::now();
    for i in 0..options.warmup {
        if i >= 1 && warming.elapsed().as_secs_f64() > WARMUP_SECONDS {
            break;
        }
        draw(renderer, true)?;
        draw(renderer, floor)?;
    }
    let mut passes = vec![Vec::new(); PASS_NAMES.len()];
    let (mut totals, mut cpu, mut floor_forward, mut forward_ratio, mut gpu_ratio) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let start = Instant::now();
    for i in 0..options.frames {
        if i >= MIN_FRAMES && start.elapsed().as_secs_f64() > options.max_seconds {
            break;
        }
        let (floor_ms, _) = draw(renderer, true)?;
        let (ms, cpu_ms) = draw(renderer, floor)?;
        let total: f64 = ms.iter().sum();
        cpu.push(cpu_ms);
        forward_ratio.push(ms[0] / floor_ms[0]);
        gpu_ratio.push(total / floor_ms.iter().sum::<f64>());
        floor_forward.push(floor_ms[0]);
        totals.push(total);
        for (pass, t) in passes.iter_mut().zip(ms) {
            pass.push(t);
        }
    }
    Ok(Timing {
        frames: cpu.len() as u32,
        passes: passes.iter().map(|p| Summary::of(p)).collect(),
        gpu_total: Summary::of(&totals),
        cpu: Summary::of(&cpu),
        floor_forward: Summary::of(&floor_forward),
        forward_ratio: Summary::of(&forward_ratio),
        gpu_ratio: Summary::of(&gpu_ratio),
    })
}

/// `name` with every character but ASCII letters, digits, `-` and `.` as `_`.
fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The short hash of the checked-out commit, or "unknown" outside a git work tree.
fn commit() -> String {
    std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_owned())
}
