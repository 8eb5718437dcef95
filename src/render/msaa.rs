//! Multisample anti-aliasing of the forward pass: per frame in flight, a multisampled
//! colour and depth image that the forward pass and the skybox draw into, and a resolve
//! pass (fullscreen.vert + msaa_resolve.frag) that writes the render target's colour from
//! them before the display transform. At one sample per pixel none of this exists and the
//! passes draw into the target itself.
//!
//! The resolve is a shader, not the attachment's AVERAGE resolve: a plain mean of HDR
//! samples lets one bright sample (a highlight, a lamp-lit rim) dominate an edge pixel, so
//! that after tone mapping the edge stays stair-stepped. Each sample is weighted by
//! 1/(1 + luma) and the sum divided by the weights (shaders/lib/msaa_resolve.glsl), which
//! is Karis 2014's tone-map, average, inverse-tone-map with T(c) = c/(1 + luma) written as
//! one weighted mean: it stays in linear radiance (the EXR and the tone mapper need it),
//! it needs no exposure, and it never brightens an edge (the weights fall as luma rises,
//! so the result is at most the plain mean); it darkens high-contrast edges by at most
//! what the f64 twin bounds (src/brdf/antialiasing.rs). Alpha (coverage) is the plain mean.
//!
//! Set 0, binding 0: the slot's multisampled colour as a sampled image; specialization
//! constant 0: the sample count. The multisampled depth is transient (nothing reads it
//! after the skybox); the colour is sampled by the resolve, so it cannot be.

use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::fullscreen::FullscreenPass;
use super::shaders;
use super::target::{DrawTarget, RenderTarget, DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::{transition, Device, Image, ImageUse, Specialization};

/// The multisampled images of one frame in flight.
struct Multisampled {
    color: Image,
    depth: Image,
}

pub struct MsaaPass {
    device: Arc<Device>,
    /// By sample count.
    resolve: FullscreenPass<vk::SampleCountFlags>,
    /// Per frame in flight; `None` at one sample per pixel.
    slots: Vec<Option<Multisampled>>,
}

/// The flag of `count` samples per pixel (a power of two up to 64).
pub fn sample_flag(count: u32) -> vk::SampleCountFlags {
    vk::SampleCountFlags::from_raw(count)
}

/// The largest sample count at most `requested` that the device can render colour and
/// depth with and sample the colour of: `requested` itself where it is supported. Every
/// device supports 1.
pub fn supported_samples(device: &Device, requested: u32) -> u32 {
    let limits = &device.limits;
    let usable = limits.framebuffer_color_sample_counts
        & limits.framebuffer_depth_sample_counts
        & limits.sampled_image_color_sample_counts;
    (0..=requested.max(1).ilog2())
        .rev()
        .map(|bit| 1 << bit)
        .find(|&count| usable.contains(sample_flag(count)))
        .unwrap_or(1)
}

impl MsaaPass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        Ok(Self {
            device: device.clone(),
            resolve: FullscreenPass::new(
                device,
                frames_in_flight,
                shaders::MSAA_RESOLVE_FRAG,
                "msaa_resolve.frag",
                0,
            )?,
            slots: (0..frames_in_flight).map(|_| None).collect(),
        })
    }

    /// Makes `slot` draw `target`'s frames with `samples` samples per pixel (supported by
    /// the device: see [`supported_samples`]), creating its images and the resolve's
    /// pipeline if needed; the caller has waited for the slot's previous frame.
    pub fn prepare(&mut self, slot: usize, target: &RenderTarget, samples: u32) -> Result<()> {
        let flag = sample_flag(samples);
        if samples == 1 {
            self.slots[slot] = None;
            return Ok(());
        }
        let current = self.slots[slot]
            .as_ref()
            .is_some_and(|m| m.color.samples == flag && m.color.extent == target.extent);
        if !current {
            let images = Multisampled {
                color: Image::multisampled(
                    &self.device,
                    target.extent,
                    flag,
                    HDR_FORMAT,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                    vk::ImageAspectFlags::COLOR,
                    "multisampled hdr frame",
                )?,
                depth: Image::multisampled(
                    &self.device,
                    target.extent,
                    flag,
                    DEPTH_FORMAT,
                    vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                    vk::ImageAspectFlags::DEPTH,
                    "multisampled depth",
                )?,
            };
            self.resolve.bind(slot, images.color.view);
            self.slots[slot] = Some(images);
        }
        self.resolve
            .prepare_pipeline(flag, HDR_FORMAT, Specialization(vec![samples]))
    }

    /// What the forward pass and skybox of `slot` draw into: its multisampled images, or
    /// `target`'s own at one sample per pixel.
    pub fn draw_target<'a>(&'a self, slot: usize, target: &'a RenderTarget) -> DrawTarget<'a> {
        match &self.slots[slot] {
            Some(m) => DrawTarget {
                color: &m.color,
                depth: &m.depth,
            },
            None => target.draw_target(),
        }
    }

    /// Records the transitions that start a frame of `slot`: its multisampled colour (if
    /// any) from nothing to an attachment. Depth is the renderer's, as at one sample.
    pub fn begin(&self, cmd: vk::CommandBuffer, slot: usize) {
        if let Some(m) = &self.slots[slot] {
            transition(
                &self.device,
                cmd,
                m.color.handle,
                m.color.aspect,
                ImageUse::UNDEFINED,
                ImageUse::COLOR_ATTACHMENT,
            );
        }
    }

    /// Records the resolve of `slot`'s multisampled colour into `target.color`, after the
    /// forward pass and the skybox; nothing at one sample per pixel. `target.color` must
    /// be a colour attachment, and stays one.
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize, target: &RenderTarget) -> Result<()> {
        let Some(m) = &self.slots[slot] else {
            return Ok(());
        };
        // The forward pass's and skybox's writes, then the resolve's reads.
        transition(
            &self.device,
            cmd,
            m.color.handle,
            m.color.aspect,
            ImageUse::COLOR_ATTACHMENT,
            ImageUse::FRAGMENT_READ,
        );
        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: target.extent,
        };
        self.resolve
            .record(cmd, slot, m.color.samples, target.color.view, area, &[])
    }
}
