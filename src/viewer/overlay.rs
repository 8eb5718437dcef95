//! The UI drawn over the swapchain image: egui-ash-renderer in dynamic-rendering mode,
//! texture updates before a frame, texture frees after the frame that freed them.

use std::sync::{Arc, Mutex};

use anyhow::{Context, Result};
use ash::vk;
use egui::{ClippedPrimitive, TextureId, TexturesDelta};
use egui_ash_renderer::allocator::GpuAllocator;
use egui_ash_renderer::{DynamicRendering, Options, RenderMode};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::AllocationSizes;

use crate::render::tonemap::is_srgb;
use crate::vk::{begin_full_rendering, CommandPool, Device};

/// Memory blocks of the UI's allocator: its font atlas and vertex buffers are a few MiB.
const UI_MEMORY_BLOCK: u64 = 8 << 20;

fn render_mode(format: vk::Format) -> RenderMode {
    RenderMode::DynamicRendering(DynamicRendering {
        color_attachment_format: format,
        depth_attachment_format: None,
        stencil_attachment_format: None,
    })
}

pub struct Overlay {
    // Dropped first: it frees its buffers and textures through its allocator and the device.
    renderer: egui_ash_renderer::Renderer<GpuAllocator>,
    /// Textures egui released with frame N, destroyed once frame N has completed.
    pending_frees: Vec<(u64, TextureId)>,
    format: vk::Format,
    /// Command buffers of the renderer's texture uploads.
    upload_pool: CommandPool,
    device: Arc<Device>,
}

impl Overlay {
    /// `frames_in_flight` is the real count: the renderer keeps one vertex buffer per frame.
    pub fn new(device: &Arc<Device>, format: vk::Format, frames_in_flight: usize) -> Result<Self> {
        // An allocator of its own: the renderer holds it in an Arc for its whole life, while
        // the device's allocator must be gone before the device is destroyed.
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: device.instance.handle.clone(),
            device: device.handle.clone(),
            physical_device: device.physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: AllocationSizes::new(UI_MEMORY_BLOCK, UI_MEMORY_BLOCK),
        })
        .context("cannot create the UI's memory allocator")?;
        let options = Options {
            in_flight_frames: frames_in_flight,
            enable_depth_test: false,
            enable_depth_write: false,
            srgb_framebuffer: is_srgb(format),
        };
        let renderer = egui_ash_renderer::Renderer::with_gpu_allocator(
            Arc::new(Mutex::new(allocator)),
            device.handle.clone(),
            render_mode(format),
            options,
        )
        .context("cannot create the UI renderer")?;
        Ok(Self {
            renderer,
            pending_frees: Vec::new(),
            format,
            upload_pool: CommandPool::new(device)?,
            device: device.clone(),
        })
    }

    /// Rebuilds the pipeline for a new swapchain format (the GPU must be idle).
    pub fn set_format(&mut self, format: vk::Format) -> Result<()> {
        if format != self.format {
            // The sRGB option is fixed at creation, so a change between sRGB and UNORM needs a new renderer.
            anyhow::ensure!(
                is_srgb(format) == is_srgb(self.format),
                "the swapchain changed its sRGB encoding"
            );
            self.renderer
                .set_render_mode(render_mode(format))
                .context("cannot rebuild the UI pipeline")?;
            self.format = format;
        }
        Ok(())
    }

    /// Uploads the textures egui changed for frame `frame`, and schedules the ones it
    /// released to be destroyed after that frame.
    pub fn update_textures(&mut self, frame: u64, mut delta: TexturesDelta) -> Result<()> {
        if !delta.set.is_empty() {
            // An update may rewrite the font atlas that frames in flight are sampling.
            self.device.wait_idle()?;
            for (id, deltas) in delta.set.drain() {
                for image in &deltas {
                    self.renderer
                        .set_texture(self.device.queue, self.upload_pool.handle, id, image)
                        .context("cannot upload a UI texture")?;
                }
            }
        }
        self.pending_frees.extend(delta.free.drain().map(|id| (frame, id)));
        Ok(())
    }

    /// Destroys the textures released with frames up to `completed`, which the GPU has finished.
    pub fn free_textures(&mut self, completed: u64) -> Result<()> {
        let (done, pending): (Vec<_>, Vec<_>) = self.pending_frees.drain(..).partition(|(f, _)| *f <= completed);
        self.pending_frees = pending;
        for (_, id) in done {
            self.renderer.free_texture(id).context("cannot free a UI texture")?;
        }
        Ok(())
    }

    /// Records the UI over `view`, which is a colour attachment whose content is kept.
    pub fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        view: vk::ImageView,
        extent: vk::Extent2D,
        pixels_per_point: f32,
        primitives: &[ClippedPrimitive],
    ) -> Result<()> {
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        begin_full_rendering(&self.device, cmd, extent, &color, None);
        let drawn = self.renderer.cmd_draw(cmd, extent, pixels_per_point, primitives);
        unsafe { self.device.handle.cmd_end_rendering(cmd) };
        drawn.context("cannot record the UI")
    }
}
