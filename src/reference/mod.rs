//! `argil reference`: the ground truth of a scene, by Monte Carlo integration on the CPU in
//! f64, from the same scene file, camera, meshes, materials (the f64 twins in
//! [`crate::brdf`]), maps, lights and environment as the real-time renderer.
//!
//! - [`bvh`]: SAH bounding volume hierarchy over every triangle.
//! - [`world`]: the scene in world space; the surface at a hit, as the shaders see it.
//! - [`texture`], [`environment`]: maps and the environment, read at full resolution.
//! - [`sampling`]: the material's lobes sampled, and their pdfs.
//! - [`integrator`]: the light along one camera ray, for each [`Transport`].
//!
//! Images are estimated as two independent halves (even and odd samples), whose
//! difference measures the noise of their mean: [`Reference::noise`].

pub mod bvh;
#[cfg(test)]
mod chi2;
pub mod environment;
pub mod integrator;
pub mod sampling;
pub mod texture;
pub mod world;

use std::fmt;
use std::str::FromStr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use glam::DVec3;
use rayon::prelude::*;

use crate::error::Interrupted;
use crate::render::environment::equirect;
use crate::rng::Rng;
use crate::scene::Scene;
use environment::EnvironmentLight;
use integrator::{CameraRays, Integrator};
use world::World;

/// Which light paths are integrated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Transport {
    /// Each light through the material at the first surface, without visibility: what
    /// the real-time renderer computes, so that comparing with it isolates its
    /// approximations (split sum, irradiance cube, texture filtering).
    Direct,
    /// Direct light with visibility: shadows from the point lights and occlusion of the
    /// environment.
    Shadows,
    /// Paths of any length: inter-reflection, with Russian roulette.
    #[default]
    Full,
}

/// Where in a pixel camera rays go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// Uniformly over the pixel's area: the image a renderer should converge to.
    #[default]
    Box,
    /// The pixel's centre only, as the rasteriser samples without anti-aliasing, so that
    /// aliasing can be told apart from shading.
    Center,
}

macro_rules! names {
    ($type:ty, $what:literal, $($variant:path => $name:literal),+) => {
        impl $type {
            pub const NAMES: &'static [&'static str] = &[$($name),+];
        }
        impl fmt::Display for $type {
            fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(match self { $($variant => $name),+ })
            }
        }
        impl FromStr for $type {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($name => Ok($variant),)+
                    _ => Err(format!(concat!("unknown ", $what, " {:?}; expected one of {}"), s, Self::NAMES.join(", "))),
                }
            }
        }
    };
}

names!(Transport, "transport", Transport::Direct => "direct", Transport::Shadows => "shadows", Transport::Full => "full");
names!(Filter, "filter", Filter::Box => "box", Filter::Center => "center");

/// How the environment's light at a surface is sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sampling {
    /// Both by the environment's luminance and by the material's lobes, weighted by the
    /// power heuristic (a uniform environment by the lobes alone).
    #[default]
    Mis,
    /// By the material's lobes only.
    Material,
    /// By the environment's luminance only.
    Light,
}

names!(Sampling, "sampling", Sampling::Mis => "mis", Sampling::Material => "material", Sampling::Light => "light");

/// What the materials' subsurface models are to the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SubsurfaceTransport {
    /// The material's own model, evaluated as part of its BRDF as the shader does.
    #[default]
    Model,
    /// Each scattering material (a subsurface model with a `scatter_radius`) is a
    /// homogeneous medium inside its mesh, walked through at random (`full` transport).
    Volume,
}

names!(SubsurfaceTransport, "subsurface", SubsurfaceTransport::Model => "model", SubsurfaceTransport::Volume => "volume");

/// When to stop sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// This many samples per pixel.
    Samples(u32),
    /// When [`Reference::noise`] falls below this, or at `max_samples` per pixel.
    Noise { target: f64, max_samples: u32 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub transport: Transport,
    pub filter: Filter,
    pub sampling: Sampling,
    pub subsurface: SubsurfaceTransport,
    pub stop: Stop,
    pub seed: u64,
    /// Longest path, in surfaces, for `Full`.
    pub max_depth: u32,
    /// Stop at the pass that would end after this long, whatever `stop` says: passes are
    /// sized by the time the ones before took, so every pixel keeps the same samples.
    pub max_time: Option<Duration>,
}

impl Settings {
    pub const DEFAULT_MAX_DEPTH: u32 = 64;
}

/// Why sampling ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The settings' [`Stop`] was met.
    Stopped,
    /// The next pass would have ended after [`Settings::max_time`].
    TimeLimit,
    /// [`Progress::interrupted`]: the rows begun were finished, the rest left.
    Interrupted,
}

/// A finished reference image.
pub struct Reference {
    pub width: u32,
    pub height: u32,
    /// Linear radiance, RGBA32F rows from the top; alpha is the fraction of the pixel's
    /// samples that hit an object.
    pub rgba: Vec<f32>,
    /// Samples per pixel: every pixel has this many, and an interrupted pass's rows up to
    /// `most_samples`.
    pub samples: u32,
    pub most_samples: u32,
    pub ending: Ending,
    /// The estimated relative RMS error of the image over covered pixels:
    /// √(Σ ((A − B)/2)²) / √(Σ ((A + B)/2)²) for the half images A and B, each channel of
    /// each covered pixel counted. ((A − B)/2)² is an unbiased estimate of the variance of
    /// their mean (A + B)/2, the image; 0 where sampling is deterministic.
    pub noise: f64,
    pub rays: u64,
    pub elapsed: Duration,
}

impl Reference {
    pub fn rays_per_second(&self) -> f64 {
        self.rays as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    /// The `argil.*` EXR header attributes that say how this image was made (read back by
    /// `argil compare`).
    pub fn exr_attributes(&self, settings: &Settings) -> [(&'static str, String); 8] {
        [
            ("argil.transport", settings.transport.to_string()),
            ("argil.filter", settings.filter.to_string()),
            ("argil.sampling", settings.sampling.to_string()),
            ("argil.subsurface", settings.subsurface.to_string()),
            ("argil.spp", self.samples.to_string()),
            ("argil.noise", format!("{:e}", self.noise)),
            ("argil.seed", settings.seed.to_string()),
            ("argil.max_depth", settings.max_depth.to_string()),
        ]
    }
}

/// Progress: samples per pixel done so far of the total expected now (which changes as a
/// noise target's estimate does).
pub trait Progress: Sync {
    fn update(&self, done: u64, total: u64);

    /// Whether the image is no longer wanted: rendering stops with an error.
    fn cancelled(&self) -> bool {
        false
    }

    /// Whether to end with the samples taken: the rows of the pass already begun are
    /// finished, the others keep the passes before (Ctrl-C in `argil reference`).
    fn interrupted(&self) -> bool {
        false
    }
}

impl Progress for () {
    fn update(&self, _: u64, _: u64) {}
}

/// Samples per pixel of the first pass; passes end where the noise is measured, and
/// each is at most as long as all before it.
const PASS_SAMPLES: u32 = 16;

/// One pixel's sums over its samples, kept apart for the two half images: sample k goes
/// to half k mod 2.
#[derive(Clone, Copy, Default)]
struct PixelSums {
    radiance: [DVec3; 2],
    hits: [u32; 2],
}

/// Samples of half 0 (the even ones) among samples 0..n.
fn even_samples(n: u32) -> u32 {
    n.div_ceil(2)
}

/// Renders the reference of `scene`.
pub fn render(scene: &Scene, settings: &Settings, progress: &dyn Progress) -> Result<Reference> {
    if settings.subsurface == SubsurfaceTransport::Volume && settings.transport != Transport::Full {
        bail!("--subsurface volume needs --transport full: light walks through the clay");
    }
    let start = Instant::now();
    let world = World::new(scene);
    let environment = EnvironmentLight::new(&scene.environment)
        .map_err(|e| equirect::in_scene_file(e, scene))
        .context("cannot prepare the environment for the reference")?;
    let integrator = Integrator::new(scene, &world, environment.as_ref(), settings);
    let camera = CameraRays::new(&scene.camera, settings.width, settings.height);
    let (width, height) = (settings.width as usize, settings.height as usize);
    let mut sums = vec![PixelSums::default(); width * height];
    // Samples per pixel of each row: the same in all, but where an interruption left a
    // pass's rows unbegun.
    let mut row_samples = vec![0u32; height];
    let ray_count = AtomicU64::new(0);
    let max_samples = match settings.stop {
        Stop::Samples(n) => n.max(1),
        Stop::Noise { max_samples, .. } => max_samples.max(1),
    };
    // Under a time limit the first pass is the fewest samples a noise estimate needs, so
    // that the passes after it can be sized to the limit early.
    let first_pass = if settings.max_time.is_some() { 2 } else { PASS_SAMPLES };
    let mut expected = match settings.stop {
        Stop::Samples(_) => max_samples,
        Stop::Noise { .. } => first_pass.min(max_samples),
    };
    let (mut done, mut pass, mut noise, mut ending) = (0u32, 0u64, f64::INFINITY, Ending::Stopped);
    let tracing = Instant::now();
    while done < expected {
        let first = done;
        let mut count = (expected - done).min(first_pass.max(done));
        if let Some(limit) = settings.max_time.filter(|_| done > 0) {
            let per_sample = tracing.elapsed().as_secs_f64() / f64::from(done);
            let fits = (limit.saturating_sub(start.elapsed()).as_secs_f64() / per_sample).floor();
            if fits < 1.0 {
                ending = Ending::TimeLimit;
                break;
            }
            count = count.min(fits as u32);
        }
        let rows_done = AtomicU64::new(0);
        sums.par_chunks_mut(width).zip(row_samples.par_iter_mut()).enumerate().for_each(|(y, (row, samples))| {
            if progress.cancelled() || progress.interrupted() {
                return;
            }
            let mut traced = 0;
            for (x, pixel) in row.iter_mut().enumerate() {
                let index = (y * width + x) as u64;
                let mut rng = Rng::new(settings.seed ^ (pass << 40) ^ index);
                for k in first..first + count {
                    let (sx, sy) = match settings.filter {
                        Filter::Box => (rng.uniform(), rng.uniform()),
                        Filter::Center => (0.5, 0.5),
                    };
                    let (origin, dir) = camera.ray(x as f64 + sx, y as f64 + sy, settings.width, settings.height);
                    let (near, far) = (f64::from(scene.camera.near), f64::from(scene.camera.far));
                    let sample = integrator.trace(origin, dir, near, far, &mut rng);
                    traced += sample.rays;
                    let half = (k % 2) as usize;
                    // A non-finite sample would poison the pixel for good: it counts as
                    // black (none is expected; the tests check every model for them).
                    if sample.radiance.is_finite() {
                        pixel.radiance[half] += sample.radiance;
                    }
                    pixel.hits[half] += u32::from(sample.hit);
                }
            }
            *samples += count;
            ray_count.fetch_add(traced, Ordering::Relaxed);
            let rows = rows_done.fetch_add(1, Ordering::Relaxed) + 1;
            progress.update(
                u64::from(first) * height as u64 + rows * u64::from(count),
                u64::from(expected) * height as u64,
            );
        });
        if progress.cancelled() {
            bail!("the reference was cancelled");
        }
        if progress.interrupted() {
            ending = Ending::Interrupted;
            break;
        }
        done += count;
        pass += 1;
        noise = estimate_noise(&sums, &row_samples);
        if let Stop::Noise { target, .. } = settings.stop {
            expected = if noise > target && done < max_samples {
                // Noise falls as 1/√N: aim at the target, at most doubling per pass.
                let needed = (f64::from(done) * (noise / target).powi(2)).ceil();
                (needed.min(f64::from(max_samples)) as u32).clamp(done + 1, (2 * done).min(max_samples))
            } else {
                done
            };
        }
    }
    let (fewest, most) = (row_samples.iter().min(), row_samples.iter().max());
    let (samples, most_samples) = (fewest.copied().unwrap_or(0), most.copied().unwrap_or(0));
    if samples == 0 {
        bail!(Interrupted("before every row had a sample: no image".to_owned()));
    }
    if ending == Ending::Interrupted {
        noise = estimate_noise(&sums, &row_samples);
    }
    let total = u64::from(done) * height as u64;
    progress.update(total, total);
    let rgba = sums
        .chunks(width)
        .zip(&row_samples)
        .flat_map(|(row, &n)| {
            let n = f64::from(n);
            row.iter().flat_map(move |p| {
                let radiance = (p.radiance[0] + p.radiance[1]) / n;
                let coverage = f64::from(p.hits[0] + p.hits[1]) / n;
                [radiance.x as f32, radiance.y as f32, radiance.z as f32, coverage as f32]
            })
        })
        .collect();
    Ok(Reference {
        width: settings.width,
        height: settings.height,
        rgba,
        samples,
        most_samples,
        ending,
        noise,
        rays: ray_count.into_inner(),
        elapsed: start.elapsed(),
    })
}

/// [`Reference::noise`] of the half images, each row's pixels after its `row_samples`.
fn estimate_noise(sums: &[PixelSums], row_samples: &[u32]) -> f64 {
    let width = sums.len() / row_samples.len().max(1);
    let (mut variance, mut signal) = (0.0, 0.0);
    for (row, &samples) in sums.chunks(width.max(1)).zip(row_samples) {
        let counts = [even_samples(samples), samples - even_samples(samples)];
        if counts[1] == 0 {
            return f64::INFINITY;
        }
        for p in row.iter().filter(|p| p.hits[0] + p.hits[1] > 0) {
            let a = p.radiance[0] / f64::from(counts[0]);
            let b = p.radiance[1] / f64::from(counts[1]);
            variance += ((a - b) * 0.5).length_squared();
            signal += ((a + b) * 0.5).length_squared();
        }
    }
    if signal > 0.0 {
        (variance / signal).sqrt()
    } else {
        0.0
    }
}
