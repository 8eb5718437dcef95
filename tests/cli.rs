//! The `argil` command as a user meets it: help, devices, rendering to files, bad input,
//! and the window under Xvfb. Every run has the validation layer on and must print no
//! validation message (leaked handles are reported when the device is destroyed).

mod common;

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output};

use common::{argil, argil_with, gpu, sampled_sphere_toml, test_dir, Xvfb};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_clean_success(o: &Output) {
    let err = stderr(o);
    assert!(o.status.success(), "argil failed: {err}");
    assert!(!err.contains("vulkan validation"), "validation messages: {err}");
}

/// Bad input: exit code 2, no panic, a message with `mentions`.
fn assert_clean_failure(o: &Output, mentions: &[&str]) {
    assert_failure(o, 2, mentions);
}

fn assert_failure(o: &Output, code: i32, mentions: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "argil's exit code: {err}");
    assert!(!err.contains("panicked"), "argil panicked: {err}");
    for m in mentions {
        assert!(err.contains(m), "error does not mention {m:?}: {err}");
    }
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 temp path")
}

#[test]
fn help_documents_every_command() {
    let o = argil(&["--help"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for word in ["render", "view", "devices", "--device", "--validation"] {
        assert!(text.contains(word), "--help lacks {word}: {text}");
    }
    let o = argil(&["render", "--help"]);
    let text = String::from_utf8_lossy(&o.stdout);
    for word in ["--out", "--width", "--height", "--exposure", ".exr", "linear"] {
        assert!(text.contains(word), "render --help lacks {word}: {text}");
    }
}

/// The contract scripts rely on, one command of each class: 0 done, 2 the input is wrong,
/// 1 argil or the machine failed (here a device lost half-way, injected).
#[test]
fn exit_codes_follow_the_contract() {
    let o = argil(&["--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    for word in ["Exit codes", "0 ", "1 ", "2 ", "ARGIL_FAULT"] {
        assert!(help.contains(word), "--help lacks {word:?}: {help}");
    }
    let dir = test_dir("exit-codes");
    let out = dir.join("frame.png");
    let size = ["--width", "32", "--height", "32"];
    let render = |scene: Option<&Path>, env: &[(&str, &str)]| {
        let mut args = vec!["render", "--out", path_str(&out)];
        args.extend(scene.map(path_str));
        args.extend(size);
        argil_with(&args, env)
    };
    let o = render(None, &[]);
    assert_clean_success(&o);
    assert_eq!(o.status.code(), Some(0));
    std::fs::remove_file(&out).expect("rendered");

    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "[camera\n").expect("write");
    assert_failure(&render(Some(&broken), &[]), 2, &["broken.toml"]);
    assert_failure(&argil(&["render", "--out"]), 2, &["--out"]);
    assert_failure(
        &argil(&["--device", "99", "render", "--out", path_str(&out)]),
        2,
        &["--device 99"],
    );
    assert_failure(
        &render(None, &[("ARGIL_FAULT", "alloc")]),
        2,
        &["ARGIL_FAULT", "alloc:N"],
    );
    assert!(!out.exists(), "nothing is written for bad input");

    let o = render(None, &[("ARGIL_FAULT", "device-lost:2")]);
    assert_failure(&o, 1, &["device was lost"]);
    assert!(!out.exists(), "nothing is written after a failure");
}

/// No Vulkan driver at all: one sentence saying what to install, exit code 1.
#[test]
fn without_a_vulkan_driver_argil_says_what_to_install() {
    let dir = test_dir("no-driver");
    let out = dir.join("frame.png");
    for variable in ["VK_ICD_FILENAMES", "VK_DRIVER_FILES"] {
        let env = [(variable, "/nonexistent/icd.json")];
        for args in [&["devices"][..], &["render", "--out", path_str(&out)], &["verify"]] {
            let o = argil_with(args, &env);
            assert_failure(&o, 1, &["no Vulkan driver", "install", "mesa-vulkan-drivers"]);
            let errors = stderr(&o).lines().filter(|l| l.starts_with("argil:")).count();
            assert_eq!(errors, 1, "one line: {}", stderr(&o));
        }
    }
    assert!(!out.exists());
}

/// An output that exists is refused without `--overwrite`; with it, a disk that fills
/// half-way through writing (injected) leaves the previous file there, byte for byte, and no
/// temporary beside it.
#[test]
fn a_write_failing_half_way_leaves_the_previous_output() {
    let dir = test_dir("half-write");
    for name in ["frame.png", "frame.exr"] {
        let out = dir.join(name);
        let previous = format!("the previous {name}, kept");
        std::fs::write(&out, &previous).expect("write");
        let kept = ["render", "--out", path_str(&out), "--width", "48", "--height", "32"];
        assert_failure(&argil(&kept), 2, &[name, "already exists", "--overwrite"]);
        assert_eq!(std::fs::read(&out).expect("read"), previous.as_bytes());
        let args = [&kept[..], &["--overwrite"]].concat();
        let o = argil_with(&args, &[("ARGIL_FAULT", "write:200")]);
        assert_failure(&o, 1, &[name, "no space left"]);
        assert_eq!(std::fs::read(&out).expect("read"), previous.as_bytes());
        let temporaries: Vec<_> = std::fs::read_dir(&dir)
            .expect("list")
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
            .collect();
        assert!(temporaries.is_empty(), "temporaries left: {temporaries:?}");
        // Without the fault the same command replaces it, as asked.
        assert_clean_success(&argil(&args));
        assert_ne!(std::fs::read(&out).expect("read"), previous.as_bytes());
    }
}

/// An output its folder would not take (missing, a file, or the output a folder) is refused
/// before any work, by every command that writes one, with or without `--overwrite`: an
/// hour's reference must not end unable to write its image.
#[test]
fn an_output_that_could_not_be_written_is_refused_at_the_start() {
    let dir = test_dir("unwritable");
    let file = dir.join("a-file");
    std::fs::write(&file, "").expect("write");
    let missing = dir.join("missing/frame.exr");
    let under_file = file.join("frame.exr");
    let (missing, under_file, folder) = (path_str(&missing), path_str(&under_file), path_str(&dir));
    for (args, problem) in [
        (vec!["render", "--out", missing], "missing does not exist"),
        (vec!["reference", "--out", under_file, "--spp", "4096"], "a-file is not a folder"),
        (vec!["reference", "--out", folder, "--overwrite"], "is a folder, not a file"),
        (vec!["verify", "--json", missing], "missing does not exist"),
        (vec!["compare", "a.exr", "b.exr", "--json", under_file], "a-file is not a folder"),
    ] {
        let o = argil(&args);
        assert_failure(&o, 2, &[problem]);
        assert_eq!(stderr(&o).lines().count(), 1, "{args:?} began its work: {}", stderr(&o));
    }
    assert_eq!(std::fs::read_dir(&dir).expect("list").count(), 1, "nothing written");
}

/// An output that another program creates while `argil render` runs is not replaced either:
/// exit code 2 naming it, the file as that program wrote it, and the frame in the temporary
/// file the message names. The scene comes through a FIFO, which argil opens after its check
/// of the outputs: the file appears between that check and the frame's write.
#[test]
fn an_output_that_appears_during_the_run_is_not_replaced() {
    let dir = test_dir("appears");
    let (fifo, out) = (dir.join("scene.toml"), dir.join("frame.exr"));
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo").success());
    let mut command = Command::new(env!("CARGO_BIN_EXE_argil"));
    command.args(["render", path_str(&fifo), "--out", path_str(&out), "--width", "48", "--height", "32"]);
    let appearing = out.clone();
    let writer = std::thread::spawn(move || {
        // Opening for writing waits for argil to open the scene to read it.
        let mut scene = std::fs::OpenOptions::new().write(true).open(&fifo).expect("open the FIFO");
        std::fs::write(&appearing, "another program's frame").expect("write");
        scene.write_all(SPHERE.as_bytes()).expect("write the scene");
    });
    let o = common::run(command);
    assert_failure(&o, 2, &["frame.exr", "appeared", "--overwrite", "argil's output is in"]);
    assert!(!stderr(&o).contains("vulkan validation"), "validation messages: {}", stderr(&o));
    writer.join().expect("the scene's writer");
    assert_eq!(std::fs::read(&out).expect("read"), b"another program's frame");
    let kept: Vec<_> = std::fs::read_dir(&dir)
        .expect("list")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with(".frame.exr.")))
        .collect();
    assert_eq!(kept.len(), 1, "{kept:?}");
    assert!(stderr(&o).contains(path_str(&kept[0])), "{}", stderr(&o));
    let frame = argil::compare::input::read_exr(&kept[0]).expect("the kept frame is an EXR");
    assert_eq!((frame.image.width, frame.image.height), (48, 32));
}

/// A disk cache that refuses every entry costs a start only the time: the frame is
/// written, and one warning names the first entry that failed, not one an entry.
#[test]
fn a_cache_that_cannot_be_written_is_reported_once() {
    let dir = test_dir("unwritable-cache");
    let file = dir.join("a-file");
    std::fs::write(&file, "not a folder").expect("write");
    let cache = file.join("cache");
    let out = dir.join("frame.png");
    let args = ["render", "--out", path_str(&out), "--width", "48", "--height", "32"];
    let o = argil_with(&args, &[("ARGIL_CACHE_DIR", path_str(&cache))]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("cannot write the cache entry")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(warnings[0].contains(path_str(&cache)), "{err}");
}

#[test]
fn devices_lists_at_least_one() {
    let o = argil(&["devices"]);
    assert_clean_success(&o);
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("0: "));
}

const SPHERE: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [0.0, 0.0, 5.0]
intensity = [40.0, 40.0, 40.0]

[[objects]]
mesh = "builtin:sphere"
material = "white"

[materials.white]
base_color = [1.0, 1.0, 1.0]
diffuse = "lambert"
specular = "none"
"#;

/// The EXR holds radiance as computed: at the centre of the sphere facing a head-on light
/// at distance 4, L = (1/π)·40/16 ≈ 0.7958 — above what any tone mapper would leave.
#[test]
fn render_exr_writes_linear_radiance_without_exposure() {
    let dir = test_dir("exr");
    let scene = dir.join("sphere.toml");
    std::fs::write(&scene, SPHERE).expect("write scene");
    for exposure in ["1", "4"] {
        let out = dir.join(format!("sphere-{exposure}.exr"));
        let o = argil(&[
            "render",
            path_str(&scene),
            "--out",
            path_str(&out),
            "--width",
            "63",
            "--height",
            "63",
            "--exposure",
            exposure,
        ]);
        assert_clean_success(&o);
        let image = image::open(&out).expect("read exr").into_rgba32f();
        let centre = image.get_pixel(31, 31);
        let expected = 40.0 / 16.0 / std::f32::consts::PI;
        for c in 0..3 {
            assert!(
                (centre[c] - expected).abs() < 1e-3 * expected,
                "centre {centre:?} vs {expected}"
            );
        }
    }
    let png = dir.join("sphere.png");
    assert_clean_success(&argil(&[
        "render",
        path_str(&scene),
        "--out",
        path_str(&png),
        "--width",
        "64",
        "--height",
        "48",
    ]));
    let image = image::open(&png).expect("read png").into_rgb8();
    assert_eq!(image.dimensions(), (64, 48));
}

#[test]
fn render_without_scene_renders_the_default_scene() {
    let dir = test_dir("default");
    let out = dir.join("clay.png");
    let o = argil(&["render", "--out", path_str(&out), "--width", "96", "--height", "54"]);
    assert_clean_success(&o);
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("clay.png"),
        "prints the path it wrote"
    );
    assert!(out.is_file());
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = test_dir("bad");
    let unknown_key = dir.join("unknown.toml");
    std::fs::write(&unknown_key, SPHERE.replace("fov_y_degrees", "fov_degrees")).expect("write");
    let out = dir.join("x.png");
    let out = path_str(&out);
    assert_clean_failure(
        &argil(&["render", path_str(&unknown_key), "--out", out]),
        &["unknown.toml", "fov_degrees"],
    );

    let nan = dir.join("nan.toml");
    std::fs::write(
        &nan,
        SPHERE.replace("base_color = [1.0, 1.0, 1.0]", "base_color = [nan, 1.0, 1.0]"),
    )
    .expect("write");
    assert_clean_failure(
        &argil(&["render", path_str(&nan), "--out", out]),
        &["nan.toml", "base_color"],
    );

    let obj = dir.join("broken.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").expect("write");
    let broken_mesh = dir.join("broken-mesh.toml");
    std::fs::write(&broken_mesh, SPHERE.replace("builtin:sphere", "broken.obj")).expect("write");
    assert_clean_failure(
        &argil(&["render", path_str(&broken_mesh), "--out", out]),
        &["broken.obj"],
    );

    assert_clean_failure(
        &argil(&["render", "/nonexistent/scene.toml", "--out", out]),
        &["/nonexistent/scene.toml"],
    );
    assert_clean_failure(&argil(&["render", "--out", out, "--width", "0"]), &["--width", "0"]);
    assert_clean_failure(
        &argil(&["render", "--out", out, "--width", "100000", "--height", "100000"]),
        &["--width", "100000"],
    );
    assert_clean_failure(&argil(&["render", "--out", out, "--exposure", "nan"]), &["--exposure"]);
    assert_clean_failure(
        &argil(&["render", "--out", path_str(&dir.join("x.bmp"))]),
        &["x.bmp", ".png", ".exr"],
    );
    assert_clean_failure(&argil(&["--device", "no-such-gpu", "devices-typo"]), &[]);
    assert_clean_failure(
        &argil(&["--device", "no-such-gpu", "render", "--out", out]),
        &["no-such-gpu"],
    );
}

/// `render --debug-view shadow-map` draws the view of a scene whose light casts shadows,
/// and refuses one where no light does: exit 2, the file and the reason named, nothing
/// written.
#[test]
fn the_shadow_map_view_needs_a_light_that_casts_shadows() {
    let dir = test_dir("shadow-map");
    let out = dir.join("view.png");
    let view = |scene: &Path| {
        argil(&[
            "render",
            path_str(scene),
            "--out",
            path_str(&out),
            "--width",
            "32",
            "--height",
            "32",
            "--debug-view",
            "shadow-map",
        ])
    };
    let lit = dir.join("lit.toml");
    std::fs::write(&lit, SPHERE).expect("write");
    assert_clean_success(&view(&lit));
    std::fs::remove_file(&out).expect("rendered");
    let unshadowed = dir.join("unshadowed.toml");
    std::fs::write(
        &unshadowed,
        SPHERE.replace("intensity = [40.0, 40.0, 40.0]", "intensity = [40.0, 40.0, 40.0]\nshadows = false"),
    )
    .expect("write");
    assert_clean_failure(&view(&unshadowed), &["unshadowed.toml", "shadow-map", "casts shadows"]);
    assert!(!out.exists(), "nothing is written for bad input");
}

/// The window path: a real X server (Xvfb), a swapchain, a few frames, a clean exit.
#[test]
fn view_opens_a_window_under_xvfb() {
    let o = view_under_xvfb(&["--frames", "5"]);
    assert_clean_success(&o);
}

/// The viewer's leak hunt: without a display it is refused as bad input, saying how to get
/// one; under Xvfb a short run samples memory ten times and counts the child's validation
/// messages (none).
#[test]
fn bench_soak_viewer_needs_a_display_and_samples_the_viewer() {
    let mut headless = Command::new(env!("CARGO_BIN_EXE_argil"));
    headless
        .args(["bench", "--soak-viewer", "10"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY");
    assert_clean_failure(&common::run(headless), &["display", "xvfb-run"]);

    let xvfb = Xvfb::start();
    let mut windowed = xvfb.command(env!("CARGO_BIN_EXE_argil"));
    windowed.args(["bench", "--soak-viewer", "40"]);
    let o = common::run(windowed);
    assert_clean_success(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(out.lines().filter(|l| l.starts_with("viewer ")).count(), 10, "{out}");
    assert!(
        out.contains("40 viewer frames") && out.contains("validation messages: 0"),
        "{out}"
    );
}

/// `argil view` under Xvfb with its own arguments; validation on.
fn view_under_xvfb(args: &[&str]) -> Output {
    let runtime = test_dir("xvfb-runtime");
    Xvfb::start()
        .view()
        .args(args)
        .env("XDG_RUNTIME_DIR", &runtime)
        .output()
        .expect("run argil view")
}

/// Where the viewer drew the 3D view, from its closing line "view WxH at x X": the window
/// beside the panel.
fn view_area(err: &str) -> (u32, u32, u32) {
    let numbers = err
        .split("; view ")
        .nth(1)
        .and_then(|rest| rest.split(';').next())
        .and_then(|area| {
            let (size, x) = area.split_once(" at x ")?;
            let (w, h) = size.split_once('x')?;
            Some((w.parse().ok()?, h.parse().ok()?, x.parse().ok()?))
        });
    numbers.unwrap_or_else(|| panic!("no view area in: {err}"))
}

/// RMSE in code values between the 3D view of a window screenshot, `left` pixels from
/// its left edge, and the headless render at `path`, which has the view's size.
fn view_rmse(window: &image::RgbImage, left: u32, path: &Path) -> f64 {
    let reference = image::open(path).expect("read render").to_rgb8();
    let (w, h) = reference.dimensions();
    let mut sum = 0.0;
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let d = f64::from(window.get_pixel(left + x, y)[c]) - f64::from(reference.get_pixel(x, y)[c]);
                sum += d * d;
            }
        }
    }
    (sum / f64::from(w * h * 3)).sqrt()
}

/// The window shows the frame `argil render` writes, beside the panel: the screenshot's
/// view area, UI included, matches the headless render of the same scene at the view's
/// size (so the camera's aspect follows the view), and the panel is left of it.
///
/// Threshold: RMSE ≤ 0.5 code values. Both frames come from the same device, shaders and
/// camera, and both targets are 8-bit sRGB encoded by the hardware (B8G8R8A8 vs R8G8B8A8
/// differ only in channel order), so they agree exactly when the window shows the right
/// frame; a moved camera, a stale scene, another aspect or UI drawn over the view gives
/// RMSE > 2.
#[test]
fn view_screenshot_matches_the_headless_render_beside_the_ui() {
    let dir = test_dir("screenshot");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, argil::scene::DEFAULT_SCENE_TOML).expect("write scene");
    let shot = dir.join("window.png");
    let (w, h) = (640u32, 400u32);
    let (width, height) = (w.to_string(), h.to_string());
    let o = view_under_xvfb(&[
        "--frames",
        "3",
        "--screenshot",
        path_str(&shot),
        path_str(&scene),
        "--width",
        width.as_str(),
        "--height",
        height.as_str(),
    ]);
    assert_clean_success(&o);
    let err = stderr(&o);
    assert!(!err.contains("which no frame had sampled"), "no frame samples the noise map: {err}");
    let (view_w, view_h, left) = view_area(&err);
    // The panel is PANEL_WIDTH points wide, at one pixel a point under Xvfb.
    let panel = argil::viewer::PANEL_WIDTH as u32;
    assert!(
        left.abs_diff(panel) <= 2 && view_w == w - left && view_h == h,
        "view {view_w}x{view_h} at x {left}"
    );
    let headless = dir.join("headless.png");
    assert_clean_success(&render_at(&scene, &headless, (view_w, view_h), &[]));

    let window = image::open(&shot).expect("read screenshot").to_rgb8();
    assert_eq!(window.dimensions(), (w, h));
    let rmse = view_rmse(&window, left, &headless);
    eprintln!("window vs headless: RMSE {rmse:.3} in the view");
    assert!(rmse <= 0.5, "the window shows another frame: RMSE {rmse:.3}");
    // The panel is drawn: its fill is not the frame's background, nor uniform.
    let panel_pixels: Vec<_> = (0..left).flat_map(|x| (0..h).map(move |y| (x, y))).collect();
    let distinct = panel_pixels
        .iter()
        .map(|&(x, y)| window.get_pixel(x, y).0)
        .collect::<std::collections::HashSet<_>>()
        .len();
    assert!(
        distinct > 20,
        "the screenshot has no UI: {distinct} colours under the panel"
    );
}

/// RMSE in code values between columns `columns` (and rows above `bottom`) of the 3D view
/// of a window screenshot, `left` pixels from its left edge, and the same pixels of `reference`.
fn region_rmse(
    window: &image::RgbImage,
    left: u32,
    reference: &image::RgbImage,
    columns: std::ops::Range<u32>,
    bottom: u32,
) -> f64 {
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in 0..bottom {
        for x in columns.clone() {
            for c in 0..3 {
                let d = f64::from(window.get_pixel(left + x, y)[c]) - f64::from(reference.get_pixel(x, y)[c]);
                sum += d * d;
                n += 1.0;
            }
        }
    }
    (sum / n).sqrt()
}

/// `argil view --split report` shows the scene as it is left of a divider down the middle
/// of the 3D view and the report's composition right of it: each part matches the headless
/// render of its configuration (RMSE ≤ 0.5, as the whole view does without the split, see
/// above), the right part is told apart from the scene (its RMSE against the scene's render
/// is more than twice that against the report's, and at least 0.25: 0.64 measured at this
/// size, the ring and ground only), the divider is drawn and the validation layer stays
/// silent. The labels' strip at the bottom and the columns next to the divider are left out.
#[test]
fn view_splits_the_view_between_two_configurations() {
    let dir = test_dir("split-view");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, argil::scene::DEFAULT_SCENE_TOML).expect("write scene");
    let file: argil::scene::file::SceneFile = toml::from_str(argil::scene::DEFAULT_SCENE_TOML).expect("parse");
    let report = dir.join("report.toml");
    let report_text = argil::bench::plan::configured(&file, "report")
        .expect("configure")
        .to_toml();
    std::fs::write(&report, report_text.expect("toml")).expect("write report");
    let shot = dir.join("window.png");
    let o = view_under_xvfb(&[
        "--frames",
        "3",
        "--screenshot",
        path_str(&shot),
        path_str(&scene),
        "--width",
        "640",
        "--height",
        "400",
        "--split",
        "report",
    ]);
    assert_clean_success(&o);
    // The start left the noise map, which only the report's reflection samples, to the
    // first frame that samples it: the split view's.
    let err = stderr(&o);
    assert!(err.contains("argil: made builtin:noise, which no frame had sampled"), "{err}");
    let (view_w, view_h, left) = view_area(&err);
    let headless = |scene: &Path, name: &str| {
        let out = dir.join(name);
        assert_clean_success(&render_at(scene, &out, (view_w, view_h), &[]));
        image::open(&out).expect("read render").to_rgb8()
    };
    let (as_is, composition) = (headless(&scene, "scene.png"), headless(&report, "report.png"));
    let window = image::open(&shot).expect("read screenshot").to_rgb8();
    let (middle, bottom) = (view_w / 2, view_h - 40);
    let (left_part, right_part) = (0..middle - 3, middle + 3..view_w);
    let left_rmse = region_rmse(&window, left, &as_is, left_part, bottom);
    let right_rmse = region_rmse(&window, left, &composition, right_part.clone(), bottom);
    let right_vs_scene = region_rmse(&window, left, &as_is, right_part, bottom);
    eprintln!(
        "split view: left vs the scene RMSE {left_rmse:.3}, right vs the report {right_rmse:.3}, right vs the \
         scene {right_vs_scene:.3}"
    );
    assert!(left_rmse <= 0.5, "the left part is not the scene: RMSE {left_rmse:.3}");
    assert!(
        right_rmse <= 0.5,
        "the right part is not the report: RMSE {right_rmse:.3}"
    );
    assert!(
        right_vs_scene >= 0.25 && right_vs_scene > 2.0 * right_rmse,
        "{right_vs_scene:.3}"
    );
    let divider = (0..bottom)
        .filter(|&y| {
            (middle.saturating_sub(1)..=middle + 1).any(|x| window.get_pixel(left + x, y).0.iter().all(|&c| c > 200))
        })
        .count();
    assert!(
        divider as u32 > bottom * 9 / 10,
        "no divider: {divider} of {bottom} rows"
    );
}

/// Moves the X pointer (XTest, through ctypes) to `over` every 0.4 s for `seconds`, then to
/// `after` once. Each move waits for the server to process it (`XSync`): with only a flush,
/// the last move was lost in up to 4 runs of 12 under load, as the script exited, and the
/// viewer never saw the pointer leave the panel.
const POINTER_SCRIPT: &str = r#"
import ctypes, sys, time
x11 = ctypes.CDLL("libX11.so.6")
xtst = ctypes.CDLL("libXtst.so.6")
x11.XOpenDisplay.restype = ctypes.c_void_p
display = ctypes.c_void_p(x11.XOpenDisplay(None))
if not display:
    sys.exit("no display")
over_x, over_y, after_x, after_y, seconds = map(float, sys.argv[1:])
def move(x, y):
    xtst.XTestFakeMotionEvent(display, -1, int(x), int(y), 0)
    x11.XSync(display, 0)
end = time.time() + seconds
jiggle = 0
while time.time() < end:
    move(over_x + jiggle, over_y)
    jiggle = 1 - jiggle
    time.sleep(0.4)
move(after_x, after_y)
x11.XCloseDisplay(display)
"#;

/// Slow frames answer the UI quickly: with the pointer over the panel on lavapipe (a full
/// frame of the default scene in a 960×720 view with 4× MSAA takes far more than
/// `SLOW_FRAME_MS`; without MSAA it took 206 ms on 2 cores, and in a 240×300 view 59 ms,
/// below it), the viewer draws the 3D view at reduced resolution, and once the pointer
/// has left the panel for the 3D view it draws a full frame again and idles. The pointer
/// is moved by XTest under Xvfb while the viewer runs.
#[test]
fn slow_frames_are_reduced_while_the_ui_is_in_use() {
    let python = Command::new("python3").arg("--version").output();
    assert!(python.is_ok(), "python3 is missing: the test moves the pointer with it");
    let dir = test_dir("responsive");
    let script = dir.join("pointer.py");
    std::fs::write(&script, POINTER_SCRIPT).expect("write script");
    let scene = dir.join("scene.toml");
    let multisampled = format!("{}\n[antialiasing]\nmsaa = 4\n", argil::scene::DEFAULT_SCENE_TOML);
    std::fs::write(&scene, multisampled).expect("write scene");
    let runtime = test_dir("xvfb-runtime");
    // The window opens at the screen's top left: the panel is x < 320, the view beyond.
    let viewer = format!(
        "{} view --seconds 40 --width 1280 --height 720 {} & viewer=$!; python3 {} 100 150 450 150 25; wait $viewer",
        env!("CARGO_BIN_EXE_argil"),
        path_str(&scene),
        path_str(&script)
    );
    let o = Xvfb::start()
        .command("sh")
        .args(["-c", &viewer])
        .env("XDG_RUNTIME_DIR", &runtime)
        .output()
        .expect("run sh");
    assert_clean_success(&o);
    let err = stderr(&o);
    let line = err
        .lines()
        .find(|l| l.contains("resolution while the UI was in use"))
        .unwrap_or_else(|| panic!("no line on reduced frames in: {err}"));
    eprintln!("{line}");
    let reduced: u64 = line
        .strip_prefix("argil: ")
        .and_then(|l| l.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count in: {line}"));
    assert!(reduced >= 2, "{line}");
    assert!(line.contains("the last frame at 1/1;"), "{line}");
}

/// Nothing changes, nothing is drawn: an idle viewer draws its first frames (egui lays
/// out its grids over a few frames until their columns settle, and opens the panel's
/// sections over 1/12 s, a frame each 10 ms or so once the warm-up frame has compiled the
/// shaders; on a loaded machine the first three took 6.4 s), then waits. Drawing
/// continuously, it draws a frame every 0.01–1 s here (1 s with the whole suite running),
/// so it would draw 15 or more in 15 s and never be idle for 5.
#[test]
fn an_idle_viewer_draws_no_frames() {
    let o = view_under_xvfb(&["--seconds", "15", "--width", "480", "--height", "270"]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let frames: u64 = err
        .split(" frames, ")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no frame count in: {err}"));
    let idle: f64 = err
        .split("; idle ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no idle time in: {err}"));
    eprintln!("{frames} frames in 15 s, idle for the last {idle} s");
    assert!(frames < 15, "{frames} frames in 15 s: {err}");
    assert!(idle >= 5.0, "a frame {idle} s before the end: {err}");
}

/// Resizes to sizes from 1×1 to 1024×640, minimise and restore, while rendering with the
/// validation layer on: no validation message (leaks included), and the swapchain was
/// recreated for the new sizes.
#[test]
fn view_survives_a_resize_storm() {
    let frames = (argil::viewer::RESIZE_STORM_TICKS + 6).to_string();
    let o = view_under_xvfb(&[
        "--frames",
        &frames,
        "--resize-storm",
        "--width",
        "480",
        "--height",
        "270",
    ]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let recreations: u64 = err
        .split(" swapchain recreations")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no recreation count in: {err}"));
    assert!(recreations >= 5, "only {recreations} swapchain recreations: {err}");
}

#[test]
fn view_rejects_bad_arguments_before_opening_a_window() {
    assert_clean_failure(&argil(&["view", "--screenshot", "x.png"]), &["--frames"]);
    assert_clean_failure(&argil(&["view", "--width", "0"]), &["--width"]);
    assert_clean_failure(
        &argil(&["view", "/nonexistent/scene.toml"]),
        &["/nonexistent/scene.toml"],
    );
    let dir = test_dir("view-existing");
    let shot = dir.join("shot.png");
    std::fs::write(&shot, "the user's picture").expect("write");
    let o = argil(&["view", "--frames", "1", "--screenshot", path_str(&shot)]);
    assert_clean_failure(&o, &["shot.png", "already exists", "--overwrite"]);
    assert_eq!(std::fs::read(&shot).expect("read"), b"the user's picture");
}

/// The scene the reload test edits on disk.
const RELOADED_SCENE: &str = r#"
[camera]
position = [0.0, 1.6, 7.5]
target = [0.2, -0.35, 0.0]

[[lights]]
kind = "point"
position = [-3.0, 4.0, 4.0]
intensity = [32.0, 30.0, 27.0]

[[objects]]
mesh = "builtin:sphere"
material = "terracotta"

[materials.terracotta]
base_color = [0.6, 0.22, 0.1]
diffuse = "oren-nayar"
diffuse_roughness = 0.5
roughness = 0.7
"#;

/// `argil render` of `scene` into `out` at `size`, with `more` arguments.
fn render_at(scene: &Path, out: &Path, size: (u32, u32), more: &[&str]) -> Output {
    let (width, height) = (size.0.to_string(), size.1.to_string());
    let mut args = vec!["render", path_str(scene), "--out", path_str(out)];
    args.extend(["--width", &width, "--height", &height]);
    args.extend(more);
    argil(&args)
}

/// A viewer under Xvfb on a scene file, open `seconds` after its first frame in a 480×270
/// window and then writing its screenshot, its stderr read line by line as it runs. A time,
/// not a count of frames: with Mesa's shader cache warm, lavapipe draws 80 frames of this
/// window in well under the two polls of the file watch a test waits for.
struct WatchedView {
    child: std::process::Child,
    lines: Box<dyn Iterator<Item = String>>,
    log: String,
    shot: std::path::PathBuf,
    _runtime: argil::scratch::Scratch,
    _xvfb: Xvfb,
}

impl WatchedView {
    fn start(scene: &Path, seconds: f64) -> Self {
        use std::io::{BufRead, BufReader};
        use std::process::Stdio;
        let shot = scene.with_file_name("window.png");
        let runtime = test_dir("xvfb-runtime");
        let seconds = seconds.to_string();
        let xvfb = Xvfb::start();
        let mut child = xvfb
            .view()
            .args(["--seconds", &seconds, "--width", "480", "--height", "270"])
            .args(["--screenshot", path_str(&shot), path_str(scene)])
            .env("XDG_RUNTIME_DIR", &runtime)
            .stderr(Stdio::piped())
            .spawn()
            .expect("run argil view");
        let lines = BufReader::new(child.stderr.take().expect("stderr")).lines().map_while(Result::ok);
        Self {
            child,
            lines: Box::new(lines),
            log: String::new(),
            shot,
            _runtime: runtime,
            _xvfb: xvfb,
        }
    }

    /// Reads the viewer's stderr up to a line containing `what`.
    fn wait_for(&mut self, what: &str) {
        for line in self.lines.by_ref() {
            self.log.push_str(&line);
            self.log.push('\n');
            if line.contains(what) {
                return;
            }
        }
        panic!("argil never printed {what:?}: {}", self.log);
    }

    /// Waits for the viewer to close cleanly, with no validation message, and checks that
    /// its last frame's view is exactly `argil render` of the scene file `expected`.
    fn assert_shows(mut self, expected: &Path) {
        self.wait_for("argil: wrote");
        // Leaks are reported after the last line of the run, when the device is destroyed.
        self.log.extend(self.lines.map(|l| l + "\n"));
        let status = self.child.wait().expect("wait for argil");
        assert!(status.success() && !self.log.contains("vulkan validation"), "{}", self.log);
        let (w, h, left) = view_area(&self.log);
        let headless = expected.with_file_name("headless.png");
        assert_clean_success(&render_at(expected, &headless, (w, h), &[]));
        let window = image::open(&self.shot).expect("read screenshot").to_rgb8();
        let reference = image::open(&headless).expect("read render").to_rgb8();
        let differing = (0..w)
            .flat_map(|x| (0..h).map(move |y| (x, y)))
            .filter(|&(x, y)| window.get_pixel(left + x, y) != reference.get_pixel(x, y))
            .count();
        assert_eq!(differing, 0, "the window does not show {}", expected.display());
    }
}

/// Ctrl-C in the terminal closes the viewer as its last frame would (its summary printed,
/// the device destroyed without a validation message), with exit code 130.
#[test]
fn ctrl_c_closes_the_viewer_with_code_130() {
    let dir = test_dir("ctrl-c");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, RELOADED_SCENE).expect("write scene");
    let mut view = WatchedView::start(&scene, 300.0);
    // Printed once the window opens, after the handler is in place.
    view.wait_for("rendering on");
    let kill = Command::new("kill")
        .args(["-INT", &view.child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(kill.success(), "kill -INT");
    view.log.extend(view.lines.by_ref().map(|l| l + "\n"));
    let status = view.child.wait().expect("wait for argil");
    assert_eq!(status.code(), Some(130), "{}", view.log);
    assert!(view.log.contains("interrupted (Ctrl-C") && view.log.contains(" frames, "), "{}", view.log);
    assert!(!view.log.contains("vulkan validation"), "{}", view.log);
    assert!(!dir.join("scene.recovered.toml").exists(), "nothing to recover");
}

/// `argil render` with `args` and the validation layer on, sent SIGINT `after` it starts;
/// its output once it ends.
fn interrupted_render(args: &[&str], after: std::time::Duration) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_argil"))
        .arg("render")
        .args(args)
        .env("ARGIL_VALIDATION", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run argil");
    std::thread::sleep(after);
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(kill.success(), "kill -INT");
    // Unheard, the signal would leave the frames to draw: the run would end with code 0,
    // or be stopped at HANG, and fail either way.
    common::wait(child, &format!("argil render {} after SIGINT", args.join(" ")))
}

/// Ctrl-C in `argil render --accumulate N` ends it after the frame being drawn: the EXR
/// holds the mean of the K frames drawn (its `argil.frames`), exactly what `--accumulate K`
/// writes, and the exit code is 130.
#[test]
fn ctrl_c_in_an_accumulating_render_writes_the_frames_drawn() {
    let dir = test_dir("render-ctrl-c");
    let scene = dir.join("sphere.toml");
    std::fs::write(&scene, sampled_sphere_toml(16)).expect("write scene");
    let (out, again) = (dir.join("interrupted.exr"), dir.join("again.exr"));
    let args = [path_str(&scene), "--out", path_str(&out), "--width", "48", "--height", "32"];
    let args = [&args[..], &["--accumulate", "65536"]].concat();
    let mut after = std::time::Duration::from_secs(3);
    let o = loop {
        let o = interrupted_render(&args, after);
        // On a machine slow enough for the signal to come during the start, nothing is
        // written (the next test): send it later.
        if stderr(&o).contains("before the first frame") && after.as_secs() < 24 {
            after *= 2;
            continue;
        }
        break o;
    };
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("of 65536 frames") && err.contains("holds their mean"), "{err}");
    assert!(!err.contains("vulkan validation"), "{err}");
    let read = |path: &Path| {
        exr::prelude::read_first_rgba_layer_from_file(
            path,
            |resolution, _| vec![[0f32; 4]; resolution.area()],
            |pixels: &mut Vec<[f32; 4]>, position, (r, g, b, a): (f32, f32, f32, f32)| {
                pixels[position.y() * 48 + position.x()] = [r, g, b, a];
            },
        )
        .expect("read the EXR")
        .layer_data
    };
    let interrupted = read(&out);
    let frames = match interrupted.attributes.other.get(&exr::prelude::Text::from("argil.frames")) {
        Some(exr::prelude::AttributeValue::Text(t)) => t.to_string(),
        other => panic!("argil.frames: {other:?}"),
    };
    let count: u32 = frames.parse().expect("a count");
    assert!((1..65536).contains(&count), "{count} frames");
    assert_clean_success(&render_at(&scene, &again, (48, 32), &["--accumulate", &frames]));
    let pixels = |layer: &exr::prelude::Layer<exr::prelude::SpecificChannels<Vec<[f32; 4]>, _>>| {
        layer.channel_data.pixels.clone()
    };
    assert!(pixels(&interrupted) == pixels(&read(&again)), "not the mean of {count} frames");
}

/// Ctrl-C during an accumulating render's start (here the loading of a ring of 2048 cells,
/// which takes seconds) ends it after the step under way: no frame is drawn, nothing is
/// written, exit code 130.
#[test]
fn ctrl_c_during_an_accumulating_renders_start_writes_nothing() {
    let dir = test_dir("render-ctrl-c-start");
    let scene = dir.join("ring.toml");
    let ring = "[[objects]]\nmesh = \"builtin:torus\"\nsubdivisions = 2048\nmaterial = \"clay\"\n\n\
                [materials.clay]\npreset = \"plasticine\"\n";
    std::fs::write(&scene, ring).expect("write scene");
    let (out, timings) = (dir.join("never.exr"), dir.join("timings.json"));
    let args = [path_str(&scene), "--out", path_str(&out), "--width", "48", "--height", "32"];
    let args = [&args[..], &["--accumulate", "4", "--timings", path_str(&timings)]].concat();
    let o = interrupted_render(&args, std::time::Duration::from_secs(1));
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("before the first frame: nothing written"), "{err}");
    assert!(!err.contains("vulkan validation"), "{err}");
    assert!(!out.exists() && !timings.exists(), "nothing written");
}

/// The scene file is reloaded when it changes on disk: a broken edit is reported and the
/// last good scene stays on screen; the next good edit is shown, with the camera kept.
#[test]
fn view_reloads_the_scene_when_its_file_changes() {
    let dir = test_dir("reload");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, RELOADED_SCENE).expect("write scene");
    let mut view = WatchedView::start(&scene, 4.0);
    view.wait_for("rendering on");
    let good = RELOADED_SCENE.replace("base_color = [0.6, 0.22, 0.1]", "base_color = [0.1, 0.5, 0.2]");
    std::fs::write(&scene, good.replace("roughness = 0.7", "roughness = 7.0")).expect("write a broken scene");
    view.wait_for("materials.terracotta.roughness = 7.0");
    // The file's camera moves too: the edit is applied.
    let good = good.replace("position = [0.0, 1.6, 7.5]", "position = [3.0, 3.0, 3.0]");
    std::fs::write(&scene, &good).expect("write");
    view.wait_for("argil: reloaded");
    let expected = dir.join("expected.toml");
    std::fs::write(&expected, &good).expect("write");
    view.assert_shows(&expected);
}

/// A file the scene reads (a texture, the environment map) is read again when it changes
/// on disk: one that no longer loads is reported and the last good scene stays on screen;
/// the next good version is shown.
#[test]
fn view_reads_a_file_of_the_scene_again_when_it_changes() {
    let dir = test_dir("inputs");
    let texture = dir.join("colour.png");
    let colour = |rgb| {
        image::RgbImage::from_pixel(2, 2, image::Rgb(rgb))
            .save(&texture)
            .expect("write texture")
    };
    let map = dir.join("sky.hdr");
    let sky = |rgb| {
        image::Rgb32FImage::from_pixel(16, 8, image::Rgb(rgb))
            .save(&map)
            .expect("write map")
    };
    colour([200, 60, 30]);
    sky([1.0, 1.0, 1.0]);
    let text = format!(
        "{RELOADED_SCENE}\n[materials.terracotta.base_color_map]\ntexture = \"colour.png\"\n\n\
         [environment]\nkind = \"map\"\npath = \"sky.hdr\"\n"
    );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, &text).expect("write scene");
    let mut view = WatchedView::start(&scene, 5.0);
    view.wait_for("rendering on");
    std::fs::write(&texture, "not an image").expect("write a broken texture");
    view.wait_for("colour.png");
    colour([30, 60, 200]);
    view.wait_for("colour.png again");
    sky([0.2, 0.4, 1.0]);
    view.wait_for("sky.hdr again");
    view.assert_shows(&scene);
}

/// Frames and lookups per pixel of the last view's running mean, from the viewer's closing
/// line "the last view's mean has K frames × N lookups".
fn accumulated_frames(err: &str) -> (u32, u32) {
    let numbers = err.split("the last view's mean has ").nth(1).and_then(|rest| {
        let mut words = rest.split_whitespace();
        let frames = words.next()?.parse().ok()?;
        let lookups = words.nth(2)?.parse().ok()?;
        Some((frames, lookups))
    });
    numbers.unwrap_or_else(|| panic!("no accumulation in: {err}"))
}

/// A still view of the sampled reflection refines: the window shows the running mean of
/// the frames drawn, exactly what `argil render --accumulate K` writes for the same K, and
/// once the mean has 1024 lookups per pixel (8 frames of 128) later frames hold it.
/// Threshold as for the split-sum screenshot: both sides compute the same fp32 mean.
#[test]
fn view_shows_the_accumulated_mean_of_a_still_sampled_view() {
    let dir = test_dir("accumulate");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, sampled_sphere_toml(128)).expect("write scene");
    let shot = dir.join("window.png");
    let o = view_under_xvfb(&[
        "--frames",
        "14",
        "--screenshot",
        path_str(&shot),
        path_str(&scene),
        "--width",
        "480",
        "--height",
        "270",
    ]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let (view_w, view_h, left) = view_area(&err);
    let (frames, lookups) = accumulated_frames(&err);
    assert_eq!(lookups, 128);
    assert!((2..=8).contains(&frames), "{frames} frames in the mean: {err}");
    let headless = dir.join("headless.png");
    let accumulate = frames.to_string();
    assert_clean_success(&render_at(&scene, &headless, (view_w, view_h), &["--accumulate", &accumulate]));
    let single = dir.join("single.png");
    assert_clean_success(&render_at(&scene, &single, (view_w, view_h), &[]));
    let window = image::open(&shot).expect("read screenshot").to_rgb8();
    let (to_mean, to_single) = (view_rmse(&window, left, &headless), view_rmse(&window, left, &single));
    eprintln!(
        "window ({frames} frames) vs render --accumulate {frames}: RMSE {to_mean:.3}; vs one frame {to_single:.3}"
    );
    assert!(to_mean <= 0.5, "the window shows another frame: RMSE {to_mean:.3}");
    assert!(to_single > to_mean, "the window shows the single frame");
}

/// The viewer keeps drawing while a still sampled view refines, up to 1024 lookups per
/// pixel (4 frames of 256 here), then goes idle.
#[test]
fn a_refining_viewer_draws_until_converged_then_idles() {
    let dir = test_dir("converge");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, sampled_sphere_toml(256)).expect("write scene");
    let o = view_under_xvfb(&["--seconds", "20", path_str(&scene), "--width", "320", "--height", "200"]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let (frames, lookups) = accumulated_frames(&err);
    let idle: f64 = err
        .split("; idle ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no idle time in: {err}"));
    eprintln!("mean of {frames} frames × {lookups} lookups, idle for the last {idle} s");
    assert_eq!(
        u64::from(frames * lookups),
        argil::render::accumulate::CONVERGED_LOOKUPS,
        "{err}"
    );
    assert!(idle >= 3.0, "a frame {idle} s before the end: {err}");
}

/// The number after "exposure in use " in the viewer's closing lines, and its source.
fn exposure_in_use(err: &str) -> (f32, String) {
    let found = err.split("exposure in use ").nth(1).and_then(|rest| {
        let mut words = rest.split_whitespace();
        Some((words.next()?.parse().ok()?, words.next()?.to_owned()))
    });
    found.unwrap_or_else(|| panic!("no exposure in: {err}"))
}

/// The specular lobe alone is nearly black at exposure 1; the viewer auto-exposes it from
/// its measured luminance, and the window shows the lobe at that exposure exactly as the
/// renderer draws it (threshold as for the shaded screenshot).
#[test]
fn view_auto_exposes_the_specular_lobe() {
    let dir = test_dir("auto-exposure");
    let shot = dir.join("window.png");
    let o = view_under_xvfb(&[
        "--debug-view",
        "specular",
        "--frames",
        "6",
        "--screenshot",
        path_str(&shot),
        "--width",
        "480",
        "--height",
        "270",
    ]);
    assert_clean_success(&o);
    let err = stderr(&o);
    let (exposure, source) = exposure_in_use(&err);
    assert_eq!(source, "(auto)", "{err}");
    assert!(exposure > 2.0, "auto exposure {exposure} for the specular lobe");
    let (view_w, view_h, left) = view_area(&err);
    let scene = argil::scene::Scene::default_scene();
    let frame = gpu().exclusive(|renderer| {
        renderer.debug_view = argil::render::DebugView::Specular;
        let gpu_scene = renderer.upload(&scene).expect("upload");
        let extent = ash::vk::Extent2D {
            width: view_w,
            height: view_h,
        };
        let frame = renderer.render_offscreen(&scene, &gpu_scene, extent, exposure);
        renderer.debug_view = argil::render::DebugView::Shaded;
        frame.expect("render")
    });
    let headless = dir.join("headless.png");
    image::RgbaImage::from_raw(view_w, view_h, frame.display)
        .expect("frame size")
        .save(&headless)
        .expect("write png");
    let window = image::open(&shot).expect("read screenshot").to_rgb8();
    let rmse = view_rmse(&window, left, &headless);
    eprintln!("specular lobe at auto exposure {exposure}: window vs renderer RMSE {rmse:.3}");
    assert!(rmse <= 0.5, "the window shows another exposure: RMSE {rmse:.3}");
}

/// The curvature view has its legend over the view's bottom-left corner: a bar from
/// strong blue (concave) to strong red (convex), in the colours the view itself uses. The
/// screenshot is taken a second in, once egui has faded the legend in (over 1/12 s, a
/// handful of frames).
#[test]
fn view_shows_the_curvature_legend() {
    let dir = test_dir("legend");
    let shot = dir.join("window.png");
    let (w, h) = (800u32, 400u32);
    let (width, height) = (w.to_string(), h.to_string());
    let o = view_under_xvfb(&[
        "--debug-view",
        "curvature",
        "--seconds",
        "1",
        "--screenshot",
        path_str(&shot),
        "--width",
        &width,
        "--height",
        &height,
    ]);
    assert_clean_success(&o);
    let (_, _, left) = view_area(&stderr(&o));
    let window = image::open(&shot).expect("read screenshot").to_rgb8();
    let legend: std::collections::HashSet<[u8; 3]> = (-70..=70)
        .map(|i| argil::viewer::curvature_legend_color(f64::from(i) / 10.0, 1.0).to_array())
        .map(|[r, g, b, _]| [r, g, b])
        .collect();
    let corner = (left + 10..left + 310).flat_map(|x| (h - 70..h - 10).map(move |y| (x, y)));
    let (mut red, mut blue) = (0, 0);
    for (x, y) in corner {
        let p = window.get_pixel(x, y).0;
        red += usize::from(p[0] > 150 && p[1] == 0 && p[2] == 0 && legend.contains(&p));
        blue += usize::from(p[2] > 150 && p[0] == 0 && p[1] == 0 && legend.contains(&p));
    }
    assert!(red > 200 && blue > 200, "legend pixels: {red} red, {blue} blue");
}
