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
            let info = vk::BufferCreateInfo::default().size(0).usage(vk::BufferUsageFlags::UNIFORM_BUFFER);
            if let Ok(buffer) = unsafe { gpu.device.handle.create_buffer(&info, None) } {
                unsafe { gpu.device.handle.destroy_buffer(buffer, None) };
            }
        })
    }));
    assert!(result.is_err(), "the invalid call was not reported as a validation error");
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
