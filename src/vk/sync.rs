//! Fences, semaphores and the synchronization2 barriers between passes.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;
use super::image::full_range;

pub struct Fence {
    device: Arc<Device>,
    pub handle: vk::Fence,
}

impl Fence {
    pub fn new(device: &Arc<Device>, signaled: bool) -> Result<Self> {
        let flags = if signaled {
            vk::FenceCreateFlags::SIGNALED
        } else {
            vk::FenceCreateFlags::empty()
        };
        let handle = unsafe {
            device
                .handle
                .create_fence(&vk::FenceCreateInfo::default().flags(flags), None)
        }
        .context("cannot create a fence")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }

    pub fn wait(&self) -> Result<()> {
        self.device
            .check_lost()
            .and_then(|()| unsafe { self.device.handle.wait_for_fences(&[self.handle], true, u64::MAX) })
            .context("waiting for a fence failed")
    }

    pub fn reset(&self) -> Result<()> {
        unsafe { self.device.handle.reset_fences(&[self.handle]) }.context("vkResetFences failed")
    }
}

impl Drop for Fence {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_fence(self.handle, None) };
    }
}

pub struct Semaphore {
    device: Arc<Device>,
    pub handle: vk::Semaphore,
}

impl Semaphore {
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let handle = unsafe {
            device
                .handle
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .context("cannot create a semaphore")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_semaphore(self.handle, None) };
    }
}

/// One side of an image layout transition: the layout, and the stage and access that
/// last touched (or will next touch) the image in it.
#[derive(Clone, Copy, Debug)]
pub struct ImageUse {
    pub layout: vk::ImageLayout,
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
}

impl ImageUse {
    pub const UNDEFINED: Self = Self {
        layout: vk::ImageLayout::UNDEFINED,
        stage: vk::PipelineStageFlags2::TOP_OF_PIPE,
        access: vk::AccessFlags2::NONE,
    };
    /// A swapchain image just acquired: its layout transition must wait for the acquire
    /// semaphore, which the submit waits for at the colour-output stage.
    pub const ACQUIRED: Self = Self {
        layout: vk::ImageLayout::UNDEFINED,
        stage: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::NONE,
    };
    pub const COLOR_ATTACHMENT: Self = Self {
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        stage: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw() | vk::AccessFlags2::COLOR_ATTACHMENT_READ.as_raw(),
        ),
    };
    pub const DEPTH_ATTACHMENT: Self = Self {
        layout: vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        stage: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw(),
        ),
    };
    /// Read and written as a storage image by compute shaders.
    pub const COMPUTE_STORAGE: Self = Self {
        layout: vk::ImageLayout::GENERAL,
        stage: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw() | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    pub const FRAGMENT_READ: Self = Self {
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        stage: vk::PipelineStageFlags2::FRAGMENT_SHADER,
        access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    };
    /// Sampled by compute shaders.
    pub const COMPUTE_READ: Self = Self {
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        stage: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    };
    /// Sampled by shaders of every stage a frame runs: the environment's images by the
    /// forward pass's vertex shader too, the frame by the tone map and the exposure measure.
    pub const SHADER_READ: Self = Self {
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        stage: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
                | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw()
                | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
        ),
        access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    };
    /// Cleared by `vkCmdClearColorImage`.
    pub const CLEAR_DST: Self = Self {
        layout: vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        stage: vk::PipelineStageFlags2::CLEAR,
        access: vk::AccessFlags2::TRANSFER_WRITE,
    };
    pub const TRANSFER_DST: Self = Self {
        layout: vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        stage: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::COPY.as_raw() | vk::PipelineStageFlags2::BLIT.as_raw(),
        ),
        access: vk::AccessFlags2::TRANSFER_WRITE,
    };
    pub const TRANSFER_SRC: Self = Self {
        layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        stage: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::COPY.as_raw() | vk::PipelineStageFlags2::BLIT.as_raw(),
        ),
        access: vk::AccessFlags2::TRANSFER_READ,
    };
    pub const PRESENT: Self = Self {
        layout: vk::ImageLayout::PRESENT_SRC_KHR,
        stage: vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
        access: vk::AccessFlags2::NONE,
    };
}

/// Records a layout transition of the first mip level of an image from `from` to `to`.
pub fn transition(
    device: &Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    from: ImageUse,
    to: ImageUse,
) {
    transition_levels(device, cmd, image, full_range(aspect), from, to);
}

/// Records a layout transition of the mip levels and layers in `range`.
pub fn transition_levels(
    device: &Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    from: ImageUse,
    to: ImageUse,
) {
    let barrier = vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(range)
        .old_layout(from.layout)
        .new_layout(to.layout)
        .src_stage_mask(from.stage)
        .src_access_mask(from.access)
        .dst_stage_mask(to.stage)
        .dst_access_mask(to.access);
    let barriers = [barrier];
    let dependency = vk::DependencyInfo::default().image_memory_barriers(&barriers);
    unsafe { device.handle.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// One side of a buffer's barrier: the stage and access that last touched (or will next
/// touch) it.
#[derive(Clone, Copy, Debug)]
pub struct BufferUse {
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
}

impl BufferUse {
    /// Written as a storage buffer by compute shaders.
    pub const COMPUTE_WRITE: Self = Self {
        stage: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::SHADER_STORAGE_WRITE,
    };
    /// Read as a storage buffer by vertex shaders.
    pub const VERTEX_READ: Self = Self {
        stage: vk::PipelineStageFlags2::VERTEX_SHADER,
        access: vk::AccessFlags2::SHADER_STORAGE_READ,
    };
    /// Written by a copy.
    pub const TRANSFER_DST: Self = Self {
        stage: vk::PipelineStageFlags2::COPY,
        access: vk::AccessFlags2::TRANSFER_WRITE,
    };
    /// Read by a copy.
    pub const TRANSFER_SRC: Self = Self {
        stage: vk::PipelineStageFlags2::COPY,
        access: vk::AccessFlags2::TRANSFER_READ,
    };
    /// Read by the host.
    pub const HOST_READ: Self = Self {
        stage: vk::PipelineStageFlags2::HOST,
        access: vk::AccessFlags2::HOST_READ,
    };
}

/// Records a barrier between two uses of the whole of `buffer`.
pub fn buffer_barrier(device: &Device, cmd: vk::CommandBuffer, buffer: vk::Buffer, from: BufferUse, to: BufferUse) {
    let barrier = vk::BufferMemoryBarrier2::default()
        .buffer(buffer)
        .offset(0)
        .size(vk::WHOLE_SIZE)
        .src_stage_mask(from.stage)
        .src_access_mask(from.access)
        .dst_stage_mask(to.stage)
        .dst_access_mask(to.access);
    let barriers = [barrier];
    let dependency = vk::DependencyInfo::default().buffer_memory_barriers(&barriers);
    unsafe { device.handle.cmd_pipeline_barrier2(cmd, &dependency) };
}
