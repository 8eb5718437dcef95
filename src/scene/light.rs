use std::path::PathBuf;

use glam::Vec3;

/// An isotropic point light. Irradiance on a surface at distance d whose
/// normal makes angle θ with the light is `intensity · cosθ / d²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity in W/sr, linear RGB.
    pub intensity: Vec3,
}

/// Light arriving from infinitely far away.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    None,
    /// Constant radiance from every direction, linear RGB.
    Uniform {
        radiance: Vec3,
    },
    /// Equirectangular .hdr or .exr image, already resolved against the
    /// scene file's folder and checked to exist.
    Map {
        path: PathBuf,
    },
}
