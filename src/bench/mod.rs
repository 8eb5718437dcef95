//! `argil bench`: run time against error. For each scene × configuration × resolution, the
//! GPU time per pass of steady frames (after a warm-up that absorbs the driver's first-draw
//! shader compile), the CPU time per frame, the GPU time as a ratio to the trivial-shader
//! floor (drawn in alternation with every row, pooled per scene and size: [`Floor`]), the
//! rows of a scene and size timed in turns, and
//! the frame's error against the scene's `full` and `shadows` references (cached, see
//! [`references`]).
//!
//! - [`plan`]: the scenes and configurations.
//! - [`references`]: the reference cache.
//! - [`report`]: the rows and the CSV, JSON and markdown written from them; [`plot`]: the
//!   plot of time against error.
//! - [`startup`]: the time from process start to the first frame, cold and warm.
//! - [`stats`]: median and p95, the date; [`host`]: the machine, which a software device
//!   runs on.
//! - [`soak`]: `--soak`, a long run that checks memory stays flat.

mod host;
pub mod plan;
pub mod plot;
pub mod references;
pub mod report;
mod sky;
pub mod soak;
pub mod startup;
pub mod stats;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use anyhow::{bail, Context, Result};
use ash::vk;
use glam::Vec3;

use crate::atomic::{write_bytes, Existing};
use crate::compare::metrics::{compare, Metrics, Rgba32};
use crate::error::InputError;
use crate::reference::{Stop, Transport};
use crate::render::msaa::supported_samples;
use crate::render::{GpuScene, OffscreenTarget, Renderer, PASS_NAMES};
use crate::scene::Scene;
use crate::vk::Device;
use plan::{BenchScene, Configuration, Moving};
use references::CachedReference;
use report::{Provenance, Results, Row};
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
    /// Patterns of the rows to run (see [`plan::selected`]); empty for all. The rows run
    /// replace their namesakes among the results already in `out`.
    pub only: Vec<String>,
    /// Pairs of a cold and a warm start measured; the median start of each is reported.
    pub startup_runs: u32,
}

/// Where the bench's references are committed and found (`--references` moves them).
const REFERENCES: &str = "bench/references";

/// The `--only` pattern of the startup measurement.
pub const STARTUP: &str = "startup";

/// Fewest timed frames a row has, whatever `max_seconds` says.
pub const MIN_FRAMES: u32 = 5;
/// Warm-up frames stop after this long, once there has been one.
const WARMUP_SECONDS: f64 = 2.0;

/// How the error is measured: the size of the frame compared and how long each
/// reference samples.
struct ErrorSpec {
    extent: vk::Extent2D,
    full: Stop,
    shadows: Stop,
}

impl ErrorSpec {
    fn new(quick: bool) -> Self {
        if quick {
            Self {
                extent: vk::Extent2D { width: 96, height: 54 },
                full: Stop::Samples(8),
                shadows: Stop::Samples(8),
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
                shadows: Stop::Noise {
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
            PathBuf::from(REFERENCES)
        }
    });
    let provenance = Provenance {
        device: device.info.name.clone(),
        driver: device.info.driver.clone(),
        host: host::describe(),
        date: stats::utc_iso8601(SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs())),
        commit: commit(),
    };
    let spec = ErrorSpec::new(options.quick);
    let sky = if options.quick {
        None
    } else {
        Some(sky::ensure(&reference_dir)?)
    };
    let plan = plan::scenes(options.quick, sky.as_deref())?;
    // A pattern that names nothing is a typo, which would otherwise leave its rows out
    // silently beside the others'.
    let unmatched: Vec<&str> = (options.only.iter())
        .filter(|p| *p != STARTUP && !plan.iter().any(|scene| scene.has(p)))
        .map(String::as_str)
        .collect();
    if !unmatched.is_empty() {
        let scenes: Vec<&str> = plan.iter().map(|s| s.name).collect();
        return Err(InputError(format!(
            "--only {}: names no row of the bench{} (its scenes: {}; or {STARTUP})",
            unmatched.join(" --only "),
            if options.quick { " --quick" } else { "" },
            scenes.join(", ")
        ))
        .into());
    }
    // The folder, and with --only the rows already in it, before any row runs: a run of
    // an hour must not end unable to write or merge what it measured. A whole run replaces
    // the rows there once it ends, so it keeps them only while it runs, if it can read them.
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let earlier = if options.only.is_empty() {
        report::read(&out).unwrap_or_default()
    } else {
        report::read(&out)?
    };
    // Each planned row's place in the results: the plan's order of scenes, configurations
    // and sizes, whichever order the rows were measured or merged in.
    let order = plan
        .iter()
        .flat_map(|s| {
            s.configurations.iter().flat_map(move |c| {
                c.resolutions
                    .iter()
                    .map(move |r| (s.name.to_owned(), c.name.clone(), r.width, r.height))
            })
        })
        .zip(0..)
        .collect();
    let mut results = Results::new(&out, earlier, order, !options.only.is_empty(), options.quick);
    let mut renderer = Renderer::new(device.clone(), 1)?;
    for scene in plan {
        let scene = scene.selected(&options.only);
        if scene.configurations.is_empty() {
            continue;
        }
        let refs = [(Transport::Full, spec.full), (Transport::Shadows, spec.shadows)].map(|(transport, stop)| {
            let settings = references::settings(spec.extent.width, spec.extent.height, transport, stop);
            references::get(&reference_dir, scene.name, &scene.text, &settings)
        });
        let [full, shadows] = refs;
        let (full, shadows) = (full?, shadows?);
        bench_scene(
            &mut renderer,
            &scene,
            options,
            &spec,
            [&full, &shadows],
            &provenance,
            &mut results,
        )?;
    }
    drop(renderer);
    let startup = options.only.is_empty() || options.only.iter().any(|p| p == STARTUP);
    if startup {
        let extent = if options.quick { plan::QUICK } else { plan::HEADLINE };
        let runs = startup::measure(device.info.index, extent, options.startup_runs)?;
        let starts = startup::median(&runs)?;
        for ((run, _), start) in startup::KINDS.iter().zip(&starts) {
            eprintln!(
                "startup ({run}, the median of {}): {:.1} ms from process start to the first frame, {:.1} ms to it \
                 written",
                runs.len(),
                start.first_frame_ms,
                start.total_ms
            );
        }
        let (json, markdown) = (
            serde_json::to_string_pretty(&starts)?,
            startup::markdown(extent, &provenance.host, &runs)?,
        );
        write_bytes(&out.join("startup.json"), Existing::Replace, json.as_bytes())?;
        write_bytes(&out.join("startup.md"), Existing::Replace, markdown.as_bytes())?;
    }
    results.finish()?;
    Ok(out)
}

/// A configuration ready to time: its scene, uploaded, and the error of its frame.
struct Prepared<'a> {
    /// Its place in the scene's plan, which the rows keep.
    index: usize,
    configuration: &'a Configuration,
    scene: Scene,
    gpu: GpuScene,
    full: Metrics,
    shadows: Metrics,
    /// What the configuration moves, as its frames move it.
    drag: Option<Drag>,
}

/// What a moving configuration moves (see [`Moving`]), where the scene as written has it,
/// which way it goes, and how many steps it has gone.
struct Drag {
    what: Moving,
    home: Vec3,
    step: Vec3,
    steps: u32,
}

/// How far [`Drag::step`] moves a light or an object, in metres.
const DRAG_STEP: f32 = 1e-4;

impl Drag {
    /// `what` of `scene`, where it stands, dragged along +x, or along −x for a row of
    /// drafts; `None` where the scene has none. Each way holds positions only its rows
    /// visit, so a draft never finds a map that another row computed where it stands.
    fn of(scene: &mut Scene, what: Moving, draft: bool) -> Option<Self> {
        let home = *position_of(scene, what)?;
        let step = if draft { -DRAG_STEP } else { DRAG_STEP } * Vec3::X;
        Some(Self {
            what,
            home,
            step,
            steps: 0,
        })
    }

    /// Moves it one step further from where the scene has it, as a drag moves it a little
    /// every frame and never back where the maps that follow it were computed: a centimetre
    /// after a hundred frames, which leaves the frames about the scene as written.
    fn step(&mut self, scene: &mut Scene) {
        self.steps += 1;
        if let Some(position) = position_of(scene, self.what) {
            *position = self.home + self.steps as f32 * self.step;
        }
    }

    /// Puts it back where the scene has it.
    fn home(&self, scene: &mut Scene) {
        if let Some(position) = position_of(scene, self.what) {
            *position = self.home;
        }
    }
}

/// Where `what` of `scene` is.
fn position_of(scene: &mut Scene, what: Moving) -> Option<&mut Vec3> {
    let ground = scene.ground_index();
    match what {
        Moving::Light => scene.lights.first_mut().map(|l| &mut l.position),
        Moving::Object => {
            let mut objects = scene.objects.iter_mut().enumerate();
            objects.find(|(i, _)| Some(*i) != ground).map(|(_, o)| &mut o.position)
        }
    }
}

/// Times and measures every configuration of `scene`.
fn bench_scene(
    renderer: &mut Renderer,
    scene: &BenchScene,
    options: &Options,
    spec: &ErrorSpec,
    refs: [&CachedReference; 2],
    provenance: &Provenance,
    results: &mut Results,
) -> Result<()> {
    let mut prepared = Vec::new();
    for (index, configuration) in scene.configurations.iter().enumerate() {
        let mut parsed = Scene::from_toml(&configuration.text, &configuration.name, Path::new(""))?;
        let samples = supported_samples(&renderer.device, parsed.antialiasing.msaa);
        if samples != parsed.antialiasing.msaa {
            eprintln!(
                "{}/{}: skipped: the device does not support {}x MSAA (it would draw {samples}x)",
                scene.name, configuration.name, parsed.antialiasing.msaa
            );
            continue;
        }
        let gpu = renderer.upload(&parsed)?;
        configuration.switch(renderer, configuration.floor, configuration.draft);
        let mut drag = configuration.moving.and_then(|what| Drag::of(&mut parsed, what, configuration.draft));
        if let Some(drag) = &mut drag {
            // The error frame, at the scene as written, as the timed frames are drawn: with
            // the maps that follow what moves computed where it was a frame before.
            drag.step(&mut parsed);
            renderer.draft = false;
            frame(renderer, &parsed, &gpu, spec.extent)?;
            renderer.draft = configuration.draft;
            drag.home(&mut parsed);
        }
        let error_frame = frame(renderer, &parsed, &gpu, spec.extent)?;
        let [full, shadows] = refs.map(|r| compare(&error_frame, &r.image).map(|c| c.metrics));
        prepared.push(Prepared {
            index,
            configuration,
            scene: parsed,
            gpu,
            full: full?,
            shadows: shadows?,
            drag,
        });
    }
    // Each row's times, then its ratios to the floor frames of the rows at its size.
    let mut extents = Vec::new();
    for extent in prepared.iter().flat_map(|p| &p.configuration.resolutions) {
        if !extents.contains(extent) {
            extents.push(*extent);
        }
    }
    for extent in extents {
        let mut at_size: Vec<&mut Prepared> =
            prepared.iter_mut().filter(|p| p.configuration.resolutions.contains(&extent)).collect();
        let timings = time_in_turns(renderer, &mut at_size, extent, options)?;
        let mut measured: Vec<(&mut Prepared, Timing)> = at_size.into_iter().zip(timings).collect();
        for (p, timing) in &measured {
            eprintln!(
                "{} {} {}x{}: GPU {:.2} ms, work {:.2} ms",
                scene.name,
                p.configuration.name,
                extent.width,
                extent.height,
                timing.gpu_total.median,
                timing.work.median
            );
        }
        measured.sort_by_key(|(p, _)| p.index);
        // The scene's own meshes' floor; a run of tessellation rows alone has only theirs.
        let floor = if measured.iter().any(|m| m.0.configuration.own_meshes) {
            Floor::pooled(measured.iter().filter(|m| m.0.configuration.own_meshes).map(|m| &m.1.floor))
        } else {
            Floor::pooled(measured.iter().map(|m| &m.1.floor))
        };
        let rows = measured.iter().map(|(prepared, timing)| {
            let row = Row::new(
                scene.name,
                prepared.configuration,
                extent,
                timing,
                &floor,
                (&prepared.full, refs[0]),
                (&prepared.shadows, refs[1]),
                provenance,
            );
            eprintln!("{}", row.line());
            row
        });
        results.add(rows.collect())?;
    }
    renderer.floor = false;
    renderer.generic = false;
    renderer.deferred = true;
    renderer.draft = false;
    Ok(())
}

/// One frame at `extent`, read back as linear radiance with coverage in alpha.
fn frame(renderer: &mut Renderer, scene: &Scene, gpu: &GpuScene, extent: vk::Extent2D) -> Result<Rgba32> {
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
    /// CPU time the whole process spent on the frame (every thread): on a software device
    /// the rendering itself.
    pub work: Summary,
    /// The floor frames drawn between the row's.
    pub floor: FloorFrames,
}

/// The times of floor frames: forward pass and whole frame (GPU ms), and the process's CPU
/// time (ms).
#[derive(Default)]
pub struct FloorFrames {
    forward: Vec<f64>,
    gpu: Vec<f64>,
    work: Vec<f64>,
}

/// What every ratio divides by: the medians of the floor frames of every row of a scene at
/// one size that draws its own meshes, in one run. The floor, a trivial shader, is bound by memory where the
/// configurations are bound by shading, so the machine's noise moves it alone: on a
/// shared 2-core machine one row's floor frames read 6–16 ms while the configurations'
/// own times stayed within 3%. Pooled over the run, the floor is one yardstick for all
/// the scene's rows.
pub struct Floor {
    pub forward: f64,
    pub gpu: f64,
    pub work: f64,
}

impl Floor {
    pub fn pooled<'a>(rows: impl Iterator<Item = &'a FloorFrames>) -> Self {
        let mut all = FloorFrames::default();
        for f in rows {
            all.forward.extend(&f.forward);
            all.gpu.extend(&f.gpu);
            all.work.extend(&f.work);
        }
        Self {
            forward: Summary::of(&all.forward).median,
            gpu: Summary::of(&all.gpu).median,
            work: Summary::of(&all.work).median,
        }
    }
}

/// What one frame took: GPU milliseconds per pass, wall milliseconds of the CPU, and CPU
/// milliseconds of the process.
struct FrameTimes {
    gpu: Vec<f64>,
    wall: f64,
    work: f64,
}

/// A row's timed frames so far.
struct Recorded {
    passes: Vec<Vec<f64>>,
    totals: Vec<f64>,
    cpu: Vec<f64>,
    work: Vec<f64>,
    floor: FloorFrames,
}

impl Recorded {
    fn new() -> Self {
        Self {
            passes: vec![Vec::new(); PASS_NAMES.len()],
            totals: Vec::new(),
            cpu: Vec::new(),
            work: Vec::new(),
            floor: FloorFrames::default(),
        }
    }

    fn frames(&self) -> u32 {
        self.totals.len() as u32
    }

    fn push(&mut self, base: FrameTimes, frame: FrameTimes) {
        self.floor.forward.push(base.gpu[0]);
        self.floor.gpu.push(base.gpu.iter().sum());
        self.floor.work.push(base.work);
        self.totals.push(frame.gpu.iter().sum());
        self.cpu.push(frame.wall);
        self.work.push(frame.work);
        for (pass, t) in self.passes.iter_mut().zip(frame.gpu) {
            pass.push(t);
        }
    }

    fn timing(self) -> Timing {
        Timing {
            frames: self.frames(),
            passes: self.passes.iter().map(|p| Summary::of(p)).collect(),
            gpu_total: Summary::of(&self.totals),
            cpu: Summary::of(&self.cpu),
            work: Summary::of(&self.work),
            floor: self.floor,
        }
    }
}

/// Turns each row of a size has: a machine's speed drifts over the minutes of a run, and
/// rows timed one after the other would each see a different machine.
const TURNS: u32 = 5;

/// Times `rows` at `extent` in [`TURNS`] rounds, the order reversed every other round,
/// each row timing a share of its frames and seconds in each: so the drift of the machine
/// falls on every row alike, and rows a few percent apart keep their order. A turn draws
/// pairs of frames into the same target without reading them back: a floor frame, then a
/// frame of the configuration (itself the floor for the floor row); the floor frames go
/// to [`Floor::pooled`]. GPU milliseconds per pass from the timestamps, CPU milliseconds
/// of writing the uniforms, recording, submitting and waiting for each frame, and the CPU
/// time of the process meanwhile.
fn time_in_turns(
    renderer: &mut Renderer,
    rows: &mut [&mut Prepared],
    extent: vk::Extent2D,
    options: &Options,
) -> Result<Vec<Timing>> {
    let offscreen = OffscreenTarget::new(&renderer.device, extent)?;
    let draw = |renderer: &mut Renderer, row: &mut Prepared, as_floor: bool| -> Result<FrameTimes> {
        if let Some(drag) = row.drag.as_mut().filter(|_| !as_floor) {
            drag.step(&mut row.scene);
        }
        row.configuration.switch(renderer, as_floor, row.configuration.draft && !as_floor);
        let (wall, work) = (Instant::now(), cpu_time::ProcessTime::now());
        let gpu = renderer
            .draw_offscreen(&row.scene, &row.gpu, &offscreen, 1.0)?
            .context("the device stopped reporting timestamps")?;
        Ok(FrameTimes {
            gpu,
            wall: wall.elapsed().as_secs_f64() * 1e3,
            work: work.elapsed().as_secs_f64() * 1e3,
        })
    };
    let turn_frames = options.frames.div_ceil(TURNS);
    let turn_min_frames = MIN_FRAMES.div_ceil(TURNS);
    let turn_seconds = options.max_seconds / f64::from(TURNS);
    let mut recorded: Vec<Recorded> = rows.iter().map(|_| Recorded::new()).collect();
    for turn in 0..TURNS {
        let mut order: Vec<usize> = (0..rows.len()).collect();
        if turn % 2 == 1 {
            order.reverse();
        }
        for i in order {
            let (row, record) = (&mut *rows[i], &mut recorded[i]);
            if record.frames() >= options.frames {
                continue;
            }
            if turn == 0 {
                // The error frame drawn before has compiled the pipeline already; what is
                // left to warm up (caches, the new target) takes a frame, so slow rows stop
                // after one.
                let warming = Instant::now();
                for i in 0..options.warmup {
                    if i >= 1 && warming.elapsed().as_secs_f64() > WARMUP_SECONDS {
                        break;
                    }
                    draw(renderer, row, true)?;
                    draw(renderer, row, row.configuration.floor)?;
                }
            } else if options.warmup > 0 {
                // What the rows between rebuilt for their own scenes (the environment, the
                // shadow and ground maps) is built again for this one.
                draw(renderer, row, row.configuration.floor)?;
            }
            let start = Instant::now();
            for i in 0..turn_frames {
                if record.frames() >= options.frames
                    || (i >= turn_min_frames && start.elapsed().as_secs_f64() > turn_seconds)
                {
                    break;
                }
                let base = draw(renderer, row, true)?;
                let frame = draw(renderer, row, row.configuration.floor)?;
                record.push(base, frame);
            }
        }
    }
    Ok(recorded.into_iter().map(Recorded::timing).collect())
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The floor is the median of every row's floor frames taken together: a fast row's
    /// three frames and a slow row's two give the third smallest of the five, not a value
    /// between the rows' medians (2 and 10.5).
    #[test]
    fn the_floor_pools_the_rows_frames() {
        let frames = |forward: &[f64]| FloorFrames {
            forward: forward.to_vec(),
            gpu: forward.iter().map(|f| 2.0 * f).collect(),
            work: forward.iter().map(|f| 3.0 * f).collect(),
        };
        let (fast, slow) = (frames(&[1.0, 2.0, 3.0]), frames(&[10.0, 11.0]));
        let floor = Floor::pooled([&fast, &slow].into_iter());
        assert_eq!((floor.forward, floor.gpu, floor.work), (3.0, 6.0, 9.0));
        let alone = Floor::pooled([&slow].into_iter());
        assert_eq!(alone.forward, 10.5);
    }

    /// Each committed reference is the one a run names for its scene and transport, and
    /// no other is there: a change to a bench scene, to what a reference's key holds or to
    /// how it is written would otherwise have the next run render them all again (about
    /// an hour on 2 cores), against which the rows' errors would move.
    #[test]
    fn every_committed_reference_is_the_one_a_run_names() {
        let dir = Path::new(REFERENCES);
        // The sky is made where it is missing, not committed; its key is its texels'.
        let scratch = crate::scratch::Scratch::new("committed-references").unwrap();
        let sky = sky::ensure(&scratch).unwrap();
        let spec = ErrorSpec::new(false);
        let mut named = Vec::new();
        for scene in plan::scenes(false, Some(&sky)).unwrap() {
            for (transport, stop) in [(Transport::Full, spec.full), (Transport::Shadows, spec.shadows)] {
                let settings = references::settings(spec.extent.width, spec.extent.height, transport, stop);
                let path = references::path(dir, scene.name, &scene.text, &settings).unwrap();
                assert!(path.is_file(), "{}: a run would render this reference again", path.display());
                named.push(path);
            }
        }
        let mut committed: Vec<PathBuf> = (std::fs::read_dir(dir).unwrap())
            .map(|entry| entry.unwrap().path())
            .filter(|path| path.file_name() != Some(sky::FILE_NAME.as_ref()))
            .collect();
        committed.sort();
        named.sort();
        assert_eq!(committed, named, "references no run names");
    }
}
