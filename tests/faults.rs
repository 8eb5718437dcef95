//! Failures of the machine, injected with `ARGIL_FAULT` (src/fault.rs), in each command
//! that drives the GPU: a failed allocation, a failed submission and a lost device end
//! `render`, `verify` and `view` with a clear message and exit code 1, within the time
//! limit of `common::run` (never a hang), with nothing written and no validation message.
//! The counts land in different phases: the first allocation or submission, the uploads,
//! and (for the viewer) the frame loop after the first frames.

mod common;

use std::process::Output;

use common::{argil_with, run, test_dir, Xvfb};

fn assert_machine_failure(o: &Output, fault: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "ARGIL_FAULT={fault}: exit code: {err}");
    assert!(!err.contains("panicked"), "ARGIL_FAULT={fault}: panicked: {err}");
    assert!(
        !err.contains("vulkan validation"),
        "ARGIL_FAULT={fault}: validation messages: {err}"
    );
    let advice = if fault.starts_with("device-lost") {
        "device was lost"
    } else {
        "ran out of memory"
    };
    assert!(err.contains(advice), "ARGIL_FAULT={fault}: no {advice:?}: {err}");
}


#[test]
fn render_fails_cleanly() {
    let dir = test_dir("render");
    let out = dir.join("frame.exr");
    let out = out.to_str().expect("utf-8");
    for fault in [
        "alloc:1",
        "alloc:12",
        "submit:1",
        "submit:4",
        "device-lost:1",
        "device-lost:6",
    ] {
        let o = argil_with(
            &["render", "--out", out, "--width", "64", "--height", "36"],
            &[("ARGIL_FAULT", fault)],
        );
        assert_machine_failure(&o, fault);
        assert!(!std::path::Path::new(out).exists(), "ARGIL_FAULT={fault}: wrote {out}");
    }
}

#[test]
fn verify_fails_cleanly() {
    let dir = test_dir("verify");
    let json = dir.join("verify.json");
    let json = json.to_str().expect("utf-8");
    for fault in ["alloc:3", "submit:2", "device-lost:5"] {
        let o = argil_with(
            &["verify", "--samples", "1000", "--json", json],
            &[("ARGIL_FAULT", fault)],
        );
        assert_machine_failure(&o, fault);
        assert!(
            !std::path::Path::new(json).exists(),
            "ARGIL_FAULT={fault}: wrote {json}"
        );
    }
}

/// A swapchain taken away (out of date) at the 5th present: the viewer recreates it and
/// finishes its frames; the window is never resized, so the recreation is the fault's.
#[test]
fn view_recovers_from_a_lost_swapchain() {
    let xvfb = Xvfb::start();
    let mut command = xvfb.view();
    command
        .args(["--frames", "20", "--width", "320", "--height", "200"])
        .env("ARGIL_FAULT", "present:5");
    let o = run(command);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("vulkan validation"), "validation messages: {err}");
    assert!(err.contains("20 frames, 1 swapchain recreations"), "{err}");
}

/// Under Xvfb; 30 and more submissions and 40 allocations are past the scene's upload,
/// in the frame loop.
#[test]
fn view_fails_cleanly() {
    for fault in ["alloc:2", "alloc:40", "submit:30", "device-lost:30", "device-lost:45"] {
        let xvfb = Xvfb::start();
        let mut command = xvfb.view();
        command
            .args(["--frames", "60", "--width", "320", "--height", "200"])
            .env("ARGIL_FAULT", fault);
        assert_machine_failure(&run(command), fault);
    }
}

/// A device lost while the scene has a change not saved (the soak's edit of the material
/// from frame 100 to 199) leaves the change in a file beside the scene's, named in the
/// error; lost before the edit, it leaves none; a panic (`ARGIL_FAULT=panic:N`) leaves it
/// too. The scene file keeps its text.
#[test]
fn view_keeps_the_changes_not_saved_when_the_device_is_lost() {
    let dir = test_dir("recover");
    let scene = dir.join("clay.toml");
    let text = "[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"clay\"\n\n[materials.clay]\nroughness = 0.5\n";
    std::fs::write(&scene, text).expect("write the scene");
    let recovered = dir.join("clay.recovered.toml");
    for (fault, edited) in [("device-lost:60", false), ("device-lost:170", true)] {
        let xvfb = Xvfb::start();
        let mut command = xvfb.view();
        command
            .arg(&scene)
            .args(["--frames", "400", "--width", "640", "--height", "200", "--soak-log"])
            .arg(dir.join(format!("soak-{fault}.json")))
            .env("ARGIL_FAULT", fault);
        let o = run(command);
        assert_machine_failure(&o, fault);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.contains("changes not saved are in"), edited, "ARGIL_FAULT={fault}: {err}");
        assert_eq!(recovered.exists(), edited, "ARGIL_FAULT={fault}: {}", recovered.display());
    }
    let written = std::fs::read_to_string(&recovered).expect("read the recovered scene");
    assert!(written.contains("diffuse = "), "the soak's edit: {written}");
    assert_eq!(std::fs::read_to_string(&scene).expect("read the scene"), text);

    // A bug's panic keeps them too, in the next free name.
    let xvfb = Xvfb::start();
    let mut command = xvfb.view();
    command
        .arg(&scene)
        .args(["--frames", "400", "--width", "640", "--height", "200", "--soak-log"])
        .arg(dir.join("soak-panic.json"))
        .env("ARGIL_FAULT", "panic:170");
    let o = run(command);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(101), "a panic's exit code: {err}");
    assert!(err.contains("panicked") && err.contains("changes not saved are in"), "{err}");
    assert!(!err.contains("vulkan validation"), "validation messages: {err}");
    let again = std::fs::read_to_string(dir.join("clay.recovered-2.toml")).expect("read the second recovered scene");
    assert!(again.contains("diffuse = "), "the soak's edit: {again}");
    assert_eq!(std::fs::read_to_string(&recovered).expect("read the first"), written, "the first is kept");
}
