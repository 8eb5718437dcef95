//! What the viewer adds to rendering, checked on the shared device without a window: the
//! debug views of the forward pass, and saving an edited scene so that `argil render`
//! draws exactly what the viewer showed.

mod common;

use argil::render::{DebugView, OffscreenFrame};
use argil::scene::{DiffuseModel, Scene, SpecularModel, Subsurface};
use common::{argil, gpu, render, rgb_difference, scene, try_render};
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
/// somewhere: the report's wrap, or the ball's own pre-integrated scattering.
fn every_lobe_scene(subsurface: Subsurface) -> Scene {
    let mut scene = Scene::default_scene();
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
/// 1 - exp(-2 · 0.5) all over, which checks the vertex attribute and the vertex shader's
/// division by the object's scale; a plane is black.
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
    let expected = 1.0 - (-1.0f32).exp();
    let sphere = pixel(&frame, 50, 50);
    assert!(
        (sphere[0] - expected).abs() < 1e-4 && sphere[1] == 0.0 && sphere[2] == 0.0,
        "sphere: {sphere:?}, expected red {expected}"
    );
    let plane = pixel(&frame, 50, 95);
    assert_eq!(plane, [0.0, 0.0, 0.0, 1.0], "plane");
}

/// On a finite image the NaN highlight shows the shaded image unchanged.
#[test]
fn nan_highlight_leaves_a_finite_image_alone() {
    let scene = Scene::default_scene();
    let shaded = render(&scene, 96, 54);
    let highlighted = render_view(&scene, DebugView::NanHighlight, 96, 54);
    assert_eq!(shaded.hdr, highlighted.hdr);
}

/// Edits as the viewer makes them (odd values, a moved camera, other models), saved with
/// the viewer's Save and rendered by `argil render`, give the image the viewer rendered.
#[test]
fn saved_scene_renders_the_same_image_with_argil_render() {
    let dir = std::env::temp_dir().join(format!("argil-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
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
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene the viewer cannot show is an error naming the file, not a crash later.
#[test]
fn viewer_rejects_scenes_it_cannot_render() {
    let dir = std::env::temp_dir().join(format!("argil-view-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
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
    assert!(error.contains("sky.hdr"), "{error}");
    std::fs::write(&path, "[[objects]]\nmesh = \"builtin:cube\"\nscale = -1\n").expect("write");
    let error = format!("{:#}", argil::viewer::load_scene(&path).expect_err("bad scale"));
    assert!(error.contains("map.toml") && error.contains("scale"), "{error}");
    std::fs::remove_dir_all(&dir).ok();
}
