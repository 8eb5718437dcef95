//! Shadows of point lights (src/render/shadow.rs, shaders/lib/shadows.glsl): on lavapipe
//! with the validation layer on, every frame charged to its test.

mod common;

use argil::reference::integrator::CameraRays;
use argil::render::{OffscreenTarget, Renderer};
use ash::vk;
use argil::cache::DiskCache;
use argil::scene::{Scene, DEFAULT_SCENE_TOML};
use common::{argil_with, draw_hdr, gpu, render, scene, test_dir};
use glam::DVec3;

/// A grey plane at y = 0 under one light and a uniform environment, seen from above at
/// an angle; `extra` adds objects, `light` the light's extra keys.
fn plane_scene(light: &str, extra: &str) -> String {
    format!(
        r#"
[camera]
position = [0.0, 5.0, 6.0]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 40.0

[[lights]]
kind = "point"
position = [1.5, 4.0, 1.0]
intensity = [20.0, 18.0, 16.0]
{light}

[environment]
kind = "uniform"
radiance = [0.1, 0.1, 0.12]

[[objects]]
mesh = "builtin:plane"
scale = 4.0
material = "ground"
{extra}

[materials.ground]
base_color = [0.6, 0.6, 0.6]
roughness = 0.7

[shadows]
resolution = 2048
"#
    )
}

const SPHERE: &str = r#"
[[objects]]
mesh = "builtin:sphere"
position = [0.0, 1.3, 0.0]
scale = 0.6
material = "ground"
"#;
const SPHERE_CENTRE: DVec3 = DVec3::new(0.0, 1.3, 0.0);
const SPHERE_RADIUS: f64 = 0.6;
const LIGHT: DVec3 = DVec3::new(1.5, 4.0, 1.0);
const SIZE: (u32, u32) = (160, 120);

fn hdr(toml: &str) -> Vec<f32> {
    render(&scene(toml), SIZE.0, SIZE.1).hdr
}

/// A lit plane with nothing above it has no shadow: the frame with shadows is the frame
/// without them, bit for bit, for a point light and for a light with a radius (whose
/// blocker search finds nothing, so no filter runs).
#[test]
fn a_lit_plane_alone_has_no_shadow() {
    for radius in ["", "radius = 0.5"] {
        let with = hdr(&plane_scene(radius, ""));
        let without = hdr(&plane_scene(&format!("{radius}\nshadows = false"), ""));
        let differing = with
            .iter()
            .zip(&without)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differing, 0, "{radius:?}: {differing} channels differ");
    }
}

/// Whether the segment from ground point g to the light passes through the sphere, and
/// how far (signed, in world units) the segment's closest approach is from its surface.
fn shadow_margin(g: DVec3) -> (bool, f64) {
    let d = LIGHT - g;
    let t = ((SPHERE_CENTRE - g).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    let miss = (g + d * t - SPHERE_CENTRE).length() - SPHERE_RADIUS;
    (miss < 0.0, miss)
}

/// Where the camera ray through pixel point (x, y) meets the ground y = 0, unless it meets
/// the sphere first (or misses the plane's 8×8 square).
fn ground_point(rays: &CameraRays, x: f64, y: f64) -> Option<DVec3> {
    let (o, d) = rays.ray(x, y, SIZE.0, SIZE.1);
    let t = -o.y / d.y;
    let g = o + d * t;
    let oc = o - SPHERE_CENTRE;
    let (a, b, c) = (
        d.length_squared(),
        oc.dot(d),
        oc.length_squared() - (SPHERE_RADIUS * 1.01).powi(2),
    );
    let hits_sphere = b * b - a * c >= 0.0 && -b > 0.0;
    (t > 0.0 && g.x.abs() < 3.9 && g.z.abs() < 3.9 && !hits_sphere).then_some(g)
}

/// A sphere above the plane under a point light (radius 0): ground pixels inside the
/// umbra hold only the environment's light (the frame of the same scene without the
/// light), pixels outside it equal the unshadowed frame, both bit for bit; and the
/// umbra's edge lies where geometry puts it to within a pixel: every pixel whose centre
/// and corners all fall on one side of the sphere's exact shadow is on that side.
#[test]
fn a_point_lights_umbra_holds_only_the_environment_and_lies_where_geometry_puts_it() {
    let shadowed = hdr(&plane_scene("", SPHERE));
    let unshadowed = hdr(&plane_scene("shadows = false", SPHERE));
    let environment_only =
        hdr(&plane_scene("", SPHERE).replace("intensity = [20.0, 18.0, 16.0]", "intensity = [0.0, 0.0, 0.0]"));
    let camera = scene(&plane_scene("", SPHERE)).camera;
    let rays = CameraRays::new(&camera, SIZE.0, SIZE.1);
    let (mut umbra, mut lit, mut edge) = (0, 0, 0);
    let mut wrong = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let points = [(0.5, 0.5), (0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
            let sides: Option<Vec<bool>> = points
                .iter()
                .map(|&(dx, dy)| ground_point(&rays, f64::from(x) + dx, f64::from(y) + dy).map(|g| shadow_margin(g).0))
                .collect();
            let Some(sides) = sides else { continue };
            if sides.iter().any(|&s| s != sides[0]) {
                edge += 1;
                continue;
            }
            let i = 4 * (y * SIZE.0 + x) as usize;
            let expected = if sides[0] { &environment_only } else { &unshadowed };
            let close = (0..3).all(|c| {
                let (a, e) = (shadowed[i + c], expected[i + c]);
                a.to_bits() == e.to_bits()
            });
            if sides[0] {
                umbra += 1;
            } else {
                lit += 1;
            }
            if !close {
                wrong.push((x, y, sides[0], shadowed[i], expected[i]));
            }
        }
    }
    eprintln!("umbra {umbra} px, lit {lit} px, edge {edge} px");
    assert!(
        umbra > 300 && lit > 5000,
        "umbra {umbra}, lit {lit}: the scene does not test much"
    );
    assert!(
        wrong.is_empty(),
        "{} pixels off their side, first: {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
}

/// A light with a radius gives a penumbra: pixels between the point light's umbra and its
/// lit side that are neither, and the umbra shrinks.
#[test]
fn a_light_with_a_radius_casts_a_penumbra() {
    let environment_only =
        hdr(&plane_scene("", SPHERE).replace("intensity = [20.0, 18.0, 16.0]", "intensity = [0.0, 0.0, 0.0]"));
    let unshadowed = hdr(&plane_scene("shadows = false", SPHERE));
    let count = |frame: &[f32]| {
        let (mut umbra, mut penumbra) = (0, 0);
        for i in (0..frame.len()).step_by(4) {
            let (e, u, a) = (environment_only[i + 1], unshadowed[i + 1], frame[i + 1]);
            if u - e < 1e-3 {
                continue;
            }
            if (a - e).abs() <= 1e-6 {
                umbra += 1;
            } else if a < u - 1e-4 * u {
                penumbra += 1;
            }
        }
        (umbra, penumbra)
    };
    let (hard_umbra, hard_penumbra) = count(&hdr(&plane_scene("", SPHERE)));
    let (soft_umbra, soft_penumbra) = count(&hdr(&plane_scene("radius = 0.3", SPHERE)));
    eprintln!("radius 0: umbra {hard_umbra}, penumbra {hard_penumbra}; radius 0.3: umbra {soft_umbra}, penumbra {soft_penumbra}");
    assert!(soft_penumbra > 4 * hard_penumbra.max(1), "no penumbra");
    assert!(soft_umbra < hard_umbra, "the umbra did not shrink");
}

/// The pixels of a soft penumbra on the ground of [`plane_scene`] (`frame` the 16-tap
/// frame, `unshadowed` the frame without shadows), and how rough a frame is there: the
/// mean square of the second difference along rows, which a smooth penumbra's gradient
/// hardly moves and each pixel's own turn of the taps does.
fn penumbra_roughness(frame: &[f32], unshadowed: &[f32]) -> impl Fn(&[f32]) -> f64 {
    let penumbra: Vec<bool> = (0..frame.len() / 4)
        .map(|p| frame[4 * p + 1] < unshadowed[4 * p + 1] && frame[4 * p + 1] > 0.05 * unshadowed[4 * p + 1])
        .collect();
    assert!(penumbra.iter().filter(|&&p| p).count() > 100, "no penumbra");
    move |frame: &[f32]| {
        let (mut sum, mut n) = (0.0, 0);
        let green = |p: usize| f64::from(frame[4 * p + 1]);
        for y in 0..SIZE.1 as usize {
            for x in 1..SIZE.0 as usize - 1 {
                let p = y * SIZE.0 as usize + x;
                if penumbra[p] {
                    sum += (green(p - 1) - 2.0 * green(p) + green(p + 1)).powi(2);
                    n += 1;
                }
            }
        }
        sum / f64::from(n.max(1))
    }
}

/// `[shadows] taps` sets a soft shadow's taps: the fewer, the noisier its penumbra (each
/// pixel turns the taps by its own angle), at the pixels of the ground without its map.
#[test]
fn fewer_taps_give_a_noisier_penumbra() {
    let soft = plane_scene("radius = 0.3", SPHERE);
    let soft = soft.replace("resolution = 2048", "resolution = 2048\nground_map = false");
    let unshadowed = hdr(&plane_scene("radius = 0.3\nshadows = false", SPHERE));
    let sixteen = hdr(&soft);
    let roughness = penumbra_roughness(&sixteen, &unshadowed);
    let taps = |n: u32| hdr(&soft.replace("resolution = 2048", &format!("resolution = 2048\ntaps = {n}")));
    let (four, sixty_four) = (roughness(&taps(4)), roughness(&taps(64)));
    let default = roughness(&sixteen);
    eprintln!("penumbra roughness: 4 taps {four:.3e}, 16 {default:.3e}, 64 {sixty_four:.3e}");
    // Noise variance goes as 1/taps: 4× and 4× here; measured 10× and 3.5×.
    assert!(four > 4.0 * default && default > 2.0 * sixty_four, "{four} {default} {sixty_four}");
}

/// The ground's shadow map (`[shadows] ground_map`, the default) gives the ground the
/// shadow its pixels find, smoothed: the frame's light the same to 0.1%, every pixel that
/// all of the light reaches the same bit for bit, and the penumbra less rough than 16 taps
/// turned at each pixel make it.
#[test]
fn the_grounds_shadow_map_is_the_shadow_of_its_pixels_smoothed() {
    let soft = plane_scene("radius = 0.3", SPHERE);
    let map = hdr(&soft);
    let pixels = hdr(&soft.replace("resolution = 2048", "resolution = 2048\nground_map = false"));
    let unshadowed = hdr(&plane_scene("radius = 0.3\nshadows = false", SPHERE));
    let roughness = penumbra_roughness(&pixels, &unshadowed);
    let green = |frame: &[f32]| frame.iter().skip(1).step_by(4).map(|&g| f64::from(g)).sum::<f64>();
    let light = (green(&map) - green(&pixels)) / green(&pixels);
    let lit = (0..pixels.len()).filter(|&i| pixels[i] == unshadowed[i] && map[i] == unshadowed[i]).count();
    let lit_pixels = (0..pixels.len()).filter(|&i| pixels[i] == unshadowed[i]).count();
    let (smoothed, turned) = (roughness(&map), roughness(&pixels));
    eprintln!("light {light:.2e}; lit {lit} of {lit_pixels}; roughness {smoothed:.3e} against {turned:.3e}");
    assert!(light.abs() < 1e-3, "{light}");
    assert!(lit >= lit_pixels * 99 / 100, "{lit} of {lit_pixels}");
    assert!(smoothed < 0.5 * turned, "{smoothed} {turned}");
}

/// Beside a soft light, whose shadow the ground reads from its map, a hard light's shadow
/// is looked up at the ground's pixels as without the map: with the soft light dark (its
/// shadow still cast, the map still read), the frame is the frame without the map bit for
/// bit, while with it lit they differ by the map's smoothing of its penumbra.
#[test]
fn a_hard_light_beside_a_soft_one_shadows_the_ground_at_its_pixels() {
    let hard = "[[lights]]\nkind = \"point\"\nposition = [-2.0, 3.0, -1.5]\nintensity = [12.0, 11.0, 10.0]\n";
    let both = plane_scene("radius = 0.3", &format!("{SPHERE}\n{hard}"));
    let dark = both.replace("intensity = [20.0, 18.0, 16.0]", "intensity = [0.0, 0.0, 0.0]");
    assert_ne!(dark, both);
    let pixels = |toml: &str| hdr(&toml.replace("resolution = 2048", "resolution = 2048\nground_map = false"));
    assert_ne!(hdr(&both), pixels(&both), "the soft light's shadow is read from the map");
    let (dark_map, dark_pixels) = (hdr(&dark), pixels(&dark));
    assert!(dark_map.iter().any(|&c| c > 0.0));
    assert_eq!(dark_map, dark_pixels, "the hard light's shadow is looked up at the pixels");
}

/// The maps are rendered when the scene changes, not every frame: two frames of the same
/// scene render them once, moving the light renders them again, and the frame is the same
/// either way. So are the ground's light map of the bounce, which a light's intensity
/// changes too, its shadow map, which a light's radius and the taps change too, and the
/// sphere's bounce gathered at its vertices, which follows the light map and where the
/// sphere stands; a floor frame between two of the scene's leaves them as they are.
#[test]
fn shadow_maps_render_only_when_the_scene_changes() {
    let toml = plane_scene("radius = 0.2", SPHERE).replace("resolution = 2048", "resolution = 2048\nbounce = true");
    let mut s = scene(&toml);
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&s).expect("upload");
        let offscreen = OffscreenTarget::new(&renderer.device, vk::Extent2D { width: 64, height: 48 }).expect("target");
        let frame = |renderer: &mut Renderer, s: &Scene| draw_hdr(renderer, s, &gpu_scene, &offscreen);
        let renders = |renderer: &argil::render::Renderer| {
            [
                renderer.shadow_map_renders(),
                renderer.ground_light_renders(),
                renderer.ground_shadow_renders(),
                renderer.vertex_light_computes(),
            ]
        };
        let [shadows, ground, ground_shadows, bounce] = renders(renderer);
        let first = frame(renderer, &s);
        let second = frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 1, ground + 1, ground_shadows + 1, bounce + 1]);
        assert_eq!(first, second);
        renderer.floor = true;
        frame(renderer, &s);
        renderer.floor = false;
        assert_eq!(frame(renderer, &s), second);
        s.lights[0].position.x += 0.5;
        let moved = frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 2, ground + 2, ground_shadows + 2, bounce + 2]);
        assert_ne!(moved, second);
        // Changing only the radius needs no new shadow map, but the penumbra on the ground.
        s.lights[0].radius = 0.4;
        frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 2, ground + 2, ground_shadows + 3, bounce + 2]);
        // The intensity changes the ground's light, not the shadows.
        s.lights[0].intensity *= 0.5;
        frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 2, ground + 3, ground_shadows + 3, bounce + 3]);
        s.shadow_taps = 8;
        frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 2, ground + 3, ground_shadows + 4, bounce + 3]);
        // Without the map, the ground's pixels find its shadows.
        s.shadow_ground_map = false;
        s.lights[0].position.x += 0.5;
        let lowered = frame(renderer, &s);
        assert_eq!(renders(renderer), [shadows + 3, ground + 4, ground_shadows + 4, bounce + 4]);
        // The sphere raised and lowered again: its shadow, the ground's light and its own
        // bounce each time, and the frame as it was.
        s.objects[1].position.y += 0.25;
        assert_ne!(frame(renderer, &s), lowered);
        s.objects[1].position.y -= 0.25;
        assert_eq!(frame(renderer, &s), lowered);
        assert_eq!(renders(renderer), [shadows + 5, ground + 6, ground_shadows + 4, bounce + 6]);
    });
}

/// `[shadows] per_vertex`: a small sphere in a larger one's soft shadow takes it from its
/// vertices, found once per change of the shadows (a light's radius too) and not per frame
/// nor when the camera moves; its frame is the pixels' to within the interpolation of the
/// penumbra (the light the frame holds the same to 1%), and not the same frame; switched off
/// and on, the frame follows; through many counts of taps, two compute pipelines are kept.
#[test]
fn soft_shadows_at_the_vertices_follow_the_shadows_not_the_frames() {
    const SHADOWED: &str = r#"
[[objects]]
mesh = "builtin:sphere"
position = [-0.6, 0.35, -0.4]
scale = 0.35
material = "ground"
"#;
    let at_pixels = plane_scene("radius = 0.3", &format!("{SPHERE}{SHADOWED}"));
    let mut s = scene(&at_pixels.replace("resolution = 2048", "resolution = 2048\nper_vertex = true"));
    assert!(s.shadow_per_vertex);
    let pixels = hdr(&at_pixels);
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&s).expect("upload");
        let extent = vk::Extent2D { width: SIZE.0, height: SIZE.1 };
        let offscreen = OffscreenTarget::new(&renderer.device, extent).expect("target");
        let frame = |renderer: &mut Renderer, s: &Scene| draw_hdr(renderer, s, &gpu_scene, &offscreen);
        let computes = renderer.vertex_light_computes();
        let first = frame(renderer, &s);
        assert_eq!(frame(renderer, &s), first);
        assert_eq!(renderer.vertex_light_computes(), computes + 1);
        assert_ne!(first, pixels, "the small sphere's shadow comes from its vertices");
        let light = |frame: &[f32]| frame.iter().map(|&c| f64::from(c)).sum::<f64>();
        let ratio = light(&first) / light(&pixels);
        assert!((ratio - 1.0).abs() < 0.01, "the frame's light {ratio} of the pixels'");
        // Switched off and on again, as the viewer's checkbox does.
        s.shadow_per_vertex = false;
        assert_eq!(frame(renderer, &s), pixels, "off: the pixels' frame");
        s.shadow_per_vertex = true;
        assert_eq!(frame(renderer, &s), first, "on again: the vertices' frame, not computed again");
        assert_eq!(renderer.vertex_light_computes(), computes + 1);
        s.camera.position.x += 0.3;
        frame(renderer, &s);
        assert_eq!(renderer.vertex_light_computes(), computes + 1, "the camera moved alone");
        s.lights[0].radius = 0.45;
        frame(renderer, &s);
        assert_eq!(renderer.vertex_light_computes(), computes + 2, "the light's radius changed");
        // A slider of taps dragged through its values: each is computed, the pipelines of
        // the last two are kept.
        for (n, taps) in [4, 8, 32, 64].into_iter().enumerate() {
            s.shadow_taps = taps;
            frame(renderer, &s);
            assert_eq!(renderer.vertex_light_computes(), computes + 3 + n as u64, "{taps} taps");
        }
        assert_eq!(renderer.vertex_light_pipelines(), 2);
    });
}

/// A draft (the viewer's frames while in use on a slow device) does not compute the
/// ground's maps that a moved light or object put out of date: the ground finds its
/// shadows, and the objects' occlusion, at its pixels, and the shadow maps are rendered at
/// a quarter of the resolution, the frame bit for bit the one without the ground's maps at
/// that resolution. The next frame that is not a draft computes them all, and a draft with
/// nothing moved reads them, computing nothing.
#[test]
fn a_draft_finds_what_its_out_of_date_ground_maps_would_hold_at_the_grounds_pixels() {
    let mut s = scene(&format!("{}\n[occlusion]\nobjects = true\n", plane_scene("radius = 0.2", SPHERE)));
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&s).expect("upload");
        let offscreen = OffscreenTarget::new(&renderer.device, vk::Extent2D { width: 64, height: 48 }).expect("target");
        let frame = |renderer: &mut argil::render::Renderer, s: &argil::scene::Scene, draft: bool| {
            renderer.draft = draft;
            let ms = renderer.draw_offscreen(s, &gpu_scene, &offscreen, 1.0);
            renderer.draft = false;
            renderer.read_offscreen(&offscreen, ms.expect("draw")).expect("read").hdr
        };
        let renders = |renderer: &argil::render::Renderer| {
            [renderer.ground_shadow_renders(), renderer.ground_occlusion_renders()]
        };
        let without_maps = |s: &argil::scene::Scene, occlusion_map: bool| {
            let mut without = s.clone();
            without.shadow_ground_map = false;
            without.occlusion.ground_map = occlusion_map;
            without.shadow_resolution /= argil::render::shadow::DRAFT_RESOLUTION_DIVISOR;
            without
        };
        let still = frame(renderer, &s, false);
        let [shadow_maps, occlusion_maps] = renders(renderer);
        assert_eq!(frame(renderer, &s, true), still, "a draft with nothing moved reads the maps");
        s.lights[0].position.x += 0.25;
        let moved = frame(renderer, &s, true);
        assert_eq!(renders(renderer), [shadow_maps, occlusion_maps], "a draft leaves the maps out of date");
        assert_eq!(moved, frame(renderer, &without_maps(&s, true), false), "the shadows at the pixels");
        let full = frame(renderer, &s, false);
        assert_eq!(renders(renderer), [shadow_maps + 1, occlusion_maps]);
        assert_ne!(full, moved, "the map smooths the penumbra");
        assert_eq!(frame(renderer, &s, true), full);
        // The sphere moved puts both maps out of date.
        s.objects[1].position.x += 0.25;
        let moved = frame(renderer, &s, true);
        assert_eq!(renders(renderer), [shadow_maps + 1, occlusion_maps]);
        assert_eq!(moved, frame(renderer, &without_maps(&s, false), false), "both at the pixels");
        frame(renderer, &s, false);
        assert_eq!(renders(renderer), [shadow_maps + 2, occlusion_maps + 1]);
    });
}

/// Pixels of the ground wholly on one side of the sphere's exact shadow (centre and
/// corners): (index, inside the umbra).
fn ground_sides() -> Vec<(usize, bool)> {
    let camera = scene(&plane_scene("", SPHERE)).camera;
    let rays = CameraRays::new(&camera, SIZE.0, SIZE.1);
    let mut sides = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let points = [(0.5, 0.5), (0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
            let side: Option<Vec<bool>> = points
                .iter()
                .map(|&(dx, dy)| ground_point(&rays, f64::from(x) + dx, f64::from(y) + dy).map(|g| shadow_margin(g).0))
                .collect();
            if let Some(side) = side.filter(|s| s.iter().all(|&v| v == s[0])) {
                sides.push((4 * (y * SIZE.0 + x) as usize, side[0]));
            }
        }
    }
    sides
}

/// The shadow debug view is the shadow factor: 1 on every covered pixel of a lit plane
/// alone, 0 in the sphere's umbra and 1 outside it (a light of radius 0).
#[test]
fn the_shadow_debug_view_shows_the_shadow_factor() {
    let view = |toml: &str| {
        gpu().exclusive(|renderer| {
            renderer.debug_view = argil::render::DebugView::Shadows;
            let frame = common::try_render(renderer, &scene(toml), SIZE.0, SIZE.1);
            renderer.debug_view = argil::render::DebugView::Shaded;
            frame.expect("render").hdr
        })
    };
    let alone = view(&plane_scene("", ""));
    assert!(alone.chunks_exact(4).filter(|p| p[3] > 0.0).all(|p| p[0] == 1.0));
    let shadowed = view(&plane_scene("", SPHERE));
    let sides = ground_sides();
    let umbra = sides.iter().filter(|s| s.1).count();
    assert!(umbra > 300, "umbra {umbra} px: the scene does not test much");
    let wrong: Vec<_> = sides
        .iter()
        .filter(|&&(i, inside)| shadowed[i] != if inside { 0.0 } else { 1.0 })
        .collect();
    assert!(
        wrong.is_empty(),
        "{} pixels off: {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
}

/// The shadow-map view of a lit plane alone passes the test on every covered pixel: each
/// shows 1 or the checker's darker texel, both in large numbers; at 16 texels a face the
/// checker's squares span several pixels (the map's resolution shows). With the sphere
/// above, umbra pixels show the sphere's distance over the ground's, well below the
/// checker's grey, and lit pixels still pass.
#[test]
fn the_shadow_map_view_passes_on_a_lit_plane_and_shows_the_blocker_in_the_umbra() {
    use argil::render::debug_view::SHADOW_MAP_VIEW_CHECKER;
    let checker = SHADOW_MAP_VIEW_CHECKER as f32;
    let view = |toml: &str| {
        gpu().exclusive(|renderer| {
            renderer.debug_view = argil::render::DebugView::ShadowMap;
            let frame = common::try_render(renderer, &scene(toml), SIZE.0, SIZE.1);
            renderer.debug_view = argil::render::DebugView::Shaded;
            frame.expect("render").hdr
        })
    };
    let coarse = view(&plane_scene("", "").replace("resolution = 2048", "resolution = 16"));
    let covered: Vec<f32> = coarse.chunks_exact(4).filter(|p| p[3] > 0.0).map(|p| p[0]).collect();
    let white = covered.iter().filter(|&&v| v == 1.0).count();
    let grey = covered.iter().filter(|&&v| v == checker).count();
    assert_eq!(white + grey, covered.len(), "pixels failing the test on a lit plane alone");
    assert!(white.min(grey) * 5 > covered.len(), "checker {white} white, {grey} grey");
    let row_changes = (0..SIZE.1 as usize)
        .flat_map(|y| (1..SIZE.0 as usize).map(move |x| 4 * (y * SIZE.0 as usize + x)))
        .filter(|&i| coarse[i + 3] > 0.0 && coarse[i - 1] > 0.0 && coarse[i] != coarse[i - 4])
        .count();
    assert!(row_changes * 4 < covered.len(), "{row_changes} changes over {} pixels", covered.len());

    let shadowed = view(&plane_scene("", SPHERE));
    let sides = ground_sides();
    let wrong: Vec<_> = sides
        .iter()
        .filter(|&&(i, inside)| {
            let v = shadowed[i];
            if inside {
                !(v > 0.3 && v < checker - 0.05)
            } else {
                v != 1.0 && v != checker
            }
        })
        .map(|&(i, inside)| (i / 4, inside, shadowed[i]))
        .collect();
    assert!(wrong.is_empty(), "{} pixels off: {:?}", wrong.len(), &wrong[..wrong.len().min(8)]);
}

/// The pixels well inside the silhouette of SPHERE, where a ray through the pixel's centre
/// passes within `within` of its radius of its centre, as indices into a frame, each with
/// the point where that ray meets the sphere.
fn sphere_pixels(rays: &CameraRays, within: f64) -> Vec<(usize, DVec3)> {
    let mut pixels = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let (o, d) = rays.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, SIZE.0, SIZE.1);
            let d = d.normalize();
            let oc = o - SPHERE_CENTRE;
            let b = oc.dot(d);
            let miss2 = oc.length_squared() - b * b;
            if miss2 <= (within * SPHERE_RADIUS).powi(2) && b <= 0.0 {
                let p = o + d * (-b - (SPHERE_RADIUS * SPHERE_RADIUS - miss2).sqrt());
                pixels.push(((y * SIZE.0 + x) as usize, p));
            }
        }
    }
    pixels
}

/// A convex ball that no object can stand in front of, seen from the light's sphere, is
/// drawn without shadow code (`Scene::shadowing_lights`); a pebble above the light, which
/// casts nothing on it, makes its draw hold that code, and the ball's pixels are the same,
/// bit for bit: the soft shadow's comparisons find nothing of a convex surface in front of
/// itself (with their bias at −1e-3 instead of 5e-4, 24 of these pixels darken). The ball
/// is coarse (2 cells along each edge of its cube), its folds far from a sphere's.
#[test]
fn a_ball_no_shadow_can_reach_is_drawn_without_shadow_code_as_with_it() {
    let ball = SPHERE.replace("scale = 0.6", "scale = 0.6\nsubdivisions = 2");
    let pebble = format!(
        "[[objects]]\nmesh = \"builtin:sphere\"\nposition = [{}, {}, {}]\nscale = 0.1\nmaterial = \"ground\"\n",
        LIGHT.x,
        LIGHT.y + 0.55,
        LIGHT.z
    );
    let alone = scene(&plane_scene("radius = 0.5", &ball));
    let beside = scene(&plane_scene("radius = 0.5", &format!("{ball}{pebble}")));
    let shadowed = |scene: &argil::scene::Scene| {
        let extents: Vec<_> = scene.meshes.iter().map(|m| m.extent()).collect();
        scene.shadowing_lights(1, &[0], |m| extents[m]) != 0
    };
    assert!(!shadowed(&alone) && shadowed(&beside));
    let rays = CameraRays::new(&alone.camera, SIZE.0, SIZE.1);
    let [alone, beside] = [alone, beside].map(|scene| render(&scene, SIZE.0, SIZE.1).hdr);
    // Its flat triangles come as near its centre as 0.88 of its radius: rays within 0.6 meet them.
    let pixels = sphere_pixels(&rays, 0.6);
    assert!(pixels.len() > 150, "{} pixels", pixels.len());
    let differing = (pixels.iter())
        .filter(|&&(i, _)| (0..4).any(|c| alone[4 * i + c].to_bits() != beside[4 * i + c].to_bits()))
        .count();
    assert_eq!(differing, 0, "{differing} of {} pixels of the ball differ", pixels.len());
}

/// Each light is weighed alone (`Scene::shadowing_lights`): a pebble between a low side
/// light and the ball lets that light shadow the ball, whose draw then runs the shadow code
/// for it alone. The pebble's shadow falls on the ball, and the key light, which nothing can
/// stand before, leaves the ball's pixels the same bit for bit with its shadows or without.
#[test]
fn a_ball_runs_the_shadow_code_of_the_lights_that_may_shadow_it_alone() {
    let extra = |side_shadows: bool| {
        format!(
            "{SPHERE}[[objects]]\nmesh = \"builtin:sphere\"\nposition = [-1.5, 1.3, 0.0]\nscale = 0.3\n\
             material = \"ground\"\n[[lights]]\nkind = \"point\"\nposition = [-3.0, 1.3, 0.0]\n\
             intensity = [6.0, 6.0, 6.0]\nshadows = {side_shadows}\n"
        )
    };
    let both = scene(&plane_scene("radius = 0.3", &extra(true)));
    let extents: Vec<_> = both.meshes.iter().map(|m| m.extent()).collect();
    assert_eq!(both.shadowing_lights(1, &[0, 1], |m| extents[m]), 0b10);
    let key_unshadowed = scene(&plane_scene("radius = 0.3\nshadows = false", &extra(true)));
    let side_unshadowed = scene(&plane_scene("radius = 0.3", &extra(false)));
    let rays = CameraRays::new(&both.camera, SIZE.0, SIZE.1);
    let pixels = sphere_pixels(&rays, 0.6);
    let [both, key_unshadowed, side_unshadowed] =
        [both, key_unshadowed, side_unshadowed].map(|scene| render(&scene, SIZE.0, SIZE.1).hdr);
    let differing = |other: &[f32]| {
        let differs = |i: usize| (0..4).any(|c| both[4 * i + c].to_bits() != other[4 * i + c].to_bits());
        pixels.iter().filter(|&&(i, _)| differs(i)).count()
    };
    assert_eq!(differing(&key_unshadowed), 0, "the key light cannot shadow the ball");
    assert!(differing(&side_unshadowed) > 10, "the pebble shadows the ball");
}

/// `[shadows] bounce` leaves the ground as it was, bit for bit (nothing is gathered on it),
/// and brightens the sphere's underside over the lit ground.
#[test]
fn bounce_lights_the_sphere_from_the_ground_and_leaves_the_ground_alone() {
    let with_bounce = |toml: String| toml.replace("resolution = 2048", "resolution = 2048\nbounce = true");
    let plain = hdr(&plane_scene("", SPHERE));
    let bounced = hdr(&with_bounce(plane_scene("", SPHERE)));
    for (i, _) in ground_sides() {
        assert!(
            (0..4).all(|c| plain[i + c].to_bits() == bounced[i + c].to_bits()),
            "ground pixel {i} changed"
        );
    }
    let brighter = plain
        .chunks_exact(4)
        .zip(bounced.chunks_exact(4))
        .filter(|(a, b)| b[1] > a[1] * 1.05)
        .count();
    assert!(brighter > 50, "{brighter} pixels brightened by the bounce");
}

/// The bounce view of a sphere over a lit ground (its light casting no shadow) is the f64
/// gather (src/brdf/bounce.rs) and its gradient at the vertices of the sphere's triangle
/// under each pixel's centre, interpolated there and moved to the pixel's normal (read
/// from the normals view), with the ground's exact light: the ground's light map read
/// bilinearly, and the GLSL gather and gradient, agree with their twins. Without a normal
/// map the pixel's normal is the interpolated one and the gradient moves nothing; with
/// the lumps' map it moves the gather by 9% (the median pixel). A coarse sphere (8 cells
/// a cube edge) gathers at its pixels, the f64 gather at the mesh's surface. The ground reaches 40 from the
/// sphere, so that the taps a tilt of the mesh's normals moves across its edge are few; its
/// light map's texels are 0.31 wide there, where the light's irradiance, 4 above, bends by
/// 2e-3 of itself.
#[test]
fn the_bounce_is_the_f64_gather_of_the_grounds_light() {
    use argil::brdf::bounce::{
        bounce_at_pixel, ground_lights_irradiance, BounceLight, BounceSource, Ground, BOUNCE_GRADIENT_TAPS,
        BOUNCE_TAPS,
    };
    use argil::reference::world::World;
    use argil::render::DebugView;
    let lumps = concat!(
        "\n[materials.ground.normal_map]\ntexture = \"builtin:clay-lumps\"\n",
        "strength = 1.0\nuv_scale = [4.0, 2.0]\n"
    );
    for (mapped, cells) in [(false, 32), (true, 32), (false, 8)] {
        let mut toml = plane_scene("shadows = false", SPHERE)
            .replace("scale = 4.0", "scale = 40.0")
            .replace("scale = 0.6", &format!("scale = 0.6\nsubdivisions = {cells}"))
            .replace("resolution = 2048", "resolution = 2048\nbounce = true");
        if mapped {
            toml.push_str(lumps);
        }
        let scene = scene(&toml);
        let at_vertices = argil::scene::Scene::bounce_at_vertices(scene.meshes[scene.objects[1].mesh].extent());
        assert_eq!(at_vertices, cells == 32);
        let [bounce, normals] = gpu().exclusive(|renderer| {
            let frames = [DebugView::Bounce, DebugView::Normals].map(|view| {
                renderer.debug_view = view;
                common::try_render(renderer, &scene, SIZE.0, SIZE.1)
            });
            renderer.debug_view = DebugView::Shaded;
            frames.map(|frame| frame.expect("render").hdr)
        });
        let rays = CameraRays::new(&scene.camera, SIZE.0, SIZE.1);
        let world = World::new(&scene);
        let ground = Ground {
            centre: [0.0; 3],
            half_side: 40.0,
            albedo: [0.6; 3],
        };
        let light = BounceLight {
            position: LIGHT.to_array(),
            intensity: [20.0, 18.0, 16.0],
        };
        let source = BounceSource {
            ground: &ground,
            ground_light: |g| ground_lights_irradiance(g, &[light], |_, _| 1.0),
            environment_over_pi: |_| [0.1, 0.1, 0.12],
        };
        let (mut errors, mut moves) = (Vec::new(), Vec::new());
        // Pixels well inside the silhouette, where mesh and sphere cover the centre alike.
        for (i, _) in sphere_pixels(&rays, 0.9) {
            let (x, y) = ((i % SIZE.0 as usize) as f64 + 0.5, (i / SIZE.0 as usize) as f64 + 0.5);
            let (o, d) = rays.ray(x, y, SIZE.0, SIZE.1);
            let hit = world.intersect(o, d, 0.0, f64::INFINITY, None).expect("the sphere");
            let surface = world.surface(&hit, d);
            let n: [f64; 3] = std::array::from_fn(|c| 2.0 * f64::from(normals[4 * i + c]) - 1.0);
            if !at_vertices {
                let gathered = source.irradiance(surface.position.to_array(), n, BOUNCE_TAPS)[1];
                if gathered > 0.0 {
                    let expected = gathered * 0.6 / std::f64::consts::PI;
                    errors.push((f64::from(bounce[4 * i + 1]) - expected).abs() / expected);
                }
                continue;
            }
            let weights = [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2];
            let (mut at_mesh_normal, mut gradient) = ([0.0; 3], [[0.0; 3]; 3]);
            for ((p, n), w) in world.hit_vertices(&hit).into_iter().zip(weights) {
                let e = source.irradiance(p.to_array(), n.to_array(), BOUNCE_TAPS);
                let g = source.gradient(p.to_array(), BOUNCE_GRADIENT_TAPS);
                for c in 0..3 {
                    at_mesh_normal[c] += w * e[c];
                    gradient[c] = std::array::from_fn(|k| gradient[c][k] + w * g[c][k]);
                }
            }
            let n_geometric = surface.normal.to_array();
            let bounced = bounce_at_pixel(at_mesh_normal, &gradient, n, n_geometric)[1];
            let expected = bounced * 0.6 / std::f64::consts::PI;
            if expected > 0.0 && at_mesh_normal[1] > 0.0 {
                moves.push((bounced - at_mesh_normal[1]).abs() / at_mesh_normal[1]);
                errors.push((f64::from(bounce[4 * i + 1]) - expected).abs() / expected);
            }
        }
        errors.sort_by(f64::total_cmp);
        let median = errors[errors.len() / 2];
        let p95 = errors[errors.len() * 95 / 100];
        assert!(errors.len() > 300, "{} sphere pixels lit by the bounce", errors.len());
        moves.sort_by(f64::total_cmp);
        let moved = moves.get(moves.len() / 2).copied().unwrap_or(0.0);
        let (pixels, max) = (errors.len(), errors[errors.len() - 1]);
        eprintln!(
            "mapped {mapped}, {cells} cells: {pixels} px: median {median:.2e}, p95 {p95:.2e}, max {max:.2e}; \
             moved by the normal: median {moved:.2e}"
        );
        assert!(median < 2e-3 && p95 < 1e-2, "relative error: median {median:.2e}, p95 {p95:.2e}");
        assert!(mapped == (moved > 1e-2), "the normal moves the bounce by {moved:.2e} (median)");
    }
}

/// A start reads the ground's maps and the bounce at the vertices from the disk cache where a
/// start before computed them from the same inputs, and draws the same bits: the default
/// scene's warm start gives the cold one's frame, and each stored entry changed on disk
/// changes it (the light map, which only the bounce at the vertices reads, once the bounce
/// is computed from it again). Another camera reads the same entries; a moved light makes
/// new ones, and the soft shadows at the vertices (`[shadows] per_vertex`) a new one of
/// what the vertices hold.
#[test]
fn the_grounds_maps_and_bounce_come_from_the_disk_cache_on_a_warm_start() {
    let dir = test_dir("ground-cache");
    let cache = dir.join("cache");
    let render = |scene: Option<&str>, name: &str| -> Vec<u8> {
        let out = dir.join(name);
        let out_arg = out.to_str().expect("utf-8");
        let mut args = vec!["render", "--width", "96", "--height", "54", "--overwrite", "--out", out_arg];
        args.extend(scene);
        let o = argil_with(&args, &[("ARGIL_CACHE_DIR", cache.to_str().expect("utf-8"))]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(out).expect("output")
    };
    // Each entry's name and key, from its file name (NAME-KEY.bin).
    let entries = || -> Vec<(String, u64)> {
        let mut entries: Vec<(String, u64)> = std::fs::read_dir(&cache)
            .expect("the cache folder")
            .map(|e| e.expect("entry").file_name().into_string().expect("utf-8"))
            .filter(|file| file.starts_with("ground-") || file.starts_with("vertex-light-"))
            .map(|file| {
                let (name, key) = file.trim_end_matches(".bin").rsplit_once('-').expect("NAME-KEY");
                (name.to_owned(), u64::from_str_radix(key, 16).expect("hex key"))
            })
            .collect();
        entries.sort();
        entries
    };
    let cold = render(None, "cold.exr");
    let stored = entries();
    let names: Vec<&str> = stored.iter().map(|(name, _)| name.as_str()).collect();
    let all = ["ground-environment", "ground-light", "ground-occlusion", "ground-shadow", "vertex-light"];
    assert_eq!(names, all);
    assert!(render(None, "warm.exr") == cold, "the warm start drew other bits");
    let disk = DiskCache::at(Some(&cache));
    let bounce_key = stored[all.len() - 1].1;
    let bounce = disk.load("vertex-light", bounce_key).expect("a whole entry");
    for (name, key) in &stored {
        let map = disk.load(name, *key).expect("a whole entry");
        disk.store(name, *key, &vec![0; map.len()]);
        if name == "ground-light" {
            std::fs::remove_file(cache.join(format!("vertex-light-{bounce_key:016x}.bin"))).expect("removed");
        }
        assert!(render(None, "changed.exr") != cold, "{name} was not read from the disk cache");
        disk.store(name, *key, &map);
        disk.store("vertex-light", bounce_key, &bounce);
    }
    assert!(render(None, "restored.exr") == cold, "the entries put back drew other bits");
    // The maps do not depend on the view: another camera reads the same entries.
    let scene = |name: &str, from: &str, to: &str| {
        let text = DEFAULT_SCENE_TOML.replace(from, to);
        assert_ne!(text, DEFAULT_SCENE_TOML);
        let path = dir.join(name);
        std::fs::write(&path, text).expect("scene");
        path.to_str().expect("utf-8").to_owned()
    };
    let turned = scene("turned.toml", "position = [0.0, 1.4, 6.2]", "position = [0.5, 1.6, 6.0]");
    assert!(render(Some(&turned), "turned.exr") != cold);
    assert_eq!(entries(), stored);
    let moved = scene("moved.toml", "position = [-4.0, 4.0, 2.5]", "position = [-3.5, 4.0, 2.5]");
    assert!(render(Some(&moved), "moved.exr") != cold);
    let added: Vec<String> = entries().into_iter().filter(|e| !stored.contains(e)).map(|(name, _)| name).collect();
    assert_eq!(added, all);
    // The soft shadows at the vertices are in the same entry, whose key they change alone.
    let per_vertex = scene("per-vertex.toml", "bounce = true", "bounce = true\nper_vertex = true");
    let before = entries();
    let cold = render(Some(&per_vertex), "per-vertex.exr");
    let added: Vec<(String, u64)> = entries().into_iter().filter(|e| !before.contains(e)).collect();
    let [(name, key)] = &added[..] else { panic!("one new entry: {added:?}") };
    assert_eq!(name, "vertex-light");
    let bits = disk.load(name, *key).expect("a whole entry");
    disk.store(name, *key, &vec![0; bits.len()]);
    assert!(render(Some(&per_vertex), "per-vertex-zeroed.exr") != cold, "the entry was not read");
}
