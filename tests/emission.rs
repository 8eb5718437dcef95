//! Emissive materials: `emission` (times `emission_map`) is added to the reflected light,
//! unchanged by lights, occlusion and shadows; an emission of 0 leaves the image bit for
//! bit; the renderer and `argil reference` see the same emitted light, and in `full`
//! transport the reference's emitters light their surroundings as the closed form says.

mod common;

use std::path::Path;

use argil::reference::integrator::CameraRays;
use argil::reference::{render, Filter, Reference, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use argil::scene::{MapSlot, Scene, DEFAULT_SCENE_TOML};
use common::test_dir;
use glam::{DVec3, Vec3};


fn settings(width: u32, height: u32, transport: Transport, samples: u32) -> Settings {
    Settings {
        width,
        height,
        transport,
        filter: Filter::Center,
        sampling: Sampling::Mis,
        subsurface: SubsurfaceTransport::Model,
        stop: Stop::Samples(samples),
        seed: 1,
        max_depth: Settings::DEFAULT_MAX_DEPTH,
        max_time: None,
    }
}

fn rgb(v: &[f32], i: usize) -> [f32; 3] {
    [v[4 * i], v[4 * i + 1], v[4 * i + 2]]
}

/// Keys of a surface that reflects nothing: all it shows is its emission.
const BLACK: &str = "diffuse = \"none\"\nspecular = \"none\"\nsubsurface = \"none\"\n";

/// The default scene (lights, studio, shadows, bounce, occlusion, maps) with an emission
/// map on every material and no emission renders bit for bit as without: the map is not
/// sampled and nothing is added. With the torus emitting, every pixel either stays bit for
/// bit (emission lights nothing in real time) or gains at most the emission (a pixel
/// partly covered gains its share).
#[test]
fn zero_emission_changes_nothing_and_emission_only_its_own_pixels() {
    let (width, height) = (160, 90);
    let plain = Scene::from_toml(DEFAULT_SCENE_TOML, "default", Path::new("")).expect("the default scene");
    let expected = common::render(&plain, width, height);
    let mut mapped = plain.clone();
    let map = plain
        .materials
        .iter()
        .find_map(|m| m.maps[MapSlot::Normal])
        .expect("a map");
    for m in &mut mapped.materials {
        m.maps[MapSlot::Emission] = Some(map);
        assert_eq!(m.emission, Vec3::ZERO);
    }
    let frame = common::render(&mapped, width, height);
    assert!(frame.hdr == expected.hdr, "an emission of 0 changed the image");

    let emission = [0.5f32, 0.25, 0.125];
    let mut glowing = plain.clone();
    let torus = glowing
        .materials
        .iter_mut()
        .find(|m| m.name == "terracotta")
        .expect("terracotta");
    torus.emission = Vec3::from(emission);
    let frame = common::render(&glowing, width, height);
    let mut changed = 0;
    for i in 0..(width * height) as usize {
        let (before, after) = (rgb(&expected.hdr, i), rgb(&frame.hdr, i));
        if before == after {
            continue;
        }
        changed += 1;
        for c in 0..3 {
            let gain = after[c] - before[c];
            let slack = 4.0 * f32::EPSILON * after[c];
            assert!(
                gain >= -slack && gain <= emission[c] + slack,
                "pixel {i} channel {c}: {} -> {}",
                before[c],
                after[c]
            );
        }
    }
    eprintln!("{changed} pixels show the torus's emission");
    assert!(changed > 1000, "{changed}");
}

/// A black emissive plane under a white ball, a point light with shadows, the studio with
/// screen-space and object occlusion and the ground bounce: every pixel where the plane
/// shows is its emission exactly, shadowed and occluded or not; every other pixel is as
/// with the plane not emitting, bit for bit.
#[test]
fn emission_is_unchanged_by_lights_occlusion_and_shadows() {
    let scene = |emission: [f32; 3]| {
        common::scene(&format!(
            r#"
[camera]
position = [0.0, 3.0, 4.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 40.0

[[lights]]
kind = "point"
position = [1.0, 4.0, 1.0]
intensity = [30.0, 30.0, 30.0]
radius = 0.3

[environment]
kind = "studio"

[shadows]
bounce = true

[occlusion]
enabled = true
objects = true

[[objects]]
mesh = "builtin:plane"
scale = 2.0
material = "ground"

[[objects]]
mesh = "builtin:sphere"
position = [0.0, 0.6, 0.0]
scale = 0.6
material = "clay"

[materials.ground]
{BLACK}emission = {emission:?}

[materials.clay]
base_color = [0.9, 0.9, 0.9]
"#
        ))
    };
    let (width, height) = (128, 96);
    let emission = [0.75f32, 0.5, 0.25];
    let dark = common::render(&scene([0.0; 3]), width, height);
    let frame = common::render(&scene(emission), width, height);
    let mut plane = 0;
    for i in 0..(width * height) as usize {
        // The black plane reflects nothing: exactly 0 where it covers the pixel.
        if dark.hdr[4 * i + 3] == 1.0 && rgb(&dark.hdr, i) == [0.0; 3] {
            plane += 1;
            assert_eq!(rgb(&frame.hdr, i), emission, "pixel {i}");
        } else {
            assert_eq!(rgb(&frame.hdr, i), rgb(&dark.hdr, i), "pixel {i}");
        }
    }
    eprintln!("{plane} pixels of the plane");
    assert!(plane > (width * height) as usize / 3, "{plane}");
}

/// With no light and no environment the image is the emission alone, which the renderer
/// and the reference (direct transport at pixel centres) compute alike: exactly for a
/// constant emission; through a constant sRGB emission map at strength 0.5 the reference
/// is the closed form to 1e-6 and the GPU within 2e-3 of it: lavapipe's sRGB decode is not
/// the exact EOTF (measured 6.4e-4, 7.2e-4 and 2.2e-4 for the texel's 200, 120 and 40).
/// Both spheres reflect white light, of which there is none.
#[test]
fn pure_emission_matches_the_reference() {
    let dir = test_dir("pure");
    image::RgbImage::from_pixel(8, 8, image::Rgb([200, 120, 40]))
        .save(dir.join("glow.png"))
        .expect("write png");
    let toml = r#"
[camera]
position = [0.0, 0.0, 6.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

[[objects]]
mesh = "builtin:sphere"
position = [-1.1, 0.0, 0.0]
material = "mapped"

[[objects]]
mesh = "builtin:sphere"
position = [1.1, 0.0, 0.0]
material = "constant"

[materials.mapped]
base_color = [1.0, 1.0, 1.0]
emission = [2.0, 1.0, 0.5]
[materials.mapped.emission_map]
texture = "glow.png"
strength = 0.5

[materials.constant]
base_color = [1.0, 1.0, 1.0]
emission = [0.25, 0.5, 1.0]
"#;
    let scene = Scene::from_toml(toml, "emission test", &dir).expect("test scene parses");
    let (width, height) = (128, 64);
    let gpu = common::render(&scene, width, height);
    let reference = render(&scene, &settings(width, height, Transport::Direct, 1), &()).expect("reference");
    // The map's texel decoded from sRGB, mixed halfway with 1.
    let decode = |v: f64| ((v / 255.0 + 0.055) / 1.055).powf(2.4);
    let glow = [(2.0, 200.0), (1.0, 120.0), (0.5, 40.0)].map(|(e, texel)| e * (1.0 + decode(texel)) / 2.0);
    let (mut exact, mut mapped, mut worst) = (0, 0, [0.0f64; 3]);
    for i in 0..(width * height) as usize {
        let covered = (gpu.hdr[4 * i + 3], reference.rgba[4 * i + 3]);
        if covered != (1.0, 1.0) {
            continue;
        }
        let (g, r) = (rgb(&gpu.hdr, i), rgb(&reference.rgba, i));
        if (i as u32 % width) >= width / 2 {
            assert_eq!((g, r), ([0.25, 0.5, 1.0], [0.25, 0.5, 1.0]), "pixel {i}");
            exact += 1;
        } else {
            mapped += 1;
            for c in 0..3 {
                let r = f64::from(r[c]);
                assert!((r - glow[c]).abs() < 1e-6 * glow[c], "pixel {i}: {r} where {}", glow[c]);
                worst[c] = worst[c].max((f64::from(g[c]) - r).abs() / r);
            }
        }
    }
    eprintln!("{exact} px exact, {mapped} px mapped, largest relative differences {worst:?}");
    assert!(exact > 1000 && mapped > 1000, "{exact}, {mapped}");
    assert!(worst.iter().all(|&w| w < 2e-3), "{worst:?}");
}

/// A white Lambert ground under a black ball of radius r emitting L, centred at height h,
/// no light and no environment: `full` transport lights the ground with the ball's light,
/// by the closed form of a sphere above a point's horizon, E = π L (r/d)² cos θ, so the
/// ground shows L r² h / d³ (the ground sees only the ball, the ball reflects nothing);
/// `direct` and `shadows` do not sample emitters, and leave it black. Tolerance: at 128
/// samples, a pixel's relative noise is about 0.6 (the ball covers ~5% of the cosine lobe),
/// the mean over ~4000 pixels' about 1%; 4% is 4σ.
#[test]
fn an_emissive_ball_lights_the_ground_in_full_transport() {
    let (radius, height, emission) = (0.5, 1.5, DVec3::new(1.0, 0.5, 0.25));
    let scene = common::scene(&format!(
        r#"
[camera]
position = [0.0, 2.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 40.0

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "ground"

[[objects]]
mesh = "builtin:sphere"
position = [0.0, {height}, 0.0]
scale = {radius}
material = "lamp"

[materials.ground]
base_color = [1.0, 1.0, 1.0]
diffuse = "lambert"
specular = "none"
subsurface = "none"

[materials.lamp]
{BLACK}emission = [{}, {}, {}]
"#,
        emission.x, emission.y, emission.z
    ));
    let (width, height_px) = (96, 72);
    let camera = CameraRays::new(&scene.camera, width, height_px);
    let centre = DVec3::new(0.0, height, 0.0);
    // Per pixel: how far its centre's ray passes from the ball's centre, and the ground
    // point it meets if it meets the ground clear of the ball's silhouette and of the
    // ground's edge.
    let (misses, ground): (Vec<f64>, Vec<Option<DVec3>>) = (0..width * height_px)
        .map(|i| {
            let (x, y) = (f64::from(i % width) + 0.5, f64::from(i / width) + 0.5);
            let (origin, dir) = camera.ray(x, y, width, height_px);
            let dir = dir.normalize();
            let along = (centre - origin).dot(dir);
            let miss = (origin + dir * along - centre).length();
            let t = -origin.y / dir.y;
            let p = origin + dir * t;
            let clear = miss > 1.05 * radius && t > 0.0 && p.x.abs() < 3.8 && p.z.abs() < 3.8;
            (miss, clear.then_some(p))
        })
        .unzip();
    let ball = (0..misses.len()).min_by(|&a, &b| misses[a].total_cmp(&misses[b])).expect("pixels");
    let ground_pixels = ground.iter().flatten().count();
    assert!(ground_pixels > 3000, "{ground_pixels}");

    let full = render(&scene, &settings(width, height_px, Transport::Full, 128), &()).expect("reference");
    let (mut measured, mut expected) = (DVec3::ZERO, DVec3::ZERO);
    for (i, p) in ground.iter().enumerate() {
        if let Some(p) = p {
            let d = (centre - *p).length();
            expected += emission * (radius * radius * height / (d * d * d));
            measured += pixel(&full, i);
        }
    }
    let ratio = measured / expected;
    eprintln!("full transport: the ground's mean radiance over the closed form's {ratio:.4}");
    assert!((ratio - DVec3::ONE).abs().max_element() < 0.04, "{ratio}");

    for transport in [Transport::Direct, Transport::Shadows] {
        let image = render(&scene, &settings(width, height_px, transport, 4), &()).expect("reference");
        for (i, p) in ground.iter().enumerate() {
            if p.is_some() {
                assert_eq!(pixel(&image, i), DVec3::ZERO, "{transport:?}: pixel {i}");
            }
        }
        assert_eq!(pixel(&image, ball), emission, "{transport:?}: the ball");
    }
}

fn pixel(image: &Reference, i: usize) -> DVec3 {
    let [r, g, b] = rgb(&image.rgba, i);
    DVec3::new(f64::from(r), f64::from(g), f64::from(b))
}
