//! Shader modules from the SPIR-V that build.rs compiled.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;

pub struct ShaderModule {
    device: Arc<Device>,
    pub handle: vk::ShaderModule,
}

impl ShaderModule {
    pub fn new(device: &Arc<Device>, spirv: &[u8], name: &str) -> Result<Self> {
        // `include_bytes!` gives no 4-byte alignment; read_spv copies into u32 words.
        let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
            .with_context(|| format!("shader '{name}' is not valid SPIR-V"))?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        let handle = unsafe { device.handle.create_shader_module(&info, None) }
            .with_context(|| format!("cannot create shader module '{name}'"))?;
        device.set_name(handle, name);
        Ok(Self {
            device: device.clone(),
            handle,
        })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_shader_module(self.handle, None) };
    }
}
