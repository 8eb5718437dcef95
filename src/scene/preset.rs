//! Material presets: complete, documented parameter sets for kinds of clay,
//! selected with `preset = "…"` in a material table (docs/scene-format.md
//! has the table and the reasons).

use serde::{Deserialize, Serialize};

use super::file::{MapDef, MaterialDef};
use super::material::{DetailBlend, DiffuseModel, Distribution, Geometry, Horizon, SpecularModel, Subsurface};

/// A kind of clay whose look a material can start from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    Plasticine,
    Terracotta,
    WetClay,
    PolymerClay,
    /// Not clay: the aluminium wire armature inside a figure, where it shows.
    MetalArmature,
}

impl Preset {
    pub const ALL: [Preset; 5] = [
        Preset::Plasticine,
        Preset::Terracotta,
        Preset::WetClay,
        Preset::PolymerClay,
        Preset::MetalArmature,
    ];

    /// Every field of the preset. UV scales suit the builtin sphere as a
    /// ball 6 cm across: u runs around it (2π units) and v from pole to pole
    /// (π units), so `[2k, k]` keeps texels square, and `[6, 3]` makes the
    /// 3 cm fingerprint map life-size.
    pub fn material(self) -> MaterialDef {
        let map = |texture: &str, strength: f64, uv_scale: [f64; 2]| {
            Some(MapDef {
                strength,
                uv_scale,
                ..MapDef::new(texture)
            })
        };
        // What every clay shares: a GGX Cook-Torrance highlight of white specular colour,
        // RNM detail blending, the smooth horizon and no base colour map.
        let clay = MaterialDef {
            preset: Some(self),
            specular: SpecularModel::CookTorrance,
            distribution: Distribution::Ggx,
            geometry: Geometry::SmithCorrelated,
            specular_color: [1.0; 3],
            detail_blend: DetailBlend::Rnm,
            horizon: Horizon::Smooth,
            base_color_map: None,
            ..MaterialDef::default()
        };
        match self {
            Preset::Plasticine => MaterialDef {
                base_color: [0.6, 0.36, 0.17],
                diffuse: DiffuseModel::Eon,
                diffuse_roughness: 0.5,
                roughness: 0.6,
                f0: 0.04,
                wrap: 0.3,
                wrap_width: 0.4,
                wrap_color: [0.9, 0.35, 0.15],
                wrap_intensity: 0.3,
                subsurface: Subsurface::PreIntegrated,
                scatter_color: [1.0, 0.5, 0.3],
                scatter_radius: 0.2,
                normal_map: map("builtin:clay-lumps", 0.6, [4.0, 2.0]),
                detail_map: map("builtin:fingerprints", 0.7, [6.0, 3.0]),
                noise_map: map("builtin:noise", 0.5, [2.0, 1.0]),
                ..clay
            },
            Preset::Terracotta => MaterialDef {
                base_color: [0.58, 0.22, 0.1],
                diffuse: DiffuseModel::OrenNayar,
                diffuse_roughness: 0.8,
                roughness: 0.9,
                f0: 0.03,
                wrap: 0.0,
                wrap_width: 0.3,
                wrap_color: [1.0; 3],
                wrap_intensity: 0.0,
                subsurface: Subsurface::None,
                scatter_color: [1.0; 3],
                scatter_radius: 0.0,
                normal_map: map("builtin:clay-lumps", 0.3, [8.0, 4.0]),
                detail_map: None,
                noise_map: map("builtin:noise", 0.3, [2.0, 1.0]),
                ..clay
            },
            Preset::WetClay => MaterialDef {
                base_color: [0.2, 0.12, 0.07],
                diffuse: DiffuseModel::Eon,
                diffuse_roughness: 0.3,
                roughness: 0.3,
                f0: 0.02,
                wrap: 0.5,
                wrap_width: 0.5,
                wrap_color: [0.6, 0.3, 0.15],
                wrap_intensity: 0.5,
                subsurface: Subsurface::EnergyConservingWrap,
                scatter_color: [1.0, 0.7, 0.5],
                scatter_radius: 0.0,
                normal_map: map("builtin:clay-lumps", 0.8, [3.0, 1.5]),
                detail_map: None,
                noise_map: map("builtin:noise", 0.7, [2.0, 1.0]),
                ..clay
            },
            Preset::PolymerClay => MaterialDef {
                base_color: [0.1, 0.24, 0.5],
                diffuse: DiffuseModel::Eon,
                diffuse_roughness: 0.3,
                roughness: 0.4,
                f0: 0.04,
                wrap: 0.25,
                wrap_width: 0.3,
                wrap_color: [0.2, 0.35, 0.9],
                wrap_intensity: 0.2,
                subsurface: Subsurface::PreIntegrated,
                scatter_color: [0.35, 0.6, 1.0],
                scatter_radius: 0.3,
                normal_map: map("builtin:clay-lumps", 0.25, [8.0, 4.0]),
                detail_map: map("builtin:fingerprints", 0.4, [6.0, 3.0]),
                noise_map: map("builtin:noise", 0.4, [2.0, 1.0]),
                ..clay
            },
            // The defaults' Lambert lobe and wrap and scatter keys, all unused by a metal.
            Preset::MetalArmature => MaterialDef {
                base_color: [0.913, 0.922, 0.924],
                metallic: 1.0,
                roughness: 0.35,
                subsurface: Subsurface::None,
                normal_map: map("builtin:clay-lumps", 0.1, [8.0, 4.0]),
                detail_map: None,
                noise_map: map("builtin:noise", 0.2, [2.0, 1.0]),
                ..clay
            },
        }
    }
}
