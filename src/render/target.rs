//! The offscreen frame every pass renders into: linear HDR radiance and depth. Writing a
//! file and presenting to a window both read from it.

use std::sync::Arc;

use anyhow::{ensure, Result};
use ash::vk;

use crate::vk::{Device, Image};

/// Linear radiance in full fp32, so an EXR holds what the shader computed.
pub const HDR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The largest frame side argil renders (also most devices' maxImageDimension2D).
pub const MAX_SIDE: u32 = 16384;

pub struct RenderTarget {
    pub color: Image,
    /// The depth of single-sampled frames. A multisampled frame tests against its own
    /// multisampled depth (src/render/msaa.rs) and leaves this one unwritten.
    pub depth: Image,
    pub extent: vk::Extent2D,
}

impl RenderTarget {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let max = MAX_SIDE.min(device.limits.max_image_dimension2_d);
        ensure!(
            (1..=max).contains(&extent.width) && (1..=max).contains(&extent.height),
            "frame size {}x{} is outside 1..={max} on this device",
            extent.width,
            extent.height
        );
        let color = Image::new_2d(
            device,
            extent,
            HDR_FORMAT,
            // Storage: the accumulation rewrites it with the running mean (accumulate.rs).
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
            "hdr frame",
        )?;
        let depth = Image::new_2d(
            device,
            extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
            "depth",
        )?;
        Ok(Self { color, depth, extent })
    }

    pub fn aspect(&self) -> f32 {
        self.draw_target().aspect()
    }

    /// The target's own images, single-sampled, as the forward pass and skybox draw into.
    pub fn draw_target(&self) -> DrawTarget<'_> {
        DrawTarget {
            color: &self.color,
            depth: &self.depth,
        }
    }
}

/// The colour and depth images the forward pass and the skybox draw into: a target's own,
/// or multisampled ones that src/render/msaa.rs resolves into it. Both have the target's
/// extent and the same sample count.
#[derive(Clone, Copy)]
pub struct DrawTarget<'a> {
    pub color: &'a Image,
    pub depth: &'a Image,
}

impl DrawTarget<'_> {
    pub fn extent(&self) -> vk::Extent2D {
        self.color.extent
    }

    pub fn aspect(&self) -> f32 {
        self.color.extent.width as f32 / self.color.extent.height as f32
    }

    pub fn samples(&self) -> vk::SampleCountFlags {
        self.color.samples
    }
}
