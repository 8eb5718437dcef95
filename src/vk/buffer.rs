//! Buffers with their memory, freed in `Drop`.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::commands::OneShot;
use super::device::Device;

pub struct Buffer {
    device: Arc<Device>,
    pub handle: vk::Buffer,
    allocation: Option<Allocation>,
    pub size: vk::DeviceSize,
}

impl Buffer {
    /// A buffer of `size` bytes in `location` (`CpuToGpu`/`GpuToCpu` buffers are mapped).
    pub fn new(
        device: &Arc<Device>,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
        name: &str,
    ) -> Result<Self> {
        let info = vk::BufferCreateInfo::default()
            .size(size.max(1))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let handle = unsafe { device.handle.create_buffer(&info, None) }
            .with_context(|| format!("cannot create buffer '{name}' ({size} bytes)"))?;
        let requirements = unsafe { device.handle.get_buffer_memory_requirements(handle) };
        let allocation = device.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.handle.destroy_buffer(handle, None) };
                return Err(e).with_context(|| format!("cannot allocate {size} bytes for buffer '{name}'"));
            }
        };
        let bound = unsafe {
            device
                .handle
                .bind_buffer_memory(handle, allocation.memory(), allocation.offset())
        };
        let buffer = Self {
            device: device.clone(),
            handle,
            allocation: Some(allocation),
            size,
        };
        bound.context("vkBindBufferMemory failed")?;
        device.set_name(handle, name);
        Ok(buffer)
    }

    /// A mapped buffer of `size` bytes that copies read from: what the host uploads.
    pub fn staging(device: &Arc<Device>, size: vk::DeviceSize, name: &str) -> Result<Self> {
        Self::new(device, size, vk::BufferUsageFlags::TRANSFER_SRC, MemoryLocation::CpuToGpu, name)
    }

    /// A mapped buffer of `size` bytes that copies write to: what the host reads back.
    pub fn readback(device: &Arc<Device>, size: vk::DeviceSize, name: &str) -> Result<Self> {
        Self::new(device, size, vk::BufferUsageFlags::TRANSFER_DST, MemoryLocation::GpuToCpu, name)
    }

    /// A device-local buffer filled with `data` through a staging copy.
    pub fn with_data<T: bytemuck::Pod>(
        device: &Arc<Device>,
        one_shot: &OneShot,
        data: &[T],
        usage: vk::BufferUsageFlags,
        name: &str,
    ) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = bytes.len() as vk::DeviceSize;
        let mut staging = Buffer::staging(device, size, "staging")?;
        staging.write(bytes)?;
        let buffer = Buffer::new(
            device,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
            name,
        )?;
        one_shot.run(|cmd| {
            let region = vk::BufferCopy::default().size(size.max(1));
            unsafe {
                device
                    .handle
                    .cmd_copy_buffer(cmd, staging.handle, buffer.handle, &[region])
            };
        })?;
        Ok(buffer)
    }

    fn mapped(&self) -> Result<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .context("buffer is not host-visible")
    }

    /// Writes `bytes` at the start of a mapped buffer.
    pub fn write(&mut self, bytes: &[u8]) -> Result<()> {
        self.write_at(0, bytes)
    }

    /// Writes `bytes` at byte `offset` of a mapped buffer.
    pub fn write_at(&mut self, offset: usize, bytes: &[u8]) -> Result<()> {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .context("buffer is not host-visible")?;
        anyhow::ensure!(
            offset + bytes.len() <= slice.len(),
            "write of {} bytes at {offset} into a {}-byte buffer",
            bytes.len(),
            slice.len()
        );
        slice[offset..offset + bytes.len()].copy_from_slice(bytes);
        Ok(())
    }

    /// The contents of a mapped buffer.
    pub fn read(&self) -> Result<&[u8]> {
        Ok(&self.mapped()?[..self.size as usize])
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_buffer(self.handle, None) };
        if let Some(a) = self.allocation.take() {
            // A failed free leaks device memory until the device dies; nothing else to do.
            let _ = self.device.allocator().free(a);
        }
    }
}
