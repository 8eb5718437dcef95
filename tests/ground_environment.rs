//! The ground's environment map (src/render/ground_maps.rs, shaders/ground_environment.comp):
//! on lavapipe with the validation layer on, every frame charged to its test.

mod common;

use argil::render::Renderer;
use argil::scene::{Environment, Scene};
use common::{gpu, percentiles, scene, try_render, CountedFrames};

const SIZE: (u32, u32) = (320, 180);

/// The default scene: its ground, of roughness 0.8 and no maps, under the studio.
fn default_scene() -> Scene {
    scene(argil::scene::DEFAULT_SCENE_TOML)
}

/// `s`'s frame with the ground's environment light read from its map, the same without,
/// and how many times the first made the map.
fn frames(s: &Scene) -> (Vec<f32>, Vec<f32>, u64) {
    gpu().exclusive(|renderer| {
        let before = renderer.ground_environment_renders();
        let with = try_render(renderer, s, SIZE.0, SIZE.1).expect("render").hdr;
        let made = renderer.ground_environment_renders() - before;
        renderer.ground_environment = false;
        let without = try_render(renderer, s, SIZE.0, SIZE.1);
        renderer.ground_environment = true;
        (with, without.expect("render").hdr, made)
    })
}

/// Each channel's difference of `a` from `b` relative to `b`, where any differs.
fn relative_differences(a: &[f32], b: &[f32]) -> Vec<f64> {
    (a.chunks(4).zip(b.chunks(4)))
        .filter(|(x, y)| x[..3] != y[..3])
        .flat_map(|(x, y)| (0..3).map(|c| ((x[c] - y[c]) / y[c].max(1e-6)).abs() as f64).collect::<Vec<_>>())
        .collect()
}

/// The default scene's ground reads the split sum from the map: one computation, and the
/// ground's pixels within what the bilinear reads of the map's fp32 texels leave of the
/// light at each pixel. Measured: median 1.8e-5, p99 1.1e-3, max 3.8e-3. Most of the tail
/// is where the split sum's tap count (prefiltered_taps) steps from one pixel to the next,
/// a step the map's reads spread over a texel: with the count fixed at eight, the p99 is
/// 4.1e-4 and the max 1.9e-3.
#[test]
fn the_grounds_environment_map_is_the_split_sum_at_each_pixel() {
    let (with, without, made) = frames(&default_scene());
    assert_eq!(made, 1);
    let differences = relative_differences(&with, &without);
    // The ground covers about half the frame.
    assert!(differences.len() > 3 * 20_000, "{} channels differ", differences.len());
    let (median, p99, max) = percentiles(differences);
    assert!(median < 1e-4 && p99 < 2e-3 && max < 6e-3, "median {median:e}, p99 {p99:e}, max {max:e}");
}

/// A ground the map cannot stand for finds its environment light at its pixels: the same
/// frame, bit for bit, without a computation.
#[test]
fn a_smooth_ground_finds_its_environment_light_at_its_pixels() {
    let mut s = default_scene();
    let ground = s.ground_index().expect("a ground");
    let material = s.objects[ground].material;
    s.materials[material].roughness = 0.3;
    let (with, without, made) = frames(&s);
    assert_eq!(made, 0);
    assert!(with == without);
}

/// The map is made when what it is made of changes, not every frame: once for two frames
/// of the same scene, even with a floor frame between (`CountedFrames::new`), not when the
/// camera or a light moves, again when the ground's material or the environment changes.
#[test]
fn the_grounds_environment_map_is_computed_only_when_the_scene_changes() {
    let mut s = default_scene();
    gpu().exclusive(|renderer| {
        let frames = CountedFrames::new(renderer, &s, Renderer::ground_environment_renders);
        s.camera.position.x += 0.5;
        s.lights[0].position.y += 0.5;
        assert_eq!(frames.draw(renderer, &s), 1);
        let ground = s.ground_index().expect("a ground");
        let material = s.objects[ground].material;
        s.materials[material].roughness = 0.9;
        assert_eq!(frames.draw(renderer, &s), 2);
        if let Environment::Studio { rotation_degrees, .. } = &mut s.environment {
            *rotation_degrees += 30.0;
        }
        assert_eq!(frames.draw(renderer, &s), 3);
    });
}
