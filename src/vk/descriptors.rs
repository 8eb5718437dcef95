//! Descriptor set layouts, pools and writes, built by hand next to the shaders that
//! declare them.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;

pub struct DescriptorSetLayout {
    device: Arc<Device>,
    pub handle: vk::DescriptorSetLayout,
    /// (type, count) per binding, so a pool can be sized for it.
    pub bindings: Vec<(vk::DescriptorType, u32)>,
}

/// Collects bindings in order: binding `i` is the `i`-th call.
#[derive(Default)]
pub struct DescriptorSetLayoutBuilder {
    bindings: Vec<vk::DescriptorSetLayoutBinding<'static>>,
}

impl DescriptorSetLayoutBuilder {
    pub fn binding(mut self, kind: vk::DescriptorType, stages: vk::ShaderStageFlags) -> Self {
        let binding = vk::DescriptorSetLayoutBinding::default()
            .binding(self.bindings.len() as u32)
            .descriptor_type(kind)
            .descriptor_count(1)
            .stage_flags(stages);
        self.bindings.push(binding);
        self
    }

    pub fn build(self, device: &Arc<Device>, name: &str) -> Result<DescriptorSetLayout> {
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&self.bindings);
        let handle = unsafe { device.handle.create_descriptor_set_layout(&info, None) }
            .with_context(|| format!("cannot create descriptor set layout '{name}'"))?;
        device.set_name(handle, name);
        let bindings = self
            .bindings
            .iter()
            .map(|b| (b.descriptor_type, b.descriptor_count))
            .collect();
        Ok(DescriptorSetLayout {
            device: device.clone(),
            handle,
            bindings,
        })
    }
}

impl Drop for DescriptorSetLayout {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_descriptor_set_layout(self.handle, None) };
    }
}

/// A pool sized for `sets` sets of one layout; its sets die with it.
pub struct DescriptorPool {
    device: Arc<Device>,
    pub handle: vk::DescriptorPool,
}

impl DescriptorPool {
    pub fn for_layout(device: &Arc<Device>, layout: &DescriptorSetLayout, sets: u32) -> Result<Self> {
        Self::for_layouts(device, &[layout], sets)
    }

    /// A pool of `sets` sets of each of `layouts`.
    pub fn for_layouts(device: &Arc<Device>, layouts: &[&DescriptorSetLayout], sets: u32) -> Result<Self> {
        let sizes: Vec<vk::DescriptorPoolSize> = layouts
            .iter()
            .flat_map(|layout| &layout.bindings)
            .map(|&(ty, count)| vk::DescriptorPoolSize {
                ty,
                descriptor_count: count * sets,
            })
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(sets * layouts.len() as u32)
            .pool_sizes(&sizes);
        let handle =
            unsafe { device.handle.create_descriptor_pool(&info, None) }.context("cannot create a descriptor pool")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }

    pub fn allocate(&self, layout: &DescriptorSetLayout) -> Result<vk::DescriptorSet> {
        let layouts = [layout.handle];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.handle)
            .set_layouts(&layouts);
        Ok(
            unsafe { self.device.handle.allocate_descriptor_sets(&info) }
                .context("cannot allocate a descriptor set")?[0],
        )
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_descriptor_pool(self.handle, None) };
    }
}

enum Resource {
    Buffer(vk::DescriptorBufferInfo),
    Image(vk::DescriptorImageInfo),
}

/// Collects the resources of one set, binding by binding, then writes them at once.
#[derive(Default)]
pub struct DescriptorWriter {
    writes: Vec<(u32, vk::DescriptorType, Resource)>,
}

impl DescriptorWriter {
    pub fn buffer(mut self, binding: u32, kind: vk::DescriptorType, buffer: vk::Buffer) -> Self {
        let info = vk::DescriptorBufferInfo {
            buffer,
            offset: 0,
            range: vk::WHOLE_SIZE,
        };
        self.writes.push((binding, kind, Resource::Buffer(info)));
        self
    }

    pub fn image(
        mut self,
        binding: u32,
        kind: vk::DescriptorType,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) -> Self {
        let info = vk::DescriptorImageInfo {
            sampler,
            image_view: view,
            image_layout: layout,
        };
        self.writes.push((binding, kind, Resource::Image(info)));
        self
    }

    pub fn write(self, device: &Device, set: vk::DescriptorSet) {
        let writes: Vec<vk::WriteDescriptorSet> = self
            .writes
            .iter()
            .map(|(binding, kind, resource)| {
                let write = vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(*binding)
                    .descriptor_type(*kind);
                match resource {
                    Resource::Buffer(info) => write.buffer_info(std::slice::from_ref(info)),
                    Resource::Image(info) => write.image_info(std::slice::from_ref(info)),
                }
            })
            .collect();
        unsafe { device.handle.update_descriptor_sets(&writes, &[]) };
    }
}
