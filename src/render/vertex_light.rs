//! What the objects' draws read at their vertices rather than at their pixels
//! (shaders/lib/vertex_light.glsl): for each object of a fine mesh
//! (`Scene::bounce_at_vertices`) but the ground, the ground's bounce gathered at each of its
//! vertices with its gradient in the normal (bounce.glsl), and each soft light's shadow;
//! for each object whose occlusion by the others is read at its vertices
//! (`Scene::occlusion_at_vertices`), what their spheres take of the environment's light.
//! Computed by shaders/vertex_light.comp into one buffer that the forward pass's vertex
//! shader reads (set 5, binding 3, beside the ground's maps), and computed again only when
//! what it is made of changes: the ground's light map, the ground's albedo, the
//! environment, the shadow maps and the lights' radii, the occluders, or where the objects
//! stand. Steady frames record nothing, where the gather, the soft shadows' search and
//! filter and the occluders' loop would run every frame (docs/performance.md). A start
//! reads its first computation from the disk cache, keyed by the frame's data, the light
//! map's own key, the environment's, the shadows', the objects and their meshes.

use std::cell::Cell;
use std::collections::HashMap;
use std::sync::Arc;

use anyhow::Result;
use ash::vk;
use bytemuck::Zeroable;
use gpu_allocator::MemoryLocation;

use super::environment::environment_kind;
use super::forward::{ForwardConstants, FROM_UNIFORM};
use super::gpu_scene::{FrameData, GpuScene, ObjectOcclusion, ObjectPush, ObjectsOcclusionFrom, MAX_POINT_LIGHTS};
use super::ground_maps::MapInputs;
use super::shaders;
use crate::cache::{self, DiskCache, Unsaved};
use crate::scene::{MeshExtent, Object, Scene};
use crate::vk::{
    buffer_barrier, transfer, Buffer, BufferUse, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, OneShot, Pipeline, PipelineLayout, ShaderModule, Specialization,
};

/// vertex_light.glsl's `MAX_VERTEX_SHADOW_LAYERS`: a vec4 holds four lights' shadows.
const MAX_VERTEX_SHADOW_LAYERS: usize = MAX_POINT_LIGHTS / 4;
/// Bytes of one vertex's entry, vertex_light.glsl's `LightAtVertex`: the bounce's gather and
/// gradient, three vec4s, then the shadows' layers, then what the occluders take.
const BYTES_PER_VERTEX: u64 = 16 * (3 + MAX_VERTEX_SHADOW_LAYERS as u64 + 1);
/// vertex_light.comp's `local_size_x`.
const WORKGROUP: u32 = 64;
/// A soft shadow's taps at a vertex, per tap at a pixel (`[shadows] taps`): computed once,
/// so more of them cost little, and the fixed disk's pattern that few taps would leave
/// from vertex to vertex does not show.
pub const VERTEX_SHADOW_TAPS_PER_TAP: u32 = 4;
/// The buffer's entries' name in the disk cache.
const DISK_ENTRY: &str = "vertex-light";

/// Where the frames before have read the buffer: its old values go once they are done.
const AFTER_READS: BufferUse = BufferUse {
    access: vk::AccessFlags2::NONE,
    ..BufferUse::VERTEX_READ
};

/// What the buffer is made of besides the scene's objects and meshes.
pub struct VertexLightInputs<'a> {
    /// `GroundMaps::light_key`: what the ground's light map was last computed from.
    pub light_key: &'a [u32],
    /// `GroundMaps::light_content`: the disk cache's key of what the light map holds.
    pub light_content: Option<u64>,
    /// The frame's data (the ground and its albedo, the bounce's switch), the environment's
    /// and the shadows' disk cache keys, as the ground's maps read them.
    pub maps: &'a MapInputs<'a>,
    /// `EnvironmentPass::generation`.
    pub environment_generation: u64,
    /// `ShadowPass::generation`.
    pub shadow_generation: u64,
    /// `ShadowPass::receivers`: per object, the lights that may shadow it.
    pub shadowing: &'a [u32],
    /// `ForwardPass::object_occlusions`: per object, where its draw reads the occlusion by
    /// the other objects from and which occluders are its own.
    pub occlusion: &'a [ObjectOcclusion],
}

/// Of the lights `shadowing` (bit i for light i, `ShadowPass::receivers`) that may shadow
/// an object of `scene`, those whose shadow its draw reads at its vertices if it reads
/// anything there, when `[shadows] per_vertex` asks for it: the soft ones, or all of them
/// in the `generic` pipelines, which read a light's radius at run time.
pub fn vertex_shadowing(scene: &Scene, generic: bool, shadowing: u32) -> u32 {
    if !scene.shadow_per_vertex {
        return 0;
    }
    let read = if generic { u32::MAX } else { scene.soft_lights() };
    read & shadowing
}

/// vertex_light.glsl's `VERTEX_SHADOW_LAYERS` of a draw that reads the shadows of the
/// lights `bits` at its vertices: the vec4s up to the last of them.
pub fn vertex_shadow_layers(bits: u32) -> u32 {
    (u32::BITS - bits.leading_zeros()).div_ceil(4)
}

/// Whether object `index` of `scene`, of mesh size `extent`, reads the bounce and the soft
/// lights' shadows at its vertices: when its mesh is fine enough
/// (`Scene::bounce_at_vertices`) and it is not the ground, when the scene bounces light,
/// when a light of `shadowing` (its lights that may shadow it) casts a shadow read there
/// ([`vertex_shadowing`]) or when the pipelines are `generic`, which read the bounce's flag
/// at run time from the same pipelines (the buffer then holds zeros).
pub fn light_at_vertices(scene: &Scene, generic: bool, shadowing: u32, index: usize, extent: MeshExtent) -> bool {
    let bounces = generic || scene.bounce_ground().is_some();
    let shadowed = vertex_shadowing(scene, generic, shadowing) != 0;
    (bounces || shadowed) && scene.ground_index() != Some(index) && Scene::bounce_at_vertices(extent)
}

/// Where each of `scene`'s objects' vertices start in the buffer, for the objects that read
/// anything at their vertices, one after the other: the bounce and the shadows
/// ([`light_at_vertices`], object i shadowed by the lights `shadowing[i]`), or the
/// occlusion by the other objects where `from[i]` says so. `mesh(i)` is mesh i's extent and
/// vertex count.
pub fn vertex_light_firsts(
    scene: &Scene,
    generic: bool,
    shadowing: &[u32],
    from: &[ObjectsOcclusionFrom],
    mesh: impl Fn(usize) -> (MeshExtent, u32),
) -> Vec<Option<u32>> {
    let mut next = 0;
    (scene.objects.iter().enumerate())
        .map(|(i, object)| {
            let (extent, vertices) = mesh(object.mesh);
            let occluded = from[i] == ObjectsOcclusionFrom::Vertices;
            let reads = occluded || light_at_vertices(scene, generic, shadowing[i], i, extent);
            reads.then(|| {
                next += vertices;
                next - vertices
            })
        })
        .collect()
}

/// [`vertex_light_firsts`] of the meshes of `gpu`.
pub fn gpu_vertex_light_firsts(
    scene: &Scene,
    generic: bool,
    shadowing: &[u32],
    from: &[ObjectsOcclusionFrom],
    gpu: &GpuScene,
) -> Vec<Option<u32>> {
    vertex_light_firsts(scene, generic, shadowing, from, |m| (gpu.meshes[m].extent, gpu.meshes[m].vertex_count))
}

/// The objects the buffer was laid out for.
struct Layout {
    /// The upload of the meshes, and each object's mesh and first vertex.
    key: (u64, Vec<(usize, Option<u32>)>),
    /// For each object that reads the buffer, its first vertex and its compute set (its
    /// mesh's vertices, the buffer).
    reading: Vec<Option<(u32, vk::DescriptorSet)>>,
    _pool: Option<DescriptorPool>,
}

pub struct VertexLight {
    device: Arc<Device>,
    disk: DiskCache,
    set_layout: DescriptorSetLayout,
    /// The forward pass's sets but for set 1, this pass's own.
    layout: PipelineLayout,
    module: ShaderModule,
    /// The pipelines of this specialization and of the one before, which a frame in flight
    /// may still use (two frames at most are in flight, and a frame's slot is waited for
    /// before it is prepared): not one for every count of taps a dragged slider passes.
    pipelines: HashMap<Specialization, Pipeline>,
    specialization: Specialization,
    /// Every reading object's vertices' entries, in `vertex_light_firsts` order.
    buffer: Buffer,
    objects: Layout,
    /// Per object, the lights whose shadows it reads at its vertices ([`vertex_shadowing`]).
    shadowing: Vec<u32>,
    /// Per object, its occlusion by the others, whose spheres it reads at its vertices when
    /// its draw does.
    occlusion: Vec<ObjectOcclusion>,
    /// What the buffer was last computed from; empty before the first.
    key: Vec<u32>,
    /// Whether the next recorded frame computes it.
    pending: Cell<bool>,
    /// The disk cache's key of that computation, when it is the first and the cache misses
    /// it, until [`VertexLight::store_computed`] stores it.
    unsaved: Unsaved,
    /// Times it was made: computed by a frame, or read from the disk cache.
    computes: Cell<u64>,
}

impl VertexLight {
    /// The pass, with the layouts of the forward pass's sets 0 (`frame_layout`), 2 to 4 and 5
    /// (`ground_layout`), whose set `ground_set` it points at its buffer.
    pub fn new(
        device: &Arc<Device>,
        frame_layout: &DescriptorSetLayout,
        environment_layout: &DescriptorSetLayout,
        shadow_layout: &DescriptorSetLayout,
        occlusion_layout: &DescriptorSetLayout,
        ground_layout: &DescriptorSetLayout,
        ground_set: vk::DescriptorSet,
    ) -> Result<Self> {
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE)
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE)
            .build(device, "vertex light compute set")?;
        let sets = [frame_layout, &set_layout, environment_layout, shadow_layout, occlusion_layout, ground_layout];
        let push = std::mem::size_of::<ObjectPush>() as u32;
        let layout = PipelineLayout::new(device, &sets, push, vk::ShaderStageFlags::COMPUTE)?;
        let pass = Self {
            module: ShaderModule::new(device, shaders::VERTEX_LIGHT_COMP, "vertex light")?,
            // Read by no frame until a scene reads anything at its vertices.
            buffer: Self::new_buffer(device, 1)?,
            device: device.clone(),
            disk: DiskCache::from_env(),
            set_layout,
            layout,
            pipelines: HashMap::new(),
            specialization: Specialization::default(),
            objects: Layout {
                key: (u64::MAX, Vec::new()),
                reading: Vec::new(),
                _pool: None,
            },
            shadowing: Vec::new(),
            occlusion: Vec::new(),
            key: Vec::new(),
            pending: Cell::new(false),
            unsaved: Unsaved::default(),
            computes: Cell::new(0),
        };
        pass.point_ground_set_at_buffer(ground_set);
        Ok(pass)
    }

    fn new_buffer(device: &Arc<Device>, vertices: u32) -> Result<Buffer> {
        let size = u64::from(vertices.max(1)) * BYTES_PER_VERTEX;
        // The disk cache's copies go in and out by transfers.
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        Buffer::new(device, size, usage, MemoryLocation::GpuOnly, "vertex light")
    }

    fn point_ground_set_at_buffer(&self, ground_set: vk::DescriptorSet) {
        DescriptorWriter::default()
            .buffer(3, vk::DescriptorType::STORAGE_BUFFER, self.buffer.handle)
            .write(&self.device, ground_set);
    }

    /// Times the buffer was made (computed, or read from the disk cache): once per change of
    /// what it is made of, not per frame.
    pub fn computes(&self) -> u64 {
        self.computes.get()
    }

    /// The compute pipelines kept: this frame's and the one before's.
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.len()
    }

    /// Has the next recorded frame compute the buffer when a frame of `scene` (`shaded`:
    /// drawn with the materials' shaders, `generic` or specialised pipelines) reads it and
    /// what it is made of changed: the ground's light map, the frame's ground and its albedo,
    /// the environment, the shadow maps, the lights' radii and which lights may shadow each
    /// object, the occluders and which objects read them here (`inputs`), the taps, the
    /// meshes' upload and where each reading object stands. A new layout of the objects
    /// makes a new buffer, pointed at by the forward pass's `ground_set`, once the frames in
    /// flight are done. The first computation is read from the disk cache instead, through
    /// `one_shot`, when it holds one of the same inputs.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        shaded: bool,
        generic: bool,
        inputs: &VertexLightInputs,
        ground_set: vk::DescriptorSet,
        one_shot: &OneShot,
    ) -> Result<()> {
        let from: Vec<ObjectsOcclusionFrom> = inputs.occlusion.iter().map(|o| o.from).collect();
        let firsts = gpu_vertex_light_firsts(scene, generic, inputs.shadowing, &from, gpu);
        if !shaded || firsts.iter().all(Option::is_none) {
            // No frame reads it; a computation asked for before is moot.
            self.pending.set(false);
            return Ok(());
        }
        let layout_key = (gpu.id, scene.objects.iter().map(|o| o.mesh).zip(firsts.iter().copied()).collect());
        if layout_key != self.objects.key {
            self.lay_out(gpu, layout_key, ground_set)?;
        }
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
        let mut key = inputs.light_key.to_vec();
        let frame: &FrameData = inputs.maps.frame;
        key.extend(bits(&frame.ground));
        key.extend(bits(&frame.ground_albedo));
        let generation = inputs.environment_generation;
        key.extend([generation as u32, (generation >> 32) as u32, gpu.id as u32]);
        self.shadowing = (inputs.shadowing.iter()).map(|&bits| vertex_shadowing(scene, generic, bits)).collect();
        key.extend(&self.shadowing);
        // The shadows', where any are read here: the bounce alone does not follow them.
        let layers = self.shadowing.iter().map(|&bits| vertex_shadow_layers(bits)).max().unwrap_or(0);
        let taps = if layers > 0 { VERTEX_SHADOW_TAPS_PER_TAP * scene.shadow_taps } else { 0 };
        if layers > 0 {
            let shadows = inputs.shadow_generation;
            key.extend([shadows as u32, (shadows >> 32) as u32, taps]);
            key.extend(scene.lights.iter().map(|light| light.radius.to_bits()));
        }
        // The occluders, where any object reads them here, and each object's own.
        self.occlusion = inputs.occlusion.to_vec();
        let occluded = self.reads_occlusion();
        if occluded {
            key.extend(bits(bytemuck::cast_slice(&frame.occluders)));
            key.push(frame.counts[3]);
            key.extend(self.occlusion.iter().flat_map(|o| [o.own.0 as u32, o.own.1 as u32, o.from as u32]));
        }
        for (object, _) in scene.objects.iter().zip(&firsts).filter(|(_, first)| first.is_some()) {
            key.extend(bits(&object.model_matrix().to_cols_array()));
        }
        if key != self.key {
            self.key = key;
            self.pending.set(true);
        }
        let specialization = ForwardConstants {
            environment_kind: environment_kind(&scene.environment),
            reflection_mode: FROM_UNIFORM,
            debug_view: FROM_UNIFORM,
            bounce: 1,
            shadow_taps: taps,
            shadows: u32::from(layers > 0),
            soft_shadows: u32::from(layers > 0),
            vertex_shadow_layers: layers,
            object_occlusion: u32::from(occluded),
            objects_occlusion_from: ObjectsOcclusionFrom::Vertices as u32,
            ..ForwardConstants::zeroed()
        }
        .specialization();
        let previous = std::mem::replace(&mut self.specialization, specialization);
        self.read_first_from_disk(scene, inputs, one_shot)?;
        if self.pending.get() && !self.pipelines.contains_key(&self.specialization) {
            let (device, layout, module) = (&self.device, &self.layout, &self.module);
            let pipeline = Pipeline::compute(device, layout, module, &self.specialization, "vertex light")?;
            self.pipelines.retain(|kept, _| *kept == previous);
            self.pipelines.insert(self.specialization.clone(), pipeline);
        }
        Ok(())
    }

    /// Reads the buffer from the disk cache in place of its first computation, if
    /// [`Self::prepare`] asked for that and the cache holds it under the key of `inputs`
    /// (the frame's data, the shadows' key, where the frame bounces light the light map's
    /// key, and where it bounces light or an object reads its occlusion here the
    /// environment's; none without them) and the reading objects of `scene`; else has that
    /// computation stored under it.
    fn read_first_from_disk(&mut self, scene: &Scene, inputs: &VertexLightInputs, one_shot: &OneShot) -> Result<()> {
        self.unsaved.miss(None);
        if !(self.pending.get() && self.computes.get() == 0 && self.disk.dir().is_some()) {
            return Ok(());
        }
        // Without a bounce the shader reads no light map, and neither it nor the occluders'
        // loop the environment.
        let bounces = inputs.maps.frame.ground_albedo[3] > 0.0;
        let light = if bounces { inputs.light_content } else { Some(0) };
        let environment = if bounces || self.reads_occlusion() { inputs.maps.environment } else { Some(0) };
        let (Some(light), Some(environment)) = (light, environment) else {
            return Ok(());
        };
        let device = &self.device.info;
        let mut parts: Vec<&[u8]> = vec![
            shaders::VERTEX_LIGHT_COMP,
            bytemuck::cast_slice(&self.specialization.0),
            device.name.as_bytes(),
            device.driver.as_bytes(),
            include_str!("vertex_light.rs").as_bytes(),
        ];
        let shadows = (inputs.maps.shadows)();
        let upstream = [light, environment, shadows].map(u64::to_le_bytes);
        let upstream = inputs.maps.with_frame(cache::key(&upstream.each_ref().map(|b| &b[..])));
        let upstream = upstream.to_le_bytes();
        parts.push(&upstream);
        let reading: Vec<(&Object, ObjectPush)> = (scene.objects.iter().enumerate())
            .filter_map(|(i, object)| Some((object, self.push(object, i)?)))
            .collect();
        let pushes: Vec<ObjectPush> = reading.iter().map(|&(_, push)| push).collect();
        parts.push(bytemuck::cast_slice(&pushes));
        parts.extend(reading.iter().map(|(object, _)| bytemuck::cast_slice(&scene.meshes[object.mesh].vertices)));
        let key = cache::key(&parts);
        let bits = self.disk.load(DISK_ENTRY, key).filter(|b| b.len() as u64 == self.buffer.size);
        let Some(bits) = bits else {
            self.unsaved.miss(Some(key));
            return Ok(());
        };
        transfer::upload_buffer(&self.device, one_shot, &self.buffer, &bits, AFTER_READS, BufferUse::VERTEX_READ)?;
        self.pending.set(false);
        self.computes.set(self.computes.get() + 1);
        Ok(())
    }

    /// Stores the buffer in the disk cache if its first computation was not there, once the
    /// frame that computed it is done (the caller has waited for it).
    pub fn store_computed(&self, one_shot: &OneShot) -> Result<()> {
        if let Some(key) = self.unsaved.take() {
            let bits = transfer::read_buffer(&self.device, one_shot, &self.buffer, BufferUse::VERTEX_READ)?;
            self.disk.store(DISK_ENTRY, key, &bits);
        }
        Ok(())
    }

    /// A buffer and compute sets for the objects of `key`, the frames in flight done with the
    /// old ones.
    fn lay_out(
        &mut self,
        gpu: &GpuScene,
        key: (u64, Vec<(usize, Option<u32>)>),
        ground_set: vk::DescriptorSet,
    ) -> Result<()> {
        self.device.wait_idle()?;
        let ends = key.1.iter().filter_map(|&(mesh, first)| Some(first? + gpu.meshes[mesh].vertex_count));
        self.buffer = Self::new_buffer(&self.device, ends.max().unwrap_or(0))?;
        self.point_ground_set_at_buffer(ground_set);
        let count = key.1.iter().filter(|(_, first)| first.is_some()).count();
        let pool = DescriptorPool::for_layout(&self.device, &self.set_layout, count as u32)?;
        let reading = (key.1.iter())
            .map(|&(mesh, first)| {
                let Some(first) = first else { return Ok(None) };
                let set = pool.allocate(&self.set_layout)?;
                DescriptorWriter::default()
                    .buffer(0, vk::DescriptorType::STORAGE_BUFFER, gpu.meshes[mesh].vertices.handle)
                    .buffer(1, vk::DescriptorType::STORAGE_BUFFER, self.buffer.handle)
                    .write(&self.device, set);
                Ok(Some((first, set)))
            })
            .collect::<Result<_>>()?;
        self.objects = Layout {
            key,
            reading,
            _pool: Some(pool),
        };
        self.key.clear();
        Ok(())
    }

    /// Computes the buffer if [`Self::prepare`] found it out of date, from the frame's set 0
    /// (`frame_set`), the environment's (`environment_set`), the shadows' (`shadow_set`),
    /// whose maps are rendered before, and the ground's maps (`ground_set`), whose light map
    /// is computed before; records nothing otherwise.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        scene: &Scene,
        gpu: &GpuScene,
        frame_set: vk::DescriptorSet,
        environment_set: vk::DescriptorSet,
        shadow_set: vk::DescriptorSet,
        ground_set: vk::DescriptorSet,
    ) {
        if !self.pending.replace(false) {
            return;
        }
        self.computes.set(self.computes.get() + 1);
        self.unsaved.record();
        let (device, d, layout) = (&self.device, &self.device.handle, self.layout.handle);
        buffer_barrier(device, cmd, self.buffer.handle, AFTER_READS, BufferUse::COMPUTE_WRITE);
        let compute = vk::PipelineBindPoint::COMPUTE;
        unsafe {
            d.cmd_bind_pipeline(cmd, compute, self.pipelines[&self.specialization].handle);
            d.cmd_bind_descriptor_sets(cmd, compute, layout, 0, &[frame_set], &[]);
            d.cmd_bind_descriptor_sets(cmd, compute, layout, 2, &[environment_set, shadow_set], &[]);
            d.cmd_bind_descriptor_sets(cmd, compute, layout, 5, &[ground_set], &[]);
        }
        for ((i, object), reading) in scene.objects.iter().enumerate().zip(&self.objects.reading) {
            let (Some((_, set)), Some(push)) = (*reading, self.push(object, i)) else { continue };
            let groups = gpu.meshes[object.mesh].vertex_count.div_ceil(WORKGROUP);
            unsafe {
                d.cmd_bind_descriptor_sets(cmd, compute, layout, 1, &[set], &[]);
                d.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, bytemuck::bytes_of(&push));
                d.cmd_dispatch(cmd, groups, 1, 1);
            }
        }
        buffer_barrier(device, cmd, self.buffer.handle, BufferUse::COMPUTE_WRITE, BufferUse::VERTEX_READ);
    }

    /// Whether an object of the scene prepared reads its occlusion by the others here.
    fn reads_occlusion(&self) -> bool {
        self.occlusion.iter().any(|o| o.from == ObjectsOcclusionFrom::Vertices)
    }

    /// The push constants of the computation of `object`, object `index` of the scene
    /// prepared, if it reads the buffer: its draw's, with the lights whose shadows it reads
    /// at its vertices.
    fn push(&self, object: &Object, index: usize) -> Option<ObjectPush> {
        let (first, _) = (*self.objects.reading.get(index)?)?;
        let (occlusion, shadowing) = (*self.occlusion.get(index)?, *self.shadowing.get(index)?);
        Some(ObjectPush::new(object, occlusion, shadowing, first))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    use crate::scene::DEFAULT_SCENE_TOML;

    /// The buffer's layout and workgroup are the shaders'.
    #[test]
    fn the_layout_and_workgroup_are_the_shaders() {
        let compute = include_str!("../../shaders/vertex_light.comp");
        assert!(compute.contains(&format!("local_size_x = {WORKGROUP})")));
        let floats = std::mem::size_of::<crate::scene::Vertex>() / 4;
        assert!(compute.contains(&format!("const uint VERTEX_FLOATS = {floats}u;")));
        let bounce = include_str!("../../shaders/lib/bounce.glsl");
        assert!(bounce.contains("struct BounceAtVertex {\n    vec4 channels[3];\n};"));
        let light = include_str!("../../shaders/lib/vertex_light.glsl");
        let entry = ["struct LightAtVertex {", "BounceAtVertex bounce;", "vec4 shadows[MAX_VERTEX_SHADOW_LAYERS];"];
        let entry = format!("{}\n    vec4 objects_take;\n}};", entry.join("\n    "));
        assert!(light.contains(&entry));
        assert!(light.contains("const uint MAX_VERTEX_SHADOW_LAYERS = MAX_POINT_LIGHTS / 4;"));
        assert_eq!(BYTES_PER_VERTEX, (3 + 4 + 1) * 16);
    }

    /// The disk cache's key holds what the shader reads: set 0's frame data (the occluders
    /// among it), the light map (its key), the environment's data, radiance and irradiance
    /// (its key), the shadows' data and maps (their key), and the meshes' vertices and the
    /// push constants, beside the buffer it writes. A shader that reads more needs the key
    /// to hold it too.
    #[test]
    fn the_disk_key_holds_every_resource_the_shader_reads() {
        let read = [(0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (2, 4), (3, 0), (3, 1), (5, 0)];
        assert_eq!(shaders::tests::bindings(shaders::VERTEX_LIGHT_COMP), read);
    }

    /// The default scene's ball and ring read at their vertices, one after the other; the
    /// ground does not, nor anything without a bounce, a soft shadow or its occlusion read
    /// there but in the generic pipelines.
    #[test]
    fn the_fine_meshes_but_the_ground_read_one_after_the_other() {
        let mut scene = Scene::from_toml(DEFAULT_SCENE_TOML, "default", Path::new("")).expect("the default scene");
        scene.shadow_per_vertex = true;
        let vertices = |scene: &Scene, object: usize| scene.meshes[scene.objects[object].mesh].vertices.len() as u32;
        let unshadowed = vec![0; scene.objects.len()];
        let mesh = |scene: &Scene, m: usize| (scene.meshes[m].extent(), scene.meshes[m].vertices.len() as u32);
        let at_pixels = vec![ObjectsOcclusionFrom::Pixels; scene.objects.len()];
        let firsts = |scene: &Scene, generic: bool, shadowing: &[u32]| {
            vertex_light_firsts(scene, generic, shadowing, &at_pixels, |m| mesh(scene, m))
        };
        let ground = scene.ground_index().expect("the default scene has a ground");
        let specialised = firsts(&scene, false, &unshadowed);
        let gathering: Vec<(usize, u32)> =
            (specialised.iter().enumerate()).filter_map(|(i, first)| first.map(|f| (i, f))).collect();
        let objects: Vec<usize> = gathering.iter().map(|&(i, _)| i).collect();
        assert_eq!(objects, (0..scene.objects.len()).filter(|&i| i != ground).collect::<Vec<_>>());
        assert_eq!(gathering[0].1, 0);
        for pair in gathering.windows(2) {
            assert_eq!(pair[1].1, pair[0].1 + vertices(&scene, pair[0].0));
        }
        assert_eq!(firsts(&scene, true, &unshadowed), specialised);
        scene.bounce = false;
        assert!(firsts(&scene, false, &unshadowed).iter().all(Option::is_none));
        // The ring's occlusion by the ball alone, read at its vertices.
        let mut from = at_pixels.clone();
        from[1] = ObjectsOcclusionFrom::Vertices;
        let occluded = vertex_light_firsts(&scene, false, &unshadowed, &from, |m| mesh(&scene, m));
        assert_eq!(occluded, [None, Some(0), None]);
        let generic = firsts(&scene, true, &unshadowed);
        assert_eq!(generic, specialised, "the generic pipelines are the same with or without");
        // The soft light's shadow alone is read there too, but on the ground, when asked for.
        let shadowed = vec![1; scene.objects.len()];
        assert_eq!(firsts(&scene, false, &shadowed), specialised);
        scene.shadow_per_vertex = false;
        assert!(firsts(&scene, false, &shadowed).iter().all(Option::is_none));
        scene.shadow_per_vertex = true;
        scene.lights[0].radius = 0.0;
        assert!(firsts(&scene, false, &shadowed).iter().all(Option::is_none), "a hard light's shadow is not");
    }

    /// A draw reads the vec4s up to its last light's; the soft lights' alone, but in the
    /// generic pipelines; none unless `[shadows] per_vertex` asks for them.
    #[test]
    fn shadow_layers_reach_the_last_light_read() {
        let layers: Vec<u32> = [0, 1, 0b1111, 0b1_0000, 1 << 15].map(vertex_shadow_layers).to_vec();
        assert_eq!(layers, [0, 1, 1, 2, 4]);
        let mut scene = Scene::from_toml(DEFAULT_SCENE_TOML, "default", Path::new("")).expect("the default scene");
        assert_eq!(vertex_shadowing(&scene, true, 1), 0);
        scene.shadow_per_vertex = true;
        assert_eq!(vertex_shadowing(&scene, false, 1), 1);
        scene.lights[0].radius = 0.0;
        assert_eq!((vertex_shadowing(&scene, false, 1), vertex_shadowing(&scene, true, 1)), (0, 1));
        assert_eq!(vertex_shadowing(&scene, true, 0), 0);
    }
}
