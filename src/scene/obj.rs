use std::path::Path;

use super::limits::{check_file_size, obj_triangles, MAX_MESH_TRIANGLES, MAX_OBJ_BYTES};
use super::{Mesh, SceneError};

impl Mesh {
    /// Loads every object and group of a Wavefront OBJ file into one mesh
    /// named after `path`. Polygons are triangulated as fans; points, lines
    /// and MTL materials are ignored. Missing normals and tangents are
    /// generated as described on [`Mesh::from_triangles`] (an object that
    /// gives normals or UVs to only some of its vertices is treated as giving
    /// none).
    pub fn load_obj(path: &Path) -> Result<Mesh, SceneError> {
        check_file_size(path, MAX_OBJ_BYTES, "OBJ files")?;
        let text = std::fs::read(path).map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        let triangles = obj_triangles(&text);
        if triangles > MAX_MESH_TRIANGLES {
            return Err(SceneError::TooLarge {
                path: path.to_path_buf(),
                problem: format!("the mesh has {triangles} triangles; at most {MAX_MESH_TRIANGLES} are accepted"),
            });
        }
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // The renderer's materials come from the scene file, so `mtllib` is
        // not even opened.
        let (models, _) =
            tobj::load_obj_buf(&mut text.as_slice(), &options, |_| Ok(Default::default())).map_err(|error| {
                SceneError::Obj {
                    path: path.to_path_buf(),
                    error,
                }
            })?;

        let name = path.display().to_string();
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut indices = Vec::new();
        let mut any_uvs = false;
        for model in &models {
            let mesh = &model.mesh;
            let count = mesh.positions.len() / 3;
            let base = u32::try_from(positions.len()).map_err(|_| too_many(&name))?;
            positions.extend(mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
            // All-zero normals are replaced by computed ones.
            if mesh.normals.len() == 3 * count {
                normals.extend(mesh.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]));
            } else {
                normals.resize(positions.len(), [0.0; 3]);
            }
            // All-zero UVs give no tangent direction, so those vertices get the
            // same fallback tangents as a file without UVs.
            if mesh.texcoords.len() == 2 * count {
                any_uvs = true;
                uvs.extend(mesh.texcoords.chunks_exact(2).map(|t| [t[0], t[1]]));
            } else {
                uvs.resize(positions.len(), [0.0; 2]);
            }
            for &index in &mesh.indices {
                indices.push(index.checked_add(base).ok_or_else(|| too_many(&name))?);
            }
        }
        Mesh::from_triangles(
            &name,
            &positions,
            Some(&normals),
            any_uvs.then_some(uvs.as_slice()),
            &indices,
        )
    }
}

fn too_many(name: &str) -> SceneError {
    SceneError::InvalidMesh {
        origin: name.to_owned(),
        problem: "more vertices than 32-bit indices can address".into(),
    }
}
