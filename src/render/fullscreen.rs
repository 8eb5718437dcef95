//! A pass that draws one triangle over the viewport (fullscreen.vert) with a fragment
//! shader reading one image: set 0, binding 0 a sampled image, one set per frame in flight;
//! push constants as the shader declares; one pipeline per key (an output format, a sample
//! count). The display transform and the MSAA resolve are such passes.

use std::collections::HashMap;
use std::fmt::Debug;
use std::hash::Hash;
use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::shaders;
use crate::vk::{
    begin_rendering, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device,
    GraphicsPipelineBuilder, Pipeline, PipelineLayout, ShaderModule, Specialization,
};

pub struct FullscreenPass<K> {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    vertex: ShaderModule,
    fragment: ShaderModule,
    name: &'static str,
    pipelines: HashMap<K, Pipeline>,
    /// Owns `sets`.
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
}

impl<K: Copy + Debug + Eq + Hash> FullscreenPass<K> {
    /// The pass of `fragment` (SPIR-V, called `name`), with `push_bytes` bytes of push
    /// constants for the fragment stage.
    pub fn new(
        device: &Arc<Device>,
        frames_in_flight: u32,
        fragment: &[u8],
        name: &'static str,
        push_bytes: u32,
    ) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::SAMPLED_IMAGE, vk::ShaderStageFlags::FRAGMENT)
            .build(device, &format!("{name} set"))?;
        let layout = PipelineLayout::new(device, &[&set_layout], push_bytes, vk::ShaderStageFlags::FRAGMENT)?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let sets = (0..frames_in_flight)
            .map(|_| pool.allocate(&set_layout))
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            vertex: ShaderModule::new(device, shaders::FULLSCREEN_VERT, "fullscreen.vert")?,
            fragment: ShaderModule::new(device, fragment, name)?,
            name,
            _set_layout: set_layout,
            layout,
            pipelines: HashMap::new(),
            _pool: pool,
            sets,
        })
    }

    /// Points `slot`'s set at `view`, read in shader-read-only layout; the slot's previous
    /// frame is done.
    pub fn bind(&self, slot: usize, view: vk::ImageView) {
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::SAMPLED_IMAGE,
                view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::Sampler::null(),
            )
            .write(&self.device, self.sets[slot]);
    }

    /// Creates `key`'s pipeline, writing `format` with `specialization`, if it does not exist.
    pub fn prepare_pipeline(&mut self, key: K, format: vk::Format, specialization: Specialization) -> Result<()> {
        if !self.pipelines.contains_key(&key) {
            let pipeline = GraphicsPipelineBuilder::new(&self.vertex, &self.fragment, format)
                .specialization(specialization)
                .build(&self.device, &self.layout, &format!("{} {key:?}", self.name))?;
            self.pipelines.insert(key, pipeline);
        }
        Ok(())
    }

    /// Records the pass with `key`'s pipeline into `area` of `output` (in colour-attachment
    /// layout, every texel of `area` written); `slot`'s image must be readable by fragment
    /// shaders.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        key: K,
        output: vk::ImageView,
        area: vk::Rect2D,
        push: &[u8],
    ) -> Result<()> {
        let pipeline = self
            .pipelines
            .get(&key)
            .with_context(|| format!("{} pipeline for {key:?} missing: prepare first", self.name))?;
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(output)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::DONT_CARE)
            .store_op(vk::AttachmentStoreOp::STORE)];
        begin_rendering(&self.device, cmd, area, &color, None);
        let d = &self.device.handle;
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
            if !push.is_empty() {
                d.cmd_push_constants(cmd, self.layout.handle, vk::ShaderStageFlags::FRAGMENT, 0, push);
            }
            d.cmd_draw(cmd, 3, 1, 0, 0);
            d.cmd_end_rendering(cmd);
        }
        Ok(())
    }
}
