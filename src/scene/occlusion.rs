//! `[occlusion]`: screen-space ambient occlusion of the environment's light (GTAO), off
//! unless a scene asks for it.

/// The settings of the occlusion pass (src/render/occlusion.rs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occlusion {
    pub enabled: bool,
    /// How far occluders are searched for, in world units.
    pub radius: f32,
    /// Slice directions per pixel.
    pub slices: u32,
    /// Depth samples on each side of a slice.
    pub steps: u32,
    /// Whether the diffuse visibility is raised by GTAO's multi-bounce fit of the albedo
    /// (the light the occluders reflect); off, the plain visibility scales it.
    pub multi_bounce: bool,
    /// Whether the objects, seen as spheres, hide the environment's light beyond the
    /// screen-space radius (shaders/lib/object_occlusion.glsl); independent of `enabled`.
    pub objects: bool,
    /// Whether the objects' occlusion of the ground is read from a map over the ground,
    /// computed once per change (src/render/ground_maps.rs), rather than from every sphere
    /// at every pixel of the ground.
    pub ground_map: bool,
    /// Whether an object's occlusion by the others is computed at its vertices and
    /// interpolated where its triangles are small against its distance to them
    /// (`Scene::occlusion_at_vertices`), rather than at every pixel.
    pub per_vertex: bool,
}

impl Default for Occlusion {
    fn default() -> Self {
        Self {
            enabled: false,
            radius: 0.5,
            slices: 4,
            steps: 8,
            multi_bounce: true,
            objects: false,
            ground_map: true,
            per_vertex: true,
        }
    }
}

/// The range `[occlusion] slices` and `steps` accept: at least one sample, and at most
/// what a frame can afford on a software device (32 × 32 × 2 depth reads per pixel).
pub const OCCLUSION_SAMPLES_RANGE: std::ops::RangeInclusive<u32> = 1..=32;
