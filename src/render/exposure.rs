//! Auto exposure for the viewer's debug views of radiance (a lobe alone is often far
//! darker than the shaded image): `exposure.comp` counts the frame's covered pixels in
//! bins of log2 luminance into a host-visible buffer per frame in flight; when that slot
//! comes round again (its fence waited, so without a stall) the histogram is read and the
//! exposure chosen that puts its [`PERCENTILE`] at the tone curve's [`START_COMPRESSION`]:
//! that much of the surface shows linearly, the brightest rest is compressed, not clipped.
//!
//! Set 0: binding 0 the HDR target (sampled), binding 1 the histogram (storage buffer);
//! push constants: [`LOG2_MIN`], [`BINS_PER_STOP`]; specialization constant 0: [`BINS`].

use std::sync::Arc;

use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;

use super::shaders;
use super::target::RenderTarget;
use crate::brdf::tonemap::START_COMPRESSION;
use crate::vk::{
    Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter, Device, Pipeline,
    PipelineLayout, ShaderModule, Specialization,
};

/// Bins of the histogram: 32 stops at two bins a stop, from 2⁻²⁰ (below anything a lit
/// surface shows) to 2¹², both ends open.
pub const BINS: usize = 64;
pub const LOG2_MIN: f32 = -20.0;
pub const BINS_PER_STOP: f32 = 2.0;
/// The share of the covered, lit pixels shown below the tone curve's shoulder.
pub const PERCENTILE: f64 = 0.95;
/// `exposure.comp`'s workgroups are 16×16 pixels.
const GROUP: u32 = 16;

/// `exposure.comp`'s `luminance_bin`: the bin of luminance `y` > 0.
pub fn luminance_bin(y: f64) -> usize {
    let bin = ((y.log2() - f64::from(LOG2_MIN)) * f64::from(BINS_PER_STOP)).floor();
    bin.clamp(0.0, (BINS - 1) as f64) as usize
}

/// The exposure that maps the [`PERCENTILE`] of the histogram (at its bin's centre in
/// log2) to [`START_COMPRESSION`]; `None` when no pixel was counted.
pub fn auto_exposure(bins: &[u32]) -> Option<f32> {
    let total: u64 = bins.iter().map(|&n| u64::from(n)).sum();
    if total == 0 {
        return None;
    }
    let wanted = (PERCENTILE * total as f64).ceil() as u64;
    let mut below = 0;
    let bin = bins.iter().position(|&n| {
        below += u64::from(n);
        below >= wanted
    })?;
    let log2_y = f64::from(LOG2_MIN) + (bin as f64 + 0.5) / f64::from(BINS_PER_STOP);
    Some((START_COMPRESSION / log2_y.exp2()) as f32)
}

struct Slot {
    histogram: Buffer,
    set: vk::DescriptorSet,
    /// This slot's frame measures, so its histogram is read when the slot comes round.
    measures: bool,
}

pub struct ExposurePass {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    pipeline: Pipeline,
    /// Owns the slots' sets.
    _pool: DescriptorPool,
    slots: Vec<Slot>,
    /// The histogram of the latest frame read back.
    latest: Option<Vec<u32>>,
}

impl ExposurePass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::SAMPLED_IMAGE, vk::ShaderStageFlags::COMPUTE)
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE)
            .build(device, "exposure set")?;
        let layout = PipelineLayout::new(device, &[&set_layout], 8, vk::ShaderStageFlags::COMPUTE)?;
        let shader = ShaderModule::new(device, shaders::EXPOSURE_COMP, "exposure.comp")?;
        let bins = Specialization(vec![BINS as u32]);
        let pipeline = Pipeline::compute(device, &layout, &shader, &bins, "exposure")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let slots = (0..frames_in_flight)
            .map(|_| {
                Ok(Slot {
                    histogram: Buffer::new(
                        device,
                        (BINS * 4) as u64,
                        vk::BufferUsageFlags::STORAGE_BUFFER,
                        MemoryLocation::GpuToCpu,
                        "luminance histogram",
                    )?,
                    set: pool.allocate(&set_layout)?,
                    measures: false,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            _set_layout: set_layout,
            layout,
            pipeline,
            _pool: pool,
            slots,
            latest: None,
        })
    }

    /// Reads the histogram `slot`'s last frame measured (the caller has waited for it),
    /// and readies the slot to measure this frame's `target` if `measure`; not measuring
    /// forgets the histograms.
    pub fn prepare(&mut self, slot: usize, target: &RenderTarget, measure: bool) -> Result<()> {
        let s = &mut self.slots[slot];
        if s.measures {
            self.latest = Some(bytemuck::pod_collect_to_vec(s.histogram.read()?));
        }
        s.measures = measure;
        if !measure {
            self.latest = None;
            return Ok(());
        }
        // Host writes before the submission are visible to it.
        s.histogram.write(&[0; BINS * 4])?;
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::SAMPLED_IMAGE,
                target.color.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::Sampler::null(),
            )
            .buffer(1, vk::DescriptorType::STORAGE_BUFFER, s.histogram.handle)
            .write(&self.device, s.set);
        Ok(())
    }

    /// The exposure from the latest histogram read back (a frame or two old).
    pub fn auto_exposure(&self) -> Option<f32> {
        self.latest.as_deref().and_then(auto_exposure)
    }

    /// The latest histogram read back.
    pub fn histogram(&self) -> Option<&[u32]> {
        self.latest.as_deref()
    }

    /// Records the measure of `slot`'s frame, whose target must be readable by compute
    /// shaders; nothing when the slot does not measure.
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize, target: &RenderTarget) {
        let s = &self.slots[slot];
        if !s.measures {
            return;
        }
        let d = &self.device.handle;
        let mut push = LOG2_MIN.to_ne_bytes().to_vec();
        push.extend(BINS_PER_STOP.to_ne_bytes());
        // The counts are read by the host once the frame's fence has signalled.
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.handle);
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.handle,
                0,
                &[s.set],
                &[],
            );
            d.cmd_push_constants(cmd, self.layout.handle, vk::ShaderStageFlags::COMPUTE, 0, &push);
            d.cmd_dispatch(
                cmd,
                target.extent.width.div_ceil(GROUP),
                target.extent.height.div_ceil(GROUP),
                1,
            );
            d.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_are_half_stops_from_the_floor_with_open_ends() {
        assert_eq!(luminance_bin(2f64.powf(-20.0)), 0);
        assert_eq!(luminance_bin(1e-30), 0);
        assert_eq!(luminance_bin(1.0), 40);
        assert_eq!(luminance_bin(1.5), 41);
        assert_eq!(luminance_bin(1e30), BINS - 1);
        let glsl = include_str!("../../shaders/exposure.comp");
        assert!(glsl.contains(
            "return uint(clamp(floor((log2(y) - push.log2_min) * push.bins_per_stop), 0.0, float(BINS - 1u)));"
        ));
        assert!(glsl.contains("return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;"));
        assert_eq!(crate::brdf::tonemap::luminance([1.0, 0.0, 0.0]), 0.2126);
    }

    #[test]
    fn the_percentile_lands_at_the_shoulder() {
        assert_eq!(auto_exposure(&[0; BINS]), None);
        // 95 pixels at Y ≈ 2⁻⁸ and 5 brighter: the 95th percentile is the dim bin's centre.
        let mut bins = [0; BINS];
        bins[luminance_bin(2f64.powf(-8.0))] = 95;
        bins[luminance_bin(4.0)] = 5;
        let centre = 2f64.powf(-8.0 + 0.25);
        let expected = START_COMPRESSION / centre;
        let exposure = f64::from(auto_exposure(&bins).expect("pixels"));
        assert!(
            (exposure - expected).abs() < 1e-4 * expected,
            "{exposure} vs {expected}"
        );
        // One more bright pixel moves the 95th percentile into the bright bin.
        bins[luminance_bin(4.0)] = 6;
        let bright = f64::from(auto_exposure(&bins).expect("pixels"));
        assert!((bright - START_COMPRESSION / 2f64.powf(2.25)).abs() < 1e-6);
    }
}
