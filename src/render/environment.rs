//! Environment lighting: the scene's `[environment]` on the GPU, bound as set 2 of the
//! forward pass (see `shaders/lib/environment.glsl`), and the skybox pass that shows it
//! behind the objects.
//!
//! Set 2: binding 0 the `EnvironmentData` uniform buffer, 1 the radiance cube map (with
//! mips), 2 the GGX-prefiltered radiance (octahedral maps, a layer per α), 3 the BRDF
//! tables, 4 the irradiance cube, 5 the luminance distribution's CDFs. What an environment
//! needs is built when a frame first uses it and kept for the next frames (until another
//! source replaces it): a studio or map builds its cube maps, spherical harmonics and
//! irradiance cube, split-sum reflection adds the prefiltered maps, sampled reflection the
//! luminance distribution, and the BRDF tables (the same for every environment) are built
//! once when a material needs them.
//! Intensity and rotation are uniforms; the kind and reflection mode are uniforms too, and
//! also specialization constants of the forward pass (see forward.rs), so that a frame runs
//! only its own mode's code. Unused bindings hold 1² placeholders (a one-float buffer for
//! binding 5): Vulkan needs every binding the shader uses statically to be valid.

pub mod equirect;
mod precompute;
pub mod sun;

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use gpu_allocator::MemoryLocation;

use super::shaders;
use super::split::Split;
use super::target::{DrawTarget, DEPTH_FORMAT, HDR_FORMAT};
use crate::brdf::environment::{irradiance_over_pi_cube, map_rotation, rotate_y, sh_project_cube, Sh9};
use crate::brdf::luminance_distribution::{LuminanceDistribution, STUDIO_GRID};
use crate::brdf::Vec3;
use crate::cache::{self, DiskCache};
use crate::scene::{Camera, DiffuseModel, Environment, Material, ReflectionMode, Scene, SpecularModel};
use crate::vk::{
    begin_full_rendering, transition, Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, GraphicsPipelineBuilder, Image, ImageUse, Pipeline, PipelineLayout, Sampler,
    ShaderModule,
};
pub use equirect::MAX_UPLOAD_WIDTH;
pub use precompute::{Cost, LUT_SAMPLES, LUT_SIZE, OCTAHEDRAL_SIDE, PREFILTERED_LEVELS};
use precompute::{Precompute, SourceCube};
use sun::Sun;

/// Faces of the studio's cube map: 0.35° texels, sharp enough behind the objects.
const STUDIO_SIZE: u32 = 256;
/// A map's cube faces hold a quarter of its width, within these bounds.
const MIN_MAP_SIZE: u32 = 16;
const MAX_MAP_SIZE: u32 = 512;
/// Spherical harmonics and the irradiance cube are computed from the first mip at most
/// this wide: bands 0–2 vary slowly, and 32² faces put their error below 1e-3; irradiance
/// is a cosine lobe's mean, which 2.8° texels resolve.
const SH_SIZE: u32 = 32;
/// Faces of the irradiance cube: it varies no faster than a cosine lobe's mean, and read
/// bilinearly from 2.8° texels it lights a Lambert sphere under one soft box within 0.14%
/// on average and 1.3% at worst (tests/environment.rs).
const IRRADIANCE_SIZE: u32 = 32;
/// A map's luminance distribution is at most as wide as the studio's: 0.7° cells, which
/// the balance heuristic's other strategies complement below that scale.
const LUMINANCE_MAX_WIDTH: usize = STUDIO_GRID.0;
/// The disk cache's entry of an irradiance cube.
const IRRADIANCE_ENTRY: &str = "irradiance";

// Values of `EnvironmentData.mode` (environment.glsl).
const KIND_NONE: u32 = 0;
const KIND_UNIFORM: u32 = 1;
const KIND_CUBE: u32 = 2;

/// `EnvironmentData` (std140).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct EnvironmentData {
    mode: [u32; 4],
    radiance: [f32; 4],
    params: [f32; 4],
    texel: [f32; 4],
    grid: [u32; 4],
    sun: [f32; 4],
    sun_irradiance: [f32; 4],
    sh: [[f32; 4]; 9],
}

/// The push constants of skybox.frag.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SkyboxPush {
    inverse_view_proj: [[f32; 4]; 4],
    camera_position: [f32; 4],
}

/// What a cube map is made from.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    Studio,
    Map(PathBuf),
}

/// What `EnvironmentPass::prepare` builds for a scene, decided before anything is built
/// ([`EnvironmentPass::plan`]).
pub struct Plan {
    source: Option<Source>,
    /// Whether the map handed over by [`EnvironmentPass::use_map`] is `source`'s.
    use_given_map: bool,
    rebuild_source: bool,
    add_prefiltered: bool,
    add_luminance: bool,
    add_lut: bool,
    /// Whether anything is built or the set and uniforms are written again.
    changed: bool,
}

impl Plan {
    /// Whether [`EnvironmentPass::prepare`] has anything to do.
    pub fn changes(&self) -> bool {
        self.changed
    }
}

/// A source's cube map and what is derived from it.
struct Cubes {
    source: Source,
    radiance: SourceCube,
    /// The prefiltered maps, built when split-sum reflection first needs them, from the
    /// map without its sun.
    prefiltered: Option<Image>,
    /// A map's sun, lifted out of the prefiltered maps with it.
    sun: Option<Sun>,
    sh: Sh9,
    /// Irradiance over π (`irradiance_over_pi_cube`): the diffuse light of the split sum,
    /// the objects' occlusion and the bounce.
    irradiance: Image,
    /// Built when sampled reflection first needs it.
    luminance: Option<Luminance>,
    /// A map source as decoded, kept while its cubes are: the sun and the luminance
    /// distribution, built when a mode first needs them, read it rather than the file.
    map: Option<equirect::Equirect>,
}

/// A source's `LuminanceDistribution` on the GPU.
struct Luminance {
    cdfs: Buffer,
    columns: u32,
    rows: u32,
}

pub struct EnvironmentPass {
    device: Arc<Device>,
    set_layout: DescriptorSetLayout,
    /// Owns `set`.
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    data: Buffer,
    sampler: Sampler,
    placeholder_cube: Image,
    placeholder_table: Image,
    placeholder_cdfs: Buffer,
    precompute: Precompute,
    cubes: Option<Cubes>,
    /// A map decoded by the caller, with its path, for the next `prepare` (`use_map`).
    given_map: Option<(PathBuf, equirect::Equirect)>,
    brdf_lut: Option<Image>,
    /// The environment `data` and `set` describe.
    current: Option<Environment>,
    /// Counts the changes of what `set` holds.
    generation: u64,
    /// A key of what `set` holds, where one is cheap to find (see [`Self::disk_key`]).
    disk_key: Option<u64>,
    skybox: Option<Skybox>,
    costs: Vec<Cost>,
}

impl EnvironmentPass {
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        // The ground's occlusion map is computed from it too (ground_maps.rs), and the
        // objects' occlusion at their vertices (forward.vert).
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let set_layout = DescriptorSetLayoutBuilder::default()
            .binding(vk::DescriptorType::UNIFORM_BUFFER, stages)
            .binding(vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages)
            .binding(vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages)
            .binding(vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages)
            .binding(vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages)
            .binding(vk::DescriptorType::STORAGE_BUFFER, stages)
            .build(device, "environment set")?;
        let pool = DescriptorPool::for_layout(device, &set_layout, 1)?;
        let set = pool.allocate(&set_layout)?;
        let data = Buffer::new(
            device,
            std::mem::size_of::<EnvironmentData>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
            "environment data",
        )?;
        let precompute = Precompute::new(device)?;
        let (placeholder_cube, placeholder_table) = precompute.placeholders()?;
        let placeholder_cdfs = precompute.upload_storage(&[0.0], "environment placeholder luminance")?;
        Ok(Self {
            device: device.clone(),
            set_layout,
            _pool: pool,
            set,
            data,
            sampler: Sampler::clamped(device)?,
            placeholder_cube,
            placeholder_table,
            placeholder_cdfs,
            precompute,
            cubes: None,
            given_map: None,
            brdf_lut: None,
            current: None,
            generation: 0,
            disk_key: None,
            skybox: None,
            costs: Vec::new(),
        })
    }

    /// The layout of set 2 of the forward pass.
    pub fn set_layout(&self) -> &DescriptorSetLayout {
        &self.set_layout
    }

    /// The set to bind as set 2; valid after `prepare`.
    pub fn set(&self) -> vk::DescriptorSet {
        self.set
    }

    /// Changes when the environment `set` describes changes (its settings, or its map read
    /// again), and only then.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// A key of everything the set holds (its data, and the code that makes its images):
    /// what a disk cache entry of an image computed from it is keyed by (ground_maps.rs).
    /// None for a map, whose texels would cost more to key than such an image to compute.
    pub fn disk_key(&self) -> Option<u64> {
        self.disk_key
    }

    /// Builds the cubes of the map at `path` from `map`, as the caller decoded it (to check
    /// it), at the next `prepare` if the scene still names `path`, rather than keeping the
    /// cubes built from the file at the same path: a scene loaded again reads every file it
    /// names, one rewritten in place too. Only then, so that a map half written by another
    /// program is not read while frames are drawn.
    pub fn use_map(&mut self, path: PathBuf, map: equirect::Equirect) {
        self.given_map = Some((path, map));
    }

    /// The cost of each precomputation step run for the current environment (empty when
    /// it needed none, or reused what was built before).
    pub fn precompute_costs(&self) -> &[Cost] {
        &self.costs
    }

    /// What [`Self::prepare`] is to build for `scene` (and a split frame's right part),
    /// once a frame: the caller asks the plan whether anything changes, then hands it on.
    pub fn plan(&self, scene: &Scene, split: Option<&Split>) -> Plan {
        let environment = &scene.environment;
        let source = match environment {
            Environment::Studio { .. } => Some(Source::Studio),
            Environment::Map { path, .. } => Some(Source::Map(path.clone())),
            Environment::None | Environment::Uniform { .. } => None,
        };
        // A split frame's right part reads the same set: what either part needs is built.
        let parts = std::iter::once((environment, scene.materials.as_slice()))
            .chain(split.map(|s| (&s.environment, s.materials.as_slice())));
        let (mut needs_prefiltered, mut needs_luminance, mut needs_lut) = (false, false, false);
        for (environment, materials) in parts {
            let mode = environment.reflection().map(|r| r.mode);
            needs_prefiltered |= source.is_some() && mode == Some(ReflectionMode::SplitSum);
            needs_luminance |= source.is_some() && mode == Some(ReflectionMode::Sampled);
            needs_lut |= mode.is_some_and(|m| m != ReflectionMode::Sampled) && needs_brdf_tables(materials);
            // Energy compensation reads E from the tables under every environment and mode.
            needs_lut |= materials
                .iter()
                .any(|m| m.energy_compensation && m.specular != SpecularModel::None);
        }
        let built_source = self.cubes.as_ref().map(|c| &c.source);
        let use_given_map = self
            .given_map
            .as_ref()
            .is_some_and(|(path, _)| matches!(&source, Some(Source::Map(named)) if named == path));
        let rebuild_source = source.is_some() && (use_given_map || built_source != source.as_ref());
        let add_prefiltered =
            needs_prefiltered && (rebuild_source || self.cubes.as_ref().is_some_and(|c| c.prefiltered.is_none()));
        let add_luminance =
            needs_luminance && (rebuild_source || self.cubes.as_ref().is_some_and(|c| c.luminance.is_none()));
        let add_lut = needs_lut && self.brdf_lut.is_none();
        let changed = rebuild_source
            || add_prefiltered
            || add_luminance
            || add_lut
            || self.current.as_ref() != Some(environment);
        Plan {
            source,
            use_given_map,
            rebuild_source,
            add_prefiltered,
            add_luminance,
            add_lut,
            changed,
        }
    }

    /// [`Self::has_sun`] after [`Self::prepare`] of `scene`, when it is known before: only
    /// a map has a sun, found in it as its cubes are built.
    pub fn sun_before_prepare(scene: &Scene) -> Option<bool> {
        match scene.environment {
            Environment::Map { .. } => None,
            Environment::None | Environment::Uniform { .. } | Environment::Studio { .. } => Some(false),
        }
    }

    /// Builds what `scene`'s environment and materials need (and a split frame's right
    /// part, see split.rs) and is not built yet, as `plan` ([`Self::plan`] of the same
    /// scene) says, and points the set and uniforms at it. Waits for the device first if
    /// anything changes (frames in flight read the set).
    pub fn prepare(&mut self, scene: &Scene, plan: Plan) -> Result<()> {
        let environment = &scene.environment;
        let given_map = self.given_map.take().filter(|_| plan.use_given_map).map(|(_, map)| map);
        if !plan.changed {
            return Ok(());
        }
        self.generation += 1;
        self.device.wait_idle()?;
        self.current = None;
        self.costs.clear();
        if plan.rebuild_source {
            self.cubes = None;
            if let Some(source) = plan.source {
                let cubes = self.build_cubes(source, given_map);
                self.cubes = Some(cubes.map_err(|e| equirect::in_scene_file(e, scene))?);
            }
        }
        if let Some(cubes) = self.cubes.as_mut().filter(|_| plan.add_prefiltered) {
            let start = Instant::now();
            let sunny = cubes.map.as_ref().and_then(sun::extract);
            if cubes.map.is_some() {
                self.costs.push(Cost {
                    step: "sun",
                    ms: start.elapsed().as_secs_f64() * 1e3,
                    gpu: false,
                });
            }
            let size = cubes.radiance.image.extent.width;
            let sunless = match &sunny {
                Some((_, map)) => Some(self.precompute.sunless(map, size, &mut self.costs)?),
                None => None,
            };
            cubes.prefiltered = Some(self.precompute.prefilter(
                sunless.as_ref().unwrap_or(&cubes.radiance),
                &self.sampler,
                &DiskCache::from_env(),
                &mut self.costs,
            )?);
            cubes.sun = sunny.map(|(sun, _)| sun);
        }
        if let Some(cubes) = self.cubes.as_mut().filter(|c| plan.add_luminance && c.luminance.is_none()) {
            cubes.luminance = Some(build_luminance(&self.precompute, cubes.map.as_ref(), &mut self.costs)?);
        }
        if plan.add_lut {
            self.brdf_lut = Some(self.precompute.brdf_lut(&DiskCache::from_env(), &mut self.costs)?);
        }
        self.write(environment)?;
        self.current = Some(environment.clone());
        Ok(())
    }

    /// Creates the skybox's pipeline for targets of `samples` samples, if the current
    /// environment is drawn and it does not exist yet.
    pub fn prepare_skybox(&mut self, samples: vk::SampleCountFlags) -> Result<()> {
        if !self.draws_skybox() {
            return Ok(());
        }
        let skybox = match self.skybox.take() {
            Some(skybox) => skybox,
            None => Skybox::new(&self.device, &self.set_layout)?,
        };
        self.skybox.insert(skybox).prepare(samples)
    }

    /// The source's cubes, with the map they were made from if it is one (`given_map`, when
    /// the caller decoded it).
    fn build_cubes(&mut self, source: Source, given_map: Option<equirect::Equirect>) -> Result<Cubes> {
        let mut loaded_map = None;
        let radiance = match &source {
            Source::Studio => self.precompute.studio(STUDIO_SIZE, &DiskCache::from_env(), &mut self.costs)?,
            Source::Map(path) => {
                let map = match given_map {
                    Some(map) => map,
                    None => load_map(path, &mut self.costs)?,
                };
                let size = (map.width / 4).clamp(MIN_MAP_SIZE, MAX_MAP_SIZE);
                // The largest power of two within the bounds, so every mip halves exactly.
                let size = 1 << (31 - size.leading_zeros());
                let cube = self.precompute.equirect(&map, size, &mut self.costs)?;
                loaded_map = Some(map);
                cube
            }
        };
        let start = Instant::now();
        let size = radiance.image.extent.width;
        let level = (size / SH_SIZE.min(size)).trailing_zeros();
        let side = size >> level;
        let texels = self.precompute.read_level(&radiance.image, level)?;
        let texel = |face: u32, x: u32, y: u32| {
            let t = texels[((face * side + y) * side + x) as usize];
            [f64::from(t[0]), f64::from(t[1]), f64::from(t[2])]
        };
        let sh = sh_project_cube(side, texel);
        self.costs.push(Cost {
            step: "spherical harmonics",
            ms: start.elapsed().as_secs_f64() * 1e3,
            gpu: false,
        });
        let start = Instant::now();
        // The cube follows from these texels by brdf/environment.rs's quadrature alone.
        let key = cache::key(&[
            bytemuck::cast_slice(&texels),
            &side.to_le_bytes(),
            &IRRADIANCE_SIZE.to_le_bytes(),
            include_str!("../brdf/environment.rs").as_bytes(),
        ]);
        let size = 6 * (IRRADIANCE_SIZE * IRRADIANCE_SIZE) as usize * std::mem::size_of::<Vec3>();
        let mut computed = false;
        let bytes = DiskCache::from_env().get_or_compute(
            IRRADIANCE_ENTRY,
            key,
            |b| b.len() == size,
            || {
                computed = true;
                bytemuck::cast_slice(&irradiance_over_pi_cube(IRRADIANCE_SIZE, side, texel)).to_vec()
            },
        );
        let irradiance: Vec<Vec3> = bytemuck::pod_collect_to_vec(&bytes);
        let irradiance = self.precompute.upload_cube(IRRADIANCE_SIZE, &irradiance, "irradiance cube")?;
        self.costs.push(Cost {
            step: if computed { "irradiance" } else { "irradiance (disk cache)" },
            ms: start.elapsed().as_secs_f64() * 1e3,
            gpu: false,
        });
        let cubes = Cubes {
            source,
            radiance,
            prefiltered: None,
            sun: None,
            sh,
            irradiance,
            luminance: None,
            map: loaded_map,
        };
        Ok(cubes)
    }

    /// Writes the uniforms and the set for `environment` from what is built.
    fn write(&mut self, environment: &Environment) -> Result<()> {
        let reflection = environment.reflection().copied().unwrap_or_default();
        let kind = environment_kind(environment);
        let (radiance, rotation_degrees) = match environment {
            Environment::None => ([0.0; 3], 0.0),
            Environment::Uniform { radiance, .. } => (radiance.to_array(), 0.0),
            Environment::Studio {
                intensity,
                rotation_degrees,
                ..
            }
            | Environment::Map {
                intensity,
                rotation_degrees,
                ..
            } => ([*intensity; 3], *rotation_degrees),
        };
        let rotation = map_rotation(f64::from(rotation_degrees));
        let cubes = cubes_of(&self.cubes, environment);
        // Sampled reflection alone reads it, in either part of a split frame.
        let luminance = cubes.and_then(|c| c.luminance.as_ref());
        // Uniform radiance reads no texel: any positive solid angle keeps the lod finite.
        let texel_solid_angle = cubes.map_or(1.0, |c| {
            let w = c.radiance.image.extent.width as f32;
            4.0 * std::f32::consts::PI / (6.0 * w * w)
        });
        // Its direction in the world: the map's rotation undone.
        let sun = cubes.and_then(|c| c.sun.as_ref());
        let sun_direction = sun.map_or([0.0; 3], |s| rotate_y(s.direction, [rotation[0], -rotation[1]]));
        let mut sh = [[0.0; 4]; 9];
        if let Some(c) = cubes {
            for (out, coefficient) in sh.iter_mut().zip(c.sh) {
                *out = [coefficient[0] as f32, coefficient[1] as f32, coefficient[2] as f32, 0.0];
            }
        }
        let data = EnvironmentData {
            mode: [kind, reflection_code(reflection.mode), reflection.samples, 0],
            radiance: [radiance[0], radiance[1], radiance[2], 0.0],
            params: [
                rotation[0] as f32,
                rotation[1] as f32,
                reflection.seed_strength,
                (PREFILTERED_LEVELS - 1) as f32,
            ],
            texel: [texel_solid_angle, 0.0, 0.0, 0.0],
            grid: [luminance.map_or(0, |l| l.columns), luminance.map_or(0, |l| l.rows), 0, 0],
            sun: [
                sun_direction[0] as f32,
                sun_direction[1] as f32,
                sun_direction[2] as f32,
                sun.map_or(0.0, |s| s.angular_radius as f32),
            ],
            sun_irradiance: sun.map_or([0.0; 4], |s| {
                [s.irradiance[0] as f32, s.irradiance[1] as f32, s.irradiance[2] as f32, 0.0]
            }),
            sh,
        };
        self.data.write(bytemuck::bytes_of(&data))?;
        // A studio's cubes follow from the code and STUDIO_SIZE alone.
        self.disk_key = cubes.filter(|c| matches!(c.source, Source::Map(_))).is_none().then(|| {
            cache::key(&[
                bytemuck::bytes_of(&data),
                &STUDIO_SIZE.to_le_bytes(),
                shaders::ENV_STUDIO_COMP,
                shaders::ENV_DOWNSAMPLE_COMP,
                include_str!("environment.rs").as_bytes(),
                include_str!("environment/precompute.rs").as_bytes(),
                include_str!("../brdf/environment.rs").as_bytes(),
            ])
        });
        let radiance_view = cubes.map_or(self.placeholder_cube.view, |c| c.radiance.image.view);
        let prefiltered_view = cubes
            .and_then(|c| c.prefiltered.as_ref())
            .map_or(self.placeholder_table.view, |i| i.view);
        let lut_view = self.brdf_lut.as_ref().map_or(self.placeholder_table.view, |i| i.view);
        let irradiance_view = cubes.map_or(self.placeholder_cube.view, |c| c.irradiance.view);
        let cdfs = luminance.map_or(self.placeholder_cdfs.handle, |l| l.cdfs.handle);
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        DescriptorWriter::default()
            .buffer(0, vk::DescriptorType::UNIFORM_BUFFER, self.data.handle)
            .image(1, sampled, radiance_view, layout, self.sampler.handle)
            .image(2, sampled, prefiltered_view, layout, self.sampler.handle)
            .image(3, sampled, lut_view, layout, self.sampler.handle)
            .image(4, sampled, irradiance_view, layout, self.sampler.handle)
            .buffer(5, vk::DescriptorType::STORAGE_BUFFER, cdfs)
            .write(&self.device, self.set);
        Ok(())
    }

    /// Whether the current environment's uniforms carry a sun (env.sun in environment.glsl):
    /// its map's, lifted out of the prefiltered cube for split-sum reflection to light as
    /// one direction.
    pub fn has_sun(&self) -> bool {
        let cubes = self.current.as_ref().and_then(|e| cubes_of(&self.cubes, e));
        cubes.is_some_and(|c| c.sun.is_some())
    }

    /// Whether the current environment is drawn behind the objects (a cube map; a uniform
    /// one is the target's clear colour).
    pub fn draws_skybox(&self) -> bool {
        matches!(self.current, Some(Environment::Studio { .. } | Environment::Map { .. }))
    }

    /// Records the skybox into `target` after the forward pass, if the environment is
    /// drawn: colour and depth are in attachment layouts and stay there.
    pub fn record_skybox(&self, cmd: vk::CommandBuffer, target: DrawTarget, camera: &Camera) -> Result<()> {
        match self.skybox.as_ref().filter(|_| self.draws_skybox()) {
            Some(skybox) => skybox.record(cmd, target, camera, self.set),
            None => Ok(()),
        }
    }

    /// Mip `level` of the radiance cube map (faces +x, −x, +y, −y, +z, −z, rows from the
    /// top), for checks; `None` without a cube map.
    pub fn read_radiance_level(&self, level: u32) -> Result<Option<Vec<[f32; 4]>>> {
        self.cubes
            .as_ref()
            .map(|c| self.precompute.read_level(&c.radiance.image, level))
            .transpose()
    }

    /// The GGX-prefiltered radiance's octahedral maps, `OCTAHEDRAL_SIDE`² texels a layer,
    /// layer k for `prefiltered_level_alpha` of level k, rows of increasing v, for checks;
    /// `None` before split sum needed them.
    pub fn read_prefiltered_maps(&self) -> Result<Option<Vec<[f32; 4]>>> {
        self.cubes
            .as_ref()
            .and_then(|c| c.prefiltered.as_ref())
            .map(|i| self.precompute.read_level(i, 0))
            .transpose()
    }

    /// The BRDF tables (layer-major, rows of increasing roughness), for checks; `None`
    /// when no environment has needed them.
    pub fn read_brdf_lut(&self) -> Result<Option<Vec<[f32; 4]>>> {
        self.brdf_lut
            .as_ref()
            .map(|i| self.precompute.read_level(i, 0))
            .transpose()
    }
}

/// The map at `path`, its loading timed.
fn load_map(path: &std::path::Path, costs: &mut Vec<Cost>) -> Result<equirect::Equirect> {
    let start = Instant::now();
    let map = equirect::load(path)?;
    costs.push(Cost {
        step: "load map",
        ms: start.elapsed().as_secs_f64() * 1e3,
        gpu: false,
    });
    Ok(map)
}

/// The luminance distribution of `map`'s texels, or of the studio without one, uploaded.
fn build_luminance(
    precompute: &Precompute,
    map: Option<&equirect::Equirect>,
    costs: &mut Vec<Cost>,
) -> Result<Luminance> {
    let start = Instant::now();
    let distribution = match map {
        None => LuminanceDistribution::studio(),
        Some(map) => {
            let texels: Vec<Vec3> = map
                .texels
                .iter()
                .map(|t| [f64::from(t[0]), f64::from(t[1]), f64::from(t[2])])
                .collect();
            LuminanceDistribution::map(&texels, map.width as usize, map.height as usize, LUMINANCE_MAX_WIDTH)
        }
    };
    let cdfs = precompute.upload_storage(&distribution.gpu_cdfs(), "environment luminance")?;
    costs.push(Cost {
        step: "luminance distribution",
        ms: start.elapsed().as_secs_f64() * 1e3,
        gpu: false,
    });
    Ok(Luminance {
        cdfs,
        columns: distribution.width() as u32,
        rows: distribution.height() as u32,
    })
}

/// `EnvironmentData.mode.y`, and the forward pass's `REFLECTION_MODE` constant.
pub(super) fn reflection_code(mode: ReflectionMode) -> u32 {
    match mode {
        ReflectionMode::SplitSum => 0,
        ReflectionMode::Seed => 1,
        ReflectionMode::Sampled => 2,
    }
}

/// The cubes that `environment` reads of those built: none without a cube map.
fn cubes_of<'a>(cubes: &'a Option<Cubes>, environment: &Environment) -> Option<&'a Cubes> {
    cubes.as_ref().filter(|_| environment_kind(environment) == KIND_CUBE)
}

/// `EnvironmentData.mode.x`, and the forward pass's `ENVIRONMENT_KIND` constant.
pub(super) fn environment_kind(environment: &Environment) -> u32 {
    match environment {
        Environment::None => KIND_NONE,
        Environment::Uniform { .. } => KIND_UNIFORM,
        Environment::Studio { .. } | Environment::Map { .. } => KIND_CUBE,
    }
}

/// Split sum and seed read the tables for a specular lobe or Oren-Nayar's albedo.
fn needs_brdf_tables(materials: &[Material]) -> bool {
    materials
        .iter()
        .any(|m| m.specular != SpecularModel::None || m.diffuse == DiffuseModel::OrenNayar)
}

/// The skybox pipeline: a fullscreen triangle at the far plane, depth-tested against the
/// forward pass's depth without writing it.
struct Skybox {
    device: Arc<Device>,
    layout: PipelineLayout,
    vertex: ShaderModule,
    fragment: ShaderModule,
    /// By the sample count of the targets they draw into.
    pipelines: HashMap<vk::SampleCountFlags, Pipeline>,
}

impl Skybox {
    fn new(device: &Arc<Device>, set_layout: &DescriptorSetLayout) -> Result<Self> {
        let layout = PipelineLayout::new(
            device,
            &[set_layout],
            std::mem::size_of::<SkyboxPush>() as u32,
            vk::ShaderStageFlags::FRAGMENT,
        )?;
        Ok(Self {
            device: device.clone(),
            layout,
            vertex: ShaderModule::new(device, shaders::SKYBOX_VERT, "skybox.vert")?,
            fragment: ShaderModule::new(device, shaders::SKYBOX_FRAG, "skybox.frag")?,
            pipelines: HashMap::new(),
        })
    }

    fn prepare(&mut self, samples: vk::SampleCountFlags) -> Result<()> {
        if !self.pipelines.contains_key(&samples) {
            let pipeline = GraphicsPipelineBuilder::new(&self.vertex, &self.fragment, HDR_FORMAT)
                .depth_test_only(DEPTH_FORMAT, vk::CompareOp::LESS_OR_EQUAL)
                .samples(samples)
                .build(&self.device, &self.layout, &format!("skybox {samples:?}"))?;
            self.pipelines.insert(samples, pipeline);
        }
        Ok(())
    }

    fn record(
        &self,
        cmd: vk::CommandBuffer,
        target: DrawTarget,
        camera: &Camera,
        set: vk::DescriptorSet,
    ) -> Result<()> {
        let pipeline = self
            .pipelines
            .get(&target.samples())
            .context("skybox pipeline missing: prepare_skybox() was not called for this sample count")?;
        let d = &self.device.handle;
        // The forward pass's colour and depth writes come first.
        let (color_image, depth_image) = (&target.color, &target.depth);
        transition(
            &self.device,
            cmd,
            color_image.handle,
            color_image.aspect,
            ImageUse::COLOR_ATTACHMENT,
            ImageUse::COLOR_ATTACHMENT,
        );
        transition(
            &self.device,
            cmd,
            depth_image.handle,
            depth_image.aspect,
            ImageUse::DEPTH_ATTACHMENT,
            ImageUse::DEPTH_ATTACHMENT,
        );
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(target.color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(target.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::DONT_CARE);
        let view_proj: Mat4 = camera.projection(target.aspect()) * camera.view();
        let push = SkyboxPush {
            inverse_view_proj: view_proj.inverse().to_cols_array_2d(),
            camera_position: camera.position.extend(1.0).to_array(),
        };
        begin_full_rendering(&self.device, cmd, target.extent(), &color, Some(&depth));
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.handle);
            d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, self.layout.handle, 0, &[set], &[]);
            d.cmd_push_constants(
                cmd,
                self.layout.handle,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_draw(cmd, 3, 1, 0, 0);
            d.cmd_end_rendering(cmd);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EnvironmentData's fields lie where environment.glsl's std140 block puts its members:
    /// the same names in the same order, each a vec4 or uvec4 (16 bytes) or an array of them.
    #[test]
    fn environment_data_matches_environment_glsl() {
        let glsl = include_str!("../../shaders/lib/environment.glsl");
        let block = glsl
            .split_once("uniform EnvironmentData {")
            .and_then(|(_, rest)| rest.split_once("} env;"))
            .expect("environment.glsl declares EnvironmentData")
            .0;
        let mut offset = 0;
        for line in block.lines() {
            let Some(member) = line.split("//").next().and_then(|m| m.trim().strip_suffix(';')) else {
                continue;
            };
            let (ty, name) = member.split_once(' ').expect("a member is `type name`");
            assert!(ty == "vec4" || ty == "uvec4", "{member}: not 16 bytes");
            let (name, count) = match name.split_once('[') {
                Some((name, count)) => (name, count.trim_end_matches(']').parse::<usize>().expect("array length")),
                None => (name, 1),
            };
            let rust = match name {
                "mode" => std::mem::offset_of!(EnvironmentData, mode),
                "radiance" => std::mem::offset_of!(EnvironmentData, radiance),
                "params" => std::mem::offset_of!(EnvironmentData, params),
                "texel" => std::mem::offset_of!(EnvironmentData, texel),
                "grid" => std::mem::offset_of!(EnvironmentData, grid),
                "sun" => std::mem::offset_of!(EnvironmentData, sun),
                "sun_irradiance" => std::mem::offset_of!(EnvironmentData, sun_irradiance),
                "sh" => std::mem::offset_of!(EnvironmentData, sh),
                other => panic!("EnvironmentData has no field {other}"),
            };
            assert_eq!(rust, offset, "{name}");
            offset += 16 * count;
        }
        assert_eq!(std::mem::size_of::<EnvironmentData>(), offset);
    }
}
