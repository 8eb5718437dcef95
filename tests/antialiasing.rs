//! Anti-aliasing (src/render/msaa.rs, shaders/lib/msaa_resolve.glsl, specular_aa.glsl): on
//! lavapipe with the validation layer on (synchronization validation included), every
//! frame charged to its test.

mod common;

use argil::brdf::antialiasing::resolve;
use argil::render::msaa::supported_samples;
use argil::scene::Scene;
use common::{argil, assert_matches_golden, gpu, render, scene};

/// `text` with an `[antialiasing]` section.
fn with_antialiasing(text: &str, msaa: u32, specular: bool) -> Scene {
    scene(&format!(
        "{text}\n[antialiasing]\nmsaa = {msaa}\nspecular = {specular}\n"
    ))
}

/// Without anti-aliasing the default scene is drawn with one sample and no roughness
/// widening: the golden `default-scene-no-antialiasing.png`, compared with the goldens'
/// tolerance (tests/common/mod.rs).
#[test]
fn without_antialiasing_the_frame_is_the_one_from_before() {
    let mut scene = Scene::default_scene();
    scene.antialiasing.msaa = 1;
    scene.antialiasing.specular = false;
    let frame = render(&scene, 320, 180);
    assert_matches_golden(&frame, "default-scene-no-antialiasing");
    gpu().exclusive(|renderer| assert_eq!(renderer.msaa_samples(&scene), 1));
}

/// The default scene with 4× MSAA and specular anti-aliasing: the resolve, its pipelines
/// and barriers in a golden frame (4 samples, which every Vulkan device supports). Its
/// silhouettes differ from the one-sample frame by RMSE 3.5 (up to 113/255 in a pixel),
/// beyond the goldens' tolerance of 1, so a resolve that lost the samples would fail.
#[test]
fn default_scene_with_msaa_matches_golden() {
    let mut scene = Scene::default_scene();
    scene.antialiasing.msaa = 4;
    let frame = render(&scene, 320, 180);
    gpu().exclusive(|renderer| assert_eq!(renderer.msaa_samples(&scene), 4));
    assert_matches_golden(&frame, "default-scene-msaa-4");
}

/// A black sphere in front of a white (luma 1) uniform background, seen head-on.
const BLACK_ON_WHITE: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[environment]
kind = "uniform"
radiance = [1.0, 1.0, 1.0]

[[objects]]
mesh = "builtin:sphere"
material = "black"

[materials.black]
base_color = [0.0, 0.0, 0.0]
diffuse = "lambert"
specular = "none"
subsurface = "none"
"#;

/// At 4 samples (which every Vulkan device supports), each pixel of a black object on a
/// white background holds what the weighted resolve of its samples gives: alpha is the
/// coverage k/4 (a plain mean), and the radiance the f64 twin's resolve of k black and
/// 4 − k white samples, so the silhouette's pixels hold intermediate values. The image
/// never comes out brighter than the box filter of its samples (the plain mean, 1 − k/4),
/// and is darker by at most the twin's worst case per edge pixel. The coverage agrees with
/// the single-sampled frame's: the 1× frame samples each edge pixel once, an error of
/// standard deviation ≤ 1/2 per edge pixel, so the means may differ by 4σ = 2√E/N.
#[test]
fn msaa_edges_hold_the_weighted_resolve_of_their_coverage_without_brightening() {
    let (width, height) = (96, 64);
    let single = render(&with_antialiasing(BLACK_ON_WHITE, 1, false), width, height);
    let multi = render(&with_antialiasing(BLACK_ON_WHITE, 4, false), width, height);
    let pixels = |hdr: &[f32]| {
        hdr.chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect::<Vec<_>>()
    };
    let (single, multi) = (pixels(&single.hdr), pixels(&multi.hdr));
    for p in &single {
        assert!(
            *p == [0.0, 0.0, 0.0, 1.0] || *p == [1.0, 1.0, 1.0, 0.0],
            "a 1x pixel is neither object nor background: {p:?}"
        );
    }
    let (mut edge, mut sum, mut box_sum, mut coverage) = (0usize, 0.0f64, 0.0f64, 0.0f64);
    let mut worst_darkening = 0.0f64;
    for p in &multi {
        let k = f64::from(p[3]) * 4.0;
        assert!((k - k.round()).abs() < 1e-6, "coverage {} is not k/4", p[3]);
        let k = k.round() as usize;
        let samples: Vec<[f64; 3]> = (0..4).map(|i| if i < k { [0.0; 3] } else { [1.0; 3] }).collect();
        let expected = resolve(&samples)[0];
        for c in &p[..3] {
            assert!(
                (f64::from(*c) - expected).abs() < 1e-6,
                "{p:?}: expected {expected} at coverage {k}/4"
            );
        }
        let box_filtered = 1.0 - k as f64 / 4.0;
        worst_darkening = worst_darkening.max(box_filtered - expected);
        edge += usize::from(k != 0 && k != 4);
        sum += f64::from(p[0]);
        box_sum += box_filtered;
        coverage += f64::from(p[3]);
    }
    let n = multi.len() as f64;
    assert!(edge >= 50, "only {edge} pixels hold intermediate values");
    let (mean, box_mean) = (sum / n, box_sum / n);
    assert!(
        mean <= box_mean + 1e-7,
        "the resolve brightened: {mean} > box {box_mean}"
    );
    let bound = worst_darkening * edge as f64 / n;
    assert!(
        box_mean - mean <= bound + 1e-7,
        "darker than the twin allows: {} > {bound}",
        box_mean - mean
    );
    let single_coverage: f64 = single.iter().map(|p| f64::from(p[3])).sum();
    let tolerance = 2.0 * (edge as f64).sqrt();
    assert!(
        (coverage - single_coverage).abs() <= tolerance,
        "coverage {coverage} at 4x, {single_coverage} at 1x (tolerance {tolerance:.1} pixels)"
    );
    eprintln!("{edge} edge pixels; mean {mean:.5}, box {box_mean:.5}; coverage {coverage:.1} vs {single_coverage}");
}

/// The skybox is drawn into the multisampled target too, and resolved (validation checks
/// the passes' barriers); the studio's frame is close to the single-sampled one except at
/// the silhouettes.
#[test]
fn msaa_with_a_skybox_renders_and_resolves() {
    let text = r#"
[camera]
position = [0.0, 0.5, 4.0]
target = [0.0, 0.0, 0.0]

[environment]
kind = "studio"

[[objects]]
mesh = "builtin:sphere"
material = "clay"

[materials.clay]
preset = "plasticine"
"#;
    let single = render(&with_antialiasing(text, 1, true), 96, 64);
    let multi = render(&with_antialiasing(text, 4, true), 96, 64);
    let (rmse, _) = common::rgb_difference(&single.display, &multi.display);
    assert!(rmse > 0.0, "4x MSAA changed nothing");
    assert!(rmse < 12.0, "4x MSAA changed more than the edges: RMSE {rmse}");
    // A pixel of the skybox alone: four equal samples resolve to themselves.
    for (a, b) in single.hdr[..4].iter().zip(&multi.hdr[..4]) {
        assert!(
            (a - b).abs() <= 1e-6 * a.abs().max(1.0),
            "a corner pixel of the skybox moved: {a} → {b}"
        );
    }
}

/// A count the device does not draw is drawn with the largest it does below it.
#[test]
fn unsupported_counts_fall_back_to_the_largest_supported_below() {
    let device = &gpu().device;
    for requested in [1, 2, 4, 8] {
        let used = supported_samples(device, requested);
        assert!(used <= requested && used.is_power_of_two());
        let flag = argil::render::msaa::sample_flag(used);
        assert!(device.limits.framebuffer_color_sample_counts.contains(flag));
    }
    assert_eq!(supported_samples(device, 4), 4, "Vulkan requires 4 samples");
}

/// Specular anti-aliasing widens lobes only where the shading normal turns: a flat ground
/// without maps renders bit for bit as without it, the normal-mapped plasticine does not.
#[test]
fn specular_aa_changes_only_surfaces_whose_normal_turns() {
    let flat = r#"
[camera]
position = [0.0, 2.0, 3.0]
target = [0.0, 0.0, 0.0]

[[lights]]
kind = "point"
position = [0.0, 3.0, -1.0]
intensity = [20.0, 20.0, 20.0]

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "glossy"

[materials.glossy]
base_color = [0.5, 0.5, 0.5]
roughness = 0.2
"#;
    let hdr = |text: &str, specular: bool| render(&with_antialiasing(text, 1, specular), 96, 64).hdr;
    let (on, off) = (hdr(flat, true), hdr(flat, false));
    let differing = on.iter().zip(&off).filter(|(a, b)| a.to_bits() != b.to_bits()).count();
    assert_eq!(differing, 0, "a flat plane changed in {differing} channels");
    let default = argil::scene::DEFAULT_SCENE_TOML;
    let (on, off) = (hdr(default, true), hdr(default, false));
    let differing = on.iter().zip(&off).filter(|(a, b)| a != b).count();
    assert!(
        differing > 100,
        "specular anti-aliasing changed only {differing} channels"
    );
}

/// Specular anti-aliasing widens the lobe that gathers the light over a pixel's normals,
/// not the microsurface: under a uniform sky, where a wider lookup reads the same radiance,
/// a glossy sphere reflects the same with it as without, limb included. Reading the split
/// sum's albedo at the widened roughness changed limb pixels by up to 28% here.
#[test]
fn specular_aa_leaves_what_a_uniform_sky_reflects() {
    let sphere = r#"
[camera]
position = [0.0, 0.4, 4.2]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 34.0

[environment]
kind = "uniform"
radiance = [1.0, 1.0, 1.0]

[[objects]]
mesh = "builtin:sphere"
material = "glossy"

[materials.glossy]
base_color = [0.7, 0.45, 0.3]
roughness = 0.3
specular = "cook-torrance"
"#;
    let hdr = |specular: bool| render(&with_antialiasing(sphere, 1, specular), 160, 90).hdr;
    let (on, off) = (hdr(true), hdr(false));
    let worst = on
        .iter()
        .zip(&off)
        .map(|(a, b)| (a - b).abs() / b.abs().max(1e-3))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "specular anti-aliasing changed a channel by {worst:.2e} (relative)");
}

/// `[antialiasing] msaa` outside 1, 2, 4, 8 is bad input: exit code 2, the file and the
/// key named, nothing written; `--msaa 3` too.
#[test]
fn a_bad_msaa_count_is_bad_input() {
    let dir = common::test_dir("bad-msaa");
    let path = dir.join("bad-msaa.toml");
    std::fs::write(&path, format!("{BLACK_ON_WHITE}\n[antialiasing]\nmsaa = 3\n")).expect("write scene");
    let out = dir.join("never.png");
    let (path_arg, out_arg) = (path.to_str().expect("utf-8"), out.to_str().expect("utf-8"));
    let output = argil(&["render", path_arg, "--out", out_arg]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(path_arg) && stderr.contains("antialiasing.msaa"),
        "{stderr}"
    );
    assert!(!out.exists());
    let output = argil(&["render", "--msaa", "3", "--out", out_arg]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--msaa"));
    assert!(!out.exists());
}
