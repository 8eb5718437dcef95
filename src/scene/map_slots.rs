//! Every material map declared once, in [`with_map_slots!`]'s table: its scene key, its
//! panel label, what it reads from its texture (role and channel) and its documentation.
//! A slot's index in the table is its GPU index: the `binding` of set 1, its bit in the
//! forward pass's `MAPS` specialization constant and its element of the `map_uv` and
//! `map_strength` arrays of `shaders/lib/material.glsl`, so those cannot disagree. The
//! GLSL side (`MAP_*` indices, bindings, channels, `MAP_COUNT`) is checked against the
//! table by the tests below; the file schema (`MaterialDef`) is generated from it in
//! `material_keys.rs`.
//!
//! A loader fills a slot with a [`MapRef`](super::MapRef) (a texture and its uv transform);
//! the channel is the slot's, glTF 2.0's convention: one occlusion-roughness-metallic
//! texture serves the three property maps, loaded once (textures are shared per path and
//! role).

use std::ops::{Index, IndexMut};

use super::texture::TextureRole;
use super::MapRef;

/// What a map reads from its texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    Rgb,
    R,
    G,
    B,
}

impl Channel {
    /// The component a one-channel map reads.
    pub fn index(self) -> Option<usize> {
        match self {
            Channel::Rgb => None,
            Channel::R => Some(0),
            Channel::G => Some(1),
            Channel::B => Some(2),
        }
    }
}

/// One map slot, as declared.
#[derive(Debug, PartialEq)]
pub struct SlotInfo {
    /// The material's table in the scene file.
    pub key: &'static str,
    /// The viewer's words for it.
    pub label: &'static str,
    /// The GLSL constant holding its index (material_maps.glsl).
    pub glsl: &'static str,
    /// How its file is decoded: sRGB colour or linear data.
    pub role: TextureRole,
    pub channel: Channel,
    /// Its row in the material keys of docs/scene-format.md.
    pub summary: &'static str,
    /// What `strength` does, its row in the maps table of docs/scene-format.md.
    pub doc: &'static str,
}

impl SlotInfo {
    /// The role column of the docs' maps table.
    pub fn role_doc(&self) -> String {
        let role = match self.role {
            TextureRole::BaseColor => "colour: 8-bit files are sRGB",
            TextureRole::Normal | TextureRole::Data => "linear data",
        };
        match self.channel {
            Channel::Rgb => role.to_owned(),
            Channel::R => format!("{role}, red channel"),
            Channel::G => format!("{role}, green channel"),
            Channel::B => format!("{role}, blue channel"),
        }
    }
}

/// Passes the table of map slots to `$callback!`, before the callback's own input: each
/// entry is `Variant { key: file_key, label, glsl, role, channel, summary, doc }`, in GPU
/// index order (append new maps: the index is a binding and a bit).
macro_rules! with_map_slots {
    ($callback:ident { $($args:tt)* }) => {
        $callback! {
            maps: [
                BaseColor {
                    key: base_color_map, label: "colour map", glsl: "MAP_BASE_COLOR",
                    role: BaseColor, channel: Rgb,
                    summary: "texture multiplying `base_color`",
                    doc: "`base_color · mix(1, map, strength)`; 0 ignores the map"
                },
                Normal {
                    key: normal_map, label: "normal map", glsl: "MAP_NORMAL",
                    role: Normal, channel: Rgb,
                    summary: "tangent-space normal map",
                    doc: "scales the tangent-space xy of the map's normal (then renormalised); 0 leaves the mesh \
                          normal (report eqs. 13–15)"
                },
                Detail {
                    key: detail_map, label: "detail map", glsl: "MAP_DETAIL",
                    role: Normal, channel: Rgb,
                    summary: "a second normal map (fingerprints) blended over `normal_map`",
                    doc: "the same, for the detail normal before blending"
                },
                Noise {
                    key: noise_map, label: "noise map", glsl: "MAP_NOISE",
                    role: Data, channel: R,
                    summary: "noise modulating reflections",
                    doc: "reflections are weighted by `mix(1, noise, strength)` (the report's eq. 17 noise texture)"
                },
                Roughness {
                    key: roughness_map, label: "roughness map", glsl: "MAP_ROUGHNESS",
                    role: Data, channel: G,
                    summary: "texture multiplying `roughness` (glTF 2.0's metallic-roughness green channel)",
                    doc: "`roughness · mix(1, map, strength)`"
                },
                Metallic {
                    key: metallic_map, label: "metallic map", glsl: "MAP_METALLIC",
                    role: Data, channel: B,
                    summary: "texture multiplying `metallic` (glTF 2.0's metallic-roughness blue channel)",
                    doc: "`metallic · mix(1, map, strength)`"
                },
                Occlusion {
                    key: occlusion_map, label: "occlusion map", glsl: "MAP_OCCLUSION",
                    role: Data, channel: R,
                    summary: "baked ambient occlusion of the environment's light, and of the point lights \
                              with `micro_shadowing` (glTF 2.0's occlusion, red channel)",
                    doc: "the environment's light is multiplied by `ao = mix(1, map, strength)`, with the \
                          screen-space occlusion's visibility; with `micro_shadowing`, each point light is \
                          micro-shadowed (Filament's form of Chan 2018): multiplied by \
                          `saturate(n·l / √(1 − ao))²`, 1 at `ao = 1`. \
                          `argil reference` applies `ao` to the environment's light only: micro-shadowing \
                          approximates geometry finer than a texel, which the reference does not have, so it \
                          stays out of the ground truth"
                },
                Scatter {
                    key: scatter_map, label: "scatter map", glsl: "MAP_SCATTER",
                    role: Data, channel: R,
                    summary: "texture scaling the subsurface scattering",
                    doc: "`scatter_color` and `wrap` are multiplied by `mix(1, map, strength)`"
                },
                Emission {
                    key: emission_map, label: "emission map", glsl: "MAP_EMISSION",
                    role: BaseColor, channel: Rgb,
                    summary: "texture multiplying `emission` (glTF 2.0's emissive texture)",
                    doc: "`emission · mix(1, map, strength)`"
                },
            ]
            $($args)*
        }
    };
}
pub(crate) use with_map_slots;

macro_rules! declare_map_slots {
    (maps: [$(
        $slot:ident {
            key: $key:ident, label: $label:literal, glsl: $glsl:literal,
            role: $role:ident, channel: $channel:ident,
            summary: $summary:literal,
            doc: $doc:literal
        },
    )+]) => {
        /// A material map, by its GPU index.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(usize)]
        pub enum MapSlot {
            $($slot,)+
        }

        /// Every slot's declaration, in GPU index order.
        pub const SLOTS: &[SlotInfo] = &[$(SlotInfo {
            key: stringify!($key),
            label: $label,
            glsl: $glsl,
            role: TextureRole::$role,
            channel: Channel::$channel,
            summary: $summary,
            doc: $doc,
        },)+];

        impl MapSlot {
            /// Every slot, in GPU index order.
            pub const ALL: [MapSlot; MAP_COUNT] = [$(MapSlot::$slot,)+];
        }
    };
}

/// How many map slots a material has (`MAP_COUNT` of material.glsl).
pub const MAP_COUNT: usize = SLOTS.len();

with_map_slots!(declare_map_slots {});

impl MapSlot {
    /// Its binding in set 1, element of the GPU arrays, and bit position in `MAPS`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Its bit in the `MAPS` specialization constant.
    pub const fn bit(self) -> u32 {
        1 << self as u32
    }

    pub fn info(self) -> &'static SlotInfo {
        &SLOTS[self.index()]
    }

    /// The slot whose table the file calls `key`.
    pub fn from_key(key: &str) -> Option<MapSlot> {
        MapSlot::ALL.into_iter().find(|s| s.info().key == key)
    }
}

/// The maps a material samples, by slot; see docs/scene-format.md.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialMaps(pub [Option<MapRef>; MAP_COUNT]);

impl MaterialMaps {
    /// Every slot with its map, if any.
    pub fn iter(&self) -> impl Iterator<Item = (MapSlot, &Option<MapRef>)> {
        MapSlot::ALL.into_iter().zip(&self.0)
    }

    pub fn iter_mut(&mut self) -> impl Iterator<Item = (MapSlot, &mut Option<MapRef>)> {
        MapSlot::ALL.into_iter().zip(&mut self.0)
    }
}

impl Index<MapSlot> for MaterialMaps {
    type Output = Option<MapRef>;

    fn index(&self, slot: MapSlot) -> &Option<MapRef> {
        &self.0[slot.index()]
    }
}

impl IndexMut<MapSlot> for MaterialMaps {
    fn index_mut(&mut self, slot: MapSlot) -> &mut Option<MapRef> {
        &mut self.0[slot.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAPS_GLSL: &str = include_str!("../../shaders/lib/material_maps.glsl");
    const MATERIAL_GLSL: &str = include_str!("../../shaders/lib/material.glsl");

    #[test]
    fn the_shaders_declare_every_slot_where_the_table_does() {
        assert!(
            MATERIAL_GLSL.contains(&format!("const int MAP_COUNT = {MAP_COUNT};")),
            "material.glsl's MAP_COUNT"
        );
        for slot in MapSlot::ALL {
            let info = slot.info();
            let index = slot.index();
            let constant = format!("const uint {} = {index}u;", info.glsl);
            assert!(MAPS_GLSL.contains(&constant), "material_maps.glsl: {constant}");
            // `_texture`: the ambient occlusion's own `occlusion_map` is another sampler.
            let binding = format!(
                "layout(set = 1, binding = {index}) uniform sampler2D {}_texture;",
                info.key
            );
            assert!(MAPS_GLSL.contains(&binding), "material_maps.glsl: {binding}");
            if let Some(c) = info.channel.index() {
                let channel = format!("const uint {}_CHANNEL = {c}u;", info.glsl);
                assert!(MAPS_GLSL.contains(&channel), "material_maps.glsl: {channel}");
            }
        }
        // No map the table does not know.
        let bindings = MAPS_GLSL.matches("layout(set = 1, binding = ").count();
        assert_eq!(bindings, MAP_COUNT);
    }

    #[test]
    fn every_slot_is_documented() {
        let docs = include_str!("../../docs/scene-format.md");
        for info in SLOTS {
            let key = format!(
                "| `{}` | table | none | see [Maps](#maps) | {} |",
                info.key, info.summary
            );
            assert!(docs.contains(&key), "docs/scene-format.md: {key}");
            let row = format!("| `{}` | {} | {} |", info.key, info.role_doc(), info.doc);
            assert!(docs.contains(&row), "docs/scene-format.md: {row}");
        }
    }

    #[test]
    fn slots_index_the_maps_and_find_their_keys() {
        for slot in MapSlot::ALL {
            assert_eq!(MapSlot::from_key(slot.info().key), Some(slot));
            assert_eq!(slot.bit().trailing_zeros() as usize, slot.index());
        }
        assert_eq!(MapSlot::from_key("no_map"), None);
    }
}
