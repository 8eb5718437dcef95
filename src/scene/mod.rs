//! Scenes: the TOML scene format (see docs/scene-format.md), its validation,
//! and the runtime data the renderer draws: meshes, materials, lights and a
//! camera.

mod antialiasing;
mod camera;
mod curvature;
mod edit;
mod error;
pub mod file;
mod gltf;
mod ground_shadow;
mod light;
pub mod limits;
pub mod map_slots;
pub mod occluders;
mod material;
pub mod material_keys;
mod mesh;
pub mod mips;
mod mikktspace;
mod obj;
mod occlusion;
mod pending;
mod preset;
mod procedural;
mod resolve;
mod shadow_receivers;
mod solid;
mod tangents;
mod texture;

#[cfg(test)]
pub(crate) mod tests;

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

pub use antialiasing::{Antialiasing, MSAA_COUNTS};
pub use camera::Camera;
pub use error::SceneError;
pub use file::SceneFile;
pub use gltf::is_model;
pub use ground_shadow::GroundRect;
pub use light::{
    Environment, PointLight, Reflection, ReflectionMode, DEFAULT_SHADOW_RESOLUTION, DEFAULT_SHADOW_TAPS,
    SHADOW_RESOLUTION_RANGE, SHADOW_TAPS_RANGE,
};
pub use material::{
    DetailBlend, DiffuseModel, Distribution, Geometry, Horizon, MapRef, MapSlot, Material, MaterialMaps, SpecularModel,
    Subsurface,
};
pub use mesh::{Mesh, MeshExtent, Vertex, BUILTIN_MESHES, BUILTIN_PREFIX};
pub use occlusion::{Occlusion, OCCLUSION_SAMPLES_RANGE};
pub use pending::PendingMaps;
pub use preset::Preset;
pub use procedural::{builtin_texture, BUILTIN_TEXTURES};
pub use texture::{
    decode_texture, load_texture, TexelFormat, TexelReader, TextureData, TextureRole, MAX_TEXTURE_BYTES,
    MAX_TEXTURE_SIDE,
};

/// The scene used when none is given; it needs no files on disk.
pub const DEFAULT_SCENE_TOML: &str = include_str!("default.toml");

/// The longest edge, as a share of its mesh's bounding radius, of an object that gathers
/// the ground's bounce at its vertices ([`Scene::bounce_at_vertices`]): the builtin sphere
/// (0.07 at its 32 cells a cube edge) and torus (0.06) do, a sphere of 16 cells (0.14) or
/// fewer and the cube (1.6) do not.
pub const BOUNCE_VERTEX_EDGE_SHARE: f32 = 0.125;

/// When a scene's builtin maps are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BuiltinMaps {
    /// As the scene loads (or read from the disk cache).
    Now,
    /// Later, by [`PendingMaps`], with stand-ins in their places meanwhile.
    StandIns,
}

/// One instance of a mesh in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    pub position: Vec3,
    /// Uniform scale, > 0.
    pub scale: f32,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Which part of its file object's mesh this is: a glTF model makes one object per
    /// primitive (0, 1, …), anything else one object, part 0. Saving writes part 0 alone.
    pub part: usize,
    /// Whether `material` is the model's own (a glTF part of an object without a
    /// `material` key), which saving leaves to the model.
    pub material_from_model: bool,
}

impl Object {
    /// Object-to-world matrix: scale about the mesh origin, then translate.
    pub fn model_matrix(&self) -> Mat4 {
        Mat4::from_translation(self.position) * Mat4::from_scale(Vec3::splat(self.scale))
    }

    /// The extent of its mesh, `mesh` ([`Mesh::extent`]), in the world: scaled, then moved.
    pub fn world_extent(&self, mesh: &MeshExtent) -> MeshExtent {
        let at = |p: Vec3| self.position + p * self.scale;
        MeshExtent {
            centre: at(mesh.centre),
            radius: mesh.radius * self.scale,
            low: at(mesh.low),
            high: at(mesh.high),
            longest_edge: mesh.longest_edge * self.scale,
            convex: mesh.convex,
        }
    }

    /// The index in `Scene::objects` of the first part of its file object, object `index`
    /// being this one (a model's parts follow each other): the parts of one file object
    /// do not occlude each other's environment light, as one object does not.
    pub fn first_part(&self, index: usize) -> usize {
        index - self.part
    }
}

/// A validated scene with its meshes loaded.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub camera: Camera,
    pub lights: Vec<PointLight>,
    /// Texels on a side of each face of a light's cube shadow map.
    pub shadow_resolution: u32,
    /// Taps of a soft shadow's blocker search and of its filter (PCSS).
    pub shadow_taps: u32,
    /// Whether the lights' light bounces off the ground onto the objects (`[shadows] bounce`).
    pub bounce: bool,
    /// Whether the ground's shadows are read from a map over it, computed once per change,
    /// rather than searched and filtered at each of its pixels (`[shadows] ground_map`).
    pub shadow_ground_map: bool,
    /// Whether the soft shadows of each finely tessellated object but the ground are found
    /// once per change at its vertices and interpolated, rather than searched and filtered
    /// at each of its pixels (`[shadows] per_vertex`, src/render/vertex_light.rs).
    pub shadow_per_vertex: bool,
    pub antialiasing: Antialiasing,
    /// Ambient occlusion of the environment's light.
    pub occlusion: Occlusion,
    pub environment: Environment,
    /// Each distinct `mesh` string of the file, loaded once.
    pub meshes: Vec<Mesh>,
    pub objects: Vec<Object>,
    /// Every material the file defines (in name order), plus the built-in
    /// `default` material if an object uses it.
    pub materials: Vec<Material>,
    /// The textures the materials' maps sample, each distinct (texture
    /// string, role) loaded once, in order of first use.
    pub textures: Vec<TextureData>,
    /// The file this scene was loaded from, if any.
    pub source: Option<PathBuf>,
    /// Every file loading it read besides its own, each once, as opened: its meshes with a
    /// glTF model's buffer files, the textures of its maps, its environment map.
    pub inputs: Vec<PathBuf>,
    /// What loading left out or changed (a glTF model's unsupported parts), one line each,
    /// starting with the file concerned; the command line prints them.
    pub warnings: Vec<String>,
}

impl Scene {
    /// Whether a material reads the pre-integrated subsurface table.
    pub fn needs_preintegrated_table(&self) -> bool {
        self.materials.iter().any(|m| m.subsurface == Subsurface::PreIntegrated)
    }

    /// The first light that casts shadows (one of the first [`limits::MAX_LIGHTS`], which
    /// the shaders see): the one the shadow-map debug view shows.
    pub fn shadow_casting_light(&self) -> Option<usize> {
        self.lights.iter().take(limits::MAX_LIGHTS).position(|l| l.shadows)
    }

    /// The index of the ground: the largest `builtin:plane` (a 2 × 2 square facing +y,
    /// scaled), the last of the largest.
    pub fn ground_index(&self) -> Option<usize> {
        (self.objects.iter().enumerate())
            .filter(|(_, o)| self.meshes[o.mesh].name == "builtin:plane")
            .max_by(|(_, a), (_, b)| a.scale.total_cmp(&b.scale))
            .map(|(index, _)| index)
    }

    /// The lights with a radius, whose shadows are soft: bit i for light i, as the draws'
    /// `shadowing_lights` name them.
    pub fn soft_lights(&self) -> u32 {
        (self.lights.iter().enumerate()).filter(|(_, light)| light.radius > 0.0).fold(0, |bits, (i, _)| bits | 1 << i)
    }

    /// The ground (see [`Self::ground_index`]).
    pub fn ground(&self) -> Option<&Object> {
        self.ground_index().map(|index| &self.objects[index])
    }

    /// The ground that bounces the lights' light when `bounce` is on.
    pub fn bounce_ground(&self) -> Option<&Object> {
        self.ground().filter(|_| self.bounce)
    }

    /// Whether an object of mesh `extent` gathers the ground's bounce at its vertices
    /// (bounce.glsl) rather than at its pixels: where its longest edge is at most
    /// [`BOUNCE_VERTEX_EDGE_SHARE`] of its bounding radius, so that its triangles are small
    /// beside the object and the ground it stands over. A coarse mesh's large faces (a
    /// cube's) would stretch one gather at each corner over the shadow it casts below.
    pub fn bounce_at_vertices(extent: MeshExtent) -> bool {
        extent.longest_edge <= BOUNCE_VERTEX_EDGE_SHARE * extent.radius
    }

    /// The folder its relative paths are resolved against: its file's, else the working
    /// directory.
    pub fn folder(&self) -> &Path {
        self.source.as_deref().and_then(Path::parent).unwrap_or(Path::new(""))
    }

    /// Prints [`Scene::warnings`] to stderr, one line each.
    pub fn print_warnings(&self) {
        for warning in &self.warnings {
            eprintln!("argil: warning: {warning}");
        }
    }

    /// Reads, parses and validates a scene file; relative paths in it are
    /// resolved against the file's folder.
    ///
    /// A glTF model (`.gltf`, `.glb`) opens alone in the default scene's studio, framed
    /// (see `gltf::open`).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        Scene::load_with(path, BuiltinMaps::Now)
    }

    fn load_with(path: &Path, builtin_maps: BuiltinMaps) -> Result<Scene, SceneError> {
        // A model's maps are its own images, which load now.
        if gltf::is_model(path) {
            return gltf::open(path);
        }
        limits::check_file_size(path, limits::MAX_SCENE_BYTES, "scene files")?;
        let text = std::fs::read_to_string(path).map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        let base_dir = path.parent().unwrap_or(Path::new(""));
        let mut scene = Scene::from_toml_with(&text, &path.display().to_string(), base_dir, builtin_maps)?;
        scene.source = Some(path.to_path_buf());
        Ok(scene)
    }

    /// Parses and validates scene TOML. `origin` names the text in error
    /// messages; relative paths are resolved against `base_dir`.
    pub fn from_toml(text: &str, origin: &str, base_dir: &Path) -> Result<Scene, SceneError> {
        Scene::from_toml_with(text, origin, base_dir, BuiltinMaps::Now)
    }

    fn from_toml_with(
        text: &str,
        origin: &str,
        base_dir: &Path,
        builtin_maps: BuiltinMaps,
    ) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text).map_err(|error| SceneError::Toml {
            origin: origin.to_owned(),
            error,
        })?;
        resolve::resolve(&file, origin, base_dir, builtin_maps)
    }

    /// Validates a parsed scene file and loads its meshes.
    pub fn from_file(file: &SceneFile, origin: &str, base_dir: &Path) -> Result<Scene, SceneError> {
        resolve::resolve(file, origin, base_dir, BuiltinMaps::Now)
    }

    /// The embedded [`DEFAULT_SCENE_TOML`]: a blue plasticine ball and a
    /// terracotta ring on a pale ground, with builtin maps.
    pub fn default_scene() -> Scene {
        Scene::from_toml(DEFAULT_SCENE_TOML, "<default scene>", Path::new(""))
            .expect("the embedded default scene is valid (checked by the tests)")
    }

    /// The scene as a file for saving with `toml::to_string_pretty`. Paths
    /// inside the folder of [`Scene::source`] are written relative to it,
    /// others as they are; every object names its material explicitly.
    ///
    /// Materials are written with every field resolved (and their `preset`,
    /// for the record), so a saved scene keeps its look when presets are retuned.
    ///
    /// # Panics
    /// If an object's `mesh` or `material` index, or a map's `texture`
    /// index, is out of range.
    pub fn to_file(&self) -> SceneFile {
        resolve::to_file(self, self.source.as_deref())
    }

    /// [`Scene::to_file`] for a file saved at `path`: paths relative to its folder.
    pub fn to_file_at(&self, path: &Path) -> SceneFile {
        resolve::to_file(self, Some(path))
    }

    /// `document`, the text of a scene file, with this scene written into it for saving at
    /// `path`: comments, order and `preset` lines kept, only changed keys rewritten.
    pub fn edit_document(&self, document: &str, path: &Path) -> anyhow::Result<String> {
        edit::edit_document(self, document, path)
    }
}
