//! Progressive accumulation of the `sampled` reflection: while nothing that the frame shows
//! changes, each frame draws the next sample set (shaders/lib/environment.glsl rotates the
//! lookups by point k of R2) and `accumulate.comp` folds it into a running mean in linear
//! HDR, which it writes back over the frame before the display transform. Any change of the
//! view (camera, scene, materials, lights, size, debug view, shadows) starts a new mean.
//!
//! Set 0: binding 0 the frame's HDR target, binding 1 the mean, both storage images in
//! `GENERAL`; push constant: the frames already in the mean.

use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::debug_view::DebugView;
use super::gpu_scene::GpuScene;
use super::shaders;
use super::split::Split;
use super::target::{RenderTarget, HDR_FORMAT};
use crate::scene::{Antialiasing, Camera, Environment, Material, Object, Occlusion, PointLight, ReflectionMode, Scene};
use crate::vk::{
    transition, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device, Image,
    ImageUse, Pipeline, PipelineLayout, ShaderModule, Specialization,
};

/// Lookups per pixel at which the viewer's still view counts as converged: it stops
/// drawing, and frames drawn after (for the UI) show the mean as it is. 16 frames at the
/// default 64 lookups, a quarter of one frame's noise.
pub const CONVERGED_LOOKUPS: u64 = 1024;

/// Which frames join the running mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accumulation {
    /// Every frame is drawn alone (`argil render`, the bench).
    Off,
    /// Every frame of a still view joins the mean.
    Unlimited,
    /// Frames join until the mean holds this many lookups per pixel; later frames of the
    /// view show the mean unchanged.
    UpTo(u64),
}

/// `accumulate.comp`'s workgroups are 8×8 pixels.
const GROUP: u32 = 8;
/// `HOLD` in accumulate.comp: the frame shows the mean without joining it.
const HOLD: u32 = u32::MAX;

/// The mean's old contents are discarded by the first frame of a view, but the previous
/// view's last accumulation (possibly another frame in flight) must be done with it first.
const DISCARDED: ImageUse = ImageUse {
    layout: vk::ImageLayout::UNDEFINED,
    ..ImageUse::COMPUTE_STORAGE
};

/// The running mean after `frames_before` values with mean `mean_before`, and one more,
/// `value`: `accumulate.comp`'s `running_mean`.
pub fn running_mean(mean_before: f64, value: f64, frames_before: u32) -> f64 {
    mean_before + (value - mean_before) / f64::from(frames_before + 1)
}

/// Everything a frame's image depends on, compared frame to frame: equal, the new frame
/// joins the mean; different, the mean starts again.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Which upload of the meshes and textures (a new one for every reload or rebuild).
    upload: u64,
    extent: vk::Extent2D,
    camera: Camera,
    lights: Vec<PointLight>,
    shadow_resolution: u32,
    shadow_taps: u32,
    bounce: bool,
    shadow_ground_map: bool,
    environment: Environment,
    objects: Vec<Object>,
    materials: Vec<Material>,
    antialiasing: Antialiasing,
    occlusion: Occlusion,
    debug_view: DebugView,
    /// The renderer's switches: shadows, the floor pipeline, the generic pipelines, the
    /// scene's occlusion.
    switches: [bool; 4],
    /// What a split frame's right part is drawn with.
    split: Option<Split>,
}

impl View {
    /// The view of a frame, or `None` when accumulating would not change its image: no
    /// environment, a reflection mode other than `sampled`, or a debug view that does not
    /// show the environment's light.
    pub fn of(
        scene: &Scene,
        gpu: &GpuScene,
        extent: vk::Extent2D,
        debug_view: DebugView,
        switches: [bool; 4],
        split: Option<&Split>,
    ) -> Option<Self> {
        let sampled = scene.environment.reflection().map(|r| r.mode) == Some(ReflectionMode::Sampled);
        (sampled && debug_view.shows_environment()).then(|| Self {
            upload: gpu.id,
            extent,
            camera: scene.camera,
            lights: scene.lights.clone(),
            shadow_resolution: scene.shadow_resolution,
            shadow_taps: scene.shadow_taps,
            bounce: scene.bounce,
            shadow_ground_map: scene.shadow_ground_map,
            environment: scene.environment.clone(),
            objects: scene.objects.clone(),
            materials: scene.materials.clone(),
            antialiasing: scene.antialiasing,
            occlusion: scene.occlusion,
            debug_view,
            switches,
            split: split.cloned(),
        })
    }

    /// Environment lookups per pixel of one frame.
    fn lookups(&self) -> u32 {
        self.environment.reflection().map_or(0, |r| r.samples)
    }
}

/// How far the mean of the current view has come.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Accumulated {
    /// Frames in the mean, this one included.
    pub frames: u32,
    /// Environment lookups per pixel of each frame.
    pub lookups_per_frame: u32,
}

impl Accumulated {
    /// Environment lookups per pixel in the mean.
    pub fn lookups(&self) -> u64 {
        u64::from(self.frames) * u64::from(self.lookups_per_frame)
    }

    /// Whether more frames would still refine the image noticeably.
    pub fn converging(&self) -> bool {
        self.lookups() < CONVERGED_LOOKUPS
    }

    /// Whether the mean has as many lookups per pixel as `accumulation` lets it have.
    fn full(&self, accumulation: Accumulation) -> bool {
        matches!(accumulation, Accumulation::UpTo(limit) if self.lookups() >= limit)
    }
}

pub struct AccumulatePass {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    pipeline: Pipeline,
    /// Owns `sets`.
    _pool: DescriptorPool,
    /// One set per frame in flight: its target and the mean.
    sets: Vec<vk::DescriptorSet>,
    /// The running mean, the size of the targets.
    mean: Option<Image>,
    /// The view the mean holds, and how many frames of it.
    view: Option<View>,
    frames: u32,
    /// Per frame in flight: the frames before it in the mean (or `HOLD`), when it
    /// accumulates.
    pending: Vec<Option<u32>>,
}

impl AccumulatePass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let set_layout = (0..2)
            .fold(DescriptorSetLayoutBuilder::default(), |b, _| {
                b.binding(vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE)
            })
            .build(device, "accumulate set")?;
        let layout = PipelineLayout::new(device, &[&set_layout], 4, vk::ShaderStageFlags::COMPUTE)?;
        let shader = ShaderModule::new(device, shaders::ACCUMULATE_COMP, "accumulate.comp")?;
        let pipeline = Pipeline::compute(device, &layout, &shader, &Specialization::default(), "accumulate")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let sets = (0..frames_in_flight)
            .map(|_| pool.allocate(&set_layout))
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            _set_layout: set_layout,
            layout,
            pipeline,
            _pool: pool,
            sets,
            mean: None,
            view: None,
            frames: 0,
            pending: vec![None; frames_in_flight as usize],
        })
    }

    /// Makes `slot`'s frame (whose previous use the caller has waited for) the next of
    /// `view`'s mean, or a mean of its own when the view changed; `None` renders the frame
    /// alone, as `argil render` does. Returns the frame's sample set.
    pub fn prepare(
        &mut self,
        slot: usize,
        view: Option<View>,
        accumulation: Accumulation,
        target: &RenderTarget,
    ) -> Result<u32> {
        let Some(view) = view.filter(|_| accumulation != Accumulation::Off) else {
            self.reset();
            self.pending[slot] = None;
            return Ok(0);
        };
        if self.view.as_ref() != Some(&view) {
            self.frames = 0;
        }
        if self.mean.as_ref().is_none_or(|m| m.extent != target.extent) {
            // Resizes are rare; the other frames in flight may still use the old mean.
            self.device.wait_idle()?;
            self.mean = Some(Image::new_2d(
                &self.device,
                target.extent,
                HDR_FORMAT,
                vk::ImageUsageFlags::STORAGE,
                vk::ImageAspectFlags::COLOR,
                "accumulated mean",
            )?);
        }
        let mean = self.mean.as_ref().map_or(vk::ImageView::null(), |m| m.view);
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::STORAGE_IMAGE,
                target.color.view,
                vk::ImageLayout::GENERAL,
                vk::Sampler::null(),
            )
            .image(
                1,
                vk::DescriptorType::STORAGE_IMAGE,
                mean,
                vk::ImageLayout::GENERAL,
                vk::Sampler::null(),
            )
            .write(&self.device, self.sets[slot]);
        self.view = Some(view);
        if self.accumulated().is_some_and(|a| a.full(accumulation)) {
            self.pending[slot] = Some(HOLD);
            return Ok(0);
        }
        let sample_set = self.frames;
        self.pending[slot] = Some(sample_set);
        self.frames += 1;
        Ok(sample_set)
    }

    /// Starts the next frame's mean afresh even if its view is the last one's (another
    /// target of the same size).
    pub fn reset(&mut self) {
        self.view = None;
        self.frames = 0;
    }

    /// How far the mean of the frame prepared last has come; `None` when it is not accumulated.
    pub fn accumulated(&self) -> Option<Accumulated> {
        self.view.as_ref().map(|v| Accumulated {
            frames: self.frames,
            lookups_per_frame: v.lookups(),
        })
    }

    /// Records the accumulation of `slot`'s frame, whose target's colour the forward pass
    /// and the skybox have just written as an attachment; returns the use it leaves the
    /// colour in (unchanged when the frame is not accumulated).
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize, target: &RenderTarget) -> Result<ImageUse> {
        let (Some(frames_before), Some(mean)) = (self.pending[slot], &self.mean) else {
            return Ok(ImageUse::COLOR_ATTACHMENT);
        };
        let d = &self.device;
        // This frame's radiance, written as an attachment, is read and rewritten as storage.
        transition(
            d,
            cmd,
            target.color.handle,
            target.color.aspect,
            ImageUse::COLOR_ATTACHMENT,
            ImageUse::COMPUTE_STORAGE,
        );
        // The previous frame's accumulation, earlier on the queue and perhaps from the
        // other frame in flight, wrote the mean (a held frame reads it, but a read after a
        // write needs the same barrier); a new view's first frame discards it.
        let mean_before = if frames_before == 0 {
            DISCARDED
        } else {
            ImageUse::COMPUTE_STORAGE
        };
        transition(d, cmd, mean.handle, mean.aspect, mean_before, ImageUse::COMPUTE_STORAGE);
        let h = &d.handle;
        unsafe {
            h.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.handle);
            h.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.handle,
                0,
                &[self.sets[slot]],
                &[],
            );
            h.cmd_push_constants(
                cmd,
                self.layout.handle,
                vk::ShaderStageFlags::COMPUTE,
                0,
                &frames_before.to_ne_bytes(),
            );
            h.cmd_dispatch(
                cmd,
                target.extent.width.div_ceil(GROUP),
                target.extent.height.div_ceil(GROUP),
                1,
            );
        }
        Ok(ImageUse::COMPUTE_STORAGE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_mean_is_the_mean_of_the_values_so_far() {
        let values = [3.0, -1.0, 7.5, 0.25, 100.0, 2.0];
        let mut mean = 0.0;
        for (k, v) in values.iter().enumerate() {
            mean = running_mean(mean, *v, k as u32);
            let expected = values[..=k].iter().sum::<f64>() / (k + 1) as f64;
            assert!(
                (mean - expected).abs() < 1e-12,
                "after {} values: {mean} vs {expected}",
                k + 1
            );
        }
        let glsl = include_str!("../../shaders/accumulate.comp");
        assert!(glsl.contains("return mean_before + (value - mean_before) / float(frames_before + 1u);"));
    }

    #[test]
    fn a_view_converges_at_the_stated_lookups() {
        let at = |frames| Accumulated {
            frames,
            lookups_per_frame: 64,
        };
        assert!(at(15).converging());
        assert!(!at(16).converging());
        assert_eq!(at(16).lookups(), CONVERGED_LOOKUPS);
        let limit = Accumulation::UpTo(CONVERGED_LOOKUPS);
        assert!(!at(15).full(limit) && at(16).full(limit));
        assert!(!at(1000).full(Accumulation::Unlimited));
        let glsl = include_str!("../../shaders/accumulate.comp");
        assert!(glsl.contains(&format!("const uint HOLD = 0x{HOLD:X}u;")));
    }
}
