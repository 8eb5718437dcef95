//! The ground's maps: square images over the ground's square (`Scene::ground`), computed at
//! their texel centres (shaders/lib/ground_light.glsl's `ground_light_point`) and read
//! bilinearly through set 5 of the forward pass, each computed again only when what it is
//! made of changes, and recording nothing in steady frames:
//! - the light map (`[shadows] bounce`, binding 0): the point lights' irradiance on the
//!   ground, each light's through its shadow map (shaders/ground_light.comp). The bounce's
//!   gather reads it where its taps meet the ground (shaders/lib/bounce.glsl), rather than
//!   every light's shadow map at every tap of every pixel. It follows the lights, the
//!   ground and the shadow maps.
//! - the occlusion map (`[occlusion] objects` and `ground_map`, binding 1): what the
//!   objects' spheres make of the environment's diffuse light on the ground
//!   (shaders/ground_occlusion.comp), which the ground reads at its pixels
//!   (shaders/lib/ground_occlusion.glsl) rather than every sphere at every one of them. It
//!   follows the objects, the ground and the environment.
//! - the shadow map (`[shadows] ground_map`, binding 2): each point light's soft shadow on
//!   the ground (shaders/ground_shadow.comp), which the ground reads at its pixels
//!   (shaders/lib/ground_shadow.glsl) rather than searching and filtering the lights'
//!   shadow maps at every one of them. It follows the lights, the ground, the shadow maps
//!   and the soft shadows' taps.
//! - the environment map (binding 4): the split sum's diffuse and specular light of the
//!   ground's material towards each direction of view (shaders/ground_environment.comp),
//!   which the ground reads at its pixels (shaders/lib/ground_environment.glsl) rather
//!   than the split sum's tables, lookups and taps at every one of them. It follows the
//!   ground's material and the environment.
//!
//! Each starts cleared to 0, which a frame that does not use the map never reads. A map's
//! first computation in a renderer is read from the disk cache (src/cache.rs) when this
//! device and driver computed it before from the same inputs (their bits, and the code
//! that makes them), and else stored there once its frame is done: each map of the
//! default scene costs a start more to compute (its shadow map about 40 ms on lavapipe)
//! than to read. The key holds the frame's data that the shaders read, the shadows' and
//! the environment's keys (`ShadowPass::disk_key`, `EnvironmentPass::disk_key`), the
//! shader and its specialization, and the environment map's the ground's material; an
//! environment without a key (a map) keeps the occlusion and environment maps off the disk.

use std::cell::Cell;
use std::collections::HashMap;
use std::sync::Arc;

use anyhow::Result;
use ash::vk;
use bytemuck::Zeroable;
use rayon::prelude::*;

use super::debug_view::DebugView;
use super::environment::environment_kind;
use super::forward::{ForwardConstants, FROM_UNIFORM};
use super::gpu_scene::{FrameData, ObjectPush, MAX_POINT_LIGHTS};
use super::material_data::MaterialData;
use super::shaders;
use crate::cache::{self, DiskCache, Unsaved};
use crate::scene::occluders::Occluder;
use crate::scene::{Environment, MapSlot, Material, Object, ReflectionMode, Scene, Subsurface};
use crate::vk::{
    transfer, transition_levels, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder, DescriptorWriter,
    Device, Image, ImageUse, OneShot, Pipeline, PipelineLayout, Sampler, ShaderModule, Specialization,
};

/// Texels on a side of the light map: 6.25 cm on the default scene's 16 m ground, finer
/// than the gather's eight taps resolve.
pub const GROUND_LIGHT_SIZE: u32 = 256;
/// Texels on a side of the occlusion map, which is seen directly: 6.25 cm on the default
/// scene's ground, a fifth of the radius of the torus's spheres. Its bilinear reads are
/// within 0.5% of the occlusion at each pixel (tests/occlusion.rs), and computing it costs
/// about a third of what reading it saves a 1280×720 frame of the default scene; at 512²
/// the error halves and the cost is that saving.
pub const GROUND_OCCLUSION_SIZE: u32 = 256;
/// Texels on a side of the shadow map, over the part of the ground that objects can shadow:
/// 2.4 by 1.8 cm on the default scene, whose penumbrae are 10 cm wide and more.
pub const GROUND_SHADOW_SIZE: u32 = 256;
/// The shadow map's taps for each of a soft shadow's (`[shadows] taps`): a texel stands for
/// several pixels, each of which would turn its taps by its own angle.
pub const GROUND_SHADOW_TAPS_PER_TAP: u32 = 4;
/// Texels on a side of the environment map, over the upper hemisphere's directions: 0.7° to
/// 1.4° apart. Its bilinear reads of the default scene's ground are within 0.4% of the split
/// sum at each pixel, 2e-5 at the median (tests/ground_environment.rs). Most of that tail
/// lies where the split sum's tap count steps from one pixel to the next, which 256²
/// would not remove: it shrinks the tail by a third where a fixed count of taps shrinks
/// it by half and more.
pub const GROUND_ENVIRONMENT_SIZE: u32 = 128;
/// The roughness below which the ground finds its environment light at its pixels: a
/// narrower lobe changes faster with the direction of view than the environment map's
/// texels follow.
pub const GROUND_ENVIRONMENT_MIN_ROUGHNESS: f32 = 0.5;
/// Layers of the shadow map: four lights to a layer, one a channel.
const GROUND_SHADOW_LAYERS: u32 = MAX_POINT_LIGHTS.div_ceil(4) as u32;
/// A map's texels.
#[derive(Clone, Copy)]
struct Texels {
    format: vk::Format,
    bytes: u64,
}

/// fp16: a value to 2⁻¹¹ of itself, which Vulkan requires to filter and store.
const HALF: Texels = Texels {
    format: vk::Format::R16G16B16A16_SFLOAT,
    bytes: 8,
};
/// fp32, for the environment map, which holds the light itself: fp16's rounding would be
/// most of the map's difference from the split sum at each pixel (3e-4 of it, median).
/// Vulkan requires it to be storable, not filterable.
const FULL: Texels = Texels {
    format: vk::Format::R32G32B32A32_SFLOAT,
    bytes: 16,
};
/// The compute shaders' `local_size_x` and `local_size_y`.
const WORKGROUP: u32 = 8;

/// The object whose occlusion the forward pass reads from the ground's occlusion map: the
/// ground, when the objects occlude the environment's light (`objects`: on for the frame,
/// with spheres to occlude) and the scene asks for the map, the ground's material bends
/// no normal (the map is the plane's), the camera sees its upper side, and the frame is
/// not split (whose parts may light the ground differently).
pub fn occlusion_ground(scene: &Scene, objects: bool, split: bool) -> Option<usize> {
    let index = scene.ground_index()?;
    let ground = &scene.objects[index];
    let maps = &scene.materials[ground.material].maps;
    let flat = maps[MapSlot::Normal].is_none() && maps[MapSlot::Detail].is_none();
    let above = scene.camera.position.y > ground.position.y;
    let lit = scene.environment != Environment::None;
    (objects && scene.occlusion.ground_map && flat && above && lit && !split).then_some(index)
}

/// The object whose shadows the forward pass reads from the ground's shadow map: the
/// ground, when the scene asks for the map, the frame has shadows (`shadows`: on for the
/// frame and drawn with the materials' shaders), a light that casts them is soft, and the
/// camera sees the ground's upper side (which side of it a light is on then decides
/// whether the map or the pixels are lit, as shadows.glsl's `shadow_receiver` asks). A
/// split frame's parts differ in materials and environment, which the shadows do not
/// depend on. The hard lights' shadows ([`hard_shadows`]) it looks up at its pixels.
pub fn shadow_ground(scene: &Scene, shadows: bool) -> Option<usize> {
    let index = scene.ground_index()?;
    let above = scene.camera.position.y > scene.objects[index].position.y;
    let soft = scene.lights.iter().any(|l| l.shadows && l.radius > 0.0);
    (scene.shadow_ground_map && shadows && soft && above).then_some(index)
}

/// The object that may read its environment light from the ground's environment map, the
/// frame's sun aside (a lobe too narrow for the map's directions, which the caller knows
/// once the environment is): the ground, when `allowed` (the renderer's
/// `ground_environment`, in a frame that is not split, not the floor; a generic pipeline
/// specialises where its ground reads the light from, as where it reads the objects'
/// occlusion from), the environment is a map's or the studio's (a uniform one's light
/// costs a pixel no lookups) reflected by the split sum, the ground's pipeline samples no
/// map that changes its material or its normal from pixel to pixel (an occlusion map
/// scales the light the map holds, an emission map adds its own), the material is rough
/// enough (`GROUND_ENVIRONMENT_MIN_ROUGHNESS`) and has no pre-integrated subsurface (whose
/// table the map's disk cache key does not hold), and the camera sees the ground's upper
/// side.
pub fn environment_ground(scene: &Scene, allowed: bool) -> Option<usize> {
    let index = scene.ground_index()?;
    let ground = &scene.objects[index];
    let material = &scene.materials[ground.material];
    let constants = ground_constants(material, &scene.environment);
    let mapped = (MapSlot::ALL.into_iter())
        .filter(|slot| !matches!(slot, MapSlot::Occlusion | MapSlot::Emission))
        .any(|slot| constants.samples(slot));
    let rough = material.roughness >= GROUND_ENVIRONMENT_MIN_ROUGHNESS;
    let preintegrated = material.subsurface == Subsurface::PreIntegrated;
    let split_sum = match &scene.environment {
        Environment::Studio { reflection, .. } | Environment::Map { reflection, .. } => {
            reflection.mode == ReflectionMode::SplitSum
        }
        Environment::None | Environment::Uniform { .. } => false,
    };
    let above = scene.camera.position.y > ground.position.y;
    (allowed && split_sum && !mapped && rough && !preintegrated && above).then_some(index)
}

/// Whether a light that casts shadows is hard: its shadow is one lookup at a pixel, whose
/// edge the ground's map would blur, so the ground that reads the soft ones from its map
/// looks the hard ones up at its pixels (lights.glsl's `point_light_visibility`).
pub fn hard_shadows(scene: &Scene) -> bool {
    scene.lights.iter().any(|l| l.shadows && l.radius <= 0.0)
}

/// One map: its image, written through `compute_set` by its shader's pipeline as the frame
/// specialises it (made when a frame first reads the map), and what it was last computed
/// from.
struct GroundMap {
    image: Image,
    texels: Texels,
    size: u32,
    compute_set: vk::DescriptorSet,
    module: ShaderModule,
    shader: &'static [u8],
    name: &'static str,
    /// A pipeline for each specialization a computation has run with: a frame in flight
    /// may still use the one before.
    pipelines: HashMap<Specialization, Pipeline>,
    /// The last a frame asked for (see [`GroundMaps::prepare`]).
    specialization: Specialization,
    /// What the map was last computed from; empty before the first and after a change the
    /// key does not hold.
    key: Vec<u32>,
    /// Whether the next recorded frame computes the map.
    pending: Cell<bool>,
    /// The disk cache's key of that computation, when it is the map's first and the cache
    /// misses it, until [`GroundMaps::store_computed`] stores it.
    unsaved: Unsaved,
    /// The disk cache's key of what the map holds, or is about to once a frame computes it,
    /// when it was computed or read first with one: what the entries of what is computed
    /// from the map are keyed by.
    content: Cell<Option<u64>>,
    /// Times the map was made: computed by a frame, or read from the disk cache.
    renders: Cell<u64>,
}

impl GroundMap {
    /// A map `size` texels on a side: a 2D image, or a 2D array of `layers` when more than
    /// one.
    #[allow(clippy::too_many_arguments)]
    fn new(
        device: &Arc<Device>,
        one_shot: &OneShot,
        compute_set: vk::DescriptorSet,
        shader: &'static [u8],
        size: u32,
        layers: u32,
        texels: Texels,
        name: &'static str,
    ) -> Result<Self> {
        let module = ShaderModule::new(device, shader, name)?;
        let extent = vk::Extent2D {
            width: size,
            height: size,
        };
        let usage = vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_DST
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let image = if layers > 1 {
            Image::array_2d(device, extent, layers, texels.format, usage, name)?
        } else {
            Image::new_2d(device, extent, texels.format, usage, vk::ImageAspectFlags::COLOR, name)?
        };
        one_shot.run(|cmd| image.record_clear(cmd, MAP_READ))?;
        DescriptorWriter::default()
            .image(
                0,
                vk::DescriptorType::STORAGE_IMAGE,
                image.view,
                vk::ImageLayout::GENERAL,
                vk::Sampler::null(),
            )
            .write(device, compute_set);
        Ok(Self {
            image,
            texels,
            size,
            compute_set,
            module,
            shader,
            name,
            pipelines: HashMap::new(),
            specialization: Specialization::default(),
            key: Vec::new(),
            pending: Cell::new(false),
            unsaved: Unsaved::default(),
            content: Cell::new(None),
            renders: Cell::new(0),
        })
    }

    /// Has the next computation of the map, if its pipeline exists, run with
    /// `specialization` (see [`Self::make_pipeline`]).
    fn specialize(&mut self, specialization: Specialization) {
        self.specialization = specialization;
    }

    /// Creates the pipeline of the computation that the next recorded frame runs, if it
    /// runs one and no frame has run it before.
    fn make_pipeline(&mut self, device: &Arc<Device>, layout: &PipelineLayout) -> Result<()> {
        if self.pending.get() && !self.pipelines.contains_key(&self.specialization) {
            let pipeline = Pipeline::compute(device, layout, &self.module, &self.specialization, self.name)?;
            self.pipelines.insert(self.specialization.clone(), pipeline);
        }
        Ok(())
    }

    /// Has the next recorded frame compute the map when it is made of `key` (None: this
    /// frame does not read it) and that differs from what it was computed from. A frame
    /// that does not read it leaves it as it is (a floor frame of the bench between two
    /// frames of the scene).
    fn prepare(&mut self, key: Option<Vec<u32>>) {
        if let Some(key) = key.filter(|key| *key != self.key) {
            self.key = key;
            self.pending.set(true);
            self.content.set(None);
        }
    }

    /// Reads the map from `disk` in place of its first computation, if [`Self::prepare`]
    /// asked for that and the disk holds it under `inputs`' key (None: these inputs have
    /// no key); else has that computation stored under it.
    fn read_first_from_disk(
        &mut self,
        device: &Arc<Device>,
        one_shot: &OneShot,
        disk: &DiskCache,
        inputs: impl FnOnce() -> Option<u64>,
    ) -> Result<()> {
        // The inputs' key is found only for a first computation, which a cache may hold.
        let first = self.pending.get() && self.renders.get() == 0 && disk.dir().is_some();
        let Some(key) = first.then(inputs).flatten().map(|inputs| {
            let device = &device.info;
            cache::key(&[
                &inputs.to_le_bytes(),
                self.shader,
                bytemuck::cast_slice(&self.specialization.0),
                &self.size.to_le_bytes(),
                &self.image.layers.to_le_bytes(),
                device.name.as_bytes(),
                device.driver.as_bytes(),
                include_str!("ground_maps.rs").as_bytes(),
            ])
        }) else {
            self.unsaved.miss(None);
            return Ok(());
        };
        let size = transfer::image_size(&self.image, self.texels.bytes);
        // What the map holds once it is read or computed.
        self.content.set(Some(key));
        let Some(bits) = disk.load(&self.entry(), key).filter(|b| b.len() == size) else {
            self.unsaved.miss(Some(key));
            return Ok(());
        };
        transfer::upload_image(device, one_shot, &self.image, &[&bits], AFTER_READS, MAP_READ)?;
        self.pending.set(false);
        self.unsaved.miss(None);
        self.renders.set(self.renders.get() + 1);
        Ok(())
    }

    /// The map's entries' name in the disk cache.
    fn entry(&self) -> String {
        self.name.replace(' ', "-")
    }

    /// Computes the map if [`Self::prepare`] found it out of date, with the other sets of
    /// `layout` bound, leaving it readable by the forward pass.
    fn record(&self, device: &Device, cmd: vk::CommandBuffer, layout: &PipelineLayout) {
        if !self.pending.replace(false) {
            return;
        }
        self.unsaved.record();
        self.renders.set(self.renders.get() + 1);
        let image = &self.image;
        let layers = image.all_levels();
        transition_levels(device, cmd, image.handle, layers, AFTER_READS, ImageUse::COMPUTE_STORAGE);
        let d = &device.handle;
        let groups = self.size.div_ceil(WORKGROUP);
        unsafe {
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                layout.handle,
                1,
                &[self.compute_set],
                &[],
            );
            let pipeline = &self.pipelines[&self.specialization];
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.handle);
            d.cmd_dispatch(cmd, groups, groups, 1);
        }
        transition_levels(device, cmd, image.handle, layers, ImageUse::COMPUTE_STORAGE, MAP_READ);
    }
}

/// How the maps are read: by the forward pass's fragments, and the light map by the
/// bounce's gather at the vertices too (vertex_light.rs).
const MAP_READ: ImageUse = ImageUse {
    stage: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw() | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw(),
    ),
    ..ImageUse::FRAGMENT_READ
};

/// Where a map is made again from: its old texels go once the frames before have read them.
const AFTER_READS: ImageUse = ImageUse {
    stage: MAP_READ.stage,
    ..ImageUse::UNDEFINED
};

/// What the maps' disk cache entries are keyed by besides each map's own code.
pub struct MapInputs<'a> {
    /// Set 0's data as the frame writes it.
    pub frame: &'a FrameData,
    /// `ShadowPass::disk_key` of the frame's shadows, asked for only by a map's first
    /// computation.
    pub shadows: &'a dyn Fn() -> u64,
    /// `EnvironmentPass::disk_key`.
    pub environment: Option<u64>,
}

impl MapInputs<'_> {
    /// The key of what is computed from the frame's data and `upstream`'s key.
    pub fn with_frame(&self, upstream: u64) -> u64 {
        // The view and the sample set are the frame's alone: no map reads them.
        let frame = FrameData {
            view_proj: [[0.0; 4]; 4],
            camera_position: [0.0; 4],
            counts: [self.frame.counts[0], self.frame.counts[1], 0, self.frame.counts[3]],
            ..*self.frame
        };
        cache::key(&[bytemuck::bytes_of(&frame), &upstream.to_le_bytes()])
    }
}

pub struct GroundMaps {
    device: Arc<Device>,
    disk: DiskCache,
    /// Set 5 of the forward pass: the maps, sampled.
    set_layout: DescriptorSetLayout,
    set: vk::DescriptorSet,
    _compute_set_layout: DescriptorSetLayout,
    _pools: [DescriptorPool; 2],
    /// The forward pass's set 0 (frame data), set 1 a map's storage image, set 2 the
    /// environment's, set 3 the shadows'; the push constants a draw's (`ObjectPush`), of
    /// which the environment map reads the ground's material.
    layout: PipelineLayout,
    _samplers: [Sampler; 2],
    light: GroundMap,
    occlusion: GroundMap,
    shadow: GroundMap,
    environment: GroundMap,
    /// The ground's material, which the environment map is computed for.
    environment_material: u32,
    /// Whether the device filters the environment map's texels, without which the ground
    /// finds its environment light at its pixels.
    environment_filtered: bool,
}

impl GroundMaps {
    /// The layout of set 5 of the forward pass, which [`Self::new`] takes over: the light,
    /// occlusion and shadow maps, what the draws read at their vertices, which
    /// vertex_light.rs computes, and the environment map.
    pub fn forward_set_layout(device: &Arc<Device>) -> Result<DescriptorSetLayout> {
        DescriptorSetLayoutBuilder::default()
            // The light map: the bounce's gather at the vertices reads it too (vertex_light.rs).
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::FRAGMENT,
            )
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .binding(vk::DescriptorType::STORAGE_BUFFER, vk::ShaderStageFlags::VERTEX)
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT,
            )
            .build(device, "ground maps set")
    }

    /// The compute shaders read the lights, the ground and the occluders from the forward
    /// pass's set 0 (`frame_layout`), the environment from its set 2 (`environment_layout`)
    /// and the shadow maps from its set 3 (`shadow_layout`).
    pub fn new(
        device: &Arc<Device>,
        one_shot: &OneShot,
        set_layout: DescriptorSetLayout,
        frame_layout: &DescriptorSetLayout,
        environment_layout: &DescriptorSetLayout,
        shadow_layout: &DescriptorSetLayout,
    ) -> Result<Self> {
        let compute_set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE)
            .build(device, "ground map compute set")?;
        let pools = [
            DescriptorPool::for_layout(device, &set_layout, 1)?,
            DescriptorPool::for_layout(device, &compute_set_layout, 4)?,
        ];
        let set = pools[0].allocate(&set_layout)?;
        let layout = PipelineLayout::new(
            device,
            &[frame_layout, &compute_set_layout, environment_layout, shadow_layout],
            std::mem::size_of::<ObjectPush>() as u32,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let map = |shader: &'static [u8], size: u32, layers: u32, texels: Texels, name: &'static str| {
            let compute_set = pools[1].allocate(&compute_set_layout)?;
            GroundMap::new(device, one_shot, compute_set, shader, size, layers, texels, name)
        };
        let light = map(shaders::GROUND_LIGHT_COMP, GROUND_LIGHT_SIZE, 1, HALF, "ground light")?;
        let occlusion = map(shaders::GROUND_OCCLUSION_COMP, GROUND_OCCLUSION_SIZE, 1, HALF, "ground occlusion")?;
        let layers = GROUND_SHADOW_LAYERS;
        let shadow = map(shaders::GROUND_SHADOW_COMP, GROUND_SHADOW_SIZE, layers, HALF, "ground shadow")?;
        let size = GROUND_ENVIRONMENT_SIZE;
        let environment = map(shaders::GROUND_ENVIRONMENT_COMP, size, 2, FULL, "ground environment")?;
        let features = unsafe {
            let instance = &device.instance.handle;
            instance.get_physical_device_format_properties(device.physical, FULL.format).optimal_tiling_features
        };
        let environment_filtered = features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR);
        // Where the device cannot filter the environment map, which the ground then never
        // reads, its binding holds a sampler that does not filter.
        let samplers = [Sampler::clamped(device)?, Sampler::nearest(device)?];
        let sampled = |writer: DescriptorWriter, binding: u32, map: &GroundMap, filtered: bool| {
            writer.image(
                binding,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                map.image.view,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                samplers[usize::from(!filtered)].handle,
            )
        };
        let writer = sampled(DescriptorWriter::default(), 0, &light, true);
        let writer = sampled(sampled(writer, 1, &occlusion, true), 2, &shadow, true);
        sampled(writer, 4, &environment, environment_filtered).write(device, set);
        Ok(Self {
            device: device.clone(),
            disk: DiskCache::from_env(),
            set_layout,
            set,
            _compute_set_layout: compute_set_layout,
            _pools: pools,
            layout,
            _samplers: samplers,
            light,
            occlusion,
            shadow,
            environment,
            environment_material: 0,
            environment_filtered,
        })
    }

    /// Whether the ground can read its environment light from the environment map.
    pub fn environment_filtered(&self) -> bool {
        self.environment_filtered
    }

    /// Set 5 of the forward pass.
    pub fn set(&self) -> vk::DescriptorSet {
        self.set
    }

    /// Its layout.
    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Has the next recorded frame compute each map the frame reads whose inputs changed:
    /// the light map when the scene bounces light and its lights, its ground or the shadow
    /// maps (their `shadow_generation`: rendered again, or switched on or off) changed; the
    /// occlusion map when `occlusion_ground` (see [`occlusion_ground`]) reads it and the
    /// ground, the frame's `occluders` or the environment (its `environment_generation`)
    /// changed; the shadow map when `shadow_ground` (see [`shadow_ground`]) reads it and
    /// the ground, the lights, the taps or the shadow maps changed; the environment map
    /// when `environment_ground` (see [`environment_ground`]) reads it and the ground's
    /// material or the environment changed. A map's first computation is read from the disk
    /// cache instead, through `one_shot`, when it holds one of the same `inputs`.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        scene: &Scene,
        occluders: &[Occluder],
        shadow_generation: u64,
        occlusion_ground: Option<usize>,
        shadow_ground: Option<usize>,
        environment_ground: Option<usize>,
        environment_generation: u64,
        one_shot: &OneShot,
        inputs: &MapInputs,
    ) -> Result<()> {
        self.specialize(scene, occlusion_ground, shadow_ground, environment_ground);
        let light_key = scene.bounce_ground().map(|ground| {
            let lights = scene.lights.iter().take(MAX_POINT_LIGHTS);
            let lights = lights.flat_map(|l| [l.position, l.intensity]).flat_map(|v| v.to_array());
            map_key(ground, lights, shadow_generation)
        });
        self.light.prepare(light_key);
        let occlusion_key = |index| occlusion_map_key(scene, index, occluders, environment_generation);
        self.occlusion.prepare(occlusion_ground.map(occlusion_key));
        self.shadow.prepare(shadow_ground.map(|index| shadow_map_key(scene, index, shadow_generation)));
        let specialization = &self.environment.specialization;
        let environment_key = |index| environment_map_key(scene, index, specialization, environment_generation);
        self.environment.prepare(environment_ground.map(environment_key));
        if let Some(index) = environment_ground {
            self.environment_material = scene.objects[index].material as u32;
        }
        let (device, disk) = (&self.device, &self.disk);
        let from_shadows = || Some(inputs.with_frame((inputs.shadows)()));
        self.light.read_first_from_disk(device, one_shot, disk, from_shadows)?;
        self.shadow.read_first_from_disk(device, one_shot, disk, from_shadows)?;
        let from_environment = || inputs.environment.map(|key| inputs.with_frame(key));
        self.occlusion.read_first_from_disk(device, one_shot, disk, from_environment)?;
        let from_material = || {
            let material = MaterialData::from(&scene.materials[scene.objects[environment_ground?].material]);
            let key = inputs.environment?;
            Some(inputs.with_frame(cache::key(&[&key.to_le_bytes(), bytemuck::bytes_of(&material)])))
        };
        self.environment.read_first_from_disk(device, one_shot, disk, from_material)?;
        // The pipelines of the maps left to compute, on both cores: a warm start makes none.
        let layout = &self.layout;
        let mut maps = [&mut self.light, &mut self.occlusion, &mut self.shadow, &mut self.environment];
        maps.par_iter_mut().try_for_each(|map| map.make_pipeline(device, layout))
    }

    /// Whether the shadow map holds the ground's shadows as a frame of `scene` whose shadow
    /// maps are at `shadow_generation` would compute them, the ground being object `ground`.
    pub fn shadow_map_current(&self, scene: &Scene, ground: usize, shadow_generation: u64) -> bool {
        self.shadow.key == shadow_map_key(scene, ground, shadow_generation)
    }

    /// Whether the occlusion map holds what `occluders` make of the environment (at
    /// `environment_generation`) on object `ground` of `scene`, as a frame would compute it.
    pub fn occlusion_map_current(
        &self,
        scene: &Scene,
        ground: usize,
        occluders: &[Occluder],
        environment_generation: u64,
    ) -> bool {
        self.occlusion.key == occlusion_map_key(scene, ground, occluders, environment_generation)
    }

    /// Stores in the disk cache each map whose first computation it did not hold, once the
    /// frame that computed it is done (the caller has waited for it).
    pub fn store_computed(&self, one_shot: &OneShot) -> Result<()> {
        for map in [&self.light, &self.occlusion, &self.shadow, &self.environment] {
            if let Some(key) = map.unsaved.take() {
                let (device, at) = (&self.device, MAP_READ);
                let bits = transfer::read_level(device, one_shot, &map.image, 0, map.texels.bytes, at)?;
                self.disk.store(&map.entry(), key, &bits);
            }
        }
        Ok(())
    }

    /// Specialises the maps that a frame of `scene` reads (`occlusion_ground` and
    /// `shadow_ground` as [`Self::prepare`] takes them) as the frame does.
    fn specialize(
        &mut self,
        scene: &Scene,
        occlusion_ground: Option<usize>,
        shadow_ground: Option<usize>,
        environment_ground: Option<usize>,
    ) {
        if scene.bounce_ground().is_some() {
            self.light.specialize(Specialization::default());
        }
        if occlusion_ground.is_some() {
            self.occlusion.specialize(occlusion_specialization(&scene.environment));
        }
        if shadow_ground.is_some() {
            let taps = GROUND_SHADOW_TAPS_PER_TAP * scene.shadow_taps;
            self.shadow.specialize(shadow_specialization(taps));
        }
        if let Some(index) = environment_ground {
            let material = &scene.materials[scene.objects[index].material];
            self.environment.specialize(environment_specialization(material, &scene.environment));
        }
    }

    /// What the light map was last computed from (its lights, the ground, the shadow maps'
    /// generation): the bounce at the vertices follows it.
    pub fn light_key(&self) -> &[u32] {
        &self.light.key
    }

    /// The disk cache's key of what the light map holds, when it was computed or read first
    /// with one: the frame's data and the shadows' key are in it, and the bounce at the
    /// vertices keys its entries by it.
    pub fn light_content(&self) -> Option<u64> {
        self.light.content.get()
    }

    /// Times the light map was made (computed, or read from the disk cache).
    pub fn light_renders(&self) -> u64 {
        self.light.renders.get()
    }

    /// Times the occlusion map was made.
    pub fn occlusion_renders(&self) -> u64 {
        self.occlusion.renders.get()
    }

    /// Times the shadow map was made.
    pub fn shadow_renders(&self) -> u64 {
        self.shadow.renders.get()
    }

    /// Times the environment map was made.
    pub fn environment_renders(&self) -> u64 {
        self.environment.renders.get()
    }

    /// Whether the environment map holds the light of object `ground` of `scene` under the
    /// environment at `environment_generation`, as a frame would compute it.
    pub fn environment_map_current(&self, scene: &Scene, ground: usize, environment_generation: u64) -> bool {
        let material = &scene.materials[scene.objects[ground].material];
        let specialization = environment_specialization(material, &scene.environment);
        self.environment.key == environment_map_key(scene, ground, &specialization, environment_generation)
    }

    /// Computes the light map and the shadow map, each if [`Self::prepare`] found it out of
    /// date, from the frame's set 0 (`frame_set`) and shadow set (`shadow_set`); records
    /// nothing otherwise.
    pub fn record_from_shadow_maps(
        &self,
        cmd: vk::CommandBuffer,
        frame_set: vk::DescriptorSet,
        shadow_set: vk::DescriptorSet,
    ) {
        if self.light.pending.get() || self.shadow.pending.get() {
            self.bind(cmd, 0, &[frame_set]);
            self.bind(cmd, 3, &[shadow_set]);
        }
        self.light.record(&self.device, cmd, &self.layout);
        self.shadow.record(&self.device, cmd, &self.layout);
    }

    /// Computes the occlusion map and the environment map, each if [`Self::prepare`] found
    /// it out of date, from the frame's set 0 (`frame_set`) and the environment's set
    /// (`environment_set`); records nothing otherwise.
    pub fn record_from_environment(
        &self,
        cmd: vk::CommandBuffer,
        frame_set: vk::DescriptorSet,
        environment_set: vk::DescriptorSet,
    ) {
        if self.occlusion.pending.get() || self.environment.pending.get() {
            self.bind(cmd, 0, &[frame_set]);
            self.bind(cmd, 2, &[environment_set]);
        }
        if self.environment.pending.get() {
            // The ground's material; the rest of a draw's constants the map does not read.
            let push = ObjectPush {
                material_index: self.environment_material,
                ..bytemuck::Zeroable::zeroed()
            };
            let (d, layout) = (&self.device.handle, self.layout.handle);
            let stages = vk::ShaderStageFlags::COMPUTE;
            unsafe { d.cmd_push_constants(cmd, layout, stages, 0, bytemuck::bytes_of(&push)) };
        }
        self.occlusion.record(&self.device, cmd, &self.layout);
        self.environment.record(&self.device, cmd, &self.layout);
    }

    fn bind(&self, cmd: vk::CommandBuffer, first: u32, sets: &[vk::DescriptorSet]) {
        let (d, layout) = (&self.device.handle, self.layout.handle);
        unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, first, sets, &[]) };
    }
}

/// A map's inputs bit for bit, the ground's square first, and the generation of the images
/// it reads: what [`GroundMap::prepare`] compares.
fn map_key(ground: &Object, inputs: impl IntoIterator<Item = f32>, generation: u64) -> Vec<u32> {
    let square = ground.position.extend(ground.scale).to_array();
    let bits = square.into_iter().chain(inputs).map(f32::to_bits);
    bits.chain([generation as u32, (generation >> 32) as u32]).collect()
}

/// The shadow map's key: the lights' positions and radii, the shadow maps' generation and
/// the taps, over object `ground`.
fn shadow_map_key(scene: &Scene, ground: usize, shadow_generation: u64) -> Vec<u32> {
    let lights = scene.lights.iter().take(MAX_POINT_LIGHTS);
    let lights = lights.flat_map(|l| l.position.extend(l.radius).to_array());
    let mut key = map_key(&scene.objects[ground], lights, shadow_generation);
    key.push(scene.shadow_taps);
    key
}

/// The occlusion map's key: the occluders' spheres and albedos and the environment's
/// generation, over object `ground`.
fn occlusion_map_key(scene: &Scene, ground: usize, occluders: &[Occluder], environment_generation: u64) -> Vec<u32> {
    let spheres = occluders.iter().flat_map(|s| [s.centre.extend(s.radius), s.albedo.extend(0.0)]);
    map_key(&scene.objects[ground], spheres.flat_map(|v| v.to_array()), environment_generation)
}

/// The environment map's key: the ground's material, the environment's generation and the
/// map's specialization (the material's models and the environment's kind), over object
/// `ground`.
fn environment_map_key(
    scene: &Scene,
    ground: usize,
    specialization: &Specialization,
    environment_generation: u64,
) -> Vec<u32> {
    let object = &scene.objects[ground];
    let material = MaterialData::from(&scene.materials[object.material]);
    let mut key = map_key(object, [], environment_generation);
    key.extend(bytemuck::cast_slice::<MaterialData, u32>(std::slice::from_ref(&material)));
    key.extend(&specialization.0);
    key
}

/// The constants of a ground's specialised draw of `material` under `environment`: the maps
/// it samples, and the environment map's pipeline.
fn ground_constants(material: &Material, environment: &Environment) -> ForwardConstants {
    ForwardConstants::new(material, environment, DebugView::Shaded, true, false)
}

/// The environment map's pipeline: the ground's draw's constants (`ground_constants`).
fn environment_specialization(material: &Material, environment: &Environment) -> Specialization {
    ground_constants(material, environment).specialization()
}

/// The occlusion map's pipeline: object_occlusion.glsl's code on, for the kind of
/// `environment`.
fn occlusion_specialization(environment: &Environment) -> Specialization {
    ForwardConstants {
        environment_kind: environment_kind(environment),
        reflection_mode: FROM_UNIFORM,
        debug_view: FROM_UNIFORM,
        object_occlusion: 1,
        ..ForwardConstants::zeroed()
    }
    .specialization()
}

/// The shadow map's pipeline: shadows.glsl's code with the scene's `taps`, for soft lights.
fn shadow_specialization(taps: u32) -> Specialization {
    ForwardConstants {
        shadow_taps: taps,
        soft_shadows: 1,
        ..ForwardConstants::zeroed()
    }
    .specialization()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map's disk cache key holds what its shader reads: set 0's frame data (binding 0) or
    /// the ground's material (binding 1), the shadows' set 3 (`ShadowPass::disk_key`) or
    /// the environment's set 2 (`EnvironmentPass::disk_key`, all of it), beside the map it
    /// writes (set 1). A shader that reads more needs its key to hold it too.
    #[test]
    fn the_disk_keys_hold_every_resource_the_shaders_read() {
        use shaders::tests::bindings;
        let from_shadows = [(0, 0), (1, 0), (3, 0), (3, 1)];
        assert_eq!(bindings(shaders::GROUND_LIGHT_COMP), from_shadows);
        assert_eq!(bindings(shaders::GROUND_SHADOW_COMP), from_shadows);
        assert_eq!(bindings(shaders::GROUND_OCCLUSION_COMP), [(0, 0), (1, 0), (2, 0), (2, 1), (2, 4)]);
        // The material (set 0's binding 1) is in the environment map's key; the subsurface
        // table (binding 2) is read by pre-integrated subsurface alone, which no ground with
        // the map has (`environment_ground`).
        let from_environment = [(0, 1), (0, 2), (1, 0), (2, 0), (2, 2), (2, 3), (2, 4)];
        assert_eq!(bindings(shaders::GROUND_ENVIRONMENT_COMP), from_environment);
    }

    /// The ground reads its environment light from the map where the map can stand for the
    /// split sum at its pixels, and only there.
    #[test]
    fn the_ground_reads_the_environment_map_where_it_can() {
        let default = || {
            Scene::from_toml(crate::scene::DEFAULT_SCENE_TOML, "default", std::path::Path::new(""))
                .expect("the default scene")
        };
        let ground = default().ground_index().expect("a ground");
        assert_eq!(environment_ground(&default(), true), Some(ground));
        assert_eq!(environment_ground(&default(), false), None);
        // An emission map, sampled where the emission is not 0, adds its own light.
        let mut emissive = default();
        let material = emissive.objects[ground].material;
        let normal_map = emissive.materials.iter().find_map(|m| m.maps[MapSlot::Normal]);
        emissive.materials[material].maps[MapSlot::Emission] = normal_map;
        emissive.materials[material].emission = glam::Vec3::ONE;
        assert_eq!(environment_ground(&emissive, true), Some(ground));
        type Change = fn(&mut Scene, usize);
        let changes: [(&str, Change); 6] = [
            ("smooth", |s, m| s.materials[m].roughness = 0.4),
            ("pre-integrated", |s, m| s.materials[m].subsurface = Subsurface::PreIntegrated),
            ("mapped", |s, m| {
                let fingerprints = s.materials.iter().find_map(|m| m.maps[MapSlot::Detail]);
                s.materials[m].maps[MapSlot::Detail] = fingerprints;
            }),
            ("seed", |s, _| s.environment.reflection_mut().expect("an environment").mode = ReflectionMode::Seed),
            ("uniform", |s, _| {
                s.environment = Environment::Uniform {
                    radiance: glam::Vec3::ONE,
                    reflection: Default::default(),
                }
            }),
            ("below", |s, _| s.camera.position.y = -2.0),
        ];
        for (name, change) in changes {
            let mut s = default();
            let material = s.objects[ground].material;
            change(&mut s, material);
            assert_eq!(environment_ground(&s, true), None, "{name}");
        }
    }

    #[test]
    fn the_workgroup_and_format_are_the_shaders() {
        for (glsl, texels) in [
            (include_str!("../../shaders/ground_light.comp"), HALF),
            (include_str!("../../shaders/ground_occlusion.comp"), HALF),
            (include_str!("../../shaders/ground_shadow.comp"), HALF),
            (include_str!("../../shaders/ground_environment.comp"), FULL),
        ] {
            assert!(glsl.contains(&format!("local_size_x = {WORKGROUP}, local_size_y = {WORKGROUP}")));
            let (qualifier, bytes) = match texels.format {
                vk::Format::R16G16B16A16_SFLOAT => ("rgba16f", 8),
                vk::Format::R32G32B32A32_SFLOAT => ("rgba32f", 16),
                other => panic!("{other:?}"),
            };
            assert!(glsl.contains(&format!("{qualifier}) uniform writeonly")) && texels.bytes == bytes);
        }
    }
}
