//! The scripted leak hunt (`argil view --soak-log FILE`, run by `argil bench --soak-viewer`):
//! while frames are drawn continuously, the camera orbits its target and every
//! [`EDIT_EVERY`] frames the first object's material switches its diffuse model, which
//! selects another pipeline and records an undo step, as a user's edit does. Memory is
//! sampled [`SAMPLES`] times and written to the log at exit.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use glam::Quat;

use crate::atomic::Existing;
use crate::bench::soak::{sample, Sample, SAMPLES};
use crate::scene::{DiffuseModel, Scene};
use crate::vk::Device;

/// Frames between two material edits.
pub const EDIT_EVERY: u64 = 100;
/// Camera orbit per frame, in radians.
const ORBIT_STEP: f32 = 0.01;

/// The step (frames drawn) from which a run of `frames` frames must hold its memory flat:
/// past the first tenth, which warms the driver's caches up, and past the first two edits
/// where the run has them (the second drawn as frame `2 EDIT_EVERY + 1`): the first makes
/// the edited model's pipeline, whose first draws grow lavapipe's memory by 12–17 MiB over
/// the next hundred frames, the second returns to the first model, and every later edit
/// selects a pipeline made before.
pub fn warmed_up(frames: u64) -> u64 {
    let tenth = frames / SAMPLES;
    if frames > 2 * EDIT_EVERY {
        tenth.max(2 * EDIT_EVERY + 1)
    } else {
        tenth
    }
}

pub struct Soak {
    log: PathBuf,
    existing: Existing,
    /// The edited material's own diffuse model, which every second edit restores.
    original: Option<DiffuseModel>,
    frames: u64,
    start: Instant,
    samples: Vec<Sample>,
}

impl Soak {
    pub fn new(log: PathBuf, existing: Existing, frames: u64) -> Self {
        Self {
            log,
            existing,
            original: None,
            frames,
            start: Instant::now(),
            samples: Vec::new(),
        }
    }

    /// What the script changes before frame `frame` (counted from 0) is drawn.
    pub fn before_frame(&mut self, frame: u64, scene: &mut Scene) {
        let camera = &mut scene.camera;
        camera.position = camera.target + Quat::from_rotation_y(ORBIT_STEP) * (camera.position - camera.target);
        if frame > 0 && frame % EDIT_EVERY == 0 {
            let material = &mut scene.materials[scene.objects[0].material];
            let original = *self.original.get_or_insert(material.diffuse);
            material.diffuse = match (frame / EDIT_EVERY % 2, original) {
                (0, _) => original,
                (_, DiffuseModel::Lambert) => DiffuseModel::OrenNayar,
                _ => DiffuseModel::Lambert,
            };
        }
    }

    /// Samples memory after frame `drawn` (counted from 1), at the run's tenths and at its
    /// last frame.
    pub fn after_frame(&mut self, device: &Device, drawn: u64) {
        if drawn % (self.frames / SAMPLES).max(1) == 0 || drawn == self.frames {
            self.samples.push(sample(device, drawn, &self.start));
        }
    }

    /// Writes the samples (JSON) to the log.
    pub fn write(&self) -> Result<()> {
        crate::atomic::write_bytes(&self.log, self.existing, serde_json::to_string_pretty(&self.samples)?.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_script_orbits_at_constant_distance_and_alternates_the_model() {
        let mut scene = Scene::default_scene();
        let distance = (scene.camera.position - scene.camera.target).length();
        let material = scene.objects[0].material;
        let first = scene.materials[material].diffuse;
        let mut soak = Soak::new(PathBuf::new(), Existing::Replace, 1000);
        let mut models = Vec::new();
        for frame in 0..=2 * EDIT_EVERY {
            soak.before_frame(frame, &mut scene);
            models.push(scene.materials[material].diffuse);
        }
        let moved = (scene.camera.position - scene.camera.target).length();
        assert!((moved - distance).abs() < 1e-3 * distance);
        assert_eq!(models[0], first);
        assert_ne!(models[EDIT_EVERY as usize], first);
        assert_eq!(models[2 * EDIT_EVERY as usize], first);
    }

    /// Memory is judged from the first tenth on, and after the first two edits where the
    /// run has them.
    #[test]
    fn the_warm_up_spans_the_first_two_edits() {
        assert_eq!(warmed_up(40), 4);
        assert_eq!(warmed_up(2 * EDIT_EVERY), 2 * EDIT_EVERY / SAMPLES);
        assert_eq!(warmed_up(500), 2 * EDIT_EVERY + 1);
        assert_eq!(warmed_up(10_000), 1000);
    }
}
