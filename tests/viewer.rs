//! What the viewer adds to rendering, checked on the shared device without a window: the
//! debug views of the forward pass, and saving an edited scene so that `argil render`
//! draws exactly what the viewer showed.

mod common;

use argil::render::accumulate::Accumulation;
use argil::render::{DebugView, OffscreenFrame, OffscreenTarget};
use argil::scene::{DiffuseModel, Scene, SpecularModel, Subsurface};
use ash::vk;
use common::{argil, gpu, render, render_forward, rgb_difference, sampled_sphere_toml, scene, try_render};
use glam::Vec3;

fn render_view(scene: &Scene, view: DebugView, width: u32, height: u32) -> OffscreenFrame {
    gpu().exclusive(|renderer| {
        renderer.debug_view = view;
        let frame = try_render(renderer, scene, width, height);
        renderer.debug_view = DebugView::Shaded;
        frame.expect("render")
    })
}

fn pixel(frame: &OffscreenFrame, x: u32, y: u32) -> [f32; 4] {
    let i = ((y * frame.width + x) * 4) as usize;
    [frame.hdr[i], frame.hdr[i + 1], frame.hdr[i + 2], frame.hdr[i + 3]]
}

/// The default scene with the ball's subsurface term on, so that every lobe contributes
/// somewhere: the report's wrap, or the ball's own pre-integrated scattering. The light
/// bounced off the ground, a term of its own (the `bounce` view), is off.
fn every_lobe_scene(subsurface: Subsurface) -> Scene {
    let mut scene = Scene::default_scene();
    scene.bounce = false;
    let ball = &mut scene.materials[scene.objects[0].material];
    ball.subsurface = subsurface;
    ball.wrap = 0.5;
    ball.wrap_intensity = 1.0;
    ball.wrap_color = Vec3::new(1.0, 0.3, 0.2);
    scene
}

/// The shaded image is the sum of its terms, so the four lobe views must add up to it on
/// every covered pixel (background pixels show the clear colour in every view), and each
/// lobe must light some pixel.
#[test]
fn lobe_views_add_up_to_the_shaded_image() {
    for subsurface in [Subsurface::Seed, Subsurface::PreIntegrated] {
        lobe_views_add_up(&every_lobe_scene(subsurface));
    }
}

fn lobe_views_add_up(scene: &Scene) {
    let (w, h) = (160, 90);
    let shaded = render_view(scene, DebugView::Shaded, w, h);
    let lobes = [
        DebugView::Diffuse,
        DebugView::Specular,
        DebugView::Subsurface,
        DebugView::Environment,
    ];
    let views: Vec<OffscreenFrame> = lobes.iter().map(|v| render_view(scene, *v, w, h)).collect();
    let mut worst = 0.0f32;
    let mut lit = [0usize; 4];
    for y in 0..h {
        for x in 0..w {
            let s = pixel(&shaded, x, y);
            if s[3] < 1.0 {
                continue;
            }
            for (c, shaded) in s.iter().take(3).enumerate() {
                let sum: f32 = views.iter().map(|v| pixel(v, x, y)[c]).sum();
                worst = worst.max((sum - shaded).abs() / shaded.max(1e-3));
            }
            for (count, v) in lit.iter_mut().zip(&views) {
                *count += usize::from(pixel(v, x, y)[0] > 1e-4);
            }
        }
    }
    assert!(worst < 1e-4, "lobes differ from the shaded image by {worst} (relative)");
    for (view, count) in lobes.iter().zip(lit) {
        assert!(count > 100, "{view:?} lights only {count} pixels");
    }
}

/// The Lambert sphere seen head-on: its normal at the centre points at the camera, +x to
/// the right, +y up; n·l is 1 where the light is behind the camera; UVs stay in [0, 1).
#[test]
fn geometry_views_show_normals_and_n_dot_l() {
    let sphere = scene(
        r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
[[lights]]
kind = "point"
position = [0.0, 0.0, 100.0]
intensity = [1.0, 1.0, 1.0]
[[objects]]
mesh = "builtin:sphere"
"#,
    );
    let (w, h) = (101, 101);
    let normals = render_view(&sphere, DebugView::Normals, w, h);
    let centre = pixel(&normals, 50, 50);
    let expected = [0.5, 0.5, 1.0];
    for c in 0..3 {
        assert!(
            (centre[c] - expected[c]).abs() < 0.01,
            "normal colour at the centre: {centre:?}"
        );
    }
    // 30° field of view at distance 5: the sphere's edge is at about 0.76 of the half width.
    let right = pixel(&normals, 80, 50);
    let top = pixel(&normals, 50, 20);
    assert!(right[0] > 0.8 && top[1] > 0.8, "right {right:?}, top {top:?}");

    // The light is far along +z, so n·l is about n.z, which the normal view shows as 0.5 + n.z/2.
    let n_dot_l = render_view(&sphere, DebugView::NDotL, w, h);
    for (x, y) in [(50, 50), (80, 50), (50, 20), (30, 70)] {
        let from_normal = 2.0 * pixel(&normals, x, y)[2] - 1.0;
        let shown = pixel(&n_dot_l, x, y)[0];
        assert!(
            (shown - from_normal).abs() < 0.01,
            "n·l at ({x}, {y}): {shown} vs n.z {from_normal}"
        );
    }

    let uvs = render_view(&sphere, DebugView::Uvs, w, h);
    let outside: Vec<&[f32]> = uvs
        .hdr
        .chunks_exact(4)
        .filter(|p| p[3] == 1.0 && !((0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1]) && p[2] == 0.0))
        .collect();
    assert!(
        outside.is_empty(),
        "UV colours outside [0, 1]: {:?}",
        &outside[..outside.len().min(5)]
    );
    for view in [DebugView::Tangents, DebugView::Bitangents] {
        let frame = render_view(&sphere, view, w, h);
        let c = pixel(&frame, 50, 50);
        // Unit vectors in the sphere's tangent plane at the centre: z component 0 → 0.5.
        assert!(
            (c[2] - 0.5).abs() < 0.02 && (0.0..=1.0).contains(&c[0]),
            "{view:?} at the centre: {c:?}"
        );
    }
}

/// The curvature view of a sphere scaled by 0.5 (world curvature 2, convex) is red at
/// `curvature_color(2)` (the legend's twin of the shader's map) all over, which checks the
/// vertex attribute and the vertex shader's division by the object's scale; a plane is
/// black. The legend's colour for κ = 2 is what the display shows there.
#[test]
fn curvature_view_shows_the_world_space_curvature() {
    let shapes = scene(
        r#"
[camera]
position = [0.0, 3.0, 4.0]
target = [0.0, 0.0, 0.0]
[[objects]]
mesh = "builtin:sphere"
position = [0.0, 0.5, 0.0]
scale = 0.5
[[objects]]
mesh = "builtin:plane"
scale = 3
"#,
    );
    let (w, h) = (101, 101);
    let frame = render_view(&shapes, DebugView::Curvature, w, h);
    let expected = argil::render::debug_view::curvature_color(2.0)[0] as f32;
    let sphere = pixel(&frame, 50, 50);
    assert!(
        (sphere[0] - expected).abs() < 1e-4 && sphere[1] == 0.0 && sphere[2] == 0.0,
        "sphere: {sphere:?}, expected red {expected}"
    );
    let i = ((50 * frame.width + 50) * 4) as usize;
    let shown = &frame.display[i..i + 3];
    let legend = argil::viewer::curvature_legend_color(2.0, 1.0).to_array();
    assert!(
        shown.iter().zip(&legend).all(|(a, b)| a.abs_diff(*b) <= 1),
        "display {shown:?}, legend {legend:?}"
    );
    let plane = pixel(&frame, 50, 95);
    assert_eq!(plane, [0.0, 0.0, 0.0, 1.0], "plane");
}

/// On a finite image the NaN highlight shows the shaded image unchanged: as the forward
/// pass shades it, which debug views draw with.
#[test]
fn nan_highlight_leaves_a_finite_image_alone() {
    let scene = Scene::default_scene();
    let shaded = render_forward(&scene, 96, 54);
    let highlighted = render_view(&scene, DebugView::NanHighlight, 96, 54);
    assert_eq!(shaded.hdr, highlighted.hdr);
}

/// Edits as the viewer makes them (odd values, a moved camera, other models), saved with
/// the viewer's Save and rendered by `argil render`, give the image the viewer rendered.
#[test]
fn saved_scene_renders_the_same_image_with_argil_render() {
    let dir = common::test_dir("save");
    let mut scene = every_lobe_scene(Subsurface::PreIntegrated);
    scene.camera.position = Vec3::new(0.3137, 1.7071, 7.1234567);
    scene.camera.target += Vec3::new(0.0123, -0.0456, 0.0789);
    scene.camera.fov_y_degrees = 33.3333;
    let ball = &mut scene.materials[scene.objects[0].material];
    ball.scatter_radius = 0.314_159_27;
    ball.scatter_color = Vec3::new(0.2, 0.666_666_7, 1.0);
    let m = &mut scene.materials[1];
    m.diffuse = DiffuseModel::Lambert;
    m.specular = SpecularModel::BlinnPhong;
    m.roughness = 0.123_456_79;
    m.base_color = Vec3::new(0.1, 0.7333, 0.05);
    scene.lights[0].intensity *= 1.37;
    scene.lights[0].position.x -= 0.777;

    let path = dir.join("edited.toml");
    argil::viewer::save::save(&scene, &argil::viewer::save::Document::default_scene(), &path, false).expect("save");
    let (w, h) = (192, 108);
    let shown = render(&scene, w, h);
    let out = dir.join("edited.png");
    let (width, height) = (w.to_string(), h.to_string());
    let o = argil(&[
        "render",
        path.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
        "--width",
        &width,
        "--height",
        &height,
    ]);
    assert!(
        o.status.success(),
        "argil render failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let rendered = image::open(&out).expect("read png").to_rgba8();
    let (rmse, max) = rgb_difference(&shown.display, rendered.as_raw());
    assert_eq!(max, 0, "the saved scene renders differently (RMSE {rmse})");
    assert_eq!(Scene::load(&path).expect("reload").materials, scene.materials);
}

/// A scene the viewer cannot show is an error naming the file, not a crash later.
#[test]
fn viewer_rejects_scenes_it_cannot_render() {
    let dir = common::test_dir("load");
    std::fs::write(dir.join("sky.hdr"), "not really an image").expect("write");
    let path = dir.join("map.toml");
    std::fs::write(
        &path,
        "[environment]\nkind = \"map\"\npath = \"sky.hdr\"\n[[objects]]\nmesh = \"builtin:cube\"\n",
    )
    .expect("write");
    let error = format!(
        "{:#}",
        argil::viewer::load_scene(&path).expect_err("the map does not decode")
    );
    assert!(error.contains("map.toml: environment.path = \"sky.hdr\""), "{error}");
    // Headers that read, then data that does not: found by decoding, after the scene file.
    std::fs::write(dir.join("sky.hdr"), b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 32 +X 64\n\x02\x02").expect("write");
    let error = format!(
        "{:#}",
        argil::viewer::load_scene(&path).expect_err("the map does not decode")
    );
    assert!(error.contains("map.toml: environment.path: environment map ") && error.contains("sky.hdr"), "{error}");
    std::fs::write(&path, "[[objects]]\nmesh = \"builtin:cube\"\nscale = -1\n").expect("write");
    let error = format!("{:#}", argil::viewer::load_scene(&path).expect_err("bad scale"));
    assert!(error.contains("map.toml") && error.contains("scale"), "{error}");
}

fn sampled_sphere(samples: u32) -> Scene {
    scene(&sampled_sphere_toml(samples))
}

/// Relative MSE over the pixels both frames cover: mean of (a − b)² / (b² + 10⁻³) per
/// channel (the 10⁻³ keeps black pixels from dominating).
fn rel_mse(a: &OffscreenFrame, b: &OffscreenFrame) -> f64 {
    let (sum, n) = a
        .hdr
        .chunks_exact(4)
        .zip(b.hdr.chunks_exact(4))
        .filter(|(p, q)| p[3] == 1.0 && q[3] == 1.0)
        .flat_map(|(p, q)| (0..3).map(move |c| (f64::from(p[c]), f64::from(q[c]))))
        .fold((0.0, 0usize), |(sum, n), (x, y)| {
            (sum + (x - y).powi(2) / (y * y + 1e-3), n + 1)
        });
    sum / n as f64
}

fn accumulated(scene: &Scene, frames: u32, size: u32) -> OffscreenFrame {
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(scene).expect("upload");
        let extent = vk::Extent2D {
            width: size,
            height: size,
        };
        renderer
            .render_accumulated(scene, &gpu_scene, extent, Some(1.0), frames)
            .expect("render")
    })
}

/// The running mean of a still view converges: after K frames of 16 lookups it is closer
/// to a single frame of 4096 lookups than after fewer, and closer than one frame of 16.
/// Measured on lavapipe (rel. MSE to N = 4096): 1 frame 2.9e-2, 4 frames 1.7e-2, 16 frames
/// 6.1e-3, 64 frames 7.6e-4. The first frames fall slower than Monte Carlo's 1/K because
/// they also read coarser mips (filtered importance sampling for their count so far), a
/// blur that the later frames' finer lookups average away.
#[test]
fn accumulated_frames_converge_to_a_high_sample_frame() {
    let size = 96;
    let reference = accumulated(&sampled_sphere(4096), 1, size);
    let noisy = sampled_sphere(16);
    let errors: Vec<(u32, f64)> = [1, 4, 16, 64]
        .into_iter()
        .map(|frames| (frames, rel_mse(&accumulated(&noisy, frames, size), &reference)))
        .collect();
    eprintln!("accumulated N = 16 vs one frame of N = 4096, rel. MSE: {errors:?}");
    for pair in errors.windows(2) {
        let ((k0, e0), (k1, e1)) = (pair[0], pair[1]);
        assert!(
            e1 < 0.75 * e0,
            "{k1} frames: {e1:.3e}, not below 3/4 of {k0} frames' {e0:.3e}"
        );
    }
    let (first, last) = (errors[0].1, errors[3].1);
    assert!(last < first / 10.0, "64 frames: {last:.3e}, one: {first:.3e}");
    // One frame is the single frame `argil render` draws.
    let single = render(&noisy, size, size);
    assert_eq!(single.hdr, accumulated(&noisy, 1, size).hdr);
}

/// Where every lookup is exact (Lambert cosine-sampled under a uniform environment: each
/// sample is ρL), every frame is the same and so is their mean: the weights sum to 1.
#[test]
fn accumulating_equal_frames_keeps_the_frame() {
    let uniform = scene(
        r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
[environment]
kind = "uniform"
radiance = [0.3, 0.5, 0.7]
reflection = "sampled"
samples = 8
[[objects]]
mesh = "builtin:sphere"
material = "m"
[materials.m]
base_color = [0.6, 0.4, 0.2]
diffuse = "lambert"
specular = "none"
"#,
    );
    let single = render(&uniform, 64, 64);
    let mean = accumulated(&uniform, 7, 64);
    let worst = single
        .hdr
        .iter()
        .zip(&mean.hdr)
        .map(|(a, b)| (a - b).abs() / a.abs().max(1e-3))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "the mean of equal frames differs by {worst} (relative)");
}

/// As the viewer draws: frames of a still view accumulate into one target after another;
/// moving the camera starts again, so the next frame is exactly the single frame of the
/// new camera. A view without the sampled reflection is not accumulated at all.
#[test]
fn accumulation_restarts_when_the_camera_moves() {
    let mut scene = sampled_sphere(8);
    let extent = vk::Extent2D { width: 64, height: 64 };
    let (frames, restarted) = gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&scene).expect("upload");
        let targets = [0, 1].map(|_| OffscreenTarget::new(&renderer.device, extent).expect("target"));
        renderer.accumulation = Accumulation::UpTo(1024);
        for target in targets.iter().cycle().take(5) {
            renderer.draw_offscreen(&scene, &gpu_scene, target, 1.0).expect("draw");
        }
        let frames = renderer.accumulated().map(|a| (a.frames, a.lookups()));
        // Up to 16 lookups (2 frames of 8), then the mean is held: the next frames show it unchanged.
        renderer.accumulation = Accumulation::UpTo(16);
        scene.camera.position.y += 0.25;
        let held: Vec<Vec<f32>> = targets
            .iter()
            .cycle()
            .take(4)
            .map(|target| {
                let gpu_ms = renderer.draw_offscreen(&scene, &gpu_scene, target, 1.0).expect("draw");
                renderer.read_offscreen(target, gpu_ms).expect("read").hdr
            })
            .collect();
        assert_eq!(renderer.accumulated().map(|a| a.frames), Some(2));
        assert!(held[0] != held[1], "the second frame joins the mean");
        assert!(held[1] == held[2] && held[2] == held[3], "a full mean changes");
        renderer.accumulation = Accumulation::UpTo(1024);
        scene.camera.position.x += 0.25;
        let gpu_ms = renderer
            .draw_offscreen(&scene, &gpu_scene, &targets[0], 1.0)
            .expect("draw");
        let restarted = renderer.read_offscreen(&targets[0], gpu_ms).expect("read");
        let after_move = renderer.accumulated().map(|a| a.frames);
        renderer.debug_view = DebugView::Normals;
        renderer
            .draw_offscreen(&scene, &gpu_scene, &targets[1], 1.0)
            .expect("draw");
        let normals = renderer.accumulated();
        renderer.debug_view = DebugView::Shaded;
        renderer.accumulation = Accumulation::Off;
        assert_eq!(after_move, Some(1), "the camera moved but the mean went on");
        assert_eq!(normals, None, "the normals view does not show the environment's noise");
        (frames, restarted)
    });
    assert_eq!(frames, Some((5, 40)));
    let fresh = render(&scene, extent.width, extent.height);
    assert_eq!(
        restarted.hdr, fresh.hdr,
        "the frame after the move is not the new camera's single frame"
    );
}

/// The exposure measure counts the frame's luminance as its f64 twin does (bins of log2 Y
/// over covered, lit pixels), read back when the slot comes round; the specular lobe alone,
/// nearly black at exposure 1, gets an exposure that shows 95% of its lit pixels below the
/// tone curve's shoulder.
#[test]
fn auto_exposure_measures_the_frame_it_follows() {
    use argil::brdf::tonemap::{luminance, START_COMPRESSION};
    use argil::render::exposure::{luminance_bin, BINS};
    let scene = every_lobe_scene(Subsurface::PreIntegrated);
    let extent = vk::Extent2D { width: 160, height: 90 };
    let (frame, histogram, exposure) = gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&scene).expect("upload");
        let target = OffscreenTarget::new(&renderer.device, extent).expect("target");
        renderer.debug_view = DebugView::Specular;
        renderer.measure_exposure = true;
        let mut gpu_ms = None;
        for _ in 0..2 {
            gpu_ms = renderer.draw_offscreen(&scene, &gpu_scene, &target, 1.0).expect("draw");
        }
        let frame = renderer.read_offscreen(&target, gpu_ms).expect("read");
        let measured = (
            renderer.luminance_histogram().map(<[u32]>::to_vec),
            renderer.auto_exposure(),
        );
        renderer.measure_exposure = false;
        renderer.draw_offscreen(&scene, &gpu_scene, &target, 1.0).expect("draw");
        assert_eq!(renderer.auto_exposure(), None, "measuring off forgets the histogram");
        renderer.debug_view = DebugView::Shaded;
        (frame, measured.0, measured.1)
    });
    let histogram = histogram.expect("the first frame's histogram is read back by the second");
    let lit: Vec<f64> = frame
        .hdr
        .chunks_exact(4)
        .filter(|p| p[3] == 1.0)
        .map(|p| luminance([p[0], p[1], p[2]].map(f64::from)))
        .filter(|y| *y > 0.0)
        .collect();
    let mut expected = vec![0u32; BINS];
    for y in &lit {
        expected[luminance_bin(*y)] += 1;
    }
    // fp32 log2 may put a pixel at a bin's edge into its neighbour.
    let moved: u32 = histogram.iter().zip(&expected).map(|(a, b)| a.abs_diff(*b)).sum();
    assert_eq!(histogram.iter().sum::<u32>() as usize, lit.len());
    assert!(moved <= 4, "GPU {histogram:?}\nCPU {expected:?}");
    let exposure = f64::from(exposure.expect("an exposure"));
    let below = lit.iter().filter(|y| *y * exposure <= START_COMPRESSION).count() as f64 / lit.len() as f64;
    eprintln!(
        "specular lobe: auto exposure {exposure:.2}, {:.1}% of lit pixels below the shoulder",
        below * 100.0
    );
    assert!(
        exposure > 2.0,
        "the specular lobe is dark at exposure 1: auto gives {exposure}"
    );
    // Half-stop bins: the 95th percentile is within a quarter stop of the bin's centre.
    assert!((0.9..=0.99).contains(&below), "{below}");
}

/// The largest difference in HDR radiance between `a` and `b` over columns `columns`, and
/// the mean one.
fn column_difference(a: &OffscreenFrame, b: &OffscreenFrame, columns: std::ops::Range<u32>) -> (f32, f64) {
    let (mut worst, mut sum, mut n) = (0.0f32, 0.0f64, 0u32);
    for y in 0..a.height {
        for x in columns.clone() {
            let (p, q) = (pixel(a, x, y), pixel(b, x, y));
            for c in 0..3 {
                let d = (p[c] - q[c]).abs();
                worst = worst.max(d);
                sum += f64::from(d);
                n += 1;
            }
        }
    }
    (worst, sum / f64::from(n.max(1)))
}

/// The viewer's split view draws the columns left of its divider as the scene is and the
/// columns right of it as the other configuration is, in one frame: each part equals the
/// same columns of the configuration's own frame, and the two configurations' frames
/// differ on both sides (so the test would see a part drawn in the wrong one).
///
/// Threshold: 1e-5 in radiance (≈ 0 after tone mapping). The parts are drawn by the same
/// pipelines from the same inputs as the whole frames, so they agree to the bit (0
/// measured); the configurations' frames differ by 1e-4 or more on average (4e-4 to 5e-4
/// measured for `seed` at this size, printed), 10 times the threshold.
#[test]
fn split_view_draws_each_half_in_its_configuration() {
    let mut scene = Scene::default_scene();
    // A split frame's ground reads the objects' occlusion and its environment light at every
    // pixel (its parts may light the ground differently), so the whole frames do too.
    scene.occlusion.ground_map = false;
    let render = |scene: &Scene, w, h| {
        gpu().exclusive(|renderer| {
            renderer.ground_environment = false;
            let frame = try_render(renderer, scene, w, h);
            renderer.ground_environment = true;
            frame.expect("render")
        })
    };
    let (w, h, x) = (160u32, 90u32, 70u32);
    // `seed`: the report's reflection; `report`: its horizon and subsurface as well.
    let mut seed = scene.clone();
    seed.environment.reflection_mut().expect("an environment").mode = argil::scene::ReflectionMode::Seed;
    let mut report = seed.clone();
    for m in &mut report.materials {
        (m.horizon, m.subsurface) = (argil::scene::Horizon::Seed, Subsurface::Seed);
    }
    let plain = render(&scene, w, h);
    for right in [seed, report] {
        let whole = render(&right, w, h);
        let split = gpu().exclusive(|renderer| {
            renderer.split = Some(argil::render::Split {
                materials: right.materials.clone(),
                environment: right.environment.clone(),
                x,
            });
            let frame = try_render(renderer, &scene, w, h);
            renderer.split = None;
            frame.expect("render split")
        });
        let (left_worst, _) = column_difference(&split, &plain, 0..x);
        let (right_worst, _) = column_difference(&split, &whole, x..w);
        let (_, left_apart) = column_difference(&plain, &whole, 0..x);
        let (_, right_apart) = column_difference(&plain, &whole, x..w);
        eprintln!(
            "split: left part vs the scene {left_worst:.2e}, right part vs the configuration {right_worst:.2e}; \
             the configurations differ by {left_apart:.2e} (left), {right_apart:.2e} (right) on average"
        );
        assert!(left_worst <= 1e-5 && right_worst <= 1e-5, "{left_worst} {right_worst}");
        assert!(left_apart >= 1e-4 && right_apart >= 1e-4, "{left_apart} {right_apart}");
    }
}

/// The viewer's reference of the current view compares the real-time frame with
/// `argil reference` of the same camera: a finite mean ꟻLIP, well below 1 for the same
/// scene (0.5 would be a wrong picture), and a heat map of the frame's size.
#[test]
fn reference_of_the_view_gives_a_finite_flip() {
    let scene = Scene::default_scene();
    let (w, h) = (80, 45);
    let frame = render(&scene, w, h);
    let settings = argil::reference::Settings {
        width: w,
        height: h,
        transport: argil::reference::Transport::Shadows,
        filter: argil::reference::Filter::Box,
        sampling: argil::reference::Sampling::Mis,
        subsurface: argil::reference::SubsurfaceTransport::Model,
        stop: argil::reference::Stop::Samples(16),
        seed: 1,
        max_depth: argil::reference::Settings::DEFAULT_MAX_DEPTH,
        max_time: None,
    };
    let compared = argil::viewer::reference_and_compare(&scene, &frame.hdr, &settings, 1.0, &()).expect("compare");
    let flip = compared.comparison.metrics.flip.mean;
    eprintln!(
        "reference of the view: mean ꟻLIP {flip:.4}, 16 spp, noise {:.2e}",
        compared.reference.noise
    );
    assert!(flip.is_finite() && flip > 0.0 && flip < 0.5, "{flip}");
    assert_eq!(compared.comparison.heat_map.dimensions(), (w, h));
}
