//! Frames in flight on a swapchain: each slot has its command buffer, fence, acquire
//! semaphore and HDR target; the swapchain has one present semaphore per image.

use std::sync::Arc;

use anyhow::{bail, Result};
use ash::vk;

use crate::render::{DisplayOutput, GpuScene, RenderTarget, Renderer};
use crate::scene::Scene;
use crate::vk::{transition, Acquired, CommandPool, Device, Fence, ImageUse, Semaphore, Swapchain};

/// Two frames in flight: the CPU records one while the GPU renders the other.
pub const FRAMES_IN_FLIGHT: usize = 2;

struct Slot {
    cmd: vk::CommandBuffer,
    done: Fence,
    image_acquired: Semaphore,
    target: RenderTarget,
}

pub struct FrameLoop {
    slots: Vec<Slot>,
    // Owns the slots' command buffers.
    _pool: CommandPool,
    swapchain: Option<Swapchain>,
    wanted: vk::Extent2D,
    stale: bool,
    frame: u64,
    gpu: GpuScene,
    renderer: Renderer,
    device: Arc<Device>,
}

impl FrameLoop {
    pub fn new(device: Arc<Device>, scene: &Scene, size: vk::Extent2D) -> Result<Self> {
        let renderer = Renderer::new(device.clone(), FRAMES_IN_FLIGHT as u32)?;
        let gpu = renderer.upload(scene)?;
        let pool = CommandPool::new(&device)?;
        let cmds = pool.allocate(FRAMES_IN_FLIGHT as u32)?;
        let swapchain = Swapchain::new(&device, size, None)?;
        let slots = cmds
            .into_iter()
            .map(|cmd| {
                Ok(Slot {
                    cmd,
                    done: Fence::new(&device, true)?,
                    image_acquired: Semaphore::new(&device)?,
                    target: RenderTarget::new(&device, swapchain.extent)?,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self { slots, _pool: pool, swapchain: Some(swapchain), wanted: size, stale: false, frame: 0, gpu, renderer, device })
    }

    pub fn frame_count(&self) -> u64 {
        self.frame
    }

    pub fn resize(&mut self, size: vk::Extent2D) {
        self.wanted = size;
        self.stale = true;
    }

    fn recreate(&mut self) -> Result<()> {
        self.device.wait_idle()?;
        let old = self.swapchain.take();
        let swapchain = Swapchain::new(&self.device, self.wanted, old.as_ref())?;
        drop(old);
        for slot in &mut self.slots {
            slot.target = RenderTarget::new(&self.device, swapchain.extent)?;
        }
        self.swapchain = Some(swapchain);
        self.stale = false;
        Ok(())
    }

    /// Draws one frame; does nothing while the window has no area (minimised).
    pub fn draw(&mut self, scene: &Scene, exposure: f32) -> Result<()> {
        if self.wanted.width == 0 || self.wanted.height == 0 {
            return Ok(());
        }
        if self.stale {
            self.recreate()?;
        }
        let index = (self.frame % FRAMES_IN_FLIGHT as u64) as usize;
        self.slots[index].done.wait()?;
        let Some(swapchain) = self.swapchain.as_ref() else { bail!("no swapchain") };
        let image = match swapchain.acquire(self.slots[index].image_acquired.handle)? {
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(());
            }
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index as usize
            }
        };
        let slot = &self.slots[index];
        slot.done.reset()?;
        self.renderer.prepare(index, scene, &slot.target, swapchain.format)?;

        let d = &self.device.handle;
        unsafe {
            d.reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty())?;
            d.begin_command_buffer(slot.cmd, &vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT))?;
        }
        let output = DisplayOutput {
            image: swapchain.images[image],
            view: swapchain.views[image],
            format: swapchain.format,
            extent: swapchain.extent,
            from: ImageUse::ACQUIRED,
        };
        self.renderer.record(slot.cmd, index, scene, &self.gpu, &slot.target, &output, exposure)?;
        transition(&self.device, slot.cmd, output.image, vk::ImageAspectFlags::COLOR, ImageUse::COLOR_ATTACHMENT, ImageUse::PRESENT);
        unsafe { d.end_command_buffer(slot.cmd)? };

        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(slot.image_acquired.handle)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.ready_to_present[image].handle)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(slot.cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals);
        self.device.submit(&[submit], slot.done.handle)?;
        if !swapchain.present(image as u32)? {
            self.stale = true;
        }
        self.frame += 1;
        Ok(())
    }

    /// Waits for the GPU and reports validation errors of the session as an error.
    pub fn finish(&self) -> Result<()> {
        self.device.wait_idle()?;
        if let Some(report) = self.device.validation() {
            if report.error_count() > 0 {
                bail!("the validation layer reported {} error(s)", report.error_count());
            }
        }
        Ok(())
    }
}

impl Drop for FrameLoop {
    fn drop(&mut self) {
        // Fences, semaphores and targets may still be in use by the last frames.
        let _ = self.device.wait_idle();
    }
}
