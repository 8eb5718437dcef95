//! `MaterialData`, a material as the shaders read it. Its declaration below is the one
//! layout: build.rs writes `struct Material` of the shaders from it (`material_struct.glsl`
//! in `OUT_DIR`, included by `shaders/lib/material.glsl`), each field's doc comment the
//! member's comment, so a field added here is a member there.

use bytemuck::{Pod, Zeroable};

use crate::scene::map_slots::MAP_COUNT;
use crate::scene::{MapRef, MapSlot, Material};

/// A Pod struct whose fields' names, offsets and sizes a test compares with the GLSL.
macro_rules! gpu_struct {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$field_meta:meta])* pub $field:ident: $ty:ty,)+ }) => {
        $(#[$meta])*
        pub struct $name {
            $($(#[$field_meta])* pub $field: $ty,)+
        }

        #[cfg(test)]
        impl $name {
            /// (name, offset, size) of every field, in order.
            const FIELDS: &[(&str, usize, usize)] =
                &[$((stringify!($field), std::mem::offset_of!($name, $field), std::mem::size_of::<$ty>())),+];
        }
    };
}

// build.rs reads the fields of this block, one a line: `f32`, `u32`, `[f32; 4]`, `[u32; 4]`
// and arrays of them over `MAP_COUNT`, with `///` comments above them; `map_strength_pad`,
// the explicit padding Pod needs, is no member there (std430 aligns the next one itself).
gpu_struct! {
    /// `Material` of the shaders (std430); the keys' fields are filled where
    /// `scene::material_keys` declares them.
    #[repr(C)]
    #[derive(Clone, Copy, Pod, Zeroable)]
    pub struct MaterialData {
        /// rgb linear albedo
        pub base_color: [f32; 4],
        /// rgb tint of the specular lobe
        pub specular_color: [f32; 4],
        /// rgb colour of the report's wrap term, a = its intensity
        pub wrap_color: [f32; 4],
        /// rgb scatter_color (per-channel reach), a = scatter_radius
        pub scatter: [f32; 4],
        /// rgb emitted radiance, linear
        pub emission: [f32; 4],
        /// perceptual; alpha = roughness^2
        pub roughness: f32,
        /// Schlick reflectance at normal incidence
        pub f0: f32,
        pub diffuse_roughness: f32,
        pub wrap: f32,
        pub wrap_width: f32,
        /// 0 dielectric, 1 metal (glTF 2.0 metallic-roughness)
        pub metallic: f32,
        /// 1: the specular lobe is energy-compensated (environment.glsl)
        pub energy_compensation: f32,
        /// 1: the occlusion map micro-shadows the point lights (lights.glsl)
        pub micro_shadowing: f32,
        /// per map slot (src/scene/map_slots.rs): xy scale, zw offset (map_uv)
        pub map_uv: [[f32; 4]; MAP_COUNT],
        /// per map slot: (cos, sin) of the scaled uv's counter-clockwise turn (map_uv)
        pub map_uv_turn: [[f32; 2]; MAP_COUNT],
        /// per map slot: its strength, 0 without the map
        pub map_strength: [f32; MAP_COUNT],
        /// up to std430's 16-byte alignment of the next member, which GLSL pads to itself
        pub map_strength_pad: [f32; MAP_STRENGTH_PAD],
        /// x normal map, y detail map: 1 for DirectX-style maps
        pub green_down: [u32; 4],
    }
}

/// The floats after `map_strength` up to the next 16 bytes: `map_uv_turn` and `map_strength`
/// take 12 bytes a slot from the 16-byte boundary after `map_uv`.
const MAP_STRENGTH_PAD: usize = ((12 * MAP_COUNT).next_multiple_of(16) - 12 * MAP_COUNT) / 4;

/// A map's uv transform as (scale, offset) and its turn's (cos, sin) (`MapRef::uv`), and its
/// strength; identity without a map.
fn map_terms(map: Option<&MapRef>) -> ([f32; 4], [f32; 2], f32) {
    map.map_or(([1.0, 1.0, 0.0, 0.0], [1.0, 0.0], 0.0), |m| {
        let turn = m.uv_turn().as_vec2();
        ([m.uv_scale.x, m.uv_scale.y, m.uv_offset.x, m.uv_offset.y], turn.to_array(), m.strength)
    })
}

impl From<&Material> for MaterialData {
    /// The keys where `material_keys` packs them, then the maps.
    fn from(m: &Material) -> Self {
        let maps = &m.maps;
        let terms = maps.0.map(|map| map_terms(map.as_ref()));
        let mut data = Self {
            map_uv: terms.map(|t| t.0),
            map_uv_turn: terms.map(|t| t.1),
            map_strength: terms.map(|t| t.2),
            green_down: [
                u32::from(maps[MapSlot::Normal].is_some_and(|m| m.green_down)),
                u32::from(maps[MapSlot::Detail].is_some_and(|m| m.green_down)),
                0,
                0,
            ],
            ..Self::zeroed()
        };
        m.pack(&mut data);
        data
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::material_keys::GPU_SLOTS;
    use crate::scene::Scene;

    /// The members of `struct Material` as build.rs wrote it: (type, name).
    fn glsl_members() -> Vec<(String, String)> {
        let glsl = include_str!(concat!(env!("OUT_DIR"), "/material_struct.glsl"));
        let start = glsl
            .find("struct Material {")
            .expect("material_struct.glsl declares struct Material");
        let body = &glsl[start..][..glsl[start..].find("};").expect("the struct ends")];
        body.lines()
            .skip(1)
            .map(|line| line.split("//").next().unwrap_or("").trim())
            .filter(|line| !line.is_empty())
            .map(|line| {
                let declaration = line.strip_suffix(';').expect("one member a line");
                let (ty, name) = declaration.split_once(' ').expect("type and name");
                (ty.to_owned(), name.trim().to_owned())
            })
            .collect()
    }

    /// std430 (size, alignment) of the member types the generated struct uses; `name[MAP_COUNT]`
    /// is an array of one element per map slot (std430: stride the element's size).
    fn std430(ty: &str, name: &str) -> (usize, usize) {
        let (size, align) = match ty {
            "float" | "uint" | "int" => (4, 4),
            "vec2" => (8, 8),
            "vec4" | "uvec4" => (16, 16),
            other => panic!("material_struct.glsl: no std430 rule here for {other}"),
        };
        match name.split_once('[') {
            Some((_, "MAP_COUNT]")) => (size * MAP_COUNT, align),
            Some((_, other)) => panic!("material_struct.glsl: no array size {other}"),
            None => (size, align),
        }
    }

    #[test]
    fn material_data_has_the_glsl_layout() {
        let mut offset = 0usize;
        let glsl: Vec<(String, usize, usize)> = glsl_members()
            .into_iter()
            .map(|(ty, name)| {
                let (size, align) = std430(&ty, &name);
                offset = offset.next_multiple_of(align);
                let name = name.split('[').next().unwrap_or(&name).to_owned();
                let member = (name, offset, size);
                offset += size;
                member
            })
            .collect();
        let rust: Vec<(String, usize, usize)> = MaterialData::FIELDS
            .iter()
            .filter(|(name, ..)| !name.ends_with("_pad"))
            .map(|&(name, offset, size)| (name.to_owned(), offset, size))
            .collect();
        assert_eq!(rust, glsl);
        assert_eq!(std::mem::size_of::<MaterialData>(), offset.next_multiple_of(16));
    }

    #[test]
    fn every_key_packs_into_a_glsl_member() {
        let members = glsl_members();
        for (key, slot) in GPU_SLOTS {
            let field = slot.split(['[', ' ']).next().unwrap_or(slot);
            let (ty, _) = members
                .iter()
                .find(|(_, name)| name == field)
                .unwrap_or_else(|| panic!("{key}: the GLSL Material has no member {field}"));
            // A colour fills a vec4's rgb, a number a float or one component.
            let indexed = slot.contains('[');
            assert_eq!(ty == "vec4", indexed, "{key} packs into {slot}, a {ty}");
        }
    }

    #[test]
    fn keys_pack_where_declared() {
        let scene = Scene::from_toml(crate::scene::DEFAULT_SCENE_TOML, "default", std::path::Path::new(""))
            .expect("the default scene");
        for m in &scene.materials {
            let data = MaterialData::from(m);
            assert_eq!(data.base_color[..3], m.base_color.to_array());
            assert_eq!(data.wrap_color, m.wrap_color.extend(m.wrap_intensity).to_array());
            assert_eq!(data.scatter, m.scatter_color.extend(m.scatter_radius).to_array());
            assert_eq!(
                [
                    data.roughness,
                    data.f0,
                    data.diffuse_roughness,
                    data.wrap,
                    data.wrap_width
                ],
                [m.roughness, m.f0, m.diffuse_roughness, m.wrap, m.wrap_width]
            );
        }
    }
}
