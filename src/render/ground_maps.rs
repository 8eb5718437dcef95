//! The ground's light map (`[shadows] bounce`): the point lights' irradiance on the ground,
//! each light's through its shadow map, at the texel centres of a square image over the
//! ground (shaders/ground_light.comp). The bounce's gather reads it bilinearly where its
//! taps meet the ground (set 5 of the forward pass; shaders/lib/bounce.glsl), rather than
//! every light's shadow map at every tap of every pixel. It is computed again only when
//! the lights, the ground or the shadow maps change; without a ground nothing is
//! recorded, and the map, cleared to 0 at the start, counts for nothing (the gather
//! returns before its taps).

use std::cell::Cell;
use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::gpu_scene::MAX_POINT_LIGHTS;
use super::shaders;
use crate::scene::Scene;
use crate::vk::{
    transition, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device, Image,
    ImageUse, OneShot, Pipeline, PipelineLayout, Sampler, ShaderModule, Specialization,
};

/// Texels on a side of the map: 6.25 cm on the default scene's 16 m ground, finer than the
/// gather's eight taps resolve.
pub const GROUND_LIGHT_SIZE: u32 = 256;
/// fp16: an irradiance to 2⁻¹¹ of itself, which Vulkan requires to filter and store.
const FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// ground_light.comp's `local_size_x` and `local_size_y`.
const WORKGROUP: u32 = 8;

pub struct GroundLightPass {
    device: Arc<Device>,
    /// Set 5 of the forward pass: the map, sampled.
    _set_layout: DescriptorSetLayout,
    set: vk::DescriptorSet,
    _compute_set_layout: DescriptorSetLayout,
    compute_set: vk::DescriptorSet,
    _pools: [DescriptorPool; 2],
    layout: PipelineLayout,
    pipeline: Pipeline,
    _sampler: Sampler,
    map: Image,
    /// The lights and the ground the map was last computed for.
    key: Vec<u32>,
    /// Whether the next recorded frame computes the map.
    pending: Cell<bool>,
    /// Frames that computed it.
    renders: Cell<u64>,
}

impl GroundLightPass {
    /// The layout of set 5 of the forward pass, which [`Self::new`] takes over.
    pub fn forward_set_layout(device: &Arc<Device>) -> Result<DescriptorSetLayout> {
        DescriptorSetLayoutBuilder::default()
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .build(device, "ground light set")
    }

    /// The compute shader reads the lights and the ground from the forward pass's set 0
    /// (`frame_layout`) and the shadow maps from its set 3 (`shadow_layout`); its set 2 is
    /// the environment's (`environment_layout`), which it does not read.
    pub fn new(
        device: &Arc<Device>,
        one_shot: &OneShot,
        set_layout: DescriptorSetLayout,
        frame_layout: &DescriptorSetLayout,
        environment_layout: &DescriptorSetLayout,
        shadow_layout: &DescriptorSetLayout,
    ) -> Result<Self> {
        let compute_set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE)
            .build(device, "ground light compute set")?;
        let pools = [
            DescriptorPool::for_layout(device, &set_layout, 1)?,
            DescriptorPool::for_layout(device, &compute_set_layout, 1)?,
        ];
        let set = pools[0].allocate(&set_layout)?;
        let compute_set = pools[1].allocate(&compute_set_layout)?;
        let layout = PipelineLayout::new(
            device,
            &[frame_layout, &compute_set_layout, environment_layout, shadow_layout],
            0,
            vk::ShaderStageFlags::empty(),
        )?;
        let compute = ShaderModule::new(device, shaders::GROUND_LIGHT_COMP, "ground_light.comp")?;
        let pipeline = Pipeline::compute(device, &layout, &compute, &Specialization::default(), "ground light")?;
        let extent = vk::Extent2D {
            width: GROUND_LIGHT_SIZE,
            height: GROUND_LIGHT_SIZE,
        };
        let map = Image::new_2d(
            device,
            extent,
            FORMAT,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            vk::ImageAspectFlags::COLOR,
            "ground light",
        )?;
        one_shot.run(|cmd| {
            transition(device, cmd, map.handle, map.aspect, ImageUse::UNDEFINED, ImageUse::CLEAR_DST);
            let black = vk::ClearColorValue { float32: [0.0; 4] };
            let range = map.all_levels();
            unsafe {
                device.handle.cmd_clear_color_image(
                    cmd,
                    map.handle,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &black,
                    &[range],
                )
            };
            transition(device, cmd, map.handle, map.aspect, ImageUse::CLEAR_DST, ImageUse::FRAGMENT_READ);
        })?;
        let sampler = Sampler::clamped(device)?;
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                map.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                sampler.handle,
            )
            .write(device, set);
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::STORAGE_IMAGE,
                map.view,
                vk::ImageLayout::GENERAL,
                vk::Sampler::null(),
            )
            .write(device, compute_set);
        Ok(Self {
            device: device.clone(),
            _set_layout: set_layout,
            set,
            _compute_set_layout: compute_set_layout,
            compute_set,
            _pools: pools,
            layout,
            pipeline,
            _sampler: sampler,
            map,
            key: Vec::new(),
            pending: Cell::new(false),
            renders: Cell::new(0),
        })
    }

    /// Set 5 of the forward pass.
    pub fn set(&self) -> vk::DescriptorSet {
        self.set
    }

    /// Has the next recorded frame compute the map when the scene has a ground to bounce
    /// light and its lights or ground changed since, or `shadows_change` (the shadow maps
    /// are rendered again, or switched on or off).
    pub fn prepare(&mut self, scene: &Scene, shadows_change: bool) {
        let Some(ground) = scene.bounce_ground() else {
            self.key.clear();
            return;
        };
        let lights = scene.lights.iter().take(MAX_POINT_LIGHTS);
        let key: Vec<u32> = (ground.position.extend(ground.scale).to_array().into_iter())
            .chain(lights.flat_map(|l| l.position.to_array().into_iter().chain(l.intensity.to_array())))
            .map(f32::to_bits)
            .collect();
        if shadows_change || key != self.key {
            self.key = key;
            self.pending.set(true);
        }
    }

    /// Frames that have computed the map.
    pub fn renders(&self) -> u64 {
        self.renders.get()
    }

    /// Computes the map if [`Self::prepare`] found it out of date, from the frame's set 0
    /// (`frame_set`) and shadow set (`shadow_set`), leaving it readable by fragment
    /// shaders; records nothing otherwise.
    pub fn record(&self, cmd: vk::CommandBuffer, frame_set: vk::DescriptorSet, shadow_set: vk::DescriptorSet) {
        if !self.pending.replace(false) {
            return;
        }
        self.renders.set(self.renders.get() + 1);
        let map = &self.map;
        // The old map goes once the frames before this one have read it.
        let after_reads = ImageUse {
            stage: vk::PipelineStageFlags2::FRAGMENT_SHADER,
            ..ImageUse::UNDEFINED
        };
        transition(&self.device, cmd, map.handle, map.aspect, after_reads, ImageUse::COMPUTE_STORAGE);
        let d = &self.device.handle;
        let groups = GROUND_LIGHT_SIZE.div_ceil(WORKGROUP);
        let bind = |first: u32, sets: &[vk::DescriptorSet]| unsafe {
            d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.layout.handle, first, sets, &[]);
        };
        bind(0, &[frame_set, self.compute_set]);
        bind(3, &[shadow_set]);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.handle);
            d.cmd_dispatch(cmd, groups, groups, 1);
        }
        transition(&self.device, cmd, map.handle, map.aspect, ImageUse::COMPUTE_STORAGE, ImageUse::FRAGMENT_READ);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_workgroup_and_format_are_the_shaders() {
        let glsl = include_str!("../../shaders/ground_light.comp");
        assert!(glsl.contains(&format!("local_size_x = {WORKGROUP}, local_size_y = {WORKGROUP}")));
        assert!(glsl.contains("rgba16f") && FORMAT == vk::Format::R16G16B16A16_SFLOAT);
    }
}
