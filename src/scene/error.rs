use std::path::PathBuf;

/// Everything that can go wrong while loading a scene or a mesh.
///
/// Every message starts with the file (or the mesh/scene name for in-memory
/// input) and is complete on its own: the underlying error's text is part of
/// the message rather than a chained `source`, so `{:#}` in anyhow does not
/// print it twice.
#[derive(thiserror::Error, Debug)]
pub enum SceneError {
    #[error("{}: cannot read: {error}", path.display())]
    Io { path: PathBuf, error: std::io::Error },

    /// Syntax errors, unknown keys, wrong types and unknown kinds; toml's
    /// message carries the line, column and offending key.
    #[error("{origin}: {error}")]
    Toml { origin: String, error: toml::de::Error },

    /// A value that parsed but is out of range, or a reference that does not
    /// resolve. `field` is a dotted path such as `materials.clay.roughness`.
    #[error("{origin}: {field} = {value}: {reason}")]
    Invalid {
        origin: String,
        field: String,
        value: String,
        reason: String,
    },

    #[error("{origin}: the scene has no objects; add at least one [[objects]] table")]
    NoObjects { origin: String },

    /// A file or a scene larger than argil accepts (`limits.rs`), refused before it is
    /// read or parsed.
    #[error("{}: {problem}", path.display())]
    TooLarge { path: PathBuf, problem: String },

    /// tobj rejected the OBJ text.
    #[error("{}: invalid OBJ: {error}", path.display())]
    Obj { path: PathBuf, error: tobj::LoadError },

    /// A glTF model that cannot be read: corrupt or truncated, a buffer missing or short,
    /// an accessor that does not fit, an extension it requires.
    #[error("{}: invalid glTF: {problem}", path.display())]
    Gltf { path: PathBuf, problem: String },

    /// Geometry that cannot be rendered: no triangles, an index out of range,
    /// a non-finite coordinate. `origin` is the mesh name (its file for OBJ).
    #[error("{origin}: {problem}")]
    InvalidMesh { origin: String, problem: String },

    /// A mesh referenced by the scene failed to load; `error` names the mesh
    /// file and the scene part names the object that referenced it.
    #[error("{origin}: {field} = {value:?}: {error}")]
    ObjectMesh {
        origin: String,
        field: String,
        value: String,
        error: Box<SceneError>,
    },

    /// An image file that cannot be a texture: not an image, corrupt or
    /// truncated, an unsupported format, too large, or non-finite texels.
    #[error("{}: {problem}", path.display())]
    Texture { path: PathBuf, problem: String },

    /// A texture referenced by a material map failed to load; `error` names
    /// the image file and `field` the map, e.g. `materials.clay.normal_map.texture`.
    #[error("{origin}: {field} = {value:?}: {error}")]
    MaterialTexture {
        origin: String,
        field: String,
        value: String,
        error: Box<SceneError>,
    },
}
