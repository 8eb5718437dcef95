//! The `argil` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use ash::vk;
use clap::{Parser, Subcommand};

use argil::atomic::Existing;
use argil::bench::startup::Recorder;
use argil::brdf::subsurface::PreintegratedTable;
use argil::error::{advice, is_input_error, is_interrupted, InputError, Interrupted, INTERRUPTED_EXIT_CODE};
use argil::reference::{Ending, Filter, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use argil::render::output::{write_linear, OutputKind};
use argil::render::warm_up::{warm_up, WARM_UP_EXTENT};
use argil::render::{count_non_finite, write_frame, DebugView, Frames, Renderer, PASS_NAMES};
use argil::scene::{PendingMaps, Scene};
use argil::vk::{device, Device, DeviceChoice, DeviceOptions};

/// The largest `--width` and `--height`: the render target's.
const MAX_SIDE: i64 = argil::render::target::MAX_SIDE as i64;

/// The exit-code contract, also in the README.
const AFTER_HELP: &str = "\
Exit codes: 0 success; 2 the input is wrong (a scene, mesh, texture, environment map or EXR, \
an argument, --device, ARGIL_FAULT, an output that exists without --overwrite or whose folder \
is missing or unwritable), and nothing was written; 1 argil or the machine failed (no Vulkan \
driver, the device lost, out of memory, an I/O error while writing); 130 interrupted by Ctrl-C, \
SIGTERM or SIGHUP (reference writes the samples taken, render --accumulate the mean of the frames \
drawn if any, view the scene's changes not saved). Outputs are written to a temporary file and renamed, \
so a failed run with --overwrite leaves the previous file as it was.

Environment: ARGIL_VALIDATION=1 turns the validation layer on; ARGIL_FAULT=KIND:N[,...] makes \
the N-th GPU allocation (alloc), queue submission (submit, device-lost), present (present: \
the swapchain out of date) or the output after N bytes (write) fail, or the N-th submission \
panic (panic), to test the above.";

#[derive(Parser)]
#[command(
    name = "argil",
    version,
    about = "A real-time renderer of physically based clay on explicit Vulkan",
    after_help = AFTER_HELP
)]
struct Cli {
    /// Vulkan device: an index or part of a name from `argil devices`.
    /// Default: discrete GPU, then integrated, then CPU (lavapipe).
    #[arg(long, global = true, value_name = "N|NAME")]
    device: Option<DeviceChoice>,
    /// Enable the Khronos validation layer (also: ARGIL_VALIDATION=1; always on in debug builds).
    /// Any validation error makes the command fail.
    #[arg(long, global = true)]
    validation: bool,
    /// Replace output files that already exist (`--out`, `--json`, `--timings`,
    /// `--screenshot`). Without it such a file is refused before the command starts: exit
    /// code 2, nothing written; one created meanwhile is not replaced either (exit code 2,
    /// the output left in the temporary file named). `bench` updates its own results folder
    /// either way.
    #[arg(long, global = true)]
    overwrite: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render one frame offscreen to a PNG (tone-mapped sRGB) or an EXR (linear radiance).
    Render {
        /// Scene file (TOML), or a glTF model (.glb, .gltf) to open alone in the studio; without
        /// one, the embedded default clay scene.
        scene: Option<PathBuf>,
        /// Output file: .png (tone-mapped, 8-bit sRGB) or .exr (linear radiance, RGBA32F,
        /// no tone mapping, no exposure).
        #[arg(long, short)]
        out: PathBuf,
        #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        width: u32,
        #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        height: u32,
        /// Exposure multiplier applied before tone mapping (PNG only).
        #[arg(long, default_value_t = 1.0)]
        exposure: f32,
        /// Also write the start's steps (wall milliseconds, and from process start to the
        /// first frame and to the frame written) to this JSON file.
        #[arg(long, value_name = "FILE")]
        timings: Option<PathBuf>,
        /// Samples per pixel of the forward pass (1, 2, 4 or 8; 1 is no MSAA), instead of
        /// the scene's [antialiasing] msaa (default 1). A count the device does not support
        /// draws with the largest it does below it, with a warning.
        #[arg(long, value_name = "N", value_parser = parse_msaa)]
        msaa: Option<u32>,
        /// Render this many frames and write their running mean, each frame with the next
        /// sample set of the `sampled` reflection (as the viewer refines a still view); other
        /// reflection modes give the single frame's image. Ctrl-C ends it after the frame being
        /// drawn and writes the mean of those drawn (exit code 130; during the start, before
        /// the first frame, nothing); the EXR's `argil.frames` gives the count.
        #[arg(long, value_name = "FRAMES", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=65536))]
        accumulate: u32,
        /// Render this debug view instead of the shaded image (the names of `argil view
        /// --debug-view`); `shadow-map` needs a light that casts shadows.
        #[arg(long, value_name = "VIEW", default_value = "shaded", value_parser = DebugView::from_name)]
        debug_view: DebugView,
    },
    /// Open a window on a scene.
    #[command(group(clap::ArgGroup::new("limit").args(["frames", "seconds"])))]
    View {
        /// Scene file (TOML), or a glTF model (.glb, .gltf) to open alone in the studio; without
        /// one, the embedded default clay scene.
        scene: Option<PathBuf>,
        /// Close after this many frames.
        #[arg(long)]
        frames: Option<u64>,
        /// Exposure multiplier applied before tone mapping.
        #[arg(long, default_value_t = 1.0)]
        exposure: f32,
        /// Initial window width in pixels.
        #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        width: u32,
        /// Initial window height in pixels.
        #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        height: u32,
        /// After the last frame, write what the window shows (UI included) to this PNG; with
        /// `--seconds`, one frame more is drawn for it when they have passed.
        #[arg(long, value_name = "FILE.png", requires = "limit")]
        screenshot: Option<PathBuf>,
        /// Resize, minimise and restore the window while rendering (for tests).
        #[arg(long, hide = true)]
        resize_storm: bool,
        /// Close this many seconds after the first frame, drawing frames only when something
        /// changes.
        #[arg(long, value_parser = parse_seconds)]
        seconds: Option<f64>,
        /// The scripted leak hunt of `argil bench --soak-viewer`: orbit, edit a material,
        /// and write memory samples (JSON) to this file.
        #[arg(long, hide = true, value_name = "FILE", requires = "frames")]
        soak_log: Option<PathBuf>,
        /// Start in this debug view (the panel's Debug view): shaded, normals, tangents,
        /// bitangents, uvs, n-dot-l, diffuse, specular, subsurface, environment, nan, curvature,
        /// occlusion, shadows, bounce, shadow-map.
        #[arg(long, value_name = "VIEW", default_value = "shaded", value_parser = DebugView::from_name)]
        debug_view: DebugView,
        /// Start with the split view on, its right half in this configuration of
        /// `argil bench` (seed, report, no-subsurface, maps-off, …).
        #[arg(long, value_name = "CONFIGURATION", value_parser = argil::viewer::parse_split_configuration)]
        split: Option<String>,
    },
    /// Render the ground truth of a scene on the CPU: Monte Carlo integration in f64 of the
    /// same scene, camera, meshes, materials, maps, lights and environment, on every core.
    /// Writes an EXR (linear radiance, alpha = coverage, the settings and the noise in its
    /// header) or a PNG (the display transform of `render`).
    Reference {
        /// Scene file (TOML), or a glTF model (.glb, .gltf) to open alone in the studio; without
        /// one, the embedded default clay scene.
        scene: Option<PathBuf>,
        /// Output file: .exr (linear radiance, RGBA32F) or .png (tone-mapped, 8-bit sRGB).
        #[arg(long, short)]
        out: PathBuf,
        #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        width: u32,
        #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE))]
        height: u32,
        /// Samples per pixel [default: 64, unless --noise is given].
        #[arg(long, conflicts_with = "noise", value_parser = clap::value_parser!(u32).range(1..))]
        spp: Option<u32>,
        /// Sample until the estimated relative RMS noise of the image (from two independent
        /// half images) is below this, e.g. 0.01 for 1%, or until --max-spp.
        #[arg(long, value_name = "X")]
        noise: Option<f64>,
        /// Most samples per pixel with --noise.
        #[arg(long, default_value_t = 65536, requires = "noise", value_parser = clap::value_parser!(u32).range(1..))]
        max_spp: u32,
        /// Stop before the pass of samples that would end after this many seconds, with
        /// every pixel sampled alike; whichever of this and --spp or --noise comes first.
        #[arg(long, value_parser = parse_seconds, value_name = "S")]
        max_seconds: Option<f64>,
        /// Light transport: direct (the real-time renderer's: each light, no visibility),
        /// shadows (direct light with visibility) or full (path tracing).
        #[arg(long, default_value_t = Transport::Full)]
        transport: Transport,
        /// Pixel filter: box (the pixel's area) or center (its centre, as the rasteriser
        /// samples without anti-aliasing).
        #[arg(long, default_value_t = Filter::Box)]
        filter: Filter,
        /// How the environment is sampled: mis (by its luminance and by the material's
        /// lobes, power heuristic), material (lobes only) or light (luminance only).
        #[arg(long, default_value_t = Sampling::Mis)]
        sampling: Sampling,
        /// Subsurface: model (each material's own model, as part of its BRDF, as the shader
        /// evaluates it) or volume (each material with a subsurface model and a
        /// scatter_radius is a scattering medium inside its mesh; needs --transport full).
        #[arg(long, default_value_t = SubsurfaceTransport::Model)]
        subsurface: SubsurfaceTransport,
        /// Seed of the samples: the same seed gives the same image on any number of threads.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Longest path, in surfaces, for --transport full.
        #[arg(long, default_value_t = Settings::DEFAULT_MAX_DEPTH, value_parser = clap::value_parser!(u32).range(1..))]
        max_depth: u32,
        /// Worker threads [default: one per core].
        #[arg(long)]
        threads: Option<usize>,
        /// Exposure multiplier applied before tone mapping (PNG only).
        #[arg(long, default_value_t = 1.0)]
        exposure: f32,
    },
    /// Time scenes × configurations × resolutions in steady frames (GPU per pass, CPU per
    /// frame, as a ratio to a trivial-shader floor) and measure each configuration's error
    /// against cached references. Writes results.csv, results.json and results.md.
    Bench {
        /// A small subset (one scene, three configurations, 160×90, tiny references) for tests.
        #[arg(long)]
        quick: bool,
        /// Timed frames per row [default: 100, --quick 10].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        frames: Option<u32>,
        /// Untimed frames first, for the driver's first-draw shader compile; stops after 2 s once
        /// there has been one [default: 5, --quick 2].
        #[arg(long)]
        warmup: Option<u32>,
        /// Stop timing a row after this many seconds, once it has 5 frames.
        #[arg(long, default_value_t = 60.0)]
        max_seconds: f64,
        /// Results folder [default: bench/results/DEVICE; --quick: in the temporary folder].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Reference cache [default: bench/references; --quick: in the temporary folder].
        #[arg(long, value_name = "DIR")]
        references: Option<PathBuf>,
        /// Only these rows: a scene or configuration name, or SCENE/CONFIGURATION (`*` matches
        /// any run of characters); repeatable. Their rows replace the same rows of the results already in the
        /// folder, and the other rows are kept, but for those of configurations the bench no longer has.
        /// A pattern that names neither a row nor `startup` is refused before any row runs (exit
        /// code 2).
        #[arg(long, value_name = "PATTERN")]
        only: Vec<String>,
        /// Runs of the three starts measured (cold, argil cold, warm), each run from empty
        /// caches; the median start of each kind is reported [default: 5, --quick 1].
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
        startup_runs: Option<u32>,
        /// Instead of timing, a long run looking for leaks: FRAMES frames, then RENDERS renders
        /// with scene reloads; host and GPU memory must stay flat (e.g. --soak 10000 1000).
        #[arg(long, num_args = 2, value_names = ["FRAMES", "RENDERS"])]
        soak: Option<Vec<u64>>,
        /// Instead of timing, the viewer's long run: FRAMES frames in a window (a display is
        /// needed: `xvfb-run -a argil bench --soak-viewer 10000`) with the camera orbiting and
        /// a material edit every 100 frames; memory must stay flat, and the validation layer
        /// (on in the child) silent, leaked objects included.
        #[arg(long, value_name = "FRAMES", conflicts_with = "soak", value_parser = clap::value_parser!(u64).range(1..))]
        soak_viewer: Option<u64>,
    },
    /// List the Vulkan devices on this machine.
    Devices,
    /// Check every BRDF model and term: GPU against f64, positivity, reciprocity, energy,
    /// stress inputs. Prints one table; fails if any check fails.
    Verify {
        /// Also write the table as JSON to this file.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Random input tuples per function (at least 10⁶ for the accuracy check).
        #[arg(long, default_value_t = argil::verify::DEFAULT_SAMPLES)]
        samples: usize,
        /// Seed of the random input tuples.
        #[arg(long, default_value_t = argil::verify::DEFAULT_SEED)]
        seed: u64,
    },
    /// Compare a linear-radiance EXR with a reference: relative MSE, PSNR, relative error,
    /// ꟻLIP over the pixels the reference covers. Exit code 2 on bad input.
    #[command(long_about = argil::compare::HELP)]
    Compare {
        /// The image measured: a real-time render (`argil render --out a.exr`) or a reference.
        a: PathBuf,
        /// The reference: its alpha > 0 marks the covered pixels, the only ones measured.
        b: PathBuf,
        /// Write the ꟻLIP heat map to this PNG (atomically).
        #[arg(long, value_name = "FILE.png")]
        out: Option<PathBuf>,
        /// Write every figure, and the `argil.*` attributes of both EXRs, as JSON (atomically).
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
    },
}

impl Command {
    /// The files the command writes where its arguments say.
    fn outputs(&self) -> Vec<&Path> {
        let outputs: [Option<&PathBuf>; 2] = match self {
            Command::Render { out, timings, .. } => [Some(out), timings.as_ref()],
            Command::View {
                screenshot, soak_log, ..
            } => [screenshot.as_ref(), soak_log.as_ref()],
            Command::Reference { out, .. } => [Some(out), None],
            Command::Verify { json, .. } => [json.as_ref(), None],
            Command::Compare { out, json, .. } => [out.as_ref(), json.as_ref()],
            Command::Bench { .. } | Command::Devices => [None, None],
        };
        outputs.into_iter().flatten().map(PathBuf::as_path).collect()
    }
}

fn load_with_stand_ins(path: Option<&Path>) -> Result<(Scene, PendingMaps)> {
    let (scene, maps) = PendingMaps::load(path)?;
    scene.print_warnings();
    Ok((scene, maps))
}

fn load_scene(path: Option<&Path>) -> Result<Scene> {
    let scene = match path {
        Some(p) => Scene::load(p)?,
        None => Scene::default_scene(),
    };
    scene.print_warnings();
    Ok(scene)
}

/// A sample count of `--msaa`: one of `[antialiasing] msaa`'s.
fn parse_msaa(text: &str) -> Result<u32, String> {
    let counts = argil::scene::MSAA_COUNTS;
    text.parse()
        .ok()
        .filter(|n| counts.contains(n))
        .ok_or_else(|| format!("{text:?} is not a sample count: one of {counts:?}"))
}

/// A number of seconds: finite and positive.
fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 => Ok(s),
        _ => Err(format!("{text:?} is not a number of seconds > 0")),
    }
}

fn check_exposure(exposure: f32) -> Result<()> {
    if !(exposure.is_finite() && exposure > 0.0) {
        return Err(InputError(format!("--exposure {exposure}: must be a finite number > 0")).into());
    }
    Ok(())
}

struct RenderOptions {
    choice: DeviceChoice,
    validation: bool,
    scene: Option<PathBuf>,
    out: PathBuf,
    outputs: Existing,
    width: u32,
    height: u32,
    exposure: f32,
    timings: Option<PathBuf>,
    msaa: Option<u32>,
    accumulate: u32,
    debug_view: DebugView,
}

fn render(options: RenderOptions, process_start: Instant) -> Result<()> {
    let RenderOptions {
        width,
        height,
        exposure,
        ..
    } = options;
    check_exposure(exposure)?;
    // Ctrl-C ends an accumulation after the frame it is drawing, and the mean of the frames
    // drawn is written; during the start, after the step under way, with nothing written.
    let then = "ending after the step or frame under way, then writing the mean of the frames drawn, if any";
    let interrupted = (options.accumulate > 1).then(|| interrupt_flag(then)).transpose()?;
    let start_interrupted = || -> Result<()> {
        match &interrupted {
            Some(flag) if flag.load(Ordering::Relaxed) => {
                Err(Interrupted("before the first frame: nothing written".into()).into())
            }
            _ => Ok(()),
        }
    };
    let mut startup = Recorder::new(process_start);
    // Stand-ins take the builtin maps' places until the maps, made beside the warm-up frame
    // below, replace them (src/scene/pending.rs).
    let scene_path = options.scene.as_deref();
    let load = || load_with_stand_ins(scene_path);
    let (mut scene, mut maps) = startup.step("scene (stand-ins for its builtin maps)", load)?;
    start_interrupted()?;
    if let Some(msaa) = options.msaa {
        scene.antialiasing.msaa = msaa;
    }
    if options.debug_view == DebugView::ShadowMap && scene.shadow_casting_light().is_none() {
        return Err(InputError(format!(
            "--debug-view shadow-map: no light of {} casts shadows (a [[lights]] entry with shadows = true)",
            scene_path.map_or("the default scene".into(), |p| p.display().to_string())
        ))
        .into());
    }
    let device = startup.step("instance and device", || {
        Device::new(
            DeviceOptions {
                choice: options.choice,
                validation: options.validation,
            },
            None,
        )
        .map(Arc::new)
    })?;
    let mut renderer = startup.step("renderer", || Renderer::new(device.clone(), 1))?;
    renderer.debug_view = options.debug_view;
    // A single frame is drawn forward: the G-buffer's fresh pages cost a first frame more
    // than the shading once a pixel saves it (at 1280×720, about 90 ms against 11).
    renderer.deferred = options.accumulate > 1;
    let mut gpu = startup.step("meshes upload", || renderer.upload(&scene))?;
    start_interrupted()?;
    let samples = renderer.msaa_samples(&scene);
    if samples != scene.antialiasing.msaa {
        eprintln!(
            "argil: warning: {} does not support {}x MSAA; drawing {samples}x, its largest below",
            device.info.name, scene.antialiasing.msaa
        );
    }
    let extent = vk::Extent2D { width, height };
    // An EXR is the linear frame: no display transform runs for it.
    let display = (OutputKind::of(&options.out)? == OutputKind::Png).then_some(exposure);
    // A frame of a few pixels drawn with the stand-ins, while the builtin maps the frame
    // samples are made (src/render/warm_up.rs); the others keep their stand-ins.
    let sampled = renderer.sampled_textures(&scene);
    maps.split_off(|texture| !sampled[texture]);
    let warmed = warm_up(&mut renderer, &mut scene, &mut gpu, maps, display.is_some(), extent)?;
    start_interrupted()?;
    let table = if scene.needs_preintegrated_table() {
        PreintegratedTable::get().compute_time()
    } else {
        Duration::ZERO
    };
    let pipelines = renderer.pipeline_time();
    let built = if renderer.pipelines_beside_environment {
        startup.record_beside("pipelines, made beside the environment precompute", pipelines);
        startup.record_beside("subsurface table, made beside the environment precompute", table);
        vec![("environment precompute, with the pipelines and subsurface table beside it", renderer.environment_time)]
    } else {
        vec![
            ("environment precompute", renderer.environment_time),
            ("subsurface table", table),
            ("pipelines", pipelines),
        ]
    };
    for (name, time) in &built {
        startup.record(name, *time);
    }
    let rest = warmed.prepared.saturating_sub(built.iter().map(|(_, t)| *t).sum());
    let steps = [
        ("targets and the rest of the frame's preparation", rest),
        ("warm-up frame (with the driver's first-draw compile)", warmed.drawn),
        ("the wait for the builtin maps", warmed.wait),
        ("maps upload", warmed.upload),
    ];
    for (name, time) in steps {
        startup.record(name, time);
    }
    startup.record_beside("builtin maps, made during the warm-up frame at a low priority", warmed.making);
    let frame = startup.step("first frame and readback", || {
        let frames = Frames {
            count: options.accumulate,
            until: interrupted.as_deref(),
        };
        renderer.render_accumulated(&scene, &gpu, extent, display, frames)
    })?;
    startup.first_frame();
    let bad = count_non_finite(&frame.hdr);
    if bad > 0 {
        eprintln!("argil: warning: {bad} NaN/Inf values in the frame");
    }
    startup.step("write", || write_frame(&frame, &options.out, options.outputs))?;
    if let Some(path) = &options.timings {
        startup.write(path, options.outputs)?;
    }
    let times = |gpu_ms: &Option<Vec<f64>>| {
        let passes = gpu_ms.as_ref().map(|ms| {
            let times: Vec<String> = PASS_NAMES.iter().zip(ms).map(|(n, t)| format!("{n} {t:.2} ms")).collect();
            times.join(", ")
        });
        passes.map(|t| format!(" (GPU: {t})")).unwrap_or_default()
    };
    println!("{}", options.out.display());
    let vk::Extent2D { width: w, height: h } = WARM_UP_EXTENT;
    eprintln!(
        "argil: {width}x{height} on {}{}; its {w}x{h} warm-up, which drew what the frame reuses{}",
        device.info.name,
        times(&frame.gpu_ms),
        times(&warmed.frame.gpu_ms)
    );
    let costs = renderer.environment().precompute_costs();
    if !costs.is_empty() {
        let steps: Vec<String> = costs
            .iter()
            .map(|c| format!("{} {:.2} ms ({})", c.step, c.ms, if c.gpu { "GPU" } else { "CPU" }))
            .collect();
        eprintln!("argil: environment precomputed once: {}", steps.join(", "));
    }
    if scene.needs_preintegrated_table() {
        eprintln!(
            "argil: pre-integrated subsurface table read or computed once: {:.2} ms (CPU)",
            PreintegratedTable::get().compute_time().as_secs_f64() * 1e3
        );
    }
    drop(gpu);
    drop(renderer);
    if let Some(report) = device.validation() {
        if report.error_count() > 0 {
            bail!("the validation layer reported {} error(s)", report.error_count());
        }
    }
    if frame.frames < options.accumulate {
        let (drawn, of, out) = (frame.frames, options.accumulate, options.out.display());
        return Err(Interrupted(format!("after {drawn} of {of} frames: {out} holds their mean")).into());
    }
    Ok(())
}

/// A progress bar with an ETA on stderr (indicatif draws nothing when stderr is not a
/// terminal), and whether Ctrl-C was pressed.
struct ProgressBar {
    bar: indicatif::ProgressBar,
    interrupted: Arc<AtomicBool>,
}

impl argil::reference::Progress for ProgressBar {
    fn update(&self, done: u64, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(done);
    }

    fn interrupted(&self) -> bool {
        self.interrupted.load(Ordering::Relaxed)
    }
}

/// Ctrl-C's flag: set by the first press, which asks the command to end with the work it
/// has done, `then` as it says.
fn interrupt_flag(then: &'static str) -> Result<Arc<AtomicBool>> {
    let flag = Arc::new(AtomicBool::new(false));
    let set = Arc::clone(&flag);
    argil::interrupt::on_ctrl_c(move || {
        set.store(true, Ordering::Relaxed);
        eprintln!("argil: interrupted: {then} (Ctrl-C again quits at once)");
    })?;
    Ok(flag)
}

fn reference(
    scene: Option<PathBuf>,
    out: PathBuf,
    outputs: Existing,
    settings: Settings,
    threads: Option<usize>,
    exposure: f32,
) -> Result<()> {
    check_exposure(exposure)?;
    if let Stop::Noise { target, .. } = settings.stop {
        if !(target.is_finite() && target > 0.0) {
            return Err(InputError(format!("--noise {target}: must be a finite number > 0")).into());
        }
    }
    OutputKind::of(&out)?;
    let scene = load_scene(scene.as_deref())?;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("cannot start the worker threads")?;
    let bar = indicatif::ProgressBar::new(1).with_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {percent}% ETA {eta}")
            .context("progress bar template")?,
    );
    let progress = ProgressBar {
        bar: bar.clone(),
        interrupted: interrupt_flag("finishing the rows begun, then writing")?,
    };
    let image = pool.install(|| argil::reference::render(&scene, &settings, &progress))?;
    bar.finish_and_clear();
    let attributes = image.exr_attributes(&settings);
    write_linear(&out, outputs, image.width, image.height, &image.rgba, exposure, &attributes)?;
    println!("{}", out.display());
    let samples = match image.most_samples {
        most if most > image.samples => format!("{}–{most} spp", image.samples),
        _ => format!("{} spp", image.samples),
    };
    let ending = match image.ending {
        Ending::Stopped => "",
        Ending::TimeLimit => ", stopped at --max-seconds",
        Ending::Interrupted => ", interrupted",
    };
    eprintln!(
        "argil: reference {}x{}, {} transport, {} filter, {samples}, noise {:.2}%, {:.1} s{ending}, {:.2} Mrays/s \
         on {} threads",
        image.width,
        image.height,
        settings.transport,
        settings.filter,
        image.noise * 100.0,
        image.elapsed.as_secs_f64(),
        image.rays_per_second() / 1e6,
        pool.current_num_threads()
    );
    if image.ending == Ending::Interrupted {
        return Err(Interrupted(format!("after {samples}: {} holds them", out.display())).into());
    }
    Ok(())
}

fn verify(
    choice: DeviceChoice,
    validation: bool,
    json: Option<PathBuf>,
    outputs: Existing,
    options: argil::verify::Options,
) -> Result<()> {
    let device = Arc::new(Device::new(DeviceOptions { choice, validation }, None)?);
    let report = argil::verify::run(&device, &options)?;
    print!("{}", report.table());
    if let Some(path) = json {
        argil::atomic::write_bytes(&path, outputs, report.json().as_bytes())?;
    }
    if let Some(validation) = device.validation() {
        if validation.error_count() > 0 {
            bail!("the validation layer reported {} error(s)", validation.error_count());
        }
    }
    if report.failures() > 0 {
        bail!("{} verification check(s) failed", report.failures());
    }
    Ok(())
}

fn bench(choice: DeviceChoice, validation: bool, options: argil::bench::Options) -> Result<()> {
    if !(options.max_seconds.is_finite() && options.max_seconds > 0.0) {
        return Err(InputError(format!(
            "--max-seconds {}: must be a finite number > 0",
            options.max_seconds
        ))
        .into());
    }
    let device = Arc::new(Device::new(DeviceOptions { choice, validation }, None)?);
    let out = argil::bench::run(&device, &options)?;
    println!("{}", out.display());
    if let Some(report) = device.validation() {
        if report.error_count() > 0 {
            bail!("the validation layer reported {} error(s)", report.error_count());
        }
    }
    Ok(())
}

fn soak_run(choice: DeviceChoice, validation: bool, counts: &[u64]) -> Result<()> {
    let device = Arc::new(Device::new(DeviceOptions { choice, validation }, None)?);
    argil::bench::soak::run(&device, counts[0], counts[1])
}

fn compare(options: argil::compare::Options) -> Result<()> {
    println!("{}", argil::compare::run(&options)?.line());
    Ok(())
}

fn run(cli: Cli, process_start: Instant) -> Result<()> {
    let validation = cli.validation || argil::vk::instance::validation_requested();
    // The same choice, as a child process's `--device` reads it.
    let device_arg = match &cli.device {
        Some(DeviceChoice::Index(i)) => Some(i.to_string()),
        Some(DeviceChoice::Name(n)) => Some(n.clone()),
        Some(DeviceChoice::Best) | None => None,
    };
    let choice = cli.device.unwrap_or(DeviceChoice::Best);
    argil::atomic::check_outputs(cli.command.outputs(), cli.overwrite)?;
    let outputs = Existing::from_overwrite(cli.overwrite);
    match cli.command {
        Command::Render {
            scene,
            out,
            width,
            height,
            exposure,
            timings,
            msaa,
            accumulate,
            debug_view,
        } => render(
            RenderOptions {
                choice,
                validation,
                scene,
                out,
                outputs,
                width,
                height,
                exposure,
                timings,
                msaa,
                accumulate,
                debug_view,
            },
            process_start,
        ),
        Command::View {
            scene,
            frames,
            exposure,
            width,
            height,
            screenshot,
            resize_storm,
            seconds,
            soak_log,
            debug_view,
            split,
        } => {
            check_exposure(exposure)?;
            let (loaded, document) = argil::viewer::open_document(scene.as_deref())?;
            loaded.scene.print_warnings();
            let options = argil::viewer::ViewOptions {
                device: choice,
                validation,
                frames,
                exposure,
                size: (width, height),
                screenshot,
                resize_storm,
                seconds,
                soak_log,
                outputs,
                debug_view,
                split,
            };
            argil::viewer::run(loaded, document, options)
        }
        Command::Verify { json, samples, seed } => {
            verify(choice, validation, json, outputs, argil::verify::Options { samples, seed })
        }
        Command::Reference {
            scene,
            out,
            width,
            height,
            spp,
            noise,
            max_spp,
            max_seconds,
            transport,
            filter,
            sampling,
            subsurface,
            seed,
            max_depth,
            threads,
            exposure,
        } => {
            let stop = match noise {
                Some(target) => Stop::Noise {
                    target,
                    max_samples: max_spp,
                },
                None => Stop::Samples(spp.unwrap_or(64)),
            };
            let settings = Settings {
                width,
                height,
                transport,
                filter,
                sampling,
                subsurface,
                stop,
                seed,
                max_depth,
                max_time: max_seconds.map(Duration::from_secs_f64),
            };
            reference(scene, out, outputs, settings, threads, exposure)
        }
        Command::Bench { soak: Some(soak), .. } => soak_run(choice, validation, &soak),
        Command::Bench {
            soak_viewer: Some(frames),
            ..
        } => argil::bench::soak::run_viewer(frames, device_arg.as_deref()),
        Command::Bench {
            quick,
            frames,
            warmup,
            max_seconds,
            out,
            references,
            only,
            startup_runs,
            soak: None,
            soak_viewer: None,
        } => {
            let options = argil::bench::Options {
                quick,
                frames: frames.unwrap_or(if quick { 10 } else { 100 }),
                warmup: warmup.unwrap_or(if quick { 2 } else { 5 }),
                max_seconds,
                out,
                references,
                only,
                startup_runs: startup_runs.unwrap_or(if quick { 1 } else { 5 }),
            };
            bench(choice, validation, options)
        }
        Command::Compare { a, b, out, json } => compare(argil::compare::Options {
            a,
            b,
            out,
            json,
            outputs,
        }),
        Command::Devices => {
            let devices = device::list_devices().context("cannot list Vulkan devices")?;
            if devices.is_empty() {
                bail!(argil::vk::instance::NO_DRIVER);
            }
            for d in devices {
                println!("{d}");
            }
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    let process_start = Instant::now();
    match run(Cli::parse(), process_start) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("argil: error: {e:#}");
            if let Some(advice) = advice(&e) {
                eprintln!("argil: {advice}");
            }
            // 2 for bad input, as clap exits for bad arguments.
            if is_input_error(&e) {
                ExitCode::from(2)
            } else if is_interrupted(&e) {
                ExitCode::from(INTERRUPTED_EXIT_CODE)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
