//! Rendering tests on the shared device: goldens, and the validation layer's verdict on
//! every frame.

mod common;

use common::{assert_matches_golden, render, scene};

const SPHERE_NO_ENVIRONMENT: &str = r#"
[[lights]]
kind = "point"
position = [2.0, 2.0, 3.0]
intensity = [10.0, 10.0, 10.0]

[[objects]]
mesh = "builtin:sphere"
"#;

#[test]
fn background_is_transparent_and_black_without_environment() {
    let frame = render(&scene(SPHERE_NO_ENVIRONMENT), 32, 32);
    assert_eq!(&frame.hdr[0..4], &[0.0, 0.0, 0.0, 0.0], "top-left pixel is background");
}

/// Solids seen from outside have their back faces culled; from inside, or with the near
/// plane cutting into them, their back faces are what the camera sees, so they are drawn.
#[test]
fn solids_are_seen_from_inside_and_through_the_near_plane() {
    for (what, camera) in [
        ("inside", "position = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, -1.0]"),
        // The eye is outside, 0.02 from the surface, but the near plane (0.05) is inside.
        ("grazing", "position = [0.0, 0.0, 1.02]\ntarget = [0.0, 0.0, 0.0]"),
    ] {
        let frame = render(
            &scene(&format!(
                "[camera]\n{camera}\n\n[[lights]]\nkind = \"point\"\nposition = [0.0, 0.5, 0.0]\n\
                 intensity = [1.0, 1.0, 1.0]\n\n[[objects]]\nmesh = \"builtin:sphere\"\n"
            )),
            16,
            16,
        );
        let centre = 4 * (8 * 16 + 8);
        assert_eq!(frame.hdr[centre + 3], 1.0, "{what}: the sphere's inside covers the centre");
        if what == "inside" {
            assert!(frame.hdr.chunks_exact(4).all(|p| p[3] == 1.0), "inside: every pixel sees the sphere");
        }
    }
}

/// The bench's floor shows the interpolated normal ·0.5 + 0.5 with coverage in alpha, and
/// turning it off gives the shaded frame back.
#[test]
fn the_floor_writes_the_interpolated_normal_and_turns_off() {
    let sphere = scene(SPHERE_NO_ENVIRONMENT);
    let (floor, shaded, again) = common::gpu().exclusive(|renderer| {
        let shaded = common::try_render(renderer, &sphere, 33, 33).expect("render");
        renderer.floor = true;
        let floor = common::try_render(renderer, &sphere, 33, 33);
        renderer.floor = false;
        let again = common::try_render(renderer, &sphere, 33, 33).expect("render");
        (floor.expect("render the floor"), shaded, again)
    });
    // The centre pixel sees the sphere's pole facing the camera on +z.
    let centre = 4 * (16 * 33 + 16);
    let expected = [0.5, 0.5, 1.0, 1.0];
    for (c, e) in floor.hdr[centre..centre + 4].iter().zip(expected) {
        assert!(
            (c - e).abs() < 0.02,
            "floor centre {:?}",
            &floor.hdr[centre..centre + 4]
        );
    }
    assert_eq!(&floor.hdr[0..4], &[0.0; 4], "the background stays uncovered");
    assert_ne!(floor.hdr, shaded.hdr);
    assert_eq!(again.hdr, shaded.hdr, "the floor leaves no trace once off");
}

/// A frame kept as linear radiance (what an EXR stores) records no display transform, and
/// its radiance is the same, bit for bit, as the one drawn with it.
#[test]
fn linear_frames_skip_the_tone_map() {
    let sphere = scene(SPHERE_NO_ENVIRONMENT);
    let extent = ash::vk::Extent2D { width: 24, height: 16 };
    let (linear, displayed, counts) = common::gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&sphere).expect("upload");
        let before = renderer.tonemap_records();
        let linear = renderer.render_accumulated(&sphere, &gpu_scene, extent, None, 1);
        let after_linear = renderer.tonemap_records();
        let displayed = renderer.render_accumulated(&sphere, &gpu_scene, extent, Some(1.0), 1);
        let counts = [before, after_linear, renderer.tonemap_records()];
        (
            linear.expect("linear frame"),
            displayed.expect("displayed frame"),
            counts,
        )
    });
    assert_eq!(counts[1], counts[0], "the linear frame ran the tone map");
    assert_eq!(counts[2], counts[1] + 1, "the displayed frame ran it once");
    assert!(linear.display.is_empty());
    assert_eq!(displayed.display.len(), 4 * 24 * 16);
    assert_eq!(linear.hdr, displayed.hdr);
    assert!(linear.gpu_ms.is_none_or(|ms| ms.iter().all(|t| t.is_finite())));
}

#[test]
fn default_scene_matches_golden() {
    let frame = render(&argil::scene::Scene::default_scene(), 320, 180);
    assert_matches_golden(&frame, "default-scene");
}

#[test]
fn cook_torrance_ggx_and_beckmann_match_golden() {
    for (distribution, roughness) in [("ggx", 0.3), ("beckmann", 0.3), ("ggx", 0.8)] {
        let text = format!(
            r#"
[camera]
position = [0.0, 0.5, 4.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 35.0

[[lights]]
kind = "point"
position = [-2.0, 3.0, 3.0]
intensity = [20.0, 20.0, 20.0]

[environment]
kind = "uniform"
radiance = [0.05, 0.05, 0.06]

[[objects]]
mesh = "builtin:sphere"
material = "clay"

[[objects]]
mesh = "builtin:plane"
position = [0.0, -1.0, 0.0]
scale = 4.0
material = "ground"

[materials.clay]
base_color = [0.7, 0.35, 0.2]
diffuse = "lambert"
specular = "cook-torrance"
distribution = "{distribution}"
roughness = {roughness}
f0 = 0.04

[materials.ground]
base_color = [0.5, 0.5, 0.5]
diffuse = "lambert"
specular = "none"
"#
        );
        let frame = render(&scene(&text), 160, 120);
        assert_matches_golden(&frame, &format!("cook-torrance-{distribution}-{roughness}"));
    }
}

/// The test harness itself: a frame that breaks a Vulkan rule must be reported, or no
/// other test's "no validation error" means anything.
#[test]
fn validation_errors_are_detected() {
    use ash::vk;
    let gpu = common::gpu();
    let report = gpu.device.validation().expect("validation on");
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        gpu.exclusive(|_| {
            // A zero-sized buffer is invalid usage (VUID-VkBufferCreateInfo-size-00912).
            let info = vk::BufferCreateInfo::default()
                .size(0)
                .usage(vk::BufferUsageFlags::UNIFORM_BUFFER);
            if let Ok(buffer) = unsafe { gpu.device.handle.create_buffer(&info, None) } {
                unsafe { gpu.device.handle.destroy_buffer(buffer, None) };
            }
        })
    }));
    assert!(
        result.is_err(),
        "the invalid call was not reported as a validation error"
    );
    assert!(report.error_count() > 0);
}

/// A plasticine ball close up: the clay-lumps normal map with the fingerprint detail map
/// blended over it (RNM), under a grazing light that brings the relief out; and the same
/// with the report's eq. 16 blend, for comparison.
#[test]
fn normal_and_detail_maps_match_golden() {
    for blend in ["rnm", "seed"] {
        let text = format!(
            r#"
[camera]
position = [0.0, 0.0, 4.2]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [-3.0, 1.0, 1.0]
intensity = [12.0, 12.0, 12.0]

[[objects]]
mesh = "builtin:sphere"
material = "clay"

[materials.clay]
preset = "plasticine"
detail_blend = "{blend}"
"#
        );
        let frame = render(&scene(&text), 160, 160);
        assert_matches_golden(&frame, &format!("plasticine-detail-{blend}"));
    }
}

/// The report's Cook-Torrance bug (its figure 5) against argil's treatment of the shading
/// normal's horizon, as an image pair: a normal-mapped sphere lit from the side, once with
/// `horizon = "seed"` (the report's i = d + s with the specular zeroed where n·l ≤ 0) and
/// once with the default `smooth` (f·cos with Smith masking, a view-facing normal and the
/// terminator's shadowing). A harsh cutoff is a step from exactly black to lit: the test
/// measures the p99 of what pixels beside black ones hold, relative to the p99 radiance.
#[test]
fn horizon_before_and_after() {
    let mut steps = Vec::new();
    for horizon in ["seed", "smooth"] {
        let text = format!(
            r#"
[camera]
position = [0.0, 0.0, 4.2]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [-4.0, 0.5, -1.0]
intensity = [20.0, 20.0, 20.0]

[[objects]]
mesh = "builtin:sphere"
material = "clay"

[materials.clay]
base_color = [0.6, 0.36, 0.17]
diffuse = "lambert"
specular = "cook-torrance"
roughness = 0.3
f0 = 0.04
horizon = "{horizon}"

[materials.clay.normal_map]
texture = "builtin:clay-lumps"
strength = 1.5
uv_scale = [2.0, 1.0]
"#
        );
        let frame = render(&scene(&text), 200, 200);
        assert_matches_golden(&frame, &format!("horizon-{horizon}"));
        let (w, h) = (frame.width as usize, frame.height as usize);
        let luminance = |x: usize, y: usize| {
            let p = &frame.hdr[(y * w + x) * 4..][..4];
            (p[3] == 1.0).then(|| p[0] + p[1] + p[2])
        };
        let mut lit: Vec<f32> = (0..w * h)
            .filter_map(|i| luminance(i % w, i / w))
            .filter(|&l| l > 0.0)
            .collect();
        lit.sort_by(f32::total_cmp);
        let p99 = lit[lit.len() * 99 / 100];
        // What a pixel beside an exactly black one holds: ~0 where the lit side fades out.
        let mut beside_black = Vec::new();
        for y in 0..h - 1 {
            for x in 0..w - 1 {
                for (a, b) in [((x, y), (x + 1, y)), ((x, y), (x, y + 1))] {
                    if let (Some(la), Some(lb)) = (luminance(a.0, a.1), luminance(b.0, b.1)) {
                        if la == 0.0 || lb == 0.0 {
                            beside_black.push(la.max(lb) / p99);
                        }
                    }
                }
            }
        }
        beside_black.sort_by(f32::total_cmp);
        let step = beside_black[beside_black.len() * 99 / 100];
        eprintln!("horizon = {horizon}: p99 of the steps from black, relative to the p99 radiance: {step:.4}");
        steps.push(step);
    }
    // Measured on lavapipe: 4.0e-3 (seed) against 0 (smooth).
    let (seed, smooth) = (steps[0], steps[1]);
    assert!(seed > 2e-3, "the report's cutoff should show as a step: {seed:.2e}");
    assert!(
        smooth < 1e-4 && smooth * 100.0 < seed,
        "the smooth horizon still steps: {smooth:.2e} vs {seed:.2e}"
    );
}

/// The subsurface models side by side, under a light from the left: none, the report's
/// wrap (eq. 18), the energy-conserving wrap, then the pre-integrated model on a ball of
/// radius 0.5 and on one of 0.25, where the same material scatters twice as far relative
/// to the curvature and so glows further past the terminator.
#[test]
fn subsurface_models_match_golden() {
    let mut text = String::from(
        r#"
[camera]
position = [0.0, 0.0, 5.5]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 22.0

[[lights]]
kind = "point"
position = [-20.0, 3.0, 4.0]
intensity = [1200.0, 1200.0, 1200.0]
# The spheres stand in a row along the light: each would shadow the next, hiding the
# models this compares.
shadows = false
"#,
    );
    let models = [
        "none",
        "seed",
        "energy-conserving-wrap",
        "pre-integrated",
        "pre-integrated",
    ];
    for (i, model) in models.iter().enumerate() {
        let scale = if i == 4 { 0.25 } else { 0.5 };
        text += &format!(
            r#"
[[objects]]
mesh = "builtin:sphere"
position = [{x:.1}, 0.0, 0.0]
scale = {scale}
material = "clay-{i}"

[materials.clay-{i}]
base_color = [0.8, 0.5, 0.3]
diffuse = "lambert"
roughness = 0.5
subsurface = "{model}"
wrap = 0.5
wrap_width = 0.4
wrap_color = [0.9, 0.4, 0.2]
wrap_intensity = 0.5
scatter_color = [1.0, 0.5, 0.25]
scatter_radius = 0.15
"#,
            x = -2.4 + 1.2 * i as f64,
        );
    }
    let frame = render(&scene(&text), 480, 160);
    assert_matches_golden(&frame, "subsurface-models");
}

/// On a flat surface (curvature 0) the pre-integrated model is Lambert's cosine: the
/// table's t = 0 row holds max(0, n·l) at texel centres with one on n·l = 0, so only
/// rounding separates it from no subsurface term at all.
#[test]
fn pre_integrated_scattering_vanishes_on_flat_surfaces() {
    let frames = ["none", "pre-integrated"].map(|model| {
        let text = format!(
            r#"
[camera]
position = [0.0, 3.0, 3.0]
target = [0.0, 0.0, 0.0]

[[lights]]
kind = "point"
position = [-1.0, 0.5, 0.0]
intensity = [5.0, 5.0, 5.0]

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "clay"

[materials.clay]
preset = "polymer-clay"
subsurface = "{model}"
scatter_radius = 1.0
"#
        );
        render(&scene(&text), 96, 96)
    });
    let worst = frames[0]
        .hdr
        .iter()
        .zip(&frames[1].hdr)
        .map(|(a, b)| f64::from((a - b).abs()) / f64::from(a.abs()).max(1e-3))
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "max relative difference {worst:.2e}");
    assert!(frames[0].hdr.chunks_exact(4).filter(|p| p[3] == 1.0).count() > 4000);
}

/// A plasticine ball seen close up, where its normal and detail maps are magnified: pixels
/// beside a triangle edge must not stand out from their neighbours more than pixels inside
/// the triangles do. Each pixel's contrast is |L − mean of its 4 neighbours| in luminance;
/// edge pixels lie within 1 pixel of a front-facing triangle edge, interior ones 3 or more
/// pixels from every edge.
#[test]
fn normal_maps_show_no_triangle_edges() {
    let scene = scene(
        r#"
[camera]
position = [0.0, 0.0, 2.2]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[lights]]
kind = "point"
position = [-3.0, 2.0, 2.0]
intensity = [14.0, 14.0, 14.0]

[[objects]]
mesh = "builtin:sphere"
material = "clay"

[materials.clay]
preset = "plasticine"
"#,
    );
    let (w, h) = (400, 400);
    let frame = render(&scene, w, h);
    let (w, h) = (w as usize, h as usize);

    // Distance in pixels (Chebyshev, capped at 3) from the nearest front-facing edge.
    let mut distance = vec![3usize; w * h];
    let object = &scene.objects[0];
    let mesh = &scene.meshes[object.mesh];
    let model = object.model_matrix();
    let view_proj = scene.camera.projection(w as f32 / h as f32) * scene.camera.view();
    let world = |i: u32| model.transform_point3(glam::Vec3::from(mesh.vertices[i as usize].position));
    for triangle in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| world(triangle[k]));
        if (b - a).cross(c - a).dot(scene.camera.position - a) <= 0.0 {
            continue;
        }
        for (p, q) in [(a, b), (b, c), (c, a)] {
            let steps = 400;
            for s in 0..=steps {
                let clip = view_proj * p.lerp(q, s as f32 / steps as f32).extend(1.0);
                let (x, y) = (
                    (clip.x / clip.w * 0.5 + 0.5) * w as f32,
                    (clip.y / clip.w * 0.5 + 0.5) * h as f32,
                );
                let (x, y) = (x.floor() as isize, y.floor() as isize);
                for dy in -2..=2isize {
                    for dx in -2..=2isize {
                        let (px, py) = (x + dx, y + dy);
                        if (0..w as isize).contains(&px) && (0..h as isize).contains(&py) {
                            let d = &mut distance[py as usize * w + px as usize];
                            *d = (*d).min(dx.unsigned_abs().max(dy.unsigned_abs()));
                        }
                    }
                }
            }
        }
    }

    let luminance = |x: usize, y: usize| {
        let p = &frame.hdr[(y * w + x) * 4..][..4];
        (p[3] == 1.0).then(|| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
    };
    let (mut edge, mut interior) = (Vec::new(), Vec::new());
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let around = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)].map(|(x, y)| luminance(x, y));
            let (Some(centre), [Some(l), Some(r), Some(u), Some(d)]) = (luminance(x, y), around) else {
                continue;
            };
            let contrast = (centre - (l + r + u + d) / 4.0).abs();
            match distance[y * w + x] {
                0 | 1 => edge.push(contrast),
                3 => interior.push(contrast),
                _ => {}
            }
        }
    }
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (edge_mean, interior_mean) = (mean(&edge), mean(&interior));
    eprintln!(
        "mean contrast: {edge_mean:.3e} beside edges ({} pixels), {interior_mean:.3e} inside triangles ({} pixels)",
        edge.len(),
        interior.len()
    );
    // Measured on lavapipe: 8.7e-4 beside edges, 8.4e-4 inside; 1.46e-3 beside edges when the
    // maps' uvs were transformed per fragment (see forward.vert).
    assert!(edge.len() > 10_000 && interior.len() > 10_000);
    assert!(
        edge_mean < 1.2 * interior_mean,
        "triangle edges stand out: mean contrast {edge_mean:.3e} beside them, {interior_mean:.3e} inside"
    );
}

/// The shaded image's pipelines come from forward.frag without its debug views, the
/// generic pipeline from the whole of it with the debug view read from the uniforms: the
/// default scene is the same image through both, with its soft shadows at the pixels or
/// at the vertices (`[shadows] per_vertex`, which the generic pipeline reads there for
/// every light).
#[test]
fn the_shaded_module_and_the_generic_pipeline_draw_the_same_image() {
    let mut scene = argil::scene::Scene::default_scene();
    for per_vertex in [false, true] {
        scene.shadow_per_vertex = per_vertex;
        let [shaded, generic] = [false, true].map(|generic| {
            common::gpu().exclusive(|renderer| {
                renderer.generic = generic;
                let frame = common::try_render(renderer, &scene, 160, 90);
                renderer.generic = false;
                frame.expect("render")
            })
        });
        let (rmse, max) = common::rgb_difference(&shaded.display, &generic.display);
        // The generic pipeline's branches on uniforms round a few pixels one code value apart
        // (RMSE 0.005); a term that one module lacks moves lit pixels by several.
        assert!(rmse < 0.05 && max <= 1, "per vertex {per_vertex}: RMSE {rmse}, max channel difference {max}");
    }
}

/// A start uploads the default scene with stand-ins for its builtin maps, draws a warm-up
/// frame of a few pixels with them while the maps are made, uploads the maps and draws
/// the frame: that frame is the frame of the scene uploaded whole, bit for bit, so the
/// material sets read the maps and nothing the warm-up made depends on the stand-ins or
/// on its size; as plain, and with MSAA and screen-space occlusion.
#[test]
fn a_frame_after_a_warm_up_with_stand_ins_is_the_frame_of_the_whole_scene() {
    use argil::render::warm_up::warm_up;
    use argil::scene::{PendingMaps, Scene};
    let extent = ash::vk::Extent2D { width: 160, height: 90 };
    let plain = |_: &mut Scene| {};
    let multisampled = |scene: &mut Scene| {
        scene.antialiasing.msaa = 4;
        scene.occlusion.enabled = true;
    };
    for configure in [&plain as &dyn Fn(&mut Scene), &multisampled] {
        let [whole, pending] = [false, true].map(|pending| {
            common::gpu().exclusive(|renderer| {
                if !pending {
                    let mut scene = Scene::default_scene();
                    configure(&mut scene);
                    let gpu = renderer.upload(&scene).expect("upload");
                    return renderer.render_accumulated(&scene, &gpu, extent, None, 1).expect("render");
                }
                let (mut scene, maps) = PendingMaps::load(None).expect("the default scene");
                configure(&mut scene);
                let mut gpu = renderer.upload(&scene).expect("upload");
                warm_up(renderer, &mut scene, &mut gpu, maps, false, extent).expect("warm-up");
                renderer.render_accumulated(&scene, &gpu, extent, None, 1).expect("render")
            })
        });
        assert!(whole.hdr == pending.hdr, "the frames differ");
    }
}
