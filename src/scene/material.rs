use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use super::Preset;

pub use crate::brdf::shading::{DiffuseModel, Horizon, ShadingModels, ShadingParams, SpecularModel};
pub use crate::brdf::specular::{Distribution, Geometry};
pub use crate::brdf::subsurface::Subsurface;

/// A validated material; see docs/scene-format.md for the meaning and range
/// of each field.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// The preset the file's table starts from; its other fields are already merged in.
    pub preset: Option<Preset>,
    /// Linear RGB albedo.
    pub base_color: Vec3,
    pub diffuse: DiffuseModel,
    pub specular: SpecularModel,
    pub distribution: Distribution,
    pub geometry: Geometry,
    /// Perceptual roughness; the microfacet alpha is `roughness²`.
    pub roughness: f32,
    /// Schlick reflectance at normal incidence.
    pub f0: f32,
    pub diffuse_roughness: f32,
    pub specular_color: Vec3,
    /// The report's wrap lighting (`Subsurface::Seed`): w₁, w₂, colour and intensity;
    /// `wrap` is also the energy-conserving wrap's w.
    pub wrap: f32,
    pub wrap_width: f32,
    pub wrap_color: Vec3,
    pub wrap_intensity: f32,
    pub subsurface: Subsurface,
    /// Per-channel reach of the energy-conserving wrap and the pre-integrated model.
    pub scatter_color: Vec3,
    /// The pre-integrated model's diffusion σ, in scene units, at scatter_color 1.
    pub scatter_radius: f32,
    /// Treatment of the shading normal\'s horizon.
    pub horizon: Horizon,
    pub maps: MaterialMaps,
}

impl Material {
    /// The models this material selects, as the shaders' specialization constants see them.
    pub fn shading_models(&self) -> ShadingModels {
        ShadingModels {
            diffuse: self.diffuse,
            specular: self.specular,
            distribution: self.distribution,
            geometry: self.geometry,
            subsurface: self.subsurface,
        }
    }

    /// The parameters in f64, for the reference models in `crate::brdf`.
    pub fn shading_params(&self) -> ShadingParams {
        let rgb = |c: Vec3| c.as_dvec3().to_array();
        ShadingParams {
            base_color: rgb(self.base_color),
            specular_color: rgb(self.specular_color),
            wrap_color: rgb(self.wrap_color),
            wrap_intensity: f64::from(self.wrap_intensity),
            roughness: f64::from(self.roughness),
            f0: f64::from(self.f0),
            diffuse_roughness: f64::from(self.diffuse_roughness),
            wrap: f64::from(self.wrap),
            wrap_width: f64::from(self.wrap_width),
            scatter_color: rgb(self.scatter_color),
            scatter_radius: f64::from(self.scatter_radius),
        }
    }
}

/// The textures a material samples; see docs/scene-format.md.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialMaps {
    /// Multiplies `base_color`: `base_color · mix(1, map, strength)`.
    pub base_color: Option<MapRef>,
    /// Tangent-space surface normals; `strength` scales their xy.
    pub normal: Option<MapRef>,
    /// A second normal map (fingerprints) blended over `normal`.
    pub detail: Option<MapRef>,
    /// Modulates reflections.
    pub noise: Option<MapRef>,
    pub detail_blend: DetailBlend,
}

/// One map of a material: a texture and how it is applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapRef {
    /// Index into [`Scene::textures`](super::Scene::textures).
    pub texture: usize,
    /// In [0, 8].
    pub strength: f32,
    /// The map is sampled at `uv · uv_scale + uv_offset`.
    pub uv_scale: Vec2,
    pub uv_offset: Vec2,
    /// The map's green channel points down the texture (DirectX convention)
    /// and must be negated; only ever set on normal and detail maps.
    pub green_down: bool,
}

/// How the detail normal map is combined with the normal map. `as u32` is
/// a shader specialization constant: never renumber.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum DetailBlend {
    /// Reoriented Normal Mapping: the detail map is rotated onto the base
    /// normal, as if the detail were carved into the base surface.
    #[default]
    Rnm = 0,
    /// Unreal Developer Network: the xy of both are added, z is the base's.
    Udn = 1,
    /// Whiteout: xy added, z multiplied.
    Whiteout = 2,
    /// The clay-appearance report's eq. 16.
    Seed = 3,
}
