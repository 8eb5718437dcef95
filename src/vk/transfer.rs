//! Whole images and buffers to and from the host, each copy a one-shot submission that is
//! waited for: what the disk cache stores of images and buffers computed on the device and
//! uploads in their place.

use std::sync::Arc;

use anyhow::{ensure, Result};
use ash::vk;

use super::buffer::Buffer;
use super::commands::OneShot;
use super::device::Device;
use super::image::{copy_region, Image};
use super::sync::{buffer_barrier, transition_levels, BufferUse, ImageUse};

/// Bytes of mip `level` of `image`, every layer, at `texel_bytes` a texel.
pub fn level_size(image: &Image, level: u32, texel_bytes: u64) -> u64 {
    let extent = image.level_extent(level);
    u64::from(extent.width) * u64::from(extent.height) * u64::from(image.layers) * texel_bytes
}

/// Bytes of every level and layer of `image`, as [`split_levels`] takes them.
pub fn image_size(image: &Image, texel_bytes: u64) -> usize {
    (0..image.mip_levels)
        .map(|level| level_size(image, level, texel_bytes))
        .sum::<u64>() as usize
}

/// `bits`, every level of `image` one after another (each as [`read_level`] gives it), as
/// one slice a level.
pub fn split_levels<'a>(image: &Image, bits: &'a [u8], texel_bytes: u64) -> Result<Vec<&'a [u8]>> {
    let expected = image_size(image, texel_bytes);
    ensure!(bits.len() == expected, "{} bytes for an image of {expected}", bits.len());
    let mut rest = bits;
    Ok((0..image.mip_levels)
        .map(|level| {
            let (bytes, tail) = rest.split_at(level_size(image, level, texel_bytes) as usize);
            rest = tail;
            bytes
        })
        .collect())
}

/// Fills every layer of each level of `image` with its slice of `levels`. The image is in
/// use `from` before (an `UNDEFINED` layout discards its contents) and `to` after.
pub fn upload_image(
    device: &Arc<Device>,
    one_shot: &OneShot,
    image: &Image,
    levels: &[&[u8]],
    from: ImageUse,
    to: ImageUse,
) -> Result<()> {
    ensure!(levels.len() == image.mip_levels as usize, "{} levels for an image of {}", levels.len(), image.mip_levels);
    let mut staging = Buffer::staging(device, levels.iter().map(|l| l.len() as u64).sum(), "image upload")?;
    let mut regions = Vec::new();
    let mut offset = 0;
    for (level, bytes) in (0..).zip(levels) {
        staging.write_at(offset, bytes)?;
        let extent = image.level_extent(level);
        regions.push(copy_region(image.aspect, level, image.layers, extent).buffer_offset(offset as u64));
        offset += bytes.len();
    }
    one_shot.run(|cmd| {
        let all = image.all_levels();
        transition_levels(device, cmd, image.handle, all, from, ImageUse::TRANSFER_DST);
        unsafe {
            device.handle.cmd_copy_buffer_to_image(
                cmd,
                staging.handle,
                image.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            )
        };
        transition_levels(device, cmd, image.handle, all, ImageUse::TRANSFER_DST, to);
    })
}

/// Mip `level` of `image`, every layer, as the image holds its texels (layer-major, rows
/// from the top); the image is in use `at` and is left there.
pub fn read_level(
    device: &Arc<Device>,
    one_shot: &OneShot,
    image: &Image,
    level: u32,
    texel_bytes: u64,
    at: ImageUse,
) -> Result<Vec<u8>> {
    let buffer = Buffer::readback(device, level_size(image, level, texel_bytes), "image readback")?;
    let range = image.level_range(level);
    one_shot.run(|cmd| {
        transition_levels(device, cmd, image.handle, range, at, ImageUse::TRANSFER_SRC);
        let region = copy_region(image.aspect, level, image.layers, image.level_extent(level));
        unsafe {
            device.handle.cmd_copy_image_to_buffer(
                cmd,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.handle,
                &[region],
            )
        };
        transition_levels(device, cmd, image.handle, range, ImageUse::TRANSFER_SRC, at);
        buffer_barrier(device, cmd, buffer.handle, BufferUse::TRANSFER_DST, BufferUse::HOST_READ);
    })?;
    Ok(buffer.read()?.to_vec())
}

/// Fills the start of `buffer` with `bytes`. The buffer is in use `from` before and `to`
/// after.
pub fn upload_buffer(
    device: &Arc<Device>,
    one_shot: &OneShot,
    buffer: &Buffer,
    bytes: &[u8],
    from: BufferUse,
    to: BufferUse,
) -> Result<()> {
    ensure!(bytes.len() as u64 <= buffer.size, "{} bytes for a buffer of {}", bytes.len(), buffer.size);
    let mut staging = Buffer::staging(device, bytes.len() as u64, "buffer upload")?;
    staging.write(bytes)?;
    one_shot.run(|cmd| {
        buffer_barrier(device, cmd, buffer.handle, from, BufferUse::TRANSFER_DST);
        let region = vk::BufferCopy::default().size(bytes.len() as u64);
        unsafe { device.handle.cmd_copy_buffer(cmd, staging.handle, buffer.handle, &[region]) };
        buffer_barrier(device, cmd, buffer.handle, BufferUse::TRANSFER_DST, to);
    })
}

/// The whole of `buffer`, in use `at` and left there.
pub fn read_buffer(device: &Arc<Device>, one_shot: &OneShot, buffer: &Buffer, at: BufferUse) -> Result<Vec<u8>> {
    let readback = Buffer::readback(device, buffer.size, "buffer readback")?;
    one_shot.run(|cmd| {
        buffer_barrier(device, cmd, buffer.handle, at, BufferUse::TRANSFER_SRC);
        let region = vk::BufferCopy::default().size(buffer.size);
        unsafe { device.handle.cmd_copy_buffer(cmd, buffer.handle, readback.handle, &[region]) };
        buffer_barrier(device, cmd, buffer.handle, BufferUse::TRANSFER_SRC, at);
        buffer_barrier(device, cmd, readback.handle, BufferUse::TRANSFER_DST, BufferUse::HOST_READ);
    })?;
    Ok(readback.read()?.to_vec())
}
