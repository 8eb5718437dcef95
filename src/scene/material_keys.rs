//! Every material key declared once: its name, type and range, default, one-sentence
//! documentation, panel label and widget, and where the GPU and the f64 models read it.
//! The file schema (`MaterialDef` and the preset merge), the runtime `Material`, validation
//! and its error text, saving, the viewer's material panel and the GPU packing are all
//! generated from [`material_keys!`]'s one table below; `shaders/lib/material.glsl` is
//! checked against it by a test in `render/gpu_scene.rs`.

use std::fmt::Debug;
use std::ops::RangeInclusive;

use glam::Vec3;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::file::{MapDef, MapKeys};
use super::map_slots::{with_map_slots, MapSlot};
use super::preset::Preset;
use super::resolve::widen;
use super::{DetailBlend, DiffuseModel, Distribution, Geometry, Horizon, MapRef, MaterialMaps, SceneError};
use super::{SpecularModel, Subsurface};
use crate::brdf::shading::ShadingParams;
use crate::render::material_data::MaterialData;

/// A key's name as the file spells it, its panel label, and its documentation sentence
/// (the panel's tooltip), with how it is typed and when the panel shows it.
pub struct Key<K> {
    pub name: &'static str,
    pub label: &'static str,
    pub doc: &'static str,
    pub kind: K,
    /// Whether the key matters under the material's models (the panel shows only those).
    pub shown: fn(&Material) -> bool,
}

impl<K> Key<K> {
    /// The tooltip: the file's key and its documentation.
    pub fn tip(&self) -> String {
        format!("{}: {}", self.name, self.doc)
    }
}

/// How a kind of key is written, validated, saved and edited.
pub trait Kind {
    /// As written in the file.
    type File: Clone + Debug + PartialEq + Serialize + DeserializeOwned;
    /// As the renderer holds it.
    type Value: Copy + Debug + PartialEq;
    /// The value narrowed, or why it is refused (the end of the error message).
    fn check(&self, x: &Self::File) -> Result<Self::Value, String>;
    /// The value as saved: f32s in their shortest decimal form.
    fn save(&self, v: &Self::Value) -> Self::File;
    fn edit<'a>(&self, v: &'a mut Self::Value) -> Edit<'a>;
}

/// A number in `[low, high]` (`(low, high]` when `low_open`; no upper bound without `high`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scalar {
    pub low: f32,
    pub low_open: bool,
    pub high: Option<f32>,
    /// The panel slider's range, inside the valid one.
    pub slider: (f32, f32),
}

impl Scalar {
    pub const UNIT: Scalar = Scalar::closed(0.0, 1.0);

    pub const fn closed(low: f32, high: f32) -> Scalar {
        Scalar {
            low,
            low_open: false,
            high: Some(high),
            slider: (low, high),
        }
    }

    /// ≥ 0, with a slider up to `slider_high`.
    pub const fn non_negative(slider_high: f32) -> Scalar {
        Scalar {
            low: 0.0,
            low_open: false,
            high: None,
            slider: (0.0, slider_high),
        }
    }

    /// > 0, with a slider over `slider`.
    pub const fn positive(slider: (f32, f32)) -> Scalar {
        Scalar {
            low: 0.0,
            low_open: true,
            high: None,
            slider,
        }
    }

    /// A slider narrower than the valid range.
    pub const fn slider(self, low: f32, high: f32) -> Scalar {
        Scalar {
            slider: (low, high),
            ..self
        }
    }

    pub fn contains(&self, x: f32) -> bool {
        let above = if self.low_open { x > self.low } else { x >= self.low };
        x.is_finite() && above && self.high.is_none_or(|high| x <= high)
    }

    pub fn slider_range(&self) -> RangeInclusive<f32> {
        self.slider.0..=self.slider.1
    }

    /// What a valid value is, as error messages say it.
    pub fn reason(&self) -> String {
        let open = if self.low_open { '(' } else { '[' };
        match self.high {
            Some(high) => format!("must be a finite number in {open}{}, {}]", limit(self.low), limit(high)),
            None if self.low_open => format!("must be a finite number > {}", limit(self.low)),
            None => format!("must be a finite number >= {}", limit(self.low)),
        }
    }
}

/// A limit as error messages print it: `8`, `10000`, `1e6`.
pub fn limit(x: f32) -> String {
    if x.abs() >= 1e5 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl Kind for Scalar {
    type File = f64;
    type Value = f32;

    /// Checked on the narrowed value, so a number too large for f32 is not finite and one
    /// too small for it is zero.
    fn check(&self, x: &f64) -> Result<f32, String> {
        let narrowed = *x as f32;
        self.contains(narrowed).then_some(narrowed).ok_or_else(|| self.reason())
    }

    fn save(&self, v: &f32) -> f64 {
        widen(*v)
    }

    fn edit<'a>(&self, v: &'a mut f32) -> Edit<'a> {
        Edit::Number(v, self.slider_range())
    }
}

/// A linear RGB colour, each component ≥ 0 (and ≤ 1 when `unit`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb {
    pub unit: bool,
}

impl Kind for Rgb {
    type File = [f64; 3];
    type Value = Vec3;

    fn check(&self, x: &[f64; 3]) -> Result<Vec3, String> {
        let narrowed = Vec3::from(x.map(|c| c as f32));
        let component = if self.unit {
            Scalar::UNIT
        } else {
            Scalar::non_negative(1.0)
        };
        if narrowed.to_array().into_iter().all(|c| component.contains(c)) {
            Ok(narrowed)
        } else {
            Err(format!("every component {}", component.reason()))
        }
    }

    fn save(&self, v: &Vec3) -> [f64; 3] {
        v.to_array().map(widen)
    }

    fn edit<'a>(&self, v: &'a mut Vec3) -> Edit<'a> {
        let high = if self.unit { 1.0 } else { f32::INFINITY };
        Edit::Color(v, 0.0..=high)
    }
}

/// One of a model enum's values, spelled as serde spells it; `options` in the panel's order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Choice<E: 'static>(pub &'static [E]);

impl<E> Kind for Choice<E>
where
    E: Copy + Debug + PartialEq + Serialize + DeserializeOwned + 'static,
{
    type File = E;
    type Value = E;

    fn check(&self, x: &E) -> Result<E, String> {
        Ok(*x)
    }

    fn save(&self, v: &E) -> E {
        *v
    }

    fn edit<'a>(&self, v: &'a mut E) -> Edit<'a> {
        Edit::Choice(Box::new(Chooser {
            value: v,
            options: self.0,
        }))
    }
}

/// `true` or `false`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flag;

impl Kind for Flag {
    type File = bool;
    type Value = bool;

    fn check(&self, x: &bool) -> Result<bool, String> {
        Ok(*x)
    }

    fn save(&self, v: &bool) -> bool {
        *v
    }

    fn edit<'a>(&self, v: &'a mut bool) -> Edit<'a> {
        Edit::Toggle(v)
    }
}

/// What the panel edits for one key.
pub enum Edit<'a> {
    /// A slider over the range.
    Number(&'a mut f32, RangeInclusive<f32>),
    /// With its components' range.
    Color(&'a mut Vec3, RangeInclusive<f32>),
    Choice(Box<dyn Choose + 'a>),
    /// A checkbox.
    Toggle(&'a mut bool),
}

/// A model choice with its options' file names.
pub trait Choose {
    fn names(&self) -> Vec<String>;
    fn selected(&self) -> Option<usize>;
    fn select(&mut self, index: usize);
}

struct Chooser<'a, E: 'static> {
    value: &'a mut E,
    options: &'static [E],
}

impl<E: Copy + PartialEq + Serialize> Choose for Chooser<'_, E> {
    fn names(&self) -> Vec<String> {
        self.options.iter().map(super::file::file_name).collect()
    }

    fn selected(&self) -> Option<usize> {
        self.options.iter().position(|o| o == self.value)
    }

    fn select(&mut self, index: usize) {
        if let Some(&option) = self.options.get(index) {
            *self.value = option;
        }
    }
}

/// Packs a key's value into its `MaterialData` field.
trait Pack<Slot: ?Sized> {
    fn pack(&self, slot: &mut Slot);
}

impl Pack<f32> for f32 {
    fn pack(&self, slot: &mut f32) {
        *slot = *self;
    }
}

/// A flag as the shaders read it: 1 or 0.
impl Pack<f32> for bool {
    fn pack(&self, slot: &mut f32) {
        *slot = f32::from(u8::from(*self));
    }
}

impl Pack<[f32]> for Vec3 {
    fn pack(&self, slot: &mut [f32]) {
        slot[..3].copy_from_slice(&self.to_array());
    }
}

/// Declares the material keys. Each entry is
/// `name: Kind = kind, default: value, label: "…", doc: "…", shown: |m| …`, then
/// `gpu: field[…]` (the `MaterialData` field or components it is packed into) and
/// `twin` (the key is a field of the f64 models' `ShadingParams`) for the numbers the
/// shaders read. Order is the file's order (saving, errors) and the panel's.
macro_rules! material_keys {
    (maps: [$($map_slot:ident { key: $map:ident, $($map_info:tt)* },)+]
    $(
        $name:ident: $kind:ty = $kind_value:expr,
        default: $default:expr,
        label: $label:literal,
        doc: $doc:literal,
        shown: $shown:expr
        $(, gpu: [$($slot:tt)+])?
        $(, twin: $twin:ident)?
        ;
    )+) => {
        /// The declarations, by key name.
        #[allow(non_upper_case_globals)]
        pub mod keys {
            use super::*;
            $(
                pub const $name: Key<$kind> = Key {
                    name: stringify!($name),
                    label: $label,
                    doc: $doc,
                    kind: $kind_value,
                    shown: $shown,
                };
            )+
        }

        /// Every key's name, in order.
        pub const KEY_NAMES: &[&str] = &[$(stringify!($name)),+];

        /// One `[materials.<name>]` table: its `preset`'s values (or the defaults, without
        /// one) with the keys written in the table on top, merged key by key, also inside
        /// the map tables. Unknown keys are errors.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(try_from = "MaterialKeys")]
        pub struct MaterialDef {
            /// The preset the table started from. Every other field already holds the
            /// merged values, so writing it back is informational: `Scene::to_file` leaves
            /// it out.
            #[serde(skip_serializing_if = "Option::is_none")]
            pub preset: Option<Preset>,
            $(
                #[doc = $doc]
                pub $name: <$kind as Kind>::File,
            )+
            // Tables last: TOML writes them after the plain keys.
            $(
                #[serde(skip_serializing_if = "Option::is_none")]
                pub $map: Option<MapDef>,
            )+
        }

        impl MaterialDef {
            /// The table of one map slot.
            pub fn map_mut(&mut self, slot: MapSlot) -> &mut Option<MapDef> {
                match slot {
                    $(MapSlot::$map_slot => &mut self.$map,)+
                }
            }

            pub fn map(&self, slot: MapSlot) -> &Option<MapDef> {
                match slot {
                    $(MapSlot::$map_slot => &self.$map,)+
                }
            }
        }

        impl Default for MaterialDef {
            /// Also the built-in neutral material: grey Lambert + GGX Cook-Torrance, no maps.
            fn default() -> Self {
                Self {
                    preset: None,
                    $($name: $default,)+
                    $($map: None,)+
                }
            }
        }

        /// A material table as written: `None` for an absent key, so that the preset's
        /// value survives it. Deserialised straight from the document, so toml's errors
        /// keep their line and column.
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct MaterialKeys {
            preset: Option<Preset>,
            $($name: Option<<$kind as Kind>::File>,)+
            $($map: Option<MapKeys>,)+
        }

        impl TryFrom<MaterialKeys> for MaterialDef {
            type Error = String;

            fn try_from(keys: MaterialKeys) -> Result<MaterialDef, String> {
                let mut def = keys.preset.map_or_else(MaterialDef::default, Preset::material);
                def.preset = keys.preset;
                $(
                    if let Some(value) = keys.$name {
                        def.$name = value;
                    }
                )+
                $(def.$map = MapDef::merge(stringify!($map), def.$map, keys.$map)?;)+
                Ok(def)
            }
        }

        /// A validated material; see docs/scene-format.md for the meaning and range of
        /// each field.
        #[derive(Clone, Debug, PartialEq)]
        pub struct Material {
            pub name: String,
            /// The preset the file's table starts from; its other fields are already merged in.
            pub preset: Option<Preset>,
            $(
                #[doc = $doc]
                pub $name: <$kind as Kind>::Value,
            )+
            pub maps: MaterialMaps,
        }

        impl Material {
            /// `def` validated; `invalid(key, value, reason)` makes the error of a key and
            /// `maps` checks the map tables, after the keys so that errors come in the
            /// order of the documented keys.
            pub(super) fn resolve(
                name: &str,
                def: &MaterialDef,
                invalid: impl Fn(&str, &dyn Debug, String) -> SceneError,
                maps: impl FnOnce() -> Result<MaterialMaps, SceneError>,
            ) -> Result<Material, SceneError> {
                Ok(Material {
                    name: name.to_owned(),
                    preset: def.preset,
                    $(
                        $name: keys::$name
                            .kind
                            .check(&def.$name)
                            .map_err(|reason| invalid(stringify!($name), &def.$name, reason))?,
                    )+
                    maps: maps()?,
                })
            }

            /// The material as saved, with `map` writing each map table.
            pub(super) fn to_def(&self, map: impl Fn(&Option<MapRef>) -> Option<MapDef>) -> MaterialDef {
                MaterialDef {
                    preset: self.preset,
                    $($name: keys::$name.kind.save(&self.$name),)+
                    $($map: map(&self.maps[MapSlot::$map_slot]),)+
                }
            }

            /// The parameters in f64, for the reference models in `crate::brdf`.
            pub fn shading_params(&self) -> ShadingParams {
                ShadingParams {
                    $($($twin: Twin::twin(&self.$name),)?)+
                }
            }

            /// The keys the shaders read, packed into their `MaterialData` fields.
            pub(crate) fn pack(&self, data: &mut MaterialData) {
                $($(Pack::pack(&self.$name, &mut data.$($slot)+);)?)+
            }

            /// Every key the material's models use, in order, with what the panel edits.
            pub fn edits(&mut self) -> Vec<(KeyInfo, Edit<'_>)> {
                let shown = [$((keys::$name.shown)(&*self)),+];
                let edits = [$((
                    KeyInfo { name: keys::$name.name, label: keys::$name.label, tip: keys::$name.tip() },
                    keys::$name.kind.edit(&mut self.$name),
                )),+];
                edits.into_iter().zip(shown).filter_map(|(edit, shown)| shown.then_some(edit)).collect()
            }
        }

        /// The GPU fields the keys are packed into, as written after `gpu:`, for the test
        /// against `shaders/lib/material.glsl`.
        #[cfg(test)]
        pub const GPU_SLOTS: &[(&str, &str)] = &[$($((stringify!($name), stringify!($($slot)+)),)?)+];
    };
}

/// A key's panel label and tooltip.
pub struct KeyInfo {
    pub name: &'static str,
    pub label: &'static str,
    pub tip: String,
}

/// A key's value as the f64 models take it.
trait Twin<T> {
    fn twin(&self) -> T;
}

impl Twin<f64> for f32 {
    fn twin(&self) -> f64 {
        f64::from(*self)
    }
}

impl Twin<[f64; 3]> for Vec3 {
    fn twin(&self) -> [f64; 3] {
        self.as_dvec3().to_array()
    }
}

const DIFFUSE_MODELS: [DiffuseModel; 4] = [
    DiffuseModel::Lambert,
    DiffuseModel::OrenNayar,
    DiffuseModel::Eon,
    DiffuseModel::None,
];
const SPECULAR_MODELS: [SpecularModel; 4] = [
    SpecularModel::CookTorrance,
    SpecularModel::TorranceSparrow,
    SpecularModel::BlinnPhong,
    SpecularModel::None,
];
const SUBSURFACE_MODELS: [Subsurface; 4] = [
    Subsurface::None,
    Subsurface::Seed,
    Subsurface::EnergyConservingWrap,
    Subsurface::PreIntegrated,
];

/// Largest scatter radius, in scene units: far beyond any object, so the pre-integrated
/// model is already uniform (t = σκ ≫ 1) there; it keeps σκ finite in fp32.
const MAX_SCATTER_RADIUS: f32 = 1e6;

/// A map's `strength`.
pub const MAP_STRENGTH: Scalar = Scalar::closed(0.0, 8.0);

/// Largest |uv_scale| component: beyond it a map repeats more often than
/// texels can be told apart even on a 16384² texture.
pub const MAX_UV_SCALE: f32 = 1e4;

fn has_specular(m: &Material) -> bool {
    m.specular != SpecularModel::None
}

fn seed_wrap(m: &Material) -> bool {
    m.subsurface == Subsurface::Seed
}

with_map_slots!(material_keys {
    base_color: Rgb = Rgb { unit: false },
        default: [0.8; 3],
        label: "base colour",
        doc: "the diffuse albedo, linear RGB",
        shown: |m| m.diffuse != DiffuseModel::None,
        gpu: [base_color[..]],
        twin: base_color;
    diffuse: Choice<DiffuseModel> = Choice(&DIFFUSE_MODELS),
        default: DiffuseModel::Lambert,
        label: "diffuse model",
        doc: "Lambert (the report's eq. 3), Oren-Nayar (eq. 4, Oren & Nayar 1994), EON \
              (energy-preserving Oren-Nayar, Portsmouth et al. 2025) or none",
        shown: |_| true;
    specular: Choice<SpecularModel> = Choice(&SPECULAR_MODELS),
        default: SpecularModel::CookTorrance,
        label: "specular model",
        doc: "Cook-Torrance (eq. 7, Cook & Torrance 1982), Torrance-Sparrow (eq. 6), \
              Blinn-Phong (eq. 5) or none",
        shown: |_| true;
    distribution: Choice<Distribution> = Choice(&[Distribution::Ggx, Distribution::Beckmann]),
        default: Distribution::Ggx,
        label: "distribution",
        doc: "the microfacet normals, GGX (Walter et al. 2007) or Beckmann (eq. 8)",
        shown: |m| has_specular(m) && m.specular != SpecularModel::BlinnPhong;
    geometry: Choice<Geometry> = Choice(&[Geometry::SmithCorrelated, Geometry::SmithSeparable]),
        default: Geometry::SmithCorrelated,
        label: "geometry",
        doc: "Smith masking-shadowing, height-correlated (Heitz 2014) or separable",
        shown: |m| has_specular(m) && m.specular != SpecularModel::BlinnPhong;
    roughness: Scalar = Scalar::UNIT,
        default: 0.5,
        label: "roughness",
        doc: "perceptual roughness; the microfacet α is roughness²",
        shown: has_specular,
        gpu: [roughness],
        twin: roughness;
    f0: Scalar = Scalar::UNIT,
        default: 0.04,
        label: "reflectance f0",
        doc: "Schlick's reflectance at normal incidence (eq. 9, Schlick 1994); clay is about 0.04",
        shown: has_specular,
        gpu: [f0],
        twin: f0;
    metallic: Scalar = Scalar::UNIT,
        default: 0.0,
        label: "metallic",
        doc: "0 for a dielectric (clay), 1 for a metal, whose F0 is the base colour and which has no \
              diffuse lobe; between, the blend of glTF 2.0's metallic-roughness model",
        shown: |m| has_specular(m) || m.diffuse != DiffuseModel::None,
        gpu: [metallic],
        twin: metallic;
    diffuse_roughness: Scalar = Scalar::UNIT,
        default: 0.0,
        label: "diffuse roughness",
        doc: "σ of the Oren-Nayar facet slopes, or EON's roughness r, in [0, 1]",
        shown: |m| matches!(m.diffuse, DiffuseModel::OrenNayar | DiffuseModel::Eon),
        gpu: [diffuse_roughness],
        twin: diffuse_roughness;
    specular_color: Rgb = Rgb { unit: false },
        default: [1.0; 3],
        label: "specular colour",
        doc: "tints the highlight",
        shown: has_specular,
        gpu: [specular_color[..]],
        twin: specular_color;
    emission: Rgb = Rgb { unit: false },
        default: [0.0; 3],
        label: "emission",
        doc: "radiance the surface emits, linear RGB, added to the reflected light whatever lights it",
        shown: |_| true,
        gpu: [emission[..]];
    wrap: Scalar = Scalar::UNIT,
        default: 0.0,
        label: "wrap",
        doc: "how far light wraps past the terminator, w₁ (the energy-conserving wrap's w)",
        shown: |m| matches!(m.subsurface, Subsurface::Seed | Subsurface::EnergyConservingWrap),
        gpu: [wrap],
        twin: wrap;
    wrap_width: Scalar = Scalar::positive((0.01, 1.0)),
        default: 0.3,
        label: "wrap width",
        doc: "the width of the wrap band, w₂",
        shown: seed_wrap,
        gpu: [wrap_width],
        twin: wrap_width;
    wrap_color: Rgb = Rgb { unit: false },
        default: [1.0; 3],
        label: "wrap colour",
        doc: "the colour of the wrapped light",
        shown: seed_wrap,
        gpu: [wrap_color[..]],
        twin: wrap_color;
    wrap_intensity: Scalar = Scalar::non_negative(4.0),
        default: 0.0,
        label: "wrap intensity",
        doc: "the strength of the wrapped light; 0 turns it off",
        shown: seed_wrap,
        gpu: [wrap_color[3]],
        twin: wrap_intensity;
    subsurface: Choice<Subsurface> = Choice(&SUBSURFACE_MODELS),
        default: Subsurface::Seed,
        label: "subsurface",
        doc: "none, the report's wrap lighting (seed, eq. 12), energy-conserving wrap, \
              or pre-integrated skin-style scattering (Penner 2011)",
        shown: |_| true;
    scatter_color: Rgb = Rgb { unit: true },
        default: [1.0; 3],
        label: "scatter colour",
        doc: "the per-channel reach of the scattered light, in [0, 1]",
        shown: |m| matches!(m.subsurface, Subsurface::EnergyConservingWrap | Subsurface::PreIntegrated),
        gpu: [scatter[..]],
        twin: scatter_color;
    scatter_radius: Scalar = Scalar::closed(0.0, MAX_SCATTER_RADIUS).slider(0.0, 2.0),
        default: 0.0,
        label: "scatter radius",
        doc: "the diffusion σ in scene units, at scatter colour 1",
        shown: |m| m.subsurface == Subsurface::PreIntegrated,
        gpu: [scatter[3]],
        twin: scatter_radius;
    horizon: Choice<Horizon> = Choice(&[Horizon::Smooth, Horizon::Seed]),
        default: Horizon::Smooth,
        label: "horizon",
        doc: "how a shading normal facing away from the light fades (smooth, or the report's seed clamp)",
        shown: |_| true;
    detail_blend: Choice<DetailBlend> = Choice(&[
            DetailBlend::Rnm,
            DetailBlend::Udn,
            DetailBlend::Whiteout,
            DetailBlend::Seed,
        ]),
        default: DetailBlend::Rnm,
        label: "detail blend",
        doc: "how the detail normals combine with the normal map: reoriented normal mapping \
              (Barré-Brisebois & Hill 2012), UDN, whiteout, or the report's eq. 16",
        shown: |m| m.maps[MapSlot::Detail].is_some();
    energy_compensation: Flag = Flag,
        default: false,
        label: "energy compensation",
        doc: "scales the specular lobe by 1 + F0 (1/E − 1), E its single-scattering albedo, for the \
              light rough microfacets scatter more than once (Kulla & Conty 2017, as Fdez-Agüera 2019)",
        shown: has_specular,
        gpu: [energy_compensation];
    micro_shadowing: Flag = Flag,
        default: false,
        label: "micro-shadowing",
        doc: "the occlusion map also shadows the point lights: each is multiplied by \
              saturate(n·l / √(1 − ao))² (Filament, after Chan 2018), for cavities finer than a texel",
        shown: |m| m.maps[MapSlot::Occlusion].is_some(),
        gpu: [micro_shadowing];
});

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_read_as_the_messages_say() {
        assert_eq!(Scalar::UNIT.reason(), "must be a finite number in [0, 1]");
        assert_eq!(MAP_STRENGTH.reason(), "must be a finite number in [0, 8]");
        assert_eq!(
            keys::scatter_radius.kind.reason(),
            "must be a finite number in [0, 1e6]"
        );
        assert_eq!(keys::wrap_width.kind.reason(), "must be a finite number > 0");
        assert_eq!(keys::wrap_intensity.kind.reason(), "must be a finite number >= 0");
        assert_eq!(limit(MAX_UV_SCALE), "10000");
        assert!(!keys::wrap_width.kind.contains(0.0) && keys::wrap_width.kind.contains(1e30));
        assert!(!Scalar::UNIT.contains(f32::NAN) && !keys::wrap_intensity.kind.contains(f32::INFINITY));
    }

    /// The panel edits a colour over its valid range: an emission of 4 stays 4.
    #[test]
    fn colours_edit_over_their_range() {
        let mut c = Vec3::splat(4.0);
        let Edit::Color(_, range) = keys::emission.kind.edit(&mut c) else {
            panic!("emission is a colour")
        };
        assert!(range.contains(&4.0) && range.contains(&0.0) && !range.contains(&-0.1));
        let Edit::Color(_, range) = keys::scatter_color.kind.edit(&mut c) else {
            panic!("scatter_color is a colour")
        };
        assert_eq!(range, 0.0..=1.0);
    }

    #[test]
    fn every_key_is_documented() {
        let docs = include_str!("../../docs/scene-format.md");
        for name in KEY_NAMES {
            assert!(
                docs.contains(&format!("| `{name}` |")),
                "docs/scene-format.md has no row for `{name}`"
            );
        }
    }
}
