//! `argil reference`, the Monte Carlo ground truth: against closed forms (a Lambert sphere
//! under a point light, the white furnace), against the real-time renderer where both
//! compute the same thing (`direct` transport, `center` filter, every model), its
//! estimators against each other, its noise estimate against the error it predicts, and
//! the command line.

mod common;

use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use argil::reference::{
    render, Ending, Filter, Progress, Reference, Sampling, Settings, Stop, SubsurfaceTransport, Transport,
};
use argil::scene::{Mesh, Scene};
use common::{argil, percentiles, scene, LAMBERT_SPHERE, test_dir};
use glam::DVec3;

fn settings(width: u32, height: u32, transport: Transport, filter: Filter, samples: u32) -> Settings {
    Settings {
        width,
        height,
        transport,
        filter,
        sampling: Sampling::Mis,
        subsurface: SubsurfaceTransport::Model,
        stop: Stop::Samples(samples),
        seed: 1,
        max_depth: Settings::DEFAULT_MAX_DEPTH,
        max_time: None,
    }
}

fn pixel(image: &Reference, i: usize) -> (DVec3, f32) {
    let p = &image.rgba[4 * i..4 * i + 4];
    (DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])), p[3])
}

const FURNACE: &str = r#"
[camera]
position = [0.0, 0.4, 4.0]
target = [0.0, 0.0, 0.0]

[environment]
kind = "uniform"
radiance = [0.5, 0.5, 0.5]

[[objects]]
mesh = "builtin:sphere"
material = "white"

[materials.white]
base_color = [1.0, 1.0, 1.0]
diffuse = "lambert"
specular = "none"
"#;

/// A white Lambert ball under uniform radiance L reflects exactly L, so every pixel,
/// covered or not, is L at any sample count, in every transport: the material's cosine
/// sampling makes each sample exact, and a convex ball sends no path back to itself.
/// Only where the interpolated normal faces away from the eye (silhouette triangles) is
/// the shading normal bent, and the terminator's shadowing takes a little away.
#[test]
fn white_furnace_is_exact_in_every_transport() {
    let scene = scene(FURNACE);
    for transport in [Transport::Direct, Transport::Shadows, Transport::Full] {
        let image = render(&scene, &settings(96, 64, transport, Filter::Box, 3), &()).expect("reference");
        let pixels = image.rgba.len() / 4;
        let mut exact = 0;
        for i in 0..pixels {
            let (radiance, _) = pixel(&image, i);
            for c in radiance.to_array() {
                assert!(
                    (0.45..=0.5 * (1.0 + 1e-6)).contains(&c),
                    "{transport}: pixel {i} is {radiance}"
                );
            }
            exact += usize::from((radiance - DVec3::splat(0.5)).abs().max_element() < 0.5e-6);
        }
        assert!(
            exact * 1000 >= pixels * 995,
            "{transport}: {exact} of {pixels} pixels are exactly L"
        );
        assert!(image.noise < 1e-6, "{transport}: noise {}", image.noise);
    }
}

/// A Lambert sphere under a point light against the closed form (ρ/π)·I·cosθ/d² on the
/// exact sphere, through the reference's camera, mesh and shading: at the pixel centre
/// one sample is the whole estimate.
#[test]
fn lambert_sphere_matches_the_closed_form() {
    let mut scene = scene(LAMBERT_SPHERE);
    scene.meshes[0] = Mesh::sphere(128);
    let (width, height) = (128, 128);
    let image = render(
        &scene,
        &settings(width, height, Transport::Direct, Filter::Center, 1),
        &(),
    )
    .expect("reference");
    let eye = DVec3::new(0.0, 0.0, 5.0);
    let light = DVec3::new(2.0, 2.0, 3.0);
    let tan_half = (15.0f64).to_radians().tan();
    let mut errors = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let ndc = |i: u32, n: u32| 2.0 * (f64::from(i) + 0.5) / f64::from(n) - 1.0;
            let dir = DVec3::new(ndc(x, width) * tan_half, -ndc(y, height) * tan_half, -1.0).normalize();
            let b = eye.dot(dir);
            let disc = b * b - (eye.length_squared() - 1.0);
            if disc <= 0.0 {
                continue;
            }
            let p = eye + (-b - disc.sqrt()) * dir;
            let n = p.normalize();
            let to_light = light - p;
            let d2 = to_light.length_squared();
            let cos_l = n.dot(to_light / d2.sqrt());
            // Away from the terminator and the silhouette, where a relative error of a
            // vanishing value or a mesh edge means nothing.
            if cos_l < 0.05 || n.dot(-dir) < 0.2 {
                continue;
            }
            let exact = DVec3::new(0.8, 0.6, 0.4) / std::f64::consts::PI * DVec3::new(10.0, 7.0, 4.0) * cos_l / d2;
            let (radiance, alpha) = pixel(&image, (y * width + x) as usize);
            assert_eq!(alpha, 1.0);
            errors.extend(((radiance - exact).abs() / exact).to_array());
        }
    }
    let (p50, p99, max) = percentiles(errors);
    eprintln!("reference vs closed form: p50 {p50:.2e} p99 {p99:.2e} max {max:.2e}");
    // The 512 × 256 sphere's interpolated normal is off by up to (π/256)²/8 ≈ 1.9e-5 rad,
    // amplified by tanθ near the terminator (the real-time test measures 8.9e-5 at p99 on
    // a mesh twice as fine; the error goes as the square of the step), then rounded to f32.
    assert!(p99 < 5e-4 && max < 2e-3, "p99 {p99:.3e}, max {max:.3e}");
}

/// On a lone convex sphere nothing can cast a shadow, so `shadows` and `full` equal
/// `direct` pixel for pixel, also on the coarse builtin sphere whose facets lie below its
/// smooth normals near the terminator: rays leave from the vertices' tangent planes.
#[test]
fn a_lone_convex_sphere_does_not_shadow_itself() {
    let scene = scene(LAMBERT_SPHERE);
    let direct = render(&scene, &settings(96, 96, Transport::Direct, Filter::Center, 1), &()).expect("direct");
    for transport in [Transport::Shadows, Transport::Full] {
        let image = render(&scene, &settings(96, 96, transport, Filter::Center, 1), &()).expect("reference");
        assert_eq!(image.rgba, direct.rgba, "{transport} differs from direct");
    }
}

const BALL_ABOVE_GROUND: &str = r#"
[camera]
position = [0.0, 3.0, 6.0]
target = [1.0, 0.0, 0.0]
fov_y_degrees = 40.0

[[lights]]
kind = "point"
position = [0.0, 5.0, 0.0]
intensity = [20.0, 20.0, 20.0]

[[objects]]
mesh = "builtin:sphere"
position = [1.2, 1.5, 0.0]
scale = 0.5
material = "white"

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "white"

[materials.white]
base_color = [0.5, 0.5, 0.5]
specular = "none"
"#;

/// A ball above the ground under a point light: with visibility the ground straight
/// below the ball's shadow centre is black, open ground is as lit as without visibility,
/// and the full transport adds light everywhere (the ball's bounce) but removes none.
#[test]
fn shadows_darken_only_where_the_light_is_hidden() {
    let scene = scene(BALL_ABOVE_GROUND);
    let (w, h) = (80, 80);
    let render_with = |transport| render(&scene, &settings(w, h, transport, Filter::Center, 4), &()).expect("ref");
    let (direct, shadows, full) = (
        render_with(Transport::Direct),
        render_with(Transport::Shadows),
        render_with(Transport::Full),
    );
    // The shadow's centre: the light (0, 5, 0) through the ball's centre onto y = 0.
    let shadow_centre = DVec3::new(1.2 * 5.0 / 3.5, 0.0, 0.0);
    let camera = scene.camera;
    let project = |p: DVec3| {
        let clip = camera.projection(1.0) * camera.view() * p.as_vec3().extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let x = ((f64::from(ndc.x) + 1.0) * 0.5 * f64::from(w)) as usize;
        let y = ((f64::from(ndc.y) + 1.0) * 0.5 * f64::from(h)) as usize;
        y * w as usize + x
    };
    let umbra = project(shadow_centre);
    assert_eq!(pixel(&shadows, umbra).0, DVec3::ZERO, "the umbra is black");
    assert!(
        pixel(&direct, umbra).0.x > 0.05,
        "without visibility the ground there is lit"
    );
    let open = project(DVec3::new(-1.5, 0.0, 1.0));
    assert_eq!(
        pixel(&shadows, open).0,
        pixel(&direct, open).0,
        "open ground sees the light"
    );
    let ground_total = |image: &Reference| (0..(w * h) as usize).map(|i| pixel(image, i).0.x).sum::<f64>();
    assert!(
        ground_total(&full) > ground_total(&shadows) * 1.01,
        "inter-reflection adds light"
    );
}

/// Light sampling, material sampling and their MIS combination are three unbiased
/// estimators of the same image: per pixel they differ only by their noise.
#[test]
fn estimators_agree_on_an_environment_lit_sphere() {
    let scene = scene(
        r#"
[camera]
position = [0.0, 0.3, 4.0]
target = [0.0, 0.0, 0.0]

[environment]
kind = "studio"

[[objects]]
mesh = "builtin:sphere"
material = "glossy"

[materials.glossy]
base_color = [0.6, 0.3, 0.2]
roughness = 0.35
f0 = 0.2
"#,
    );
    let images: Vec<(Sampling, Reference)> = [Sampling::Mis, Sampling::Material, Sampling::Light]
        .into_iter()
        .map(|sampling| {
            let s = Settings {
                sampling,
                ..settings(48, 48, Transport::Direct, Filter::Center, 48)
            };
            (sampling, render(&scene, &s, &()).expect("reference"))
        })
        .collect();
    let covered: Vec<usize> = (0..48 * 48).filter(|&i| pixel(&images[0].1, i).1 == 1.0).collect();
    for (sampling, image) in &images[1..] {
        let mis = &images[0].1;
        let (mut difference, mut signal) = (0.0, 0.0);
        for &i in &covered {
            difference += (pixel(image, i).0 - pixel(mis, i).0).length_squared();
            signal += pixel(mis, i).0.length_squared();
        }
        let relative = (difference / signal).sqrt();
        // Two independent estimates differ by √(σ₁² + σ₂²); allow for the estimate of σ.
        let expected = (image.noise.powi(2) + mis.noise.powi(2)).sqrt();
        eprintln!(
            "{sampling} vs mis: RMS difference {relative:.4}, expected from their noise {expected:.4} (noise {:.4} and {:.4})",
            image.noise, mis.noise
        );
        assert!(
            relative < 1.3 * expected,
            "{sampling}: {relative:.4} against {expected:.4}"
        );
        assert!(mis.noise <= image.noise * 1.05, "MIS is no noisier than {sampling}");
    }
}

/// The noise printed is the error one can expect: two references with different seeds
/// differ by √2 times it.
#[test]
fn the_noise_estimate_predicts_the_error() {
    let scene = Scene::default_scene();
    let run = |seed| {
        let s = Settings {
            seed,
            ..settings(64, 36, Transport::Full, Filter::Box, 16)
        };
        render(&scene, &s, &()).expect("reference")
    };
    let (a, b) = (run(1), run(2));
    let (mut difference, mut signal) = (0.0, 0.0);
    for i in 0..64 * 36 {
        if pixel(&a, i).1 > 0.0 || pixel(&b, i).1 > 0.0 {
            let (pa, pb) = (pixel(&a, i).0, pixel(&b, i).0);
            difference += (pa - pb).length_squared();
            signal += ((pa + pb) * 0.5).length_squared();
        }
    }
    let measured = (difference / signal).sqrt() / std::f64::consts::SQRT_2;
    let estimated = 0.5 * (a.noise + b.noise);
    eprintln!("noise estimated {estimated:.4}, measured between seeds {measured:.4}");
    assert!(
        (0.8..1.25).contains(&(measured / estimated)),
        "measured {measured:.4}, estimated {estimated:.4}"
    );
}

/// A pixel's samples depend only on the seed: one thread or two give the same bits.
#[test]
fn the_same_seed_gives_the_same_image_on_any_number_of_threads() {
    let scene = Scene::default_scene();
    let s = settings(40, 24, Transport::Full, Filter::Box, 4);
    let on = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| render(&scene, &s, &()).expect("reference"))
    };
    assert_eq!(on(1).rgba, on(2).rgba);
}

/// A noise target stops as soon as it is met.
#[test]
fn a_noise_target_is_met() {
    let scene = Scene::default_scene();
    let s = Settings {
        stop: Stop::Noise {
            target: 0.05,
            max_samples: 4096,
        },
        ..settings(48, 27, Transport::Direct, Filter::Box, 1)
    };
    let image = render(&scene, &s, &()).expect("reference");
    assert!(image.noise <= 0.05, "noise {}", image.noise);
    assert!(image.samples < 4096, "{} samples", image.samples);
}


/// Interrupted once half the rows of the second pass are done.
struct InterruptInSecondPass {
    height: u64,
    interrupted: AtomicBool,
}

impl Progress for InterruptInSecondPass {
    fn update(&self, done: u64, _: u64) {
        if done >= 16 * self.height + 16 * self.height / 2 {
            self.interrupted.store(true, Ordering::Relaxed);
        }
    }

    fn interrupted(&self) -> bool {
        self.interrupted.load(Ordering::Relaxed)
    }
}

/// An interruption keeps every sample taken: the rows the interrupted pass began have its
/// samples, the others the passes before, each row bit for bit as the reference of its
/// count, and the image says how many.
#[test]
fn an_interrupted_reference_keeps_every_row_it_finished() {
    let scene = scene(LAMBERT_SPHERE);
    let (width, height) = (24, 12);
    // Passes of 16, 16 and 32 samples; interrupted in the second.
    let progress = InterruptInSecondPass {
        height: height as u64,
        interrupted: AtomicBool::new(false),
    };
    let image = render(&scene, &settings(width, height, Transport::Direct, Filter::Box, 64), &progress)
        .expect("reference");
    assert_eq!(image.ending, Ending::Interrupted);
    assert_eq!((image.samples, image.most_samples), (16, 32));
    let of = |samples| {
        render(&scene, &settings(width, height, Transport::Direct, Filter::Box, samples), &()).expect("reference")
    };
    let (sixteen, thirty_two) = (of(16), of(32));
    let row = |image: &Reference, y: usize| image.rgba[y * 4 * width as usize..(y + 1) * 4 * width as usize].to_vec();
    // Each row is one of the two; rows of background alone are both.
    let rows: Vec<(bool, bool)> = (0..height as usize)
        .map(|y| (row(&image, y) == row(&sixteen, y), row(&image, y) == row(&thirty_two, y)))
        .collect();
    assert!(rows.iter().all(|&(a, b)| a || b), "rows as 16 and as 32 samples: {rows:?}");
    assert!(rows.contains(&(true, false)) && rows.contains(&(false, true)), "{rows:?}");
    assert!(image.noise.is_finite() && image.noise > 0.0, "noise {}", image.noise);
}

/// A time limit ends sampling with every pixel sampled alike, well before a sample count
/// that would take hours.
#[test]
fn a_time_limit_ends_the_reference_with_whole_passes() {
    let scene = scene(LAMBERT_SPHERE);
    let s = Settings {
        max_time: Some(Duration::from_millis(500)),
        ..settings(32, 18, Transport::Direct, Filter::Box, 1 << 30)
    };
    let image = render(&scene, &s, &()).expect("reference");
    assert_eq!(image.ending, Ending::TimeLimit);
    assert_eq!(image.samples, image.most_samples);
    assert!(image.samples >= 2 && image.samples < 1 << 30, "{} samples", image.samples);
    // Not a timing check: a limit that did not stop sampling would run for years.
    assert!(image.elapsed < Duration::from_secs(60), "{:?}", image.elapsed);
}

/// Ctrl-C (SIGINT) in `argil reference` writes the samples taken and exits with code 130;
/// sent before the first pass ends, it writes nothing (and the next try waits longer).
#[test]
fn ctrl_c_writes_the_samples_taken_and_exits_130() {
    let dir = test_dir("interrupt");
    let scene_file = dir.join("sphere.toml");
    std::fs::write(&scene_file, LAMBERT_SPHERE).expect("write the scene");
    let out = dir.join("ref.exr");
    for wait in [2, 8, 32] {
        let child = Command::new(env!("CARGO_BIN_EXE_argil"))
            .args(["reference", scene_file.to_str().expect("utf-8"), "--out", out.to_str().expect("utf-8")])
            .args(["--width", "64", "--height", "32", "--transport", "direct", "--spp", "1000000000"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run argil");
        std::thread::sleep(Duration::from_secs(wait));
        let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("run kill");
        assert!(kill.success(), "kill -INT");
        let o = child.wait_with_output().expect("wait for argil");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "{stderr}");
        if !out.exists() {
            assert!(stderr.contains("before every row had a sample"), "{stderr}");
            continue;
        }
        assert!(stderr.contains(", interrupted,") && stderr.contains("holds them"), "{stderr}");
        let image = exr::prelude::read_first_rgba_layer_from_file(
            &out,
            |_, _| (),
            |_: &mut (), _, (_, _, _, _): (f32, f32, f32, f32)| (),
        )
        .expect("read the EXR");
        let spp = match image.layer_data.attributes.other.get(&exr::prelude::Text::from("argil.spp")) {
            Some(exr::prelude::AttributeValue::Text(t)) => t.to_string(),
            other => panic!("argil.spp: {other:?}"),
        };
        assert!(spp.parse::<u32>().expect("a count") >= 16, "{spp} spp");
        return;
    }
    panic!("no pass of 64×32 pixels ended within 32 s");
}

#[test]
fn the_command_writes_an_exr_with_its_settings() {
    let dir = test_dir("cli");
    let out = dir.join("ref.exr");
    let o = argil(&[
        "reference",
        "--out",
        out.to_str().expect("utf-8"),
        "--width",
        "32",
        "--height",
        "18",
        "--spp",
        "4",
        "--transport",
        "shadows",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(
        stderr.contains("shadows transport") && stderr.contains("Mrays/s"),
        "{stderr}"
    );
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &out,
        |resolution, _| vec![[0.0f32; 4]; resolution.width() * resolution.height()],
        |pixels: &mut Vec<[f32; 4]>, p, (r, g, b, a): (f32, f32, f32, f32)| pixels[p.y() * 32 + p.x()] = [r, g, b, a],
    )
    .expect("read the EXR");
    let attributes = &image.layer_data.attributes.other;
    let text = |name: &str| match attributes.get(&exr::prelude::Text::from(name)) {
        Some(exr::prelude::AttributeValue::Text(t)) => t.to_string(),
        other => panic!("{name}: {other:?}"),
    };
    assert_eq!(text("argil.transport"), "shadows");
    assert_eq!(text("argil.filter"), "box");
    assert_eq!(text("argil.spp"), "4");
    assert!(text("argil.noise").parse::<f64>().expect("a number") > 0.0);
    let pixels = &image.layer_data.channel_data.pixels;
    assert!(
        pixels.iter().any(|p| p[3] == 1.0) && pixels.iter().any(|p| p[3] == 0.0),
        "coverage in alpha"
    );
    std::fs::remove_dir_all(dir).expect("clean up");
}

#[test]
fn the_command_refuses_bad_input_before_rendering() {
    let dir = test_dir("bad");
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "[camera\n").expect("write");
    // A map whose headers read but whose data does not: found as the reference decodes it.
    std::fs::write(dir.join("sky.hdr"), b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 32 +X 64\n\x02\x02").expect("write");
    let truncated = dir.join("map.toml");
    let map_scene = format!("{LAMBERT_SPHERE}\n[environment]\nkind = \"map\"\npath = \"sky.hdr\"\n");
    std::fs::write(&truncated, map_scene).expect("write");
    let out = dir.join("out.exr");
    let out_str = out.to_str().expect("utf-8");
    for (args, mention) in [
        (
            vec!["reference", broken.to_str().expect("utf-8"), "--out", out_str],
            "broken.toml",
        ),
        (
            vec!["reference", truncated.to_str().expect("utf-8"), "--out", out_str, "--spp", "1"],
            "map.toml: environment.path: environment map ",
        ),
        (
            vec!["reference", "--out", dir.join("out.jpg").to_str().expect("utf-8")],
            "out.jpg",
        ),
        (
            vec!["reference", "--out", out_str, "--transport", "sideways"],
            "sideways",
        ),
        (vec!["reference", "--out", out_str, "--noise=-1"], "--noise"),
        (vec!["reference", "--out", out_str, "--spp", "0"], "--spp"),
    ] {
        let o = argil(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: bad input exits with 2");
        assert!(stderr.contains(mention), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    assert_eq!(std::fs::read_dir(&dir).expect("dir").count(), 3, "nothing was written");
    std::fs::remove_dir_all(dir).expect("clean up");
}

/// In `direct` transport at pixel centres the reference computes what the forward pass
/// computes, on the same mesh: one point light through each model (and a uniform
/// environment, exact for Lambert in both), one sample a pixel being the whole estimate.
/// What separates them is the GPU's fp32 arithmetic: measured on lavapipe, p50 1–10e-7 and
/// p99 2–6e-6 for every model, the bounds of `tests/accuracy.rs` (where the f64 twins are
/// evaluated on the drawn mesh by hand); the largest, 2–3e-4, are a few pixels where n·l
/// is small. A normal map adds the GPU's 8-bit sub-texel filter weights (magnified here,
/// so no mip is read): measured p50 1e-3, p99 2.6e-2, with 40% in a few dim pixels whose
/// mapped normal is near the light's horizon, where a small turn is a large fraction.
#[test]
fn direct_transport_at_pixel_centres_matches_the_real_time_renderer() {
    const FP32: [f64; 3] = [3e-6, 2e-5, 1e-3];
    // (material and environment, bounds of p50, p99 and max of the relative error)
    let cases: &[(&str, [f64; 3])] = &[
        ("diffuse = \"lambert\"\nspecular = \"none\"", FP32),
        (
            "diffuse = \"oren-nayar\"\ndiffuse_roughness = 0.5\nspecular = \"none\"",
            FP32,
        ),
        ("diffuse = \"eon\"\ndiffuse_roughness = 0.5\nspecular = \"none\"", FP32),
        (
            "diffuse = \"none\"\nroughness = 0.4\ndistribution = \"ggx\"\ngeometry = \"smith-correlated\"",
            FP32,
        ),
        (
            "diffuse = \"none\"\nroughness = 0.4\ndistribution = \"ggx\"\ngeometry = \"smith-separable\"",
            FP32,
        ),
        ("diffuse = \"none\"\nroughness = 0.4\ndistribution = \"beckmann\"", FP32),
        (
            "diffuse = \"none\"\nroughness = 0.4\ndistribution = \"beckmann\"\ngeometry = \"smith-separable\"",
            FP32,
        ),
        (
            "diffuse = \"none\"\nspecular = \"torrance-sparrow\"\nroughness = 0.4",
            FP32,
        ),
        ("diffuse = \"none\"\nspecular = \"blinn-phong\"\nroughness = 0.4", FP32),
        (
            "roughness = 0.6\nwrap = 0.5\nwrap_width = 0.3\nwrap_color = [0.9, 0.3, 0.2]\nwrap_intensity = 0.8",
            FP32,
        ),
        (
            "subsurface = \"energy-conserving-wrap\"\nwrap = 0.6\nscatter_color = [1.0, 0.5, 0.25]",
            FP32,
        ),
        (
            "diffuse = \"eon\"\ndiffuse_roughness = 0.5\nsubsurface = \"pre-integrated\"\nscatter_radius = 0.4",
            FP32,
        ),
        ("horizon = \"seed\"\nroughness = 0.3", FP32),
        // The GPU reads E from the fp16 BRDF tables with 8-bit sub-texel weights, the
        // reference from the f64 texels, exactly interpolated: measured p50 2.1e-4, p99
        // 6.0e-4, max 7.3e-4.
        (
            "diffuse = \"none\"\nmetallic = 1.0\nroughness = 0.9\nenergy_compensation = true",
            [5e-4, 2e-3, 3e-3],
        ),
        (
            "specular = \"none\"\n[environment]\nkind = \"uniform\"\nradiance = [0.2, 0.3, 0.4]",
            FP32,
        ),
        (
            "roughness = 0.5\n[materials.m.normal_map]\ntexture = \"builtin:clay-lumps\"\nuv_scale = [0.05, 0.05]",
            [3e-3, 5e-2, 1.0],
        ),
    ];
    let (width, height) = (128, 128);
    let mut failures = Vec::new();
    for (material, [p50_bound, p99_bound, max_bound]) in cases {
        let scene = scene(&format!(
            r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [2.0, 2.0, 3.0]
intensity = [12.0, 12.0, 12.0]

# The reference samples the pixel centre with the material as it is; specular
# anti-aliasing widens a lobe by the normal's change across the pixel.
[antialiasing]
specular = false

[[objects]]
mesh = "builtin:sphere"
material = "m"

[materials.m]
base_color = [0.8, 0.5, 0.3]
f0 = 0.04
{material}
"#
        ));
        let gpu = common::render(&scene, width, height);
        let reference = render(
            &scene,
            &settings(width, height, Transport::Direct, Filter::Center, 1),
            &(),
        )
        .expect("reference");
        let pixels = (width * height) as usize;
        let mut lit: Vec<f64> = (0..pixels).map(|i| pixel(&reference, i).0.min_element()).collect();
        lit.sort_by(f64::total_cmp);
        // Relative error means nothing where a lobe or the terminator takes the value to ~0.
        let floor = 1e-2 * lit[pixels * 99 / 100];
        let mut errors = Vec::new();
        for i in 0..pixels {
            let (r, alpha) = pixel(&reference, i);
            let g = DVec3::new(
                f64::from(gpu.hdr[4 * i]),
                f64::from(gpu.hdr[4 * i + 1]),
                f64::from(gpu.hdr[4 * i + 2]),
            );
            if alpha == 1.0 && gpu.hdr[4 * i + 3] == 1.0 && r.min_element() > floor {
                errors.extend(((g - r).abs() / r).to_array());
            }
        }
        let label = material.replace('\n', " ");
        let covered = errors.len() / 3;
        let (p50, p99, max) = percentiles(errors);
        eprintln!("{label}: {covered} px, p50 {p50:.2e} p99 {p99:.2e} max {max:.2e}");
        if covered < 500 || p50 > *p50_bound || p99 > *p99_bound || max > *max_bound {
            failures.push(format!(
                "{label}: {covered} px, p50 {p50:.3e} (≤ {p50_bound:e}), p99 {p99:.3e} (≤ {p99_bound:e}), max {max:.3e} (≤ {max_bound:e})"
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "the reference and the renderer differ:\n{}",
        failures.join("\n")
    );
}

/// A white (non-absorbing) clay as a medium loses no light, whatever its mean free path
/// per channel: under uniform radiance L every path brings back L on average. Each
/// channel's mean over the ball is L within the estimate's own noise.
#[test]
fn a_white_scattering_medium_is_a_furnace() {
    let scene = scene(&FURNACE.replace(
        "specular = \"none\"",
        "specular = \"none\"\nsubsurface = \"pre-integrated\"\nscatter_radius = 0.2\nscatter_color = [1.0, 0.5, 0.3]",
    ));
    let s = Settings {
        subsurface: SubsurfaceTransport::Volume,
        ..settings(48, 32, Transport::Full, Filter::Center, 64)
    };
    let image = render(&scene, &s, &()).expect("reference");
    let covered: Vec<DVec3> = (0..48 * 32)
        .map(|i| pixel(&image, i))
        .filter(|p| p.1 == 1.0)
        .map(|p| p.0)
        .collect();
    let n = covered.len() as f64;
    let mean = covered.iter().sum::<DVec3>() / n;
    // The standard error of a mean of n pixels, each with the estimate's relative noise.
    let error = image.noise * 0.5 / n.sqrt();
    eprintln!(
        "volume furnace: mean {mean} over {n} px, noise {:.3}, standard error {error:.2e}",
        image.noise
    );
    for c in mean.to_array() {
        assert!(
            (c - 0.5).abs() < 4.0 * error + 1e-3,
            "mean {mean}, standard error {error:.2e}"
        );
    }
}

/// A rough white metal ball under uniform radiance loses a single-scattering lobe's light
/// (at roughness 0.9 the reference's ball averages half of L); with `energy_compensation`
/// the renderer's split sum and the reference (whose BRDF evaluation, and so its MIS,
/// includes the same factor) both reflect about all of it. Against the compensated reference, the compensated
/// render is closer by ꟻLIP and relative MSE (the metrics of `argil compare`) than the
/// uncompensated one (measured at 32 spp: ꟻLIP 0.074 against 0.55, rel-MSE 1.9e-2 against
/// 0.27), and the uncompensated reference is darker.
#[test]
fn energy_compensation_brings_render_and_reference_together_on_a_rough_metal() {
    use argil::compare::metrics::{compare, Rgba32};
    // The furnace's ball turned into the metal, as the reference (no specular anti-aliasing).
    let toml = |on: bool| {
        FURNACE.replace(
            "diffuse = \"lambert\"\nspecular = \"none\"",
            &format!("metallic = 1.0\nroughness = 0.9\nenergy_compensation = {on}\n[antialiasing]\nspecular = false"),
        )
    };
    let (width, height) = (64, 64);
    let rgba = |pixels: &[f32]| Rgba32 {
        width: width as usize,
        height: height as usize,
        pixels: pixels.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]).collect(),
    };
    let s = settings(width, height, Transport::Full, Filter::Center, 32);
    let reference_on = render(&scene(&toml(true)), &s, &()).expect("reference");
    let reference_off = render(&scene(&toml(false)), &s, &()).expect("reference");
    let truth = rgba(&reference_on.rgba);
    let mean = |image: &Reference| {
        let covered: Vec<DVec3> = (0..(width * height) as usize)
            .filter(|&i| pixel(image, i).1 == 1.0)
            .map(|i| pixel(image, i).0)
            .collect();
        covered.iter().sum::<DVec3>().x / covered.len() as f64
    };
    let (mean_on, mean_off) = (mean(&reference_on), mean(&reference_off));
    let metrics = |on: bool| {
        let frame = common::render(&scene(&toml(on)), width, height);
        compare(&rgba(&frame.hdr), &truth).expect("same size").metrics
    };
    let (on, off) = (metrics(true), metrics(false));
    eprintln!(
        "reference (full, center, 32 spp, noise {:.4}): mean over the ball {mean_on:.4} compensated, {mean_off:.4} not, of 0.5; \
         render vs it: compensated ꟻLIP {:.4} rel-MSE {:.2e}, uncompensated ꟻLIP {:.4} rel-MSE {:.2e}",
        reference_on.noise, on.flip.mean, on.rel_mse, off.flip.mean, off.rel_mse
    );
    assert!((mean_on - 0.5).abs() < 0.01, "compensated: {mean_on}");
    assert!(mean_off < 0.5 * 0.95, "uncompensated: {mean_off}");
    assert!(on.flip.mean < 0.5 * off.flip.mean, "ꟻLIP {} vs {}", on.flip.mean, off.flip.mean);
    assert!(on.rel_mse < 0.25 * off.rel_mse, "rel-MSE {} vs {}", on.rel_mse, off.rel_mse);
}
