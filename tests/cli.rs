//! The `argil` command as a user meets it: help, devices, rendering to files, bad input,
//! and the window under Xvfb. Every run has the validation layer on and must print no
//! validation message (leaked handles are reported when the device is destroyed).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn argil(args: &[&str]) -> Output {
    let runtime = std::env::temp_dir().join(format!("argil-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    Command::new(env!("CARGO_BIN_EXE_argil"))
        .args(args)
        .env("ARGIL_VALIDATION", "1")
        .env("XDG_RUNTIME_DIR", &runtime)
        .output()
        .expect("run argil")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_clean_success(o: &Output) {
    let err = stderr(o);
    assert!(o.status.success(), "argil failed: {err}");
    assert!(!err.contains("vulkan validation"), "validation messages: {err}");
}

fn assert_clean_failure(o: &Output, mentions: &[&str]) {
    let err = stderr(o);
    assert!(!o.status.success(), "argil succeeded on bad input");
    assert!(!err.contains("panicked"), "argil panicked: {err}");
    for m in mentions {
        assert!(err.contains(m), "error does not mention {m:?}: {err}");
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("argil-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
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
    let dir = temp_dir("exr");
    let scene = dir.join("sphere.toml");
    std::fs::write(&scene, SPHERE).expect("write scene");
    for exposure in ["1", "4"] {
        let out = dir.join(format!("sphere-{exposure}.exr"));
        let o = argil(&["render", path_str(&scene), "--out", path_str(&out), "--width", "63", "--height", "63", "--exposure", exposure]);
        assert_clean_success(&o);
        let image = image::open(&out).expect("read exr").into_rgba32f();
        let centre = image.get_pixel(31, 31);
        let expected = 40.0 / 16.0 / std::f32::consts::PI;
        for c in 0..3 {
            assert!((centre[c] - expected).abs() < 1e-3 * expected, "centre {centre:?} vs {expected}");
        }
    }
    let png = dir.join("sphere.png");
    assert_clean_success(&argil(&["render", path_str(&scene), "--out", path_str(&png), "--width", "64", "--height", "48"]));
    let image = image::open(&png).expect("read png").into_rgb8();
    assert_eq!(image.dimensions(), (64, 48));
}

#[test]
fn render_without_scene_renders_the_default_scene() {
    let out = temp_dir("default").join("clay.png");
    let o = argil(&["render", "--out", path_str(&out), "--width", "96", "--height", "54"]);
    assert_clean_success(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("clay.png"), "prints the path it wrote");
    assert!(out.is_file());
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = temp_dir("bad");
    let unknown_key = dir.join("unknown.toml");
    std::fs::write(&unknown_key, SPHERE.replace("fov_y_degrees", "fov_degrees")).expect("write");
    let out = dir.join("x.png");
    let out = path_str(&out);
    assert_clean_failure(&argil(&["render", path_str(&unknown_key), "--out", out]), &["unknown.toml", "fov_degrees"]);

    let nan = dir.join("nan.toml");
    std::fs::write(&nan, SPHERE.replace("base_color = [1.0, 1.0, 1.0]", "base_color = [nan, 1.0, 1.0]")).expect("write");
    assert_clean_failure(&argil(&["render", path_str(&nan), "--out", out]), &["nan.toml", "base_color"]);

    let obj = dir.join("broken.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").expect("write");
    let broken_mesh = dir.join("broken-mesh.toml");
    std::fs::write(&broken_mesh, SPHERE.replace("builtin:sphere", "broken.obj")).expect("write");
    assert_clean_failure(&argil(&["render", path_str(&broken_mesh), "--out", out]), &["broken.obj"]);

    assert_clean_failure(&argil(&["render", "/nonexistent/scene.toml", "--out", out]), &["/nonexistent/scene.toml"]);
    assert_clean_failure(&argil(&["render", "--out", out, "--width", "0"]), &["0x720"]);
    assert_clean_failure(&argil(&["render", "--out", out, "--width", "100000", "--height", "100000"]), &["100000x100000"]);
    assert_clean_failure(&argil(&["render", "--out", out, "--exposure", "nan"]), &["--exposure"]);
    assert_clean_failure(&argil(&["render", "--out", path_str(&dir.join("x.bmp"))]), &["x.bmp", ".png", ".exr"]);
    assert_clean_failure(&argil(&["--device", "no-such-gpu", "devices-typo"]), &[]);
    assert_clean_failure(&argil(&["--device", "no-such-gpu", "render", "--out", out]), &["no-such-gpu"]);
}

/// The window path: a real X server (Xvfb), a swapchain, a few frames, a clean exit.
#[test]
fn view_opens_a_window_under_xvfb() {
    let status = Command::new("xvfb-run").arg("--help").output();
    assert!(status.is_ok(), "xvfb-run is missing: `make setup` installs it");
    let runtime = temp_dir("xvfb-runtime");
    let o = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", env!("CARGO_BIN_EXE_argil"), "view", "--frames", "5"])
        .env("ARGIL_VALIDATION", "1")
        .env("XDG_RUNTIME_DIR", &runtime)
        .output()
        .expect("run xvfb-run");
    assert_clean_success(&o);
}
