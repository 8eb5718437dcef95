//! What the rendering tests share: one Vulkan device per test binary (lavapipe start-up is
//! not free) with the validation layer on, frames rendered one at a time so that every
//! validation error is charged to the test whose frame caused it, and image comparison.

#![allow(dead_code)] // each test binary uses its own part of this module

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use argil::render::{count_non_finite, GpuScene, OffscreenFrame, OffscreenTarget, Renderer};
use argil::scratch::Scratch;
use argil::scene::Scene;
use argil::vk::{Device, DeviceChoice, DeviceOptions};
use ash::vk;

pub struct Gpu {
    pub device: Arc<Device>,
    renderer: Mutex<Renderer>,
}

/// The device of this test binary: `ARGIL_TEST_DEVICE` (index or name) or the default choice.
pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        let choice = std::env::var("ARGIL_TEST_DEVICE")
            .map(|s| s.parse().expect("infallible"))
            .unwrap_or(DeviceChoice::Best);
        let device = Arc::new(
            Device::new(
                DeviceOptions {
                    choice,
                    validation: true,
                },
                None,
            )
            .expect("a Vulkan device with the validation layer (run `make setup`)"),
        );
        let renderer = Mutex::new(Renderer::new(device.clone(), 1).expect("renderer"));
        Gpu { device, renderer }
    })
}

impl Gpu {
    /// Runs `work` alone on the device and fails if the validation layer reported an error
    /// meanwhile.
    pub fn exclusive<R>(&self, work: impl FnOnce(&mut Renderer) -> R) -> R {
        let mut renderer = self.renderer.lock().unwrap_or_else(|e| e.into_inner());
        let report = self.device.validation().expect("tests run with validation on");
        let (errors, first_message) = (report.error_count(), report.message_count());
        let result = work(&mut renderer);
        let new_errors = report.error_count() - errors;
        assert_eq!(
            new_errors,
            0,
            "the validation layer reported {new_errors} error(s):\n{}",
            report.messages_since(first_message).join("\n")
        );
        result
    }
}

/// Uploads `scene` and renders it offscreen at `width`×`height`, exposure 1; for tests that
/// inspect the renderer afterwards or expect an error. Call inside [`Gpu::exclusive`].
pub fn try_render(renderer: &mut Renderer, scene: &Scene, width: u32, height: u32) -> anyhow::Result<OffscreenFrame> {
    let gpu_scene = renderer.upload(scene)?;
    renderer.render_offscreen(scene, &gpu_scene, vk::Extent2D { width, height }, 1.0)
}

/// Draws one frame of `scene`, uploaded as `gpu_scene`, into `target` at exposure 1 and
/// reads its HDR radiance back; the renderer keeps what it made (shadow maps, what is read
/// at the vertices) for the next frame, as the viewer's does.
pub fn draw_hdr(renderer: &mut Renderer, scene: &Scene, gpu_scene: &GpuScene, target: &OffscreenTarget) -> Vec<f32> {
    let ms = renderer.draw_offscreen(scene, gpu_scene, target, 1.0).expect("draw");
    renderer.read_offscreen(target, ms).expect("read").hdr
}

/// Frames of a scene drawn into a small offscreen target, for tests that count what the
/// renderer makes once per change of what it is made of (`made`, such as
/// `Renderer::ground_occlusion_renders`), not per frame.
pub struct CountedFrames {
    gpu_scene: GpuScene,
    target: OffscreenTarget,
    made: fn(&Renderer) -> u64,
    before: u64,
}

impl CountedFrames {
    /// Uploads `scene` and draws two frames of it, a floor frame of the bench's between
    /// them (which reads nothing made and leaves it as it is), checking that they made it
    /// once.
    pub fn new(renderer: &mut Renderer, scene: &Scene, made: fn(&Renderer) -> u64) -> Self {
        let gpu_scene = renderer.upload(scene).expect("upload");
        let target = OffscreenTarget::new(&renderer.device, vk::Extent2D { width: 64, height: 48 }).expect("target");
        let frames = Self {
            gpu_scene,
            target,
            made,
            before: made(renderer),
        };
        assert_eq!(frames.draw(renderer, scene), 1);
        renderer.floor = true;
        frames.draw(renderer, scene);
        renderer.floor = false;
        assert_eq!(frames.draw(renderer, scene), 1);
        frames
    }

    /// Draws a frame of `scene` (the uploaded one, changed or not) and returns how many
    /// times the renderer made what is counted since [`Self::new`] began.
    pub fn draw(&self, renderer: &mut Renderer, scene: &Scene) -> u64 {
        renderer.draw_offscreen(scene, &self.gpu_scene, &self.target, 1.0).expect("draw");
        (self.made)(renderer) - self.before
    }
}

/// Renders `scene` at `width`×`height` and checks the frame has no NaN/Inf value.
pub fn render(scene: &Scene, width: u32, height: u32) -> OffscreenFrame {
    let frame = gpu().exclusive(|renderer| try_render(renderer, scene, width, height).expect("render"));
    assert_eq!(count_non_finite(&frame.hdr), 0, "NaN/Inf values in the rendered frame");
    frame
}

/// [`render`] with every object drawn in the forward pass (`Renderer::deferred` off): for
/// comparisons bit for bit with frames the G-buffer does not serve, which the deferred
/// frame matches only to the last bits of fp32 (tests/deferred.rs).
pub fn render_forward(scene: &Scene, width: u32, height: u32) -> OffscreenFrame {
    let frame = gpu().exclusive(|renderer| {
        renderer.deferred = false;
        let frame = try_render(renderer, scene, width, height);
        renderer.deferred = true;
        frame.expect("render")
    });
    assert_eq!(count_non_finite(&frame.hdr), 0, "NaN/Inf values in the rendered frame");
    frame
}

pub fn project_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Where failing image tests leave `NAME-actual.png` and `NAME-diff.png` for a human.
pub fn failure_dir() -> PathBuf {
    project_dir().join("target").join("test-failures")
}

/// Root-mean-square difference in 8-bit units over RGB, and the largest channel difference.
pub fn rgb_difference(a: &[u8], b: &[u8]) -> (f64, u8) {
    assert_eq!(a.len(), b.len());
    let mut sum = 0.0f64;
    let mut max = 0u8;
    let mut n = 0usize;
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for c in 0..3 {
            let d = pa[c].abs_diff(pb[c]);
            sum += f64::from(d) * f64::from(d);
            max = max.max(d);
            n += 1;
        }
    }
    ((sum / n as f64).sqrt(), max)
}

/// Compares a frame's display image with `tests/golden/NAME.png`.
///
/// Tolerance: RMSE ≤ 1.0 in 8-bit units. The renderer is deterministic on one machine;
/// across Mesa/LLVM versions and CPUs, fp contraction and transcendental approximations
/// move tone-mapped values by at most one code value on some pixels (RMSE < 1), while a
/// 2% change of any lobe's radiance moves lit pixels by 2–5 code values.
/// `ARGIL_BLESS=1` writes the golden instead (review the image before committing it).
pub fn assert_matches_golden(frame: &OffscreenFrame, name: &str) {
    const MAX_RMSE: f64 = 1.0;
    let golden_path = project_dir().join("tests/golden").join(format!("{name}.png"));
    let actual = image::RgbaImage::from_raw(frame.width, frame.height, frame.display.clone()).expect("size");
    if std::env::var_os("ARGIL_BLESS").is_some() {
        actual.save(&golden_path).expect("write golden");
        eprintln!("wrote golden {}", golden_path.display());
        return;
    }
    let golden = image::open(&golden_path)
        .unwrap_or_else(|e| {
            panic!(
                "cannot read golden {}: {e} (ARGIL_BLESS=1 creates it)",
                golden_path.display()
            )
        })
        .to_rgba8();
    assert_eq!(
        golden.dimensions(),
        actual.dimensions(),
        "golden {name} has another size"
    );
    let (rmse, max) = rgb_difference(golden.as_raw(), actual.as_raw());
    if rmse > MAX_RMSE {
        let dir = failure_dir();
        std::fs::create_dir_all(&dir).expect("create failure dir");
        let actual_path = dir.join(format!("{name}-actual.png"));
        let diff_path = dir.join(format!("{name}-diff.png"));
        actual.save(&actual_path).expect("write actual");
        let diff = image::RgbaImage::from_fn(frame.width, frame.height, |x, y| {
            let (a, g) = (actual.get_pixel(x, y), golden.get_pixel(x, y));
            let d = (0..3).map(|c| a[c].abs_diff(g[c])).max().unwrap_or(0);
            image::Rgba([d.saturating_mul(8), 0, 0, 255])
        });
        diff.save(&diff_path).expect("write diff");
        panic!(
            "{name}: RMSE {rmse:.3} > {MAX_RMSE} (max channel difference {max}); see {} and {}",
            actual_path.display(),
            diff_path.display()
        );
    }
    eprintln!("{name}: RMSE {rmse:.3} (max channel difference {max})");
}

/// A scene from TOML text, with paths relative to `tests/`.
pub fn scene(toml: &str) -> Scene {
    Scene::from_toml(
        toml,
        "test scene",
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").as_path(),
    )
    .expect("test scene parses")
}

/// Runs the `argil` binary with the validation layer on and a private runtime directory.
pub fn argil(args: &[&str]) -> Output {
    argil_with(args, &[])
}

/// [`argil`] with more environment variables.
pub fn argil_with(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_argil"));
    command.args(args).envs(env.iter().copied());
    run(command)
}

/// A fresh folder for a test's files, removed when dropped: `argil-TEST-NAME-K-PID`, TEST
/// the test binary and K counting its folders, so that tests running at once never share one.
pub fn test_dir(name: &str) -> Scratch {
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let k = COUNT.fetch_add(1, Ordering::Relaxed);
    Scratch::new(&format!("{}-{name}-{k}", env!("CARGO_CRATE_NAME"))).expect("test folder")
}

/// Runs `command` with the validation layer on and a private runtime directory, and fails
/// if it runs for more than [`HANG`].
pub fn run(mut command: Command) -> Output {
    let runtime = test_dir("runtime");
    let child = command
        .env("ARGIL_VALIDATION", "1")
        .env("XDG_RUNTIME_DIR", &runtime)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run argil");
    wait(child, &format!("{command:?}"))
}

/// The output of `child` (`what` names it), once it ends; fails if it runs for more than
/// [`HANG`].
pub fn wait(child: std::process::Child, what: &str) -> Output {
    let pid = child.id();
    let (done, output) = std::sync::mpsc::channel();
    std::thread::spawn(move || done.send(child.wait_with_output()));
    match output.recv_timeout(HANG) {
        Ok(output) => output.expect("wait for argil"),
        Err(_) => {
            // Only the process this test started, by its id.
            let _ = Command::new("kill").args(["-9", &pid.to_string()]).status();
            panic!("{what} still running after {HANG:?}: it hangs");
        }
    }
}

/// A private X server for the viewer's tests, stopped when dropped. The server chooses a
/// free display itself (`-displayfd`), so tests starting servers at once never race for a
/// number, and argil's exit code reaches the test with no wrapper script (`xvfb-run`) whose
/// own clean-up can replace it.
pub struct Xvfb {
    server: std::process::Child,
    display: String,
}

impl Xvfb {
    pub fn start() -> Self {
        use std::io::{BufRead, BufReader};
        use std::process::Stdio;
        let mut server = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp", "-noreset"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("run Xvfb (`make setup` installs it)");
        // The server writes its display number once it accepts connections.
        let mut number = String::new();
        let stdout = server.stdout.take().expect("Xvfb's stdout");
        BufReader::new(stdout).read_line(&mut number).expect("read Xvfb's display");
        let number = number.trim();
        assert!(!number.is_empty(), "Xvfb ended before it opened a display");
        Self {
            server,
            display: format!(":{number}"),
        }
    }

    /// `program` as a client of this server, with the validation layer on.
    pub fn command(&self, program: &str) -> Command {
        let mut command = Command::new(program);
        command
            .env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY")
            .env("ARGIL_VALIDATION", "1");
        command
    }

    /// argil's `view` on this server.
    pub fn view(&self) -> Command {
        let mut command = self.command(env!("CARGO_BIN_EXE_argil"));
        command.arg("view");
        command
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM, so that the server removes its lock file and socket.
        let _ = Command::new("kill").arg(self.server.id().to_string()).status();
        let _ = self.server.wait();
    }
}

/// Longer than any command of the tests takes on lavapipe with the machine busy (the
/// slowest, the viewer's reload test, takes about a minute).
pub const HANG: std::time::Duration = std::time::Duration::from_secs(600);

/// (p50, p99, max) of the errors.
pub fn percentiles(mut errors: Vec<f64>) -> (f64, f64, f64) {
    assert!(!errors.is_empty());
    errors.sort_by(f64::total_cmp);
    let at = |q: f64| errors[((errors.len() - 1) as f64 * q) as usize];
    (at(0.5), at(0.99), errors[errors.len() - 1])
}

/// A Lambert sphere at the origin under one point light, seen head-on from z = 5.
pub const LAMBERT_SPHERE: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [2.0, 2.0, 3.0]
intensity = [10.0, 7.0, 4.0]

[[objects]]
mesh = "builtin:sphere"
material = "white"

[materials.white]
base_color = [0.8, 0.6, 0.4]
diffuse = "lambert"
specular = "none"
"#;

/// A glossy clay sphere under the studio, its environment light `samples` sampled lookups a
/// frame: noisy in both lobes, for the accumulation's tests.
pub fn sampled_sphere_toml(samples: u32) -> String {
    format!(
        r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 25.0
[environment]
kind = "studio"
reflection = "sampled"
samples = {samples}
[[objects]]
mesh = "builtin:sphere"
material = "m"
[materials.m]
base_color = [0.62, 0.26, 0.12]
diffuse = "lambert"
specular = "cook-torrance"
roughness = 0.3
"#
    )
}
