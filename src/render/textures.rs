//! Material textures on the GPU: uploaded once with the full mip chain made on the CPU
//! (scene/mips.rs; a builtin map's from the disk cache); tables read by texel, their top
//! level alone.

use std::sync::Arc;

use anyhow::{bail, ensure, Context, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::cache::DiskCache;
use crate::scene::mips::cached_mip_levels;
use crate::scene::{TexelFormat, TextureData};
use crate::vk::{copy_region, full_range, transition_levels, Buffer, Device, Image, ImageUse, OneShot};

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
        let levels = [texture.pixels.as_slice()].into_iter().chain(below.iter().map(Vec::as_slice));
        let image = Image::with_mips(
            device,
            extent,
            1 + below.len() as u32,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            vk::ImageAspectFlags::COLOR,
            &texture.name,
        )?;
        let mut staging = Buffer::new(
            device,
            levels.clone().map(|l| l.len() as u64).sum(),
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
            "texture staging",
        )?;
        let mut regions = Vec::new();
        let mut offset = 0;
        for (level, bytes) in (0..).zip(levels) {
            staging.write_at(offset, bytes)?;
            let region = copy_region(image.aspect, level, 1, image.level_extent(level));
            regions.push(region.buffer_offset(offset as u64));
            offset += bytes.len();
        }
        one_shot
            .run(|cmd| record_upload(device, cmd, &staging, &image, &regions))
            .with_context(|| format!("uploading texture '{}'", texture.name))?;
        Ok(Self { image })
    }
}

/// Copies every level from `staging` and leaves them readable by fragment shaders.
fn record_upload(
    device: &Device,
    cmd: vk::CommandBuffer,
    staging: &Buffer,
    image: &Image,
    regions: &[vk::BufferImageCopy],
) {
    let all = full_range(image.aspect).level_count(image.mip_levels);
    transition_levels(device, cmd, image.handle, all, ImageUse::UNDEFINED, ImageUse::TRANSFER_DST);
    unsafe {
        device.handle.cmd_copy_buffer_to_image(
            cmd,
            staging.handle,
            image.handle,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            regions,
        )
    };
    transition_levels(device, cmd, image.handle, all, ImageUse::TRANSFER_DST, ImageUse::FRAGMENT_READ);
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
