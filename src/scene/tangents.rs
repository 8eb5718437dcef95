//! Per-vertex normals and tangents for meshes that arrive without them.
//!
//! Accumulation runs in f64 so that large but finite f32 coordinates cannot
//! overflow a cross product, and every division is guarded: degenerate input
//! falls back to a valid frame instead of producing NaN.

use glam::{DVec2, DVec3, Vec3, Vec4};

/// Below this sine of the angle between a triangle's two UV edges, the UV
/// mapping is degenerate within f32 precision and gives no tangent direction.
const MIN_UV_SINE: f64 = 1e-7;

/// Below this sine of the angle between two edges, a triangle has no usable
/// area or corner angles.
const MIN_AREA_SINE: f64 = 1e-12;

/// A tangent whose component orthogonal to the normal is shorter than this
/// fraction of its length points along the normal: what remains is rounding
/// noise, not a direction.
const MIN_ORTHOGONAL_FRACTION: f64 = 1e-6;

fn dvec3(v: [f32; 3]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}

fn triangles(indices: &[u32]) -> impl Iterator<Item = [usize; 3]> + '_ {
    indices
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
}

/// Unit normals: `given` ones normalised where they have a length, otherwise
/// the area-weighted average of the adjacent faces' normals, otherwise +y.
/// `indices` must be in range.
pub(super) fn vertex_normals(positions: &[[f32; 3]], given: Option<&[[f32; 3]]>, indices: &[u32]) -> Vec<Vec3> {
    let mut accumulated = vec![DVec3::ZERO; positions.len()];
    for [a, b, c] in triangles(indices) {
        let p0 = dvec3(positions[a]);
        // |cross| is twice the area: larger faces count more.
        let face = (dvec3(positions[b]) - p0).cross(dvec3(positions[c]) - p0);
        for v in [a, b, c] {
            accumulated[v] += face;
        }
    }
    accumulated
        .iter()
        .enumerate()
        .map(|(i, sum)| {
            given
                .and_then(|normals| dvec3(normals[i]).try_normalize())
                .or_else(|| sum.try_normalize())
                .unwrap_or(DVec3::Y)
                .as_vec3()
        })
        .collect()
}

/// Tangents with handedness in w, following the convention documented on
/// [`Vertex`](super::Vertex), for unit `normals`; `indices` must be in range.
///
/// Each triangle's tangent T and bitangent B come from its edges and UV
/// deltas (e1 = p1 - p0, e2 = p2 - p0, r = 1 / (Δu1 Δv2 - Δu2 Δv1),
/// T = r (e1 Δv2 - e2 Δv1), B = r (e2 Δu1 - e1 Δu2)). As in MikkTSpace, each
/// corner adds T projected onto the vertex's tangent plane and B, both
/// normalised and weighted by the corner angle, so neither a triangle's size
/// nor its UV scale dominates. The sum is orthogonalised against the normal
/// and w = sign(dot(cross(n, t), B)).
///
/// Triangles with no area or degenerate UVs contribute nothing; a vertex left
/// without a tangent (or all of them when `uvs` is `None`) gets an arbitrary
/// unit vector orthogonal to its normal, with w = +1.
pub(super) fn vertex_tangents(
    positions: &[[f32; 3]],
    normals: &[Vec3],
    uvs: Option<&[[f32; 2]]>,
    indices: &[u32],
) -> Vec<Vec4> {
    let normals: Vec<DVec3> = normals.iter().map(|n| n.as_dvec3()).collect();
    let mut tangent_sums = vec![DVec3::ZERO; positions.len()];
    let mut bitangent_sums = vec![DVec3::ZERO; positions.len()];
    let mut weights = vec![0.0; positions.len()];
    if let Some(uvs) = uvs {
        let uv = |i: usize| DVec2::new(uvs[i][0].into(), uvs[i][1].into());
        for corners in triangles(indices) {
            let p = corners.map(|i| dvec3(positions[i]));
            let Some((tangent, bitangent)) = triangle_frame(p, corners.map(uv)) else {
                continue;
            };
            for k in 0..3 {
                let v = corners[k];
                let n = normals[v];
                let (Some(t), Some(angle)) = (
                    orthogonal_direction(tangent, n, 1.0),
                    corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]),
                ) else {
                    continue;
                };
                tangent_sums[v] += t * angle;
                bitangent_sums[v] += bitangent * angle;
                weights[v] += angle;
            }
        }
    }
    (0..normals.len())
        .map(|v| {
            let n = normals[v];
            let (t, w) = match orthogonal_direction(tangent_sums[v], n, weights[v]) {
                Some(t) if n.cross(t).dot(bitangent_sums[v]) < 0.0 => (t, -1.0),
                Some(t) => (t, 1.0),
                None => (n.any_orthonormal_vector(), 1.0),
            };
            t.as_vec3().extend(w)
        })
        .collect()
}

/// A tangent given with the mesh (glTF's, or MikkTSpace's) made orthogonal to the unit
/// `normal` and unit, its w ±1; `None` if it is not finite or lies (nearly) along the
/// normal, where what is left is rounding noise: the mesh's own tangent serves there.
pub(super) fn orthogonal_tangent(given: [f32; 4], normal: Vec3) -> Option<Vec4> {
    let t = Vec3::new(given[0], given[1], given[2]);
    let orthogonal = t - normal * normal.dot(t);
    (orthogonal.length() > 1e-3 * t.length())
        .then(|| orthogonal.normalize().extend(if given[3] < 0.0 { -1.0 } else { 1.0 }))
}

/// The unit direction of `v`'s component orthogonal to the unit vector `n`,
/// if that component is longer than rounding noise relative to `length`, the
/// magnitude `v` would have without cancellation.
fn orthogonal_direction(v: DVec3, n: DVec3, length: f64) -> Option<DVec3> {
    let orthogonal = v - n * n.dot(v);
    if orthogonal.length() > MIN_ORTHOGONAL_FRACTION * length {
        orthogonal.try_normalize()
    } else {
        None
    }
}

/// Unit tangent and bitangent of one triangle, or `None` if it has no area or
/// its UV mapping is degenerate.
fn triangle_frame(p: [DVec3; 3], uv: [DVec2; 3]) -> Option<(DVec3, DVec3)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    if e1.cross(e2).length() <= MIN_AREA_SINE * e1.length() * e2.length() {
        return None;
    }
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.perp_dot(d2);
    if det.abs() <= MIN_UV_SINE * d1.length() * d2.length() {
        return None;
    }
    let r = det.recip();
    let tangent = (e1 * d2.y - e2 * d1.y) * r;
    let bitangent = (e2 * d1.x - e1 * d2.x) * r;
    Some((tangent.try_normalize()?, bitangent.try_normalize()?))
}

/// Angle at corner `p` of triangle (p, q, r), or `None` if an edge there has
/// no length.
fn corner_angle(p: DVec3, q: DVec3, r: DVec3) -> Option<f64> {
    let a = (q - p).try_normalize()?;
    let b = (r - p).try_normalize()?;
    Some(a.dot(b).clamp(-1.0, 1.0).acos())
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::{Mesh, Vertex};
    use glam::Vec2;

    use super::*;

    /// The guarantees every generated vertex must meet, curvature included.
    fn assert_valid(vertices: &[Vertex]) {
        for v in vertices {
            let n = Vec3::from(v.normal);
            let t = Vec4::from(v.tangent);
            assert!(n.is_finite() && t.is_finite() && Vec2::from(v.uv).is_finite(), "{v:?}");
            assert!((n.length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!(n.dot(t.truncate()).abs() < 1e-5, "{v:?}");
            assert!(t.w == 1.0 || t.w == -1.0, "{v:?}");
            assert!(v.curvature.is_finite(), "{v:?}");
        }
    }

    const QUAD: [[f32; 3]; 4] = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    const QUAD_INDICES: [u32; 6] = [0, 1, 2, 0, 2, 3];

    fn quad(uvs: [[f32; 2]; 4]) -> Mesh {
        let mesh = Mesh::from_triangles("quad", &QUAD, None, Some(&uvs), &QUAD_INDICES).unwrap();
        assert_valid(&mesh.vertices);
        mesh
    }

    #[test]
    fn tangent_follows_u_with_positive_handedness() {
        let mesh = quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        for v in &mesh.vertices {
            assert_eq!(v.normal, [0.0, 0.0, 1.0]);
            assert_eq!(v.tangent, [1.0, 0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn mirrored_uvs_flip_handedness() {
        // u mirrored: the tangent follows u (towards -x), the bitangent still
        // points up (+v), so cross(n, t) = -y needs w = -1.
        let mesh = quad([[1.0, 0.0], [0.0, 0.0], [0.0, 1.0], [1.0, 1.0]]);
        for v in &mesh.vertices {
            assert_eq!(v.tangent, [-1.0, 0.0, 0.0, -1.0]);
        }
        // v mirrored: tangent +x, bitangent -y.
        let mesh = quad([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
        for v in &mesh.vertices {
            assert_eq!(v.tangent, [1.0, 0.0, 0.0, -1.0]);
        }
    }

    #[test]
    fn rotated_uvs_rotate_the_tangent() {
        // u increases along +y: tangent +y, and v along -x = cross(z, y).
        let mesh = quad([[0.0, 1.0], [0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        for v in &mesh.vertices {
            assert!(Vec4::from(v.tangent).abs_diff_eq(Vec4::new(0.0, 1.0, 0.0, 1.0), 1e-6));
        }
    }

    #[test]
    fn tangent_is_orthogonalised_against_a_tilted_normal() {
        let tilted = Vec3::new(0.3, 0.2, 1.0).normalize().to_array();
        let mesh = Mesh::from_triangles(
            "tilted",
            &QUAD,
            Some(&[tilted; 4]),
            Some(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
            &QUAD_INDICES,
        )
        .unwrap();
        assert_valid(&mesh.vertices);
        for v in &mesh.vertices {
            assert!(v.tangent[0] > 0.9 && v.tangent[3] == 1.0, "{v:?}");
        }
    }

    #[test]
    fn degenerate_uvs_fall_back_to_an_orthonormal_tangent() {
        for uvs in [
            [[0.5, 0.5]; 4],                                      // all equal
            [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [3.0, 3.0]],     // collinear
            [[0.0, 0.0], [1e-30, 0.0], [0.0, 1e-30], [0.0, 0.0]], // det underflows in f32
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1e-9], [0.0, 0.0]],    // sliver in UV space
        ] {
            let mesh = quad(uvs);
            for v in &mesh.vertices {
                assert_eq!(v.normal, [0.0, 0.0, 1.0]);
            }
        }
    }

    #[test]
    fn one_degenerate_triangle_does_not_spoil_its_neighbour() {
        // The second triangle's UVs are collinear; the first one still
        // determines the tangent of the shared vertices.
        let mesh = quad([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 2.0]]);
        for i in 0..3 {
            assert_eq!(mesh.vertices[i].tangent, [1.0, 0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn zero_area_triangles_stay_finite() {
        let positions = [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            [2.0, 2.0, 2.0],
        ];
        let uvs = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let mesh = Mesh::from_triangles("flat", &positions, None, Some(&uvs), &[0, 1, 2, 3, 4, 5]).unwrap();
        assert_valid(&mesh.vertices);
        for v in &mesh.vertices {
            assert_eq!(v.normal, [0.0, 1.0, 0.0]);
        }
    }

    #[test]
    fn zero_length_normals_are_replaced_by_the_face_normal() {
        let normals = [[0.0; 3], [0.0, 0.0, 2.0], [0.0; 3], [0.0; 3]];
        let mesh = Mesh::from_triangles("n", &QUAD, Some(&normals), None, &QUAD_INDICES).unwrap();
        assert_valid(&mesh.vertices);
        for v in &mesh.vertices {
            assert_eq!(v.normal, [0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn missing_normals_are_area_weighted_and_smooth() {
        // A small and a large triangle sharing vertex 0, bent along the x axis.
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],  // small, facing +z
            [0.0, 0.0, -3.0], // large, facing -y... seen from below
        ];
        let normals = vertex_normals(&positions, None, &[0, 1, 2, 0, 3, 1]);
        // Face normals: (0,0,1) with doubled area 1 and (0,-3,0)x... = (0,-3,0)
        // with doubled area 3, so vertex 0 leans three times more to -y.
        let expected = Vec3::new(0.0, -3.0, 1.0).normalize();
        assert!(normals[0].abs_diff_eq(expected, 1e-6), "{}", normals[0]);
        assert_eq!(normals[2], Vec3::Z);
        assert_eq!(normals[3], Vec3::NEG_Y);
    }

    #[test]
    fn missing_uvs_give_an_orthonormal_basis() {
        let mesh = Mesh::from_triangles("no-uv", &QUAD, None, None, &QUAD_INDICES).unwrap();
        assert_valid(&mesh.vertices);
        assert!(mesh.vertices.iter().all(|v| v.uv == [0.0, 0.0] && v.tangent[3] == 1.0));
    }

    #[test]
    fn extreme_coordinates_stay_finite() {
        let big = 3.0e38;
        let positions = [[-big, -big, 0.0], [big, -big, 0.0], [big, big, 0.0], [-big, big, 1e-30]];
        let uvs = [[0.0, 0.0], [1e-38, 0.0], [1e-38, 1e-38], [0.0, 1e-38]];
        let mesh = Mesh::from_triangles("big", &positions, None, Some(&uvs), &QUAD_INDICES).unwrap();
        assert_valid(&mesh.vertices);
        assert_eq!(mesh.vertices[1].tangent, [1.0, 0.0, 0.0, 1.0]);
    }

    /// A few random triangles with normals and UVs.
    pub(in crate::scene) struct Soup {
        pub positions: Vec<[f32; 3]>,
        pub normals: Vec<[f32; 3]>,
        pub uvs: Vec<[f32; 2]>,
        pub indices: Vec<u32>,
    }

    /// 500 soups of random triangles over a tiny grid of values, so that coincident
    /// points, collinear edges, zero normals and repeated UVs are frequent; `seed` (not 0)
    /// picks them.
    pub(in crate::scene) fn degenerate_soups(seed: u64) -> Vec<Soup> {
        let mut state = seed;
        let mut next = |range: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % range
        };
        (0..500)
            .map(|_| {
                let count = 3 + next(6) as usize;
                let mut value = || next(5) as f32 * 0.5 - 1.0;
                let positions = (0..count).map(|_| [value(), value(), value()]).collect();
                let normals = (0..count).map(|_| [value(), value(), value()]).collect();
                let uvs = (0..count).map(|_| [value(), value()]).collect();
                let indices = (0..3 * (1 + next(8))).map(|_| next(count as u64) as u32).collect();
                Soup {
                    positions,
                    normals,
                    uvs,
                    indices,
                }
            })
            .collect()
    }

    #[test]
    fn random_degenerate_soup_stays_valid() {
        for soup in degenerate_soups(0x2545_f491_4f6c_dd1d) {
            for normals in [None, Some(soup.normals.as_slice())] {
                let mesh =
                    Mesh::from_triangles("soup", &soup.positions, normals, Some(&soup.uvs), &soup.indices).unwrap();
                assert_valid(&mesh.vertices);
            }
        }
    }
}
