//! The forward pass: every object, shaded by every point light, into the HDR target.
//!
//! Set 0: binding 0 the `FrameData` uniform buffer, binding 1 the `Materials` storage
//! buffer, binding 2 the pre-integrated subsurface table; set 2: the environment (see environment.rs); set 3: the
//! shadow maps (see shadow.rs); push constants: `ObjectPush` (see
//! shaders/lib/scene_data.glsl). One pipeline per combination of BRDF models in use,
//! chosen by specialization constants; for `argil bench`, one more that draws every object
//! with the trivial `floor.frag`.

use std::collections::HashMap;
use std::mem::offset_of;
use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;

use super::debug_view::DebugView;
use super::gpu_scene::{FrameData, GpuScene, MaterialData, ObjectPush};
use super::shaders;
use super::subsurface::SubsurfaceTable;
use super::target::{RenderTarget, DEPTH_FORMAT, HDR_FORMAT};
use crate::scene::{Material, Scene, Vertex};
use crate::vk::{
    begin_full_rendering, Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter,
    Device, GraphicsPipelineBuilder, OneShot, Pipeline, PipelineLayout, ShaderModule, Specialization,
};

/// The specialization constants of `forward.frag` for a material: its models (shading.glsl),
/// which maps it has (material_maps.glsl), its horizon treatment and subsurface model.
pub fn material_specialization(m: &Material) -> Specialization {
    let models = m.shading_models();
    let maps = &m.maps;
    Specialization(vec![
        models.diffuse as u32,
        models.specular as u32,
        models.distribution as u32,
        models.geometry as u32,
        u32::from(maps.base_color.is_some()),
        u32::from(maps.normal.is_some()),
        u32::from(maps.detail.is_some()),
        u32::from(maps.noise.is_some()),
        maps.detail_blend as u32,
        m.horizon as u32,
        models.subsurface as u32,
    ])
}

/// What one frame in flight owns: its uniforms, materials and the set pointing at them.
struct FrameSlot {
    frame_data: Buffer,
    materials: Buffer,
    set: vk::DescriptorSet,
}

pub struct ForwardPass {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    _set_layout: DescriptorSetLayout,
    /// Set 1: a material's maps (material_maps.glsl); its sets belong to a `GpuScene`.
    material_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    vertex: ShaderModule,
    fragment: ShaderModule,
    pipelines: HashMap<Specialization, Pipeline>,
    /// `floor.frag`'s pipeline, created the first time a frame asks for the floor.
    floor: Option<Pipeline>,
    /// The pipeline of each material of the scene last prepared, in `Scene::materials` order.
    material_pipelines: Vec<vk::Pipeline>,
    /// Owns the slots' sets.
    _pool: DescriptorPool,
    slots: Vec<FrameSlot>,
    subsurface: SubsurfaceTable,
}

impl ForwardPass {
    pub fn new(
        device: &Arc<Device>,
        one_shot: &OneShot,
        frames_in_flight: u32,
        environment_layout: &DescriptorSetLayout,
        shadow_layout: &DescriptorSetLayout,
    ) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(
                vk::DescriptorType::UNIFORM_BUFFER,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            )
            .binding(
                vk::DescriptorType::STORAGE_BUFFER,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            )
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .build(device, "forward set")?;
        let subsurface = SubsurfaceTable::upload(device, one_shot)?;
        let material_layout = (0..4)
            .fold(DescriptorSetLayoutBuilder::default(), |b, _| {
                b.binding(
                    vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    vk::ShaderStageFlags::FRAGMENT,
                )
            })
            .build(device, "material maps set")?;
        let layout = PipelineLayout::new(
            device,
            &[&set_layout, &material_layout, environment_layout, shadow_layout],
            std::mem::size_of::<ObjectPush>() as u32,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        )?;
        let vertex = ShaderModule::new(device, shaders::FORWARD_VERT, "forward.vert")?;
        let fragment = ShaderModule::new(device, shaders::FORWARD_FRAG, "forward.frag")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let slots = (0..frames_in_flight)
            .map(|_| {
                let frame_data = Buffer::new(
                    device,
                    std::mem::size_of::<FrameData>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                    MemoryLocation::CpuToGpu,
                    "frame data",
                )?;
                let materials = Self::material_buffer(device, 1)?;
                let set = pool.allocate(&set_layout)?;
                Self::write_set(device, set, &frame_data, &materials, &subsurface);
                Ok(FrameSlot {
                    frame_data,
                    materials,
                    set,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            _set_layout: set_layout,
            material_layout,
            layout,
            vertex,
            fragment,
            pipelines: HashMap::new(),
            floor: None,
            material_pipelines: Vec::new(),
            _pool: pool,
            slots,
            subsurface,
        })
    }

    /// The layout of set 1, for the scene's material sets.
    pub fn material_layout(&self) -> &DescriptorSetLayout {
        &self.material_layout
    }

    fn material_buffer(device: &Arc<Device>, count: usize) -> Result<Buffer> {
        Buffer::new(
            device,
            (count.max(1) * std::mem::size_of::<MaterialData>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
            "materials",
        )
    }

    fn write_set(
        device: &Device,
        set: vk::DescriptorSet,
        frame_data: &Buffer,
        materials: &Buffer,
        subsurface: &SubsurfaceTable,
    ) {
        let writer = DescriptorWriter::default()
            .buffer(0, vk::DescriptorType::UNIFORM_BUFFER, frame_data.handle)
            .buffer(1, vk::DescriptorType::STORAGE_BUFFER, materials.handle);
        subsurface.bind(writer).write(device, set);
    }

    fn pipeline(&mut self, specialization: &Specialization) -> Result<vk::Pipeline> {
        if let Some(p) = self.pipelines.get(specialization) {
            return Ok(p.handle);
        }
        let pipeline = self.build_pipeline(
            &self.fragment,
            specialization,
            &format!("forward {:?}", specialization.0),
        )?;
        let handle = pipeline.handle;
        self.pipelines.insert(specialization.clone(), pipeline);
        Ok(handle)
    }

    fn floor_pipeline(&mut self) -> Result<vk::Pipeline> {
        if let Some(p) = &self.floor {
            return Ok(p.handle);
        }
        // The module may go once the pipeline exists.
        let fragment = ShaderModule::new(&self.device, shaders::FLOOR_FRAG, "floor.frag")?;
        let pipeline = self.build_pipeline(&fragment, &Specialization::default(), "forward floor")?;
        Ok(self.floor.insert(pipeline).handle)
    }

    fn build_pipeline(&self, fragment: &ShaderModule, specialization: &Specialization, name: &str) -> Result<Pipeline> {
        let stride = std::mem::size_of::<Vertex>() as u32;
        // Locations 0..=4, as forward.vert declares them.
        GraphicsPipelineBuilder::new(&self.vertex, fragment, HDR_FORMAT)
            .vertex_layout(
                stride,
                &[
                    (vk::Format::R32G32B32_SFLOAT, offset_of!(Vertex, position) as u32),
                    (vk::Format::R32G32B32_SFLOAT, offset_of!(Vertex, normal) as u32),
                    (vk::Format::R32G32_SFLOAT, offset_of!(Vertex, uv) as u32),
                    (vk::Format::R32G32B32A32_SFLOAT, offset_of!(Vertex, tangent) as u32),
                    (vk::Format::R32_SFLOAT, offset_of!(Vertex, curvature) as u32),
                ],
            )
            .depth(DEPTH_FORMAT)
            .specialization(specialization.clone())
            .build(&self.device, &self.layout, name)
    }

    /// Writes this frame's uniforms and materials into `slot` (whose previous use the
    /// caller has waited for) and creates any pipeline the scene's materials need, or with
    /// `floor` the floor's pipeline for every material.
    pub fn prepare(
        &mut self,
        slot: usize,
        scene: &Scene,
        aspect: f32,
        debug_view: DebugView,
        floor: bool,
    ) -> Result<()> {
        let mut frame_data = FrameData::new(scene, aspect)?;
        frame_data.counts[1] = debug_view as u32;
        let materials: Vec<MaterialData> = scene.materials.iter().map(MaterialData::from).collect();
        self.material_pipelines = scene
            .materials
            .iter()
            .map(|m| {
                if floor {
                    self.floor_pipeline()
                } else {
                    self.pipeline(&material_specialization(m))
                }
            })
            .collect::<Result<_>>()?;
        let s = &mut self.slots[slot];
        s.frame_data.write(bytemuck::bytes_of(&frame_data))?;
        let bytes: &[u8] = bytemuck::cast_slice(&materials);
        if bytes.len() as u64 > s.materials.size {
            s.materials = Self::material_buffer(&self.device, materials.len())?;
            Self::write_set(&self.device, s.set, &s.frame_data, &s.materials, &self.subsurface);
        }
        s.materials.write(bytes)
    }

    /// Records the pass. The target's colour and depth must be in attachment layouts; its
    /// depth is kept for the skybox.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        scene: &Scene,
        gpu: &GpuScene,
        target: &RenderTarget,
        clear: [f32; 4],
        environment_set: vk::DescriptorSet,
        shadow_set: vk::DescriptorSet,
    ) -> Result<()> {
        let d = &self.device.handle;
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(target.color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            })];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(target.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            });
        begin_full_rendering(&self.device, cmd, target.extent, &color, Some(&depth));
        unsafe {
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.handle,
                0,
                &[self.slots[slot].set],
                &[],
            );
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.handle,
                2,
                &[environment_set, shadow_set],
                &[],
            );
        }
        let mut bound = vk::Pipeline::null();
        for object in &scene.objects {
            let pipeline = *self
                .material_pipelines
                .get(object.material)
                .context("forward pipeline missing: prepare() was not called for this scene")?;
            let mesh = &gpu.meshes[object.mesh];
            let push = ObjectPush::new(object);
            unsafe {
                if pipeline != bound {
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                    bound = pipeline;
                }
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.handle,
                    1,
                    &[gpu.material_sets[object.material]],
                    &[],
                );
                d.cmd_push_constants(
                    cmd,
                    self.layout.handle,
                    vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                    0,
                    bytemuck::bytes_of(&push),
                );
                d.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.handle], &[0]);
                d.cmd_bind_index_buffer(cmd, mesh.indices.handle, 0, vk::IndexType::UINT32);
                d.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, 0);
            }
        }
        unsafe { d.cmd_end_rendering(cmd) };
        Ok(())
    }
}
