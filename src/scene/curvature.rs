//! Per-vertex mean curvature, the input of pre-integrated (Penner 2011) subsurface
//! scattering: how strongly the surface bends decides how much light scattered under it
//! reaches the other side of the terminator.
//!
//! For each vertex i, the average over its distinct edge-neighbours j of the normal
//! curvature along the edge, k_ij = (n_i - n_j)·(p_i - p_j) / |p_i - p_j|²: exactly 1/R on
//! a sphere of radius R with exact normals, positive where the surface is convex (normals
//! diverge), negative where it is concave. Averaged over the edge directions of a vertex
//! it lies between the two principal curvatures (Euler's formula), at their mean when the
//! edges are spread evenly.

use std::collections::HashMap;

use glam::DVec3;
use rayon::slice::ParallelSliceMut;

use super::Vertex;

/// An edge shorter than this fraction of its endpoints' distance from the origin is
/// within a few f32 roundings of zero length: its direction, and its curvature, is noise.
const MIN_EDGE_FRACTION: f64 = 1e-6;

/// Fills in every vertex's `curvature` (1/length, object space) from its position and
/// normal; `indices` must be in range.
///
/// Vertices with bit-identical positions and normals are one point of the surface split
/// only by UVs (texture seams, the edges of the builtin sphere's cube faces), so they pool their neighbours
/// and share one value; vertices at one position with different normals (hard edges) stay
/// apart. Degenerate edges and zero normals are skipped; a vertex without a usable edge
/// gets 0. The result is always finite.
pub(super) fn fill_curvature(vertices: &mut [Vertex], indices: &[u32]) {
    let mut points: HashMap<[u32; 6], u32> = HashMap::with_capacity(vertices.len());
    let point: Vec<u32> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let ([px, py, pz], [nx, ny, nz]) = (v.position, v.normal);
            // + 0.0 turns -0.0 into 0.0, so the two zeros weld.
            let key = [px, py, pz, nx, ny, nz].map(|x| (x + 0.0).to_bits());
            *points.entry(key).or_insert(i as u32)
        })
        .collect();

    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(2 * indices.len());
    for t in indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (a, b) = (point[a as usize], point[b as usize]);
            if a != b {
                edges.extend([(a, b), (b, a)]);
            }
        }
    }
    edges.par_sort_unstable();
    edges.dedup();

    let position = |i: u32| DVec3::from(vertices[i as usize].position.map(f64::from));
    let normal = |i: u32| DVec3::from(vertices[i as usize].normal.map(f64::from)).try_normalize();
    let mut curvature = vec![0.0f32; vertices.len()];
    for from_one_point in edges.chunk_by(|x, y| x.0 == y.0) {
        let i = from_one_point[0].0;
        let Some(n_i) = normal(i) else { continue };
        let p_i = position(i);
        let (mut sum, mut count) = (0.0, 0u32);
        for &(_, j) in from_one_point {
            let (p_j, Some(n_j)) = (position(j), normal(j)) else {
                continue;
            };
            let d = p_i - p_j;
            let length2 = d.length_squared();
            let min_length = MIN_EDGE_FRACTION * p_i.length().max(p_j.length());
            if length2 > min_length * min_length {
                sum += (n_i - n_j).dot(d) / length2;
                count += 1;
            }
        }
        if count > 0 {
            // |k_ij| ≤ 2 / |p_i - p_j|, which can exceed f32's range for edges near the
            // smallest f32 values.
            let max = f64::from(f32::MAX);
            curvature[i as usize] = (sum / f64::from(count)).clamp(-max, max) as f32;
        }
    }
    for (v, &p) in vertices.iter_mut().zip(&point) {
        v.curvature = curvature[p as usize];
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::Mesh;

    fn curvatures(mesh: &Mesh) -> impl Iterator<Item = f32> + '_ {
        mesh.vertices.iter().map(|v| v.curvature)
    }

    /// `mesh` rebuilt by `from_triangles` with its positions scaled by `scale` and its
    /// normals multiplied by `flip` (-1 turns it inside out, with the winding reversed).
    fn transformed(mesh: &Mesh, scale: f32, flip: f32) -> Mesh {
        let positions: Vec<_> = mesh.vertices.iter().map(|v| v.position.map(|x| x * scale)).collect();
        let normals: Vec<_> = mesh.vertices.iter().map(|v| v.normal.map(|x| x * flip)).collect();
        let mut indices = mesh.indices.clone();
        if flip < 0.0 {
            indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        }
        Mesh::from_triangles("test", &positions, Some(&normals), None, &indices).unwrap()
    }

    fn max_error(mesh: &Mesh, expected: f32) -> f32 {
        curvatures(mesh).map(|k| (k - expected).abs()).fold(0.0, f32::max)
    }

    /// The estimator is exact on a sphere, so only rounding is left: positions and normals
    /// are f32 (relative 6e-8) and the shortest edges, at the cube sphere's corners, are
    /// 0.046 R long, which makes a relative error of about 6e-8 / 0.046 ≈ 1.3e-6 per edge;
    /// 1e-4 of 1/R bounds it with room. The faces' shared edges and corners included.
    #[test]
    fn sphere_is_one_over_its_radius() {
        let unit = Mesh::builtin("builtin:sphere").unwrap();
        for (radius, flip) in [(1.0, 1.0), (3.0, 1.0), (0.01, 1.0), (3.0, -1.0)] {
            let sphere = transformed(&unit, radius, flip);
            let expected = flip / radius;
            let error = max_error(&sphere, expected);
            println!("sphere of radius {radius}, normals × {flip}: max |κ - {expected}| = {error}");
            assert!(error < 1e-4 / radius, "{error}");
        }
        assert!(max_error(&unit, 1.0) < 1e-4);
    }

    #[test]
    fn flat_faces_have_none() {
        for name in ["builtin:plane", "builtin:cube"] {
            let mesh = Mesh::builtin(name).unwrap();
            assert!(curvatures(&mesh).all(|k| k == 0.0), "{name}");
        }
    }

    /// On the equators one principal direction runs around the tube (curvature 1/r) and
    /// the other around the y axis (1/(R + r) outside, -1/(R - r) inside). The vertex's
    /// edges point along both and along the quads' diagonals, so the average lies between
    /// the principal curvatures, and, by symmetry, is the same all round an equator,
    /// across the u = 0 seam too. The diagonals lean towards the tube's direction, so it
    /// is not their mean, but it has the mean's sign: positive outside, and inside
    /// positive on the builtin torus (r < R/2) and negative on a fat one (r > R/2).
    #[test]
    fn torus_equators_lie_between_the_principal_curvatures() {
        for (major, minor) in [(1.0, 0.35), (1.0, 0.7)] {
            let sides = 48;
            let torus = Mesh::torus(major, minor, 128, sides);
            let columns = 129;
            let equator = |ring: usize| &torus.vertices[ring * columns..(ring + 1) * columns];
            for (ring, around_axis) in [(0, 1.0 / (major + minor)), (sides / 2, -1.0 / (major - minor))] {
                let ring = ring as usize;
                let (low, high) = (around_axis.min(1.0 / minor), around_axis.max(1.0 / minor));
                let first = equator(ring)[0].curvature;
                for v in equator(ring) {
                    assert!((v.curvature - first).abs() < 1e-4 * first.abs(), "{v:?} vs {first}");
                    assert!(low < v.curvature && v.curvature < high, "{v:?}: not in [{low}, {high}]");
                }
                let mean = (low + high) / 2.0;
                println!("torus {major}/{minor}, ring {ring}: κ = {first}, principal {low}..{high}, mean {mean}");
                assert_eq!(first > 0.0, mean > 0.0);
            }
        }
    }

    /// Coincident points, zero-area triangles, a zero normal, opposite normals and edges
    /// so short that their curvature exceeds f32's range all give finite values.
    #[test]
    fn degenerate_input_stays_finite() {
        let tiny = 1e-39;
        let positions = [[0.0; 3], [tiny, 0.0, 0.0], [0.0, tiny, 0.0], [0.0; 3], [0.0; 3]];
        let normals = [
            [-1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0; 3],
            [0.0, -1.0, 0.0],
        ];
        let mesh = Mesh::from_triangles("tiny", &positions, Some(&normals), None, &[0, 1, 2, 0, 3, 4]).unwrap();
        assert!(curvatures(&mesh).all(f32::is_finite), "{:?}", mesh.vertices);
        assert_eq!(mesh.vertices[0].curvature, f32::MAX);
        // Vertices 3 and 4 only touch vertex 0, at the same point.
        assert_eq!((mesh.vertices[3].curvature, mesh.vertices[4].curvature), (0.0, 0.0));
        let unit = Vec3::ONE.normalize().to_array();
        let unused = Mesh::from_triangles("unused", &[[0.0; 3]; 4], Some(&[unit; 4]), None, &[0, 1, 2]).unwrap();
        assert!(curvatures(&unused).all(|k| k == 0.0));
    }
}
