//! glTF 2.0 models (.gltf with external or `data:` buffers and images, and .glb): every triangle
//! primitive of the model's scene becomes a part, a [`Mesh`] in world space with the node
//! transforms baked in. What argil does not draw (other primitive modes, skins,
//! animations, morph targets, extensions other than KHR_materials_emissive_strength and
//! KHR_texture_transform) is named in one warning each.
//!
//! The `gltf` crate parses and validates the JSON (the indices between its objects
//! included); this module reads the buffers itself, within [`MAX_GLTF_BYTES`], and checks
//! every accessor it reads against its buffer, so that a bad file is an error, never a
//! panic in the crate's readers.

use std::collections::BTreeSet;
use std::io::Read;
use std::path::{Path, PathBuf};

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::buffer::Source;
use ::gltf::mesh::util::ReadTexCoords;
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Document, Gltf, Node, Primitive, Semantic};
use base64::Engine;
use glam::{Mat3, Mat4, Vec3, Vec4};

use super::file::{MapDef, MaterialDef, ObjectDef, SceneFile};
use super::limits::{check_file_size, MAX_GLTF_BYTES, MAX_MESH_TRIANGLES};
use super::map_slots::MapSlot;
use super::material_keys::MAP_STRENGTH;
use super::mesh::check_triangles;
use super::mikktspace;
use super::{Camera, Mesh, Scene, SceneError, DEFAULT_SCENE_TOML};

/// Whether a path (or a scene's `mesh` string) names a glTF model, by its extension in
/// any case.
pub fn is_model(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// A loaded model.
#[derive(Debug)]
pub struct Model {
    /// One per triangle primitive of each node of the scene, in the order of a depth-first
    /// walk of its nodes.
    pub parts: Vec<Part>,
    /// The file's materials as scene material tables, by glTF index, each named
    /// `"<file> #<index> <name>"`.
    pub materials: Vec<(String, MaterialDef)>,
    /// The images embedded in the file (by a buffer view or a `data:` URI) that the
    /// materials' maps name, each as (texture name, encoded bytes); the name,
    /// `"<absolute model path>#image<index>"`, is no file: these are decoded from the
    /// bytes, once per texture name and role as files are.
    pub images: Vec<Embedded>,
    /// The files of its buffers that are not in the model's own file (nor `data:` URIs).
    pub buffer_files: Vec<PathBuf>,
    /// One line each, starting with the file's name.
    pub warnings: Vec<String>,
}

/// One primitive of a model.
#[derive(Debug)]
pub struct Part {
    /// In world space, named after the file.
    pub mesh: Mesh,
    /// Its index in [`Model::materials`]; `None` for glTF's default material.
    pub material: Option<usize>,
}

/// An image embedded in the model: its texture name and its encoded bytes.
type Embedded = (String, Vec<u8>);

/// A primitive to draw: the node's world matrix, its mesh's index and the primitive.
type Instance<'a> = (Mat4, usize, Primitive<'a>);

impl Model {
    /// Reads the model at `path`, its buffers relative to its folder.
    pub fn load(path: &Path) -> Result<Model, SceneError> {
        let invalid = |problem: String| SceneError::Gltf {
            path: path.to_path_buf(),
            problem,
        };
        check_file_size(path, MAX_GLTF_BYTES, "glTF files")?;
        let bytes = std::fs::read(path).map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        check_glb_header(&bytes).map_err(invalid)?;
        let Gltf { document, blob } = Gltf::from_slice_without_validation(&bytes).map_err(|e| invalid(message(e)))?;
        // Before validation, which reports an extension the crate does not know less plainly.
        if let Some(extension) = document.extensions_required().find(|e| !SUPPORTED_EXTENSIONS.contains(e)) {
            return Err(invalid(format!(
                "the model requires the extension {extension}, which argil does not support"
            )));
        }
        let document = Document::from_json(document.into_json()).map_err(|e| invalid(message(e)))?;
        let folder = path.parent().unwrap_or(Path::new(""));
        let mut buffer_files = Vec::new();
        let buffers = document
            .buffers()
            .map(|buffer| {
                let data = match buffer.source() {
                    Source::Bin => blob.clone().ok_or_else(|| "the file has no binary chunk".to_owned()),
                    Source::Uri(uri) => read_uri(uri, folder).map(|(data, file)| {
                        buffer_files.extend(file);
                        data
                    }),
                };
                let data = data.map_err(|problem| format!("buffer {}: {problem}", buffer.index()))?;
                if data.len() < buffer.length() {
                    return Err(format!(
                        "buffer {}: {} bytes of data where the file declares {}",
                        buffer.index(),
                        data.len(),
                        buffer.length()
                    ));
                }
                Ok(data)
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(invalid)?;
        let name = path.display().to_string();
        let mut warnings = unsupported_parts(&document);
        let instances = instances(&document).map_err(invalid)?;

        // Triangles counted from the accessors' counts, before any is read.
        let mut triangles = 0u64;
        let mut skipped_modes = BTreeSet::new();
        for (_, _, primitive) in &instances {
            match primitive.mode() {
                Mode::Triangles => {
                    let corners = primitive.indices().or_else(|| primitive.get(&Semantic::Positions));
                    triangles += corners.map_or(0, |a| a.count() as u64 / 3);
                }
                other => {
                    skipped_modes.insert(mode_name(other));
                }
            }
        }
        if triangles > MAX_MESH_TRIANGLES {
            return Err(SceneError::TooLarge {
                path: path.to_path_buf(),
                problem: format!("the model has {triangles} triangles; at most {MAX_MESH_TRIANGLES} are accepted"),
            });
        }
        warnings.extend(
            skipped_modes
                .iter()
                .map(|mode| format!("primitives of mode {mode} are not drawn")),
        );

        let mut parts = Vec::new();
        for (world, mesh, primitive) in instances.iter().filter(|(_, _, p)| p.mode() == Mode::Triangles) {
            let origin = format!("{name}: mesh {mesh} primitive {}", primitive.index());
            let mut mesh = part(&origin, *world, primitive, &buffers)?;
            mesh.name.clone_from(&name);
            parts.push(Part {
                mesh,
                material: primitive.material().index(),
            });
        }
        if parts.is_empty() {
            return Err(invalid("the model's scene has no triangles to draw".to_owned()));
        }
        let embedded = embedded_images(&document, &buffers, folder, path).map_err(invalid)?;
        let materials = materials(&document, path, &embedded, &mut warnings).map_err(invalid)?;
        // glTF: a primitive MUST have the texture coordinates its material's textures read
        // (every map argil keeps reads TEXCOORD_0); without them the maps would read one texel.
        for (_, mesh, primitive) in instances.iter().filter(|(_, _, p)| p.mode() == Mode::Triangles) {
            let Some(material) = primitive.material().index() else {
                continue;
            };
            let mapped = MapSlot::ALL.iter().any(|&slot| materials[material].1.map(slot).is_some());
            if mapped && primitive.get(&Semantic::TexCoords(0)).is_none() {
                return Err(invalid(format!(
                    "mesh {mesh} primitive {}: material {material} has textures on TEXCOORD_0, which the primitive lacks",
                    primitive.index()
                )));
            }
        }
        let named: BTreeSet<&str> = materials
            .iter()
            .flat_map(|(_, def)| MapSlot::ALL.map(|slot| def.map(slot)))
            .flatten()
            .map(|map| map.texture.as_str())
            .collect();
        let images = embedded
            .into_iter()
            .flatten()
            .filter(|(texture, _)| named.contains(texture.as_str()))
            .collect();
        Ok(Model {
            parts,
            materials,
            images,
            buffer_files,
            warnings: warnings.into_iter().map(|w| format!("{name}: {w}")).collect(),
        })
    }
}

/// The `gltf` crate's error without its own "invalid glTF:" prefix, which
/// [`SceneError::Gltf`] has already.
fn message(error: ::gltf::Error) -> String {
    match error {
        ::gltf::Error::Validation(errors) => errors
            .iter()
            .map(|(path, error)| format!("{path}: {error}"))
            .collect::<Vec<_>>()
            .join("; "),
        other => other.to_string(),
    }
}

/// A .glb file's header against the file's length: the `gltf` crate subtracts the header's
/// size from the declared length unchecked.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let declared = bytes
        .get(8..12)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
        .ok_or("truncated: the .glb header is incomplete")?;
    if declared < 12 || declared > bytes.len() {
        return Err(format!(
            "truncated or corrupt .glb: its header declares {declared} bytes and the file has {}",
            bytes.len()
        ));
    }
    Ok(())
}

/// The bytes a buffer's URI names: a base64 `data:` URI, or a file relative to `folder`,
/// with that file.
fn read_uri(uri: &str, folder: &Path) -> Result<(Vec<u8>, Option<PathBuf>), String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (_, encoded) = data
            .split_once(";base64,")
            .ok_or("a data: URI that is not base64-encoded")?;
        return base64::engine::general_purpose::STANDARD
            .decode(encoded)
            .map(|bytes| (bytes, None))
            .map_err(|e| format!("its data: URI is not valid base64: {e}"));
    }
    if uri.contains("://") {
        return Err(format!(
            "{uri:?} is not a relative file URI; argil reads only local files"
        ));
    }
    let decoded = percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| format!("{uri:?} is not UTF-8 once percent-decoded"))?;
    let file = folder.join(decoded.as_ref());
    check_file_size(&file, MAX_GLTF_BYTES, "glTF buffers").map_err(|e| e.to_string())?;
    let bytes = std::fs::read(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    Ok((bytes, Some(file)))
}

/// The extensions argil reads (the `gltf` crate's features that parse them are on).
const SUPPORTED_EXTENSIONS: &[&str] = &["KHR_materials_emissive_strength", KHR_TEXTURE_TRANSFORM];

const KHR_TEXTURE_TRANSFORM: &str = "KHR_texture_transform";

/// A texture reference's KHR_texture_transform, in glTF's UVs (v down the image):
/// `uv' = offset + rotate(rotation, scale · uv)`, reading `TEXCOORD_<tex_coord>` if given.
#[derive(Clone, Copy, Debug)]
struct UvTransform {
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
    tex_coord: Option<u32>,
}

impl UvTransform {
    /// Of a base colour, metallic-roughness or emissive texture, which the `gltf` crate parses.
    fn of_info(info: &::gltf::texture::Info) -> Option<UvTransform> {
        info.texture_transform().map(|t| UvTransform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
            tex_coord: t.tex_coord(),
        })
    }

    /// Of a normal or occlusion texture, whose extensions the `gltf` crate leaves as JSON.
    fn parse(extension: Option<&::gltf::json::Value>) -> Result<Option<UvTransform>, String> {
        let Some(value) = extension else {
            return Ok(None);
        };
        let t: ::gltf::json::extensions::texture::TextureTransform =
            ::gltf::json::deserialize::from_value(value.clone()).map_err(|e| format!("{KHR_TEXTURE_TRANSFORM}: {e}"))?;
        Ok(Some(UvTransform {
            offset: t.offset.0,
            rotation: t.rotation.0,
            scale: t.scale.0,
            tex_coord: t.tex_coord,
        }))
    }

    /// `map` sampled through this transform. argil's UVs run up the image, v = 1 - v_glTF.
    /// glTF's `uv' = o + R(θ) (s ⊙ uv)` turns the scaled UVs by θ counter-clockwise as
    /// seen with v up (the direction of the arrows of Khronos' TextureTransformTest model),
    /// so in argil's UVs it is the same turn of the same scale, offset by
    /// `(o_u + s_v sin θ, 1 - s_v cos θ - o_v)`.
    fn apply(&self, map: MapDef) -> MapDef {
        let ([su, sv], [ou, ov]) = (self.scale.map(f64::from), self.offset.map(f64::from));
        let (sin, cos) = f64::from(self.rotation).sin_cos();
        MapDef {
            uv_scale: [su, sv],
            uv_offset: [ou + sv * sin, 1.0 - sv * cos - ov],
            uv_rotation_degrees: f64::from(self.rotation).to_degrees(),
            ..map
        }
    }
}

/// The warnings for what the model has and argil does not draw.
fn unsupported_parts(document: &Document) -> Vec<String> {
    let mut warnings: Vec<String> = document
        .extensions_used()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .map(|e| format!("the extension {e} is not supported and is ignored"))
        .collect();
    let count = |n: usize, what: &str| (n > 0).then(|| format!("{n} {what}"));
    warnings.extend(count(document.animations().count(), "animation(s) are not played"));
    warnings.extend(count(
        document.skins().count(),
        "skin(s) are ignored: meshes are drawn in their bind pose",
    ));
    let morphed = document
        .meshes()
        .flat_map(|m| m.primitives())
        .filter(|p| p.morph_targets().next().is_some())
        .count();
    warnings.extend(count(
        morphed,
        "primitive(s) have morph targets, which are ignored (the base shape is drawn)",
    ));
    warnings
}

/// The model's materials as scene materials: glTF's metallic-roughness model is argil's
/// `metallic` blend, with the base colour factor (its alpha dropped) and map, the
/// metallic and roughness factors and their map, the normal map with its scale, the
/// occlusion map with its strength and the emissive factor (times its strength) and
/// map, each map with its KHR_texture_transform's offset and scale. What argil cannot
/// draw yet is named in `warnings`, once per model; a malformed KHR_texture_transform on a
/// normal or occlusion texture is an error naming the material (on the other textures the
/// `gltf` crate refuses it already).
fn materials(
    document: &Document,
    path: &Path,
    embedded: &[Option<Embedded>],
    warnings: &mut Vec<String>,
) -> Result<Vec<(String, MaterialDef)>, String> {
    let unused = std::cell::RefCell::new(BTreeSet::new());
    let note = |warning: &str| {
        unused.borrow_mut().insert(warning.to_owned());
    };
    let images = &document.as_json().images;
    let folder = path.parent().unwrap_or(Path::new(""));
    // A map of image `index` (a texture's source), if argil can read it: a file beside the
    // model, named absolute so that it does not depend on the scene's folder.
    let image = |index: usize, tex_coord: u32| -> Option<String> {
        if tex_coord != 0 {
            note("textures on TEXCOORD_1 or above are not supported; those maps are left out");
            return None;
        }
        if let Some((texture, _)) = embedded.get(index).and_then(Option::as_ref) {
            return Some(texture.clone());
        }
        let uri = images.get(index)?.uri.as_deref()?;
        let decoded = percent_encoding::percent_decode_str(uri).decode_utf8_lossy();
        let file = folder.join(decoded.as_ref());
        Some(std::path::absolute(&file).unwrap_or(file).display().to_string())
    };
    // The map of image `index` read through `transform`, whose texCoord, if it has one,
    // overrides the reference's `tex_coord`.
    let map = |index: usize, tex_coord: u32, transform: Option<UvTransform>| {
        let Some(transform) = transform else {
            return image(index, tex_coord).map(MapDef::new);
        };
        let tex_coord = transform.tex_coord.unwrap_or(tex_coord);
        image(index, tex_coord).map(|texture| transform.apply(MapDef::new(texture)))
    };
    // A map with the strength the file gives (`what`), clamped to argil's range.
    let scaled = |index: usize, tex_coord: u32, transform: Option<UvTransform>, strength: f32, what: &str| {
        if !MAP_STRENGTH.contains(strength) {
            note(&format!("{what} outside argil's map strength range is clamped to it"));
        }
        let strength = strength.clamp(MAP_STRENGTH.low, MAP_STRENGTH.high.unwrap_or(f32::MAX));
        map(index, tex_coord, transform).map(|m| MapDef {
            strength: f64::from(strength),
            ..m
        })
    };
    let materials = document
        .materials()
        .map(|material| {
            let index = material.index().unwrap_or_default();
            let transform = |extension: Option<&::gltf::json::Value>, texture: &str| {
                UvTransform::parse(extension).map_err(|problem| format!("material {index}: {texture}: {problem}"))
            };
            let pbr = material.pbr_metallic_roughness();
            let [r, g, b, _] = pbr.base_color_factor();
            let info_map = |info: ::gltf::texture::Info| {
                map(info.texture().source().index(), info.tex_coord(), UvTransform::of_info(&info))
            };
            let base_color_map = pbr.base_color_texture().and_then(info_map);
            // One metallic-roughness texture serves both slots, which read its G and B
            // channels (map_slots.rs); the factors are the values it multiplies.
            let metallic_roughness = pbr.metallic_roughness_texture().and_then(info_map);
            let normal_map = match material.normal_texture() {
                Some(info) => scaled(
                    info.texture().source().index(),
                    info.tex_coord(),
                    transform(info.extension_value(KHR_TEXTURE_TRANSFORM), "normalTexture")?,
                    info.scale(),
                    "a normal texture's scale",
                ),
                None => None,
            };
            let occlusion_map = match material.occlusion_texture() {
                Some(info) => scaled(
                    info.texture().source().index(),
                    info.tex_coord(),
                    transform(info.extension_value(KHR_TEXTURE_TRANSFORM), "occlusionTexture")?,
                    info.strength(),
                    "an occlusion texture's strength",
                ),
                None => None,
            };
            // KHR_materials_emissive_strength scales the factor, which glTF otherwise
            // keeps in [0, 1]; the texture multiplies it, as `emission_map` does.
            let strength = material.emissive_strength().unwrap_or(1.0);
            let emission = material.emissive_factor().map(|c| f64::from(c) * f64::from(strength));
            let emission_map = material.emissive_texture().and_then(info_map);
            if material.alpha_mode() != ::gltf::material::AlphaMode::Opaque {
                note("transparency (alphaMode MASK or BLEND) is not supported: surfaces are drawn opaque");
            }
            let name = format!("{} #{index} {}", path.display(), material.name().unwrap_or(""));
            let def = MaterialDef {
                base_color: [r, g, b].map(f64::from),
                // glTF's roughness is perceptual, α = roughness², as argil's `roughness` is
                // (material_keys.rs): the factor is taken as it is.
                roughness: f64::from(pbr.roughness_factor()),
                metallic: f64::from(pbr.metallic_factor()),
                base_color_map,
                normal_map,
                roughness_map: metallic_roughness.clone(),
                metallic_map: metallic_roughness,
                occlusion_map,
                emission,
                emission_map,
                ..MaterialDef::default()
            };
            Ok((name.trim_end().to_owned(), def))
        })
        .collect::<Result<_, String>>()?;
    warnings.extend(unused.into_inner());
    Ok(materials)
}

/// Every image of the model, by index, that is embedded in it (a buffer view or a `data:`
/// URI): its texture name, the model's absolute path and `#image<index>`, and its bytes;
/// `None` for an image in a file of its own.
fn embedded_images(
    document: &Document,
    buffers: &[Vec<u8>],
    folder: &Path,
    path: &Path,
) -> Result<Vec<Option<Embedded>>, String> {
    let model = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    document
        .images()
        .map(|image| {
            let index = image.index();
            let bytes = match image.source() {
                ::gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
                    read_uri(uri, folder).map(|(bytes, _)| Some(bytes))
                }
                ::gltf::image::Source::Uri { .. } => Ok(None),
                ::gltf::image::Source::View { view, .. } => view_bytes(&view, buffers).map(|b| Some(b.to_vec())),
            };
            bytes
                .map(|bytes| bytes.map(|bytes| (format!("{}#image{index}", model.display()), bytes)))
                .map_err(|problem| format!("image {index}: {problem}"))
        })
        .collect()
}

/// The nodes of the default scene (else the first), each with its world matrix, depth
/// first. glTF's nodes form trees; a node reached twice (a cycle, or a node shared by two
/// parents) is an error rather than endless recursion.
fn walk(document: &Document) -> Result<Vec<(Mat4, Node<'_>)>, String> {
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or("the file has no scene to draw")?;
    let mut seen = vec![false; document.nodes().count()];
    let mut stack: Vec<_> = scene.nodes().map(|node| (Mat4::IDENTITY, node)).collect();
    stack.reverse();
    let mut nodes = Vec::new();
    while let Some((parent, node)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(format!(
                "node {} is reached twice: the nodes of a scene must form trees",
                node.index()
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let children: Vec<_> = node.children().map(|child| (world, child)).collect();
        stack.extend(children.into_iter().rev());
        nodes.push((world, node));
    }
    Ok(nodes)
}

/// The primitives of the scene's nodes, each with its node's world matrix.
fn instances(document: &Document) -> Result<Vec<Instance<'_>>, String> {
    Ok(walk(document)?
        .into_iter()
        .filter_map(|(world, node)| node.mesh().map(|mesh| (world, mesh)))
        .flat_map(|(world, mesh)| mesh.primitives().map(move |p| (world, mesh.index(), p)))
        .collect())
}

/// glTF's name of a primitive mode.
fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

/// One primitive in world space: `world` applied to positions and tangents, its inverse
/// transpose to normals, and the winding reversed where `world` mirrors (det < 0), so that
/// front faces stay counter-clockwise seen from outside. Tangents the file lacks, where it
/// has normals and UVs, are MikkTSpace's (mikktspace.rs). Errors name `origin`.
fn part(origin: &str, world: Mat4, primitive: &Primitive, buffers: &[Vec<u8>]) -> Result<Mesh, SceneError> {
    let invalid = |problem: String| SceneError::InvalidMesh {
        origin: origin.to_owned(),
        problem,
    };
    let read = |accessor: Accessor, semantic: &str, types: &[DataType], dimensions: Dimensions| {
        check_accessor(&accessor, types, dimensions, buffers)
            .map_err(|problem| invalid(format!("{semantic} (accessor {}): {problem}", accessor.index())))
    };
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(Vec::as_slice));
    let positions = primitive
        .get(&Semantic::Positions)
        .ok_or_else(|| invalid("no POSITION attribute".into()))?;
    read(positions, "POSITION", &[DataType::F32], Dimensions::Vec3)?;
    let mut positions: Vec<[f32; 3]> = reader.read_positions().map(Iterator::collect).unwrap_or_default();
    let mut normals: Option<Vec<[f32; 3]>> = match primitive.get(&Semantic::Normals) {
        Some(accessor) => {
            read(accessor, "NORMAL", &[DataType::F32], Dimensions::Vec3)?;
            reader.read_normals().map(Iterator::collect)
        }
        None => None,
    };
    let mut tangents: Option<Vec<[f32; 4]>> = match primitive.get(&Semantic::Tangents) {
        Some(accessor) => {
            read(accessor, "TANGENT", &[DataType::F32], Dimensions::Vec4)?;
            reader.read_tangents().map(Iterator::collect)
        }
        None => None,
    };
    // glTF's v runs down the image and argil's up it (as OBJ's): v' = 1 - v.
    let mut uvs: Option<Vec<[f32; 2]>> = match primitive.get(&Semantic::TexCoords(0)) {
        Some(accessor) => {
            let types = [DataType::F32, DataType::U8, DataType::U16];
            read(accessor, "TEXCOORD_0", &types, Dimensions::Vec2)?;
            reader
                .read_tex_coords(0)
                .map(ReadTexCoords::into_f32)
                .map(|uvs| uvs.map(|[u, v]| [u, 1.0 - v]).collect())
        }
        None => None,
    };
    let mut indices: Vec<u32> = match primitive.indices() {
        Some(accessor) => {
            let types = [DataType::U8, DataType::U16, DataType::U32];
            read(accessor, "indices", &types, Dimensions::Scalar)?;
            reader
                .read_indices()
                .map(|i| i.into_u32().collect())
                .unwrap_or_default()
        }
        None => (0..positions.len() as u32).collect(),
    };
    if let Some(t) = &tangents {
        if t.len() != positions.len() {
            return Err(invalid(format!(
                "{} tangents for {} vertices",
                t.len(),
                positions.len()
            )));
        }
    }
    // Before MikkTSpace and the flat-shading split, which index the attributes.
    check_triangles(origin, &positions, normals.as_deref(), uvs.as_deref(), &indices)?;
    // glTF's rule: tangents missing from the file are MikkTSpace's, generated before the
    // node's transform, as the file's own would have been.
    let split = match (&tangents, &normals, &uvs) {
        (None, Some(given_normals), Some(given_uvs)) => {
            mikktspace::split_by_tangents(&positions, given_normals, given_uvs, &indices)
        }
        _ => None,
    };
    if let Some(split) = split {
        positions = split.positions;
        normals = Some(split.normals);
        uvs = Some(split.uvs);
        tangents = Some(split.tangents);
        indices = split.indices;
    }

    let linear = Mat3::from_mat4(world);
    let normal_matrix = linear.inverse().transpose();
    let mirrors = linear.determinant() < 0.0;
    for p in &mut positions {
        *p = world.transform_point3(Vec3::from(*p)).to_array();
    }
    for n in normals.iter_mut().flatten() {
        *n = (normal_matrix * Vec3::from(*n)).to_array();
    }
    // The bitangent w · cross(n, t) turns with the frame; a mirror flips its handedness.
    let handedness = if mirrors { -1.0 } else { 1.0 };
    for t in tangents.iter_mut().flatten() {
        let v = Vec4::from(*t);
        *t = (linear * v.truncate()).extend(v.w * handedness).to_array();
    }
    if mirrors {
        for triangle in indices.chunks_exact_mut(3) {
            triangle.swap(1, 2);
        }
    }
    if normals.is_none() {
        // glTF's rule: without normals a primitive is flat shaded and its tangents are
        // ignored. Unshared corners get their own triangle's normal from `from_triangles`.
        positions = indices.iter().map(|&i| positions[i as usize]).collect();
        uvs = uvs.map(|uvs| indices.iter().map(|&i| uvs[i as usize]).collect());
        tangents = None;
        indices = (0..positions.len() as u32).collect();
    }
    Mesh::from_triangles_with_tangents(
        origin,
        &positions,
        normals.as_deref(),
        uvs.as_deref(),
        tangents.as_deref(),
        &indices,
    )
}

/// Checks that the `gltf` crate's reader can read `accessor` as the type argil asks of it
/// (its readers index slices and assume the types unchecked): one of `types` (integers
/// normalized, except indices), `dimensions`, dense, and within its view and buffer.
fn check_accessor(
    accessor: &Accessor,
    types: &[DataType],
    dimensions: Dimensions,
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    let data_type = accessor.data_type();
    let integer = data_type != DataType::F32;
    let indices = dimensions == Dimensions::Scalar;
    if !types.contains(&data_type)
        || accessor.dimensions() != dimensions
        || (integer && !indices && !accessor.normalized())
    {
        return Err(format!(
            "{:?} {:?}{} is not a supported type",
            accessor.dimensions(),
            data_type,
            if accessor.normalized() { " (normalized)" } else { "" }
        ));
    }
    if accessor.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let view = accessor
        .view()
        .ok_or("an accessor without a buffer view is not supported")?;
    if accessor.count() == 0 {
        return Err("no elements".into());
    }
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!("a byte stride of {stride} for elements of {size} bytes"));
    }
    let accessor_end = (accessor.count() - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(size))
        .and_then(|n| n.checked_add(accessor.offset()));
    if accessor_end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{} elements from byte {} do not fit in buffer view {} ({} bytes)",
            accessor.count(),
            accessor.offset(),
            view.index(),
            view.length()
        ));
    }
    view_bytes(&view, buffers)?;
    Ok(())
}

/// The bytes of buffer `view`, checked to lie within its buffer.
fn view_bytes<'a>(view: &::gltf::buffer::View, buffers: &'a [Vec<u8>]) -> Result<&'a [u8], String> {
    let buffer = buffers.get(view.buffer().index()).map_or(&[][..], Vec::as_slice);
    let end = view.offset().checked_add(view.length());
    end.and_then(|end| buffer.get(view.offset()..end)).ok_or_else(|| {
        format!(
            "buffer view {} (bytes {}..+{}) is outside buffer {} ({} bytes)",
            view.index(),
            view.offset(),
            view.length(),
            view.buffer().index(),
            buffer.len()
        )
    })
}

/// A model opened on its own (`argil view model.glb`): the default scene's studio
/// environment and lights around the model alone, seen through the model's first camera
/// if it has one, otherwise framing its bounding sphere from the default camera's
/// direction. The default scene is lit for objects of about unit size, so its lights are
/// placed, sized and brightened for the model's size (positions about the model's centre
/// and radii times its radius, intensities times its square, so the light falling on it
/// is the default scene's); so is the occlusion radius. The clipping distances enclose
/// the model, however large.
pub(super) fn open(path: &Path) -> Result<Scene, SceneError> {
    let origin = path.display().to_string();
    let mut file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).map_err(|error| SceneError::Toml {
        origin: "<default scene>".to_owned(),
        error,
    })?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    file.objects = vec![ObjectDef {
        mesh: name,
        position: [0.0; 3],
        scale: 1.0,
        material: None,
        subdivisions: None,
    }];
    file.materials.clear();
    let mut scene = Scene::from_file(&file, &origin, path.parent().unwrap_or(Path::new("")))?;
    scene.source = Some(path.to_path_buf());

    let (centre, radius) = bounds(&scene.meshes);
    for light in &mut scene.lights {
        light.position = centre + light.position * radius;
        light.radius *= radius;
        light.intensity *= radius * radius;
    }
    scene.occlusion.radius *= radius;
    let camera = match first_camera(path, &mut scene.warnings)? {
        Some((world, fov_y_degrees)) => {
            let position = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or(Vec3::NEG_Z);
            Camera {
                position,
                target: position + forward * position.distance(centre).max(radius),
                fov_y_degrees,
                ..scene.camera
            }
        }
        None => {
            let forward = (scene.camera.target - scene.camera.position).normalize_or(Vec3::NEG_Z);
            let half_y = scene.camera.fov_y_degrees.to_radians() * 0.5;
            Camera {
                position: centre - forward * (radius / half_y.sin()),
                target: centre,
                ..scene.camera
            }
        }
    };
    // The model lies within [distance - radius, distance + radius] of the camera; the
    // near plane stays a small fraction of the far one, for the depth buffer's precision.
    let distance = camera.position.distance(centre);
    let far = (distance + radius) * 1.01;
    scene.camera = Camera {
        near: ((distance - radius) * 0.99).max(far * 1e-4),
        far,
        ..camera
    };
    Ok(scene)
}

/// The centre of the meshes' bounding box and the radius about it that encloses every
/// vertex (at least a little above 0, so that a point still makes a view).
fn bounds(meshes: &[Mesh]) -> (Vec3, f32) {
    let points = || meshes.iter().flat_map(|m| &m.vertices).map(|v| Vec3::from(v.position));
    let (min, max) = points().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    });
    let centre = (min + max) * 0.5;
    let radius = points().map(|p| p.distance(centre)).fold(0.0, f32::max);
    (centre, radius.max(1e-3))
}

/// The world matrix and vertical field of view (degrees) of the first camera in a walk of
/// the model's scene, if it is a perspective one; an orthographic one is named in
/// `warnings`. Only the JSON is read again (the model itself loaded already).
fn first_camera(path: &Path, warnings: &mut Vec<String>) -> Result<Option<(Mat4, f32)>, SceneError> {
    let invalid = |problem: String| SceneError::Gltf {
        path: path.to_path_buf(),
        problem,
    };
    let io = |error| SceneError::Io {
        path: path.to_path_buf(),
        error,
    };
    let mut file = std::fs::File::open(path).map_err(io)?;
    let mut head = [0; 20];
    let glb = file.read_exact(&mut head).is_ok() && head.starts_with(b"glTF");
    let json = if glb {
        // The JSON chunk follows the 12-byte header and its own 8-byte header.
        let length = u32::from_le_bytes([head[12], head[13], head[14], head[15]]);
        let mut json = Vec::new();
        file.take(u64::from(length)).read_to_end(&mut json).map_err(io)?;
        json
    } else {
        std::fs::read(path).map_err(io)?
    };
    let root = ::gltf::json::deserialize::from_slice(&json).map_err(|e| invalid(e.to_string()))?;
    let document = Document::from_json(root).map_err(|e| invalid(message(e)))?;
    let Some((world, camera)) = walk(&document)
        .map_err(invalid)?
        .into_iter()
        .find_map(|(world, node)| node.camera().map(|camera| (world, camera.index())))
    else {
        return Ok(None);
    };
    match document
        .as_json()
        .cameras
        .get(camera)
        .and_then(|c| c.perspective.as_ref())
    {
        Some(perspective) => Ok(Some((world, perspective.yfov.to_degrees().clamp(1.0, 179.0)))),
        None => {
            warnings.push(format!(
                "{}: camera {camera} is orthographic, which argil does not draw; the view frames the model",
                path.display()
            ));
            Ok(None)
        }
    }
}
