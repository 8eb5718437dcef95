//! Whether a mesh is the outward-facing surface of a solid: seen from outside such a
//! surface, the nearest triangle along every ray faces the viewer, so the forward pass may
//! cull its back faces (render/forward.rs) without changing a pixel.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use rayon::slice::ParallelSliceMut;

use super::mesh::position_key;
use super::Mesh;

impl Mesh {
    /// Whether the mesh bounds a solid from outside: every edge between distinct corners
    /// is traversed once in each direction by the triangles (closed, consistently wound)
    /// and the volume they enclose is positive (counter-clockwise from outside, as
    /// [`Mesh`] wants front faces). Triangles with two equal corners cover no pixel and
    /// are skipped; anything else (open borders, T-junctions, edges of three or more
    /// triangles, inward winding) answers false, which only costs the culling.
    pub fn bounds_solid(&self) -> bool {
        // Each vertex's corner: the first vertex at its position.
        let mut corners: HashMap<[u32; 3], u32> = HashMap::with_capacity(self.vertices.len());
        let corner: Vec<u32> = (0..self.vertices.len() as u32)
            .map(|i| *corners.entry(position_key(self.vertices[i as usize].position)).or_insert(i))
            .collect();
        // Each traversal of an edge: its corners in ascending order, and whether it runs
        // from the lower to the higher. Sorted rather than hashed: millions of triangles
        // (a scanned model) take a fraction of a second.
        let mut traversals: Vec<(u64, bool)> = Vec::with_capacity(self.indices.len());
        let mut six_volume = 0.0;
        for triangle in self.indices.chunks_exact(3) {
            let triangle = [triangle[0], triangle[1], triangle[2]];
            let corners = triangle.map(|i| corner[i as usize]);
            if corners[0] == corners[1] || corners[1] == corners[2] || corners[2] == corners[0] {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                let (low, high) = (a.min(b), a.max(b));
                traversals.push(((u64::from(low) << 32) | u64::from(high), a < b));
            }
            let [p, q, r] = triangle.map(|i| DVec3::from(Vec3::from(self.vertices[i as usize].position)));
            six_volume += p.dot(q.cross(r));
        }
        traversals.par_sort_unstable();
        let once_each_way = |edge: &[(u64, bool)]| matches!(edge, [(_, false), (_, true)]);
        !traversals.is_empty() && traversals.chunk_by(|x, y| x.0 == y.0).all(once_each_way) && six_volume > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_solids_bound_solids_and_the_plane_does_not() {
        for name in ["builtin:sphere", "builtin:torus", "builtin:cube"] {
            let mesh = Mesh::builtin(name).expect("builtin");
            assert!(mesh.bounds_solid(), "{name}");
        }
        assert!(!Mesh::builtin("builtin:plane").expect("builtin").bounds_solid());
        assert!(Mesh::sphere(1).bounds_solid());
    }

    #[test]
    fn inward_winding_a_hole_or_a_third_triangle_on_an_edge_is_no_solid() {
        let cube = Mesh::cube();
        let mut inward = cube.clone();
        for triangle in inward.indices.chunks_exact_mut(3) {
            triangle.swap(1, 2);
        }
        assert!(!inward.bounds_solid());
        let mut holed = cube.clone();
        holed.indices.truncate(holed.indices.len() - 3);
        assert!(!holed.bounds_solid());
        let mut finned = cube.clone();
        finned.indices.extend_from_slice(&cube.indices[..3]);
        assert!(!finned.bounds_solid());
        // One vertex moved an ulp off the corner the neighbouring faces share tears it open.
        let mut torn = cube;
        torn.vertices[0].position[0] = f32::from_bits(torn.vertices[0].position[0].to_bits() + 1);
        assert!(!torn.bounds_solid());
    }

    /// Copies of a corner on different faces may carry −0 where the others have +0.
    #[test]
    fn negative_and_positive_zero_are_one_corner() {
        let mut sphere = Mesh::sphere(2);
        let mut flipped = 0;
        for vertex in sphere.vertices.iter_mut().step_by(2) {
            for x in vertex.position.iter_mut().filter(|x| **x == 0.0) {
                *x = -*x;
                flipped += 1;
            }
        }
        assert!(flipped > 0);
        assert!(sphere.bounds_solid());
    }

    #[test]
    fn zero_area_triangles_are_skipped() {
        let mut cube = Mesh::cube();
        let i = cube.indices[0];
        cube.indices.extend_from_slice(&[i, i, cube.indices[1]]);
        assert!(cube.bounds_solid());
    }
}
