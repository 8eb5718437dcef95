//! The solids shaded once a pixel from their surfaces (src/render/deferred.rs): on lavapipe
//! with the validation layer on, against the forward pass that shades them per triangle.

mod common;

use argil::render::{DebugView, OffscreenTarget, Renderer};
use argil::scene::{Object, Scene, DEFAULT_SCENE_TOML};
use ash::vk;
use common::{draw_hdr, gpu, scene};
use glam::Vec3;

const SIZE: vk::Extent2D = vk::Extent2D { width: 96, height: 64 };

/// A scene whose solids' surfaces hold what the G-buffer must carry besides the default
/// scene's (deferred_solids_are_shaded_as_the_forward_pass_shades_them).
const MAPPED: &str = r#"
[camera]
position = [0.0, 1.2, 4.0]
target = [0.0, 0.4, 0.0]
fov_y_degrees = 40.0

[[lights]]
kind = "point"
position = [2.0, 4.0, 3.0]
intensity = [30.0, 30.0, 30.0]

[environment]
kind = "studio"
reflection = "seed"

[occlusion]
objects = true
per_vertex = false

[antialiasing]
specular = true

[[objects]]
mesh = "builtin:sphere"
position = [-0.6, 0.5, 0.0]
scale = 0.5
material = "plasticine"

[[objects]]
mesh = "builtin:torus"
position = [0.7, 0.3, -0.3]
scale = 0.5
material = "glowing"

[[objects]]
mesh = "builtin:plane"
scale = 6.0
material = "ground"

[materials.plasticine]
preset = "plasticine"

[materials.glowing]
preset = "terracotta"
emission = [0.2, 0.05, 0.0]

[materials.glowing.occlusion_map]
texture = "builtin:clay-lumps"

[materials.ground]
base_color = [0.7, 0.7, 0.7]
"#;

/// A frame of `s` at `size` with the solids deferred or drawn forward, and how many were
/// deferred.
fn frame(renderer: &mut Renderer, s: &Scene, size: vk::Extent2D, deferred: bool) -> (Vec<f32>, usize) {
    let gpu_scene = renderer.upload(s).expect("upload");
    let target = OffscreenTarget::new(&renderer.device, size).expect("target");
    renderer.deferred = deferred;
    let hdr = draw_hdr(renderer, s, &gpu_scene, &target);
    let objects = renderer.deferred_objects();
    renderer.deferred = true;
    (hdr, objects)
}

/// The largest difference between two frames' channels relative to the larger, over the
/// channels above `floor`, and the count of channels that differ at all.
fn largest_relative_difference(a: &[f32], b: &[f32], floor: f32) -> (f32, usize) {
    assert_eq!(a.len(), b.len());
    let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
    let largest = (a.iter().zip(b))
        .filter(|(x, y)| x.abs().max(y.abs()) > floor)
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()))
        .fold(0.0, f32::max);
    (largest, differ)
}

/// The G-buffer holds the fp32 values the forward pass's shading starts from, so the
/// deferred frame is the forward one but for the last bits of arithmetic that the two
/// shaders' compilers order differently (the surface's own light is added to the bounce
/// before the rest, not after): at most a few units in the last place of fp32 (1e-6 of the
/// value allows 8), most channels (the background's, the ground's) the same bit for bit.
/// Scenes at a size where the solids' triangles are small enough to be deferred: the
/// default one (split sum, pre-integrated subsurface, maps, the bounce and the objects'
/// occlusion at the vertices, soft shadows at the pixels), and one that reads what the
/// G-buffer must carry otherwise: the report's reflection with its noise map, an occlusion
/// map, emission, a hard light's shadow at the pixels, the objects' occlusion at the
/// pixels and specular anti-aliasing.
#[test]
fn deferred_solids_are_shaded_as_the_forward_pass_shades_them() {
    let scenes = [
        ("default", Scene::from_toml(DEFAULT_SCENE_TOML, "default", std::path::Path::new("")).expect("default")),
        ("mapped", scene(MAPPED)),
    ];
    gpu().exclusive(|renderer| {
        for (name, s) in &scenes {
            let (forward, none) = frame(renderer, s, SIZE, false);
            let (deferred, objects) = frame(renderer, s, SIZE, true);
            assert_eq!((none, objects), (0, 2), "{name}: the ball and the ring are deferred");
            let (largest, differ) = largest_relative_difference(&deferred, &forward, 1e-6);
            eprintln!("{name}: {differ} of {} channels differ, by at most {largest:.2e} of their value", forward.len());
            assert!(largest < 1e-6, "{name}: the deferred frame is {largest:e} from the forward one");
            assert!(differ < forward.len() / 2, "{name}: the background and the ground are the same");
        }
    });
}

/// Solids of the same material share their G-buffer pipeline, each draw's instance saying
/// which solid a pixel shows: the frame is the forward pass's.
#[test]
fn solids_of_one_material_share_their_surfaces_pipeline() {
    // The mapped scene's ring made a second ball of the first one's clay, beside it.
    let mut s = scene(MAPPED);
    s.objects[1] = Object { position: Vec3::new(0.6, 0.5, -0.4), ..s.objects[0] };
    gpu().exclusive(|renderer| {
        let (forward, _) = frame(renderer, &s, SIZE, false);
        let (deferred, objects) = frame(renderer, &s, SIZE, true);
        assert_eq!((objects, renderer.deferred_surface_pipelines()), (2, 1));
        let (largest, _) = largest_relative_difference(&deferred, &forward, 1e-6);
        assert!(largest < 1e-6, "the deferred frame is {largest:e} from the forward one");
    });
}

/// Frames that the G-buffer does not serve draw every object forward: multisampled ones, a
/// debug view, the generic pipelines, and one whose solids' triangles are large (the
/// default scene's ball and ring cover about 111 and 131 pixels a triangle at 2560×1440,
/// 0.2 at 96×64); and an object that reads its soft shadows at its vertices is drawn forward
/// beside the deferred ones.
#[test]
fn frames_the_g_buffer_does_not_serve_are_drawn_forward() {
    let default = Scene::from_toml(DEFAULT_SCENE_TOML, "default", std::path::Path::new("")).expect("default");
    gpu().exclusive(|renderer| {
        let deferred = |renderer: &mut Renderer, s: &Scene| frame(renderer, s, SIZE, true).1;
        assert_eq!(deferred(renderer, &default), 2);
        let large = vk::Extent2D { width: 2560, height: 1440 };
        assert_eq!(frame(renderer, &default, large, true).1, 0, "large triangles");
        let mut msaa = default.clone();
        msaa.antialiasing.msaa = 4;
        assert_eq!(deferred(renderer, &msaa), 0, "multisampled");
        renderer.debug_view = DebugView::Normals;
        assert_eq!(deferred(renderer, &default), 0, "a debug view");
        renderer.debug_view = DebugView::Shaded;
        renderer.generic = true;
        assert_eq!(deferred(renderer, &default), 0, "the generic pipelines");
        renderer.generic = false;
        let mut per_vertex = default.clone();
        per_vertex.shadow_per_vertex = true;
        assert_eq!(deferred(renderer, &per_vertex), 1, "the ring reads the ball's shadow at its vertices");
    });
}
