//! Texture data on the CPU.

/// The layout of a texture's texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelFormat {
    Rgba8Srgb,
    Rgba8Unorm,
    Rgba16Unorm,
    Rgba32Float,
}

/// A decoded texture: tightly packed RGBA rows, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub format: TexelFormat,
    pub pixels: Vec<u8>,
}
