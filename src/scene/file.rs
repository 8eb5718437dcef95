//! The on-disk scene schema, exactly as written in TOML. It is resolved and
//! validated into a runtime [`Scene`](super::Scene) by `Scene::from_toml`, and
//! produced back from one by `Scene::to_file` for saving.
//!
//! Numbers are kept as f64, as TOML stores them, so that validation can
//! report a value exactly as written before it is narrowed to the
//! renderer's f32, and so that saved files print f32 values in their
//! shortest form (0.6, not 0.6000000238418579).

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::light::ReflectionMode;
pub use super::material_keys::MaterialDef;

/// A whole scene file. Every section is optional; validation rejects a scene
/// without objects.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    #[serde(default)]
    pub camera: CameraDef,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<LightDef>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadows: Option<ShadowsDef>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub antialiasing: Option<AntialiasingDef>,
    pub occlusion: Option<OcclusionDef>,
    #[serde(default)]
    pub environment: EnvironmentDef,
    #[serde(default)]
    pub objects: Vec<ObjectDef>,
    /// Sorted by name so saved files are stable.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialDef>,
}

/// A model or option as the file spells it (`"oren-nayar"`).
pub fn file_name<T: Serialize>(value: &T) -> String {
    match toml::Value::try_from(value) {
        Ok(toml::Value::String(s)) => s,
        _ => "?".to_owned(),
    }
}

impl SceneFile {
    /// The file as TOML, with one line per key (arrays inline).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        toml::to_string(self)
    }
}

/// `[camera]`: a right-handed, y-up perspective camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDef {
    pub position: [f64; 3],
    pub target: [f64; 3],
    /// Vertical field of view, in degrees.
    pub fov_y_degrees: f64,
}

impl Default for CameraDef {
    fn default() -> Self {
        Self {
            position: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            fov_y_degrees: 30.0,
        }
    }
}

/// One `[[lights]]` entry, selected by `kind`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightDef {
    Point {
        position: [f64; 3],
        /// Radiant intensity in W/sr, linear RGB.
        intensity: [f64; 3],
        /// Radius of the emitting sphere (absent: 0, a point).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius: Option<f64>,
        /// Whether objects shadow the light (absent: true).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        shadows: Option<bool>,
    },
}

/// `[shadows]`: settings of every light's shadow map.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShadowsDef {
    /// Texels on a side of each cube face (absent: 1024).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resolution: Option<u32>,
    /// Taps of a soft shadow's blocker search and of its filter (absent: 16).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub taps: Option<u32>,
    /// Whether the lights' light bounces off the ground onto the objects (absent: false).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bounce: Option<bool>,
    /// Whether the ground's shadows are read from a map over it (absent: true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_map: Option<bool>,
    /// Whether finely tessellated objects take their soft shadows at their vertices
    /// (absent: false).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_vertex: Option<bool>,
}

/// `[antialiasing]`: multisampling and specular anti-aliasing of the frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AntialiasingDef {
    /// Samples per pixel of the forward pass: 1, 2, 4 or 8 (absent: 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub msaa: Option<u32>,
    /// Specular lobes widened by the shading normal's variation over a pixel (absent: true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular: Option<bool>,
}

/// `[occlusion]`: ambient occlusion of the environment's light (absent keys: defaults).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OcclusionDef {
    /// Whether the pass runs (absent: false).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub enabled: Option<bool>,
    /// Search radius in world units (absent: 0.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Slice directions per pixel (absent: 4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slices: Option<u32>,
    /// Samples on each side of a slice (absent: 8).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps: Option<u32>,
    /// GTAO's multi-bounce fit on the diffuse visibility (absent: true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub multi_bounce: Option<bool>,
    /// Occlusion by the objects as spheres (absent: false).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub objects: Option<bool>,
    /// The objects' occlusion of the ground read from a map over it (absent: true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_map: Option<bool>,
    /// The objects' occlusion of each other computed at their vertices (absent: true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_vertex: Option<bool>,
}

/// `[environment]`, selected by `kind`. Optional keys are `None` when absent
/// (and are then not written back); see docs/scene-format.md for defaults.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum EnvironmentDef {
    #[default]
    None,
    /// Constant radiance from every direction, linear RGB.
    Uniform {
        radiance: [f64; 3],
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reflection: Option<ReflectionMode>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        samples: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        seed_strength: Option<f64>,
    },
    /// The procedural studio.
    Studio {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        intensity: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotation_degrees: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reflection: Option<ReflectionMode>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        samples: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        seed_strength: Option<f64>,
    },
    /// Equirectangular .hdr or .exr, relative to the scene file's folder.
    Map {
        path: PathBuf,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        intensity: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotation_degrees: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reflection: Option<ReflectionMode>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        samples: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        seed_strength: Option<f64>,
    },
}

impl EnvironmentDef {
    /// The keys of its reflection (`reflection`, `samples`, `seed_strength`), which every
    /// kind but `none` has.
    pub fn reflection_keys_mut(&mut self) -> Option<(&mut Option<ReflectionMode>, &mut Option<u32>, &mut Option<f64>)> {
        match self {
            EnvironmentDef::None => None,
            EnvironmentDef::Uniform {
                reflection,
                samples,
                seed_strength,
                ..
            }
            | EnvironmentDef::Studio {
                reflection,
                samples,
                seed_strength,
                ..
            }
            | EnvironmentDef::Map {
                reflection,
                samples,
                seed_strength,
                ..
            } => Some((reflection, samples, seed_strength)),
        }
    }
}

/// One `[[objects]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDef {
    /// `builtin:<name>`, or an .obj, .gltf or .glb path relative to the scene file's folder.
    pub mesh: String,
    #[serde(default)]
    pub position: [f64; 3],
    #[serde(default = "one")]
    pub scale: f64,
    /// A key of `[materials]`; absent means the built-in neutral material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// `builtin:sphere`: cells along each edge of its cube, absent meaning
    /// `SPHERE_SUBDIVISIONS`; `builtin:torus`: cells around its ring, absent meaning
    /// `TORUS_SUBDIVISIONS`; no other mesh has the key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subdivisions: Option<u32>,
}

fn one() -> f64 {
    1.0
}

/// A material map table such as `[materials.clay.normal_map]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapDef {
    /// An image path relative to the scene file's folder, or `builtin:<name>`.
    pub texture: String,
    pub strength: f64,
    pub uv_scale: [f64; 2],
    pub uv_offset: [f64; 2],
    /// Degrees the scaled uv turns counter-clockwise (v up) before the offset.
    pub uv_rotation_degrees: f64,
    /// Which way the green channel of a normal map points.
    pub green: Green,
}

impl MapDef {
    /// `texture` with every other key at its default.
    pub fn new(texture: impl Into<String>) -> MapDef {
        MapDef {
            texture: texture.into(),
            strength: 1.0,
            uv_scale: [1.0; 2],
            uv_offset: [0.0; 2],
            uv_rotation_degrees: 0.0,
            green: Green::Up,
        }
    }
}

/// The direction of +green in a normal map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Green {
    /// +v, up the texture (OpenGL convention).
    #[default]
    Up,
    /// -v (DirectX convention).
    Down,
}

/// A map table as written: `None` for an absent key.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MapKeys {
    texture: Option<String>,
    strength: Option<f64>,
    uv_scale: Option<[f64; 2]>,
    uv_offset: Option<[f64; 2]>,
    uv_rotation_degrees: Option<f64>,
    green: Option<Green>,
}

fn set<T>(field: &mut T, key: Option<T>) {
    if let Some(value) = key {
        *field = value;
    }
}

impl MapDef {
    /// The preset's map (if any) with the table's keys on top.
    pub(super) fn merge(name: &str, preset: Option<MapDef>, keys: Option<MapKeys>) -> Result<Option<MapDef>, String> {
        let Some(keys) = keys else {
            return Ok(preset);
        };
        let mut map = match (preset, keys.texture) {
            (Some(preset), None) => preset,
            (Some(preset), Some(texture)) => MapDef { texture, ..preset },
            (None, Some(texture)) => MapDef::new(texture),
            (None, None) => {
                return Err(format!(
                    "missing field `texture` in `{name}` (no preset supplies this map)"
                ))
            }
        };
        set(&mut map.strength, keys.strength);
        set(&mut map.uv_scale, keys.uv_scale);
        set(&mut map.uv_offset, keys.uv_offset);
        set(&mut map.uv_rotation_degrees, keys.uv_rotation_degrees);
        set(&mut map.green, keys.green);
        Ok(Some(map))
    }
}
