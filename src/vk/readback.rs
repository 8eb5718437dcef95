//! Copying an image back to the CPU: a host-visible buffer, a copy recorded after the
//! image's last write, and the bytes once the frame's fence has signalled.

use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::buffer::Buffer;
use super::device::Device;
use super::image::{copy_region, Image};
use super::sync::{transition, ImageUse};

/// What a copy needs to know of an image: an [`Image`] of ours, or a swapchain's.
#[derive(Clone, Copy)]
pub struct ImageRegion {
    pub handle: vk::Image,
    pub extent: vk::Extent2D,
    pub aspect: vk::ImageAspectFlags,
}

impl From<&Image> for ImageRegion {
    fn from(image: &Image) -> Self {
        Self {
            handle: image.handle,
            extent: image.extent,
            aspect: image.aspect,
        }
    }
}

pub struct Readback {
    buffer: Buffer,
    pub extent: vk::Extent2D,
}

impl Readback {
    /// A buffer for a tightly packed copy of `image` (`bytes_per_pixel` per texel).
    pub fn new(device: &Arc<Device>, image: impl Into<ImageRegion>, bytes_per_pixel: u32) -> Result<Self> {
        let image = image.into();
        let size = u64::from(image.extent.width) * u64::from(image.extent.height) * u64::from(bytes_per_pixel);
        let buffer = Buffer::readback(device, size, "readback")?;
        Ok(Self {
            buffer,
            extent: image.extent,
        })
    }

    /// Records the copy. The image is in use `from` and is left in `TRANSFER_SRC`; the
    /// buffer write is made visible to the host.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, image: impl Into<ImageRegion>, from: ImageUse) {
        let image = image.into();
        transition(device, cmd, image.handle, image.aspect, from, ImageUse::TRANSFER_SRC);
        let region = copy_region(image.aspect, 0, 1, image.extent);
        unsafe {
            device.handle.cmd_copy_image_to_buffer(
                cmd,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                self.buffer.handle,
                &[region],
            );
        }
        let to_host = vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ);
        let barriers = [to_host];
        let dependency = vk::DependencyInfo::default().memory_barriers(&barriers);
        unsafe { device.handle.cmd_pipeline_barrier2(cmd, &dependency) };
    }

    /// The copied bytes; valid once the submission that recorded the copy has completed.
    pub fn bytes(&self) -> Result<&[u8]> {
        self.buffer.read()
    }
}
