//! Shadow maps of the point lights: one cube depth map per light that casts shadows, its
//! six faces layers of one 2D array image, rendered only when the lights, the objects or
//! the settings change (a frame that changes nothing records no draw). Set 3 of the
//! forward pass (shaders/lib/shadows.glsl): binding 0 the `ShadowData` uniform buffer,
//! binding 1 the maps; the ground's light and shadow maps are computed from them too
//! (ground_maps.rs), the shadow map over the part of the ground that objects can shadow
//! (`Scene::ground_shadow_rect`), which `ShadowData` holds. What the shadows can reach,
//! that rectangle and the lights that may shadow each object (`Scene::shadowing_lights`), is
//! found once per change of the lights or the objects. A draft (`Renderer::draft`) that
//! finds the maps out of date renders a second set at a quarter of the resolution.

use std::cell::Cell;
use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DVec3, Mat4, Vec3};
use gpu_allocator::MemoryLocation;

use super::gpu_scene::{GpuScene, MAX_POINT_LIGHTS};
use super::shaders;
use super::target::DEPTH_FORMAT;
use crate::brdf::shadow::CUBE_FACE_AXES;
use crate::cache;
use crate::scene::{GroundRect, Mesh, Scene, Vertex};
use crate::vk::{
    begin_full_rendering, transition_levels, Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, GraphicsPipelineBuilder, Image, ImageUse, ImageView, Pipeline, PipelineLayout, Sampler,
    ShaderModule,
};

/// The far plane is this far beyond the scene's furthest point from the light, and the
/// near plane this fraction of the far one: what the GLSL's depth bias assumes
/// (SHADOW_DEPTH_BIAS covers 2⁻²⁴ · far/near with a margin).
const FAR_MARGIN: f32 = 1.01;
const NEAR_OVER_FAR: f32 = 1e-3;

/// `ShadowLight` of shadows.glsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ShadowLightData {
    /// First layer (< 0: no map), radius, near, far.
    map: [f32; 4],
}

/// `ShadowData` (std140).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ShadowData {
    settings: [u32; 4],
    lights: [ShadowLightData; MAX_POINT_LIGHTS],
    /// The ground's rectangle that objects can shadow: its centre's x and z, then half its
    /// extent; all 0 where nothing can.
    ground: [f32; 4],
}

/// The projection of face `face` of a cube map about the origin with planes `near` and
/// `far`: the point q goes to x = q·A, y = q·B, w = q·F (the face's axes, so that
/// (x/w, y/w) is the (a, b) of `cube_direction`) and depth f/(f − n)·(1 − n/(q·F))
/// (`shadow_depth` in src/brdf/shadow.rs).
pub fn face_projection(face: usize, near: f32, far: f32) -> Mat4 {
    let [f, a, b] = CUBE_FACE_AXES[face].map(|v| Vec3::from(v.map(|x| x as f32)));
    let k = far / (far - near);
    Mat4::from_cols_array_2d(&[
        [a.x, a.y, a.z, 0.0],
        [b.x, b.y, b.z, 0.0],
        [k * f.x, k * f.y, k * f.z, -k * near],
        [f.x, f.y, f.z, 0.0],
    ])
    .transpose()
}

/// The near and far planes of a light's faces: the far plane just beyond every object.
fn depth_range(light: Vec3, bounds: &[(Vec3, f32)]) -> (f32, f32) {
    let furthest = bounds
        .iter()
        .map(|&(c, r)| (c.as_dvec3() - light.as_dvec3()).length() + f64::from(r))
        .fold(0.0, f64::max) as f32;
    let far = (furthest * FAR_MARGIN).max(f32::MIN_POSITIVE / NEAR_OVER_FAR);
    (far * NEAR_OVER_FAR, far)
}

/// A draft's maps, where the full ones are out of date (a light or an object being
/// dragged): this fraction of the scene's resolution on a side, a sixteenth of the texels
/// to clear and rasterise.
pub const DRAFT_RESOLUTION_DIVISOR: u32 = 4;

/// The maps of the lights that cast shadows, with the views their faces render through,
/// and what they were last rendered from.
struct ShadowMaps {
    image: Image,
    layer_views: Vec<ImageView>,
    resolution: u32,
    /// The lights, objects, meshes and resolution (`shadow_key`); empty before the first.
    key: Vec<u64>,
    faces: Vec<Face>,
}

impl ShadowMaps {
    fn new(device: &Arc<Device>, resolution: u32, layers: u32, name: &str) -> Result<Self> {
        let image = Image::depth_array(
            device,
            resolution,
            layers,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            name,
        )?;
        let layer_views = (0..layers).map(|l| image.layer_view(l)).collect::<Result<_>>()?;
        Ok(Self {
            image,
            layer_views,
            resolution,
            key: Vec::new(),
            faces: Vec::new(),
        })
    }
}

/// What one frame in flight owns: its `ShadowData` and the set pointing at it, and the
/// maps' view the set points at (null when none is known to be alive).
struct FrameSlot {
    data: Buffer,
    set: vk::DescriptorSet,
    maps_view: vk::ImageView,
}

/// One face to render: its layer and the light's near and far planes and position.
#[derive(Clone, Copy, PartialEq)]
struct Face {
    layer: u32,
    light: Vec3,
    near: f32,
    far: f32,
}

pub struct ShadowPass {
    device: Arc<Device>,
    set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    pipeline: Pipeline,
    _pool: DescriptorPool,
    slots: Vec<FrameSlot>,
    sampler: Sampler,
    /// The maps at the scene's resolution, and a draft's (`DRAFT_RESOLUTION_DIVISOR`).
    full: Option<ShadowMaps>,
    draft: Option<ShadowMaps>,
    /// Whether the last [`Self::prepare`] chose the draft's maps.
    drafting: bool,
    /// The key of the maps the last [`Self::prepare`] chose.
    key: Vec<u64>,
    /// The lights that cast shadows and the data of the last [`Self::prepare`]: with the
    /// meshes' vertices, what [`Self::disk_key`] holds.
    shadowed: Vec<usize>,
    data: ShadowData,
    /// Whether the next recorded frame renders the chosen maps.
    pending: Cell<bool>,
    /// Counts the changes of what the chosen maps hold.
    generation: u64,
    /// Frames that rendered them.
    renders: Cell<u64>,
    /// What the shadows reach, and the key and lights' radii it was found from.
    reach: (ShadowReach, Vec<u64>),
}

/// What the shadows of the shadowed lights can reach.
#[derive(Default)]
struct ShadowReach {
    /// The ground's rectangle that objects can shadow.
    ground: Option<GroundRect>,
    /// Per object, the lights that may shadow a point of it, bit i for light i.
    receivers: Vec<u32>,
}

impl ShadowPass {
    pub fn new(device: &Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::UNIFORM_BUFFER, stages)
            .binding(vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages)
            .build(device, "shadow set")?;
        let (layout, pipeline) = depth_pipeline(device, "shadow map")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let slots = (0..frames_in_flight)
            .map(|_| {
                Ok(FrameSlot {
                    data: Buffer::new(
                        device,
                        std::mem::size_of::<ShadowData>() as u64,
                        vk::BufferUsageFlags::UNIFORM_BUFFER,
                        MemoryLocation::CpuToGpu,
                        "shadow data",
                    )?,
                    set: pool.allocate(&set_layout)?,
                    maps_view: vk::ImageView::null(),
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            set_layout,
            layout,
            pipeline,
            _pool: pool,
            slots,
            sampler: Sampler::nearest(device)?,
            full: None,
            draft: None,
            drafting: false,
            key: Vec::new(),
            shadowed: Vec::new(),
            data: ShadowData::zeroed(),
            pending: Cell::new(false),
            generation: 0,
            renders: Cell::new(0),
            reach: (ShadowReach::default(), Vec::new()),
        })
    }

    /// Per object of the scene of the last [`Self::prepare`], the lights that may shadow a
    /// point of it, bit i for light i (`Scene::shadowing_lights`): none without a shadowed
    /// light.
    pub fn receivers(&self) -> &[u32] {
        &self.reach.0.receivers
    }

    /// The layout of set 3 of the forward pass.
    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Set 3 of the forward pass for `slot`.
    pub fn set(&self, slot: usize) -> vk::DescriptorSet {
        self.slots[slot].set
    }

    /// Writes `slot`'s shadow data (the caller has waited for its previous frame) and, when
    /// the lights, objects or settings changed since the maps were rendered, has the next
    /// recorded frame render them again. `enabled` off gives every light a factor of 1. A
    /// `draft` that finds the maps out of date renders maps of its own at a lower
    /// resolution instead; where they are current, it reads them.
    pub fn prepare(&mut self, slot: usize, scene: &Scene, gpu: &GpuScene, enabled: bool, draft: bool) -> Result<()> {
        let shadowed: Vec<usize> = (0..scene.lights.len().min(MAX_POINT_LIGHTS))
            .filter(|&i| enabled && scene.lights[i].shadows)
            .collect();
        // Without a shadowed light, one 1-texel cube keeps the set valid.
        let full_resolution = if shadowed.is_empty() {
            1
        } else {
            scene.shadow_resolution
        };
        let layers = 6 * shadowed.len().max(1) as u32;
        let full_key = shadow_key(scene, &shadowed, full_resolution, |_| gpu.id);
        let drafting = draft
            && full_resolution >= DRAFT_RESOLUTION_DIVISOR
            && self.full.as_ref().is_none_or(|m| m.key != full_key);
        let (resolution, key) = if drafting {
            let resolution = full_resolution / DRAFT_RESOLUTION_DIVISOR;
            (resolution, shadow_key(scene, &shadowed, resolution, |_| gpu.id))
        } else {
            (full_resolution, full_key.clone())
        };
        let maps = self.maps(drafting, resolution, layers)?;
        let view = maps.image.view;
        let out_of_date = key != maps.key;
        if out_of_date {
            let bounds = scene.bounding_spheres();
            maps.faces = shadowed
                .iter()
                .enumerate()
                .flat_map(|(k, &i)| {
                    let light = scene.lights[i].position;
                    let (near, far) = depth_range(light, &bounds);
                    (0..6).map(move |face| Face {
                        layer: 6 * k as u32 + face,
                        light,
                        near,
                        far,
                    })
                })
                .collect();
            maps.key = key.clone();
        }
        let mut data = ShadowData::zeroed();
        data.settings[0] = resolution;
        data.lights.iter_mut().for_each(|l| l.map[0] = -1.0);
        for (k, &i) in shadowed.iter().enumerate() {
            let face = &maps.faces[6 * k];
            data.lights[i].map = [6.0 * k as f32, scene.lights[i].radius, face.near, face.far];
        }
        if out_of_date {
            self.pending.set(true);
        }
        let frame_slot = &mut self.slots[slot];
        if frame_slot.maps_view != view {
            DescriptorWriter::default()
                .buffer(0, vk::DescriptorType::UNIFORM_BUFFER, frame_slot.data.handle)
                .image(
                    1,
                    vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    view,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    self.sampler.handle,
                )
                .write(&self.device, frame_slot.set);
            frame_slot.maps_view = view;
        }
        // Either maps' key holds its resolution: a draft's and a full frame's differ.
        if key != self.key {
            self.key = key;
            self.generation += 1;
        }
        self.drafting = drafting;
        // What the shadows reach does not depend on the maps' resolution.
        let radii = shadowed.iter().map(|&i| u64::from(scene.lights[i].radius.to_bits()));
        let reach_key: Vec<u64> = full_key.into_iter().chain(radii).collect();
        if reach_key != self.reach.1 {
            let reach = ShadowReach {
                ground: scene.ground_shadow_rect(&shadowed),
                receivers: (0..scene.objects.len())
                    .map(|i| scene.shadowing_lights(i, &shadowed, |mesh| gpu.meshes[mesh].extent))
                    .collect(),
            };
            self.reach = (reach, reach_key);
        }
        if let Some(rect) = self.reach.0.ground {
            let (centre, half) = ((rect.min + rect.max) * 0.5, (rect.max - rect.min) * 0.5);
            data.ground = [centre.x, centre.y, half.x, half.y];
        }
        self.slots[slot].data.write(bytemuck::bytes_of(&data))?;
        (self.shadowed, self.data) = (shadowed, data);
        Ok(())
    }

    /// A key of everything the maps and the data of the last [`Self::prepare`] of `scene`
    /// hold, the meshes by their vertices and the code by its text: what a disk cache entry
    /// of an image computed from them is keyed by (ground_maps.rs), where [`Self::prepare`]'s
    /// key stands for the meshes by their upload, which another process does not share.
    pub fn disk_key(&self, scene: &Scene) -> u64 {
        let resolution = self.data.settings[0];
        let key = shadow_key(scene, &self.shadowed, resolution, |mesh| mesh_key(&scene.meshes[mesh]));
        cache::key(&[
            bytemuck::cast_slice(&key),
            bytemuck::bytes_of(&self.data),
            shaders::SHADOW_VERT,
            include_str!("shadow.rs").as_bytes(),
        ])
    }

    /// The full maps, or the draft's, made anew (once the frames that read the old ones are
    /// done) where they have another resolution or number of layers.
    fn maps(&mut self, draft: bool, resolution: u32, layers: u32) -> Result<&mut ShadowMaps> {
        let maps = if draft { &mut self.draft } else { &mut self.full };
        if maps.as_ref().is_none_or(|m| m.resolution != resolution || m.image.layers != layers) {
            self.device.wait_idle()?;
            *maps = None;
            let name = if draft { "draft shadow maps" } else { "shadow maps" };
            *maps = Some(ShadowMaps::new(&self.device, resolution, layers, name)?);
            // A new view may reuse a destroyed one's handle: every set is written again.
            self.slots.iter_mut().for_each(|s| s.maps_view = vk::ImageView::null());
        }
        maps.as_mut().context("shadow maps missing")
    }

    /// Changes when what the maps are rendered from changes (the lights, the objects or
    /// the settings, or shadows switched on or off), and only then.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Frames that have rendered the maps.
    pub fn renders(&self) -> u64 {
        self.renders.get()
    }

    /// Renders the maps if [`Self::prepare`] found them out of date, leaving them readable
    /// by fragment and compute shaders; records nothing otherwise.
    pub fn record(&self, cmd: vk::CommandBuffer, scene: &Scene, gpu: &GpuScene) -> Result<()> {
        if !self.pending.replace(false) {
            return Ok(());
        }
        self.renders.set(self.renders.get() + 1);
        let maps = if self.drafting { &self.draft } else { &self.full };
        let maps = maps.as_ref().context("shadow maps missing: prepare() was not called")?;
        let d = &self.device.handle;
        let range = maps.image.all_levels();
        // The old contents go, once the frames before this one have read them.
        let discard = ImageUse {
            stage: ImageUse::SHADER_READ.stage,
            ..ImageUse::UNDEFINED
        };
        transition_levels(
            &self.device,
            cmd,
            maps.image.handle,
            range,
            discard,
            ImageUse::DEPTH_ATTACHMENT,
        );
        let extent = maps.image.extent;
        for (layer, view) in maps.layer_views.iter().enumerate() {
            let depth = vk::RenderingAttachmentInfo::default()
                .image_view(view.handle)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
                });
            begin_full_rendering(&self.device, cmd, extent, &[], Some(&depth));
            if let Some(face) = maps.faces.iter().find(|f| f.layer == layer as u32) {
                let projection = face_projection(layer % 6, face.near, face.far) * Mat4::from_translation(-face.light);
                draw_depth(&self.device, cmd, &self.layout, &self.pipeline, scene, gpu, projection);
            }
            unsafe { d.cmd_end_rendering(cmd) };
        }
        transition_levels(
            &self.device,
            cmd,
            maps.image.handle,
            range,
            ImageUse::DEPTH_ATTACHMENT,
            ImageUse::SHADER_READ,
        );
        Ok(())
    }
}

/// A depth-only pipeline of shadow.vert (positions only, `clip_from_object` pushed) into
/// `DEPTH_FORMAT`, with its layout: what [`draw_depth`] draws with.
pub(super) fn depth_pipeline(device: &Arc<Device>, name: &str) -> Result<(PipelineLayout, Pipeline)> {
    let layout = PipelineLayout::new(
        device,
        &[],
        std::mem::size_of::<Mat4>() as u32,
        vk::ShaderStageFlags::VERTEX,
    )?;
    let vertex = ShaderModule::new(device, shaders::SHADOW_VERT, "shadow.vert")?;
    let pipeline = GraphicsPipelineBuilder::depth_only(&vertex, DEPTH_FORMAT)
        .vertex_layout(
            std::mem::size_of::<Vertex>() as u32,
            &[(
                vk::Format::R32G32B32_SFLOAT,
                std::mem::offset_of!(Vertex, position) as u32,
            )],
        )
        .build(device, &layout, name)?;
    Ok((layout, pipeline))
}

/// Draws every object of `scene` with `pipeline`, a depth-only pipeline of shadow.vert
/// (push constants: `clip_from_object`), through `clip_from_world`, inside a rendering.
pub(super) fn draw_depth(
    device: &Device,
    cmd: vk::CommandBuffer,
    layout: &PipelineLayout,
    pipeline: &Pipeline,
    scene: &Scene,
    gpu: &GpuScene,
    clip_from_world: Mat4,
) {
    let d = &device.handle;
    unsafe { d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.handle) };
    for object in &scene.objects {
        let mesh = &gpu.meshes[object.mesh];
        let clip_from_object = clip_from_world * object.model_matrix();
        unsafe {
            d.cmd_push_constants(
                cmd,
                layout.handle,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&clip_from_object),
            );
            d.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.handle], &[0]);
            d.cmd_bind_index_buffer(cmd, mesh.indices.handle, 0, vk::IndexType::UINT32);
            d.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, 0);
        }
    }
}

/// Everything the maps depend on, as bits: the resolution, each shadowed light's position,
/// and each object's placement and mesh, whose vertices `mesh_vertices(index)` stands for.
fn shadow_key(
    scene: &Scene,
    shadowed: &[usize],
    resolution: u32,
    mesh_vertices: impl Fn(usize) -> u64,
) -> Vec<u64> {
    let mut key = vec![u64::from(resolution)];
    let vector = |key: &mut Vec<u64>, v: DVec3| key.extend(v.to_array().map(f64::to_bits));
    for &i in shadowed {
        key.push(i as u64);
        vector(&mut key, scene.lights[i].position.as_dvec3());
    }
    for object in &scene.objects {
        vector(&mut key, object.position.as_dvec3());
        key.extend([u64::from(object.scale.to_bits()), object.mesh as u64, mesh_vertices(object.mesh)]);
    }
    key
}

/// A key of what the maps read of `mesh`: its positions and triangles.
fn mesh_key(mesh: &Mesh) -> u64 {
    let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
    cache::key(&[bytemuck::cast_slice(&positions), bytemuck::cast_slice(&mesh.indices)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::environment::cube_direction;
    use crate::brdf::shadow::shadow_depth;

    /// A point along (a, b) of each face at major-axis distance λ projects to (a, b) and
    /// to the depth the f64 twin gives.
    #[test]
    fn face_projection_puts_points_where_the_shaders_read_them() {
        let (near, far) = (0.01, 10.0);
        for face in 0..6 {
            for (a, b, lambda) in [(0.0, 0.0, 1.0), (0.6, -0.3, 4.0), (-0.9, 0.95, 9.0)] {
                let d = cube_direction(face as u32, a, b);
                let major = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let q = Vec3::from(d.map(|x| (x / major * lambda) as f32));
                let clip = face_projection(face, near, far) * q.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!(
                    (f64::from(ndc.x) - a).abs() < 1e-6 && (f64::from(ndc.y) - b).abs() < 1e-6,
                    "face {face}"
                );
                let depth = shadow_depth(lambda, f64::from(near), f64::from(far));
                assert!(
                    (f64::from(ndc.z) - depth).abs() < 1e-6,
                    "face {face}: {} against {depth}",
                    ndc.z
                );
            }
        }
    }
}
