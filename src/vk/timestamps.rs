//! GPU timestamps around passes, through a query pool.

use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;

use super::device::Device;

/// Two timestamps per pass: `begin(i)` and `end(i)` bracket pass `i`.
pub struct Timestamps {
    device: Arc<Device>,
    pool: vk::QueryPool,
    passes: u32,
    period_ns: f64,
}

impl Timestamps {
    /// `None` when the device's queue cannot write timestamps.
    pub fn new(device: &Arc<Device>, passes: u32) -> Result<Option<Self>> {
        let Some(period_ns) = device.timestamp_period_ns else {
            return Ok(None);
        };
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(passes * 2);
        let pool =
            unsafe { device.handle.create_query_pool(&info, None) }.context("cannot create a timestamp query pool")?;
        Ok(Some(Self {
            device: device.clone(),
            pool,
            passes,
            period_ns,
        }))
    }

    /// Resets every query; recorded before the first pass of a frame.
    pub fn reset(&self, cmd: vk::CommandBuffer) {
        unsafe {
            self.device
                .handle
                .cmd_reset_query_pool(cmd, self.pool, 0, self.passes * 2)
        };
    }

    pub fn begin(&self, cmd: vk::CommandBuffer, pass: u32) {
        unsafe {
            self.device
                .handle
                .cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::TOP_OF_PIPE, self.pool, pass * 2)
        };
    }

    pub fn end(&self, cmd: vk::CommandBuffer, pass: u32) {
        unsafe {
            self.device.handle.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
                self.pool,
                pass * 2 + 1,
            )
        };
    }

    /// Milliseconds per pass of the last frame whose queries completed (after its fence).
    pub fn read_ms(&self) -> Result<Vec<f64>> {
        let mut ticks = vec![0u64; (self.passes * 2) as usize];
        unsafe {
            self.device.handle.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .context("cannot read GPU timestamps")?;
        Ok(ticks
            .chunks_exact(2)
            .map(|t| t[1].saturating_sub(t[0]) as f64 * self.period_ns * 1e-6)
            .collect())
    }
}

impl Drop for Timestamps {
    fn drop(&mut self) {
        unsafe { self.device.handle.destroy_query_pool(self.pool, None) };
    }
}
