//! The deferred pass's targets: the solids' surfaces at each pixel (the G-buffer that
//! forward.frag's GBUFFER build writes), and which solid each pixel shows, as a depth that
//! each solid's shading draw tests for equality. Lavapipe shades a triangle's pixels in
//! blocks of 4×4, the whole block for each triangle that touches it: where a solid's
//! triangles are small in the frame (forward.rs's `fine_solid`), each pixel was shaded
//! many times (about nine at 320×180 in the default scene). Shaded from the G-buffer
//! (forward.frag's DEFERRED build), each pixel is shaded once, and only the surface (its
//! maps and normals) is found per triangle.

use std::sync::Arc;

use anyhow::Result;
use ash::vk;

use super::shaders;
use super::target::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::{
    begin_full_rendering, transition, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, GraphicsPipelineBuilder, Image, ImageUse, Pipeline, PipelineLayout, Sampler,
    ShaderModule,
};

/// The G-buffer's images, RGBA32F each (forward.frag's `out_g`).
pub const G_ATTACHMENTS: usize = 7;
/// The G-buffer image whose alpha holds the pixel's object, as its depth (deferred.glsl).
const G_OBJECT: usize = 6;

/// Frames in a row of a slot that defer nothing before its images are freed: the bench's
/// floor frames alternate with deferred ones, and a G-buffer made again for each (at
/// 1920×1080, 232 MB of fresh pages) took longer than the shading it saved.
const IDLE_FRAMES_KEPT: u32 = 16;

/// One frame slot's images at one extent.
struct Targets {
    extent: vk::Extent2D,
    g: Vec<Image>,
    objects: Image,
    /// The slot's frames since the last that deferred.
    idle_frames: u32,
}

pub struct DeferredPass {
    device: Arc<Device>,
    sampler: Sampler,
    /// Set 6 of the shading draws: the G-buffer (`gbuffer` in forward.frag).
    g_layout: DescriptorSetLayout,
    /// Kept alive for the objects pass's sets allocated with it.
    _objects_set_layout: DescriptorSetLayout,
    objects_layout: PipelineLayout,
    objects_pipeline: Pipeline,
    vertex: ShaderModule,
    _pool: DescriptorPool,
    /// Per slot: the G-buffer's set and the objects pass's.
    sets: Vec<(vk::DescriptorSet, vk::DescriptorSet)>,
    targets: Vec<Option<Targets>>,
}

impl DeferredPass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let g_layout = (0..G_ATTACHMENTS)
            .fold(DescriptorSetLayoutBuilder::default(), |b, _| {
                b.binding(sampled, vk::ShaderStageFlags::FRAGMENT)
            })
            .build(device, "G-buffer set")?;
        let objects_set_layout = DescriptorSetLayoutBuilder::default()
            .binding(sampled, vk::ShaderStageFlags::FRAGMENT)
            .build(device, "deferred objects set")?;
        let objects_layout = PipelineLayout::new(device, &[&objects_set_layout], 0, vk::ShaderStageFlags::FRAGMENT)?;
        let vertex = ShaderModule::new(device, shaders::DEFERRED_VERT, "deferred.vert")?;
        let fragment = ShaderModule::new(device, shaders::DEFERRED_OBJECTS_FRAG, "deferred_objects.frag")?;
        let objects_pipeline = GraphicsPipelineBuilder::new(&vertex, &fragment, HDR_FORMAT)
            .color_formats(&[])
            .depth_write_by(DEPTH_FORMAT, vk::CompareOp::ALWAYS)
            .build(device, &objects_layout, "deferred objects")?;
        let pool = DescriptorPool::for_layouts(device, &[&g_layout, &objects_set_layout], frames_in_flight)?;
        let sets = (0..frames_in_flight)
            .map(|_| Ok((pool.allocate(&g_layout)?, pool.allocate(&objects_set_layout)?)))
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            sampler: Sampler::nearest(device)?,
            g_layout,
            _objects_set_layout: objects_set_layout,
            objects_layout,
            objects_pipeline,
            vertex,
            _pool: pool,
            sets,
            targets: (0..frames_in_flight).map(|_| None).collect(),
        })
    }

    /// Whether `device` can draw into the G-buffer and bind it beside the forward pass's
    /// six sets.
    pub fn supported(device: &Device) -> bool {
        let limits = &device.limits;
        limits.max_color_attachments as usize >= G_ATTACHMENTS
            && limits.max_fragment_output_attachments as usize >= G_ATTACHMENTS
            && limits.max_bound_descriptor_sets >= 7
    }

    pub fn g_layout(&self) -> &DescriptorSetLayout {
        &self.g_layout
    }

    /// The vertex shader of the shading draws: one triangle over the viewport at the depth
    /// of the instance's object.
    pub fn vertex(&self) -> &ShaderModule {
        &self.vertex
    }

    /// `slot`'s images at `extent`, made when it changes, or none for a frame that defers
    /// nothing (kept for [`IDLE_FRAMES_KEPT`] such frames); the slot's previous frame is done.
    pub fn prepare(&mut self, slot: usize, extent: Option<vk::Extent2D>) -> Result<()> {
        let targets = &mut self.targets[slot];
        let Some(extent) = extent else {
            if let Some(t) = targets.as_mut() {
                t.idle_frames += 1;
                if t.idle_frames > IDLE_FRAMES_KEPT {
                    *targets = None;
                }
            }
            return Ok(());
        };
        if let Some(t) = targets.as_mut().filter(|t| t.extent == extent) {
            t.idle_frames = 0;
            return Ok(());
        }
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let color = vk::ImageAspectFlags::COLOR;
        let g = (0..G_ATTACHMENTS)
            .map(|i| Image::new_2d(&self.device, extent, HDR_FORMAT, usage, color, &format!("G-buffer {i}")))
            .collect::<Result<Vec<_>>>()?;
        let objects = Image::new_2d(
            &self.device,
            extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
            "deferred objects",
        )?;
        let (g_set, objects_set) = self.sets[slot];
        let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let writer = g.iter().enumerate().fold(DescriptorWriter::default(), |w, (i, image)| {
            w.image(i as u32, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, image.view, layout, self.sampler.handle)
        });
        writer.write(&self.device, g_set);
        DescriptorWriter::default()
            .image(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, g[G_OBJECT].view, layout, self.sampler.handle)
            .write(&self.device, objects_set);
        self.targets[slot] = Some(Targets { extent, g, objects, idle_frames: 0 });
        Ok(())
    }

    pub fn g_set(&self, slot: usize) -> vk::DescriptorSet {
        self.sets[slot].0
    }

    /// Begins the rendering of the solids' surfaces into `slot`'s G-buffer, with `depth`
    /// cleared. Only the image that says which solid a pixel shows is cleared (to none): the
    /// others are read only where a solid was drawn.
    pub fn begin_surfaces(&self, cmd: vk::CommandBuffer, slot: usize, depth: &Image) -> Result<()> {
        let t = self.targets(slot)?;
        for image in &t.g {
            transition(&self.device, cmd, image.handle, image.aspect, ImageUse::UNDEFINED, ImageUse::COLOR_ATTACHMENT);
        }
        let color: Vec<vk::RenderingAttachmentInfo> = t
            .g
            .iter()
            .enumerate()
            .map(|(i, image)| {
                let load = if i == G_OBJECT { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::DONT_CARE };
                vk::RenderingAttachmentInfo::default()
                    .image_view(image.view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(load)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue::default())
            })
            .collect();
        let depth = depth_attachment(depth, vk::AttachmentLoadOp::CLEAR, 1.0);
        begin_full_rendering(&self.device, cmd, t.extent, &color, Some(&depth));
        Ok(())
    }

    /// Ends the surfaces' rendering, writes which solid each pixel of the rectangles
    /// `solids` (those the solids may cover) shows and begins the rendering of their light
    /// into `color` (cleared to `clear`), the draws testing it.
    pub fn begin_shading(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        solids: &[vk::Rect2D],
        color: &Image,
        clear: [f32; 4],
    ) -> Result<()> {
        let d = &self.device;
        let t = self.targets(slot)?;
        unsafe { d.handle.cmd_end_rendering(cmd) };
        for image in &t.g {
            transition(d, cmd, image.handle, image.aspect, ImageUse::COLOR_ATTACHMENT, ImageUse::FRAGMENT_READ);
        }
        let objects = &t.objects;
        transition(d, cmd, objects.handle, objects.aspect, ImageUse::UNDEFINED, ImageUse::DEPTH_ATTACHMENT);
        let depth = depth_attachment(objects, vk::AttachmentLoadOp::CLEAR, 0.0);
        begin_full_rendering(d, cmd, t.extent, &[], Some(&depth));
        unsafe {
            let graphics = vk::PipelineBindPoint::GRAPHICS;
            d.handle.cmd_bind_pipeline(cmd, graphics, self.objects_pipeline.handle);
            let set = [self.sets[slot].1];
            d.handle.cmd_bind_descriptor_sets(cmd, graphics, self.objects_layout.handle, 0, &set, &[]);
            for &rect in solids {
                d.handle.cmd_set_scissor(cmd, 0, &[rect]);
                d.handle.cmd_draw(cmd, 3, 1, 0, 0);
            }
            d.handle.cmd_end_rendering(cmd);
        }
        transition(d, cmd, objects.handle, objects.aspect, ImageUse::DEPTH_ATTACHMENT, ImageUse::DEPTH_ATTACHMENT);
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            })];
        let depth = depth_attachment(objects, vk::AttachmentLoadOp::LOAD, 0.0);
        begin_full_rendering(d, cmd, t.extent, &color, Some(&depth));
        Ok(())
    }

    fn targets(&self, slot: usize) -> Result<&Targets> {
        self.targets[slot]
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("deferred targets missing: prepare() was not called for slot {slot}"))
    }
}

fn depth_attachment(image: &Image, load: vk::AttachmentLoadOp, clear: f32) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(image.view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(load)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth: clear, stencil: 0 },
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders::tests::bindings;

    /// The G-buffer's images and the one holding the object, as forward.frag writes them and
    /// its DEFERRED build binds and reads them (set 6, binding i for image i).
    #[test]
    fn the_g_buffer_is_the_shaders() {
        let glsl = include_str!("../../shaders/forward.frag");
        assert!(glsl.contains(&format!("out vec4 out_g[{G_ATTACHMENTS}];")));
        assert!(glsl.contains(&format!("out_g[{G_OBJECT}] = vec4(s.objects_take, deferred_object_depth(")));
        assert!(glsl.contains(&format!("if (g[{G_OBJECT}].w != deferred_object_depth(in_deferred_object))")));
        assert!(glsl.contains(&format!("for (int i = 0; i < {G_ATTACHMENTS}; ++i) g[i] = vec4(0.0);")));
        let set_6: Vec<u32> = (bindings(shaders::FORWARD_DEFERRED_FRAG).into_iter())
            .filter_map(|(set, binding)| (set == 6).then_some(binding))
            .collect();
        assert_eq!(set_6, (0..G_ATTACHMENTS as u32).collect::<Vec<_>>());
    }
}
