use std::path::PathBuf;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// An isotropic point light. Irradiance on a surface at distance d whose
/// normal makes angle θ with the light is `intensity · cosθ / d²`; with a
/// `radius`, a sphere of the same power, which casts soft shadows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity in W/sr, linear RGB.
    pub intensity: Vec3,
    /// Radius of the emitting sphere; 0 is a point.
    pub radius: f32,
    /// Whether objects shadow this light.
    pub shadows: bool,
}

impl PointLight {
    /// A point light (radius 0) that casts shadows, as a scene file's defaults give.
    pub fn new(position: Vec3, intensity: Vec3) -> Self {
        Self {
            position,
            intensity,
            radius: 0.0,
            shadows: true,
        }
    }
}

/// `[shadows] resolution`: the side of each face of a light's cube shadow map, in texels.
pub const DEFAULT_SHADOW_RESOLUTION: u32 = 1024;
/// The range `[shadows] resolution` accepts: below 16 texels a face resolves nothing, and
/// a 4096² cube is 400 MB of depth per light.
pub const SHADOW_RESOLUTION_RANGE: std::ops::RangeInclusive<u32> = 16..=4096;

/// `[shadows] taps`: a soft shadow's taps, as many in its blocker search as in its filter.
pub const DEFAULT_SHADOW_TAPS: u32 = 16;
/// The range `[shadows] taps` accepts: one tap is a hard shadow's lookup, and 64 (128
/// lookups a light and pixel) is past where more taps change a penumbra visibly.
pub const SHADOW_TAPS_RANGE: std::ops::RangeInclusive<u32> = 1..=64;

/// Light arriving from infinitely far away.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    None,
    /// Constant radiance from every direction, linear RGB.
    Uniform {
        radiance: Vec3,
        reflection: Reflection,
    },
    /// The procedural studio (soft boxes in a grey cyclorama), generated on the GPU.
    Studio {
        intensity: f32,
        rotation_degrees: f32,
        reflection: Reflection,
    },
    /// Equirectangular .hdr or .exr image, already resolved against the
    /// scene file's folder and checked to exist.
    Map {
        path: PathBuf,
        intensity: f32,
        rotation_degrees: f32,
        reflection: Reflection,
    },
}

impl Environment {
    /// How the environment lights surfaces; `None` has no light.
    pub fn reflection(&self) -> Option<&Reflection> {
        match self {
            Environment::None => None,
            Environment::Uniform { reflection, .. }
            | Environment::Studio { reflection, .. }
            | Environment::Map { reflection, .. } => Some(reflection),
        }
    }

    pub fn reflection_mut(&mut self) -> Option<&mut Reflection> {
        match self {
            Environment::None => None,
            Environment::Uniform { reflection, .. }
            | Environment::Studio { reflection, .. }
            | Environment::Map { reflection, .. } => Some(reflection),
        }
    }
}

/// How the environment's light reflected by a surface is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ReflectionMode {
    /// Prefiltered specular cube map × DFG table, diffuse from an irradiance cube (Karis 2013).
    #[default]
    SplitSum,
    /// The seed report's single lookup along the reflected direction (eq. 17).
    Seed,
    /// Importance-sampled environment lookups per pixel; converges to the true integral.
    Sampled,
}

/// A reflection mode with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflection {
    pub mode: ReflectionMode,
    /// Environment lookups per pixel for `Sampled`.
    pub samples: u32,
    /// Scale of the reflected lookup for `Seed`.
    pub seed_strength: f32,
}

impl Reflection {
    pub const DEFAULT_SAMPLES: u32 = 64;
    pub const MAX_SAMPLES: u32 = 4096;
    pub const DEFAULT_SEED_STRENGTH: f32 = 0.05;
}

impl Default for Reflection {
    fn default() -> Self {
        Self {
            mode: ReflectionMode::SplitSum,
            samples: Self::DEFAULT_SAMPLES,
            seed_strength: Self::DEFAULT_SEED_STRENGTH,
        }
    }
}
