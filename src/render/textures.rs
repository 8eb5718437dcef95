//! Material textures on the GPU: uploaded once with a full mip chain made by blits; tables
//! read by texel, their top level alone.

use std::sync::Arc;

use anyhow::{bail, ensure, Context, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::scene::{TexelFormat, TextureData};
use crate::vk::{copy_region, full_range, mip_count, transition_levels, Buffer, Device, Image, ImageUse, OneShot};

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
    /// Uploads `texture` and builds its mip chain on the GPU (linear blits, which average
    /// sRGB texels in linear space as the format says).
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot, texture: &TextureData) -> Result<Self> {
        Self::upload_levels(device, one_shot, texture, true)
    }

    /// Uploads `texture` as its top level alone: a table that shaders read by texel, which
    /// no mip would serve (and whose first blit of a format makes lavapipe compile a blit
    /// shader: 75 ms of every start for the RGBA32F subsurface table).
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
        // Without blits, the texture has its top level only (filtering still works).
        let blits = vk::FormatFeatureFlags::BLIT_SRC | vk::FormatFeatureFlags::BLIT_DST;
        let levels = if mips && features.contains(blits) { mip_count(extent) } else { 1 };

        let mut staging = Buffer::new(
            device,
            expected,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
            "texture staging",
        )?;
        staging.write(&texture.pixels)?;
        let image = Image::with_mips(
            device,
            extent,
            levels,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
            &texture.name,
        )?;
        one_shot
            .run(|cmd| record_upload(device, cmd, &staging, &image))
            .with_context(|| format!("uploading texture '{}'", texture.name))?;
        Ok(Self { image })
    }
}

fn level(image: &Image, level: u32) -> vk::ImageSubresourceRange {
    full_range(image.aspect).base_mip_level(level)
}

fn level_extent(extent: vk::Extent2D, level: u32) -> vk::Offset3D {
    vk::Offset3D {
        x: (extent.width >> level).max(1) as i32,
        y: (extent.height >> level).max(1) as i32,
        z: 1,
    }
}

/// Copy into level 0, then each level is blitted from the one above it, which is left
/// readable by fragment shaders once used.
fn record_upload(device: &Device, cmd: vk::CommandBuffer, staging: &Buffer, image: &Image) {
    let all = full_range(image.aspect).level_count(image.mip_levels);
    transition_levels(
        device,
        cmd,
        image.handle,
        all,
        ImageUse::UNDEFINED,
        ImageUse::TRANSFER_DST,
    );
    let region = copy_region(image.aspect, 0, 1, image.extent);
    unsafe {
        device.handle.cmd_copy_buffer_to_image(
            cmd,
            staging.handle,
            image.handle,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
        )
    };
    for i in 1..image.mip_levels {
        transition_levels(
            device,
            cmd,
            image.handle,
            level(image, i - 1),
            ImageUse::TRANSFER_DST,
            ImageUse::TRANSFER_SRC,
        );
        let layers = |mip| {
            vk::ImageSubresourceLayers::default()
                .aspect_mask(image.aspect)
                .mip_level(mip)
                .layer_count(1)
        };
        let blit = vk::ImageBlit::default()
            .src_subresource(layers(i - 1))
            .src_offsets([vk::Offset3D::default(), level_extent(image.extent, i - 1)])
            .dst_subresource(layers(i))
            .dst_offsets([vk::Offset3D::default(), level_extent(image.extent, i)]);
        unsafe {
            device.handle.cmd_blit_image(
                cmd,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[blit],
                vk::Filter::LINEAR,
            )
        };
        transition_levels(
            device,
            cmd,
            image.handle,
            level(image, i - 1),
            ImageUse::TRANSFER_SRC,
            ImageUse::FRAGMENT_READ,
        );
    }
    let last = level(image, image.mip_levels - 1);
    transition_levels(
        device,
        cmd,
        image.handle,
        last,
        ImageUse::TRANSFER_DST,
        ImageUse::FRAGMENT_READ,
    );
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
