use glam::Vec3;
use serde::{Deserialize, Serialize};

// The `as u32` values of these enums are shader specialization constants:
// never reorder or renumber the variants.

/// Diffuse lobe. `diffuse_roughness` is sigma in radians for Oren-Nayar and
/// the roughness r of EON (energy-preserving Oren-Nayar).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum DiffuseModel {
    #[default]
    Lambert = 0,
    OrenNayar = 1,
    Eon = 2,
    None = 3,
}

/// Specular lobe.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum SpecularModel {
    #[default]
    CookTorrance = 0,
    TorranceSparrow = 1,
    BlinnPhong = 2,
    None = 3,
}

/// Microfacet normal distribution of the specular lobe.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Distribution {
    #[default]
    Ggx = 0,
    Beckmann = 1,
}

/// Smith masking-shadowing form of the specular lobe.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Geometry {
    #[default]
    SmithCorrelated = 0,
    SmithSeparable = 1,
}

/// A validated material; see docs/scene-format.md for the meaning and range
/// of each field.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
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
    /// Wrap-lighting subsurface approximation; 0 disables it.
    pub wrap: f32,
    pub wrap_width: f32,
    pub wrap_color: Vec3,
    pub wrap_intensity: f32,
}
