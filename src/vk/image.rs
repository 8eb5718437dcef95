//! 2D images (single- or multisampled) and cube maps (with or without mip chains) with a
//! view and their memory, freed in `Drop`, and extra views of single mip levels.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::device::Device;
use super::sync::{transition_levels, ImageUse};

pub struct Image {
    device: Arc<Device>,
    pub handle: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
    /// Array layers: 1, or 6 for a cube map.
    pub layers: u32,
    pub samples: vk::SampleCountFlags,
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
        let shape = Shape {
            extent,
            mip_levels,
            layers: 1,
            view_type: vk::ImageViewType::TYPE_2D,
            samples: vk::SampleCountFlags::TYPE_1,
        };
        Self::create(device, shape, format, usage, aspect, name)
    }

    /// A single-level image of `samples` samples per texel: a multisampled attachment.
    pub fn multisampled(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        samples: vk::SampleCountFlags,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        let shape = Shape {
            extent,
            mip_levels: 1,
            layers: 1,
            view_type: vk::ImageViewType::TYPE_2D,
            samples,
        };
        Self::create(device, shape, format, usage, aspect, name)
    }

    /// A colour cube map with `size`² faces and `mip_levels` levels; the view is a cube
    /// view of all of them. Layers are the faces +x, −x, +y, −y, +z, −z.
    pub fn cube(
        device: &Arc<Device>,
        size: u32,
        mip_levels: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        name: &str,
    ) -> Result<Self> {
        let extent = vk::Extent2D {
            width: size,
            height: size,
        };
        let shape = Shape {
            extent,
            mip_levels,
            layers: 6,
            view_type: vk::ImageViewType::CUBE,
            samples: vk::SampleCountFlags::TYPE_1,
        };
        Self::create(device, shape, format, usage, vk::ImageAspectFlags::COLOR, name)
    }

    /// A colour 2D array image of `layers` single-level layers; the view is a 2D array view.
    pub fn array_2d(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        layers: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        name: &str,
    ) -> Result<Self> {
        Self::array(device, extent, layers, format, usage, vk::ImageAspectFlags::COLOR, name)
    }

    /// A depth 2D array image of `layers` single-level `size`² layers (the faces of cube
    /// shadow maps); the view is a 2D array view for sampling, [`Self::layer_view`] one
    /// layer for rendering.
    pub fn depth_array(
        device: &Arc<Device>,
        size: u32,
        layers: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        name: &str,
    ) -> Result<Self> {
        let extent = vk::Extent2D {
            width: size,
            height: size,
        };
        Self::array(device, extent, layers, format, usage, vk::ImageAspectFlags::DEPTH, name)
    }

    fn array(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        layers: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        let shape = Shape {
            extent,
            mip_levels: 1,
            layers,
            view_type: vk::ImageViewType::TYPE_2D_ARRAY,
            samples: vk::SampleCountFlags::TYPE_1,
        };
        Self::create(device, shape, format, usage, aspect, name)
    }

    fn create(
        device: &Arc<Device>,
        shape: Shape,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
        name: &str,
    ) -> Result<Self> {
        let Shape {
            extent,
            mip_levels,
            layers,
            view_type,
            samples,
        } = shape;
        let flags = if view_type == vk::ImageViewType::CUBE {
            vk::ImageCreateFlags::CUBE_COMPATIBLE
        } else {
            vk::ImageCreateFlags::empty()
        };
        let info = vk::ImageCreateInfo::default()
            .flags(flags)
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(mip_levels)
            .array_layers(layers)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let handle = unsafe { device.handle.create_image(&info, None) }.with_context(|| {
            format!(
                "cannot create image '{name}' {}x{} {format:?}",
                extent.width, extent.height
            )
        })?;
        let requirements = unsafe { device.handle.get_image_memory_requirements(handle) };
        let allocation = device.allocate(&AllocationCreateDesc {
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
            layers,
            samples,
        };
        let a = image.allocation.as_ref().expect("allocated above");
        unsafe { device.handle.bind_image_memory(handle, a.memory(), a.offset()) }
            .context("vkBindImageMemory failed")?;
        image.view = image.create_view(view_type, image.all_levels())?;
        device.set_name(handle, name);
        Ok(image)
    }

    /// Records clearing every level and layer to 0, whatever they held, leaving the image in
    /// `then` (its usage must include `TRANSFER_DST`).
    pub fn record_clear(&self, cmd: vk::CommandBuffer, then: ImageUse) {
        let range = self.all_levels();
        let d = &self.device;
        transition_levels(d, cmd, self.handle, range, ImageUse::UNDEFINED, ImageUse::CLEAR_DST);
        let zero = vk::ClearColorValue { float32: [0.0; 4] };
        let layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        unsafe { d.handle.cmd_clear_color_image(cmd, self.handle, layout, &zero, &[range]) };
        transition_levels(d, cmd, self.handle, range, ImageUse::CLEAR_DST, then);
    }

    /// The size of mip `level`: each side halved per level, down to 1.
    pub fn level_extent(&self, level: u32) -> vk::Extent2D {
        vk::Extent2D {
            width: (self.extent.width >> level).max(1),
            height: (self.extent.height >> level).max(1),
        }
    }

    /// Every level and layer.
    pub fn all_levels(&self) -> vk::ImageSubresourceRange {
        full_range(self.aspect)
            .level_count(self.mip_levels)
            .layer_count(self.layers)
    }

    /// Mip `level`, every layer.
    pub fn level_range(&self, level: u32) -> vk::ImageSubresourceRange {
        full_range(self.aspect).base_mip_level(level).layer_count(self.layers)
    }

    /// A 2D array view of mip `level`: what compute shaders write a level through.
    pub fn level_view(&self, level: u32) -> Result<ImageView> {
        let handle = self.create_view(vk::ImageViewType::TYPE_2D_ARRAY, self.level_range(level))?;
        Ok(ImageView {
            device: self.device.clone(),
            handle,
        })
    }

    /// A 2D view of array layer `layer`: what a pass renders one layer through.
    pub fn layer_view(&self, layer: u32) -> Result<ImageView> {
        let range = full_range(self.aspect).base_array_layer(layer);
        let handle = self.create_view(vk::ImageViewType::TYPE_2D, range)?;
        Ok(ImageView {
            device: self.device.clone(),
            handle,
        })
    }

    fn create_view(&self, view_type: vk::ImageViewType, range: vk::ImageSubresourceRange) -> Result<vk::ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(self.handle)
            .view_type(view_type)
            .format(self.format)
            .subresource_range(range);
        unsafe { self.device.handle.create_image_view(&info, None) }
            .with_context(|| format!("cannot create a {view_type:?} view of an image"))
    }
}

struct Shape {
    extent: vk::Extent2D,
    mip_levels: u32,
    layers: u32,
    view_type: vk::ImageViewType,
    samples: vk::SampleCountFlags,
}

/// An extra view of an image, destroyed in `Drop`; the image must outlive it.
pub struct ImageView {
    device: Arc<Device>,
    pub handle: vk::ImageView,
}

impl Drop for ImageView {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_image_view(self.handle, None) };
    }
}

/// A tightly packed buffer ⇄ image copy of `extent` texels of mip `level`, all `layers`.
pub fn copy_region(aspect: vk::ImageAspectFlags, level: u32, layers: u32, extent: vk::Extent2D) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default()
                .aspect_mask(aspect)
                .mip_level(level)
                .layer_count(layers),
        )
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}

/// The first mip level of a single-layer image (`.level_count(n)` for more).
pub fn full_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
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
