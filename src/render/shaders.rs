//! SPIR-V compiled by build.rs from `shaders/`.

macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file, ".spv"))
    };
}

pub const FORWARD_VERT: &[u8] = spirv!("forward.vert");
pub const FORWARD_FRAG: &[u8] = spirv!("forward.frag");
pub const FORWARD_SHADED_FRAG: &[u8] = spirv!("forward_shaded.frag");
pub const FORWARD_LEAN_FRAG: &[u8] = spirv!("forward_lean.frag");
pub const FORWARD_GBUFFER_FRAG: &[u8] = spirv!("forward_gbuffer.frag");
pub const FORWARD_DEFERRED_FRAG: &[u8] = spirv!("forward_deferred.frag");
pub const FORWARD_DEFERRED_LEAN_FRAG: &[u8] = spirv!("forward_deferred_lean.frag");
pub const DEFERRED_VERT: &[u8] = spirv!("deferred.vert");
pub const DEFERRED_OBJECTS_FRAG: &[u8] = spirv!("deferred_objects.frag");
pub const FLOOR_FRAG: &[u8] = spirv!("floor.frag");
pub const FULLSCREEN_VERT: &[u8] = spirv!("fullscreen.vert");
pub const TONEMAP_FRAG: &[u8] = spirv!("tonemap.frag");
pub const SKYBOX_VERT: &[u8] = spirv!("skybox.vert");
pub const SKYBOX_FRAG: &[u8] = spirv!("skybox.frag");
pub const ENV_STUDIO_COMP: &[u8] = spirv!("env_studio.comp");
pub const ENV_EQUIRECT_COMP: &[u8] = spirv!("env_equirect.comp");
pub const ENV_DOWNSAMPLE_COMP: &[u8] = spirv!("env_downsample.comp");
pub const ENV_PREFILTER_COMP: &[u8] = spirv!("env_prefilter.comp");
pub const ENV_OCTAHEDRAL_COMP: &[u8] = spirv!("env_octahedral.comp");
pub const ENV_BRDF_LUT_COMP: &[u8] = spirv!("env_brdf_lut.comp");
pub const ACCUMULATE_COMP: &[u8] = spirv!("accumulate.comp");
pub const EXPOSURE_COMP: &[u8] = spirv!("exposure.comp");
pub const SHADOW_VERT: &[u8] = spirv!("shadow.vert");
pub const MSAA_RESOLVE_FRAG: &[u8] = spirv!("msaa_resolve.frag");
pub const GTAO_COMP: &[u8] = spirv!("gtao.comp");
pub const GTAO_DENOISE_COMP: &[u8] = spirv!("gtao_denoise.comp");
pub const GROUND_LIGHT_COMP: &[u8] = spirv!("ground_light.comp");
pub const GROUND_OCCLUSION_COMP: &[u8] = spirv!("ground_occlusion.comp");
pub const GROUND_SHADOW_COMP: &[u8] = spirv!("ground_shadow.comp");
pub const GROUND_ENVIRONMENT_COMP: &[u8] = spirv!("ground_environment.comp");
pub const VERTEX_LIGHT_COMP: &[u8] = spirv!("vertex_light.comp");

#[cfg(test)]
pub mod tests {
    use std::collections::HashMap;

    /// The (set, binding) pairs a SPIR-V module decorates: the resources its entry point
    /// reads and writes (the compiler drops those it does not use).
    pub fn bindings(spirv: &[u8]) -> Vec<(u32, u32)> {
        const OP_DECORATE: u32 = 71;
        const BINDING: u32 = 33;
        const DESCRIPTOR_SET: u32 = 34;
        let words: Vec<u32> = spirv.chunks_exact(4).map(|w| u32::from_le_bytes(w.try_into().unwrap())).collect();
        let (mut sets, mut bindings) = (HashMap::new(), HashMap::new());
        let mut at = 5;
        while at < words.len() {
            let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xffff);
            if opcode == OP_DECORATE && count == 4 {
                let (target, decoration, value) = (words[at + 1], words[at + 2], words[at + 3]);
                match decoration {
                    DESCRIPTOR_SET => sets.insert(target, value),
                    BINDING => bindings.insert(target, value),
                    _ => None,
                };
            }
            at += count.max(1);
        }
        let mut pairs: Vec<(u32, u32)> = sets.iter().map(|(target, &set)| (set, bindings[target])).collect();
        pairs.sort_unstable();
        pairs
    }
}
