//! Ambient occlusion of the environment's light (`[occlusion]`): a depth prepass of the
//! objects (shadow.vert, depth only), then GTAO (shaders/gtao.comp) from that depth into a
//! full-resolution visibility image, whose 4×4 jitter pattern shaders/gtao_denoise.comp
//! averages into the image the forward pass reads at its own pixel (set 4,
//! binding 0; shaders/lib/occlusion_map.glsl) to darken the environment's diffuse light
//! (with GTAO's multi-bounce fit) and specular light (specular occlusion). The point
//! lights are not touched: their shadow maps occlude them. Off, nothing is recorded and
//! the set points at a 1×1 placeholder the specialised forward pipelines never read.

use std::sync::Arc;

use anyhow::{bail, Result};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::Mat4;

use super::shaders;
use super::shadow::{depth_pipeline, draw_depth};
use super::target::DEPTH_FORMAT;
use crate::scene::{Occlusion, Scene};
use crate::vk::{
    begin_full_rendering, transition, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, Image, ImageUse, OneShot, Pipeline, PipelineLayout, Sampler, ShaderModule,
    Specialization,
};

/// How the forward pass applies the visibility: the `OCCLUSION` specialization constant
/// of shaders/lib/occlusion_map.glsl.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum OcclusionMode {
    /// No occlusion pass: visibility 1, nothing read.
    Off = 0,
    /// The diffuse light through GTAO's multi-bounce fit, the specular by specular occlusion.
    MultiBounce = 1,
    /// The diffuse light scaled by the visibility itself, the specular as above.
    Plain = 2,
}

impl OcclusionMode {
    /// The mode of a frame of `settings` (`enabled` off: the renderer's toggle or the floor).
    pub fn of(settings: &Occlusion, enabled: bool) -> Self {
        match (enabled && settings.enabled, settings.multi_bounce) {
            (false, _) => OcclusionMode::Off,
            (true, true) => OcclusionMode::MultiBounce,
            (true, false) => OcclusionMode::Plain,
        }
    }
}

/// The visibility image's format: fp32, whose storage-image support Vulkan requires.
const VISIBILITY_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// gtao.comp's `local_size_x` and `local_size_y`.
const WORKGROUP: u32 = 8;

/// `GtaoPush` of gtao.comp.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GtaoPush {
    world_from_clip: [[f32; 4]; 4],
    camera: [f32; 4],
    settings: [u32; 4],
}

/// The prepass's depth and the visibility computed from it, at the frame's size.
struct Targets {
    depth: Image,
    /// gtao.comp's jittered visibility.
    raw: Image,
    /// gtao_denoise.comp's mean of it.
    visibility: Image,
}

pub struct OcclusionPass {
    device: Arc<Device>,
    /// Set 4 of the forward pass.
    set_layout: DescriptorSetLayout,
    set: vk::DescriptorSet,
    gtao_set_layout: DescriptorSetLayout,
    gtao_set: vk::DescriptorSet,
    _pools: [DescriptorPool; 2],
    /// Made when the pass first turns on: most scenes never turn it on.
    pipelines: Option<Pipelines>,
    sampler: Sampler,
    placeholder: Image,
    targets: Option<Targets>,
    /// What the next recorded frame runs with; `None`: the pass is off for it.
    frame: Option<(GtaoPush, Mat4)>,
}

/// The prepass's and GTAO's pipelines.
struct Pipelines {
    prepass_layout: PipelineLayout,
    prepass: Pipeline,
    gtao_layout: PipelineLayout,
    gtao: Pipeline,
    denoise: Pipeline,
}

impl Pipelines {
    fn new(device: &Arc<Device>, gtao_set_layout: &DescriptorSetLayout) -> Result<Self> {
        let (prepass_layout, prepass) = depth_pipeline(device, "occlusion prepass")?;
        let gtao_layout = PipelineLayout::new(
            device,
            &[gtao_set_layout],
            std::mem::size_of::<GtaoPush>() as u32,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let compute = ShaderModule::new(device, shaders::GTAO_COMP, "gtao.comp")?;
        let gtao = Pipeline::compute(device, &gtao_layout, &compute, &Specialization::default(), "gtao")?;
        let compute = ShaderModule::new(device, shaders::GTAO_DENOISE_COMP, "gtao_denoise.comp")?;
        let denoise = Pipeline::compute(
            device,
            &gtao_layout,
            &compute,
            &Specialization::default(),
            "gtao denoise",
        )?;
        Ok(Self {
            prepass_layout,
            prepass,
            gtao_layout,
            gtao,
            denoise,
        })
    }
}

impl OcclusionPass {
    pub fn new(device: &Arc<Device>, one_shot: &OneShot) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .build(device, "occlusion set")?;
        let gtao_set_layout = DescriptorSetLayoutBuilder::default()
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::COMPUTE,
            )
            .binding(vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE)
            .binding(vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE)
            .build(device, "gtao set")?;
        let pools = [
            DescriptorPool::for_layout(device, &set_layout, 1)?,
            DescriptorPool::for_layout(device, &gtao_set_layout, 1)?,
        ];
        let set = pools[0].allocate(&set_layout)?;
        let gtao_set = pools[1].allocate(&gtao_set_layout)?;
        let placeholder = visibility_image(device, vk::Extent2D { width: 1, height: 1 }, "occlusion placeholder")?;
        one_shot.run(|cmd| {
            transition(
                device,
                cmd,
                placeholder.handle,
                placeholder.aspect,
                ImageUse::UNDEFINED,
                ImageUse::FRAGMENT_READ,
            )
        })?;
        let pass = Self {
            device: device.clone(),
            set_layout,
            set,
            gtao_set_layout,
            gtao_set,
            _pools: pools,
            pipelines: None,
            sampler: Sampler::nearest(device)?,
            placeholder,
            targets: None,
            frame: None,
        };
        pass.bind_forward(&pass.placeholder);
        Ok(pass)
    }

    /// The layout of set 4 of the forward pass.
    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Set 4 of the forward pass.
    pub fn set(&self) -> vk::DescriptorSet {
        self.set
    }

    fn bind_forward(&self, visibility: &Image) {
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                visibility.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                self.sampler.handle,
            )
            .write(&self.device, self.set);
    }

    /// Sets up the next recorded frame: unless `mode` is off, occlusion by the scene's
    /// settings in a frame of `extent`. The pipelines are made when the pass first turns on,
    /// the images (waiting for the frames that read the old ones) when the size changes,
    /// and the forward pass's set is pointed at them, or back at the placeholder, when the
    /// pass turns on or off.
    pub fn prepare(&mut self, scene: &Scene, extent: vk::Extent2D, mode: OcclusionMode) -> Result<()> {
        let enabled = mode != OcclusionMode::Off;
        if enabled && self.pipelines.is_none() {
            self.pipelines = Some(Pipelines::new(&self.device, &self.gtao_set_layout)?);
        }
        let settings: &Occlusion = &scene.occlusion;
        let was_on = self.frame.is_some();
        let view_proj = scene.camera.view_projection(extent.width as f32 / extent.height as f32);
        self.frame = enabled.then(|| {
            let push = GtaoPush {
                world_from_clip: view_proj.inverse().to_cols_array_2d(),
                camera: scene.camera.position.extend(settings.radius).to_array(),
                settings: [settings.slices, settings.steps, 0, 0],
            };
            (push, view_proj)
        });
        let new_targets = enabled && self.targets.as_ref().is_none_or(|t| t.depth.extent != extent);
        if enabled == was_on && !new_targets {
            return Ok(());
        }
        self.device.wait_idle()?;
        if new_targets {
            self.targets = None;
            let targets = Targets {
                depth: Image::new_2d(
                    &self.device,
                    extent,
                    DEPTH_FORMAT,
                    vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                    vk::ImageAspectFlags::DEPTH,
                    "occlusion depth",
                )?,
                raw: visibility_image(&self.device, extent, "occlusion raw visibility")?,
                visibility: visibility_image(&self.device, extent, "occlusion visibility")?,
            };
            DescriptorWriter::default()
                .image(
                    0,
                    vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    targets.depth.view,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    self.sampler.handle,
                )
                .image(
                    1,
                    vk::DescriptorType::STORAGE_IMAGE,
                    targets.raw.view,
                    vk::ImageLayout::GENERAL,
                    vk::Sampler::null(),
                )
                .image(
                    2,
                    vk::DescriptorType::STORAGE_IMAGE,
                    targets.visibility.view,
                    vk::ImageLayout::GENERAL,
                    vk::Sampler::null(),
                )
                .write(&self.device, self.gtao_set);
            self.targets = Some(targets);
        }
        match (&self.targets, enabled) {
            (Some(targets), true) => self.bind_forward(&targets.visibility),
            _ => self.bind_forward(&self.placeholder),
        }
        Ok(())
    }

    /// Records the prepass and GTAO when [`Self::prepare`] turned the pass on, leaving the
    /// visibility readable by fragment shaders; records nothing otherwise.
    pub fn record(&self, cmd: vk::CommandBuffer, scene: &Scene, gpu: &super::GpuScene) -> Result<()> {
        let Some((push, view_proj)) = &self.frame else {
            return Ok(());
        };
        let (Some(targets), Some(pipelines)) = (&self.targets, &self.pipelines) else {
            bail!("occlusion targets missing: prepare() was not called");
        };
        let d = &self.device.handle;
        let Targets { depth, raw, visibility } = targets;
        // The previous frame's compute shaders read this depth and the raw visibility, and
        // its forward pass the visibility: their contents go once those reads are done.
        let after = |stage| ImageUse {
            stage,
            ..ImageUse::UNDEFINED
        };
        transition(
            &self.device,
            cmd,
            depth.handle,
            depth.aspect,
            after(vk::PipelineStageFlags2::COMPUTE_SHADER),
            ImageUse::DEPTH_ATTACHMENT,
        );
        let attachment = vk::RenderingAttachmentInfo::default()
            .image_view(depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            });
        begin_full_rendering(&self.device, cmd, depth.extent, &[], Some(&attachment));
        draw_depth(
            &self.device,
            cmd,
            &pipelines.prepass_layout,
            &pipelines.prepass,
            scene,
            gpu,
            *view_proj,
        );
        unsafe { d.cmd_end_rendering(cmd) };
        transition(
            &self.device,
            cmd,
            depth.handle,
            depth.aspect,
            ImageUse::DEPTH_ATTACHMENT,
            ImageUse::COMPUTE_READ,
        );
        let stages = [
            (raw, vk::PipelineStageFlags2::COMPUTE_SHADER),
            (visibility, vk::PipelineStageFlags2::FRAGMENT_SHADER),
        ];
        for (image, last_read) in stages {
            transition(
                &self.device,
                cmd,
                image.handle,
                image.aspect,
                after(last_read),
                ImageUse::COMPUTE_STORAGE,
            );
        }
        let extent = visibility.extent;
        let groups = [extent.width.div_ceil(WORKGROUP), extent.height.div_ceil(WORKGROUP)];
        unsafe {
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                pipelines.gtao_layout.handle,
                0,
                &[self.gtao_set],
                &[],
            );
            d.cmd_push_constants(
                cmd,
                pipelines.gtao_layout.handle,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(push),
            );
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipelines.gtao.handle);
            d.cmd_dispatch(cmd, groups[0], groups[1], 1);
        }
        // The denoiser reads what gtao.comp wrote, pixels away from where it reads.
        transition(
            &self.device,
            cmd,
            raw.handle,
            raw.aspect,
            ImageUse::COMPUTE_STORAGE,
            ImageUse::COMPUTE_STORAGE,
        );
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipelines.denoise.handle);
            d.cmd_dispatch(cmd, groups[0], groups[1], 1);
        }
        transition(
            &self.device,
            cmd,
            visibility.handle,
            visibility.aspect,
            ImageUse::COMPUTE_STORAGE,
            ImageUse::FRAGMENT_READ,
        );
        Ok(())
    }
}

fn visibility_image(device: &Arc<Device>, extent: vk::Extent2D, name: &str) -> Result<Image> {
    Image::new_2d(
        device,
        extent,
        VISIBILITY_FORMAT,
        vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED,
        vk::ImageAspectFlags::COLOR,
        name,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The push constants are laid out as gtao.comp declares them, and fit the 128 bytes
    /// every device offers.
    #[test]
    fn push_constants_match_the_shader() {
        let glsl = include_str!("../../shaders/lib/gtao_frame.glsl");
        for member in ["mat4 world_from_clip;", "vec4 camera;", "uvec4 settings;"] {
            assert!(glsl.contains(member), "gtao.comp has no {member}");
        }
        for shader in [
            include_str!("../../shaders/gtao.comp"),
            include_str!("../../shaders/gtao_denoise.comp"),
        ] {
            assert!(shader.contains(&format!("local_size_x = {WORKGROUP}, local_size_y = {WORKGROUP}")));
        }
        assert!(std::mem::size_of::<GtaoPush>() <= 128);
    }
}
