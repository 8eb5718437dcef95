//! Samplers, freed in `Drop`.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;

pub struct Sampler {
    device: Arc<Device>,
    pub handle: vk::Sampler,
}

impl Sampler {
    /// Trilinear, repeating (material maps tile), anisotropic when the device has it.
    pub fn material(device: &Arc<Device>) -> Result<Self> {
        let mut info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .max_lod(vk::LOD_CLAMP_NONE);
        if let Some(max) = device.max_anisotropy {
            // 16x is where the quality of grazing views stops improving visibly.
            info = info.anisotropy_enable(true).max_anisotropy(max.min(16.0));
        }
        Self::create(device, &info)
    }

    /// Trilinear and clamped to the edge: cube maps (whose faces filter seamlessly) and
    /// lookup tables.
    pub fn clamped(device: &Arc<Device>) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE);
        Self::create(device, &info)
    }

    /// Nearest, clamped to the edge, one level: images read texel by texel (shadow maps,
    /// whose depth format need not filter, and the subsurface table).
    pub fn nearest(device: &Arc<Device>) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        Self::create(device, &info)
    }

    fn create(device: &Arc<Device>, info: &vk::SamplerCreateInfo) -> Result<Self> {
        let handle = unsafe { device.handle.create_sampler(info, None) }.context("cannot create a sampler")?;
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_sampler(self.handle, None) };
    }
}
