//! A start's warm-up: a frame of a few pixels drawn with stand-ins for the scene's
//! builtin maps while other threads make the maps (`PendingMaps`). It makes what the
//! frames need (the environment, the subsurface table, the pipelines, the shadow maps and
//! the ground's maps) and has the driver compile the frame's shaders, which lavapipe does
//! at a pipeline's first draw on its queue's one thread; then the maps go into the scene
//! and its upload. The frames after it are those of the scene loaded whole, bit for bit.

use std::time::{Duration, Instant};

use anyhow::Result;
use ash::vk;

use super::{GpuScene, OffscreenFrame, Renderer};
use crate::scene::{PendingMaps, Scene};

/// The warm-up frame's size: small, as only what it makes and compiles is kept.
pub const WARM_UP_EXTENT: vk::Extent2D = vk::Extent2D { width: 16, height: 16 };

/// How long each part of a warm-up took, on the calling thread but `making`.
pub struct WarmUp {
    /// Making what the frame needs before it draws (`Renderer::prepare_offscreen`).
    pub prepared: Duration,
    /// The warm-up frame, with the driver's first-draw compile, and its GPU times.
    pub drawn: Duration,
    pub frame: OffscreenFrame,
    /// Waiting for the maps once the frame was done.
    pub wait: Duration,
    /// Uploading them in place of the stand-ins.
    pub upload: Duration,
    /// The maps' threads, from their start to the last map made.
    pub making: Duration,
}

/// Warms `renderer` up for `scene`, uploaded as `gpu` with stand-ins for its builtin
/// `maps`, and puts the maps in both; `display`: whether the frames that follow are
/// tone-mapped offscreen (whose pipeline the warm-up then makes too); `frame_extent`: their
/// size, which decides which solids they shade from the G-buffer (src/render/deferred.rs).
pub fn warm_up(
    renderer: &mut Renderer,
    scene: &mut Scene,
    gpu: &mut GpuScene,
    mut maps: PendingMaps,
    display: bool,
    frame_extent: vk::Extent2D,
) -> Result<WarmUp> {
    let start = Instant::now();
    let target = renderer.offscreen_target(WARM_UP_EXTENT, display)?;
    renderer.deferral_extent = Some(frame_extent);
    let frame = warm_up_frame(renderer, scene, gpu, &target, &mut maps);
    renderer.deferral_extent = None;
    let (prepared, frame) = frame?;
    let drawn = Instant::now();
    let stand_ins = maps.stand_ins();
    let making = maps.finish(scene)?;
    let made = Instant::now();
    renderer.replace_textures(gpu, scene, &stand_ins)?;
    Ok(WarmUp {
        prepared: prepared - start,
        drawn: drawn - prepared,
        frame,
        wait: made - drawn,
        upload: made.elapsed(),
        making,
    })
}

/// Prepares and draws the warm-up frame, beginning `maps` between the two; returns when the
/// preparation ended, and the frame.
fn warm_up_frame(
    renderer: &mut Renderer,
    scene: &Scene,
    gpu: &GpuScene,
    target: &super::OffscreenTarget,
    maps: &mut PendingMaps,
) -> Result<(Instant, OffscreenFrame)> {
    // The maps begin after the environment's precompute, whose compute keeps both cores
    // busy, and take the core the driver's compile leaves.
    renderer.prepare_offscreen(scene, gpu, target)?;
    let prepared = Instant::now();
    maps.begin();
    Ok((prepared, renderer.render_accumulated_into(scene, gpu, target, 1.0, 1)?))
}
