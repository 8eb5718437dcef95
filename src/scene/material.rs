use glam::{DVec2, Vec2};
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
    /// The map is sampled at [`MapRef::uv`]: the mesh's uv times `uv_scale`, turned
    /// `uv_rotation_degrees` counter-clockwise (v up the texture), plus `uv_offset`.
    pub uv_scale: Vec2,
    pub uv_offset: Vec2,
    pub uv_rotation_degrees: f32,
    /// The map's green channel points down the texture (DirectX convention)
    /// and must be negated; only ever set on normal and detail maps.
    pub green_down: bool,
}

impl MapRef {
    /// (cos, sin) of the uv's turn.
    pub fn uv_turn(&self) -> DVec2 {
        let (sin, cos) = f64::from(self.uv_rotation_degrees).to_radians().sin_cos();
        DVec2::new(cos, sin)
    }

    /// The map's uv at the mesh's `uv`; twin of `map_uv` in shaders/lib/material.glsl, whose
    /// turn is this one's in f32.
    pub fn uv(&self, uv: DVec2) -> DVec2 {
        let scaled = uv * self.uv_scale.as_dvec2();
        let turn = self.uv_turn();
        DVec2::new(turn.x * scaled.x - turn.y * scaled.y, turn.y * scaled.x + turn.x * scaled.y)
            + self.uv_offset.as_dvec2()
    }
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
