//! Ambient occlusion of the environment's light (src/render/occlusion.rs, shaders/gtao.comp):
//! on lavapipe with the validation layer on, every frame charged to its test.

mod common;

use argil::render::{DebugView, OffscreenTarget, Renderer};
use argil::reference::integrator::CameraRays;
use argil::scene::{Environment, Scene};
use ash::vk;
use common::{draw_hdr, gpu, render, scene, try_render, CountedFrames};
use glam::Vec3;

const SIZE: (u32, u32) = (160, 120);

/// A Lambert ball of albedo `albedo` under a uniform white environment (no lights), alone
/// or resting on a ground of the same material; `occlusion` is the `[occlusion]` section.
fn ball_scene(ground: bool, albedo: f32, occlusion: &str) -> String {
    let ground = if ground {
        "[[objects]]\nmesh = \"builtin:plane\"\nscale = 6.0\nmaterial = \"clay\"\n"
    } else {
        ""
    };
    format!(
        r#"
[camera]
position = [0.0, 2.0, 5.0]
target = [0.0, 0.6, 0.0]
fov_y_degrees = 40.0

[environment]
kind = "uniform"
radiance = [1.0, 1.0, 1.0]

[[objects]]
mesh = "builtin:sphere"
position = [0.0, 1.0, 0.0]
material = "clay"

{ground}
[materials.clay]
base_color = [{albedo}, {albedo}, {albedo}]
specular = "none"

{occlusion}
"#
    )
}

/// What the ground 0.25 from the ball keeps of the sky at most. Exactly: the ball (radius
/// 1, its centre 1.25 away) subtends a cone of half-angle 53° whose axis is 37° from the
/// normal, whose cosine-weighted share of the sky is cos 37° sin² 53° = 0.51, so the
/// visibility is 0.49; GTAO within a radius of 0.8 sees the nearer part of that cone.
const NEAR_AT_MOST: f32 = 0.75;

const ON: &str = "[occlusion]\nenabled = true\nradius = 0.8";

fn hdr(toml: &str) -> Vec<f32> {
    render(&scene(toml), SIZE.0, SIZE.1).hdr
}

/// Channels that differ in their bits, and the largest difference.
fn differences(a: &[f32], b: &[f32]) -> (usize, f32) {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .fold((0, 0.0), |(n, max), (x, y)| (n + 1, max.max((x - y).abs())))
}

/// The white furnace: a white Lambert ball alone under a uniform white environment
/// reflects exactly the environment's radiance, and nothing occludes it, so occlusion on
/// changes nothing. GTAO sees nothing above the depth's own tangent planes of a convex
/// mesh and divides by the open-horizon sum of the same slices, so the frame is the same
/// bit for bit.
#[test]
fn a_ball_alone_in_the_white_furnace_is_not_occluded() {
    let off = hdr(&ball_scene(false, 1.0, ""));
    let on = hdr(&ball_scene(false, 1.0, ON));
    let (differing, max) = differences(&on, &off);
    assert_eq!(differing, 0, "{differing} channels differ, by up to {max}");
    let covered: Vec<f32> = off.chunks_exact(4).filter(|p| p[3] > 0.0).map(|p| p[0]).collect();
    assert!(covered.len() > 1000, "the ball covers {} pixels", covered.len());
    assert!(covered.iter().all(|&r| (r - 1.0).abs() < 1e-5), "the ball is not white");
}

/// The pixel a world point projects to, in the frame of `scene`.
fn pixel_of(scene: &Scene, point: Vec3) -> (usize, usize) {
    let clip = scene.camera.view_projection(SIZE.0 as f32 / SIZE.1 as f32) * point.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let x = ((ndc.x + 1.0) * 0.5 * SIZE.0 as f32) as usize;
    let y = ((ndc.y + 1.0) * 0.5 * SIZE.1 as f32) as usize;
    (x, y)
}

/// Pixels of the ground in front of the ball, 0.25 and 0.49 from its surface, and of open
/// ground, 1.47 from it (further than the radius of 0.8), all in view.
fn ground_pixels(scene: &Scene) -> ((usize, usize), (usize, usize), (usize, usize)) {
    let at = |x, z| pixel_of(scene, Vec3::new(x, 0.0, z));
    (at(0.0, 0.75), at(0.0, 1.1), at(-1.6, 1.6))
}

fn red(hdr: &[f32], (x, y): (usize, usize)) -> f32 {
    hdr[(y * SIZE.0 as usize + x) * 4]
}

/// The ground beside the ball's contact sees less of the sky than open ground: with
/// occlusion it is darker, by more the nearer the contact, while open ground keeps the
/// unoccluded radiance; the multi-bounce fit gives back part of what a bright ground and
/// ball reflect. Without occlusion both are the same.
#[test]
fn the_ground_beside_the_ball_is_darker_than_open_ground() {
    let grey = |occlusion: &str| ball_scene(true, 0.5, occlusion);
    let s = scene(&grey(ON));
    let (near, further, open) = ground_pixels(&s);
    let off = hdr(&grey(""));
    let on = hdr(&grey(ON));
    let plain = hdr(&grey(&format!("{ON}\nmulti_bounce = false")));
    assert_eq!(
        red(&off, near),
        red(&off, open),
        "without occlusion the ground is uniform"
    );
    assert_eq!(red(&on, open), red(&off, open), "open ground is not occluded");
    let (near_on, further_on) = (red(&on, near), red(&on, further));
    assert!(
        near_on < NEAR_AT_MOST * red(&off, near) && near_on < further_on && further_on < red(&off, further),
        "near {near_on}, further {further_on}, open {}",
        red(&on, open)
    );
    assert!(
        red(&plain, near) < near_on,
        "the multi-bounce fit raises the visibility of a grey ground: {} against {near_on}",
        red(&plain, near)
    );
}

/// The occlusion debug view shows the visibility: 1 on open ground, less beside the ball;
/// with the pass off, 1 everywhere.
#[test]
fn the_debug_view_shows_the_visibility() {
    let s = scene(&ball_scene(true, 0.5, ON));
    let (near, _, open) = ground_pixels(&s);
    let view = |s: &Scene| {
        gpu().exclusive(|renderer| {
            renderer.debug_view = DebugView::Occlusion;
            let frame = try_render(renderer, s, SIZE.0, SIZE.1);
            renderer.debug_view = DebugView::Shaded;
            frame.expect("render").hdr
        })
    };
    let on = view(&s);
    assert_eq!(red(&on, open), 1.0);
    assert!(
        red(&on, near) < NEAR_AT_MOST,
        "visibility beside the ball {}",
        red(&on, near)
    );
    let off = view(&scene(&ball_scene(true, 0.5, "")));
    let covered: Vec<f32> = off.chunks_exact(4).filter(|p| p[3] > 0.0).map(|p| p[0]).collect();
    assert!(covered.iter().all(|&v| v == 1.0));
}

/// Off, the frame is the frame without the section, bit for bit, whether the scene turns
/// it off or the renderer's toggle does.
#[test]
fn occlusion_off_is_the_frame_without_it() {
    let without = hdr(&ball_scene(true, 0.5, ""));
    let disabled = hdr(&ball_scene(true, 0.5, "[occlusion]\nenabled = false\nradius = 2.0"));
    assert_eq!(differences(&disabled, &without).0, 0);
    let toggled = gpu().exclusive(|renderer| {
        renderer.occlusion = false;
        let frame = try_render(renderer, &scene(&ball_scene(true, 0.5, ON)), SIZE.0, SIZE.1);
        renderer.occlusion = true;
        frame.expect("render").hdr
    });
    assert_eq!(differences(&toggled, &without).0, 0);
}

/// Frames that turn the pass on and off and change size in one renderer: the images
/// are made again and the forward pass's set follows, with the validation layer (and its
/// synchronization checks) silent, and each frame is what a fresh render of it gives.
#[test]
fn switching_on_off_and_resizing_stays_valid_and_consistent() {
    let on = scene(&ball_scene(true, 0.5, ON));
    let off = scene(&ball_scene(true, 0.5, ""));
    let reference = hdr(&ball_scene(true, 0.5, ON));
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&on).expect("upload");
        for (s, size) in [(&on, (64, 48)), (&off, (64, 48)), (&on, (96, 72)), (&on, SIZE)] {
            let extent = vk::Extent2D {
                width: size.0,
                height: size.1,
            };
            let target = OffscreenTarget::new(&renderer.device, extent).expect("target");
            for _ in 0..2 {
                let ms = renderer.draw_offscreen(s, &gpu_scene, &target, 1.0).expect("draw");
                let frame = renderer.read_offscreen(&target, ms).expect("read");
                if size == SIZE {
                    assert_eq!(differences(&frame.hdr, &reference).0, 0);
                }
            }
        }
    });
}

const OBJECTS: &str = "[occlusion]\nobjects = true";

/// A second ball beside the first, 2.4 from it (0.4 between their surfaces).
const SECOND_BALL: &str = "\n[[objects]]\nmesh = \"builtin:sphere\"\nposition = [2.4, 1.0, 0.0]\nmaterial = \"clay\"\n";

/// The white furnace with `[occlusion] objects`: a white ball alone under a uniform white
/// environment, and two white balls on a white ground, render as without it, bit for bit.
/// Exactly, not within a tolerance: a sphere of albedo 1 under a uniform radiance L sends
/// back ρ L = L, which is what it hides, so every factor is 1 − π F · 0 / E = 1 (and the
/// uniform environment's SH irradiance over π is L times 1.0, no rounding); the ground is
/// no occluder and each ball skips its own sphere.
#[test]
fn objects_keep_the_white_furnace() {
    for (ground, extra) in [(false, ""), (true, SECOND_BALL)] {
        let off = hdr(&(ball_scene(ground, 1.0, "") + extra));
        let on = hdr(&(ball_scene(ground, 1.0, OBJECTS) + extra));
        let (differing, max) = differences(&on, &off);
        assert_eq!(differing, 0, "ground {ground}: {differing} channels differ, by up to {max}");
        let covered: Vec<f32> = on.chunks_exact(4).filter(|p| p[3] > 0.0).map(|p| p[0]).collect();
        assert!(covered.iter().all(|&r| (r - 1.0).abs() < 1e-5), "ground {ground}: not white");
    }
}

/// A grey ball does not occlude itself: alone, it renders as without object occlusion,
/// bit for bit (points on its surface lie on its own sphere, which would hide half their
/// sky), while a second ball beside it does darken it. Each ball's draw skips its own run
/// of the occluders: listed the other way round, the pair renders the same, bit for bit
/// (each ball's one factor is the other's).
#[test]
fn a_ball_does_not_occlude_itself() {
    let off = hdr(&ball_scene(false, 0.5, ""));
    let on = hdr(&ball_scene(false, 0.5, OBJECTS));
    assert_eq!(differences(&on, &off).0, 0);
    let pair_off = hdr(&(ball_scene(false, 0.5, "") + SECOND_BALL));
    let pair = ball_scene(false, 0.5, OBJECTS) + SECOND_BALL;
    let pair_on = hdr(&pair);
    let darker = pair_on.chunks_exact(4).zip(pair_off.chunks_exact(4)).filter(|(a, b)| a[0] < b[0]).count();
    assert!(darker > 100, "{darker} pixels darkened by the other ball");
    let swapped = pair.replacen("[[objects]]", &format!("{}\n[[objects]]", SECOND_BALL.trim()), 1);
    let swapped = &swapped[..swapped.rfind(SECOND_BALL).expect("the second ball")];
    assert_eq!(scene(swapped).objects[0].position.x, 2.4, "{swapped}");
    assert_eq!(differences(&hdr(swapped), &pair_on).0, 0);
}

/// The ground beside a grey ball darkens with `[occlusion] objects` (GTAO off), more the
/// nearer the contact: 0.25 from the ball's surface the sphere's cap (half-angle 53°, its
/// axis 37° from the normal) takes the form factor cos 37° sin² 53° = 0.512 of the sky
/// and sends back half of it (albedo 0.5), so the ground keeps 1 − 0.512 · 0.5 = 0.744
/// of its light; further away less is taken, and without the key both are the same.
#[test]
fn objects_darken_the_ground_beside_a_ball_more_nearer_it() {
    let grey = |occlusion: &str| ball_scene(true, 0.5, occlusion);
    let s = scene(&grey(OBJECTS));
    let (near, further, open) = ground_pixels(&s);
    let off = hdr(&grey(""));
    let on = hdr(&grey(OBJECTS));
    assert_eq!(red(&off, near), red(&off, further), "without occlusion the ground is uniform");
    let kept = |p| red(&on, p) / red(&off, p);
    let (near_kept, further_kept, open_kept) = (kept(near), kept(further), kept(open));
    // The pixel's centre is within a few hundredths of the point the figure is for.
    assert!((near_kept - 0.744).abs() < 0.03, "near the ball the ground keeps {near_kept}");
    assert!(
        near_kept < further_kept && further_kept < open_kept && open_kept < 1.0,
        "kept: near {near_kept}, further {further_kept}, open {open_kept}"
    );
}

/// Two grey balls off the centre of a grey ground under the studio, (centre, radius), with
/// the objects' occlusion.
const STUDIO_BALLS: [(Vec3, f32); 2] = [(Vec3::new(-1.2, 1.0, 0.5), 1.0), (Vec3::new(1.5, 0.6, -0.8), 0.6)];

/// The scene of [`STUDIO_BALLS`], the ground's occlusion from its map or (`ground_map =
/// false`) from every sphere.
fn studio_ground(ground_map: bool) -> String {
    studio(&STUDIO_BALLS, &format!("ground_map = {ground_map}"))
}

/// Grey `balls` (centre, radius) on a grey ground under the studio, with the objects'
/// occlusion and the `[occlusion]` keys `occlusion`.
fn studio(balls: &[(Vec3, f32)], occlusion: &str) -> String {
    let balls: String = balls
        .iter()
        .map(|(c, r)| {
            let position = format!("[{}, {}, {}]", c.x, c.y, c.z);
            format!("[[objects]]\nmesh = \"builtin:sphere\"\nposition = {position}\nscale = {r}\nmaterial = \"clay\"\n")
        })
        .collect();
    format!(
        r#"
[camera]
position = [0.0, 3.0, 7.0]
target = [0.3, 0.5, 0.0]
fov_y_degrees = 40.0

[environment]
kind = "studio"

[occlusion]
objects = true
{occlusion}

{balls}[[objects]]
mesh = "builtin:plane"
scale = 6.0
material = "clay"

[materials.clay]
base_color = [0.5, 0.5, 0.5]
specular = "none"
"#
    )
}

/// Which of the ground (`Some(None)`) or a ball (`Some(Some(i))`) the camera ray through
/// the centre of pixel (x, y) surely meets, clear of edges; None near an edge or off both.
fn studio_pixel(rays: &CameraRays, x: u32, y: u32) -> Option<Option<usize>> {
    let (o, d) = rays.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, SIZE.0, SIZE.1);
    let meets = |(c, r): (Vec3, f32), scale: f64| {
        let oc = o - c.as_dvec3();
        let (b, c) = (oc.dot(d) / d.length(), oc.length_squared() - (f64::from(r) * scale).powi(2));
        b * b - c >= 0.0 && -b > 0.0
    };
    if let Some(ball) = STUDIO_BALLS.iter().position(|&ball| meets(ball, 0.97)) {
        return Some(Some(ball));
    }
    let g = o + d * (-o.y / d.y);
    let on_ground = d.y < 0.0 && g.x.abs() < 5.9 && g.z.abs() < 5.9;
    (on_ground && !STUDIO_BALLS.iter().any(|&ball| meets(ball, 1.05))).then_some(None)
}

/// Frame `a` of the studio's balls against frame `b`, which differ on one kind of surface
/// only (`ground_differs`: the ground, else the balls).
struct StudioComparison {
    /// The relative differences of the clear pixels of that kind, sorted.
    errors: Vec<f32>,
    /// The least share of its light `b` keeps there against the frame without the objects'
    /// occlusion.
    darkest: f32,
    /// Clear pixels of the other kind, each the same in both frames bit for bit.
    same: usize,
}

impl StudioComparison {
    fn new(s: &Scene, a: &[f32], b: &[f32], ground_differs: bool) -> Self {
        let mut open = s.clone();
        open.occlusion.objects = false;
        let open = render(&open, SIZE.0, SIZE.1).hdr;
        let rays = CameraRays::new(&s.camera, SIZE.0, SIZE.1);
        let (mut errors, mut same, mut darkest) = (Vec::new(), 0, 1.0f32);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let i = 4 * (y * SIZE.0 + x) as usize;
                let Some(pixel) = studio_pixel(&rays, x, y) else { continue };
                if pixel.is_none() == ground_differs {
                    errors.push(((a[i] - b[i]) / b[i]).abs());
                    darkest = darkest.min(b[i] / open[i]);
                } else {
                    assert_eq!(a[i..i + 3], b[i..i + 3], "pixel ({x}, {y}) changed");
                    same += 1;
                }
            }
        }
        errors.sort_by(f32::total_cmp);
        Self { errors, darkest, same }
    }

    fn median_and_max(&self) -> (f32, f32) {
        (self.errors[self.errors.len() / 2], self.errors[self.errors.len() - 1])
    }
}

/// The ground's occlusion map is what every sphere makes of the ground's light at each
/// pixel, to its bilinear interpolation over 256² texels (4.7 cm here) and fp16: the
/// ground's pixels within 0.6% of those of the frame without the map (0.45% measured,
/// next to the contacts, where the occlusion bends fastest; 0.2% with 512² texels) and
/// their median within 0.05% (2.7e-4, fp16's rounding), where the spheres take up to half
/// of the light. The balls' pixels are the same bit for bit.
#[test]
fn the_grounds_occlusion_map_is_the_occlusion_at_each_pixel() {
    let s = scene(&studio_ground(true));
    let c = StudioComparison::new(&s, &hdr(&studio_ground(true)), &hdr(&studio_ground(false)), true);
    let ((median, max), ground, darkest) = (c.median_and_max(), c.errors.len(), c.darkest);
    eprintln!("{ground} ground pixels: relative error median {median:.2e}, max {max:.2e}; darkest kept {darkest}");
    assert!(ground > 5000 && c.same > 1000, "{ground} ground pixels, {} of the balls", c.same);
    assert!(darkest < 0.6, "the spheres take little of the ground's light: {darkest}");
    assert!(median < 5e-4 && max < 6e-3, "median {median:.2e}, max {max:.2e}");
}

/// The objects' occlusion computed at the balls' vertices is the one computed at each of
/// their pixels, to the interpolation across their triangles (edges 8 cm at most, an
/// eighteenth of the 1.4 gap, so within (3/4)(1/18)² = 0.23% of the occlusion): the balls'
/// pixels within 0.2% of those of the frame that computes it at each pixel (5.3e-4
/// measured), where the other ball takes up to a third of the light. The ground's pixels,
/// which read the map, are the same bit for bit; and where the balls come closer than four
/// of their edges, every pixel computes it again, so the frame is the per-pixel frame.
#[test]
fn objects_occlusion_at_vertices_is_the_occlusion_at_each_pixel() {
    let s = scene(&studio_ground(true));
    let at_vertices = hdr(&studio(&STUDIO_BALLS, "per_vertex = true"));
    let every_pixel = hdr(&studio(&STUDIO_BALLS, "per_vertex = false"));
    let c = StudioComparison::new(&s, &at_vertices, &every_pixel, false);
    let ((median, max), balls, darkest) = (c.median_and_max(), c.errors.len(), c.darkest);
    eprintln!("{balls} ball pixels: relative error median {median:.2e}, max {max:.2e}; darkest kept {darkest}");
    assert!(c.same > 5000 && balls > 1000, "{} ground pixels, {balls} of the balls", c.same);
    assert!(darkest < 0.75, "the balls take little of each other's light: {darkest}");
    assert!(max < 2e-3, "max {max:.2e}");

    let near = [STUDIO_BALLS[0], (STUDIO_BALLS[0].0 + Vec3::new(1.7, -0.4, 0.0), 0.6)];
    let (a, b) = (hdr(&studio(&near, "per_vertex = true")), hdr(&studio(&near, "per_vertex = false")));
    assert_eq!(differences(&a, &b).0, 0, "balls 0.1 apart read the spheres at every pixel");
}

/// The balls' occlusion by each other, read at their vertices, is computed when what it is
/// made of changes, not every frame: once for two frames, not when the camera moves, again
/// when a ball moves, back where it was (the first frame bit for bit), or the environment
/// changes.
#[test]
fn objects_occlusion_at_vertices_is_computed_only_when_the_scene_changes() {
    let mut s = scene(&studio(&STUDIO_BALLS, "per_vertex = true"));
    gpu().exclusive(|renderer| {
        let gpu_scene = renderer.upload(&s).expect("upload");
        let offscreen = OffscreenTarget::new(&renderer.device, vk::Extent2D { width: 64, height: 48 }).expect("target");
        let frame = |renderer: &mut argil::render::Renderer, s: &Scene| draw_hdr(renderer, s, &gpu_scene, &offscreen);
        let before = renderer.vertex_light_computes();
        let first = frame(renderer, &s);
        assert_eq!(frame(renderer, &s), first);
        assert_eq!(renderer.vertex_light_computes(), before + 1);
        s.camera.position.x += 0.5;
        frame(renderer, &s);
        assert_eq!(renderer.vertex_light_computes(), before + 1, "the camera moved alone");
        s.camera.position.x -= 0.5;
        s.objects[0].position.x += 0.3;
        assert_ne!(frame(renderer, &s), first);
        assert_eq!(renderer.vertex_light_computes(), before + 2);
        s.objects[0].position.x -= 0.3;
        assert_eq!(frame(renderer, &s), first);
        assert_eq!(renderer.vertex_light_computes(), before + 3);
        if let Environment::Studio { intensity, .. } = &mut s.environment {
            *intensity *= 0.5;
        }
        frame(renderer, &s);
        assert_eq!(renderer.vertex_light_computes(), before + 4);
    });
}

/// The occlusion map is computed when what it is made of changes, not every frame: once
/// for two frames of the same scene, even with a floor frame between (`CountedFrames::new`),
/// again when an object moves or the environment changes, not when the camera moves; without
/// `ground_map`, never.
#[test]
fn the_grounds_occlusion_map_is_computed_only_when_the_scene_changes() {
    let mut s = scene(&studio_ground(true));
    gpu().exclusive(|renderer| {
        let frames = CountedFrames::new(renderer, &s, Renderer::ground_occlusion_renders);
        s.camera.position.x += 0.5;
        assert_eq!(frames.draw(renderer, &s), 1);
        s.objects[0].position.x += 0.5;
        assert_eq!(frames.draw(renderer, &s), 2);
        if let Environment::Studio { intensity, .. } = &mut s.environment {
            *intensity *= 0.5;
        }
        assert_eq!(frames.draw(renderer, &s), 3);
        s.occlusion.ground_map = false;
        s.objects[0].position.x += 0.5;
        assert_eq!(frames.draw(renderer, &s), 3);
    });
}
