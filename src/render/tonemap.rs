//! The display transform: reads the HDR target, writes display colours into an 8-bit
//! image (a file's or a swapchain's). Set 0, binding 0: the HDR frame as a sampled image;
//! push constants: exposure and where the frame starts in the output. One pipeline per
//! output format.

use std::cell::Cell;
use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::fullscreen::FullscreenPass;
use super::shaders;
use super::target::RenderTarget;
use crate::vk::{Device, Specialization};

/// The format of 8-bit tone-mapped frames written to files: the hardware sRGB-encodes.
pub const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Whether writes to `format` are sRGB-encoded by the hardware.
pub fn is_srgb(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_SRGB | vk::Format::A8B8G8R8_SRGB_PACK32
    )
}

/// `tonemap.frag`'s push constants: the frame's offset in the output (ivec2), the
/// exposure (f32), output pixels per HDR texel (i32).
const PUSH_BYTES: u32 = 16;

pub struct TonemapPass {
    /// By output format.
    pass: FullscreenPass<vk::Format>,
    /// Passes recorded so far.
    records: Cell<u64>,
}

impl TonemapPass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        Ok(Self {
            pass: FullscreenPass::new(
                device,
                frames_in_flight,
                shaders::TONEMAP_FRAG,
                "tonemap.frag",
                PUSH_BYTES,
            )?,
            records: Cell::new(0),
        })
    }

    /// How many times the pass has been recorded: frames written only as linear radiance
    /// have none.
    pub fn records(&self) -> u64 {
        self.records.get()
    }

    /// Points `slot`'s set at `target` and creates the pipeline for `format` if needed.
    pub fn prepare(&mut self, slot: usize, target: &RenderTarget, format: vk::Format) -> Result<()> {
        self.pass.bind(slot, target.color.view);
        // The shader encodes sRGB itself only when the hardware will not.
        let encode = Specialization(vec![u32::from(!is_srgb(format))]);
        self.pass.prepare_pipeline(format, format, encode)
    }

    /// Records the pass into `area` of `output` (in colour-attachment layout), which is the
    /// HDR target's size times `scale` (each texel drawn as `scale`×`scale` pixels); the
    /// target must be readable by fragment shaders.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        output: vk::ImageView,
        format: vk::Format,
        area: vk::Rect2D,
        exposure: f32,
        scale: u32,
    ) -> Result<()> {
        let mut push = area.offset.x.to_ne_bytes().to_vec();
        push.extend(area.offset.y.to_ne_bytes());
        push.extend(exposure.to_ne_bytes());
        push.extend((scale.max(1) as i32).to_ne_bytes());
        self.records.set(self.records.get() + 1);
        self.pass.record(cmd, slot, format, output, area, &push)
    }
}
