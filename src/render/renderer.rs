//! The renderer: owns the device's passes and records a frame from the scene into the HDR
//! target, then through the display transform into an 8-bit image.

use std::cell::Cell;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use ash::vk;

use super::accumulate::{AccumulatePass, Accumulated, Accumulation, View};
use super::debug_view::DebugView;
use super::deferred::DeferredPass;
use super::environment::equirect::Equirect;
use super::environment::EnvironmentPass;
use super::exposure::ExposurePass;
use super::forward::{ForwardConstants, FrameChoices, ForwardPass};
use super::gpu_scene::GpuScene;
use super::ground_maps::{environment_ground, occlusion_ground, shadow_ground, GroundMaps, MapInputs};
use super::msaa::{sample_flag, supported_samples, MsaaPass};
use super::occlusion::{OcclusionMode, OcclusionPass};
use super::shadow::ShadowPass;
use super::split::Split;
use super::target::RenderTarget;
use super::tonemap::{TonemapPass, DISPLAY_FORMAT};
use super::vertex_light::{VertexLight, VertexLightInputs};
use crate::priority::low_priority_pool;
use crate::scene::occluders::Occluder;
use crate::scene::{Environment, MapSlot, Scene};
use crate::vk::{transition, Device, Image, ImageUse, OneShot, Readback, Timestamps};

/// The passes of a frame, in order; GPU times are reported with these names.
/// The shadow maps and the occlusion are drawn first but named after the older passes:
/// index 0 stays the forward pass. The MSAA resolve takes no time at one sample per pixel
/// (nothing runs).
pub const PASS_NAMES: [&str; 8] = [
    "forward",
    "skybox",
    "tonemap",
    "shadow",
    "resolve",
    "occlusion",
    "accumulate",
    "exposure",
];
const PASS_FORWARD: u32 = 0;
const PASS_SKYBOX: u32 = 1;
const PASS_TONEMAP: u32 = 2;
const PASS_SHADOW: u32 = 3;
const PASS_RESOLVE: u32 = 4;
const PASS_OCCLUSION: u32 = 5;
const PASS_ACCUMULATE: u32 = 6;
const PASS_EXPOSURE: u32 = 7;

/// Where the display transform writes (an image in use `from` before this frame), and
/// the exposure it applies before tone mapping. The frame covers `area` of the image,
/// which has the render target's size times `scale`: each texel is drawn as `scale`×`scale`
/// pixels (the viewer's reduced resolution; 1 otherwise).
pub struct DisplayOutput {
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub area: vk::Rect2D,
    pub from: ImageUse,
    pub exposure: f32,
    pub scale: u32,
}

/// One offscreen frame read back to the CPU.
pub struct OffscreenFrame {
    pub width: u32,
    pub height: u32,
    /// Linear radiance, RGBA, row-major from the top-left pixel.
    pub hdr: Vec<f32>,
    /// Tone-mapped sRGB, RGBA8; empty when the frame was drawn without its display
    /// transform ([`OffscreenTarget::hdr_only`]).
    pub display: Vec<u8>,
    /// Milliseconds per pass of [`PASS_NAMES`], when the device has timestamps.
    pub gpu_ms: Option<Vec<f64>>,
    /// The frames [`Renderer::render_accumulated`] drew for this mean: [`Frames::count`], or
    /// fewer where [`Frames::until`] ended it (1 as [`Renderer::read_offscreen`] reads it).
    pub frames: u32,
}

/// How many frames [`Renderer::render_accumulated`] averages, and a flag (Ctrl-C's) that,
/// once set, ends it after the frame it is drawing, keeping the mean of those drawn.
#[derive(Clone, Copy)]
pub struct Frames<'a> {
    pub count: u32,
    pub until: Option<&'a AtomicBool>,
}

impl From<u32> for Frames<'_> {
    fn from(count: u32) -> Self {
        Frames { count, until: None }
    }
}

pub struct Renderer {
    pub device: Arc<Device>,
    one_shot: OneShot,
    environment: EnvironmentPass,
    shadow: ShadowPass,
    ground_maps: GroundMaps,
    vertex_light: VertexLight,
    occlusion_pass: OcclusionPass,
    forward: ForwardPass,
    msaa: MsaaPass,
    accumulate: AccumulatePass,
    exposure: ExposurePass,
    tonemap: TonemapPass,
    /// One query pool per frame in flight; empty when the device has no timestamps.
    timestamps: Vec<Timestamps>,
    /// What the forward pass shows; `Shaded` except in the viewer's debug views.
    pub debug_view: DebugView,
    /// Draws every object with `floor.frag` instead of its material, single-sampled:
    /// `argil bench`'s measure of what the geometry and targets cost without shading.
    pub floor: bool,
    /// Wall time spent preparing environments (their precompute), with the pipelines made
    /// beside it when they were, for the startup's account.
    pub environment_time: Duration,
    /// Whether the last environment precompute had the forward pass's pipelines and
    /// subsurface table made beside it (`prepare_environment_and_pipelines`).
    pub pipelines_beside_environment: bool,
    /// Pipelines with the debug view, environment and reflection mode read from uniforms
    /// and every map sampled, instead of specialised to the frame: what the bench compares
    /// the specialised pipelines against.
    pub generic: bool,
    /// Whether the solids of a frame that can be (`FrameChoices::deferred`) are shaded once a
    /// pixel from their surfaces (deferred.rs) rather than in the forward pass.
    pub deferred: bool,
    /// Whether the ground reads its environment light from its environment map where it
    /// can (`ground_maps::environment_ground`) rather than finding the split sum at each of
    /// its pixels: what the bench compares.
    pub ground_environment: bool,
    /// The size of frame whose triangles decide which solids are deferred, where it is not
    /// the target's: a warm-up of a few pixels makes what the frames after it draw with.
    pub deferral_extent: Option<vk::Extent2D>,
    /// A frame drawn while the viewer is in use on a slow device, at a reduced size: where
    /// the ground's shadow or occlusion map is out of date (a light or an object moved),
    /// the ground finds its soft shadows or the objects' occlusion at its pixels, fewer at
    /// that size than the maps' texels, and the map is computed again by the next frame
    /// that is not a draft; out-of-date shadow maps are rendered at a quarter of the
    /// resolution (`ShadowPass::prepare`).
    pub draft: bool,
    /// Whether lights cast shadows (each light's `shadows` still applies); the viewer's toggle.
    pub shadows: bool,
    /// Whether a scene's `[occlusion] enabled` applies; the viewer's toggle.
    pub occlusion: bool,
    /// Which frames of a still view with the `sampled` reflection join a running mean
    /// (accumulate.rs); off, every frame is the same single frame.
    pub accumulation: Accumulation,
    /// Whether frames measure their luminance for [`Self::auto_exposure`]; the viewer's
    /// auto exposure of debug views.
    pub measure_exposure: bool,
    /// Draws the right part of frames with other materials and reflection mode (split.rs);
    /// the viewer's split view.
    pub split: Option<Split>,
    /// Scenes uploaded so far: the next upload's id.
    uploads: Cell<u64>,
}

/// The images an offscreen frame renders into and the buffers it is read back through,
/// kept across frames so that repeated frames time only the rendering.
pub struct OffscreenTarget {
    pub target: RenderTarget,
    hdr_readback: Readback,
    /// The tone-mapped image and its readback; `None` for frames kept as linear radiance.
    display: Option<(Image, Readback)>,
}

impl OffscreenTarget {
    /// A target for the linear frame and its tone-mapped display image.
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let mut offscreen = Self::hdr_only(device, extent)?;
        let display = Image::new_2d(
            device,
            extent,
            DISPLAY_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
            "display frame",
        )?;
        let readback = Readback::new(device, &display, 4)?;
        offscreen.display = Some((display, readback));
        Ok(offscreen)
    }

    /// A target for the linear frame alone: frames drawn into it skip the display
    /// transform (an EXR needs none).
    pub fn hdr_only(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let target = RenderTarget::new(device, extent)?;
        Ok(Self {
            hdr_readback: Readback::new(device, &target.color, 16)?,
            target,
            display: None,
        })
    }
}

impl Renderer {
    pub fn new(device: Arc<Device>, frames_in_flight: u32) -> Result<Self> {
        let timestamps = (0..frames_in_flight)
            .filter_map(|_| Timestamps::new(&device, PASS_NAMES.len() as u32).transpose())
            .collect::<Result<_>>()?;
        let environment = EnvironmentPass::new(&device)?;
        let one_shot = OneShot::new(&device)?;
        let shadow = ShadowPass::new(&device, frames_in_flight)?;
        let occlusion_pass = OcclusionPass::new(&device, &one_shot)?;
        let ground_maps_layout = GroundMaps::forward_set_layout(&device)?;
        let forward = ForwardPass::new(
            &device,
            &one_shot,
            frames_in_flight,
            environment.set_layout(),
            shadow.set_layout(),
            occlusion_pass.set_layout(),
            &ground_maps_layout,
        )?;
        let ground_maps = GroundMaps::new(
            &device,
            &one_shot,
            ground_maps_layout,
            forward.frame_layout(),
            environment.set_layout(),
            shadow.set_layout(),
        )?;
        let vertex_light = VertexLight::new(
            &device,
            forward.frame_layout(),
            environment.set_layout(),
            shadow.set_layout(),
            occlusion_pass.set_layout(),
            ground_maps.set_layout(),
            ground_maps.set(),
        )?;
        Ok(Self {
            forward,
            shadow,
            ground_maps,
            vertex_light,
            msaa: MsaaPass::new(&device, frames_in_flight)?,
            occlusion_pass,
            one_shot,
            environment,
            accumulate: AccumulatePass::new(&device, frames_in_flight)?,
            exposure: ExposurePass::new(&device, frames_in_flight)?,
            tonemap: TonemapPass::new(&device, frames_in_flight)?,
            timestamps,
            debug_view: DebugView::Shaded,
            floor: false,
            generic: false,
            deferred: true,
            ground_environment: true,
            deferral_extent: None,
            draft: false,
            environment_time: Duration::ZERO,
            pipelines_beside_environment: false,
            shadows: true,
            occlusion: true,
            accumulation: Accumulation::Off,
            measure_exposure: false,
            split: None,
            uploads: Cell::new(0),
            device,
        })
    }

    /// Wall time spent creating the forward pass's pipelines so far.
    pub fn pipeline_time(&self) -> Duration {
        self.forward.pipeline_time
    }

    /// Builds the environment from `map`, decoded from the file at `path`, at the next frame
    /// (see `EnvironmentPass::use_map`): for a scene loaded again from its files.
    pub fn use_environment_map(&mut self, path: PathBuf, map: Equirect) {
        self.environment.use_map(path, map);
    }

    /// Uploads the scene's meshes and textures.
    pub fn upload(&self, scene: &Scene) -> Result<GpuScene> {
        let id = self.uploads.replace(self.uploads.get() + 1);
        GpuScene::upload(&self.device, &self.one_shot, scene, self.forward.material_layout(), id)
    }

    /// Uploads textures `indices` of `scene` into `gpu`, its upload with stand-ins for
    /// them (see [`GpuScene::replace_textures`]).
    pub fn replace_textures(&self, gpu: &mut GpuScene, scene: &Scene, indices: &[usize]) -> Result<()> {
        gpu.replace_textures(&self.device, &self.one_shot, scene, indices)
    }

    /// Which of `scene.textures` the frames of `scene` sample, by index: the maps of the
    /// objects' materials that their pipelines read (a specialised pipeline only those whose
    /// effect it draws, such as the noise map in the report's reflection alone; the generic
    /// one every map). With a split view, every texture.
    pub fn sampled_textures(&self, scene: &Scene) -> Vec<bool> {
        let mut sampled = vec![self.split.is_some(); scene.textures.len()];
        let (view, specialize, specular_aa) = (self.debug_view, !self.generic, scene.antialiasing.specular);
        for object in &scene.objects {
            let m = &scene.materials[object.material];
            let constants = ForwardConstants::new(m, &scene.environment, view, specialize, specular_aa);
            for slot in MapSlot::ALL.into_iter().filter(|&slot| constants.samples(slot)) {
                if let Some(map) = &m.maps[slot] {
                    sampled[map.texture] = true;
                }
            }
        }
        sampled
    }

    /// Samples per pixel that frames of `scene` are drawn with: its `[antialiasing] msaa`,
    /// or the largest count below it the device supports; 1 for the floor.
    pub fn msaa_samples(&self, scene: &Scene) -> u32 {
        if self.floor {
            1
        } else {
            supported_samples(&self.device, scene.antialiasing.msaa)
        }
    }

    /// How many times the shadow maps have been rendered: once per change of the lights,
    /// objects or settings, not per frame.
    pub fn shadow_map_renders(&self) -> u64 {
        self.shadow.renders()
    }

    /// How many times the ground's light map has been made (computed, or read from the disk
    /// cache): once per change of the lights, the ground or the shadow maps, not per frame.
    pub fn ground_light_renders(&self) -> u64 {
        self.ground_maps.light_renders()
    }

    /// How many times what the draws read at their vertices has been made (computed, or read
    /// from the disk cache): once per change of the ground's light map, the environment, the
    /// shadow maps or where the objects stand, not per frame.
    pub fn vertex_light_computes(&self) -> u64 {
        self.vertex_light.computes()
    }

    /// How many of the last prepared frame's objects are shaded from the G-buffer (deferred.rs).
    pub fn deferred_objects(&self) -> usize {
        self.forward.deferred_objects()
    }

    /// How many pipelines draw those objects' surfaces into the G-buffer.
    pub fn deferred_surface_pipelines(&self) -> usize {
        self.forward.deferred_surface_pipelines()
    }

    /// How many compute pipelines that pass keeps: two at most, whatever it was computed with.
    pub fn vertex_light_pipelines(&self) -> usize {
        self.vertex_light.pipeline_count()
    }

    /// How many times the ground's occlusion map has been made: once per change of the
    /// objects, the ground or the environment, not per frame.
    pub fn ground_occlusion_renders(&self) -> u64 {
        self.ground_maps.occlusion_renders()
    }

    /// How many times the ground's environment map has been made: once per change of the
    /// ground's material or the environment, not per frame.
    pub fn ground_environment_renders(&self) -> u64 {
        self.ground_maps.environment_renders()
    }

    /// How many times the ground's shadow map has been made: once per change of the lights,
    /// the ground, the shadow maps or the taps, not per frame.
    pub fn ground_shadow_renders(&self) -> u64 {
        self.ground_maps.shadow_renders()
    }

    /// Writes the per-frame data of `slot` and creates what the frame needs; the caller has
    /// waited for the slot's previous frame.
    pub fn prepare(
        &mut self,
        slot: usize,
        scene: &Scene,
        gpu: &GpuScene,
        target: &RenderTarget,
        output_format: vk::Format,
    ) -> Result<()> {
        if let Some(split) = &self.split {
            split.check(scene)?;
        }
        let samples = self.msaa_samples(scene);
        // The floor measures geometry and targets alone: no occlusion under it.
        let occlusion = OcclusionMode::of(&scene.occlusion, self.occlusion && !self.floor);
        let occluders = scene.occluders();
        // Without spheres to read, the pipelines hold no object occlusion.
        let objects = self.occlusion && !self.floor && scene.occlusion.objects && !occluders.is_empty();
        // A draft reads the ground's maps it finds out of date at the ground's pixels instead.
        // The environment's generation is the last frame's: where this frame's environment
        // changes, the map is computed, as in a frame that is not a draft.
        let last_environment = self.environment.generation();
        let ground = occlusion_ground(scene, objects, self.split.is_some()).filter(|&ground| {
            !self.draft || self.ground_maps.occlusion_map_current(scene, ground, &occluders, last_environment)
        });
        // The shadow pass first: the ground's shadow map follows its generation.
        self.shadow.prepare(slot, scene, gpu, self.shadows, self.draft)?;
        let shadow_ground = shadow_ground(scene, self.shadows && !self.floor).filter(|&ground| {
            !self.draft || self.ground_maps.shadow_map_current(scene, ground, self.shadow.generation())
        });
        // A split frame's parts light the ground differently; the map holds one light.
        let whole = !self.floor && self.split.is_none();
        let allowed = self.ground_environment && whole && self.ground_maps.environment_filtered();
        let environment_ground = environment_ground(scene, allowed).filter(|&ground| {
            !self.draft || self.ground_maps.environment_map_current(scene, ground, last_environment)
        });
        let choices = FrameChoices {
            debug_view: self.debug_view,
            floor: self.floor,
            specialize: !self.generic,
            samples: sample_flag(samples),
            occlusion,
            objects,
            ground_map: ground,
            ground_shadows: shadow_ground,
            // Without a sun, once it is known (prepare_environment_and_pipelines).
            ground_environment: environment_ground,
            // The environment's, once it is known (prepare_environment_and_pipelines).
            sun: false,
            deferred: self.deferred
                && DeferredPass::supported(&self.device)
                && samples == 1
                && self.split.is_none()
                && self.debug_view == DebugView::Shaded
                && !self.generic
                && !self.floor,
            extent: self.deferral_extent.unwrap_or(target.extent),
        };
        // The shadow pass found which objects' draws need shadow code.
        let shadowing = self.shadow.receivers().to_vec();
        let choices = self.prepare_environment_and_pipelines(scene, gpu, &occluders, &shadowing, choices)?;
        self.environment.prepare_skybox(sample_flag(samples))?;
        self.msaa.prepare(slot, target, samples)?;
        self.occlusion_pass.prepare(scene, target.extent, occlusion)?;
        let switches = [self.shadows, self.floor, self.generic, self.occlusion];
        let view = (self.accumulation != Accumulation::Off)
            .then(|| {
                View::of(
                    scene,
                    gpu,
                    target.extent,
                    self.debug_view,
                    switches,
                    self.split.as_ref(),
                )
            })
            .flatten();
        let sample_set = self.accumulate.prepare(slot, view, self.accumulation, target)?;
        self.forward
            .prepare(slot, scene, self.split.as_ref(), target.aspect(), sample_set, &occluders, &choices)?;
        self.forward.prepare_deferred(slot, target.extent)?;
        let inputs = MapInputs {
            frame: self.forward.frame_data(),
            shadows: &|| self.shadow.disk_key(scene),
            environment: self.environment.disk_key(),
        };
        let (environment, shadows) = (self.environment.generation(), self.shadow.generation());
        self.ground_maps.prepare(
            scene,
            &occluders,
            shadows,
            ground,
            shadow_ground,
            choices.ground_environment,
            environment,
            &self.one_shot,
            &inputs,
        )?;
        let (shaded, generic) = (!self.floor, self.generic);
        let occlusion = self.forward.object_occlusions();
        let vertex_light_inputs = VertexLightInputs {
            light_key: self.ground_maps.light_key(),
            light_content: self.ground_maps.light_content(),
            maps: &inputs,
            environment_generation: environment,
            shadow_generation: shadows,
            shadowing: &shadowing,
            occlusion: &occlusion,
        };
        let (ground_set, one_shot) = (self.ground_maps.set(), &self.one_shot);
        self.vertex_light.prepare(scene, gpu, shaded, generic, &vertex_light_inputs, ground_set, one_shot)?;
        self.exposure.prepare(slot, target, self.measure_exposure)?;
        self.tonemap.prepare(slot, target, output_format)
    }

    /// The environment's precompute and the forward pass's pipelines (and subsurface table)
    /// for `choices`, but the sun, which comes from the environment. The precompute runs on
    /// the device's queue, which lavapipe's one thread serves (compiling its shaders there
    /// too), while this thread waits: where the sun is known before it, the pipelines and
    /// the table are made meanwhile, at a low priority (src/priority.rs), so that the
    /// queue's thread keeps most of its core. The ground's maps make theirs once they know
    /// which maps the disk cache does not hold (`GroundMaps::prepare`). Returns `choices`
    /// with the sun.
    fn prepare_environment_and_pipelines(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        occluders: &[Occluder],
        shadowing: &[u32],
        choices: FrameChoices,
    ) -> Result<FrameChoices> {
        let start = Instant::now();
        let split = self.split.as_ref();
        let plan = self.environment.plan(scene, split);
        let changes = plan.changes();
        let beside = EnvironmentPass::sun_before_prepare(scene).filter(|_| changes);
        if changes {
            self.pipelines_beside_environment = beside.is_some();
        }
        let Some(sun) = beside else {
            self.environment.prepare(scene, plan)?;
            self.environment_time += start.elapsed();
            let choices = choices.with_sun(self.environment.has_sun());
            self.forward.prepare_pipelines(scene, gpu, split, occluders, shadowing, &choices, &self.one_shot)?;
            return Ok(choices);
        };
        let choices = choices.with_sun(sun);
        let pool = low_priority_pool()?;
        let (environment, forward, one_shot) = (&mut self.environment, &mut self.forward, &self.one_shot);
        let make_pipelines = || forward.prepare_pipelines(scene, gpu, split, occluders, shadowing, &choices, one_shot);
        let (precomputed, pipelines) = std::thread::scope(|threads| {
            let precompute = threads.spawn(move || environment.prepare(scene, plan));
            let pipelines = pool.install(make_pipelines);
            (precompute.join(), pipelines)
        });
        self.environment_time += start.elapsed();
        precomputed.unwrap_or_else(|panic| std::panic::resume_unwind(panic))?;
        pipelines.map(|()| choices)
    }

    /// Records the whole frame: forward pass and skybox into `target` (or into multisampled
    /// images resolved into it), display transform into `output` (when there is one), which
    /// is left as a colour attachment. `target.color` is left readable by shaders.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        scene: &Scene,
        gpu: &GpuScene,
        target: &RenderTarget,
        output: Option<&DisplayOutput>,
    ) -> Result<()> {
        let d = &self.device;
        if let Some(t) = self.timestamps.get(slot) {
            t.reset(cmd);
        }
        transition(
            d,
            cmd,
            target.color.handle,
            target.color.aspect,
            ImageUse::UNDEFINED,
            ImageUse::COLOR_ATTACHMENT,
        );
        let draw = self.msaa.draw_target(slot, target);
        self.msaa.begin(cmd, slot);
        transition(
            d,
            cmd,
            draw.depth.handle,
            draw.depth.aspect,
            ImageUse::UNDEFINED,
            ImageUse::DEPTH_ATTACHMENT,
        );
        // The ground's light and shadow maps are computed from the shadow maps, and timed
        // with them, as is the bounce at the vertices from the light map; its occlusion map
        // with the occlusion.
        self.timed(cmd, slot, PASS_SHADOW, || {
            self.shadow.record(cmd, scene, gpu)?;
            let frame_set = self.forward.frame_set(slot);
            self.ground_maps.record_from_shadow_maps(cmd, frame_set, self.shadow.set(slot));
            let (environment_set, ground_set) = (self.environment.set(), self.ground_maps.set());
            let shadow_set = self.shadow.set(slot);
            self.vertex_light.record(cmd, scene, gpu, frame_set, environment_set, shadow_set, ground_set);
            Ok(())
        })?;
        self.timed(cmd, slot, PASS_OCCLUSION, || {
            let frame_set = self.forward.frame_set(slot);
            self.ground_maps.record_from_environment(cmd, frame_set, self.environment.set());
            self.occlusion_pass.record(cmd, scene, gpu)
        })?;
        self.timed(cmd, slot, PASS_FORWARD, || {
            self.forward.record(
                cmd,
                slot,
                scene,
                self.split.as_ref(),
                gpu,
                draw,
                background(scene),
                self.environment.set(),
                self.shadow.set(slot),
                self.occlusion_pass.set(),
                self.ground_maps.set(),
            )
        })?;
        self.timed(cmd, slot, PASS_SKYBOX, || {
            self.environment.record_skybox(cmd, draw, &scene.camera)
        })?;
        self.timed(cmd, slot, PASS_RESOLVE, || self.msaa.record(cmd, slot, target))?;
        let color = self.timed(cmd, slot, PASS_ACCUMULATE, || self.accumulate.record(cmd, slot, target))?;

        transition(
            d,
            cmd,
            target.color.handle,
            target.color.aspect,
            color,
            ImageUse::SHADER_READ,
        );
        self.timed(cmd, slot, PASS_EXPOSURE, || {
            self.exposure.record(cmd, slot, target);
            Ok(())
        })?;
        // Without an output the pass is still timed (at nothing), as every query is read.
        self.timed(cmd, slot, PASS_TONEMAP, || {
            let Some(output) = output else { return Ok(()) };
            transition(
                d,
                cmd,
                output.image,
                vk::ImageAspectFlags::COLOR,
                output.from,
                ImageUse::COLOR_ATTACHMENT,
            );
            self.tonemap.record(
                cmd,
                slot,
                output.view,
                output.format,
                output.area,
                output.exposure,
                output.scale,
            )
        })
    }

    /// How many frames have been recorded with their display transform.
    pub fn tonemap_records(&self) -> u64 {
        self.tonemap.records()
    }

    /// Records `pass` between the two timestamps that time it, when the device has them.
    fn timed<R>(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        pass: u32,
        record: impl FnOnce() -> Result<R>,
    ) -> Result<R> {
        let timestamps = self.timestamps.get(slot);
        if let Some(t) = timestamps {
            t.begin(cmd, pass);
        }
        let recorded = record()?;
        if let Some(t) = timestamps {
            t.end(cmd, pass);
        }
        Ok(recorded)
    }

    /// The exposure that the luminance measured a frame or two ago asks for (see
    /// exposure.rs); `None` until a measured frame has been read back.
    pub fn auto_exposure(&self) -> Option<f32> {
        self.exposure.auto_exposure()
    }

    /// The luminance histogram behind [`Self::auto_exposure`].
    pub fn luminance_histogram(&self) -> Option<&[u32]> {
        self.exposure.histogram()
    }

    /// How far the running mean of the frame prepared last has come; `None` when that
    /// frame was not accumulated.
    pub fn accumulated(&self) -> Option<Accumulated> {
        self.accumulate.accumulated()
    }

    /// The environment's GPU resources and what precomputing them cost.
    pub fn environment(&self) -> &EnvironmentPass {
        &self.environment
    }

    /// GPU milliseconds per pass of the last completed frame of `slot`.
    pub fn gpu_times(&self, slot: usize) -> Result<Option<Vec<f64>>> {
        self.timestamps.get(slot).map(Timestamps::read_ms).transpose()
    }

    /// Renders one frame of `scene` offscreen and reads both the HDR and the display
    /// image back.
    pub fn render_offscreen(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        extent: vk::Extent2D,
        exposure: f32,
    ) -> Result<OffscreenFrame> {
        let offscreen = OffscreenTarget::new(&self.device, extent)?;
        let gpu_ms = self.draw_offscreen(scene, gpu, &offscreen, exposure)?;
        self.read_offscreen(&offscreen, gpu_ms)
    }

    /// Renders `frames` frames of `scene` into one target, accumulating the `sampled`
    /// reflection's running mean from a fresh start (one frame is
    /// [`Self::render_offscreen`]'s image), and reads the mean back with the last frame's
    /// GPU times. With `exposure`, also the display image at that exposure; without, the
    /// linear frame alone, and the display transform does not run.
    pub fn render_accumulated<'a>(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        extent: vk::Extent2D,
        exposure: Option<f32>,
        frames: impl Into<Frames<'a>>,
    ) -> Result<OffscreenFrame> {
        let offscreen = self.offscreen_target(extent, exposure.is_some())?;
        self.render_accumulated_into(scene, gpu, &offscreen, exposure.unwrap_or(1.0), frames)
    }

    /// A target for offscreen frames at `extent`, with a display image when `display`.
    pub fn offscreen_target(&self, extent: vk::Extent2D, display: bool) -> Result<OffscreenTarget> {
        if display {
            OffscreenTarget::new(&self.device, extent)
        } else {
            OffscreenTarget::hdr_only(&self.device, extent)
        }
    }

    /// Creates what a frame of `scene` into `offscreen` needs before it draws (the
    /// environment's precompute, the subsurface table, the pipelines) and draws nothing, so
    /// `gpu` may still hold stand-ins for the scene's builtin maps.
    pub fn prepare_offscreen(&mut self, scene: &Scene, gpu: &GpuScene, offscreen: &OffscreenTarget) -> Result<()> {
        self.prepare(0, scene, gpu, &offscreen.target, DISPLAY_FORMAT)
    }

    /// [`Self::render_accumulated`] into `offscreen`, its display image (if it has one) at
    /// `exposure`.
    pub fn render_accumulated_into<'a>(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        offscreen: &OffscreenTarget,
        exposure: f32,
        frames: impl Into<Frames<'a>>,
    ) -> Result<OffscreenFrame> {
        let Frames { count, until } = frames.into();
        let accumulation = if count > 1 {
            Accumulation::Unlimited
        } else {
            Accumulation::Off
        };
        let accumulation = std::mem::replace(&mut self.accumulation, accumulation);
        self.accumulate.reset();
        let (mut gpu_ms, mut drawn) = (Ok(None), 0);
        while drawn < count {
            gpu_ms = self.draw_offscreen(scene, gpu, offscreen, exposure);
            if gpu_ms.is_err() {
                break;
            }
            drawn += 1;
            if until.is_some_and(|flag| flag.load(Ordering::Relaxed)) {
                break;
            }
        }
        self.accumulation = accumulation;
        let frame = self.read_offscreen(offscreen, gpu_ms?)?;
        Ok(OffscreenFrame { frames: drawn, ..frame })
    }

    /// Renders one frame of `scene` into `offscreen`, waits for it, and returns its GPU
    /// milliseconds per pass of [`PASS_NAMES`] (when the device has timestamps).
    pub fn draw_offscreen(
        &mut self,
        scene: &Scene,
        gpu: &GpuScene,
        offscreen: &OffscreenTarget,
        exposure: f32,
    ) -> Result<Option<Vec<f64>>> {
        self.prepare(0, scene, gpu, &offscreen.target, DISPLAY_FORMAT)?;
        let output = offscreen.display.as_ref().map(|(display, _)| DisplayOutput {
            image: display.handle,
            view: display.view,
            format: DISPLAY_FORMAT,
            area: vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: offscreen.target.extent,
            },
            from: ImageUse::UNDEFINED,
            exposure,
            scale: 1,
        });
        self.one_shot
            .run(|cmd| self.record(cmd, 0, scene, gpu, &offscreen.target, output.as_ref()))??;
        self.ground_maps.store_computed(&self.one_shot)?;
        self.vertex_light.store_computed(&self.one_shot)?;
        self.gpu_times(0)
    }

    /// Reads back the frame [`Self::draw_offscreen`] last drew into `offscreen`.
    pub fn read_offscreen(&self, offscreen: &OffscreenTarget, gpu_ms: Option<Vec<f64>>) -> Result<OffscreenFrame> {
        self.one_shot.run(|cmd| {
            offscreen
                .hdr_readback
                .record(&self.device, cmd, &offscreen.target.color, ImageUse::FRAGMENT_READ);
            if let Some((display, readback)) = &offscreen.display {
                readback.record(&self.device, cmd, display, ImageUse::COLOR_ATTACHMENT);
            }
        })?;
        let extent = offscreen.target.extent;
        let display = match &offscreen.display {
            Some((_, readback)) => readback.bytes()?.to_vec(),
            None => Vec::new(),
        };
        Ok(OffscreenFrame {
            width: extent.width,
            height: extent.height,
            hdr: bytemuck::pod_collect_to_vec(offscreen.hdr_readback.bytes()?),
            display,
            gpu_ms,
            frames: 1,
        })
    }
}

/// What pixels that no object covers show before the skybox: the uniform environment's
/// radiance, or black; alpha is coverage, so 0.
fn background(scene: &Scene) -> [f32; 4] {
    match &scene.environment {
        Environment::Uniform { radiance, .. } => radiance.extend(0.0).to_array(),
        _ => [0.0; 4],
    }
}
