//! Pipeline layouts and pipelines: a builder for graphics pipelines that render with
//! dynamic rendering, compute pipelines, and specialization constants for both.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::descriptors::DescriptorSetLayout;
use super::device::Device;
use super::shader::ShaderModule;

pub struct PipelineLayout {
    device: Arc<Device>,
    pub handle: vk::PipelineLayout,
}

impl PipelineLayout {
    /// `push_constant_size` bytes of push constants visible to `push_stages` (0: none).
    pub fn new(
        device: &Arc<Device>,
        set_layouts: &[&DescriptorSetLayout],
        push_constant_size: u32,
        push_stages: vk::ShaderStageFlags,
    ) -> Result<Self> {
        let sets: Vec<vk::DescriptorSetLayout> = set_layouts.iter().map(|l| l.handle).collect();
        let ranges = [vk::PushConstantRange {
            stage_flags: push_stages,
            offset: 0,
            size: push_constant_size,
        }];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&sets)
            .push_constant_ranges(if push_constant_size > 0 { &ranges } else { &[] });
        let handle =
            unsafe { device.handle.create_pipeline_layout(&info, None) }.context("cannot create a pipeline layout")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_pipeline_layout(self.handle, None) };
    }
}

/// 32-bit specialization constants with ids 0, 1, 2… in the order given: the shader
/// declares `layout(constant_id = i)`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Specialization(pub Vec<u32>);

impl Specialization {
    fn entries(&self) -> Vec<vk::SpecializationMapEntry> {
        (0..self.0.len() as u32)
            .map(|i| vk::SpecializationMapEntry {
                constant_id: i,
                offset: i * 4,
                size: 4,
            })
            .collect()
    }
}

pub struct Pipeline {
    device: Arc<Device>,
    pub handle: vk::Pipeline,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_pipeline(self.handle, None) };
    }
}

impl Pipeline {
    pub fn compute(
        device: &Arc<Device>,
        layout: &PipelineLayout,
        shader: &ShaderModule,
        specialization: &Specialization,
        name: &str,
    ) -> Result<Self> {
        let entries = specialization.entries();
        let data: &[u8] = bytemuck::cast_slice(&specialization.0);
        let spec_info = vk::SpecializationInfo::default().map_entries(&entries).data(data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(shader.handle)
            .name(c"main")
            .specialization_info(&spec_info);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.handle);
        let handle = unsafe {
            device
                .handle
                .create_compute_pipelines(device.pipeline_cache.handle, &[info], None)
        }
        .map_err(|(_, e)| e)
        .with_context(|| format!("cannot create compute pipeline '{name}'"))?[0];
        device.set_name(handle, name);
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }
}

/// What a graphics pipeline draws into and how; everything else (viewport, scissor) is
/// dynamic state set when recording.
pub struct GraphicsPipelineBuilder<'a> {
    vertex: &'a ShaderModule,
    /// None for a depth-only pipeline.
    fragment: Option<&'a ShaderModule>,
    specialization: Specialization,
    vertex_stride: u32,
    vertex_attributes: Vec<vk::VertexInputAttributeDescription>,
    /// Empty for a depth-only pipeline.
    color_formats: Vec<vk::Format>,
    depth_format: Option<vk::Format>,
    depth_write: bool,
    depth_compare: vk::CompareOp,
    /// Whether the draws set the cull mode (`vkCmdSetCullMode`); otherwise nothing is culled.
    dynamic_cull_mode: bool,
    samples: vk::SampleCountFlags,
}

impl<'a> GraphicsPipelineBuilder<'a> {
    pub fn new(vertex: &'a ShaderModule, fragment: &'a ShaderModule, color_format: vk::Format) -> Self {
        Self {
            vertex,
            fragment: Some(fragment),
            specialization: Specialization::default(),
            vertex_stride: 0,
            vertex_attributes: Vec::new(),
            color_formats: vec![color_format],
            depth_format: None,
            depth_write: false,
            depth_compare: vk::CompareOp::LESS,
            dynamic_cull_mode: false,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    /// A pipeline without a fragment shader or colour attachment that writes depth into
    /// `depth_format` (less-than): shadow maps.
    pub fn depth_only(vertex: &'a ShaderModule, depth_format: vk::Format) -> Self {
        Self {
            vertex,
            fragment: None,
            specialization: Specialization::default(),
            vertex_stride: 0,
            vertex_attributes: Vec::new(),
            color_formats: Vec::new(),
            depth_format: Some(depth_format),
            depth_write: true,
            depth_compare: vk::CompareOp::LESS,
            dynamic_cull_mode: false,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    /// One interleaved vertex buffer at binding 0: `(format, byte offset)` per location.
    pub fn vertex_layout(mut self, stride: u32, attributes: &[(vk::Format, u32)]) -> Self {
        self.vertex_stride = stride;
        self.vertex_attributes = attributes
            .iter()
            .enumerate()
            .map(|(location, &(format, offset))| vk::VertexInputAttributeDescription {
                location: location as u32,
                binding: 0,
                format,
                offset,
            })
            .collect();
        self
    }

    /// The colour attachments' formats, in their locations' order, in place of the one.
    pub fn color_formats(mut self, formats: &[vk::Format]) -> Self {
        self.color_formats = formats.to_vec();
        self
    }

    /// Depth written where `compare` passes.
    pub fn depth_write_by(self, format: vk::Format, compare: vk::CompareOp) -> Self {
        self.depth_state(format, true, compare)
    }

    /// Depth test and write, less-than.
    pub fn depth(self, format: vk::Format) -> Self {
        self.depth_state(format, true, vk::CompareOp::LESS)
    }

    /// Depth test by `compare` without writing depth.
    pub fn depth_test_only(self, format: vk::Format, compare: vk::CompareOp) -> Self {
        self.depth_state(format, false, compare)
    }

    fn depth_state(mut self, format: vk::Format, write: bool, compare: vk::CompareOp) -> Self {
        self.depth_format = Some(format);
        self.depth_write = write;
        self.depth_compare = compare;
        self
    }

    /// The cull mode is set by each draw (core in Vulkan 1.3), so one pipeline draws both
    /// open meshes and solids whose back faces are culled.
    pub fn dynamic_cull_mode(mut self) -> Self {
        self.dynamic_cull_mode = true;
        self
    }

    /// Rasterization samples per pixel, as the attachments have (default 1).
    pub fn samples(mut self, samples: vk::SampleCountFlags) -> Self {
        self.samples = samples;
        self
    }

    pub fn specialization(mut self, specialization: Specialization) -> Self {
        self.specialization = specialization;
        self
    }

    pub fn build(self, device: &Arc<Device>, layout: &PipelineLayout, name: &str) -> Result<Pipeline> {
        let entries = self.specialization.entries();
        let data: &[u8] = bytemuck::cast_slice(&self.specialization.0);
        let spec_info = vk::SpecializationInfo::default().map_entries(&entries).data(data);
        let mut stages = vec![vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(self.vertex.handle)
            .name(c"main")
            .specialization_info(&spec_info)];
        if let Some(fragment) = self.fragment {
            stages.push(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::FRAGMENT)
                    .module(fragment.handle)
                    .name(c"main")
                    .specialization_info(&spec_info),
            );
        }
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: self.vertex_stride,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let vertex_input = if self.vertex_attributes.is_empty() {
            vk::PipelineVertexInputStateCreateInfo::default()
        } else {
            vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&bindings)
                .vertex_attribute_descriptions(&self.vertex_attributes)
        };
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(self.samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(self.depth_format.is_some())
            .depth_write_enable(self.depth_write)
            .depth_compare_op(self.depth_compare);
        let blend_attachment =
            vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA);
        let blend_attachments: Vec<_> = self.color_formats.iter().map(|_| blend_attachment).collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if self.dynamic_cull_mode {
            dynamic_states.push(vk::DynamicState::CULL_MODE);
        }
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&self.color_formats)
            .depth_attachment_format(self.depth_format.unwrap_or(vk::Format::UNDEFINED));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.handle)
            .push_next(&mut rendering);
        let handle = unsafe {
            device
                .handle
                .create_graphics_pipelines(device.pipeline_cache.handle, &[info], None)
        }
        .map_err(|(_, e)| e)
        .with_context(|| format!("cannot create graphics pipeline '{name}'"))?[0];
        device.set_name(handle, name);
        Ok(Pipeline {
            device: device.clone(),
            handle,
        })
    }
}

/// Begins dynamic rendering into the whole of `extent` and sets the dynamic viewport
/// (depth range 0..1) and scissor to it, as every pass of the renderer draws.
pub fn begin_full_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
    color: &[vk::RenderingAttachmentInfo],
    depth: Option<&vk::RenderingAttachmentInfo>,
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    begin_rendering(device, cmd, area, color, depth);
}

/// Begins dynamic rendering into `area` of the attachments, with the viewport and scissor
/// covering that area.
pub fn begin_rendering(
    device: &Device,
    cmd: vk::CommandBuffer,
    area: vk::Rect2D,
    color: &[vk::RenderingAttachmentInfo],
    depth: Option<&vk::RenderingAttachmentInfo>,
) {
    let mut rendering = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(color);
    if let Some(depth) = depth {
        rendering = rendering.depth_attachment(depth);
    }
    let viewport = vk::Viewport {
        x: area.offset.x as f32,
        y: area.offset.y as f32,
        width: area.extent.width as f32,
        height: area.extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    unsafe {
        device.handle.cmd_begin_rendering(cmd, &rendering);
        device.handle.cmd_set_viewport(cmd, 0, &[viewport]);
        device.handle.cmd_set_scissor(cmd, 0, &[area]);
    }
}
