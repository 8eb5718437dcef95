//! MikkTSpace tangents (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited") for
//! glTF primitives that have normals and texture coordinates but no tangents: glTF 2.0
//! asks a renderer to generate these, the frame its models' normal maps are baked in.
//!
//! MikkTSpace gives every triangle corner a tangent. A vertex whose corners get different
//! ones (across a mirrored UV seam) is split, one vertex per distinct tangent, so vertices
//! stay shared where their corners agree. A corner left without a usable tangent (a
//! degenerate triangle) takes its vertex's first usable one; a vertex without any gets a
//! zero tangent, which the mesh replaces with its own (tangents.rs).
//!
//! MikkTSpace compares the corners meeting at a point pairwise: a fan of 10,000 triangles
//! about one vertex took it 3.7 s, one of 100,000 took 400 s. A primitive with more such
//! pairs than [`pair_budget`] allows keeps argil's own tangents instead.

use std::collections::HashMap;

use glam::{Vec3, Vec4};

use super::mesh::position_key;
use super::tangents;

/// A primitive with its vertices split where their corners' tangents differ.
#[derive(Debug, PartialEq)]
pub(super) struct Split {
    pub positions: Vec<[f32; 3]>,
    /// Unit: the normals MikkTSpace worked with.
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub tangents: Vec<[f32; 4]>,
    pub indices: Vec<u32>,
}

/// The triangles as MikkTSpace reads them, and what it writes: a tangent per corner.
struct Corners<'a> {
    positions: &'a [[f32; 3]],
    normals: &'a [Vec3],
    uvs: &'a [[f32; 2]],
    indices: &'a [u32],
    tangents: Vec<Option<Vec4>>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, corner: usize) -> usize {
        self.indices[face * 3 + corner] as usize
    }
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, corner: usize) -> [f32; 3] {
        self.positions[self.vertex(face, corner)]
    }

    fn normal(&self, face: usize, corner: usize) -> [f32; 3] {
        self.normals[self.vertex(face, corner)].to_array()
    }

    fn tex_coord(&self, face: usize, corner: usize) -> [f32; 2] {
        self.uvs[self.vertex(face, corner)]
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, corner: usize) {
        let normal = self.normals[self.vertex(face, corner)];
        self.tangents[face * 3 + corner] = tangents::orthogonal_tangent(tangent, normal);
    }
}

/// Pairs of corners at one point MikkTSpace may compare, for `corners` corners: 64 a corner
/// (a closed mesh has about 6) and at least 10⁷, about half a second.
fn pair_budget(corners: usize) -> u64 {
    (64 * corners as u64).max(10_000_000)
}

/// MikkTSpace's tangents for the triangles `indices` (in range, every coordinate finite:
/// see `mesh::check_triangles`), with argil's v-up UVs, so that w follows the convention on
/// [`Vertex`](super::Vertex); vertices are split where their corners' tangents differ.
/// Vertices keep their indices; the copies that splitting adds follow them. `None` when the
/// corners meeting at one point are too many for MikkTSpace's pairwise comparison.
pub(super) fn split_by_tangents(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    indices: &[u32],
) -> Option<Split> {
    let mut at_point: HashMap<[u32; 3], u64> = HashMap::new();
    for &v in indices {
        *at_point.entry(position_key(positions[v as usize])).or_default() += 1;
    }
    if at_point.values().map(|k| k * k).sum::<u64>() > pair_budget(indices.len()) {
        return None;
    }
    // MikkTSpace takes unit normals: zero-length ones get the mesh's own (area-weighted),
    // which the copies keep rather than averaging their own triangles' normals again.
    let unit_normals = tangents::vertex_normals(positions, Some(normals), indices);
    let mut corners = Corners {
        positions,
        normals: &unit_normals,
        uvs,
        indices,
        tangents: vec![None; indices.len()],
    };
    // `false` when every triangle is degenerate: no corner has a tangent then.
    bevy_mikktspace::generate_tangents(&mut corners);

    let mut first = vec![None; positions.len()];
    for (&v, tangent) in indices.iter().zip(&corners.tangents) {
        first[v as usize] = first[v as usize].or(*tangent);
    }
    let mut split = Split {
        positions: positions.to_vec(),
        normals: unit_normals.iter().map(|n| n.to_array()).collect(),
        uvs: uvs.to_vec(),
        tangents: first.iter().map(|t| t.unwrap_or(Vec4::ZERO).to_array()).collect(),
        indices: Vec::with_capacity(indices.len()),
    };
    let mut copies: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    for (&v, tangent) in indices.iter().zip(&corners.tangents) {
        let vertex = v as usize;
        let index = match tangent.map(|t| t.to_array()) {
            Some(t) if t != split.tangents[vertex] => *copies.entry((v, t.map(f32::to_bits))).or_insert_with(|| {
                split.positions.push(positions[vertex]);
                split.normals.push(unit_normals[vertex].to_array());
                split.uvs.push(uvs[vertex]);
                split.tangents.push(t);
                (split.positions.len() - 1) as u32
            }),
            _ => v,
        };
        split.indices.push(index);
    }
    Some(split)
}

#[cfg(test)]
mod tests {
    use super::super::tangents::tests::{degenerate_soups, Soup};
    use super::super::Mesh;
    use super::*;

    const QUAD: [[f32; 3]; 4] = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    const QUAD_INDICES: [u32; 6] = [0, 1, 2, 0, 2, 3];
    const UP: [[f32; 3]; 4] = [[0.0, 0.0, 1.0]; 4];

    fn quad(uvs: [[f32; 2]; 4]) -> Split {
        split_by_tangents(&QUAD, &UP, &uvs, &QUAD_INDICES).expect("within the budget")
    }

    #[test]
    fn tangent_follows_u_with_positive_handedness() {
        let split = quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(split.indices, QUAD_INDICES);
        assert_eq!(split.tangents, [[1.0, 0.0, 0.0, 1.0]; 4]);
    }

    #[test]
    fn mirrored_uvs_flip_handedness() {
        // u mirrored: the tangent follows u (towards -x) and v still runs up (+y), along
        // -cross(n, t).
        let split = quad([[1.0, 0.0], [0.0, 0.0], [0.0, 1.0], [1.0, 1.0]]);
        assert_eq!(split.tangents, [[-1.0, 0.0, 0.0, -1.0]; 4]);
        // v mirrored: the tangent is +x and v runs down.
        let split = quad([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
        assert_eq!(split.tangents, [[1.0, 0.0, 0.0, -1.0]; 4]);
    }

    /// Two quads side by side, the right one's UVs mirrored about their shared edge: the
    /// two vertices on that edge get a copy each (8 vertices from 6), the others none.
    #[test]
    fn vertices_split_only_across_a_mirror_seam() {
        // Vertex i at (i mod 3, i div 3); u runs 0, 1, 0 along each row.
        let positions: Vec<[f32; 3]> = (0..6).map(|i| [(i % 3) as f32, (i / 3) as f32, 0.0]).collect();
        let uvs: Vec<[f32; 2]> = (0..6).map(|i| [(i % 3 % 2) as f32, (i / 3) as f32]).collect();
        let indices = [0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4];
        let split = split_by_tangents(&positions, &[[0.0, 0.0, 1.0]; 6], &uvs, &indices).expect("within the budget");
        assert_eq!(split.positions.len(), 8);
        assert_eq!(split.indices, [0, 1, 4, 0, 4, 3, 6, 2, 5, 6, 5, 7]);
        assert_eq!(split.positions[6..], [positions[1], positions[4]]);
        for (i, t) in split.tangents.iter().enumerate() {
            let left = matches!(i, 0 | 1 | 3 | 4);
            let expected = if left {
                [1.0, 0.0, 0.0, 1.0]
            } else {
                [-1.0, 0.0, 0.0, -1.0]
            };
            assert_eq!(*t, expected, "vertex {i}");
        }
    }

    /// A smooth mesh with consistent UVs keeps every vertex, and its tangents agree with
    /// the ones argil computes for OBJ files (the same corner-angle weighting). The torus:
    /// MikkTSpace welds vertices equal in position, normal and UV, as the builtin sphere's
    /// at the edges of its cube faces, which argil's own tangents keep apart.
    #[test]
    fn a_smooth_mesh_is_not_split() {
        let torus = Mesh::torus(1.0, 0.35, 16, 8);
        let positions: Vec<[f32; 3]> = torus.vertices.iter().map(|v| v.position).collect();
        let normals: Vec<[f32; 3]> = torus.vertices.iter().map(|v| v.normal).collect();
        let uvs: Vec<[f32; 2]> = torus.vertices.iter().map(|v| v.uv).collect();
        let split = split_by_tangents(&positions, &normals, &uvs, &torus.indices).expect("within the budget");
        assert_eq!(split.indices, torus.indices);
        let own = Mesh::from_triangles("torus", &positions, Some(&normals), Some(&uvs), &torus.indices)
            .expect("the torus loads");
        for (t, v) in split.tangents.iter().zip(&own.vertices) {
            let (t, own) = (Vec4::from(*t), Vec4::from(v.tangent));
            assert_eq!(t.w, own.w);
            assert!(t.truncate().dot(own.truncate()) > 0.9999, "{t} against {own}");
        }
    }

    /// On random triangles where degenerate ones are frequent, every tangent is unit and
    /// orthogonal to its normal, or zero (none usable), and the mesh built with them has a
    /// valid frame at every vertex.
    #[test]
    fn degenerate_soup_gives_unit_tangents_or_none() {
        let mut without = 0;
        for soup in degenerate_soups(0x9e37_79b9_7f4a_7c15) {
            let Soup {
                positions,
                normals,
                uvs,
                indices,
            } = soup;
            let split = split_by_tangents(&positions, &normals, &uvs, &indices).expect("within the budget");
            for (t, n) in split.tangents.iter().zip(&split.normals) {
                let (t, n) = (Vec4::from(*t), Vec3::from(*n));
                if t == Vec4::ZERO {
                    without += 1;
                    continue;
                }
                assert!(t.is_finite() && (t.truncate().length() - 1.0).abs() < 1e-5, "{t}");
                assert!(t.truncate().dot(n).abs() < 1e-5 && t.w.abs() == 1.0, "{t} against {n}");
            }
            let mesh = Mesh::from_triangles_with_tangents(
                "soup",
                &split.positions,
                Some(&split.normals),
                Some(&split.uvs),
                Some(&split.tangents),
                &split.indices,
            )
            .expect("soup loads");
            for v in &mesh.vertices {
                let (n, t) = (Vec3::from(v.normal), Vec4::from(v.tangent));
                assert!(t.is_finite() && (t.truncate().length() - 1.0).abs() < 1e-5, "{v:?}");
                assert!(n.dot(t.truncate()).abs() < 1e-5 && t.w.abs() == 1.0, "{v:?}");
            }
        }
        assert!(
            without > 0,
            "the soup has no vertex without a tangent: it tests less than it says"
        );
    }

    #[test]
    fn extreme_coordinates_stay_finite() {
        let big = 3.0e38;
        let positions = [[-big, -big, 0.0], [big, -big, 0.0], [big, big, 0.0], [-big, big, 1e-30]];
        let uvs = [[0.0, 0.0], [1e-38, 0.0], [1e-38, 1e-38], [0.0, 1e-38]];
        let split = split_by_tangents(&positions, &UP, &uvs, &QUAD_INDICES).expect("within the budget");
        assert!(
            split.tangents.iter().flatten().all(|x| x.is_finite()),
            "{:?}",
            split.tangents
        );
    }

    /// A disc of `n` triangles fanned about its centre.
    fn fan(n: u32) -> (Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>) {
        let rim = (0..=n).map(|k| k as f32 / n as f32 * std::f32::consts::TAU);
        let positions = std::iter::once([0.0; 3]).chain(rim.clone().map(|a| [a.cos(), a.sin(), 0.0]));
        let uvs = std::iter::once([0.5; 2]).chain(rim.map(|a| [0.5 + 0.5 * a.cos(), 0.5 + 0.5 * a.sin()]));
        let indices = (0..n).flat_map(|k| [0, k + 1, k + 2]).collect();
        (positions.collect(), uvs.collect(), indices)
    }

    /// A fan of 1,000 triangles gets MikkTSpace's tangents; one of 10,000 (3.7 s of
    /// MikkTSpace) keeps argil's own.
    #[test]
    fn a_large_fan_is_left_to_argil_s_tangents() {
        for (n, within) in [(1_000, true), (10_000, false)] {
            let (positions, uvs, indices) = fan(n);
            let normals = vec![[0.0, 0.0, 1.0]; positions.len()];
            let split = split_by_tangents(&positions, &normals, &uvs, &indices);
            assert_eq!(split.is_some(), within, "{n} triangles");
            if let Some(split) = split {
                assert!(split.tangents.iter().all(|&t| t[0] > 0.9999 && t[3] == 1.0));
            }
        }
    }
}
