//! The pre-integrated subsurface table on the GPU: `brdf::subsurface` computes it in f64
//! once per process; it is uploaded as RGBA32F and bound at set 0, binding 2, of the
//! forward pass and of `argil verify`'s harness (subsurface.glsl reads it by texel).

use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::textures::GpuTexture;
use crate::brdf::subsurface::{PreintegratedTable, PREINTEGRATED_HEIGHT, PREINTEGRATED_WIDTH};
use crate::scene::{TexelFormat, TextureData};
use crate::vk::{DescriptorWriter, Device, OneShot, Sampler};

/// The binding of the table in set 0, after the set's buffers.
pub const SUBSURFACE_TABLE_BINDING: u32 = 2;

pub struct SubsurfaceTable {
    texture: GpuTexture,
    /// Nearest and clamped to the edge: the shaders fetch and gather texels, and an RGBA32F
    /// format need not filter.
    sampler: Sampler,
}

impl SubsurfaceTable {
    pub fn upload(device: &Arc<Device>, one_shot: &OneShot) -> Result<Self> {
        let table = PreintegratedTable::get();
        let data = TextureData {
            name: "pre-integrated subsurface table".to_owned(),
            width: PREINTEGRATED_WIDTH as u32,
            height: PREINTEGRATED_HEIGHT as u32,
            format: TexelFormat::Rgba32Float,
            pixels: bytemuck::cast_slice(table.texels()).to_vec(),
        };
        Ok(Self {
            texture: GpuTexture::upload_table(device, one_shot, &data)?,
            sampler: Sampler::nearest(device)?,
        })
    }

    /// A 1² table of zeros for the binding while no material needs the real one.
    pub fn placeholder(device: &Arc<Device>, one_shot: &OneShot) -> Result<Self> {
        let data = TextureData {
            name: "pre-integrated subsurface placeholder".to_owned(),
            width: 1,
            height: 1,
            format: TexelFormat::Rgba32Float,
            pixels: vec![0; 16],
        };
        Ok(Self {
            texture: GpuTexture::upload_table(device, one_shot, &data)?,
            sampler: Sampler::nearest(device)?,
        })
    }

    /// Adds the table at `SUBSURFACE_TABLE_BINDING` to a set's writes.
    pub fn bind(&self, writer: DescriptorWriter) -> DescriptorWriter {
        writer.image(
            SUBSURFACE_TABLE_BINDING,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            self.texture.image.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            self.sampler.handle,
        )
    }
}
