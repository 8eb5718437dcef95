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
use super::material::{DetailBlend, DiffuseModel, Distribution, Geometry, Horizon, SpecularModel, Subsurface};
use super::preset::Preset;

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
    /// `builtin:sphere` only: cells along each edge of its cube; absent means
    /// `SPHERE_SUBDIVISIONS`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subdivisions: Option<u32>,
}

fn one() -> f64 {
    1.0
}

/// One `[materials.<name>]` table: its `preset`'s values (or the defaults
/// below, without one) with the keys written in the table on top, merged key
/// by key, also inside the map tables. Unknown keys are errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MaterialKeys")]
pub struct MaterialDef {
    /// The preset the table started from. Every other field already holds
    /// the merged values, so writing it back is informational:
    /// `Scene::to_file` leaves it out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
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
    pub subsurface: Subsurface,
    pub scatter_color: [f64; 3],
    pub scatter_radius: f64,
    pub horizon: Horizon,
    pub detail_blend: DetailBlend,
    // Tables last: TOML writes them after the plain keys.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_color_map: Option<MapDef>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_map: Option<MapDef>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detail_map: Option<MapDef>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_map: Option<MapDef>,
}

impl Default for MaterialDef {
    /// Also the built-in neutral material: grey Lambert + GGX Cook-Torrance,
    /// no maps.
    fn default() -> Self {
        Self {
            preset: None,
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
            subsurface: Subsurface::Seed,
            scatter_color: [1.0; 3],
            scatter_radius: 0.0,
            horizon: Horizon::Smooth,
            detail_blend: DetailBlend::Rnm,
            base_color_map: None,
            normal_map: None,
            detail_map: None,
            noise_map: None,
        }
    }
}

/// A material map table such as `[materials.clay.normal_map]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapDef {
    /// An image path relative to the scene file's folder, or `builtin:<name>`.
    pub texture: String,
    pub strength: f64,
    pub uv_scale: [f64; 2],
    pub uv_offset: [f64; 2],
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

/// A material table as written: `None` for an absent key, so that the
/// preset's value survives it. Deserialised straight from the document, so
/// toml's errors keep their line and column.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialKeys {
    preset: Option<Preset>,
    base_color: Option<[f64; 3]>,
    diffuse: Option<DiffuseModel>,
    specular: Option<SpecularModel>,
    distribution: Option<Distribution>,
    geometry: Option<Geometry>,
    roughness: Option<f64>,
    f0: Option<f64>,
    diffuse_roughness: Option<f64>,
    specular_color: Option<[f64; 3]>,
    wrap: Option<f64>,
    wrap_width: Option<f64>,
    wrap_color: Option<[f64; 3]>,
    wrap_intensity: Option<f64>,
    subsurface: Option<Subsurface>,
    scatter_color: Option<[f64; 3]>,
    scatter_radius: Option<f64>,
    horizon: Option<Horizon>,
    detail_blend: Option<DetailBlend>,
    base_color_map: Option<MapKeys>,
    normal_map: Option<MapKeys>,
    detail_map: Option<MapKeys>,
    noise_map: Option<MapKeys>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MapKeys {
    texture: Option<String>,
    strength: Option<f64>,
    uv_scale: Option<[f64; 2]>,
    uv_offset: Option<[f64; 2]>,
    green: Option<Green>,
}

impl TryFrom<MaterialKeys> for MaterialDef {
    type Error = String;

    fn try_from(keys: MaterialKeys) -> Result<MaterialDef, String> {
        let mut def = keys.preset.map_or_else(MaterialDef::default, Preset::material);
        def.preset = keys.preset;
        set(&mut def.base_color, keys.base_color);
        set(&mut def.diffuse, keys.diffuse);
        set(&mut def.specular, keys.specular);
        set(&mut def.distribution, keys.distribution);
        set(&mut def.geometry, keys.geometry);
        set(&mut def.roughness, keys.roughness);
        set(&mut def.f0, keys.f0);
        set(&mut def.diffuse_roughness, keys.diffuse_roughness);
        set(&mut def.specular_color, keys.specular_color);
        set(&mut def.wrap, keys.wrap);
        set(&mut def.wrap_width, keys.wrap_width);
        set(&mut def.wrap_color, keys.wrap_color);
        set(&mut def.wrap_intensity, keys.wrap_intensity);
        set(&mut def.subsurface, keys.subsurface);
        set(&mut def.scatter_color, keys.scatter_color);
        set(&mut def.scatter_radius, keys.scatter_radius);
        set(&mut def.horizon, keys.horizon);
        set(&mut def.detail_blend, keys.detail_blend);
        def.base_color_map = merge_map("base_color_map", def.base_color_map, keys.base_color_map)?;
        def.normal_map = merge_map("normal_map", def.normal_map, keys.normal_map)?;
        def.detail_map = merge_map("detail_map", def.detail_map, keys.detail_map)?;
        def.noise_map = merge_map("noise_map", def.noise_map, keys.noise_map)?;
        Ok(def)
    }
}

fn set<T>(field: &mut T, key: Option<T>) {
    if let Some(value) = key {
        *field = value;
    }
}

/// The preset's map (if any) with the table's keys on top.
fn merge_map(name: &str, preset: Option<MapDef>, keys: Option<MapKeys>) -> Result<Option<MapDef>, String> {
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
    set(&mut map.green, keys.green);
    Ok(Some(map))
}
