use glam::Vec3;

pub use crate::brdf::shading::{DiffuseModel, ShadingModels, ShadingParams, SpecularModel};
pub use crate::brdf::specular::{Distribution, Geometry};

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

impl Material {
    /// The models this material selects, as the shaders' specialization constants see them.
    pub fn shading_models(&self) -> ShadingModels {
        ShadingModels {
            diffuse: self.diffuse,
            specular: self.specular,
            distribution: self.distribution,
            geometry: self.geometry,
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
        }
    }
}
