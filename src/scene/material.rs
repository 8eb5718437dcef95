use glam::Vec2;
use serde::{Deserialize, Serialize};

pub use super::map_slots::{MapSlot, MaterialMaps};
pub use super::material_keys::Material;
pub use crate::brdf::shading::{DiffuseModel, Horizon, ShadingModels, SpecularModel};
pub use crate::brdf::specular::{Distribution, Geometry};
pub use crate::brdf::subsurface::Subsurface;

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
