//! The display transform: reads the HDR target, writes display colours into an 8-bit
//! image (a file's or a swapchain's). Set 0, binding 0: the HDR frame as a sampled image;
//! push constants: exposure and where the frame starts in the output. One pipeline per
//! output format.

use std::collections::HashMap;
use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::shaders;
use super::target::RenderTarget;
use crate::vk::{
    begin_rendering, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device,
    GraphicsPipelineBuilder, Pipeline, PipelineLayout, ShaderModule, Specialization,
};

/// The format of 8-bit tone-mapped frames written to files: the hardware sRGB-encodes.
pub const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Whether writes to `format` are sRGB-encoded by the hardware.
pub fn is_srgb(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_SRGB | vk::Format::A8B8G8R8_SRGB_PACK32
    )
}

/// `tonemap.frag`'s push constants: the frame's offset in the output (ivec2), then the
/// exposure (f32).
const PUSH_BYTES: u32 = 12;

pub struct TonemapPass {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    vertex: ShaderModule,
    fragment: ShaderModule,
    pipelines: HashMap<vk::Format, Pipeline>,
    /// Owns `sets`.
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
}

impl TonemapPass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::SAMPLED_IMAGE, vk::ShaderStageFlags::FRAGMENT)
            .build(device, "tonemap set")?;
        let layout = PipelineLayout::new(device, &[&set_layout], PUSH_BYTES, vk::ShaderStageFlags::FRAGMENT)?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let sets = (0..frames_in_flight)
            .map(|_| pool.allocate(&set_layout))
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            vertex: ShaderModule::new(device, shaders::FULLSCREEN_VERT, "fullscreen.vert")?,
            fragment: ShaderModule::new(device, shaders::TONEMAP_FRAG, "tonemap.frag")?,
            _set_layout: set_layout,
            layout,
            pipelines: HashMap::new(),
            _pool: pool,
            sets,
        })
    }

    /// Points `slot`'s set at `target` and creates the pipeline for `format` if needed.
    pub fn prepare(&mut self, slot: usize, target: &RenderTarget, format: vk::Format) -> Result<()> {
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::SAMPLED_IMAGE,
                target.color.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::Sampler::null(),
            )
            .write(&self.device, self.sets[slot]);
        if !self.pipelines.contains_key(&format) {
            // The shader encodes sRGB itself only when the hardware will not.
            let encode = Specialization(vec![u32::from(!is_srgb(format))]);
            let pipeline = GraphicsPipelineBuilder::new(&self.vertex, &self.fragment, format)
                .specialization(encode)
                .build(&self.device, &self.layout, &format!("tonemap {format:?}"))?;
            self.pipelines.insert(format, pipeline);
        }
        Ok(())
    }

    /// Records the pass into `area` of `output` (in colour-attachment layout), which is the
    /// HDR target's size; the target must be readable by fragment shaders.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        output: vk::ImageView,
        format: vk::Format,
        area: vk::Rect2D,
        exposure: f32,
    ) -> Result<()> {
        let pipeline = self
            .pipelines
            .get(&format)
            .ok_or_else(|| anyhow::anyhow!("tonemap pipeline for {format:?} missing: prepare() first"))?;
        let d = &self.device.handle;
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(output)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::DONT_CARE)
            .store_op(vk::AttachmentStoreOp::STORE)];
        begin_rendering(&self.device, cmd, area, &color, None);
        let mut push = area.offset.x.to_ne_bytes().to_vec();
        push.extend(area.offset.y.to_ne_bytes());
        push.extend(exposure.to_ne_bytes());
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.handle);
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.handle,
                0,
                &[self.sets[slot]],
                &[],
            );
            d.cmd_push_constants(cmd, self.layout.handle, vk::ShaderStageFlags::FRAGMENT, 0, &push);
            d.cmd_draw(cmd, 3, 1, 0, 0);
            d.cmd_end_rendering(cmd);
        }
        Ok(())
    }
}
