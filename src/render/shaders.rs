//! SPIR-V compiled by build.rs from `shaders/`.

macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file, ".spv"))
    };
}

pub const FORWARD_VERT: &[u8] = spirv!("forward.vert");
pub const FORWARD_FRAG: &[u8] = spirv!("forward.frag");
pub const FULLSCREEN_VERT: &[u8] = spirv!("fullscreen.vert");
pub const TONEMAP_FRAG: &[u8] = spirv!("tonemap.frag");
