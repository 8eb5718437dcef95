//! Frames in flight on a swapchain: each slot has its command buffer, fence, acquire
//! semaphore, HDR target, UI timestamps and pending screenshot; the swapchain has one
//! present semaphore per image. A frame is the renderer's (forward, tone map into the
//! swapchain image) followed by the UI pass over it.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use ash::vk;
use egui::{ClippedPrimitive, TexturesDelta};

use super::overlay::Overlay;
use crate::atomic::{write_atomically, Existing};
use crate::render::accumulate::{Accumulation, CONVERGED_LOOKUPS};
use crate::render::environment::equirect::Equirect;
use crate::render::{DebugView, DisplayOutput, GpuScene, OffscreenFrame, RenderTarget, Renderer, PASS_NAMES};
use crate::render::warm_up::warm_up;
use crate::scene::{Environment, PendingMaps, Scene};
use crate::vk::{
    transition, Acquired, CommandPool, Device, Fence, ImageRegion, ImageUse, Readback, Semaphore, Swapchain, Timestamps,
};

/// Two frames in flight: the CPU records one while the GPU renders the other.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Names of the GPU times [`FrameLoop::gpu_ms`] reports: the renderer's passes, then the UI.
pub fn gpu_pass_names() -> Vec<&'static str> {
    PASS_NAMES.iter().copied().chain(["ui"]).collect()
}

/// When a frame's swapchain image is copied for a screenshot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaptureStage {
    /// The tone-mapped frame alone.
    BeforeUi,
    /// What the window shows.
    AfterUi,
}

/// A screenshot request for one frame.
pub struct Capture {
    pub path: PathBuf,
    pub existing: Existing,
    pub stage: CaptureStage,
}

/// The UI of one frame, tessellated by egui.
pub struct UiFrame {
    pub primitives: Vec<ClippedPrimitive>,
    pub textures: TexturesDelta,
    pub pixels_per_point: f32,
}

/// A screenshot being copied: written once its slot's fence has signalled.
struct PendingCapture {
    readback: Readback,
    path: PathBuf,
    existing: Existing,
    format: vk::Format,
    /// The part of the image written (the frame alone leaves out the panel's place).
    crop: vk::Rect2D,
}

struct Slot {
    cmd: vk::CommandBuffer,
    done: Fence,
    image_acquired: Semaphore,
    target: RenderTarget,
    ui_timestamps: Option<Timestamps>,
    /// Whether a frame was submitted with this slot, so its queries hold results.
    submitted: bool,
    /// The output pixels per HDR texel of its last frame.
    scale: u32,
    capture: Option<PendingCapture>,
}

pub struct FrameLoop {
    // Dropped before the device; `Drop` waits for the GPU first.
    overlay: Overlay,
    slots: Vec<Slot>,
    // Owns the slots' command buffers.
    _pool: CommandPool,
    swapchain: Option<Swapchain>,
    wanted: vk::Extent2D,
    /// Pixels left of the frame, where the UI panel is.
    frame_left: u32,
    /// Output pixels per HDR texel of the next frame (see [`FrameLoop::set_scale`]).
    scale: u32,
    /// Frames drawn at a scale above 1.
    reduced_frames: u64,
    /// GPU milliseconds, all passes, of the last completed frame drawn at scale 1, and of
    /// the last drawn at a larger scale.
    full_gpu_ms: Option<f64>,
    reduced_gpu_ms: Option<f64>,
    stale: bool,
    /// Frames submitted so far; frame `n` uses slot `n % FRAMES_IN_FLIGHT`.
    frame: u64,
    recreations: u64,
    gpu: GpuScene,
    /// The builtin maps the start left as stand-ins, as no frame sampled them, until one
    /// does ([`FrameLoop::make_sampled_maps`]).
    unsampled: Option<PendingMaps>,
    pub renderer: Renderer,
    gpu_ms: Option<Vec<f64>>,
    /// Screenshots written (or failed) since the last [`FrameLoop::take_screenshots`].
    screenshots: Vec<(PathBuf, Result<()>)>,
    device: Arc<Device>,
}

impl FrameLoop {
    pub fn new(device: Arc<Device>, scene: &Scene, size: vk::Extent2D) -> Result<Self> {
        let mut renderer = Renderer::new(device.clone(), FRAMES_IN_FLIGHT as u32)?;
        // A still view of the sampled reflection refines until it has converged.
        renderer.accumulation = Accumulation::UpTo(CONVERGED_LOOKUPS);
        let gpu = renderer.upload(scene)?;
        let pool = CommandPool::new(&device)?;
        let cmds = pool.allocate(FRAMES_IN_FLIGHT as u32)?;
        let swapchain = Swapchain::new(&device, size, None)?;
        let overlay = Overlay::new(&device, swapchain.format, FRAMES_IN_FLIGHT)?;
        let slots = cmds
            .into_iter()
            .map(|cmd| {
                Ok(Slot {
                    cmd,
                    done: Fence::new(&device, true)?,
                    image_acquired: Semaphore::new(&device)?,
                    target: RenderTarget::new(&device, swapchain.extent)?,
                    ui_timestamps: Timestamps::new(&device, 1)?,
                    submitted: false,
                    scale: 1,
                    capture: None,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            overlay,
            slots,
            _pool: pool,
            swapchain: Some(swapchain),
            wanted: size,
            frame_left: 0,
            scale: 1,
            reduced_frames: 0,
            full_gpu_ms: None,
            reduced_gpu_ms: None,
            stale: false,
            frame: 0,
            recreations: 0,
            gpu,
            unsampled: None,
            renderer,
            gpu_ms: None,
            screenshots: Vec::new(),
            device,
        })
    }

    /// Draws a warm-up frame of `scene`, uploaded with stand-ins for its builtin `maps`,
    /// while the maps its frames sample are made, and puts them in the scene and its upload
    /// (src/render/warm_up.rs); the others wait for a frame that samples them.
    pub fn warm_up(&mut self, scene: &mut Scene, mut maps: PendingMaps) -> Result<()> {
        let sampled = self.renderer.sampled_textures(scene);
        self.unsampled = Some(maps.split_off(|texture| !sampled[texture])).filter(|m| !m.is_empty());
        let frames = self.frame_area().extent;
        warm_up(&mut self.renderer, scene, &mut self.gpu, maps, false, frames).map(drop)
    }

    /// Makes the builtin maps left as stand-ins that the next frame of `scene` samples (as
    /// the report's reflection samples the noise map), or all of them with `every`, and
    /// puts them in the scene and its upload, once the frames in flight are done.
    pub fn make_sampled_maps(&mut self, scene: &mut Scene, every: bool) -> Result<()> {
        let Some(unsampled) = self.unsampled.as_mut() else {
            return Ok(());
        };
        let sampled = self.renderer.sampled_textures(scene);
        let now = unsampled.split_off(|texture| every || sampled[texture]);
        if unsampled.is_empty() {
            self.unsampled = None;
        }
        if now.is_empty() {
            return Ok(());
        }
        let (start, indices) = (Instant::now(), now.stand_ins());
        now.finish(scene)?;
        self.device.wait_idle()?;
        self.renderer.replace_textures(&mut self.gpu, scene, &indices)?;
        let names: Vec<&str> = indices.iter().map(|&i| scene.textures[i].name.as_str()).collect();
        eprintln!(
            "argil: made {}, which no frame had sampled, in {} ms",
            names.join(", "),
            start.elapsed().as_millis()
        );
        Ok(())
    }

    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    pub fn frame_count(&self) -> u64 {
        self.frame
    }

    pub fn recreations(&self) -> u64 {
        self.recreations
    }

    /// GPU milliseconds per pass ([`gpu_pass_names`]) of the last completed frame.
    pub fn gpu_ms(&self) -> Option<&[f64]> {
        self.gpu_ms.as_deref()
    }

    /// The screenshots written since the last call, with their outcome.
    pub fn take_screenshots(&mut self) -> Vec<(PathBuf, Result<()>)> {
        std::mem::take(&mut self.screenshots)
    }

    pub fn resize(&mut self, size: vk::Extent2D) {
        self.wanted = size;
        self.stale = true;
    }

    /// Draws the frame right of `left` pixels (the UI panel's place); its camera aspect
    /// follows. Applied with the next frame.
    pub fn set_frame_left(&mut self, left: u32) {
        self.frame_left = left;
    }

    /// Draws the next frames at 1/`scale` of the frame area's resolution, each texel shown
    /// as `scale`×`scale` pixels: cheap frames while the UI is in use.
    pub fn set_scale(&mut self, scale: u32) {
        self.scale = scale.max(1);
    }

    /// The scale of the next frame.
    pub fn scale(&self) -> u32 {
        self.scale
    }

    /// Frames drawn so far at a scale above 1.
    pub fn reduced_frames(&self) -> u64 {
        self.reduced_frames
    }

    /// GPU milliseconds, every pass, of the last completed full-resolution frame.
    pub fn full_gpu_ms(&self) -> Option<f64> {
        self.full_gpu_ms
    }

    /// The same of the last completed frame at reduced resolution.
    pub fn reduced_gpu_ms(&self) -> Option<f64> {
        self.reduced_gpu_ms
    }

    /// Where the frame of the next draw goes in the window, in pixels.
    pub fn frame_area(&self) -> vk::Rect2D {
        let extent = self.swapchain.as_ref().map_or(self.wanted, |s| s.extent);
        // At least one pixel wide, so that a panel as wide as the window leaves a target.
        let left = self.frame_left.min(extent.width.saturating_sub(1));
        vk::Rect2D {
            offset: vk::Offset2D { x: left as i32, y: 0 },
            extent: vk::Extent2D {
                width: extent.width - left,
                height: extent.height,
            },
        }
    }

    /// Whether the window has an area to draw into (not while minimised).
    pub fn has_area(&self) -> bool {
        self.wanted.width > 0 && self.wanted.height > 0
    }

    /// Renders the shaded `scene` offscreen at `extent` and reads it back, once the frames
    /// in flight are done (the viewer's reference compares it): no split, no debug view, not
    /// a draft.
    pub fn render_still(&mut self, scene: &Scene, extent: vk::Extent2D, exposure: f32) -> Result<OffscreenFrame> {
        self.device.wait_idle()?;
        let split = self.renderer.split.take();
        let debug_view = std::mem::replace(&mut self.renderer.debug_view, DebugView::Shaded);
        self.renderer.draft = false;
        let frame = self.renderer.render_offscreen(scene, &self.gpu, extent, exposure);
        (self.renderer.split, self.renderer.debug_view) = (split, debug_view);
        frame
    }

    /// Replaces the scene's meshes and textures on the GPU and its environment map with `map`,
    /// as the viewer decoded it to check it (after a reload, or an edit of what the scene loads).
    pub fn set_scene(&mut self, scene: &Scene, map: Option<Equirect>) -> Result<()> {
        self.device.wait_idle()?;
        self.use_environment_map(scene, map);
        self.gpu = self.renderer.upload(scene)?;
        // A scene loaded again comes with its maps made.
        self.unsampled = None;
        Ok(())
    }

    /// Has the renderer build `scene`'s environment from `map`, the file it names as decoded,
    /// rather than decoding it again.
    pub fn use_environment_map(&mut self, scene: &Scene, map: Option<Equirect>) {
        if let (Environment::Map { path, .. }, Some(map)) = (&scene.environment, map) {
            self.renderer.use_environment_map(path.clone(), map);
        }
    }

    fn recreate(&mut self) -> Result<()> {
        self.device.wait_idle()?;
        let old = self.swapchain.take();
        let swapchain = Swapchain::new(&self.device, self.wanted, old.as_ref())?;
        drop(old);
        self.overlay.set_format(swapchain.format)?;
        self.swapchain = Some(swapchain);
        self.resize_targets()?;
        self.stale = false;
        self.recreations += 1;
        Ok(())
    }

    /// Makes every slot's HDR target the size of the frame area, divided by the scale.
    fn resize_targets(&mut self) -> Result<()> {
        let area = self.frame_area().extent;
        let extent = vk::Extent2D {
            width: area.width.div_ceil(self.scale),
            height: area.height.div_ceil(self.scale),
        };
        if self.slots.iter().all(|s| s.target.extent == extent) {
            return Ok(());
        }
        self.device.wait_idle()?;
        for slot in &mut self.slots {
            slot.target = RenderTarget::new(&self.device, extent)?;
        }
        Ok(())
    }

    /// What a slot's last frame left once its fence has signalled: GPU times, a screenshot.
    fn collect(&mut self, index: usize) -> Result<()> {
        let slot = &mut self.slots[index];
        if slot.submitted {
            let passes = self.renderer.gpu_times(index)?;
            let ui = slot.ui_timestamps.as_ref().map(Timestamps::read_ms).transpose()?;
            self.gpu_ms = passes.zip(ui).map(|(p, u)| p.into_iter().chain(u).collect());
            let last = if slot.scale == 1 {
                &mut self.full_gpu_ms
            } else {
                &mut self.reduced_gpu_ms
            };
            *last = self.gpu_ms.as_ref().map(|ms| ms.iter().sum()).or(*last);
        }
        if let Some(capture) = slot.capture.take() {
            let written = write_screenshot(&capture);
            self.screenshots.push((capture.path, written));
        }
        Ok(())
    }

    /// Draws one frame with `ui` over it; returns whether a frame was submitted (not while
    /// the window has no area, nor when the swapchain turned out to be out of date).
    pub fn draw(&mut self, scene: &Scene, exposure: f32, ui: UiFrame, capture: Option<Capture>) -> Result<bool> {
        self.overlay.update_textures(self.frame, ui.textures)?;
        if !self.has_area() {
            return Ok(false);
        }
        if self.stale {
            self.recreate()?;
        }
        self.resize_targets()?;
        let area = self.frame_area();
        let index = (self.frame % FRAMES_IN_FLIGHT as u64) as usize;
        self.slots[index].done.wait()?;
        self.collect(index)?;
        // Frame `frame - FRAMES_IN_FLIGHT` used this slot, so it and every frame before it are done.
        if let Some(completed) = self.frame.checked_sub(FRAMES_IN_FLIGHT as u64) {
            self.overlay.free_textures(completed)?;
        }
        let Some(swapchain) = self.swapchain.as_ref() else {
            bail!("no swapchain")
        };
        let image = match swapchain.acquire(self.slots[index].image_acquired.handle)? {
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(false);
            }
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index as usize
            }
        };
        let (format, extent) = (swapchain.format, swapchain.extent);
        let output = DisplayOutput {
            image: swapchain.images[image],
            view: swapchain.views[image],
            format,
            area,
            from: ImageUse::ACQUIRED,
            exposure,
            scale: self.scale,
        };
        let region = ImageRegion {
            handle: output.image,
            extent,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let readback = capture
            .map(|c| {
                Ok::<_, anyhow::Error>((
                    c.stage,
                    PendingCapture {
                        readback: Readback::new(&self.device, region, 4)?,
                        path: c.path,
                        existing: c.existing,
                        format,
                        crop: match c.stage {
                            CaptureStage::BeforeUi => area,
                            CaptureStage::AfterUi => vk::Rect2D {
                                offset: vk::Offset2D::default(),
                                extent,
                            },
                        },
                    },
                ))
            })
            .transpose()?;

        let slot = &mut self.slots[index];
        slot.done.reset()?;
        self.renderer.draft = self.scale > 1;
        self.renderer.prepare(index, scene, &self.gpu, &slot.target, format)?;
        let d = &self.device.handle;
        let cmd = slot.cmd;
        unsafe {
            d.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
            d.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )?;
        }
        if let Some(t) = &slot.ui_timestamps {
            t.reset(cmd);
        }
        self.renderer
            .record(cmd, index, scene, &self.gpu, &slot.target, Some(&output))?;

        // The tone-mapped image is a colour attachment here; a capture leaves it a transfer source.
        let copy = |stage: CaptureStage| -> ImageUse {
            match &readback {
                Some((s, c)) if *s == stage => {
                    c.readback.record(&self.device, cmd, region, ImageUse::COLOR_ATTACHMENT);
                    ImageUse::TRANSFER_SRC
                }
                _ => ImageUse::COLOR_ATTACHMENT,
            }
        };
        // The UI loads what the tone-map pass stored.
        let before_ui = copy(CaptureStage::BeforeUi);
        transition(
            &self.device,
            cmd,
            output.image,
            vk::ImageAspectFlags::COLOR,
            before_ui,
            ImageUse::COLOR_ATTACHMENT,
        );
        if let Some(t) = &slot.ui_timestamps {
            t.begin(cmd, 0);
        }
        self.overlay
            .record(cmd, output.view, extent, ui.pixels_per_point, &ui.primitives)?;
        if let Some(t) = &slot.ui_timestamps {
            t.end(cmd, 0);
        }
        let after_ui = copy(CaptureStage::AfterUi);
        transition(
            &self.device,
            cmd,
            output.image,
            vk::ImageAspectFlags::COLOR,
            after_ui,
            ImageUse::PRESENT,
        );
        unsafe { d.end_command_buffer(cmd)? };

        let Some(swapchain) = self.swapchain.as_ref() else {
            bail!("no swapchain")
        };
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(slot.image_acquired.handle)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.ready_to_present[image].handle)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals);
        self.device.submit(&[submit], slot.done.handle)?;
        slot.submitted = true;
        slot.scale = self.scale;
        self.reduced_frames += u64::from(self.scale > 1);
        slot.capture = readback.map(|(_, c)| c);
        if !swapchain.present(image as u32)? {
            self.stale = true;
        }
        self.frame += 1;
        Ok(true)
    }

    /// Waits for the GPU, writes pending screenshots and reports validation errors of the
    /// session as an error.
    pub fn finish(&mut self) -> Result<()> {
        self.device.wait_idle()?;
        for index in 0..self.slots.len() {
            self.collect(index)?;
        }
        self.overlay.free_textures(u64::MAX)?;
        if let Some(report) = self.device.validation() {
            if report.error_count() > 0 {
                bail!("the validation layer reported {} error(s)", report.error_count());
            }
        }
        Ok(())
    }
}

/// RGBA8 from a swapchain image's bytes (B8G8R8A8 formats swap red and blue), opaque.
pub fn display_rgba(bytes: &[u8], format: vk::Format) -> Vec<u8> {
    let bgra = matches!(format, vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM);
    bytes
        .chunks_exact(4)
        .flat_map(|p| {
            if bgra {
                [p[2], p[1], p[0], 255]
            } else {
                [p[0], p[1], p[2], 255]
            }
        })
        .collect()
}

fn write_screenshot(capture: &PendingCapture) -> Result<()> {
    let extent = capture.readback.extent;
    let rgba = display_rgba(capture.readback.bytes()?, capture.format);
    let image =
        image::RgbaImage::from_raw(extent.width, extent.height, rgba).context("screenshot has the wrong size")?;
    let crop = capture.crop;
    let image = image::imageops::crop_imm(
        &image,
        crop.offset.x as u32,
        crop.offset.y as u32,
        crop.extent.width,
        crop.extent.height,
    )
    .to_image();
    let format = image::ImageFormat::from_path(&capture.path)
        .with_context(|| format!("cannot write {}", capture.path.display()))?;
    write_atomically(&capture.path, capture.existing, |sink| Ok(image.write_to(sink, format)?))
}

impl Drop for FrameLoop {
    fn drop(&mut self) {
        // Fences, semaphores, targets and UI buffers may still be in use by the last frames.
        let _ = self.device.wait_idle();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swapchain_bytes_become_opaque_rgba() {
        let bytes = [10, 20, 30, 0, 1, 2, 3, 128];
        assert_eq!(
            display_rgba(&bytes, vk::Format::B8G8R8A8_SRGB),
            vec![30, 20, 10, 255, 3, 2, 1, 255]
        );
        assert_eq!(
            display_rgba(&bytes, vk::Format::R8G8B8A8_SRGB),
            vec![10, 20, 30, 255, 1, 2, 3, 255]
        );
    }

    #[test]
    fn gpu_times_name_every_pass_and_the_ui() {
        assert_eq!(
            gpu_pass_names(),
            vec![
                "forward",
                "skybox",
                "tonemap",
                "shadow",
                "resolve",
                "occlusion",
                "accumulate",
                "exposure",
                "ui"
            ]
        );
    }
}
