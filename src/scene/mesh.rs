use std::f32::consts::TAU;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use super::{curvature, tangents, SceneError};

/// One vertex as the vertex shader reads it (52 bytes, no padding).
///
/// Tangent-space convention (builtins, OBJ files and normal maps alike):
/// `tangent.xyz` is the unit direction of increasing u, orthogonal to
/// `normal`; the bitangent `tangent.w * cross(normal, tangent.xyz)` points
/// towards increasing v, and `tangent.w` is +1 or -1 (-1 where the UVs are
/// mirrored). v increases upwards in the texture, as in OBJ files, so normal
/// maps are OpenGL-style (+Y = +v = bitangent); this matches MikkTSpace.
///
/// `curvature` is the surface's mean curvature at the vertex in object space
/// (1/length): +1/R on a sphere of radius R, 0 on a plane, negative where the
/// surface is concave. Every `Mesh` constructor computes it from the positions and
/// normals (see `curvature.rs`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub tangent: [f32; 4],
    pub curvature: f32,
}

const _: () = assert!(std::mem::size_of::<Vertex>() == 52);

/// An indexed triangle list; front faces are counter-clockwise seen from
/// outside (from the side the normals point to).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// `builtin:<name>` for builtins, the file path for OBJ meshes; a scene
    /// saves its objects' meshes under this name.
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

/// Prefix of the mesh names that [`Mesh::builtin`] understands.
pub const BUILTIN_PREFIX: &str = "builtin:";

/// Tessellation of `builtin:sphere` and `builtin:torus`: fine enough that
/// silhouettes stay smooth at 1080p when the object fills the view.
const SPHERE_SEGMENTS: u32 = 128;
const SPHERE_RINGS: u32 = 64;
const TORUS_SEGMENTS: u32 = 128;
const TORUS_SIDES: u32 = 48;

/// Upper bound on either tessellation count of a sphere or torus, keeping
/// vertex counts and u32 indices far from overflow.
const MAX_GRID_STEPS: u32 = 4096;

impl Mesh {
    /// The builtin mesh called `name` (`builtin:sphere`, `builtin:torus`,
    /// `builtin:plane` or `builtin:cube`), or `None` for any other name.
    pub fn builtin(name: &str) -> Option<Mesh> {
        match name.strip_prefix(BUILTIN_PREFIX)? {
            "sphere" => Some(Mesh::sphere(SPHERE_SEGMENTS, SPHERE_RINGS)),
            "torus" => Some(Mesh::torus(1.0, 0.35, TORUS_SEGMENTS, TORUS_SIDES)),
            "plane" => Some(Mesh::plane()),
            "cube" => Some(Mesh::cube()),
            _ => None,
        }
    }

    /// Unit UV sphere centred at the origin, `segments` around the y axis
    /// (clamped to 3..=4096) and `rings` from pole to pole (2..=4096).
    ///
    /// u runs around the y axis (u = 0 and u = 1 meet on the +z side, u grows
    /// towards +x there) and v from the south pole (v = 0, y = -1) to the north
    /// pole. Normals equal positions; the tangent is the exact ∂p/∂u
    /// direction, which stays defined at the poles.
    pub fn sphere(segments: u32, rings: u32) -> Mesh {
        Mesh::grid("builtin:sphere", segments, rings, |u, v| {
            let (sin_phi, cos_phi) = angle_sin_cos(u);
            // Exact poles, so the pole vertices of a column coincide and
            // their degenerate triangles are dropped.
            let position = if v == 0.0 {
                Vec3::NEG_Y
            } else if v == 1.0 {
                Vec3::Y
            } else {
                let (ring_radius, minus_y) = (std::f32::consts::PI * v).sin_cos();
                Vec3::new(ring_radius * sin_phi, -minus_y, ring_radius * cos_phi).normalize()
            };
            let tangent = Vec3::new(cos_phi, 0.0, -sin_phi);
            (position, position, tangent)
        })
    }

    /// Torus around the y axis (lying in the xz plane), with the tube's
    /// centre line at `major_radius` and the tube's radius `minor_radius`;
    /// `segments` around the y axis (clamped to 3..=4096) and `sides` around
    /// the tube (2..=4096).
    ///
    /// u runs around the y axis like the sphere's, v around the tube starting
    /// on the outer equator and going up first.
    pub fn torus(major_radius: f32, minor_radius: f32, segments: u32, sides: u32) -> Mesh {
        Mesh::grid("builtin:torus", segments, sides, |u, v| {
            let (sin_phi, cos_phi) = angle_sin_cos(u);
            let (sin_theta, cos_theta) = angle_sin_cos(v);
            let radial = Vec3::new(sin_phi, 0.0, cos_phi);
            let normal = radial * cos_theta + Vec3::Y * sin_theta;
            let position = radial * major_radius + normal * minor_radius;
            (position, normal, Vec3::new(cos_phi, 0.0, -sin_phi))
        })
    }

    /// 2 × 2 square in the xz plane centred at the origin, normal +y.
    /// u grows towards +x, v towards -z.
    pub fn plane() -> Mesh {
        let mut mesh = Mesh {
            name: "builtin:plane".into(),
            vertices: Vec::with_capacity(4),
            indices: Vec::with_capacity(6),
        };
        mesh.push_face(Vec3::Y, Vec3::X, Vec3::ZERO);
        mesh.with_curvature()
    }

    /// Cube of side 2 centred at the origin: 24 vertices so that each face has
    /// its own flat normal and a full 0..1 UV square. Seen from outside each
    /// face, u grows to the right and v upwards (for the top and bottom faces
    /// "upwards" is -z and +z respectively).
    pub fn cube() -> Mesh {
        let mut mesh = Mesh {
            name: "builtin:cube".into(),
            vertices: Vec::with_capacity(24),
            indices: Vec::with_capacity(36),
        };
        // (normal, tangent); the bitangent cross(normal, tangent) is +y on the
        // side faces.
        let faces = [
            (Vec3::X, Vec3::NEG_Z),
            (Vec3::NEG_X, Vec3::Z),
            (Vec3::Y, Vec3::X),
            (Vec3::NEG_Y, Vec3::X),
            (Vec3::Z, Vec3::X),
            (Vec3::NEG_Z, Vec3::NEG_X),
        ];
        for (normal, tangent) in faces {
            mesh.push_face(normal, tangent, normal);
        }
        mesh.with_curvature()
    }

    /// Builds a mesh from raw triangle data, filling in what is missing.
    ///
    /// * `normals`: `None`, or a zero-length normal, gets the area-weighted
    ///   average of the normals of the triangles using that vertex (for a
    ///   vertex of a single triangle, that triangle's normal); a vertex whose
    ///   triangles all have zero area gets +y. Other normals are normalised.
    /// * `uvs`: with `None`, UVs are 0 and each tangent is an arbitrary unit
    ///   vector orthogonal to the normal (glam's `any_orthonormal_vector`,
    ///   continuous except where the normal's z changes sign) with w = +1.
    /// * Tangents follow the convention on [`Vertex`], and so does the curvature.
    ///
    /// `name` is the mesh's name and the origin shown in errors: a non-finite
    /// coordinate, an index out of range, an index count that is not a
    /// multiple of 3, attribute arrays whose length differs from
    /// `positions`', or no triangles at all.
    pub fn from_triangles(
        name: &str,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        uvs: Option<&[[f32; 2]]>,
        indices: &[u32],
    ) -> Result<Mesh, SceneError> {
        let invalid = |problem: String| SceneError::InvalidMesh {
            origin: name.to_owned(),
            problem,
        };
        check_finite("position", positions).map_err(&invalid)?;
        if let Some(normals) = normals {
            check_len("normal", normals.len(), positions.len()).map_err(&invalid)?;
            check_finite("normal", normals).map_err(&invalid)?;
        }
        if let Some(uvs) = uvs {
            check_len("texture coordinate", uvs.len(), positions.len()).map_err(&invalid)?;
            check_finite("texture coordinate", uvs).map_err(&invalid)?;
        }
        if indices.is_empty() {
            return Err(invalid("no triangles".into()));
        }
        if indices.len() % 3 != 0 {
            return Err(invalid(format!(
                "{} indices is not a whole number of triangles",
                indices.len()
            )));
        }
        if let Some((at, &index)) = indices
            .iter()
            .enumerate()
            .find(|&(_, &index)| index as usize >= positions.len())
        {
            return Err(invalid(format!(
                "index {index} (triangle {}) is out of range: there are {} vertices",
                at / 3,
                positions.len()
            )));
        }

        let normals = tangents::vertex_normals(positions, normals, indices);
        let tangents = tangents::vertex_tangents(positions, &normals, uvs, indices);
        let vertices = (0..positions.len())
            .map(|i| Vertex {
                position: positions[i],
                normal: normals[i].to_array(),
                uv: uvs.map_or([0.0; 2], |uvs| uvs[i]),
                tangent: tangents[i].to_array(),
                curvature: 0.0,
            })
            .collect();
        Ok(Mesh {
            name: name.to_owned(),
            vertices,
            indices: indices.to_vec(),
        }
        .with_curvature())
    }

    /// A (segments + 1) × (rings + 1) vertex grid over u, v ∈ [0, 1] with a
    /// duplicated seam column/row so UVs reach 1. `surface(u, v)` returns
    /// (position, unit normal, unit ∂p/∂u direction) with ∂p/∂v along
    /// cross(normal, tangent), which makes the triangles counter-clockwise
    /// from outside. Triangles with two coincident corners (at poles) are
    /// dropped.
    fn grid(name: &str, segments: u32, rings: u32, surface: impl Fn(f32, f32) -> (Vec3, Vec3, Vec3)) -> Mesh {
        let segments = segments.clamp(3, MAX_GRID_STEPS);
        let rings = rings.clamp(2, MAX_GRID_STEPS);
        let columns = segments + 1;
        let mut vertices = Vec::with_capacity((columns * (rings + 1)) as usize);
        for ring in 0..=rings {
            let v = ring as f32 / rings as f32;
            for segment in 0..=segments {
                let u = segment as f32 / segments as f32;
                let (position, normal, tangent) = surface(u, v);
                vertices.push(Vertex {
                    position: position.to_array(),
                    normal: normal.to_array(),
                    uv: [u, v],
                    tangent: tangent.extend(1.0).to_array(),
                    curvature: 0.0,
                });
            }
        }
        let mut indices = Vec::with_capacity((segments * rings * 6) as usize);
        for ring in 0..rings {
            for segment in 0..segments {
                let a = ring * columns + segment;
                let (b, c, d) = (a + 1, a + 1 + columns, a + columns);
                for triangle in [[a, b, c], [a, c, d]] {
                    let [p, q, r] = triangle.map(|i| vertices[i as usize].position);
                    if p != q && q != r && r != p {
                        indices.extend_from_slice(&triangle);
                    }
                }
            }
        }
        Mesh {
            name: name.to_owned(),
            vertices,
            indices,
        }
        .with_curvature()
    }

    /// The mesh with every vertex's curvature estimated from its positions,
    /// normals and triangles.
    fn with_curvature(mut self) -> Mesh {
        curvature::fill_curvature(&mut self.vertices, &self.indices);
        self
    }

    /// Appends a 2 × 2 quad centred at `centre` facing `normal`, with u along
    /// `tangent` and v along cross(normal, tangent).
    fn push_face(&mut self, normal: Vec3, tangent: Vec3, centre: Vec3) {
        let bitangent = normal.cross(tangent);
        let base = self.vertices.len() as u32;
        for uv in [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ] {
            let offset = uv * 2.0 - Vec2::ONE;
            self.vertices.push(Vertex {
                position: (centre + tangent * offset.x + bitangent * offset.y).to_array(),
                normal: normal.to_array(),
                uv: uv.to_array(),
                tangent: tangent.extend(1.0).to_array(),
                curvature: 0.0,
            });
        }
        self.indices.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
    }
}

/// sin and cos of the angle `t · 2π`, exact at t = 0 and t = 1 so that seam
/// vertices coincide bit for bit.
fn angle_sin_cos(t: f32) -> (f32, f32) {
    if t == 0.0 || t == 1.0 {
        (0.0, 1.0)
    } else {
        (t * TAU).sin_cos()
    }
}

fn check_len(what: &str, len: usize, expected: usize) -> Result<(), String> {
    if len == expected {
        Ok(())
    } else {
        Err(format!("{len} {what}s for {expected} vertices"))
    }
}

fn check_finite<const N: usize>(what: &str, values: &[[f32; N]]) -> Result<(), String> {
    match values.iter().position(|value| value.iter().any(|x| !x.is_finite())) {
        Some(i) => Err(format!("vertex {i}: {what} {:?} is not finite", values[i])),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn triangles(mesh: &Mesh) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        mesh.indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]].map(|i| Vec3::from(mesh.vertices[i as usize].position)))
    }

    /// Every triangle's geometric normal cross(e1, e2) points along
    /// `outward(centroid)`, i.e. it is counter-clockwise seen from outside.
    fn assert_outward(mesh: &Mesh, outward: impl Fn(Vec3) -> Vec3) {
        assert!(!mesh.indices.is_empty());
        assert_eq!(mesh.indices.len() % 3, 0);
        assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.vertices.len()));
        for [a, b, c] in triangles(mesh) {
            let face = (b - a).cross(c - a);
            let centroid = (a + b + c) / 3.0;
            assert!(
                face.dot(outward(centroid)) > 0.0,
                "{}: triangle {a} {b} {c} faces inwards or has no area",
                mesh.name
            );
        }
    }

    fn assert_frames(mesh: &Mesh) {
        for v in &mesh.vertices {
            let n = Vec3::from(v.normal);
            let t = Vec4::from(v.tangent);
            assert!(n.is_finite() && t.is_finite() && Vec2::from(v.uv).is_finite());
            assert!((n.length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{v:?}");
            assert!(n.dot(t.truncate()).abs() < 1e-5, "{v:?}");
            assert!(t.w == 1.0 || t.w == -1.0, "{v:?}");
        }
    }

    #[test]
    fn sphere_is_a_unit_sphere_with_exact_normals() {
        let mesh = Mesh::builtin("builtin:sphere").unwrap();
        assert_eq!(mesh.name, "builtin:sphere");
        assert_eq!(mesh.vertices.len(), 129 * 65);
        // Two triangles per quad, minus one per column at each pole.
        assert_eq!(mesh.indices.len(), 3 * (2 * 128 * 64 - 2 * 128));
        for v in &mesh.vertices {
            let p = Vec3::from(v.position);
            assert!((p.length() - 1.0).abs() < 1e-6, "{p}");
            assert_eq!(v.normal, v.position);
            assert_eq!(v.tangent[3], 1.0);
        }
        assert_frames(&mesh);
        assert_outward(&mesh, |centroid| centroid);
    }

    #[test]
    fn sphere_uvs_follow_the_tangent_convention() {
        let mesh = Mesh::sphere(8, 4);
        // The vertex on the +z equator: u = 0, v = 0.5, tangent +x, and
        // cross(n, t) = +y is the direction of increasing v.
        let front = mesh.vertices[2 * 9];
        assert_eq!(front.uv, [0.0, 0.5]);
        assert!(Vec3::from(front.position).abs_diff_eq(Vec3::Z, 1e-6));
        assert!(Vec4::from(front.tangent).abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6));
        let south = mesh.vertices[0];
        assert_eq!(south.position, [0.0, -1.0, 0.0]);
        let north = mesh.vertices.last().unwrap();
        assert_eq!(north.position, [0.0, 1.0, 0.0]);
        assert_eq!(north.uv, [1.0, 1.0]);
    }

    #[test]
    fn small_or_zero_tessellation_is_clamped() {
        let mesh = Mesh::sphere(0, 0);
        assert_frames(&mesh);
        assert_outward(&mesh, |centroid| centroid);
        let torus = Mesh::torus(1.0, 0.3, 1, 1);
        assert_eq!(torus.vertices.len(), 4 * 3);
        assert_frames(&torus);
        let huge = Mesh::sphere(u32::MAX, 2);
        assert_eq!(huge.vertices.len(), 4097 * 3);
    }

    #[test]
    fn torus_lies_in_xz_with_outward_winding() {
        let mesh = Mesh::builtin("builtin:torus").unwrap();
        // Direction from the nearest point of the tube's centre circle.
        let from_tube_centre = |p: Vec3| p - Vec3::new(p.x, 0.0, p.z).normalize();
        for v in &mesh.vertices {
            let p = Vec3::from(v.position);
            let offset = from_tube_centre(p);
            assert!((offset.length() - 0.35).abs() < 1e-5, "{p}");
            assert!(Vec3::from(v.normal).abs_diff_eq(offset / 0.35, 1e-5));
        }
        let max_y = mesh.vertices.iter().map(|v| v.position[1]).fold(f32::MIN, f32::max);
        let max_x = mesh.vertices.iter().map(|v| v.position[0]).fold(f32::MIN, f32::max);
        assert!((max_y - 0.35).abs() < 1e-4 && (max_x - 1.35).abs() < 1e-4);
        assert_frames(&mesh);
        assert_outward(&mesh, from_tube_centre);
    }

    #[test]
    fn plane_is_2x2_facing_up() {
        let mesh = Mesh::builtin("builtin:plane").unwrap();
        assert_eq!(mesh.vertices.len(), 4);
        for v in &mesh.vertices {
            assert_eq!(v.normal, [0.0, 1.0, 0.0]);
            assert_eq!(v.position[1], 0.0);
            assert_eq!(v.position[0].abs(), 1.0);
            assert_eq!(v.position[2].abs(), 1.0);
        }
        assert_frames(&mesh);
        assert_outward(&mesh, |_| Vec3::Y);
    }

    #[test]
    fn cube_has_flat_faces_and_outward_winding() {
        let mesh = Mesh::builtin("builtin:cube").unwrap();
        assert_eq!((mesh.vertices.len(), mesh.indices.len()), (24, 36));
        for v in &mesh.vertices {
            let p = Vec3::from(v.position);
            assert_eq!(p.abs().max_element(), 1.0);
            assert_eq!(p.abs(), Vec3::ONE);
        }
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.vertices[i as usize]);
            let face = (Vec3::from(b.position) - Vec3::from(a.position))
                .cross(Vec3::from(c.position) - Vec3::from(a.position))
                .normalize();
            for v in [a, b, c] {
                assert_eq!(Vec3::from(v.normal), face);
            }
        }
        // v points up the side faces, and away from the viewer on the top.
        for v in &mesh.vertices {
            let (n, t) = (Vec3::from(v.normal), Vec4::from(v.tangent));
            let bitangent = n.cross(t.truncate()) * t.w;
            let expected = match v.normal[1] {
                1.0 => Vec3::NEG_Z,
                -1.0 => Vec3::Z,
                _ => Vec3::Y,
            };
            assert_eq!(bitangent, expected, "{v:?}");
        }
        assert_frames(&mesh);
        assert_outward(&mesh, |centroid| centroid);
        assert!(Mesh::builtin("builtin:cone").is_none());
        assert!(Mesh::builtin("sphere").is_none());
    }

    /// The analytic tangents of the builtins agree with the ones generated
    /// from their UVs, so builtins and OBJ files share one convention.
    #[test]
    fn builtin_tangents_match_generated_ones() {
        for name in ["builtin:plane", "builtin:cube", "builtin:sphere", "builtin:torus"] {
            let mesh = Mesh::builtin(name).unwrap();
            let positions: Vec<_> = mesh.vertices.iter().map(|v| v.position).collect();
            let normals: Vec<_> = mesh.vertices.iter().map(|v| v.normal).collect();
            let uvs: Vec<_> = mesh.vertices.iter().map(|v| v.uv).collect();
            let generated = Mesh::from_triangles(name, &positions, Some(&normals), Some(&uvs), &mesh.indices).unwrap();
            for (built, made) in mesh.vertices.iter().zip(&generated.vertices) {
                assert!(Vec3::from(built.normal).abs_diff_eq(made.normal.into(), 1e-6));
                // Pole vertices touch a single, lopsided triangle.
                if built.position[1].abs() == 1.0 && name == "builtin:sphere" {
                    continue;
                }
                let (b, m) = (Vec4::from(built.tangent), Vec4::from(made.tangent));
                assert_eq!(b.w, m.w, "{name} {built:?}");
                assert!(b.truncate().dot(m.truncate()) > 0.999, "{name}: {b} vs {m}");
            }
        }
    }

    #[test]
    fn vertex_is_52_bytes_and_pod() {
        let vertices = Mesh::plane().vertices;
        let bytes: &[u8] = bytemuck::cast_slice(&vertices);
        assert_eq!(bytes.len(), 4 * 52);
        assert_eq!(std::mem::offset_of!(Vertex, tangent), 32);
        assert_eq!(std::mem::offset_of!(Vertex, curvature), 48);
    }

    #[test]
    fn from_triangles_rejects_bad_input() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let error = |positions: &[[f32; 3]], normals: Option<&[[f32; 3]]>, indices: &[u32]| {
            Mesh::from_triangles("test-mesh", positions, normals, None, indices)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(error(&p, None, &[]), "test-mesh: no triangles");
        assert_eq!(
            error(&p, None, &[0, 1]),
            "test-mesh: 2 indices is not a whole number of triangles"
        );
        assert_eq!(
            error(&p, None, &[0, 1, 3]),
            "test-mesh: index 3 (triangle 0) is out of range: there are 3 vertices"
        );
        let nan = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(
            error(&nan, None, &[0, 1, 2]),
            "test-mesh: vertex 1: position [NaN, 0.0, 0.0] is not finite"
        );
        assert_eq!(
            error(&p, Some(&p[..2]), &[0, 1, 2]),
            "test-mesh: 2 normals for 3 vertices"
        );
        let uvs = [[0.0, f32::INFINITY]; 3];
        assert_eq!(
            Mesh::from_triangles("m", &p, None, Some(&uvs), &[0, 1, 2])
                .unwrap_err()
                .to_string(),
            "m: vertex 0: texture coordinate [0.0, inf] is not finite"
        );
    }
}
