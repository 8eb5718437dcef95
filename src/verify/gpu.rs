//! The compute harness: shaders/verify_brdf.comp evaluates one function of brdf.glsl on every
//! tuple of a storage buffer, one dispatch per function, and the results are read back.
//! Both buffers live in host-visible memory: the CPU writes the tuples and reads the results
//! in place, without staging copies.

use std::sync::Arc;

use anyhow::{ensure, Context, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::render::subsurface::SubsurfaceTable;
use crate::vk::{
    Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device, OneShot,
    Pipeline, PipelineLayout, ShaderModule, Specialization,
};

use super::functions::{Function, Tuple, Values};

/// SPIR-V of shaders/verify_brdf.comp, compiled by build.rs like the renderer's shaders.
const VERIFY_BRDF_COMP: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/verify_brdf.comp.spv"));
/// `local_size_x` of verify_brdf.comp.
const WORKGROUP_SIZE: u32 = 64;
/// Bytes of one tuple's results: two vec4.
const RESULT_SIZE: usize = std::mem::size_of::<Values<f32>>();

pub struct Harness {
    device: Arc<Device>,
    one_shot: OneShot,
    shader: ShaderModule,
    pipeline_layout: PipelineLayout,
    /// Owns `set`.
    _pool: DescriptorPool,
    _set_layout: DescriptorSetLayout,
    set: vk::DescriptorSet,
    inputs: Buffer,
    outputs: Buffer,
    /// Read by brdf_cos with a pre-integrated subsurface model.
    _subsurface: SubsurfaceTable,
    /// Tuples per dispatch: what the storage buffers hold.
    capacity: usize,
}

impl Harness {
    /// A harness for up to `capacity` tuples per dispatch.
    /// A harness for up to `tuples` tuples a function, evaluated in as few dispatches as
    /// the device's largest storage buffer allows.
    pub fn new(device: &Arc<Device>, tuples: usize) -> Result<Self> {
        let limits = &device.limits;
        let per_buffer = limits.max_storage_buffer_range as usize / std::mem::size_of::<Tuple>().max(RESULT_SIZE);
        let capacity = tuples.min(per_buffer).max(1);
        let input_size = (capacity * std::mem::size_of::<Tuple>()) as vk::DeviceSize;
        let output_size = (capacity * RESULT_SIZE) as vk::DeviceSize;
        ensure!(
            (capacity as u64).div_ceil(u64::from(WORKGROUP_SIZE)) <= u64::from(limits.max_compute_work_group_count[0]),
            "{capacity} tuples need more workgroups than {} dispatches",
            device.info.name
        );

        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let inputs = Buffer::new(device, input_size, storage, MemoryLocation::CpuToGpu, "verify inputs")?;
        let outputs = Buffer::new(device, output_size, storage, MemoryLocation::GpuToCpu, "verify results")?;

        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE)
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE)
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::COMPUTE,
            )
            .build(device, "verify set layout")?;
        let one_shot = OneShot::new(device)?;
        let subsurface = SubsurfaceTable::upload(device, &one_shot)?;
        let pool = DescriptorPool::for_layout(device, &set_layout, 1)?;
        let set = pool.allocate(&set_layout)?;
        let writer = DescriptorWriter::default()
            .buffer(0, vk::DescriptorType::STORAGE_BUFFER, inputs.handle)
            .buffer(1, vk::DescriptorType::STORAGE_BUFFER, outputs.handle);
        subsurface.bind(writer).write(device, set);
        // The push constant is the tuple count.
        let pipeline_layout = PipelineLayout::new(device, &[&set_layout], 4, vk::ShaderStageFlags::COMPUTE)?;
        let shader = ShaderModule::new(device, VERIFY_BRDF_COMP, "verify_brdf.comp")?;
        Ok(Self {
            device: device.clone(),
            one_shot,
            shader,
            pipeline_layout,
            _pool: pool,
            _set_layout: set_layout,
            set,
            inputs,
            outputs,
            _subsurface: subsurface,
            capacity,
        })
    }

    /// Evaluates `function` on every tuple on the GPU, in one dispatch, into `results`
    /// (reused: fresh 32 MB vectors per function cost more in page faults than the copy).
    pub fn evaluate(&mut self, function: Function, tuples: &[Tuple], results: &mut Vec<Values<f32>>) -> Result<()> {
        let name = format!("verify {}", function.name());
        // One pipeline per function: the specialization constant folds the other cases away.
        let pipeline = Pipeline::compute(
            &self.device,
            &self.pipeline_layout,
            &self.shader,
            &Specialization(vec![function.id()]),
            &name,
        )?;
        results.clear();
        for chunk in tuples.chunks(self.capacity) {
            self.dispatch(function, &pipeline, chunk, results)?;
        }
        Ok(())
    }

    /// Evaluates `tuples` (at most `capacity`), appending their values to `results`.
    fn dispatch(
        &mut self,
        function: Function,
        pipeline: &Pipeline,
        tuples: &[Tuple],
        results: &mut Vec<Values<f32>>,
    ) -> Result<()> {
        self.inputs.write(bytemuck::cast_slice(tuples))?;
        let count = tuples.len() as u32;
        let device = &self.device.handle;
        self.one_shot
            .run(|cmd| unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.handle);
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.pipeline_layout.handle,
                    0,
                    &[self.set],
                    &[],
                );
                device.cmd_push_constants(
                    cmd,
                    self.pipeline_layout.handle,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    &count.to_ne_bytes(),
                );
                device.cmd_dispatch(cmd, count.div_ceil(WORKGROUP_SIZE), 1, 1);
                // The results are read by the host once the fence has signalled.
                let to_host = [vk::MemoryBarrier2::default()
                    .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                    .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                    .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                    .dst_access_mask(vk::AccessFlags2::HOST_READ)];
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
            })
            .with_context(|| format!("cannot run the harness on {}", function.name()))?;
        let bytes = &self.outputs.read()?[..tuples.len() * RESULT_SIZE];
        // The mapping is at least 4-byte aligned, but copy rather than assume it.
        results.extend(
            bytes
                .chunks_exact(RESULT_SIZE)
                .map(bytemuck::pod_read_unaligned::<Values<f32>>),
        );
        Ok(())
    }
}
