//! `[antialiasing]`: how the frame is filtered against aliasing: multisampling of the
//! forward pass (silhouettes) and the widening of specular lobes by the shading normal's
//! screen-space variation (normal-mapped detail).

/// Samples per pixel of the forward pass that `[antialiasing] msaa` accepts; 1 is none.
pub const MSAA_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// The frame's anti-aliasing settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Antialiasing {
    /// Samples per pixel of the forward pass and skybox, one of [`MSAA_COUNTS`].
    pub msaa: u32,
    /// Whether specular lobes are widened by the variation of the shading normal across
    /// the pixel (shaders/lib/specular_aa.glsl).
    pub specular: bool,
}

impl Antialiasing {
    /// What a scene file without `[antialiasing]` gets. Measured by `argil bench` on
    /// lavapipe (README): specular anti-aliasing costs nothing measurable and takes 4% off
    /// the normal-mapped close-up's ꟻLIP, so it is on; 4× MSAA costs 1.7× the default
    /// scene's work for 0.6% off its ꟻLIP at the bench's size, so it is asked for.
    pub const DEFAULT: Self = Self {
        msaa: 1,
        specular: true,
    };
}

impl Default for Antialiasing {
    fn default() -> Self {
        Self::DEFAULT
    }
}
