//! Command pools and the one-shot submission used for uploads and offscreen frames.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;
use super::sync::Fence;

pub struct CommandPool {
    device: Arc<Device>,
    pub handle: vk::CommandPool,
}

impl CommandPool {
    /// A pool whose buffers can be reset one by one (each frame in flight re-records its own).
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let handle =
            unsafe { device.handle.create_command_pool(&info, None) }.context("cannot create a command pool")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }

    pub fn allocate(&self, count: u32) -> Result<Vec<vk::CommandBuffer>> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.handle)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count);
        unsafe { self.device.handle.allocate_command_buffers(&info) }.context("cannot allocate command buffers")
    }
}

impl Drop for CommandPool {
    fn drop(&mut self) {
        // Destroying the pool frees its command buffers.
        unsafe { self.device.handle.destroy_command_pool(self.handle, None) };
    }
}

/// Records a command buffer, submits it and waits for it: uploads, readbacks, and the
/// single frame of `argil render`.
pub struct OneShot {
    device: Arc<Device>,
    /// Owns `cmd` and frees it when dropped.
    _pool: CommandPool,
    cmd: vk::CommandBuffer,
    fence: Fence,
}

impl OneShot {
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let pool = CommandPool::new(device)?;
        let cmd = pool.allocate(1)?[0];
        let fence = Fence::new(device, false)?;
        Ok(Self {
            device: device.clone(),
            _pool: pool,
            cmd,
            fence,
        })
    }

    /// Records `record` into a fresh command buffer, submits it and waits until the GPU is done.
    pub fn run<R>(&self, record: impl FnOnce(vk::CommandBuffer) -> R) -> Result<R> {
        let device = &self.device.handle;
        unsafe {
            device.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(self.cmd, &begin)?;
        }
        let result = record(self.cmd);
        unsafe { device.end_command_buffer(self.cmd) }.context("vkEndCommandBuffer failed")?;
        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos);
        self.fence.reset()?;
        self.device.submit(&[submit], self.fence.handle)?;
        self.fence.wait()?;
        Ok(result)
    }
}
