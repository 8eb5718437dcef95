//! The property maps (roughness, metallic, occlusion, scatter): each multiplies its
//! material value as glTF 2.0 defines it, a map of constant 1 is no map, one packed
//! occlusion-roughness-metallic texture loads once, a missing file is a clear error, and
//! the renderer and `argil reference` agree on a mapped sphere; the occlusion map
//! micro-shadows the point lights.

mod common;

use std::path::Path;

use argil::brdf::occlusion::micro_shadowing;
use argil::reference::integrator::CameraRays;
use argil::reference::{render, Filter, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use argil::scene::{MapSlot, Scene};
use common::{argil, percentiles, test_dir};
use glam::DVec3;


/// A 64² RGB8 PNG whose texel at column x is `texel(x)`.
fn write_png(path: &Path, texel: impl Fn(u32) -> [u8; 3]) {
    image::RgbImage::from_fn(64, 64, |x, _| image::Rgb(texel(x)))
        .save(path)
        .expect("write png");
}

/// Reference settings that evaluate the frame's own model: direct light at each pixel's
/// centre, one sample.
fn direct_at_pixel_centres(width: u32, height: u32) -> Settings {
    Settings {
        width,
        height,
        transport: Transport::Direct,
        filter: Filter::Center,
        sampling: Sampling::Mis,
        subsurface: SubsurfaceTransport::Model,
        stop: Stop::Samples(1),
        seed: 1,
        max_depth: Settings::DEFAULT_MAX_DEPTH,
        max_time: None,
    }
}

/// The keys of a glossy, half-metallic, wrapped clay.
const CLAY: &str = "diffuse = \"lambert\"\nsubsurface = \"energy-conserving-wrap\"\nwrap = 0.5\n\
                    scatter_color = [1.0, 0.6, 0.4]\nmetallic = 0.5\n";

/// The environment of most tests: uniform, so a Lambert lobe's light from it is exact at
/// one sample in the reference.
const UNIFORM: &str = "[environment]\nkind = \"uniform\"\nradiance = [0.2, 0.25, 0.3]\n";

/// A sphere under a point light and `environment`; `material` is `[materials.m]`'s keys
/// (and map tables) after its base colour.
fn sphere(environment: &str, material: &str, dir: &Path) -> Scene {
    let toml = format!(
        r#"
[camera]
position = [0.0, 0.0, 5.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 30.0

{environment}

[[lights]]
kind = "point"
position = [2.0, 2.0, 3.0]
intensity = [12.0, 12.0, 12.0]

[antialiasing]
specular = false

[[objects]]
mesh = "builtin:sphere"
material = "m"

[materials.m]
base_color = [0.8, 0.5, 0.3]
{material}
"#
    );
    Scene::from_toml(&toml, "maps test", dir).expect("test scene parses")
}

fn luminance(hdr: &[f32], i: usize) -> f64 {
    (0..3).map(|c| f64::from(hdr[4 * i + c])).sum::<f64>() / 3.0
}

/// Each half of a two-valued roughness map renders as the uniform material of that
/// roughness: the map multiplies `roughness` by its green channel. Tolerance: the GPU
/// multiplies 0.8 by the UNORM texel 128/255 in f32 where the uniform material holds the
/// f64 product rounded to f32, a difference of an ulp of roughness (relative radiance
/// change < 1e-5); 1e-3 relative leaves room for that and nothing else. Pixels near the
/// map's two edges blend both halves (bilinear and mip filtering) and match neither.
#[test]
fn each_half_of_a_roughness_map_renders_as_its_uniform_roughness() {
    let dir = test_dir("halves");
    write_png(
        &dir.join("halves.png"),
        |x| if x < 32 { [0, 255, 0] } else { [0, 128, 0] },
    );
    let material = |roughness: f64, map: &str| format!("{CLAY}roughness = {roughness}\n{map}");
    let map = "[materials.m.roughness_map]\ntexture = \"halves.png\"\n";
    let mapped = common::render(&sphere(UNIFORM, &material(0.8, map), &dir), 128, 128);
    let rough = common::render(&sphere(UNIFORM, &material(0.8, ""), &dir), 128, 128);
    let smooth_value = 0.8 * 128.0 / 255.0;
    let smooth = common::render(&sphere(UNIFORM, &material(smooth_value, ""), &dir), 128, 128);
    let (mut differing, mut as_rough, mut as_smooth) = (0, 0, 0);
    for i in 0..128 * 128 {
        let (m, r, s) = (
            luminance(&mapped.hdr, i),
            luminance(&rough.hdr, i),
            luminance(&smooth.hdr, i),
        );
        if (r - s).abs() < 0.05 * r.max(s) {
            continue;
        }
        differing += 1;
        let close = |x: f64| (m - x).abs() <= 1e-3 * x + 1e-6;
        as_rough += usize::from(close(r));
        as_smooth += usize::from(close(s));
    }
    eprintln!("{differing} pixels tell the roughnesses apart: {as_rough} as 0.8, {as_smooth} as {smooth_value:.4}");
    assert!(differing > 2000, "{differing}");
    assert!(
        as_rough + as_smooth >= differing * 9 / 10,
        "{as_rough} + {as_smooth} of {differing}"
    );
    assert!(
        as_rough > differing / 5 && as_smooth > differing / 5,
        "{as_rough}, {as_smooth}"
    );
}

/// Property maps of constant 1 (one white texture as the packed occlusion-roughness-
/// metallic map and as the scatter map) leave the image as without maps, and the texture
/// loads once; a map of 0.5 changes the image. Roughness, metallic and scatter maps of 1
/// leave every pixel bit for bit. The occlusion map's product with the environment's light
/// is exact too, but it changes how the compiler fuses the sum of the point lights' and the
/// environment's light into multiply-adds: measured, 1 f32 ulp (1.4e-7 relative) on some
/// channels; the bound is 2 ulp. Drawn forward: the scatter map keeps its object out of
/// the G-buffer, which matches the forward pass to the last bits alone.
#[test]
fn property_maps_of_one_are_no_maps() {
    let dir = test_dir("ones");
    write_png(&dir.join("white.png"), |_| [255; 3]);
    write_png(&dir.join("grey.png"), |_| [128; 3]);
    let maps = |texture: &str, keys: &[&str]| {
        keys.iter()
            .map(|key| format!("[materials.m.{key}]\ntexture = \"{texture}\"\n"))
            .collect::<String>()
    };
    let exact = ["roughness_map", "metallic_map", "scatter_map"];
    let all = ["roughness_map", "metallic_map", "scatter_map", "occlusion_map"];
    let plain = common::render_forward(&sphere(UNIFORM, CLAY, &dir), 96, 96);
    let white = sphere(UNIFORM, &format!("{CLAY}{}", maps("white.png", &all)), &dir);
    assert_eq!(white.textures.len(), 1, "one texture serves the four maps");
    let m = &white.materials[0];
    for slot in [
        MapSlot::Roughness,
        MapSlot::Metallic,
        MapSlot::Occlusion,
        MapSlot::Scatter,
    ] {
        assert_eq!(m.maps[slot].map(|map| map.texture), Some(0), "{slot:?}");
    }
    let white_exact = common::render_forward(
        &sphere(UNIFORM, &format!("{CLAY}{}", maps("white.png", &exact)), &dir),
        96,
        96,
    );
    assert!(
        white_exact.hdr == plain.hdr,
        "roughness, metallic and scatter maps of 1 changed the image"
    );
    let white_all = common::render_forward(&white, 96, 96);
    let worst = white_all
        .hdr
        .iter()
        .zip(&plain.hdr)
        .map(|(a, b)| f64::from((a - b).abs()) / f64::from(b.abs()).max(1e-12))
        .fold(0.0, f64::max);
    eprintln!("maps of 1 with the occlusion map: largest relative difference {worst:e}");
    assert!(worst <= 2.0 * f64::from(f32::EPSILON), "{worst:e}");
    let grey = common::render_forward(
        &sphere(UNIFORM, &format!("{CLAY}{}", maps("grey.png", &all)), &dir),
        96,
        96,
    );
    assert!(grey.hdr != plain.hdr, "a map of 0.5 must change the image");
}

/// A missing map file fails validation with exit code 2, naming the file and the key.
#[test]
fn a_missing_map_file_is_an_error_naming_it() {
    let dir = test_dir("missing");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"m\"\n[materials.m.metallic_map]\ntexture = \"orm.png\"\n",
    )
    .expect("write scene");
    let out = dir.join("out.png");
    let o = argil(&[
        "render",
        scene.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("orm.png") && stderr.contains("metallic_map"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
}

/// With the property maps (the builtin noise's channels as a packed texture and as the
/// scatter map), the renderer and the reference compute the same image where both see the
/// same thing: direct transport at pixel centres, one sample. The glossy clay under the
/// point light takes the roughness, metallic and scatter maps; a Lambert ball under the
/// uniform environment (exact at one sample), without the point light (which the renderer
/// micro-shadows by the occlusion map and the reference does not), the metallic and
/// occlusion maps. Bounds:
/// those of `tests/reference.rs` for an unmapped material (fp32) widened, as for its
/// normal map, by the GPU's 8-bit sub-texel filter weights on the magnified noise (the
/// reference filters bilinearly in f64). Measured p50 0.7–1.2e-3, p99 0.7–1.0e-2, and
/// fewer than 0.2% of channels above 5%: dim pixels at the silhouette (max 0.6).
#[test]
fn the_reference_applies_the_property_maps_as_the_renderer_does() {
    let dir = test_dir("reference");
    let maps = |keys: &[&str]| {
        keys.iter()
            .map(|key| {
                // Turned and offset, so that the shader's map_uv and MapRef::uv are held together.
                let transform = "uv_scale = [0.1, 0.1]\nuv_rotation_degrees = 30.0\nuv_offset = [0.3, -0.2]\n";
                format!("[materials.m.{key}]\ntexture = \"builtin:noise\"\n{transform}")
            })
            .collect::<String>()
    };
    let cases = [
        (
            "",
            CLAY.to_owned(),
            ["roughness_map", "metallic_map", "scatter_map"].as_slice(),
        ),
        (
            UNIFORM,
            "diffuse = \"lambert\"\nspecular = \"none\"\nsubsurface = \"none\"\nmetallic = 0.5\n".to_owned(),
            ["metallic_map", "occlusion_map"].as_slice(),
        ),
    ];
    let (width, height) = (128, 128);
    let settings = direct_at_pixel_centres(width, height);
    let mut failures = Vec::new();
    for (environment, material, keys) in cases {
        let lit = |mut scene: Scene| {
            if keys.contains(&"occlusion_map") {
                scene.lights.clear();
            }
            scene
        };
        let scene = lit(sphere(environment, &format!("roughness = 0.7\n{material}{}", maps(keys)), &dir));
        let gpu = common::render(&scene, width, height);
        let reference = render(&scene, &settings, &()).expect("reference");
        let unmapped = lit(sphere(environment, &format!("roughness = 0.7\n{material}"), &dir));
        let unmapped = render(&unmapped, &settings, &()).expect("reference");
        let pixels = (width * height) as usize;
        let rgb =
            |v: &[f32], i: usize| DVec3::new(f64::from(v[4 * i]), f64::from(v[4 * i + 1]), f64::from(v[4 * i + 2]));
        let mut errors = Vec::new();
        let mut changed = 0;
        for i in 0..pixels {
            let (r, g) = (rgb(&reference.rgba, i), rgb(&gpu.hdr, i));
            if reference.rgba[4 * i + 3] == 1.0 && gpu.hdr[4 * i + 3] == 1.0 && r.min_element() > 1e-3 {
                errors.extend(((g - r).abs() / r).to_array());
                changed += usize::from((r - rgb(&unmapped.rgba, i)).abs().max_element() > 1e-2 * r.max_element());
            }
        }
        let covered = errors.len() / 3;
        let large = errors.iter().filter(|&&e| e > 5e-2).count();
        let (p50, p99, max) = percentiles(errors);
        let label = keys.join(", ");
        eprintln!(
            "{label}: {covered} px ({changed} changed by the maps), p50 {p50:.2e} p99 {p99:.2e} max {max:.2e}, \
             {large} channels above 5%"
        );
        if covered < 2000 || changed < covered / 2 || p50 > 3e-3 || p99 > 5e-2 || max > 1.0 || large > 3 * covered / 200
        {
            failures.push(format!(
                "{label}: {covered} px, {changed} changed, p50 {p50:.3e} p99 {p99:.3e} max {max:.3e}"
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "the reference and the renderer differ:\n{}",
        failures.join("\n")
    );
}

const MICRO_LIGHT: DVec3 = DVec3::new(0.5, 1.5, 0.0);
const MICRO_SIZE: (u32, u32) = (128, 96);

/// A glossy grey plane (y = 0, 8 × 8) seen from above under one low point light at
/// MICRO_LIGHT, no environment; `map` is its material's map tables.
fn micro_plane(map: &str, dir: &Path) -> Scene {
    let toml = format!(
        r#"
[camera]
position = [0.0, 6.0, 4.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 50.0

[[lights]]
kind = "point"
position = [{}, {}, {}]
intensity = [6.0, 6.0, 6.0]

[antialiasing]
specular = false

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "m"

[materials.m]
base_color = [0.6, 0.6, 0.6]
roughness = 0.4
{map}
"#,
        MICRO_LIGHT.x, MICRO_LIGHT.y, MICRO_LIGHT.z
    );
    Scene::from_toml(&toml, "micro-shadowing test", dir).expect("test scene parses")
}

/// The occlusion map micro-shadows the point light: under a constant map of ao = 128/255
/// every plane pixel is the unmapped render times micro_shadowing(n·l, ao), n·l from the
/// exact point of the plane under the pixel's centre, on both sides of the open cone's
/// edge n·l = √(1 − ao) ≈ 0.71 (diffuse and specular lobes alike). Tolerance 1e-5
/// relative: the factor is (n·l)²/(1 − ao) below the edge, so it doubles the relative error
/// of the GPU's n·l from its interpolated f32 position and adds a few ulp of inversesqrt
/// (measured: 1.5e-6); a factor not squared, or the cone's edge misplaced, is off by
/// percents.
/// A map of 1 leaves the frame bit for bit as without a map, and so does any map with
/// `micro_shadowing` off, the default (no environment here).
#[test]
fn the_occlusion_map_micro_shadows_the_point_lights() {
    let dir = test_dir("micro");
    write_png(&dir.join("grey.png"), |_| [128; 3]);
    write_png(&dir.join("white.png"), |_| [255; 3]);
    let unflagged = |texture: &str| format!("[materials.m.occlusion_map]\ntexture = \"{texture}\"\n");
    let map = |texture: &str| format!("micro_shadowing = true\n{}", unflagged(texture));
    let (width, height) = MICRO_SIZE;
    let plain = common::render(&micro_plane("", &dir), width, height);
    for (name, text) in [("a map of 1", map("white.png")), ("micro_shadowing off", unflagged("grey.png"))] {
        let frame = common::render(&micro_plane(&text, &dir), width, height);
        let differing = frame.hdr.iter().zip(&plain.hdr).filter(|(a, b)| a.to_bits() != b.to_bits()).count();
        assert_eq!(differing, 0, "{name} changed {differing} channels");
    }

    let scene = micro_plane(&map("grey.png"), &dir);
    let grey = common::render(&scene, width, height);
    let ao = 128.0 / 255.0;
    let rays = CameraRays::new(&scene.camera, width, height);
    let (mut shadowed, mut open, mut worst) = (0, 0, 0.0f64);
    let mut wrong = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let (o, d) = rays.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, width, height);
            let g = o + d * (-o.y / d.y);
            if g.x.abs() > 3.9 || g.z.abs() > 3.9 {
                continue;
            }
            let factor = micro_shadowing((MICRO_LIGHT - g).normalize().y, ao);
            if factor < 0.99 {
                shadowed += 1;
            } else if factor == 1.0 {
                open += 1;
            }
            let i = (y * width + x) as usize;
            for c in 0..3 {
                let (expected, got) = (f64::from(plain.hdr[4 * i + c]) * factor, f64::from(grey.hdr[4 * i + c]));
                let error = (got - expected).abs() / expected.max(1e-9);
                worst = worst.max(error);
                if error > 1e-5 {
                    wrong.push(format!("({x}, {y}) channel {c}: {got:e}, expected {expected:e}"));
                }
            }
        }
    }
    eprintln!("micro-shadowing: {shadowed} px shadowed, {open} px open, largest relative error {worst:e}");
    assert!(shadowed > 2000 && open > 500, "{shadowed} shadowed, {open} open");
    assert!(wrong.is_empty(), "{} channels off, first: {:?}", wrong.len(), &wrong[..wrong.len().min(5)]);
}

/// An image is upright on a mesh: an OBJ quad facing the camera, with v up as OBJ files
/// have it, shows its texture's top half (red) above its bottom half (blue), in the frame
/// and in the reference alike.
#[test]
fn an_image_texture_is_upright_on_an_obj_quad() {
    let dir = test_dir("upright");
    image::RgbImage::from_fn(8, 8, |_, y| image::Rgb(if y < 4 { [255, 0, 0] } else { [0, 0, 255] }))
        .save(dir.join("halves.png"))
        .expect("write png");
    std::fs::write(
        dir.join("quad.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
         f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
    )
    .expect("write obj");
    let text = r#"
[camera]
position = [0.0, 0.0, 4.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 40.0

[environment]
kind = "uniform"
radiance = [1.0, 1.0, 1.0]

[[objects]]
mesh = "quad.obj"
material = "m"

[materials.m]
base_color = [1.0, 1.0, 1.0]
specular = "none"
subsurface = "none"
[materials.m.base_color_map]
texture = "halves.png"
"#;
    let scene = Scene::from_toml(text, "upright test", &dir).expect("test scene parses");
    let (width, height) = (32, 32);
    let frame = common::render(&scene, width, height);
    let settings = direct_at_pixel_centres(width, height);
    let reference = render(&scene, &settings, &()).expect("reference");
    for (name, rgba) in [("frame", &frame.hdr), ("reference", &reference.rgba)] {
        let pixel = |y: u32| {
            let i = ((y * width + width / 2) * 4) as usize;
            [rgba[i], rgba[i + 2]]
        };
        let ([top_red, top_blue], [bottom_red, bottom_blue]) = (pixel(height / 4), pixel(3 * height / 4));
        assert!(top_red > 10.0 * top_blue, "{name}: the quad's top is not red: {top_red} {top_blue}");
        assert!(bottom_blue > 10.0 * bottom_red, "{name}: the quad's bottom is not blue: {bottom_red} {bottom_blue}");
    }
}

/// A frame samples the maps its pipelines read: the presets' noise map only under the
/// report's reflection (`argil render` makes it only then), their normal maps in both.
#[test]
fn the_noise_map_is_sampled_only_under_the_reports_reflection() {
    let sampled = |toml: &str, name: &str| {
        let scene = common::scene(toml);
        let texture = scene.textures.iter().position(|t| t.name == name).expect("a builtin map");
        common::gpu().exclusive(|renderer| renderer.sampled_textures(&scene)[texture])
    };
    let default = argil::scene::DEFAULT_SCENE_TOML;
    let seed = default.replace("intensity = 0.6\n", "intensity = 0.6\nreflection = \"seed\"\n");
    assert_ne!(seed, default);
    assert!(!sampled(default, "builtin:noise"));
    assert!(sampled(&seed, "builtin:noise"));
    assert!(sampled(default, "builtin:clay-lumps") && sampled(&seed, "builtin:clay-lumps"));
}
