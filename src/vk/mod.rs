//! Explicit Vulkan, one concept a file. Every wrapper owns its handle and destroys it in
//! `Drop`; resources hold an `Arc<Device>` so the device outlives them.

pub mod buffer;
pub mod commands;
pub mod descriptors;
pub mod device;
pub mod image;
pub mod instance;
pub mod pipeline;
pub mod pipeline_cache;
pub mod readback;
pub mod sampler;
pub mod shader;
pub mod surface;
pub mod swapchain;
pub mod sync;
pub mod timestamps;
pub mod transfer;

pub use buffer::Buffer;
pub use commands::{CommandPool, OneShot};
pub use descriptors::{DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter};
pub use device::{Device, DeviceChoice, DeviceInfo, DeviceOptions, WindowHandles};
pub use image::{mip_count, Image, ImageView};
pub use pipeline::{
    begin_full_rendering, begin_rendering, GraphicsPipelineBuilder, Pipeline, PipelineLayout, Specialization,
};
pub use pipeline_cache::PipelineCache;
pub use readback::{ImageRegion, Readback};
pub use sampler::Sampler;
pub use shader::ShaderModule;
pub use swapchain::{Acquired, Swapchain};
pub use sync::{buffer_barrier, transition, transition_levels, BufferUse, Fence, ImageUse, Semaphore};
pub use timestamps::Timestamps;
