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
use super::material::{DiffuseModel, Distribution, Geometry, SpecularModel};

/// A whole scene file. Every section is optional; validation rejects a scene
/// without objects.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    #[serde(default)]
    pub camera: CameraDef,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<LightDef>,
    #[serde(default)]
    pub environment: EnvironmentDef,
    #[serde(default)]
    pub objects: Vec<ObjectDef>,
    /// Sorted by name so saved files are stable.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, MaterialDef>,
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
    },
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

/// One `[[objects]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDef {
    /// `builtin:<name>` or an .obj path relative to the scene file's folder.
    pub mesh: String,
    #[serde(default)]
    pub position: [f64; 3],
    #[serde(default = "one")]
    pub scale: f64,
    /// A key of `[materials]`; absent means the built-in neutral material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

fn one() -> f64 {
    1.0
}

/// One `[materials.<name>]` table; every field has a default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MaterialDef {
    pub base_color: [f64; 3],
    pub diffuse: DiffuseModel,
    pub specular: SpecularModel,
    pub distribution: Distribution,
    pub geometry: Geometry,
    pub roughness: f64,
    pub f0: f64,
    pub diffuse_roughness: f64,
    pub specular_color: [f64; 3],
    pub wrap: f64,
    pub wrap_width: f64,
    pub wrap_color: [f64; 3],
    pub wrap_intensity: f64,
}

impl Default for MaterialDef {
    /// Also the built-in neutral material: grey Lambert + GGX Cook-Torrance.
    fn default() -> Self {
        Self {
            base_color: [0.8; 3],
            diffuse: DiffuseModel::Lambert,
            specular: SpecularModel::CookTorrance,
            distribution: Distribution::Ggx,
            geometry: Geometry::SmithCorrelated,
            roughness: 0.5,
            f0: 0.04,
            diffuse_roughness: 0.0,
            specular_color: [1.0; 3],
            wrap: 0.0,
            wrap_width: 0.3,
            wrap_color: [1.0; 3],
            wrap_intensity: 0.0,
        }
    }
}
