//! The forward pass: every object, shaded by every point light, into the HDR target.
//!
//! Set 0: binding 0 the `FrameData` uniform buffer, binding 1 the `Materials` storage
//! buffer, binding 2 the pre-integrated subsurface table (uploaded when a scene first
//! needs it, a placeholder until then); set 2: the environment (see environment.rs); set 3:
//! the shadow maps (see shadow.rs); set 4: the ambient occlusion (see occlusion.rs); push constants: `ObjectPush` (see
//! shaders/lib/scene_data.glsl). One pipeline per combination of BRDF models in use,
//! chosen by specialization constants, and sample count (src/render/msaa.rs); for
//! `argil bench`, one more that draws every object with the trivial `floor.frag`.

use std::collections::HashMap;
use std::mem::offset_of;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use rayon::prelude::*;

use super::debug_view::DebugView;
use super::deferred::{DeferredPass, G_ATTACHMENTS};
use super::environment::{environment_kind, reflection_code};
use super::gpu_scene::{FrameData, GpuScene, ObjectOcclusion, ObjectPush, ObjectsOcclusionFrom};
use super::ground_maps;
use super::material_data::MaterialData;
use super::occlusion::OcclusionMode;
use super::shaders;
use super::split::Split;
use super::subsurface::SubsurfaceTable;
use super::target::{DrawTarget, DEPTH_FORMAT, HDR_FORMAT};
use super::vertex_light::{gpu_vertex_light_firsts, light_at_vertices, vertex_shadow_layers, vertex_shadowing};
use crate::scene::limits::MAX_OBJECTS;
use crate::scene::map_slots::MAP_COUNT;
use crate::scene::occluders::Occluder;
use crate::scene::{
    DetailBlend, Environment, Horizon, MapRef, MapSlot, Material, ReflectionMode, Scene, SpecularModel, Subsurface,
    Vertex, DEFAULT_SHADOW_TAPS,
};
use crate::vk::{
    begin_full_rendering, transition, Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, GraphicsPipelineBuilder, ImageUse, OneShot, Pipeline, PipelineLayout, ShaderModule,
    Specialization,
};

/// A specialization constant's value that leaves the choice to the uniform the shader
/// also has (`FROM_UNIFORM` in shaders/lib/specialization.glsl): the generic pipeline.
pub const FROM_UNIFORM: u32 = u32::MAX;

/// The specialization constants of `forward.frag`, in `constant_id` order: a material's
/// models (shading.glsl), which maps it samples (`maps`: bit `MapSlot::bit` per slot,
/// material_maps.glsl) and how the detail map blends, its horizon and
/// subsurface model, the debug view (debug_views.glsl), the environment's kind and
/// reflection mode (environment.glsl), specular anti-aliasing (specular_aa.glsl), and how
/// the environment's light is occluded (`OcclusionMode`, occlusion_map.glsl), whether the
/// objects occlude it and where the draw reads that from (`ObjectsOcclusionFrom`,
/// object_occlusion.glsl), those three always specialised; and whether the pipeline holds
/// the ground's bounce (bounce.glsl), a map's sun and the material's energy compensation
/// (environment.glsl), which the generic pipeline always does; a soft shadow's taps
/// (`[shadows] taps`, shadows.glsl); whether the draw reads its shadows from the
/// ground's shadow map (ground_shadow.glsl); whether the frame has shadows at all
/// (lights.glsl), which the generic pipeline always holds; whether the draw that reads
/// the soft lights' shadows from the ground's map or its vertices looks hard lights up at
/// its pixels beside them; whether a light that may shadow the draw's object is soft
/// (shadows.glsl), which the generic pipeline holds; whether the draw gathers the bounce at
/// its vertices (bounce.glsl), by its mesh; the vec4s of soft lights' shadows it reads at
/// its vertices (vertex_light.glsl); and whether the draw reads its environment light from
/// the ground's environment map (ground_environment.glsl), always specialised.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ForwardConstants {
    pub diffuse_model: u32,
    pub specular_model: u32,
    pub distribution: u32,
    pub geometry: u32,
    pub maps: u32,
    pub detail_blend: u32,
    pub horizon: u32,
    pub subsurface: u32,
    pub debug_view: u32,
    pub environment_kind: u32,
    pub reflection_mode: u32,
    pub specular_aa: u32,
    pub occlusion: u32,
    pub object_occlusion: u32,
    pub objects_occlusion_from: u32,
    pub bounce: u32,
    pub sun: u32,
    pub energy_compensation: u32,
    pub shadow_taps: u32,
    pub ground_shadows: u32,
    pub shadows: u32,
    pub hard_shadows_at_pixels: u32,
    pub soft_shadows: u32,
    pub bounce_at_vertices: u32,
    pub vertex_shadow_layers: u32,
    pub ground_environment: u32,
}

impl ForwardConstants {
    /// The GLSL names, in field order, checked against the shaders by a test.
    pub const NAMES: [&'static str; 26] = [
        "DIFFUSE_MODEL",
        "SPECULAR_MODEL",
        "DISTRIBUTION",
        "GEOMETRY",
        "MAPS",
        "DETAIL_BLEND",
        "HORIZON",
        "SUBSURFACE",
        "DEBUG_VIEW",
        "ENVIRONMENT_KIND",
        "REFLECTION_MODE",
        "SPECULAR_AA",
        "OCCLUSION",
        "OBJECT_OCCLUSION",
        "OBJECTS_OCCLUSION_FROM",
        "BOUNCE",
        "ENV_SUN",
        "ENERGY_COMPENSATION",
        "SHADOW_TAPS",
        "GROUND_SHADOWS",
        "SHADOWS",
        "HARD_SHADOWS_AT_PIXELS",
        "SOFT_SHADOWS",
        "BOUNCE_AT_VERTICES",
        "VERTEX_SHADOW_LAYERS",
        "GROUND_ENVIRONMENT",
    ];

    /// The pipeline of material `m` under `environment` in `debug_view`. Specialised, it
    /// holds only what the frame uses: a map at strength 0 changes nothing and is not
    /// sampled, the noise map only modulates the report's reflection, and the debug view,
    /// environment kind and reflection mode are constants. Generic (`specialize` false),
    /// those three come from the uniforms and every map is sampled, as the bench compares.
    /// `specular_aa` is the scene's `[antialiasing] specular`.
    pub fn new(
        m: &Material,
        environment: &Environment,
        debug_view: DebugView,
        specialize: bool,
        specular_aa: bool,
    ) -> Self {
        let models = m.shading_models();
        let maps = &m.maps;
        let reflection = environment.reflection().map(|r| r.mode);
        let sampled =
            |map: &Option<MapRef>, used: bool| map.is_some_and(|map| !specialize || (used && map.strength != 0.0));
        let specialized = |value: u32| if specialize { value } else { FROM_UNIFORM };
        let detail = sampled(&maps[MapSlot::Detail], true);
        // A normal map at strength 0 decodes to +z, which only RNM and whiteout blend a
        // detail map over as they would over no normal map.
        let flat_base_is_none = !detail || matches!(m.detail_blend, DetailBlend::Rnm | DetailBlend::Whiteout);
        let used = MapSlot::ALL.map(|slot| match slot {
            MapSlot::Normal => maps[slot].is_some_and(|n| !specialize || n.strength != 0.0 || !flat_base_is_none),
            MapSlot::Detail => detail,
            MapSlot::Noise => sampled(&maps[slot], reflection == Some(ReflectionMode::Seed)),
            MapSlot::BaseColor | MapSlot::Metallic => sampled(&maps[slot], true),
            MapSlot::Roughness => sampled(&maps[slot], models.specular != SpecularModel::None),
            // It occludes the environment's light and micro-shadows the point lights.
            MapSlot::Occlusion => sampled(&maps[slot], true),
            MapSlot::Scatter => sampled(&maps[slot], models.subsurface != Subsurface::None),
            MapSlot::Emission => sampled(&maps[slot], m.emission != glam::Vec3::ZERO),
        });
        Self {
            diffuse_model: models.diffuse as u32,
            specular_model: models.specular as u32,
            distribution: models.distribution as u32,
            geometry: models.geometry as u32,
            maps: MapSlot::ALL
                .into_iter()
                .zip(used)
                .filter(|&(_, used)| used)
                .fold(0, |bits, (slot, _)| bits | slot.bit()),
            detail_blend: m.detail_blend as u32,
            horizon: m.horizon as u32,
            subsurface: models.subsurface as u32,
            debug_view: specialized(debug_view as u32),
            environment_kind: specialized(environment_kind(environment)),
            reflection_mode: specialized(reflection.map_or(0, reflection_code)),
            specular_aa: u32::from(specular_aa),
            occlusion: 0,
            object_occlusion: 0,
            objects_occlusion_from: ObjectsOcclusionFrom::Pixels as u32,
            bounce: 0,
            sun: 0,
            energy_compensation: u32::from(m.energy_compensation || !specialize),
            shadow_taps: DEFAULT_SHADOW_TAPS,
            ground_shadows: 0,
            shadows: 1,
            hard_shadows_at_pixels: 0,
            soft_shadows: 1,
            bounce_at_vertices: 0,
            vertex_shadow_layers: 0,
            ground_environment: 0,
        }
    }

    /// Whether the pipeline samples `slot`.
    pub fn samples(&self, slot: MapSlot) -> bool {
        self.maps & slot.bit() != 0
    }

    pub fn specialization(&self) -> Specialization {
        Specialization(bytemuck::cast_slice(std::slice::from_ref(self)).to_vec())
    }

    /// The smallest build of forward.frag that holds the code these constants run.
    fn fragment_build(&self) -> FragmentBuild {
        let sampled = [reflection_code(ReflectionMode::Sampled), FROM_UNIFORM].contains(&self.reflection_mode);
        let seed_composition = self.horizon == Horizon::Seed as u32;
        if self.debug_view != DebugView::Shaded as u32 {
            FragmentBuild::DebugViews
        } else if sampled || seed_composition || self.sun != 0 {
            FragmentBuild::Shaded
        } else {
            FragmentBuild::Lean
        }
    }
}

/// The builds of forward.frag (build.rs), each leaving out code that the pipelines made
/// from it never run but whose SPIR-V each pipeline's creation would read: on lavapipe,
/// which translates a module whole at every creation, the lean build's pipelines take
/// 0.6× the time of the shaded one's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FragmentBuild {
    /// Everything: debug views, or the generic pipeline, which reads the view from the
    /// uniforms.
    DebugViews,
    /// The shaded image with any reflection mode.
    Shaded,
    /// The shaded image with a reflection of lookups (split sum, seed) or none, argil's
    /// composition of the BRDFs and no map's sun.
    Lean,
}

/// What one frame in flight owns: its uniforms, materials and the set pointing at them.
struct FrameSlot {
    frame_data: Buffer,
    materials: Buffer,
    set: vk::DescriptorSet,
    /// The set binds the pre-integrated table rather than its placeholder.
    binds_table: bool,
}

pub struct ForwardPass {
    device: Arc<Device>,
    /// Kept alive for the sets allocated with it.
    set_layout: DescriptorSetLayout,
    /// Set 1: a material's maps (material_maps.glsl); its sets belong to a `GpuScene`.
    material_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    vertex: ShaderModule,
    /// forward.frag's builds (`FragmentBuild`).
    fragment: ShaderModule,
    shaded_fragment: ShaderModule,
    lean_fragment: ShaderModule,
    pipelines: HashMap<DrawPipeline, Pipeline>,
    /// `floor.frag`'s pipeline by sample count, created the first time a frame asks for it.
    floor: HashMap<vk::SampleCountFlags, Pipeline>,
    /// The pipeline of each object of the scene last prepared, in `Scene::objects` order:
    /// its material's, specialised to where it reads the other objects' occlusion.
    object_pipelines: Vec<vk::Pipeline>,
    /// The same for the right part of a split frame (split.rs); empty without one.
    split_pipelines: Vec<vk::Pipeline>,
    /// The G-buffer and shading draws' pipelines of each object the frame defers
    /// (deferred.rs), in `Scene::objects` order; None for the objects it draws forward.
    deferred_pipelines: Vec<Option<(vk::Pipeline, vk::Pipeline)>>,
    deferred: DeferredPass,
    /// The forward sets and the G-buffer's (set 6): the deferred shading draws'.
    deferred_layout: PipelineLayout,
    /// forward.frag's builds for the deferred pass: the surfaces', and the shading's, whole
    /// and lean (`FragmentBuild`).
    gbuffer_fragment: ShaderModule,
    deferred_fragment: ShaderModule,
    deferred_lean_fragment: ShaderModule,
    /// What each object's draw reads besides its object, in `Scene::objects` order, for the
    /// scene last prepared.
    object_draws: Vec<ObjectDraw>,
    /// Owns the slots' sets.
    _pool: DescriptorPool,
    slots: Vec<FrameSlot>,
    /// The frame data the last [`Self::prepare`] wrote.
    frame_data: FrameData,
    /// The pre-integrated subsurface table, once a scene's material has needed it; until
    /// then `placeholder` fills its binding.
    subsurface: Option<SubsurfaceTable>,
    placeholder: SubsurfaceTable,
    /// Wall time spent creating pipelines, for the startup's account.
    pub pipeline_time: Duration,
}

impl ForwardPass {
    pub fn new(
        device: &Arc<Device>,
        one_shot: &OneShot,
        frames_in_flight: u32,
        environment_layout: &DescriptorSetLayout,
        shadow_layout: &DescriptorSetLayout,
        occlusion_layout: &DescriptorSetLayout,
        ground_maps_layout: &DescriptorSetLayout,
    ) -> Result<Self> {
        // The ground's maps are computed from the frame data too, its environment map from
        // its material with the split sum's code, which holds the subsurface table's
        // reads (ground_maps.rs).
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(
                vk::DescriptorType::UNIFORM_BUFFER,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE,
            )
            .binding(
                vk::DescriptorType::STORAGE_BUFFER,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE,
            )
            .binding(
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE,
            )
            .build(device, "forward set")?;
        let placeholder = SubsurfaceTable::placeholder(device, one_shot)?;
        let material_layout = (0..MAP_COUNT)
            .fold(DescriptorSetLayoutBuilder::default(), |b, _| {
                b.binding(
                    vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    vk::ShaderStageFlags::FRAGMENT,
                )
            })
            .build(device, "material maps set")?;
        let sets = [
            &set_layout,
            &material_layout,
            environment_layout,
            shadow_layout,
            occlusion_layout,
            ground_maps_layout,
        ];
        let push = std::mem::size_of::<ObjectPush>() as u32;
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let layout = PipelineLayout::new(device, &sets, push, stages)?;
        let deferred = DeferredPass::new(device, frames_in_flight)?;
        let deferred_sets: Vec<&DescriptorSetLayout> =
            sets.iter().copied().chain(std::iter::once(deferred.g_layout())).collect();
        let deferred_layout = PipelineLayout::new(device, &deferred_sets, push, stages)?;
        let vertex = ShaderModule::new(device, shaders::FORWARD_VERT, "forward.vert")?;
        let fragment = ShaderModule::new(device, shaders::FORWARD_FRAG, "forward.frag")?;
        let shaded_fragment = ShaderModule::new(device, shaders::FORWARD_SHADED_FRAG, "forward_shaded.frag")?;
        let lean_fragment = ShaderModule::new(device, shaders::FORWARD_LEAN_FRAG, "forward_lean.frag")?;
        let gbuffer_fragment = ShaderModule::new(device, shaders::FORWARD_GBUFFER_FRAG, "forward_gbuffer.frag")?;
        let deferred_fragment = ShaderModule::new(device, shaders::FORWARD_DEFERRED_FRAG, "forward_deferred.frag")?;
        let deferred_lean_fragment =
            ShaderModule::new(device, shaders::FORWARD_DEFERRED_LEAN_FRAG, "forward_deferred_lean.frag")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, frames_in_flight)?;
        let slots = (0..frames_in_flight)
            .map(|_| {
                let frame_data = Buffer::new(
                    device,
                    std::mem::size_of::<FrameData>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                    MemoryLocation::CpuToGpu,
                    "frame data",
                )?;
                let materials = Self::material_buffer(device, 1)?;
                let set = pool.allocate(&set_layout)?;
                Self::write_set(device, set, &frame_data, &materials, &placeholder);
                Ok(FrameSlot {
                    frame_data,
                    materials,
                    set,
                    binds_table: false,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            device: device.clone(),
            set_layout,
            material_layout,
            layout,
            vertex,
            fragment,
            shaded_fragment,
            lean_fragment,
            pipelines: HashMap::new(),
            floor: HashMap::new(),
            object_pipelines: Vec::new(),
            split_pipelines: Vec::new(),
            deferred_pipelines: Vec::new(),
            deferred,
            deferred_layout,
            gbuffer_fragment,
            deferred_fragment,
            deferred_lean_fragment,
            object_draws: Vec::new(),
            _pool: pool,
            slots,
            frame_data: bytemuck::Zeroable::zeroed(),
            subsurface: None,
            placeholder,
            pipeline_time: Duration::ZERO,
        })
    }

    /// The layout of set 0: the frame's data, materials and subsurface table.
    pub fn frame_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// Per object of the scene last prepared, where its draw reads its occlusion by the
    /// other objects from and which occluders are its own.
    pub fn object_occlusions(&self) -> Vec<ObjectOcclusion> {
        self.object_draws.iter().map(|draw| draw.occlusion).collect()
    }

    /// The frame data of set 0, as the last [`Self::prepare`] wrote it.
    pub fn frame_data(&self) -> &FrameData {
        &self.frame_data
    }

    /// Set 0 of `slot`.
    pub fn frame_set(&self, slot: usize) -> vk::DescriptorSet {
        self.slots[slot].set
    }

    /// The layout of set 1, for the scene's material sets.
    pub fn material_layout(&self) -> &DescriptorSetLayout {
        &self.material_layout
    }

    fn material_buffer(device: &Arc<Device>, count: usize) -> Result<Buffer> {
        Buffer::new(
            device,
            (count.max(1) * std::mem::size_of::<MaterialData>()) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
            "materials",
        )
    }

    fn write_set(
        device: &Device,
        set: vk::DescriptorSet,
        frame_data: &Buffer,
        materials: &Buffer,
        subsurface: &SubsurfaceTable,
    ) {
        let writer = DescriptorWriter::default()
            .buffer(0, vk::DescriptorType::UNIFORM_BUFFER, frame_data.handle)
            .buffer(1, vk::DescriptorType::STORAGE_BUFFER, materials.handle);
        subsurface.bind(writer).write(device, set);
    }

    /// The pipelines of `draws`, in their order. Those not made yet are created side by
    /// side, one per thread of the current pool (rayon's): a software device (lavapipe)
    /// compiles each on the calling thread, and the frame waits for all of them.
    fn pipelines_for(&mut self, draws: &[DrawPipeline]) -> Result<Vec<vk::Pipeline>> {
        let mut missing: Vec<&DrawPipeline> = Vec::new();
        for draw in draws {
            if !self.pipelines.contains_key(draw) && !missing.contains(&draw) {
                missing.push(draw);
            }
        }
        if !missing.is_empty() {
            let start = Instant::now();
            let built = missing.par_iter().map(|draw| self.build_draw_pipeline(draw)).collect::<Result<Vec<_>>>()?;
            self.pipeline_time += start.elapsed();
            for (draw, pipeline) in missing.into_iter().zip(built) {
                self.pipelines.insert(*draw, pipeline);
            }
        }
        Ok(draws.iter().map(|draw| self.pipelines[draw].handle).collect())
    }

    fn build_draw_pipeline(&self, draw: &DrawPipeline) -> Result<Pipeline> {
        match *draw {
            DrawPipeline::Forward(samples, c) => {
                let specialization = c.specialization();
                let name = format!("forward {samples:?} {:?}", specialization.0);
                let fragment = match c.fragment_build() {
                    FragmentBuild::DebugViews => &self.fragment,
                    FragmentBuild::Shaded => &self.shaded_fragment,
                    FragmentBuild::Lean => &self.lean_fragment,
                };
                self.build_pipeline(fragment, samples, &specialization, &name)
            }
            DrawPipeline::Surfaces(c) => self
                .mesh_pipeline(&self.gbuffer_fragment)
                .color_formats(&[HDR_FORMAT; G_ATTACHMENTS])
                .specialization(c.specialization())
                .build(&self.device, &self.layout, "surfaces"),
            DrawPipeline::Shading(c) => {
                let fragment = match c.fragment_build() {
                    FragmentBuild::Lean => &self.deferred_lean_fragment,
                    FragmentBuild::Shaded | FragmentBuild::DebugViews => &self.deferred_fragment,
                };
                GraphicsPipelineBuilder::new(self.deferred.vertex(), fragment, HDR_FORMAT)
                    .depth_test_only(DEPTH_FORMAT, vk::CompareOp::EQUAL)
                    .specialization(c.specialization())
                    .build(&self.device, &self.deferred_layout, "deferred shading")
            }
        }
    }

    fn floor_pipeline(&mut self, samples: vk::SampleCountFlags) -> Result<vk::Pipeline> {
        if let Some(p) = self.floor.get(&samples) {
            return Ok(p.handle);
        }
        // The module may go once the pipeline exists.
        let fragment = ShaderModule::new(&self.device, shaders::FLOOR_FRAG, "floor.frag")?;
        let pipeline = self.build_pipeline(&fragment, samples, &Specialization::default(), "forward floor")?;
        Ok(self.floor.entry(samples).or_insert(pipeline).handle)
    }

    fn build_pipeline(
        &self,
        fragment: &ShaderModule,
        samples: vk::SampleCountFlags,
        specialization: &Specialization,
        name: &str,
    ) -> Result<Pipeline> {
        self.mesh_pipeline(fragment)
            .samples(samples)
            .specialization(specialization.clone())
            .build(&self.device, &self.layout, name)
    }

    /// A pipeline of forward.vert and `fragment` drawing the meshes, depth tested.
    fn mesh_pipeline<'a>(&'a self, fragment: &'a ShaderModule) -> GraphicsPipelineBuilder<'a> {
        let stride = std::mem::size_of::<Vertex>() as u32;
        // Locations 0..=4, as forward.vert declares them.
        GraphicsPipelineBuilder::new(&self.vertex, fragment, HDR_FORMAT)
            .vertex_layout(
                stride,
                &[
                    (vk::Format::R32G32B32_SFLOAT, offset_of!(Vertex, position) as u32),
                    (vk::Format::R32G32B32_SFLOAT, offset_of!(Vertex, normal) as u32),
                    (vk::Format::R32G32_SFLOAT, offset_of!(Vertex, uv) as u32),
                    (vk::Format::R32G32B32A32_SFLOAT, offset_of!(Vertex, tangent) as u32),
                    (vk::Format::R32_SFLOAT, offset_of!(Vertex, curvature) as u32),
                ],
            )
            .depth(DEPTH_FORMAT)
            .dynamic_cull_mode()
    }

    /// Creates what the draws of `scene`'s materials need (and a `split` frame's right
    /// part's, with pipelines of their own): a pipeline per draw as `choices` specialise it
    /// (or the floor's), and the pre-integrated subsurface table if a material reads it.
    /// `occluders` (`Scene::occluders`) are the spheres whose occlusion the objects read
    /// when `choices.objects`, and `gpu`'s meshes say whether an object reads them at its
    /// vertices (`Scene::occlusion_at_vertices`); the draw of object i holds shadow code
    /// where a light may shadow it, and runs it for the lights `shadowing[i]` (bit i for
    /// light i, `ShadowPass::receivers`). Uses no frame slot, so it may run
    /// while frames are in flight, or beside the environment's precompute (renderer.rs).
    #[allow(clippy::too_many_arguments)]
    pub fn prepare_pipelines(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        split: Option<&Split>,
        occluders: &[Occluder],
        shadowing: &[u32],
        choices: &FrameChoices,
        one_shot: &OneShot,
    ) -> Result<()> {
        let at_vertices = |i: usize| {
            choices.objects && scene.occlusion_at_vertices(occluders, i, gpu.meshes[scene.objects[i].mesh].extent)
        };
        let occlusions: Vec<ObjectOcclusion> = (0..scene.objects.len())
            .map(|i| ObjectOcclusion {
                own: scene.own_occluders(occluders, i),
                from: if choices.ground_map == Some(i) {
                    ObjectsOcclusionFrom::GroundMap
                } else if at_vertices(i) {
                    ObjectsOcclusionFrom::Vertices
                } else {
                    ObjectsOcclusionFrom::Pixels
                },
            })
            .collect();
        let from: Vec<ObjectsOcclusionFrom> = occlusions.iter().map(|o| o.from).collect();
        let generic = !choices.specialize;
        let vertex_light_firsts = gpu_vertex_light_firsts(scene, generic, shadowing, &from, gpu);
        self.object_draws = (occlusions.iter().zip(shadowing).zip(vertex_light_firsts))
            .map(|((&occlusion, &shadowing_lights), vertex_light_first)| ObjectDraw {
                occlusion,
                shadowing_lights,
                vertex_light_first,
            })
            .collect();
        let parts = 1 + usize::from(split.is_some());
        self.deferred_pipelines = vec![None; scene.objects.len()];
        let pipelines = if choices.floor {
            vec![self.floor_pipeline(choices.samples)?; parts * scene.objects.len()]
        } else {
            let at_vertices: Vec<bool> = (scene.objects.iter().enumerate())
                .map(|(i, o)| light_at_vertices(scene, generic, shadowing[i], i, gpu.meshes[o.mesh].extent))
                .collect();
            let constants = draw_constants(scene, split, &from, shadowing, &at_vertices, choices);
            let deferred: Vec<bool> = (constants.iter().enumerate())
                .map(|(i, c)| {
                    let fine = scene.objects.get(i).is_some_and(|o| fine_solid(scene, gpu, o, choices.extent));
                    choices.deferred && split.is_none() && fine && deferrable(c)
                })
                .collect();
            // A deferred object's two pipelines follow the others, in its order.
            let mut draws: Vec<DrawPipeline> = (constants.iter().zip(&deferred))
                .map(|(&c, &deferred)| {
                    if deferred {
                        DrawPipeline::Shading(c)
                    } else {
                        DrawPipeline::Forward(choices.samples, c)
                    }
                })
                .collect();
            let deferred_objects: Vec<usize> = (0..deferred.len()).filter(|&i| deferred[i]).collect();
            draws.extend(deferred_objects.iter().map(|&i| DrawPipeline::Surfaces(constants[i])));
            let mut pipelines = self.pipelines_for(&draws)?;
            let surfaces = pipelines.split_off(constants.len());
            for (&i, surfaces) in deferred_objects.iter().zip(surfaces) {
                self.deferred_pipelines[i] = Some((surfaces, pipelines[i]));
            }
            pipelines
        };
        // The objects with the scene's materials, then with the split's.
        let (scene_pipelines, split_pipelines) = pipelines.split_at(scene.objects.len());
        (self.object_pipelines, self.split_pipelines) = (scene_pipelines.to_vec(), split_pipelines.to_vec());
        let split_materials = split.map_or(&[][..], |s| s.materials.as_slice());
        let preintegrated = |m: &Material| m.subsurface == Subsurface::PreIntegrated;
        let needs_table = scene.needs_preintegrated_table() || split_materials.iter().any(preintegrated);
        if needs_table && self.subsurface.is_none() {
            self.subsurface = Some(SubsurfaceTable::upload(&self.device, one_shot)?);
        }
        Ok(())
    }

    /// Writes this frame's uniforms (with the `sampled` reflection's `sample_set`) and
    /// materials (a `split` frame's follow the scene's) into `slot`, whose previous use the
    /// caller has waited for, after [`Self::prepare_pipelines`] of the same `choices`.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        slot: usize,
        scene: &Scene,
        split: Option<&Split>,
        aspect: f32,
        sample_set: u32,
        occluders: &[Occluder],
        choices: &FrameChoices,
    ) -> Result<()> {
        let mut frame_data = FrameData::new(scene, occluders, aspect)?;
        if !choices.objects {
            frame_data.counts[3] = 0;
        }
        frame_data.counts[1] = choices.debug_view as u32;
        frame_data.counts[2] = sample_set;
        let split_materials = split.map_or(&[][..], |s| s.materials.as_slice());
        let materials: Vec<MaterialData> = scene
            .materials
            .iter()
            .chain(split_materials)
            .map(MaterialData::from)
            .collect();
        self.frame_data = frame_data;
        let s = &mut self.slots[slot];
        s.frame_data.write(bytemuck::bytes_of(&frame_data))?;
        let bytes: &[u8] = bytemuck::cast_slice(&materials);
        let grow = bytes.len() as u64 > s.materials.size;
        if grow {
            s.materials = Self::material_buffer(&self.device, materials.len())?;
        }
        // Only this slot's set is rewritten: the other slots' frames may still be running.
        if grow || s.binds_table != self.subsurface.is_some() {
            let table = self.subsurface.as_ref().unwrap_or(&self.placeholder);
            Self::write_set(&self.device, s.set, &s.frame_data, &s.materials, table);
            s.binds_table = self.subsurface.is_some();
        }
        s.materials.write(bytes)
    }

    /// How many objects the last prepared frame shades from the G-buffer.
    pub fn deferred_objects(&self) -> usize {
        self.deferred_pipelines.iter().flatten().count()
    }

    /// How many pipelines draw the deferred objects' surfaces: one for the objects of the
    /// same constants, whose draws' instances tell them apart.
    pub fn deferred_surface_pipelines(&self) -> usize {
        let surfaces: std::collections::HashSet<vk::Pipeline> =
            self.deferred_pipelines.iter().flatten().map(|&(surfaces, _)| surfaces).collect();
        surfaces.len()
    }

    /// Makes `slot`'s G-buffer for a frame of `extent` if the last prepared frame defers
    /// objects, or lets it go; its previous frame is done.
    pub fn prepare_deferred(&mut self, slot: usize, extent: vk::Extent2D) -> Result<()> {
        let deferring = self.deferred_objects() > 0;
        self.deferred.prepare(slot, deferring.then_some(extent))
    }

    /// Records the pass into `target`, of the sample count `prepare` had. Its colour and
    /// depth must be in attachment layouts; its depth is kept for the skybox. With the
    /// `split` that `prepare` had, each part of the target is drawn with its own pipelines.
    /// The objects it defers are drawn first, into the G-buffer, and shaded from it.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        scene: &Scene,
        split: Option<&Split>,
        gpu: &GpuScene,
        target: DrawTarget,
        clear: [f32; 4],
        environment_set: vk::DescriptorSet,
        shadow_set: vk::DescriptorSet,
        occlusion_set: vk::DescriptorSet,
        ground_maps_set: vk::DescriptorSet,
    ) -> Result<()> {
        let d = &self.device.handle;
        let aspect = target.extent().width as f32 / target.extent().height as f32;
        let order = draw_order(scene, |mesh| gpu.meshes[mesh].solid, aspect);
        let deferred = |index: usize| self.deferred_pipelines.get(index).copied().flatten();
        let shared_sets = [environment_set, shadow_set, occlusion_set, ground_maps_set];
        let bind_sets = |layout: &PipelineLayout, g_set: Option<vk::DescriptorSet>| unsafe {
            let graphics = vk::PipelineBindPoint::GRAPHICS;
            d.cmd_bind_descriptor_sets(cmd, graphics, layout.handle, 0, &[self.slots[slot].set], &[]);
            d.cmd_bind_descriptor_sets(cmd, graphics, layout.handle, 2, &shared_sets, &[]);
            if let Some(set) = g_set {
                d.cmd_bind_descriptor_sets(cmd, graphics, layout.handle, 6, &[set], &[]);
            }
        };
        // prepare_pipelines defers nothing in a split frame.
        let deferring = self.deferred_objects() > 0;
        if deferring {
            self.deferred.begin_surfaces(cmd, slot, target.depth)?;
            bind_sets(&self.layout, None);
            let mut bound = vk::Pipeline::null();
            for &(index, cull) in &order {
                let Some((surfaces, _)) = deferred(index) else { continue };
                self.draw_object(cmd, scene, gpu, (index, deferred_object(index)), cull, surfaces, 0, &mut bound)?;
            }
            // Each solid's light is drawn over the pixels it may cover, which lavapipe would
            // otherwise visit over the whole frame, to find the depth test fail.
            let shaded: Vec<(usize, vk::Pipeline, vk::Rect2D)> = order
                .iter()
                .filter_map(|&(index, _)| deferred(index).map(|(_, shading)| (index, shading)))
                .map(|(index, shading)| (index, shading, object_pixels(scene, gpu, index, target.extent())))
                .filter(|(_, _, rect)| rect.extent.width > 0 && rect.extent.height > 0)
                .collect();
            let rects: Vec<vk::Rect2D> = shaded.iter().map(|&(_, _, rect)| rect).collect();
            self.deferred.begin_shading(cmd, slot, &rects, target.color, clear)?;
            bind_sets(&self.deferred_layout, Some(self.deferred.g_set(slot)));
            for &(index, shading, rect) in &shaded {
                let push = self.object_push(&scene.objects[index], index, 0)?;
                unsafe {
                    d.cmd_set_scissor(cmd, 0, &[rect]);
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, shading);
                    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
                    d.cmd_push_constants(cmd, self.deferred_layout.handle, stages, 0, bytemuck::bytes_of(&push));
                    // The instance is the object's depth in the objects' image.
                    d.cmd_draw(cmd, 3, 1, 0, deferred_object(index));
                }
            }
            unsafe { d.cmd_end_rendering(cmd) };
            // The forward draws load what the shading wrote and test the solids' depth.
            let (color, depth, device) = (target.color, target.depth, &self.device);
            let (color_use, depth_use) = (ImageUse::COLOR_ATTACHMENT, ImageUse::DEPTH_ATTACHMENT);
            transition(device, cmd, color.handle, color.aspect, color_use, color_use);
            transition(device, cmd, depth.handle, depth.aspect, depth_use, depth_use);
        }
        let load = if deferring { vk::AttachmentLoadOp::LOAD } else { vk::AttachmentLoadOp::CLEAR };
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(target.color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            })];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(target.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            });
        begin_full_rendering(&self.device, cmd, target.extent(), &color, Some(&depth));
        bind_sets(&self.layout, None);
        let forward = |index: usize| deferred(index).is_none();
        match split {
            None => self.draw_objects(cmd, scene, gpu, &order, forward, &self.object_pipelines, 0)?,
            Some(split) => {
                let [left, right] = split.scissors(target.extent());
                let parts = [
                    (left, &self.object_pipelines, 0),
                    (right, &self.split_pipelines, scene.materials.len()),
                ];
                for (scissor, pipelines, first_material) in parts {
                    unsafe { d.cmd_set_scissor(cmd, 0, &[scissor]) };
                    self.draw_objects(cmd, scene, gpu, &order, forward, pipelines, first_material)?;
                }
            }
        }
        unsafe { d.cmd_end_rendering(cmd) };
        Ok(())
    }

    /// Draws the objects of `order` that `drawn` accepts with `pipelines` (one per object),
    /// reading its material at `first_material` + its index in the materials buffer.
    #[allow(clippy::too_many_arguments)]
    fn draw_objects(
        &self,
        cmd: vk::CommandBuffer,
        scene: &Scene,
        gpu: &GpuScene,
        order: &[(usize, vk::CullModeFlags)],
        drawn: impl Fn(usize) -> bool,
        pipelines: &[vk::Pipeline],
        first_material: usize,
    ) -> Result<()> {
        let mut bound = vk::Pipeline::null();
        for &(index, cull) in order.iter().filter(|(index, _)| drawn(*index)) {
            let pipeline = *pipelines
                .get(index)
                .context("forward pipeline missing: prepare() was not called for this scene")?;
            self.draw_object(cmd, scene, gpu, (index, 0), cull, pipeline, first_material, &mut bound)?;
        }
        Ok(())
    }

    /// Object `index`'s push constants, its material at `first_material` + its index.
    fn object_push(&self, object: &crate::scene::Object, index: usize, first_material: usize) -> Result<ObjectPush> {
        let draw = *self
            .object_draws
            .get(index)
            .context("object missing: prepare() was not called for this scene")?;
        let vertex_light_first = draw.vertex_light_first.unwrap_or(0);
        let mut push = ObjectPush::new(object, draw.occlusion, draw.shadowing_lights, vertex_light_first);
        push.material_index += first_material as u32;
        Ok(push)
    }

    /// Draws object `index` as instance `instance` (forward.vert's deferred object) with
    /// `pipeline` (bound unless it is `bound`), culling `cull`.
    #[allow(clippy::too_many_arguments)]
    fn draw_object(
        &self,
        cmd: vk::CommandBuffer,
        scene: &Scene,
        gpu: &GpuScene,
        (index, instance): (usize, u32),
        cull: vk::CullModeFlags,
        pipeline: vk::Pipeline,
        first_material: usize,
        bound: &mut vk::Pipeline,
    ) -> Result<()> {
        let d = &self.device.handle;
        let object = &scene.objects[index];
        let mesh = &gpu.meshes[object.mesh];
        let push = self.object_push(object, index, first_material)?;
        unsafe {
            if pipeline != *bound {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                *bound = pipeline;
            }
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.handle,
                1,
                &[gpu.material_sets[object.material]],
                &[],
            );
            d.cmd_push_constants(
                cmd,
                self.layout.handle,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_set_cull_mode(cmd, cull);
            d.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.handle], &[0]);
            d.cmd_bind_index_buffer(cmd, mesh.indices.handle, 0, vk::IndexType::UINT32);
            d.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, instance);
        }
        Ok(())
    }
}

/// The order the forward pass draws `scene`'s objects in, each with its cull mode: first the
/// solids seen from outside (their back faces culled: no front face of theirs covers a pixel
/// twice), nearest first, then the other meshes in the scene's order. Grounds and backdrops
/// are open meshes, so the depth test rejects what the solids hide of them before it is
/// shaded (drawn first, the default scene's ground costs 10% more shading). Only objects
/// at exactly equal depth could show otherwise than in the scene's order. `solid(mesh)`:
/// the bounding sphere of mesh `mesh` where it bounds a solid (`GpuMesh::solid`).
fn draw_order(
    scene: &Scene,
    solid: impl Fn(usize) -> Option<(Vec3, f32)>,
    aspect: f32,
) -> Vec<(usize, vk::CullModeFlags)> {
    let mut order: Vec<(usize, Option<f32>)> = scene
        .objects
        .iter()
        .enumerate()
        .map(|(index, object)| {
            let distance = solid(object.mesh).and_then(|(centre, radius)| {
                let centre = object.position + centre * object.scale;
                let outside = scene.camera.sees_from_outside(aspect, centre, radius * object.scale);
                outside.then(|| centre.distance(scene.camera.position))
            });
            (index, distance)
        })
        .collect();
    // Stable: the other meshes keep the scene's order.
    order.sort_by(|(_, a), (_, b)| match (a, b) {
        (Some(a), Some(b)) => a.total_cmp(b),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    order
        .into_iter()
        .map(|(index, distance)| {
            let cull = if distance.is_some() {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            };
            (index, cull)
        })
        .collect()
}

/// What a frame decides for the pipelines of all its draws ([`ForwardPass::prepare_pipelines`]).
#[derive(Clone, Copy)]
pub struct FrameChoices {
    pub debug_view: DebugView,
    /// Every object drawn with `floor.frag` instead of its material.
    pub floor: bool,
    /// Specialised to the frame, or generic (see [`ForwardConstants::new`]).
    pub specialize: bool,
    pub samples: vk::SampleCountFlags,
    /// How the environment's light is occluded.
    pub occlusion: OcclusionMode,
    /// Whether the objects read the other objects' occlusion.
    pub objects: bool,
    /// The object that reads theirs from the ground's occlusion map (ground_maps.rs).
    pub ground_map: Option<usize>,
    /// The object that reads its shadows from the ground's shadow map (ground_maps.rs).
    pub ground_shadows: Option<usize>,
    /// The object that reads its environment light from the ground's environment map
    /// (ground_maps.rs).
    pub ground_environment: Option<usize>,
    /// Whether the environment's map has a sun lifted out of it (environment.rs).
    pub sun: bool,
    /// Whether the solids are shaded once a pixel from their surfaces (deferred.rs): a
    /// single-sampled frame of the shaded image in specialised pipelines, not split.
    pub deferred: bool,
    /// The frame's size, which tells how many pixels a solid's triangles cover.
    pub extent: vk::Extent2D,
}

impl FrameChoices {
    /// The choices with the environment's sun, whose lobe is too narrow for the ground's
    /// environment map to hold.
    pub fn with_sun(self, sun: bool) -> Self {
        Self {
            sun,
            ground_environment: self.ground_environment.filter(|_| !sun),
            ..self
        }
    }
}

/// Below this many pixels a triangle, by [`fine_solid`]'s estimate, a solid is shaded from
/// the G-buffer. The G-buffer's images cost memory traffic in proportion to the pixels,
/// the repeated shading it saves falls as the triangles grow: the default scene's ball and
/// ring (about 63 and 74 pixels a triangle by the estimate at 1920×1080, 111 and 131 at
/// 2560×1440) took 6% less CPU time a frame deferred at 1920×1080, 3% more at 2560×1440
/// (`argil render --accumulate`, docs/performance.md).
const DEFERRED_MAX_PIXELS_PER_TRIANGLE: f32 = 96.0;

/// Whether `object` is a solid whose triangles are small in a frame of `extent`: its
/// bounding sphere's outline over half its triangles (those facing the eye) is below
/// [`DEFERRED_MAX_PIXELS_PER_TRIANGLE`].
fn fine_solid(scene: &Scene, gpu: &GpuScene, object: &crate::scene::Object, extent: vk::Extent2D) -> bool {
    let mesh = &gpu.meshes[object.mesh];
    if mesh.solid.is_none() {
        return false;
    }
    let e = object.world_extent(&mesh.extent);
    let pixels = scene.camera.sphere_pixels(extent.height, e.centre, e.radius);
    let facing = (mesh.index_count / 3) as f32 / 2.0;
    pixels < DEFERRED_MAX_PIXELS_PER_TRIANGLE * facing
}

/// The pixels of a frame of `extent` that object `index` may cover: those that both its
/// bounding sphere and its bounding box may (`Camera::sphere_pixel_bounds`,
/// `Camera::box_pixel_bounds`), the tighter each for a round and a flat mesh.
fn object_pixels(scene: &Scene, gpu: &GpuScene, index: usize, extent: vk::Extent2D) -> vk::Rect2D {
    let object = &scene.objects[index];
    let e = object.world_extent(&gpu.meshes[object.mesh].extent);
    let camera = &scene.camera;
    let sphere = camera.sphere_pixel_bounds(extent.width, extent.height, e.centre, e.radius);
    let aabb = camera.box_pixel_bounds(extent.width, extent.height, e.low, e.high);
    let (min, max) = (sphere.0.max(aabb.0), sphere.1.min(aabb.1));
    let max = max.max(min);
    vk::Rect2D {
        offset: vk::Offset2D { x: min.x as i32, y: min.y as i32 },
        extent: vk::Extent2D { width: max.x - min.x, height: max.y - min.y },
    }
}

/// Whether a draw of these constants can be deferred: the G-buffer holds neither the
/// soft lights' shadows at the vertices nor a scatter map's change to the material.
fn deferrable(c: &ForwardConstants) -> bool {
    c.vertex_shadow_layers == 0 && !c.samples(MapSlot::Scatter)
}

const _: () = assert!(MAX_OBJECTS < 1 << 16, "deferred.glsl's object depths stay within [0, 1]");

/// Object `index`'s number in the deferred pass: the instance of its draws into the
/// G-buffer and of its shading draw (deferred.glsl's object depth), 0 being no object.
fn deferred_object(index: usize) -> u32 {
    index as u32 + 1
}

/// A pipeline of the pass: an object's forward draw into targets of a sample count, a
/// deferred object's draw of its surfaces into the G-buffer, or its shading draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum DrawPipeline {
    Forward(vk::SampleCountFlags, ForwardConstants),
    Surfaces(ForwardConstants),
    Shading(ForwardConstants),
}

/// What an object's draw reads besides its object: how it reads the other objects'
/// occlusion, and the lights that may shadow it, bit i for light i.
#[derive(Clone, Copy)]
struct ObjectDraw {
    occlusion: ObjectOcclusion,
    shadowing_lights: u32,
    /// Its first vertex in what the draws read at their vertices, where it reads there.
    vertex_light_first: Option<u32>,
}

/// The constants of each draw: `scene`'s objects, then the same with `split`'s materials,
/// object i reading the other objects' occlusion from `from[i]`, holding shadow code
/// where a light may shadow it (`shadowing[i]`, `ShadowPass::receivers`), and reading the
/// bounce and the soft lights' shadows at its vertices where `at_vertices[i]`
/// (vertex_light.rs).
fn draw_constants(
    scene: &Scene,
    split: Option<&Split>,
    from: &[ObjectsOcclusionFrom],
    shadowing: &[u32],
    at_vertices: &[bool],
    choices: &FrameChoices,
) -> Vec<ForwardConstants> {
    let bounces = scene.bounce && scene.ground().is_some();
    let hard_shadows = ground_maps::hard_shadows(scene);
    let generic = !choices.specialize;
    // The ground lies at its own height, where the gather finds nothing to bounce.
    let ground = scene.ground_index();
    // What a specialised pipeline holds only when the frame uses it; the generic one
    // always holds it and reads the frame's uniforms.
    let held = |used: bool| u32::from(used || !choices.specialize);
    let soft_lights = scene.soft_lights();
    let split_parts = split.map(|s| (s.materials.as_slice(), &s.environment));
    std::iter::once((scene.materials.as_slice(), &scene.environment))
        .chain(split_parts)
        .flat_map(|(materials, environment)| {
            let draws = scene.objects.iter().zip(from).enumerate();
            draws.map(move |(i, (object, &from))| (&materials[object.material], environment, from, i))
        })
        .map(|(m, environment, from, i)| {
            let is_ground = ground == Some(i);
            let (view, specialize, specular_aa) = (choices.debug_view, choices.specialize, scene.antialiasing.specular);
            let mut constants = ForwardConstants::new(m, environment, view, specialize, specular_aa);
            constants.occlusion = choices.occlusion as u32;
            constants.object_occlusion = u32::from(choices.objects);
            constants.objects_occlusion_from = from as u32;
            constants.bounce = held(bounces && !is_ground);
            constants.bounce_at_vertices = u32::from(at_vertices[i]);
            constants.sun = held(choices.sun);
            constants.shadow_taps = scene.shadow_taps;
            let ground_shadows = choices.ground_shadows == Some(i);
            constants.ground_shadows = u32::from(ground_shadows);
            constants.ground_environment = u32::from(choices.ground_environment == Some(i));
            let at_vertices = if at_vertices[i] { vertex_shadowing(scene, generic, shadowing[i]) } else { 0 };
            constants.vertex_shadow_layers = vertex_shadow_layers(at_vertices);
            // Beside the shadows it reads elsewhere, a hard light's it looks up at its pixels.
            let hard = shadowing[i] & !soft_lights != 0;
            let hard_at_pixels = if ground_shadows { hard_shadows } else { at_vertices != 0 && hard };
            constants.hard_shadows_at_pixels = u32::from(hard_at_pixels);
            constants.shadows = held(shadowing[i] != 0);
            constants.soft_shadows = held(shadowing[i] & soft_lights != 0);
            constants
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `layout(constant_id = N) const TYPE NAME` of the forward pass's shaders.
    fn shader_constants() -> Vec<(u32, String)> {
        let sources = [
            include_str!("../../shaders/forward.frag"),
            include_str!("../../shaders/lib/material_maps.glsl"),
            include_str!("../../shaders/lib/environment.glsl"),
            include_str!("../../shaders/lib/occlusion_map.glsl"),
            include_str!("../../shaders/lib/object_occlusion.glsl"),
            include_str!("../../shaders/lib/bounce.glsl"),
            include_str!("../../shaders/lib/vertex_light.glsl"),
            include_str!("../../shaders/lib/shadows.glsl"),
            include_str!("../../shaders/lib/ground_shadow.glsl"),
            include_str!("../../shaders/lib/ground_environment.glsl"),
            include_str!("../../shaders/lib/lights.glsl"),
        ];
        sources
            .iter()
            .flat_map(|s| s.lines())
            .filter_map(|line| {
                let rest = line.trim().strip_prefix("layout(constant_id = ")?;
                let (id, declaration) = rest.split_once(')')?;
                let name = declaration.split_whitespace().nth(2)?;
                Some((id.parse().ok()?, name.to_owned()))
            })
            .collect()
    }

    #[test]
    fn constants_match_the_shaders_ids_and_names() {
        let mut found = shader_constants();
        found.sort();
        let expected: Vec<(u32, String)> = (ForwardConstants::NAMES.iter())
            .enumerate()
            .map(|(i, name)| (i as u32, (*name).to_owned()))
            .collect();
        assert_eq!(found, expected);
        assert_eq!(
            std::mem::size_of::<ForwardConstants>(),
            4 * ForwardConstants::NAMES.len()
        );
        let glsl = include_str!("../../shaders/lib/specialization.glsl");
        assert!(glsl.contains(&format!("FROM_UNIFORM = 0x{FROM_UNIFORM:X}u;")));
        let glsl = include_str!("../../shaders/lib/shadows.glsl");
        assert!(glsl.contains(&format!("const uint SHADOW_TAPS = {DEFAULT_SHADOW_TAPS}u;")));
        let glsl = include_str!("../../shaders/lib/occlusion_map.glsl");
        for (mode, name) in [
            (OcclusionMode::Off, "OCCLUSION_OFF"),
            (OcclusionMode::MultiBounce, "OCCLUSION_MULTI_BOUNCE"),
            (OcclusionMode::Plain, "OCCLUSION_PLAIN"),
        ] {
            assert!(
                glsl.contains(&format!("const uint {name} = {}u;", mode as u32)),
                "{name}"
            );
        }
    }

    /// The default scene's plasticine (normal, detail and noise maps) with a base colour
    /// map and the property maps too, every map at `strength`.
    fn mapped_material(strength: f32) -> Material {
        let scene = Scene::from_toml(crate::scene::DEFAULT_SCENE_TOML, "default", std::path::Path::new(""))
            .expect("the default scene");
        let mut m = scene
            .materials
            .into_iter()
            .find(|m| m.maps[MapSlot::Noise].is_some())
            .expect("plasticine");
        m.maps[MapSlot::BaseColor] = m.maps[MapSlot::Normal];
        let noise = m.maps[MapSlot::Noise];
        for (_, map) in m.maps.iter_mut() {
            // The property maps: the noise texture.
            map.get_or_insert(noise.expect("a noise map")).strength = strength;
        }
        m
    }

    fn uniform(mode: ReflectionMode) -> Environment {
        Environment::Uniform {
            radiance: glam::Vec3::ONE,
            reflection: crate::scene::Reflection {
                mode,
                ..Default::default()
            },
        }
    }

    #[test]
    fn specialised_pipelines_sample_only_maps_that_change_the_image() {
        let shown = ForwardConstants::new(
            &mapped_material(0.5),
            &uniform(ReflectionMode::SplitSum),
            DebugView::Shaded,
            true,
            true,
        );
        assert!(shown.samples(MapSlot::BaseColor) && shown.samples(MapSlot::Normal));
        assert!(
            !shown.samples(MapSlot::Noise),
            "the noise map modulates only the seed reflection"
        );
        assert!(!shown.samples(MapSlot::Emission), "the emission map multiplies an emission of 0");
        let mut glowing = mapped_material(0.5);
        glowing.emission = glam::Vec3::new(0.0, 0.0, 0.5);
        let glowing = ForwardConstants::new(
            &glowing,
            &uniform(ReflectionMode::SplitSum),
            DebugView::Shaded,
            true,
            true,
        );
        assert!(glowing.samples(MapSlot::Emission));
        let seed = ForwardConstants::new(
            &mapped_material(0.5),
            &uniform(ReflectionMode::Seed),
            DebugView::Shaded,
            true,
            true,
        );
        assert!(seed.samples(MapSlot::Noise));
        let off = ForwardConstants::new(
            &mapped_material(0.0),
            &uniform(ReflectionMode::Seed),
            DebugView::Shaded,
            true,
            true,
        );
        assert_eq!(off.maps, 0);
        assert_eq!((off.debug_view, off.environment_kind, off.reflection_mode), (0, 1, 1));
        // A detail map over a normal map at strength 0: UDN and the report's blend see the
        // base's +z, so the normal map stays; RNM and whiteout do not.
        let mut detailed = mapped_material(0.0);
        detailed.maps[MapSlot::Detail].as_mut().expect("a detail map").strength = 1.0;
        for (blend, normal) in [
            (DetailBlend::Rnm, false),
            (DetailBlend::Whiteout, false),
            (DetailBlend::Udn, true),
            (DetailBlend::Seed, true),
        ] {
            detailed.detail_blend = blend;
            let c = ForwardConstants::new(
                &detailed,
                &uniform(ReflectionMode::SplitSum),
                DebugView::Shaded,
                true,
                true,
            );
            assert_eq!(
                (c.samples(MapSlot::Normal), c.samples(MapSlot::Detail)),
                (normal, true),
                "{blend:?}"
            );
        }
    }

    /// A pipeline that may run the sampled reflection (specialised to it or reading the
    /// mode from the uniforms), the report's composition or a map's sun is made from a
    /// build that holds them; one that runs none of them from the lean build; a debug view
    /// from the build with the views.
    #[test]
    fn pipelines_are_made_from_a_build_that_holds_their_code() {
        let m = mapped_material(0.5);
        let build = |mode, view, specialize| {
            ForwardConstants::new(&m, &uniform(mode), view, specialize, true).fragment_build()
        };
        use FragmentBuild::*;
        for (mode, specialised) in [
            (ReflectionMode::SplitSum, Lean),
            (ReflectionMode::Seed, Lean),
            (ReflectionMode::Sampled, Shaded),
        ] {
            assert_eq!(build(mode, DebugView::Shaded, true), specialised, "{mode:?}");
            assert_eq!(build(mode, DebugView::Shaded, false), DebugViews, "{mode:?}, generic");
            assert_eq!(build(mode, DebugView::Normals, true), DebugViews, "{mode:?}, a debug view");
        }
        let lean = ForwardConstants::new(&m, &uniform(ReflectionMode::SplitSum), DebugView::Shaded, true, true);
        let held = [
            ("the reflection mode from the uniforms", ForwardConstants { reflection_mode: FROM_UNIFORM, ..lean }),
            ("the report's composition", ForwardConstants { horizon: Horizon::Seed as u32, ..lean }),
            ("a map's sun", ForwardConstants { sun: 1, ..lean }),
        ];
        for (what, constants) in held {
            assert_eq!(constants.fragment_build(), Shaded, "{what}");
        }
    }

    /// The lean build leaves out every feature that shaders/lib/specialization.glsl lets a
    /// build leave out, and nothing else.
    #[test]
    fn the_lean_build_leaves_out_the_features_the_shaders_name() {
        let glsl = include_str!("../../shaders/lib/specialization.glsl");
        let features: Vec<&str> = glsl.lines().filter_map(|l| l.strip_prefix("#ifndef ")).collect();
        let features: Vec<&str> = features.into_iter().filter(|f| !f.starts_with("ARGIL_")).collect();
        assert_eq!(features, ["SAMPLED_REFLECTION", "SEED_COMPOSITION", "SUN_LOBE"]);
        let build = include_str!("../../build.rs");
        let lean = &build[build.find("\"forward_lean.frag\"").expect("the lean build")..];
        let macros = &lean[..lean.find(']').expect("its macros")];
        for feature in features.iter().chain(&["DEBUG_VIEWS"]) {
            assert!(macros.contains(&format!("(\"{feature}\", \"0\")")), "{feature}");
        }
        assert_eq!(macros.matches("\"0\")").count(), features.len() + 1);
    }

    /// The ground's own draw holds no bounce gather, every other draw of a bouncing scene
    /// does, and the generic pipeline always does; the ground's draw alone reads its
    /// shadows from the ground's map when the frame has one; a draw that no shadow can
    /// reach, and every draw of a frame without shadow maps, holds no shadow code, but for
    /// the generic pipeline; a draw holds the soft shadows' search and filter only where a
    /// soft light may shadow its object, but for the generic pipeline; a fine mesh reads a
    /// soft light's shadow at its vertices and a hard light's at its pixels.
    #[test]
    fn draws_hold_the_bounce_and_the_shadows_they_use() {
        let scene = Scene::from_toml(crate::scene::DEFAULT_SCENE_TOML, "default", std::path::Path::new(""))
            .expect("the default scene");
        let ground = scene.ground_index().expect("a ground");
        let from = vec![ObjectsOcclusionFrom::Pixels; scene.objects.len()];
        let constants = |scene: &Scene, specialize: bool, shadows: bool| -> Vec<ForwardConstants> {
            let choices = FrameChoices {
                debug_view: DebugView::Shaded,
                floor: false,
                specialize,
                samples: vk::SampleCountFlags::TYPE_1,
                occlusion: OcclusionMode::Off,
                objects: true,
                ground_map: None,
                ground_shadows: shadows.then_some(ground),
                ground_environment: None,
                sun: false,
                deferred: false,
                extent: vk::Extent2D { width: 1, height: 1 },
            };
            let extents: Vec<_> = scene.meshes.iter().map(|m| m.extent()).collect();
            let lights: Vec<usize> = if shadows { vec![0] } else { Vec::new() };
            let shadowing: Vec<u32> =
                (0..scene.objects.len()).map(|i| scene.shadowing_lights(i, &lights, |m| extents[m])).collect();
            let at_vertices: Vec<bool> = (scene.objects.iter().enumerate())
                .map(|(i, o)| light_at_vertices(scene, !specialize, shadowing[i], i, extents[o.mesh]))
                .collect();
            draw_constants(scene, None, &from, &shadowing, &at_vertices, &choices)
        };
        let specialised = constants(&scene, true, true);
        assert_eq!(specialised.len(), scene.objects.len());
        // The ball, convex and where nothing stands before the light, is lit whole.
        let (ball, ring) = (0, 1);
        for (i, c) in specialised.iter().enumerate() {
            let expected = (u32::from(i != ground), u32::from(i == ground), u32::from(i != ball));
            assert_eq!((c.bounce, c.ground_shadows, c.shadows), expected);
        }
        // The ball's and the ring's fine meshes gather at their vertices; the ground does not.
        let at_vertices: Vec<u32> = specialised.iter().map(|c| c.bounce_at_vertices).collect();
        assert_eq!(at_vertices, [1, 1, 0]);
        assert_eq!((specialised[ball].soft_shadows, specialised[ring].soft_shadows), (0, 1));
        let layers = |constants: &[ForwardConstants]| -> Vec<u32> {
            constants.iter().map(|c| c.vertex_shadow_layers).collect()
        };
        assert_eq!(layers(&specialised), [0, 0, 0], "unless [shadows] per_vertex asks for them");
        let mut per_vertex = scene.clone();
        per_vertex.shadow_per_vertex = true;
        let at_vertices = constants(&per_vertex, true, true);
        assert_eq!(layers(&at_vertices), [0, 1, 0], "the ring reads the soft light's shadow at its vertices");
        assert!(at_vertices.iter().all(|c| c.hard_shadows_at_pixels == 0));
        let generic = |scene: &Scene, shadows: bool| constants(scene, false, shadows);
        assert!(generic(&scene, true).iter().all(|c| c.bounce == 1), "the generic pipeline holds the bounce");
        assert!(constants(&scene, true, false).iter().all(|c| c.shadows == 0 && c.ground_shadows == 0));
        assert!(generic(&scene, false).iter().all(|c| c.shadows == 1), "the generic pipeline holds the shadows");
        let mut hard = per_vertex.clone();
        hard.lights[0].radius = 0.0;
        assert!(constants(&hard, true, true).iter().all(|c| c.soft_shadows == 0));
        assert!(generic(&hard, true).iter().all(|c| c.soft_shadows == 1), "the generic pipeline holds them");
        fn hard_at(constants: &[ForwardConstants]) -> Vec<(u32, u32)> {
            constants.iter().map(|c| (c.vertex_shadow_layers, c.hard_shadows_at_pixels)).collect()
        }
        assert_eq!(hard_at(&constants(&hard, true, true)), [(0, 0), (0, 0), (0, 1)]);
        // The generic ring reads every light at its vertices, and the hard one at its pixels.
        assert_eq!(hard_at(&generic(&hard, true)), [(0, 0), (1, 1), (0, 1)]);
    }

    #[test]
    fn generic_pipelines_read_the_uniforms_and_sample_every_map() {
        let generic = ForwardConstants::new(
            &mapped_material(0.0),
            &Environment::None,
            DebugView::Normals,
            false,
            true,
        );
        assert_eq!(generic.maps, (1 << MAP_COUNT) - 1);
        assert_eq!(
            (generic.debug_view, generic.environment_kind, generic.reflection_mode),
            (FROM_UNIFORM, FROM_UNIFORM, FROM_UNIFORM)
        );
    }

    /// Solids come first, nearest first, culled; the open ground keeps its place after
    /// them, and a solid the camera is inside is drawn whole among the open meshes.
    #[test]
    fn solids_seen_from_outside_are_drawn_first_and_culled() {
        let scene = Scene::from_toml(
            r#"
[camera]
position = [0.0, 0.0, 10.0]
target = [0.0, 0.0, 0.0]

[[objects]]
mesh = "builtin:plane"
position = [0.0, -1.0, 0.0]

[[objects]]
mesh = "builtin:sphere"
position = [0.0, 0.0, -4.0]

[[objects]]
mesh = "builtin:torus"
position = [0.0, 0.0, 2.0]

[[objects]]
mesh = "builtin:sphere"
position = [0.0, 0.0, 10.0]
scale = 2.0
"#,
            "order.toml",
            std::path::Path::new(""),
        )
        .expect("scene");
        let solid = |mesh: usize| {
            let mesh = &scene.meshes[mesh];
            mesh.bounds_solid().then(|| mesh.bounding_sphere())
        };
        let (back, none) = (vk::CullModeFlags::BACK, vk::CullModeFlags::NONE);
        assert_eq!(
            draw_order(&scene, solid, 16.0 / 9.0),
            vec![(2, back), (1, back), (0, none), (3, none)]
        );
    }
}
