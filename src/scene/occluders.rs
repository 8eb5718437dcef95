//! The objects as spheres that hide the environment's light (`[occlusion] objects`,
//! shaders/lib/object_occlusion.glsl): the builtin sphere exactly, the builtin torus as
//! spheres along its ring, any other mesh its bounding sphere. The builtin plane, the
//! ground, is none: what it hides is below every surface above it.

use glam::Vec3;

use super::limits::MAX_OCCLUDERS;
use super::mesh::{MeshExtent, TORUS_RADII};
use super::Scene;

/// Spheres a builtin torus becomes: with 9 along the ring, each of the tube's volume share
/// (radius ∛(π R r² / 6) = 0.40 for R = 1, r = 0.35), neighbours overlap slightly, so the
/// ring has no gaps a ray passes through between them.
pub const TORUS_SPHERES: usize = 9;

/// The share of its gap to the nearest other sphere an object's longest edge may span for
/// its occlusion to be computed at its vertices ([`Scene::occlusion_at_vertices`]).
pub const VERTEX_OCCLUSION_GAP_SHARE: f32 = 0.25;

/// One sphere of an object, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occluder {
    pub centre: Vec3,
    pub radius: f32,
    /// The object's material's base colour: what the sphere reflects of the light it receives.
    pub albedo: Vec3,
    /// The first part of the file object it stands for (`Object::first_part`), whose
    /// parts it does not occlude.
    pub object: usize,
}

impl Scene {
    /// Object `index`'s bounding sphere in world space: (centre, radius).
    pub fn bounding_sphere(&self, index: usize) -> (Vec3, f32) {
        let o = &self.objects[index];
        let (centre, radius) = self.meshes[o.mesh].bounding_sphere();
        (o.position + centre * o.scale, radius * o.scale)
    }

    /// Object `index`'s bounding box in world space: (lowest corner, highest corner).
    pub fn bounding_box(&self, index: usize) -> (Vec3, Vec3) {
        let o = &self.objects[index];
        let (lo, hi) = self.meshes[o.mesh].bounding_box();
        (o.position + lo * o.scale, o.position + hi * o.scale)
    }

    /// Each object's bounding sphere in world space: (centre, radius).
    pub fn bounding_spheres(&self) -> Vec<(Vec3, f32)> {
        (0..self.objects.len()).map(|i| self.bounding_sphere(i)).collect()
    }

    /// The spheres of every object with `[occlusion] objects` on (none off): the largest
    /// [`MAX_OCCLUDERS`], grouped by object in the scene's order, so that the spheres a
    /// draw skips, its own object's, are one run ([`Scene::own_occluders`]).
    pub fn occluders(&self) -> Vec<Occluder> {
        if !self.occlusion.objects {
            return Vec::new();
        }
        // Every frame lists them: a mesh's vertices are walked only for a mesh that is
        // its bounding sphere, not for the builtins, whose spheres are known.
        let mut spheres: Vec<Occluder> = self
            .objects
            .iter()
            .enumerate()
            .flat_map(|(i, o)| {
                let albedo = self.materials[o.material].base_color;
                let sphere = |centre: Vec3, radius: f32| Occluder {
                    centre,
                    radius,
                    albedo,
                    object: o.first_part(i),
                };
                match self.meshes[o.mesh].name.as_str() {
                    "builtin:plane" => Vec::new(),
                    "builtin:sphere" => vec![sphere(o.position, o.scale)],
                    "builtin:torus" => {
                        let (ring, tube) = TORUS_RADII;
                        let radius = (std::f32::consts::PI * ring * tube * tube / 6.0).cbrt();
                        (0..TORUS_SPHERES)
                            .map(|k| {
                                let phi = std::f32::consts::TAU * k as f32 / TORUS_SPHERES as f32;
                                let on_ring = Vec3::new(phi.sin(), 0.0, phi.cos()) * ring;
                                sphere(o.position + on_ring * o.scale, radius * o.scale)
                            })
                            .collect()
                    }
                    _ => {
                        let (centre, radius) = self.bounding_sphere(i);
                        vec![sphere(centre, radius)]
                    }
                }
            })
            .collect();
        spheres.sort_by(|a, b| b.radius.total_cmp(&a.radius));
        spheres.truncate(MAX_OCCLUDERS);
        spheres.sort_by_key(|s| s.object);
        spheres
    }

    /// The run of `occluders` ([`Scene::occluders`]) that stands for object `index`'s file
    /// object, which does not occlude it: (first, count), count 0 for an object without
    /// spheres.
    pub fn own_occluders(&self, occluders: &[Occluder], index: usize) -> (usize, usize) {
        let object = self.objects[index].first_part(index);
        let first = occluders.iter().position(|o| o.object == object).unwrap_or(0);
        let count = occluders[first..].iter().take_while(|o| o.object == object).count();
        (first, count)
    }

    /// Whether object `index`, of mesh size `extent`, has its occlusion by the other
    /// objects' spheres computed at its vertices and interpolated (`[occlusion]
    /// per_vertex`): not the ground, whose square spans the scene, and only where its
    /// longest edge is at most [`VERTEX_OCCLUSION_GAP_SHARE`] of the gap between its
    /// bounding sphere and every other sphere. A sphere's cap, (r/d)² cos θ, bends over
    /// lengths of its distance d, so a straight line across an edge h misses it by about
    /// (3/4)(h/d)² of itself: 5% of the occlusion at the largest edge allowed.
    pub fn occlusion_at_vertices(&self, occluders: &[Occluder], index: usize, extent: MeshExtent) -> bool {
        let o = &self.objects[index];
        let world = o.world_extent(&extent);
        let (centre, radius) = (world.centre, world.radius);
        let own = o.first_part(index);
        let least_gap = world.longest_edge / VERTEX_OCCLUSION_GAP_SHARE;
        self.occlusion.per_vertex
            && self.ground_index() != Some(index)
            && (occluders.iter().filter(|s| s.object != own))
                .all(|s| s.centre.distance(centre) - s.radius - radius >= least_gap)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    #[test]
    fn objects_become_spheres_and_the_ground_none() {
        let text = r#"
[camera]
position = [0.0, 2.0, 6.0]
target = [0.0, 0.0, 0.0]
[occlusion]
objects = true
[[objects]]
mesh = "builtin:plane"
scale = 5.0
[[objects]]
mesh = "builtin:sphere"
position = [1.0, 0.5, 0.0]
scale = 0.5
[[objects]]
mesh = "builtin:torus"
position = [-1.0, 0.35, 0.0]
scale = 0.5
[[objects]]
mesh = "builtin:cube"
position = [0.0, 1.0, -2.0]
"#;
        let scene = Scene::from_toml(text, "scene.toml", Path::new("")).expect("scene");
        let spheres = scene.occluders();
        assert_eq!(spheres.len(), 1 + TORUS_SPHERES + 1);
        assert!(spheres.iter().all(|s| s.object != 0), "the ground is no occluder");
        let ball: Vec<_> = spheres.iter().filter(|s| s.object == 1).collect();
        assert_eq!((ball[0].centre, ball[0].radius), (Vec3::new(1.0, 0.5, 0.0), 0.5));
        let cube = spheres.iter().find(|s| s.object == 3).expect("the cube's sphere");
        assert!((cube.radius - 3f32.sqrt()).abs() < 1e-5, "{}", cube.radius);
        for ring in spheres.iter().filter(|s| s.object == 2) {
            let offset = ring.centre - Vec3::new(-1.0, 0.35, 0.0);
            assert!((offset.length() - 0.5).abs() < 1e-5 && offset.y == 0.0, "{offset}");
            assert!((ring.radius - 0.2).abs() < 0.005, "{}", ring.radius);
        }
        let off = Scene::from_toml(&text.replace("objects = true", "objects = false"), "s", Path::new(""));
        assert!(off.expect("scene").occluders().is_empty());

        // The torus and the cube as the two parts of one model: the cube's sphere is the
        // model's, and does not occlude the torus.
        let mut model = scene;
        model.objects[3].part = 1;
        let spheres = model.occluders();
        assert!(spheres.iter().all(|s| s.object != 3));
        assert_eq!(spheres.iter().filter(|s| s.object == 2).count(), TORUS_SPHERES + 1);
        assert!(spheres.windows(2).all(|pair| pair[0].object <= pair[1].object), "grouped by object");
        let torus = spheres.iter().position(|s| s.object == 2).expect("the torus");
        assert_eq!(model.own_occluders(&spheres, 3), (torus, TORUS_SPHERES + 1));
        assert_eq!(model.own_occluders(&spheres, 2), (torus, TORUS_SPHERES + 1));
        assert_eq!(model.own_occluders(&spheres, 1), (0, 1));
        assert_eq!(model.own_occluders(&spheres, 0).1, 0, "the ground has no spheres");
    }

    /// An object's occlusion is computed at its vertices with `per_vertex`, where its
    /// longest edge is at most a quarter of its gap to every other object's sphere, and
    /// never on the ground.
    #[test]
    fn occlusion_is_at_vertices_where_edges_are_small_against_the_gaps() {
        let text = |x: f32| {
            format!(
                "[camera]\nposition = [0.0, 2.0, 9.0]\ntarget = [0.0, 0.0, 0.0]\n\
                 [occlusion]\nobjects = true\nper_vertex = true\n\
                 [[objects]]\nmesh = \"builtin:plane\"\nscale = 5.0\n\
                 [[objects]]\nmesh = \"builtin:sphere\"\nposition = [0.0, 1.0, 0.0]\n\
                 [[objects]]\nmesh = \"builtin:sphere\"\nposition = [{x}, 1.0, 0.0]\nscale = 0.5\n"
            )
        };
        let scene = Scene::from_toml(&text(3.5), "scene.toml", Path::new("")).expect("scene");
        let extents: Vec<MeshExtent> = scene.objects.iter().map(|o| scene.meshes[o.mesh].extent()).collect();
        let sphere = extents[1];
        // 32 cells along each edge of the cube the sphere is made from.
        assert!(sphere.longest_edge > 0.02 && sphere.longest_edge < 0.1, "{sphere:?}");
        let at_vertices = |scene: &Scene| {
            let occluders = scene.occluders();
            (0..3).map(|i| scene.occlusion_at_vertices(&occluders, i, extents[i])).collect::<Vec<_>>()
        };
        assert_eq!(at_vertices(&scene), [false, true, true], "a gap of 2");
        // The gap at which the big ball's edges are a quarter of it.
        let least = 1.5 + sphere.longest_edge / VERTEX_OCCLUSION_GAP_SHARE;
        let near = |x: f32| Scene::from_toml(&text(x), "scene.toml", Path::new("")).expect("scene");
        assert_eq!(at_vertices(&near(least + 0.01)), [false, true, true]);
        assert_eq!(at_vertices(&near(least - 0.01)), [false, false, true], "the small ball's edges are half");
        assert_eq!(at_vertices(&near(1.4)), [false, false, false], "overlapping");
        let mut off = scene;
        off.occlusion.per_vertex = false;
        assert_eq!(at_vertices(&off), [false; 3]);
    }
}
