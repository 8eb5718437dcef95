//! The driver's compiled pipelines, kept across runs: a `VkPipelineCache` created from what
//! the last run of the same driver on the same device left in the disk cache
//! (`crate::cache`), and written back there when the device goes.

use anyhow::{Context, Result};
use ash::vk;

use crate::cache::{self, DiskCache};

pub struct PipelineCache {
    pub handle: vk::PipelineCache,
    disk: DiskCache,
    /// The driver's cache data is only valid for one device, driver and cache layout.
    key: u64,
}

/// The disk cache's entry name.
const ENTRY: &str = "pipelines";

impl PipelineCache {
    /// A cache seeded from `disk`'s entry for this device and driver, if it has one.
    pub fn new(device: &ash::Device, properties: &vk::PhysicalDeviceProperties, disk: DiskCache) -> Result<Self> {
        let key = cache::key(&[
            &properties.vendor_id.to_le_bytes(),
            &properties.device_id.to_le_bytes(),
            &properties.driver_version.to_le_bytes(),
            &properties.pipeline_cache_uuid,
        ]);
        let initial = disk.load(ENTRY, key).unwrap_or_default();
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&initial);
        // Drivers check the data's header and ignore data of another device or version;
        // one that rejects it anyway gets an empty cache.
        let handle = match unsafe { device.create_pipeline_cache(&info, None) } {
            Ok(handle) => handle,
            Err(_) if !initial.is_empty() => {
                unsafe { device.create_pipeline_cache(&vk::PipelineCacheCreateInfo::default(), None) }
                    .context("cannot create a pipeline cache")?
            }
            Err(e) => return Err(e).context("cannot create a pipeline cache"),
        };
        Ok(Self { handle, disk, key })
    }

    /// Writes what the driver has compiled to the disk cache and destroys the cache; the
    /// device calls it before it is destroyed itself.
    pub fn save_and_destroy(&mut self, device: &ash::Device) {
        if let Ok(data) = unsafe { device.get_pipeline_cache_data(self.handle) } {
            if !data.is_empty() {
                self.disk.store(ENTRY, self.key, &data);
            }
        }
        unsafe { device.destroy_pipeline_cache(self.handle, None) };
        self.handle = vk::PipelineCache::null();
    }
}
