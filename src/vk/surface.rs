//! A window's Vulkan surface.

use anyhow::{Context, Result};
use ash::{khr, vk};

use super::device::WindowHandles;
use super::instance::Instance;

pub struct Surface {
    pub loader: khr::surface::Instance,
    pub handle: vk::SurfaceKHR,
}

impl Surface {
    pub fn new(instance: &Instance, window: WindowHandles) -> Result<Self> {
        let handle = unsafe {
            ash_window::create_surface(&instance.entry, &instance.handle, window.display, window.window, None)
        }
        .context("cannot create a Vulkan surface for the window")?;
        let loader = khr::surface::Instance::new(&instance.entry, &instance.handle);
        Ok(Self { loader, handle })
    }

    /// Whether `family` of `physical` can present to this surface.
    pub fn supports(&self, physical: vk::PhysicalDevice, family: u32) -> bool {
        unsafe {
            self.loader
                .get_physical_device_surface_support(physical, family, self.handle)
        }
        .unwrap_or(false)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        unsafe { self.loader.destroy_surface(self.handle, None) };
    }
}
