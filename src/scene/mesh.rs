use std::f32::consts::TAU;
use std::ops::RangeInclusive;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use super::limits::{SPHERE_SUBDIVISIONS_RANGE, TORUS_SUBDIVISIONS_RANGE};
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
    /// The `subdivisions` key of a `builtin:sphere` (cells along each cube edge) or a
    /// `builtin:torus` (cells around its ring); `None` for every other mesh.
    pub subdivisions: Option<u32>,
}

/// The eight corners of the box from `low` to `high`.
pub fn box_corners(low: Vec3, high: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|k| Vec3::select(glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0), high, low))
}

/// A mesh's size in its own units ([`Mesh::extent`]), or an object's in the world's
/// ([`super::Object::world_extent`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshExtent {
    /// Its bounding sphere ([`Mesh::bounding_sphere`]).
    pub centre: Vec3,
    pub radius: f32,
    /// Its bounding box ([`Mesh::bounding_box`]): lowest and highest corner.
    pub low: Vec3,
    pub high: Vec3,
    pub longest_edge: f32,
    /// [`Mesh::is_convex`].
    pub convex: bool,
}

/// Prefix of the mesh names that [`Mesh::builtin`] understands.
pub const BUILTIN_PREFIX: &str = "builtin:";
/// Every builtin mesh's name, as [`Mesh::builtin`] knows them.
pub const BUILTIN_MESHES: [&str; 4] = ["builtin:sphere", "builtin:torus", "builtin:plane", "builtin:cube"];

/// Default tessellation of `builtin:sphere` (cells along each cube edge: 4 × 32 = 128 around
/// the equator) and `builtin:torus` (cells around its ring, and [`torus_sides`] around its
/// tube: 48): fine enough that silhouettes stay smooth at 1080p when the object fills the
/// view. Their `subdivisions` key sets them per object.
pub const SPHERE_SUBDIVISIONS: u32 = 32;
pub const TORUS_SUBDIVISIONS: u32 = 128;
/// `builtin:torus`'s ring and tube radii.
pub const TORUS_RADII: (f32, f32) = (1.0, 0.35);

/// Cells around `builtin:torus`'s tube for `segments` around its ring: 3/8 as many (at least
/// 3), which keeps its cells about square, 2π/n long on the centre line and 2π · 0.35 / (3n/8)
/// = 0.93 × 2π/n across.
fn torus_sides(segments: u32) -> u32 {
    let sides = (3 * u64::from(segments) + 4) / 8;
    u32::try_from(sides).unwrap_or(u32::MAX).max(3)
}

/// Upper bound on either tessellation count of a torus, and on a sphere's cells along a
/// cube edge (6 × 2 × 4096² triangles), keeping vertex counts and u32 indices far from
/// overflow.
const MAX_GRID_STEPS: u32 = 4096;

impl Mesh {
    /// The builtin mesh called `name` (one of [`BUILTIN_MESHES`]), or `None` for any other
    /// name.
    pub fn builtin(name: &str) -> Option<Mesh> {
        match name.strip_prefix(BUILTIN_PREFIX)? {
            "plane" => Some(Mesh::plane()),
            "cube" => Some(Mesh::cube()),
            _ => Mesh::subdivided(name, Mesh::subdivisions_key(name)?.0),
        }
    }

    /// The `subdivisions` key of the builtin mesh called `name`, if it has one
    /// (`builtin:sphere`, `builtin:torus`): its default and its range.
    pub fn subdivisions_key(name: &str) -> Option<(u32, RangeInclusive<u32>)> {
        match name.strip_prefix(BUILTIN_PREFIX)? {
            "sphere" => Some((SPHERE_SUBDIVISIONS, SPHERE_SUBDIVISIONS_RANGE)),
            "torus" => Some((TORUS_SUBDIVISIONS, TORUS_SUBDIVISIONS_RANGE)),
            _ => None,
        }
    }

    /// The builtin meshes that have a `subdivisions` key.
    pub fn subdivided_meshes() -> Vec<&'static str> {
        BUILTIN_MESHES.into_iter().filter(|n| Mesh::subdivisions_key(n).is_some()).collect()
    }

    /// The builtin mesh called `name` at `subdivisions`, if it has the key.
    pub fn subdivided(name: &str, subdivisions: u32) -> Option<Mesh> {
        match name.strip_prefix(BUILTIN_PREFIX)? {
            "sphere" => Some(Mesh::sphere(subdivisions)),
            "torus" => {
                let (major, minor) = TORUS_RADII;
                let torus = Mesh::torus(major, minor, subdivisions, torus_sides(subdivisions));
                Some(Mesh {
                    subdivisions: Some(subdivisions),
                    ..torus
                })
            }
            _ => None,
        }
    }

    /// Unit sphere centred at the origin, without poles in its mesh or its UVs: a cube
    /// whose faces are `subdivisions` × `subdivisions` grids (clamped to 1..=4096), each
    /// warped to the sphere by the tangent (equiangular) warp, so that cells are even
    /// (Zucker and Higashi 2018, "Cube-to-sphere projections for procedural texturing and
    /// beyond", JCGT 7(2)). Vertices on the cube's edges are bit-identical from both faces.
    ///
    /// The four side faces carry the UV sphere's parametrisation, u = longitude / 2π (u = 0
    /// on the +z side, growing towards +x there; the band's u runs from -1/8 to 7/8 and
    /// meets itself at u = -1/8 ≡ 7/8) and v = 1/2 + latitude / π, so maps tile across
    /// their shared edges as on a UV sphere and `[2k, k]` UV scales keep texels square.
    /// Each cap (the ±y faces) has u and v proportional to its two warp angles at the same
    /// density, with u along +x and v towards -z on the top, +z on the bottom (as on the
    /// cube): regular at the pole, and equal to the band's UVs at the middle of its edges
    /// with the +z face. Normals equal positions; tangents are the exact ∂p/∂u directions.
    pub fn sphere(subdivisions: u32) -> Mesh {
        let n = subdivisions.clamp(1, MAX_GRID_STEPS);
        // tan(π/4 · k / n) for k = 2i - n, odd in k and exactly ±1 at the cube's edges, so
        // that the faces meeting at an edge compute the same corner vectors.
        let warp = |i: u32| {
            let k = 2 * i as i64 - n as i64;
            let magnitude = if k.unsigned_abs() == n as u64 {
                1.0
            } else {
                (std::f32::consts::FRAC_PI_4 * k.unsigned_abs() as f32 / n as f32).tan()
            };
            magnitude.copysign(k as f32)
        };
        let warps: Vec<f32> = (0..=n).map(warp).collect();
        let columns = n + 1;
        let mut vertices = Vec::with_capacity((6 * columns * columns) as usize);
        let mut indices = Vec::with_capacity((6 * 6 * n * n) as usize);
        for face in SPHERE_FACES {
            let base = vertices.len() as u32;
            for &b in &warps {
                for &a in &warps {
                    let position = unit(face.normal + face.right * a + face.up * b);
                    let (uv, tangent) = face.parametrisation(position);
                    vertices.push(Vertex {
                        position: position.to_array(),
                        normal: position.to_array(),
                        uv: uv.to_array(),
                        tangent: tangent.extend(1.0).to_array(),
                        curvature: 0.0,
                    });
                }
            }
            push_grid_triangles(&mut indices, base, n, n, |column, row| outward_diagonal(column, row, n));
        }
        Mesh {
            name: "builtin:sphere".into(),
            vertices,
            indices,
            subdivisions: Some(n),
        }
        .with_curvature()
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
            subdivisions: None,
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
            subdivisions: None,
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
        Mesh::from_triangles_with_tangents(name, positions, normals, uvs, None, indices)
    }

    /// [`Mesh::from_triangles`] with the file's tangents where it has them (glTF's, whose
    /// bitangent `w · cross(n, t)` follows the same convention): each is made orthogonal to
    /// its normal; one that has no direction left, or is not finite, is computed instead.
    pub fn from_triangles_with_tangents(
        name: &str,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        uvs: Option<&[[f32; 2]]>,
        given_tangents: Option<&[[f32; 4]]>,
        indices: &[u32],
    ) -> Result<Mesh, SceneError> {
        check_triangles(name, positions, normals, uvs, indices)?;
        let normals = tangents::vertex_normals(positions, normals, indices);
        let mut tangents = tangents::vertex_tangents(positions, &normals, uvs, indices);
        if let Some(given) = given_tangents {
            check_len("tangent", given.len(), positions.len()).map_err(|problem| SceneError::InvalidMesh {
                origin: name.to_owned(),
                problem,
            })?;
            for ((tangent, given), normal) in tangents.iter_mut().zip(given).zip(&normals) {
                if let Some(t) = tangents::orthogonal_tangent(*given, *normal) {
                    *tangent = t;
                }
            }
        }
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
            subdivisions: None,
        }
        .with_curvature())
    }

    /// A (segments + 1) × (rings + 1) vertex grid over u, v ∈ [0, 1] with a
    /// duplicated seam column/row so UVs reach 1. `surface(u, v)` returns
    /// (position, unit normal, unit ∂p/∂u direction) with ∂p/∂v along
    /// cross(normal, tangent), which makes the triangles counter-clockwise
    /// from outside.
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
        push_grid_triangles(&mut indices, 0, segments, rings, |_, _| true);
        Mesh {
            name: name.to_owned(),
            vertices,
            indices,
            subdivisions: None,
        }
        .with_curvature()
    }

    /// Whether the mesh bounds a convex solid, whose surface cannot shadow itself: the
    /// builtin sphere, cube and plane (a test checks that each of their edges folds
    /// outward or is flat).
    pub fn is_convex(&self) -> bool {
        matches!(self.name.as_str(), "builtin:sphere" | "builtin:cube" | "builtin:plane")
    }

    /// Its bounds, longest edge and convexity, kept where choices are made every frame.
    pub fn extent(&self) -> MeshExtent {
        let (centre, radius) = self.bounding_sphere();
        let (low, high) = self.bounding_box();
        let position = |i: u32| Vec3::from(self.vertices[i as usize].position);
        let longest_edge = self
            .indices
            .chunks_exact(3)
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| position(a).distance(position(b)))
            .fold(0.0, f32::max);
        MeshExtent {
            centre,
            radius,
            low,
            high,
            longest_edge,
            convex: self.is_convex(),
        }
    }

    /// The box holding every vertex: (lowest corner, highest corner).
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(Vec3::from(v.position)), hi.max(Vec3::from(v.position))),
        )
    }

    /// A sphere holding every vertex: (centre of the bounding box, radius).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let (lo, hi) = self.bounding_box();
        let centre = (lo + hi) * 0.5;
        let radius = self
            .vertices
            .iter()
            .map(|v| (Vec3::from(v.position) - centre).length())
            .fold(0.0, f32::max);
        (centre, radius)
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

/// Two triangles per cell of a grid of `columns` × `rows` cells whose (columns + 1) ×
/// (rows + 1) vertices start at `base`, row by row; counter-clockwise when columns advance
/// along the tangent and rows along cross(normal, tangent). Cell (column, row) is split
/// along the diagonal from its first vertex to its last where `first_diagonal` says so,
/// along the other elsewhere.
fn push_grid_triangles(
    indices: &mut Vec<u32>,
    base: u32,
    columns: u32,
    rows: u32,
    first_diagonal: impl Fn(u32, u32) -> bool,
) {
    let stride = columns + 1;
    for row in 0..rows {
        for column in 0..columns {
            let a = base + row * stride + column;
            let (b, c, d) = (a + 1, a + 1 + stride, a + stride);
            if first_diagonal(column, row) {
                indices.extend_from_slice(&[a, b, c, a, c, d]);
            } else {
                indices.extend_from_slice(&[a, b, d, b, c, d]);
            }
        }
    }
}

/// Whether cell (column, row) of a face of the cube sphere, n × n cells, is split along
/// its first diagonal: the one from its corner nearest the face's centre, whose fold is
/// outward (its midpoint lies further from the sphere's centre than the other's), so that
/// every edge is convex and the mesh bounds a convex solid ([`Mesh::is_convex`]). The other
/// diagonal folds inward, by up to 1e-3 of the radius at 32 subdivisions. The first
/// diagonal points away from the centre where the cell lies in the quadrant of increasing
/// or decreasing column and row alike.
fn outward_diagonal(column: u32, row: u32, n: u32) -> bool {
    (2 * i64::from(column) + 1 - i64::from(n)) * (2 * i64::from(row) + 1 - i64::from(n)) >= 0
}

/// One face of the cube sphere: its centre `normal`, and `right` × `up` = `normal` the
/// directions its grid's columns and rows advance in.
struct SphereFace {
    normal: Vec3,
    right: Vec3,
    up: Vec3,
    /// The side faces' longitude at the face centre; `None` on the caps.
    longitude: Option<f32>,
}

/// The four side faces in the order of increasing u (their `right` is the direction of
/// increasing longitude), then the top and bottom caps.
const SPHERE_FACES: [SphereFace; 6] = {
    const fn side(normal: Vec3, right: Vec3, longitude: f32) -> SphereFace {
        SphereFace {
            normal,
            right,
            up: Vec3::Y,
            longitude: Some(longitude),
        }
    }
    const fn cap(normal: Vec3, up: Vec3) -> SphereFace {
        SphereFace {
            normal,
            right: Vec3::X,
            up,
            longitude: None,
        }
    }
    use std::f32::consts::{FRAC_PI_2, PI};
    [
        side(Vec3::Z, Vec3::X, 0.0),
        side(Vec3::X, Vec3::NEG_Z, FRAC_PI_2),
        side(Vec3::NEG_Z, Vec3::NEG_X, PI),
        side(Vec3::NEG_X, Vec3::Z, 3.0 * FRAC_PI_2),
        cap(Vec3::Y, Vec3::NEG_Z),
        cap(Vec3::NEG_Y, Vec3::Z),
    ]
};

impl SphereFace {
    /// The UV and the unit ∂p/∂u direction of the point `p` of this face (see
    /// [`Mesh::sphere`]).
    fn parametrisation(&self, p: Vec3) -> (Vec2, Vec3) {
        use std::f32::consts::PI;
        // The angles of p from the face centre towards `right` and towards `up`.
        let across = p.dot(self.right).atan2(p.dot(self.normal));
        match self.longitude {
            Some(centre) => {
                let uv = Vec2::new((centre + across) / TAU, 0.5 + p.y.clamp(-1.0, 1.0).asin() / PI);
                (uv, Vec3::new(p.z, 0.0, -p.x).normalize())
            }
            None => {
                let along = p.dot(self.up).atan2(p.dot(self.normal));
                let uv = Vec2::new(across / TAU, self.normal.y.max(0.0) + along / PI);
                (uv, (self.right - p * p.dot(self.right)).normalize())
            }
        }
    }
}

/// `q / |q|` with |q| summed from the smallest square up, so that vectors whose components
/// are permutations and sign changes of each other (the cube's faces meeting at an edge)
/// give the same components bit for bit.
fn unit(q: Vec3) -> Vec3 {
    let mut squares = (q * q).to_array();
    squares.sort_by(f32::total_cmp);
    q / (squares[0] + squares[1] + squares[2]).sqrt()
}

/// A vertex position as a hash key: equal where the coordinates are (−0 and +0 alike), so
/// the corners of triangles that meet share it however their vertices are split (UV
/// seams, creases).
pub(super) fn position_key(position: [f32; 3]) -> [u32; 3] {
    // + 0.0 turns -0.0 into 0.0.
    position.map(|x| (x + 0.0).to_bits())
}

/// The checks of [`Mesh::from_triangles`] on its input, for loaders that work on it first:
/// finite coordinates, one of each attribute per position, and whole triangles whose
/// indices are in range. Errors name `name`.
pub(super) fn check_triangles(
    name: &str,
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
    uvs: Option<&[[f32; 2]]>,
    indices: &[u32],
) -> Result<(), SceneError> {
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
    Ok(())
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
        assert_eq!(mesh.vertices.len(), 6 * 33 * 33);
        assert_eq!(mesh.indices.len(), 6 * 6 * 32 * 32);
        for v in &mesh.vertices {
            let p = Vec3::from(v.position);
            assert!((p.length() - 1.0).abs() < 1e-6, "{p}");
            assert_eq!(v.normal, v.position);
            assert_eq!(v.tangent[3], 1.0);
        }
        assert_frames(&mesh);
        assert_outward(&mesh, |centroid| centroid);
    }

    /// The largest height, over the mesh's radius, of a vertex above the plane of a triangle
    /// that shares an edge with its own (vertices welded by position): 0 or less where every
    /// edge folds outward or is flat.
    fn inward_fold(mesh: &Mesh) -> f32 {
        let key = |i: u32| position_key(mesh.vertices[i as usize].position);
        let point = |i: u32| Vec3::from(mesh.vertices[i as usize].position);
        let mut opposite: std::collections::HashMap<_, Vec<u32>> = std::collections::HashMap::new();
        for t in mesh.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
                opposite.entry((a.min(b), a.max(b))).or_default().push(t[(k + 2) % 3]);
            }
        }
        let radius = mesh.bounding_sphere().1;
        let mut worst = f32::NEG_INFINITY;
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(point);
            let normal = (b - a).cross(c - a).normalize();
            for k in 0..3 {
                let (p, q) = (key(t[k]), key(t[(k + 1) % 3]));
                for &o in &opposite[&(p.min(q), p.max(q))] {
                    worst = worst.max(normal.dot(point(o) - a) / radius);
                }
            }
        }
        worst
    }

    /// The meshes that say they bound convex solids fold outward (or not at all, within
    /// rounding) at every edge, the torus inward at some: a closed, connected surface
    /// convex at each edge bounds a convex solid (Tietze's theorem).
    #[test]
    fn convex_builtins_fold_outward_at_every_edge() {
        let meshes = [1, 2, 3, 4, 7, 32, 64].map(Mesh::sphere).into_iter().chain([Mesh::cube(), Mesh::plane()]);
        for mesh in meshes {
            assert!(mesh.is_convex());
            let fold = inward_fold(&mesh);
            assert!(fold < 1e-6, "{} ({:?}) folds inward by {fold:e} of its radius", mesh.name, mesh.subdivisions);
        }
        let torus = Mesh::builtin("builtin:torus").unwrap();
        assert!(!torus.is_convex() && inward_fold(&torus) > 1e-3);
    }

    /// With vertices welded by position, every edge borders exactly two triangles: the
    /// faces meet without cracks.
    #[test]
    fn sphere_is_closed() {
        for n in [1, 2, 7, 32] {
            let mesh = Mesh::sphere(n);
            let mut welded = std::collections::HashMap::new();
            let point: Vec<usize> = mesh
                .vertices
                .iter()
                .map(|v| {
                    let count = welded.len();
                    *welded.entry(position_key(v.position)).or_insert(count)
                })
                .collect();
            assert_eq!(welded.len() as u32, 6 * n * n + 2, "distinct points of sphere({n})");
            let mut edges = std::collections::HashMap::new();
            for t in mesh.indices.chunks_exact(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    let (a, b) = (point[a as usize], point[b as usize]);
                    *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
            assert!(edges.values().all(|&count| count == 2), "sphere({n}) has open edges");
        }
    }

    /// The UV sphere's u compresses without bound towards its poles; here, per triangle,
    /// the map from UV (u scaled by 2π and v by π, the units the presets' `[2k, k]` UV
    /// scales assume) to the surface stretches by between 0.5 and 1.5 in every direction,
    /// and by less than 2 more in one direction than the other.
    #[test]
    fn sphere_uvs_have_no_pole() {
        use std::f32::consts::PI;
        let mesh = Mesh::builtin("builtin:sphere").unwrap();
        let (mut low, mut high, mut anisotropy) = (f32::MAX, 0.0f32, 0.0f32);
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.vertices[i as usize]);
            let p = |v: Vertex| Vec3::from(v.position);
            let uv = |v: Vertex| Vec2::from(v.uv) * Vec2::new(2.0 * PI, PI);
            let (e1, e2) = (p(b) - p(a), p(c) - p(a));
            let (d1, d2) = (uv(b) - uv(a), uv(c) - uv(a));
            // ∂p/∂u and ∂p/∂v of the triangle, and the singular values of [∂p/∂u ∂p/∂v].
            let det = d1.x * d2.y - d2.x * d1.y;
            let dp_du = (e1 * d2.y - e2 * d1.y) / det;
            let dp_dv = (e2 * d1.x - e1 * d2.x) / det;
            let (guu, guv, gvv) = (dp_du.dot(dp_du), dp_du.dot(dp_dv), dp_dv.dot(dp_dv));
            let mean = (guu + gvv) / 2.0;
            let spread = (((guu - gvv) / 2.0).powi(2) + guv * guv).sqrt();
            let (small, large) = ((mean - spread).sqrt(), (mean + spread).sqrt());
            (low, high) = (low.min(small), high.max(large));
            anisotropy = anisotropy.max(large / small);
        }
        println!("stretch {low}..{high}, anisotropy up to {anisotropy}");
        assert!(
            low > 0.5 && high < 1.5 && anisotropy < 2.0,
            "{low}..{high}, {anisotropy}"
        );
    }

    #[test]
    fn sphere_uvs_follow_the_tangent_convention() {
        let mesh = Mesh::sphere(8);
        let at = |p: Vec3| {
            let found: Vec<_> = mesh
                .vertices
                .iter()
                .filter(|v| Vec3::from(v.position).abs_diff_eq(p, 1e-6))
                .collect();
            assert!(!found.is_empty(), "no vertex at {p}");
            found
        };
        // On the +z equator: u = 0, v = 0.5, tangent +x, and cross(n, t) = +y is the
        // direction of increasing v.
        let front = at(Vec3::Z);
        assert_eq!(front.len(), 1);
        assert!(Vec2::from(front[0].uv).abs_diff_eq(Vec2::new(0.0, 0.5), 1e-6));
        assert!(Vec4::from(front[0].tangent).abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6));
        // The north pole is the middle of the top cap: u along +x, v towards -z.
        let north = at(Vec3::Y);
        assert_eq!(north.len(), 1);
        assert!(Vec2::from(north[0].uv).abs_diff_eq(Vec2::new(0.0, 1.0), 1e-6));
        assert!(Vec4::from(north[0].tangent).abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6));
        let south = at(Vec3::NEG_Y);
        assert!(Vec2::from(south[0].uv).abs_diff_eq(Vec2::ZERO, 1e-6));
        // The side faces share UVs along their edges (u modulo 1), so maps tile across
        // them; the caps meet the +z face with the same UVs at the middle of its edges.
        let same_uv = |p: Vec3| {
            let uvs: Vec<Vec2> = at(p).iter().map(|v| Vec2::from(v.uv)).collect();
            uvs.iter().all(|uv| {
                let d = *uv - uvs[0];
                (d.x - d.x.round()).abs() < 1e-6 && d.y.abs() < 1e-6
            })
        };
        for corner in [
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(1.0, std::f32::consts::FRAC_PI_8.tan(), -1.0),
        ] {
            assert!(same_uv(unit(corner)), "{corner}");
        }
        assert!(same_uv(unit(Vec3::new(0.0, 1.0, 1.0))));
        assert!(same_uv(unit(Vec3::new(0.0, -1.0, 1.0))));
    }

    #[test]
    fn small_or_zero_tessellation_is_clamped() {
        let mesh = Mesh::sphere(0);
        assert_eq!(mesh.vertices.len(), 6 * 4);
        assert_frames(&mesh);
        assert_outward(&mesh, |centroid| centroid);
        let torus = Mesh::torus(1.0, 0.3, 1, 1);
        assert_eq!(torus.vertices.len(), 4 * 3);
        assert_frames(&torus);
        let huge = Mesh::torus(1.0, 0.3, u32::MAX, 2);
        assert_eq!(huge.vertices.len(), 4097 * 3);
        // The builtin's tube keeps 3/8 of its ring's cells, and at least 3.
        assert_eq!([1, 3, 9, 64, 128].map(torus_sides), [3, 3, 3, 24, 48]);
        assert_eq!(torus_sides(u32::MAX), (3 * u64::from(u32::MAX) / 8 + 1) as u32);
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
        for name in BUILTIN_MESHES {
            let mesh = Mesh::builtin(name).unwrap();
            let positions: Vec<_> = mesh.vertices.iter().map(|v| v.position).collect();
            let normals: Vec<_> = mesh.vertices.iter().map(|v| v.normal).collect();
            let uvs: Vec<_> = mesh.vertices.iter().map(|v| v.uv).collect();
            let generated = Mesh::from_triangles(name, &positions, Some(&normals), Some(&uvs), &mesh.indices).unwrap();
            for (built, made) in mesh.vertices.iter().zip(&generated.vertices) {
                assert!(Vec3::from(built.normal).abs_diff_eq(made.normal.into(), 1e-6));
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
