//! The swapchain of a window: its images and views, one "ready to present" semaphore per
//! image (a present may still be using the previous one for the same image), recreation.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::{khr, vk};

use super::device::Device;
use super::sync::Semaphore;

pub struct Swapchain {
    device: Arc<Device>,
    pub loader: khr::swapchain::Device,
    pub handle: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    /// Signalled when rendering to image `i` is done; waited for by its present.
    pub ready_to_present: Vec<Semaphore>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
}

/// What acquiring an image gave.
pub enum Acquired {
    Image {
        index: u32,
        suboptimal: bool,
    },
    /// The swapchain no longer matches the surface: recreate it.
    OutOfDate,
}

impl Swapchain {
    /// A swapchain for the device's surface of about `wanted` pixels (the surface decides),
    /// replacing `old` if given.
    pub fn new(device: &Arc<Device>, wanted: vk::Extent2D, old: Option<&Swapchain>) -> Result<Self> {
        let surface = device
            .surface
            .as_ref()
            .context("the device was created without a window surface")?;
        let (caps, formats) = unsafe {
            (
                surface
                    .loader
                    .get_physical_device_surface_capabilities(device.physical, surface.handle)?,
                surface
                    .loader
                    .get_physical_device_surface_formats(device.physical, surface.handle)?,
            )
        };
        // An sRGB format lets the hardware encode; the tone-map pass encodes otherwise.
        let preferred = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];
        let chosen = preferred
            .iter()
            .find_map(|p| formats.iter().find(|f| f.format == *p))
            .or_else(|| formats.first())
            .context("the surface offers no formats")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: wanted
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: wanted
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.handle)
            .min_image_count(image_count)
            .image_format(chosen.format)
            .image_color_space(chosen.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.handle));
        let loader = khr::swapchain::Device::new(&device.instance.handle, &device.handle);
        let handle = unsafe { loader.create_swapchain(&info, None) }.context("cannot create the swapchain")?;
        let mut swapchain = Self {
            device: device.clone(),
            loader,
            handle,
            images: Vec::new(),
            views: Vec::new(),
            ready_to_present: Vec::new(),
            format: chosen.format,
            extent,
        };
        swapchain.images = unsafe { swapchain.loader.get_swapchain_images(handle) }?;
        for &image in &swapchain.images {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(chosen.format)
                .subresource_range(super::image::full_range(vk::ImageAspectFlags::COLOR));
            swapchain
                .views
                .push(unsafe { device.handle.create_image_view(&view_info, None) }?);
            swapchain.ready_to_present.push(Semaphore::new(device)?);
        }
        Ok(swapchain)
    }

    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Acquired> {
        match unsafe {
            self.loader
                .acquire_next_image(self.handle, u64::MAX, signal, vk::Fence::null())
        } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(e) => Err(e).context("vkAcquireNextImageKHR failed"),
        }
    }

    /// Presents image `index` once its semaphore signals; `false` when the swapchain must be
    /// recreated.
    pub fn present(&self, index: u32) -> Result<bool> {
        let waits = [self.ready_to_present[index as usize].handle];
        let swapchains = [self.handle];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match self.device.present(&self.loader, &info) {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(e) => Err(e).context("vkQueuePresentKHR failed"),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        unsafe {
            for &view in &self.views {
                self.device.handle.destroy_image_view(view, None);
            }
            self.loader.destroy_swapchain(self.handle, None);
        }
    }
}
