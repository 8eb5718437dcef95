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
pub const VERTEX_BOUNCE_COMP: &[u8] = spirv!("vertex_bounce.comp");
