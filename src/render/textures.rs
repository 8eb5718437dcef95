//! Material textures on the GPU: uploaded once with the full mip chain made on the CPU
//! (scene/mips.rs; a builtin map's from the disk cache); tables read by texel, their top
//! level alone.

use std::sync::Arc;

use anyhow::{bail, ensure, Context, Result};
use ash::vk;

use crate::cache::DiskCache;
use crate::scene::mips::cached_mip_levels;
use crate::scene::{TexelFormat, TextureData};
use crate::vk::{transfer, Device, Image, ImageUse, OneShot};

fn vk_format(format: TexelFormat) -> (vk::Format, u32) {
    match format {
        TexelFormat::Rgba8Srgb => (vk::Format::R8G8B8A8_SRGB, 4),
        TexelFormat::Rgba8Unorm => (vk::Format::R8G8B8A8_UNORM, 4),
        TexelFormat::Rgba16Unorm => (vk::Format::R16G16B16A16_UNORM, 8),
        TexelFormat::Rgba32Float => (vk::Format::R32G32B32A32_SFLOAT, 16),
    }
}

pub struct GpuTexture {
    pub image: Image,
}

impl GpuTexture {
    /// Uploads `texture` with its mip chain.
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot, texture: &TextureData) -> Result<Self> {
        Self::upload_levels(device, one_shot, texture, true)
    }

    /// Uploads `texture` as its top level alone: a table that shaders read by texel, which
    /// no mip would serve.
    pub fn upload_table(device: &Arc<Device>, one_shot: &OneShot, texture: &TextureData) -> Result<Self> {
        Self::upload_levels(device, one_shot, texture, false)
    }

    fn upload_levels(device: &Arc<Device>, one_shot: &OneShot, texture: &TextureData, mips: bool) -> Result<Self> {
        let (format, texel_bytes) = vk_format(texture.format);
        let extent = vk::Extent2D {
            width: texture.width,
            height: texture.height,
        };
        let expected = u64::from(texture.width) * u64::from(texture.height) * u64::from(texel_bytes);
        ensure!(
            texture.pixels.len() as u64 == expected,
            "texture '{}' has {} bytes for {}x{} {:?}",
            texture.name,
            texture.pixels.len(),
            texture.width,
            texture.height,
            texture.format
        );
        let features = unsafe {
            device
                .instance
                .handle
                .get_physical_device_format_properties(device.physical, format)
        }
        .optimal_tiling_features;
        let filterable = vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
        if !features.contains(filterable) {
            bail!(
                "texture '{}': this device cannot filter {format:?} textures",
                texture.name
            );
        }
        let below = if mips {
            cached_mip_levels(texture, &DiskCache::from_env())
        } else {
            Vec::new()
        };
        let levels: Vec<&[u8]> = std::iter::once(texture.pixels.as_slice())
            .chain(below.iter().map(Vec::as_slice))
            .collect();
        let image = Image::with_mips(
            device,
            extent,
            levels.len() as u32,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            vk::ImageAspectFlags::COLOR,
            &texture.name,
        )?;
        transfer::upload_image(device, one_shot, &image, &levels, ImageUse::UNDEFINED, ImageUse::FRAGMENT_READ)
            .with_context(|| format!("uploading texture '{}'", texture.name))?;
        Ok(Self { image })
    }
}

/// A 1×1 stand-in bound where a material has no map, so every material binds the same
/// layout.
pub fn placeholder(name: &str, format: TexelFormat, texel: [u8; 4]) -> TextureData {
    TextureData {
        name: name.to_owned(),
        width: 1,
        height: 1,
        format,
        pixels: texel.to_vec(),
    }
}
