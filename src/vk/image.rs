//! 2D images (with or without mip chains) with a view and their memory, freed in `Drop`.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::device::Device;

pub struct Image {
    device: Arc<Device>,
    pub handle: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
}

/// The number of levels of a full mip chain down to 1×1.
pub fn mip_count(extent: vk::Extent2D) -> u32 {
    32 - extent.width.max(extent.height).max(1).leading_zeros()
}

impl Image {
    /// A single-level image.
    pub fn new_2d(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        Self::with_mips(device, extent, 1, format, usage, aspect, name)
    }

    /// An image with `mip_levels` levels, the view covering all of them.
    pub fn with_mips(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        mip_levels: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let handle = unsafe { device.handle.create_image(&info, None) }
            .with_context(|| format!("cannot create image '{name}' {}x{} {format:?}", extent.width, extent.height))?;
        let requirements = unsafe { device.handle.get_image_memory_requirements(handle) };
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.handle.destroy_image(handle, None) };
                return Err(e).with_context(|| format!("cannot allocate memory for image '{name}'"));
            }
        };
        let mut image = Self {
            device: device.clone(),
            handle,
            view: vk::ImageView::null(),
            allocation: Some(allocation),
            format,
            extent,
            aspect,
            mip_levels,
        };
        let a = image.allocation.as_ref().expect("allocated above");
        unsafe { device.handle.bind_image_memory(handle, a.memory(), a.offset()) }
            .context("vkBindImageMemory failed")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(full_range(aspect).level_count(mip_levels));
        image.view = unsafe { device.handle.create_image_view(&view_info, None) }
            .with_context(|| format!("cannot create a view of image '{name}'"))?;
        device.set_name(handle, name);
        Ok(image)
    }
}

/// The first mip level of a single-layer image (`.level_count(n)` for more).
pub fn full_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default().aspect_mask(aspect).level_count(1).layer_count(1)
}

impl Drop for Image {
    fn drop(&mut self) {
        unsafe {
            self.device.handle.destroy_image_view(self.view, None);
            self.device.handle.destroy_image(self.handle, None);
        }
        if let Some(a) = self.allocation.take() {
            let _ = self.device.allocator().free(a);
        }
    }
}
