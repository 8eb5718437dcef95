//! The once-per-environment GPU work, in compute shaders: the source cube map (the studio,
//! or an equirectangular map converted), its mip chain, the GGX-prefiltered cube map and
//! the octahedral maps split sum reads it through, and the environment-independent BRDF
//! tables. Each step is timed (GPU timestamps when the queue has them, else CPU time) for
//! `argil render` to print.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use ash::vk;

use super::equirect::Equirect;
use crate::brdf::environment::{prefiltered_level_alpha, LUT_LAYERS};
use crate::cache::{self, DiskCache};
use crate::render::shaders;
use crate::vk::{
    transfer, transition_levels, Buffer, DescriptorPool, DescriptorSetLayout, DescriptorSetLayoutBuilder,
    DescriptorWriter, Device, Image, ImageUse, ImageView, OneShot, Pipeline, PipelineLayout, Sampler, ShaderModule,
    Specialization, Timestamps,
};

/// Every cube map and table is RGBA16F: filterable and storable on every Vulkan device.
pub const FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Prefiltered levels: the mirror at level 0 and α = 2^(k − 6) at level k
/// (`prefiltered_level_alpha`), each a cube of (128 >> k)² faces, so that a level's texels
/// are about 0.8 α wide, but none of fewer than 8²: the bilinear lookups of 4² and 2² faces
/// bent the lobe's smooth mean between texel centres, +2.1% and +7.8% on average (mean
/// |error| 3.4% and 12%) at roughness 0.7 and 1 under a soft box. With 64² faces at level 0
/// and steps of 1/5 in roughness, a GGX lobe at roughness 0.3 blended lobes 4× apart in α
/// and read 4% bright under a soft box.
const PREFILTERED_SIZE: u32 = 128;
const PREFILTERED_MIN_SIZE: u32 = 8;
pub const PREFILTERED_LEVELS: u32 = 7;
/// The octahedral maps of the prefiltered cube's levels, one a layer, that split sum reads
/// (env_octahedral.comp): 256² texels inside a border of one, about as fine as level 0's
/// 128² faces (4π/256² against 4π/(6 · 128²) steradians a texel).
pub const OCTAHEDRAL_SIDE: u32 = 256 + 2;
/// GGX samples per texel of the prefiltered level 1; with filtered importance
/// sampling, 128 keep each texel within a few percent of the lobe's mean (under a soft box:
/// 1–5% mean |error|). Coarser levels take more a texel (`prefilter_samples`), up to
/// `PREFILTER_MAX_SAMPLES`.
const PREFILTER_SAMPLES: u32 = 128;
const PREFILTER_MAX_SAMPLES: u32 = 1024;
/// BRDF tables: n·v × roughness, and the samples per texel (QMC error ~1e-3).
pub const LUT_SIZE: vk::Extent2D = vk::Extent2D { width: 32, height: 32 };
pub const LUT_SAMPLES: u32 = 512;
/// The disk cache's entries of the BRDF tables, the studio's cube with its mips and an
/// environment's prefiltered maps.
const LUT_ENTRY: &str = "brdf-tables";
const STUDIO_ENTRY: &str = "studio-cube";
const PREFILTERED_ENTRY: &str = "prefiltered-environment";
/// Compute shaders' workgroups are 8×8 texels of one layer.
const GROUP: u32 = 8;

/// The finest source mip the prefilter reads for a level of `side`² faces at `roughness`:
/// no finer than the level's own texels where the GGX lobe is narrower than they are (no
/// aliasing), less as the lobe spans them. The lobe covers about 1/p at its peak, 4πα²
/// (p = D/4 at l = r), which is 6α² side² texels of 4π/(6 side²). Clamping every level to its
/// texels blurred the rough levels' 2² and 4² faces with the source's own (+4.4% mean error
/// at roughness 1 under a soft box, against +1.6% without).
fn prefilter_min_lod(roughness: f32, side: u32, source_size: u32) -> f32 {
    let alpha = crate::brdf::clamp_alpha(f64::from(roughness * roughness));
    let lobe_texels = 6.0 * alpha * alpha * f64::from(side * side);
    let levels = (f64::from(source_size) / f64::from(side)).log2() - 0.5 * lobe_texels.max(1.0).log2();
    levels.max(0.0) as f32
}

/// Faces of the prefiltered cube of `level`.
fn prefiltered_side(level: u32) -> u32 {
    (PREFILTERED_SIZE >> level).max(PREFILTERED_MIN_SIZE)
}

/// GGX samples per texel of level `level`. Level 0 holds the mirror, one lookup. From level
/// 1 on, a level has a quarter of the texels of the one before, so each takes four times
/// the samples for the same cost, up to a cap. 128 at every mip left a sun's highlight blotchy
/// at roughness 0.3 (mips 2 and 3), and spent three quarters of the time on mip 0.
fn prefilter_samples(level: u32) -> u32 {
    match level {
        0 => 1,
        _ => (PREFILTER_SAMPLES << (2 * (level - 1))).min(PREFILTER_MAX_SAMPLES),
    }
}

/// The roughness each mip of the prefiltered cube is filtered for.
fn level_roughness() -> [f32; PREFILTERED_LEVELS as usize] {
    std::array::from_fn(|level| prefiltered_level_alpha(level as u32, PREFILTERED_LEVELS - 1).sqrt() as f32)
}

/// Bytes of an RGBA16F texel.
const TEXEL_BYTES: u64 = 8;

/// Bytes of every level and layer of an RGBA16F image, as `upload_levels` takes them.
fn level_bytes(image: &Image) -> usize {
    transfer::image_size(image, TEXEL_BYTES)
}

/// The texels of a cube map level with `side`² faces, for a dispatch.
fn cube_texels(side: u32) -> vk::Extent3D {
    vk::Extent3D {
        width: side,
        height: side,
        depth: 6,
    }
}

/// What every computed image is used for: written by compute shaders, sampled, read back
/// for the disk cache and uploaded from it.
const STORAGE_USAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::STORAGE.as_raw()
        | vk::ImageUsageFlags::SAMPLED.as_raw()
        | vk::ImageUsageFlags::TRANSFER_SRC.as_raw()
        | vk::ImageUsageFlags::TRANSFER_DST.as_raw(),
);

/// Where every finished image is left: sampled by shaders (the prefilter kernel reads the
/// source cube in a later submission, which the fence orders).
pub const SHADING_READ: ImageUse = ImageUse::SHADER_READ;

/// One step's cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Cost {
    pub step: &'static str,
    pub ms: f64,
    /// Measured by GPU timestamps (else CPU wall time around the submission).
    pub gpu: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum KernelKind {
    Studio,
    Equirect,
    Downsample,
    Prefilter,
    Octahedral,
    BrdfLut,
}

impl KernelKind {
    fn spirv(self) -> (&'static [u8], &'static str) {
        match self {
            KernelKind::Studio => (shaders::ENV_STUDIO_COMP, "env_studio.comp"),
            KernelKind::Equirect => (shaders::ENV_EQUIRECT_COMP, "env_equirect.comp"),
            KernelKind::Downsample => (shaders::ENV_DOWNSAMPLE_COMP, "env_downsample.comp"),
            KernelKind::Prefilter => (shaders::ENV_PREFILTER_COMP, "env_prefilter.comp"),
            KernelKind::Octahedral => (shaders::ENV_OCTAHEDRAL_COMP, "env_octahedral.comp"),
            KernelKind::BrdfLut => (shaders::ENV_BRDF_LUT_COMP, "env_brdf_lut.comp"),
        }
    }

    /// The shader's bindings in order, and its push-constant bytes.
    fn interface(self) -> (&'static [vk::DescriptorType], u32) {
        use vk::DescriptorType as T;
        match self {
            KernelKind::Studio => (&[T::STORAGE_IMAGE], 0),
            KernelKind::Equirect => (&[T::STORAGE_IMAGE, T::STORAGE_BUFFER], 8),
            KernelKind::Downsample => (&[T::STORAGE_IMAGE, T::STORAGE_IMAGE], 0),
            KernelKind::Prefilter => (&[T::COMBINED_IMAGE_SAMPLER, T::STORAGE_IMAGE], 16),
            KernelKind::Octahedral => (&[T::COMBINED_IMAGE_SAMPLER, T::STORAGE_IMAGE], 0),
            KernelKind::BrdfLut => (&[T::STORAGE_IMAGE], 4),
        }
    }
}

/// A compute pipeline with its own set layout.
struct Kernel {
    set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    pipeline: Pipeline,
}

/// What one dispatch binds: its set's resources, in binding order.
enum Resource<'a> {
    Storage(vk::ImageView),
    Sampled(vk::ImageView, &'a Sampler),
    Buffer(&'a Buffer),
}

/// The compute kernels, each created the first time an environment needs it.
pub struct Precompute {
    device: Arc<Device>,
    one_shot: OneShot,
    kernels: HashMap<KernelKind, Kernel>,
}

/// A cube map with its mip chain of solid-angle-weighted means.
pub struct SourceCube {
    pub image: Image,
    /// The disk cache's key of its texels where they follow from code alone (the studio's),
    /// which then stands for them in the keys of what is made from them.
    pub key: Option<u64>,
}

impl Precompute {
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let features = unsafe {
            device
                .instance
                .handle
                .get_physical_device_format_properties(device.physical, FORMAT)
        }
        .optimal_tiling_features;
        let needed = vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
        if !features.contains(needed) {
            bail!("this device cannot filter and store {FORMAT:?} images, which environment maps need");
        }
        Ok(Self {
            device: device.clone(),
            one_shot: OneShot::new(device)?,
            kernels: HashMap::new(),
        })
    }

    fn kernel(&mut self, kind: KernelKind) -> Result<&Kernel> {
        if !self.kernels.contains_key(&kind) {
            let (spirv, name) = kind.spirv();
            let (bindings, push_size) = kind.interface();
            let set_layout = bindings
                .iter()
                .fold(DescriptorSetLayoutBuilder::default(), |b, &t| {
                    b.binding(t, vk::ShaderStageFlags::COMPUTE)
                })
                .build(&self.device, name)?;
            let layout = PipelineLayout::new(&self.device, &[&set_layout], push_size, vk::ShaderStageFlags::COMPUTE)?;
            let shader = ShaderModule::new(&self.device, spirv, name)?;
            let pipeline = Pipeline::compute(&self.device, &layout, &shader, &Specialization::default(), name)?;
            self.kernels.insert(
                kind,
                Kernel {
                    set_layout,
                    layout,
                    pipeline,
                },
            );
        }
        self.kernels.get(&kind).context("kernel created above")
    }

    /// Records one dispatch of `kind` over `texels` (width × height × layers); its set
    /// comes from `pool`, which must outlive the submission.
    fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        kind: KernelKind,
        pool: &DescriptorPool,
        resources: &[Resource],
        push: &[u8],
        texels: vk::Extent3D,
    ) -> Result<()> {
        let kernel = self.kernels.get(&kind).context("compute kernel not created")?;
        let set = pool.allocate(&kernel.set_layout)?;
        let writer = resources
            .iter()
            .enumerate()
            .fold(DescriptorWriter::default(), |w, (i, r)| {
                let binding = i as u32;
                match r {
                    Resource::Storage(view) => w.image(
                        binding,
                        vk::DescriptorType::STORAGE_IMAGE,
                        *view,
                        vk::ImageLayout::GENERAL,
                        vk::Sampler::null(),
                    ),
                    Resource::Sampled(view, sampler) => w.image(
                        binding,
                        vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                        *view,
                        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                        sampler.handle,
                    ),
                    Resource::Buffer(buffer) => w.buffer(binding, vk::DescriptorType::STORAGE_BUFFER, buffer.handle),
                }
            });
        writer.write(&self.device, set);
        let d = &self.device.handle;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, kernel.pipeline.handle);
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                kernel.layout.handle,
                0,
                &[set],
                &[],
            );
            if !push.is_empty() {
                d.cmd_push_constants(cmd, kernel.layout.handle, vk::ShaderStageFlags::COMPUTE, 0, push);
            }
            d.cmd_dispatch(
                cmd,
                texels.width.div_ceil(GROUP),
                texels.height.div_ceil(GROUP),
                texels.depth,
            );
        }
        Ok(())
    }

    /// A pool for `sets` sets of `kind`'s layout.
    fn pool(&mut self, kind: KernelKind, sets: u32) -> Result<DescriptorPool> {
        let device = self.device.clone();
        let kernel = self.kernel(kind)?;
        DescriptorPool::for_layout(&device, &kernel.set_layout, sets)
    }

    /// Runs `record` in one submission and measures it.
    fn timed(
        &self,
        step: &'static str,
        costs: &mut Vec<Cost>,
        record: impl FnOnce(vk::CommandBuffer) -> Result<()>,
    ) -> Result<()> {
        let timestamps = Timestamps::new(&self.device, 1)?;
        let start = Instant::now();
        self.one_shot
            .run(|cmd| {
                if let Some(t) = &timestamps {
                    t.reset(cmd);
                    t.begin(cmd, 0);
                }
                let recorded = record(cmd);
                if let Some(t) = &timestamps {
                    t.end(cmd, 0);
                }
                recorded
            })
            .and_then(|recorded| recorded)
            .with_context(|| format!("environment precomputation '{step}'"))?;
        let cost = match &timestamps {
            Some(t) => Cost {
                step,
                ms: t.read_ms()?[0],
                gpu: true,
            },
            None => Cost {
                step,
                ms: start.elapsed().as_secs_f64() * 1e3,
                gpu: false,
            },
        };
        costs.push(cost);
        Ok(())
    }

    /// A source cube of `size`² faces with its mip chain down to 1², one view a level.
    fn source_cube(&self, size: u32) -> Result<(Image, Vec<ImageView>)> {
        let levels = crate::vk::mip_count(vk::Extent2D {
            width: size,
            height: size,
        });
        self.storage_cube(size, levels, "environment cube")
    }

    /// Level 0 of `cube` (a [`Self::source_cube`]) from `kind` (studio or equirect), then
    /// its mip chain, left readable by shaders; `steps` names the two in `costs`.
    fn source(
        &mut self,
        kind: KernelKind,
        (image, views): (Image, Vec<ImageView>),
        map: Option<&Equirect>,
        steps: [&'static str; 2],
        costs: &mut Vec<Cost>,
    ) -> Result<SourceCube> {
        let (size, levels) = (image.extent.width, image.mip_levels);
        let upload = map
            .map(|m| {
                Buffer::with_data(
                    &self.device,
                    &self.one_shot,
                    &m.texels,
                    vk::BufferUsageFlags::STORAGE_BUFFER,
                    "equirect",
                )
            })
            .transpose()?;
        let source_pool = self.pool(kind, 1)?;
        self.timed(steps[0], costs, |cmd| {
            transition_levels(
                &self.device,
                cmd,
                image.handle,
                image.all_levels(),
                ImageUse::UNDEFINED,
                ImageUse::COMPUTE_STORAGE,
            );
            let mut resources = vec![Resource::Storage(views[0].handle)];
            let mut push = Vec::new();
            if let (Some(buffer), Some(m)) = (&upload, map) {
                resources.push(Resource::Buffer(buffer));
                push.extend_from_slice(bytemuck::bytes_of(&[m.width, m.height]));
            }
            self.dispatch(cmd, kind, &source_pool, &resources, &push, cube_texels(size))
        })?;
        let mip_pool = self.pool(KernelKind::Downsample, levels.max(2) - 1)?;
        self.timed(steps[1], costs, |cmd| {
            for level in 1..levels {
                self.storage_barrier(cmd, &image);
                let resources = [
                    Resource::Storage(views[level as usize - 1].handle),
                    Resource::Storage(views[level as usize].handle),
                ];
                let side = (size >> level).max(1);
                self.dispatch(
                    cmd,
                    KernelKind::Downsample,
                    &mip_pool,
                    &resources,
                    &[],
                    cube_texels(side),
                )?;
            }
            transition_levels(
                &self.device,
                cmd,
                image.handle,
                image.all_levels(),
                ImageUse::COMPUTE_STORAGE,
                SHADING_READ,
            );
            Ok(())
        })?;
        Ok(SourceCube { image, key: None })
    }

    /// Orders one compute dispatch's image writes before the next one's reads.
    fn storage_barrier(&self, cmd: vk::CommandBuffer, image: &Image) {
        transition_levels(
            &self.device,
            cmd,
            image.handle,
            image.all_levels(),
            ImageUse::COMPUTE_STORAGE,
            ImageUse::COMPUTE_STORAGE,
        );
    }

    /// The studio's cube map with its mips: read from `disk` when this device and driver
    /// made it before, else made and stored.
    pub fn studio(&mut self, size: u32, disk: &DiskCache, costs: &mut Vec<Cost>) -> Result<SourceCube> {
        let start = Instant::now();
        let key = cache::key(&[
            shaders::ENV_STUDIO_COMP,
            shaders::ENV_DOWNSAMPLE_COMP,
            &size.to_le_bytes(),
            self.device.info.name.as_bytes(),
            self.device.info.driver.as_bytes(),
        ]);
        let cube = self.source_cube(size)?;
        if self.load_cached(disk, STUDIO_ENTRY, key, &cube.0, ("studio and mips (disk cache)", start), costs)? {
            return Ok(SourceCube {
                image: cube.0,
                key: Some(key),
            });
        }
        let studio = self.source(KernelKind::Studio, cube, None, ["studio", "mips"], costs)?;
        self.store_cached(disk, STUDIO_ENTRY, key, &studio.image)?;
        Ok(SourceCube {
            key: Some(key),
            ..studio
        })
    }

    /// An equirectangular map's cube map.
    pub fn equirect(&mut self, map: &Equirect, size: u32, costs: &mut Vec<Cost>) -> Result<SourceCube> {
        let cube = self.source_cube(size)?;
        self.source(KernelKind::Equirect, cube, Some(map), ["equirect to cube", "mips"], costs)
    }

    /// The cube map of a map whose sun was taken out (`sun::extract`), which the
    /// prefiltered cube is made from; its steps are named apart from the map's own cube's.
    pub fn sunless(&mut self, map: &Equirect, size: u32, costs: &mut Vec<Cost>) -> Result<SourceCube> {
        let cube = self.source_cube(size)?;
        self.source(KernelKind::Equirect, cube, Some(map), ["sunless equirect to cube", "sunless mips"], costs)
    }

    /// A cube map that compute shaders write level by level, with one view per level.
    fn storage_cube(&self, size: u32, levels: u32, name: &str) -> Result<(Image, Vec<ImageView>)> {
        let image = Image::cube(&self.device, size, levels, FORMAT, STORAGE_USAGE, name)?;
        let views = (0..levels)
            .map(|l| image.level_view(l))
            .collect::<Result<Vec<ImageView>>>()?;
        Ok((image, views))
    }

    /// The GGX-prefiltered radiance of `source` as octahedral maps, layer k filtered for
    /// `prefiltered_level_alpha` of level k. Read from `disk` when this device and driver
    /// prefiltered the same source texels before (the studio at every start, a map opened
    /// again), else computed (the prefiltered cube, then its levels resampled) and stored.
    pub fn prefilter(
        &mut self,
        source: &SourceCube,
        sampler: &Sampler,
        disk: &DiskCache,
        costs: &mut Vec<Cost>,
    ) -> Result<Image> {
        let side = vk::Extent2D {
            width: OCTAHEDRAL_SIDE,
            height: OCTAHEDRAL_SIDE,
        };
        let maps = Image::array_2d(&self.device, side, PREFILTERED_LEVELS, FORMAT, STORAGE_USAGE, "prefiltered maps")?;
        // Its mips follow from level 0 by `env_downsample.comp`, so level 0 stands for the
        // whole source where its own key does not (a map's cube, read back: 3 MiB at 256²).
        let start = Instant::now();
        let source_key = match source.key {
            Some(key) => key.to_le_bytes().to_vec(),
            None => self.read_level_bits(&source.image, 0)?,
        };
        let key = cache::key(&[
            &source_key,
            shaders::ENV_DOWNSAMPLE_COMP,
            shaders::ENV_PREFILTER_COMP,
            shaders::ENV_OCTAHEDRAL_COMP,
            &(0..PREFILTERED_LEVELS).flat_map(|level| prefiltered_side(level).to_le_bytes()).collect::<Vec<_>>(),
            &OCTAHEDRAL_SIDE.to_le_bytes(),
            &(0..PREFILTERED_LEVELS).flat_map(|level| prefilter_samples(level).to_le_bytes()).collect::<Vec<_>>(),
            &level_roughness().map(f32::to_le_bytes).concat(),
            self.device.info.name.as_bytes(),
            self.device.info.driver.as_bytes(),
        ]);
        if self.load_cached(disk, PREFILTERED_ENTRY, key, &maps, ("prefilter (disk cache)", start), costs)? {
            return Ok(maps);
        }
        let cubes = (0..PREFILTERED_LEVELS)
            .map(|level| self.storage_cube(prefiltered_side(level), 1, "prefiltered level"))
            .collect::<Result<Vec<_>>>()?;
        self.compute_prefiltered(source, sampler, &cubes, costs)?;
        self.resample_octahedral(&cubes, sampler, &maps, costs)?;
        self.store_cached(disk, PREFILTERED_ENTRY, key, &maps)?;
        Ok(maps)
    }

    /// Each prefiltered level's cube into its layer of `maps`, left readable by shaders.
    fn resample_octahedral(
        &mut self,
        cubes: &[(Image, Vec<ImageView>)],
        sampler: &Sampler,
        maps: &Image,
        costs: &mut Vec<Cost>,
    ) -> Result<()> {
        let pool = self.pool(KernelKind::Octahedral, PREFILTERED_LEVELS)?;
        let layers = (0..PREFILTERED_LEVELS)
            .map(|layer| maps.layer_view(layer))
            .collect::<Result<Vec<ImageView>>>()?;
        let texels = vk::Extent3D {
            width: OCTAHEDRAL_SIDE,
            height: OCTAHEDRAL_SIDE,
            depth: 1,
        };
        self.timed("octahedral maps", costs, |cmd| {
            transition_levels(
                &self.device,
                cmd,
                maps.handle,
                maps.all_levels(),
                ImageUse::UNDEFINED,
                ImageUse::COMPUTE_STORAGE,
            );
            for ((cube, _), layer) in cubes.iter().zip(&layers) {
                let resources = [Resource::Sampled(cube.view, sampler), Resource::Storage(layer.handle)];
                self.dispatch(cmd, KernelKind::Octahedral, &pool, &resources, &[], texels)?;
            }
            transition_levels(
                &self.device,
                cmd,
                maps.handle,
                maps.all_levels(),
                ImageUse::COMPUTE_STORAGE,
                SHADING_READ,
            );
            Ok(())
        })
    }

    /// Each level's cube in `cubes` (its image and its one level's storage view), left
    /// readable by shaders.
    fn compute_prefiltered(
        &mut self,
        source: &SourceCube,
        sampler: &Sampler,
        cubes: &[(Image, Vec<ImageView>)],
        costs: &mut Vec<Cost>,
    ) -> Result<()> {
        let pool = self.pool(KernelKind::Prefilter, PREFILTERED_LEVELS)?;
        let source_size = source.image.extent.width;
        let texel_solid_angle = 4.0 * std::f32::consts::PI / (6.0 * (source_size * source_size) as f32);
        self.timed("prefilter", costs, |cmd| {
            for (image, _) in cubes {
                let all = image.all_levels();
                transition_levels(&self.device, cmd, image.handle, all, ImageUse::UNDEFINED, ImageUse::COMPUTE_STORAGE);
            }
            for ((level, roughness), (_, views)) in (0..).zip(level_roughness()).zip(cubes) {
                let side = prefiltered_side(level);
                let min_lod = prefilter_min_lod(roughness, side, source_size);
                let push: [u32; 4] = [
                    roughness.to_bits(),
                    texel_solid_angle.to_bits(),
                    min_lod.to_bits(),
                    prefilter_samples(level),
                ];
                let resources = [
                    Resource::Sampled(source.image.view, sampler),
                    Resource::Storage(views[0].handle),
                ];
                self.dispatch(
                    cmd,
                    KernelKind::Prefilter,
                    &pool,
                    &resources,
                    bytemuck::bytes_of(&push),
                    cube_texels(side),
                )?;
            }
            for (image, _) in cubes {
                let all = image.all_levels();
                transition_levels(&self.device, cmd, image.handle, all, ImageUse::COMPUTE_STORAGE, SHADING_READ);
            }
            Ok(())
        })
    }

    /// The BRDF tables, `LUT_LAYERS` layers of `LUT_SIZE`: read from `disk` when this
    /// device and driver computed them before with this shader, else computed and stored.
    pub fn brdf_lut(&mut self, disk: &DiskCache, costs: &mut Vec<Cost>) -> Result<Image> {
        let start = Instant::now();
        let image = Image::array_2d(&self.device, LUT_SIZE, LUT_LAYERS, FORMAT, STORAGE_USAGE, "brdf tables")?;
        // The driver's arithmetic is part of the result, so its identity is in the key.
        let key = cache::key(&[
            shaders::ENV_BRDF_LUT_COMP,
            &LUT_SAMPLES.to_le_bytes(),
            &LUT_SIZE.width.to_le_bytes(),
            &LUT_SIZE.height.to_le_bytes(),
            &LUT_LAYERS.to_le_bytes(),
            self.device.info.name.as_bytes(),
            self.device.info.driver.as_bytes(),
        ]);
        if !self.load_cached(disk, LUT_ENTRY, key, &image, ("brdf tables (disk cache)", start), costs)? {
            self.compute_brdf_lut(&image, costs)?;
            self.store_cached(disk, LUT_ENTRY, key, &image)?;
        }
        Ok(image)
    }

    fn compute_brdf_lut(&mut self, image: &Image, costs: &mut Vec<Cost>) -> Result<()> {
        let pool = self.pool(KernelKind::BrdfLut, 1)?;
        self.timed("brdf tables", costs, |cmd| {
            transition_levels(
                &self.device,
                cmd,
                image.handle,
                image.all_levels(),
                ImageUse::UNDEFINED,
                ImageUse::COMPUTE_STORAGE,
            );
            let resources = [Resource::Storage(image.view)];
            self.dispatch(
                cmd,
                KernelKind::BrdfLut,
                &pool,
                &resources,
                &LUT_SAMPLES.to_ne_bytes(),
                vk::Extent3D {
                    width: LUT_SIZE.width,
                    height: LUT_SIZE.height,
                    depth: LUT_LAYERS,
                },
            )?;
            transition_levels(
                &self.device,
                cmd,
                image.handle,
                image.all_levels(),
                ImageUse::COMPUTE_STORAGE,
                SHADING_READ,
            );
            Ok(())
        })
    }

    /// A one-level cube of `size`² faces holding `texels` (RGB, face-major, rows from the
    /// top) rounded to RGBA16F, in `SHADING_READ`.
    pub fn upload_cube(&self, size: u32, texels: &[[f64; 3]], name: &str) -> Result<Image> {
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let image = Image::cube(&self.device, size, 1, FORMAT, usage, name)?;
        let bits: Vec<u8> = texels
            .iter()
            .flat_map(|t| [t[0], t[1], t[2], 1.0])
            .flat_map(|c| half::f16::from_f64(c).to_bits().to_ne_bytes())
            .collect();
        self.upload_levels(&image, &bits)?;
        Ok(image)
    }

    /// Fills `image` from `disk`'s entry `name` under `key` (as [`Self::store_cached`] wrote
    /// it) if the disk holds it whole, leaving it in `SHADING_READ`, with a cost `step` from
    /// `start`; whether it did.
    fn load_cached(
        &self,
        disk: &DiskCache,
        name: &str,
        key: u64,
        image: &Image,
        (step, start): (&'static str, Instant),
        costs: &mut Vec<Cost>,
    ) -> Result<bool> {
        let Some(cached) = disk.load(name, key).filter(|b| b.len() == level_bytes(image)) else {
            return Ok(false);
        };
        self.upload_levels(image, &cached)?;
        costs.push(Cost {
            step,
            ms: start.elapsed().as_secs_f64() * 1e3,
            gpu: false,
        });
        Ok(true)
    }

    /// Stores every level of `image`, in `SHADING_READ`, in `disk` under `name` and `key`.
    fn store_cached(&self, disk: &DiskCache, name: &str, key: u64, image: &Image) -> Result<()> {
        let levels = (0..image.mip_levels).map(|level| self.read_level_bits(image, level));
        disk.store(name, key, &levels.collect::<Result<Vec<_>>>()?.concat());
        Ok(())
    }

    /// Fills every level and layer of an image with `bits` (the levels' `read_level_bits`
    /// one after another), leaving it in `SHADING_READ`.
    fn upload_levels(&self, image: &Image, bits: &[u8]) -> Result<()> {
        let levels = transfer::split_levels(image, bits, TEXEL_BYTES)?;
        transfer::upload_image(&self.device, &self.one_shot, image, &levels, ImageUse::UNDEFINED, SHADING_READ)
    }

    /// Mip `level` of an RGBA16F image, every layer, as f32 texels (layer-major, rows from
    /// the top); the image is in `SHADING_READ` and is left there.
    pub fn read_level(&self, image: &Image, level: u32) -> Result<Vec<[f32; 4]>> {
        let bits = self.read_level_bits(image, level)?;
        let float = |t: &[u8]| half::f16::from_bits(u16::from_ne_bytes([t[0], t[1]])).to_f32();
        Ok(bits
            .chunks_exact(8)
            .map(|t| [float(&t[0..2]), float(&t[2..4]), float(&t[4..6]), float(&t[6..8])])
            .collect())
    }

    /// `read_level`'s texels as the image holds them: RGBA16F bits, native byte order.
    fn read_level_bits(&self, image: &Image, level: u32) -> Result<Vec<u8>> {
        transfer::read_level(&self.device, &self.one_shot, image, level, TEXEL_BYTES, SHADING_READ)
    }

    /// A device-local storage buffer holding `data`.
    pub fn upload_storage(&self, data: &[f32], name: &str) -> Result<Buffer> {
        Buffer::with_data(&self.device, &self.one_shot, data, vk::BufferUsageFlags::STORAGE_BUFFER, name)
    }

    /// Placeholders for descriptors an environment does not use (Vulkan needs every
    /// statically used binding valid): a 1² cube and a 1×1 table layer, cleared to 0.
    pub fn placeholders(&self) -> Result<(Image, Image)> {
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let unit = vk::Extent2D { width: 1, height: 1 };
        let cube = Image::cube(&self.device, 1, 1, FORMAT, usage, "environment placeholder cube")?;
        let table = Image::array_2d(&self.device, unit, 1, FORMAT, usage, "environment placeholder table")?;
        self.one_shot.run(|cmd| {
            cube.record_clear(cmd, SHADING_READ);
            table.record_clear(cmd, SHADING_READ);
        })?;
        Ok((cube, table))
    }
}
