//! Cheap frames while the UI is in use at slow frame rates: with the pointer over the
//! panel, a popup (a dropdown's list) open, a drag under way or the camera moving, a device
//! whose full frame takes more than [`SLOW_FRAME_MS`] draws the 3D view at 1/[`REDUCED_SCALE`]
//! of its resolution, so that the UI answers within a fraction of a second and a pick lands
//! where it was aimed; the next frame after the interaction is at full resolution again.

/// GPU milliseconds of a full-resolution frame above which interacting frames are reduced.
pub const SLOW_FRAME_MS: f64 = 100.0;
/// Output pixels per rendered texel along each axis while interacting on a slow device.
pub const REDUCED_SCALE: u32 = 4;

/// Whether the UI or the camera is in use: what the next frame answers.
pub fn in_use(ctx: &egui::Context, camera_moving: bool) -> bool {
    camera_moving || ctx.is_pointer_over_egui() || ctx.egui_is_using_pointer() || egui::Popup::is_any_open(ctx)
}

/// The scale of the next frame: reduced while in use when full frames are slow
/// (`full_gpu_ms`, the last full-resolution frame's GPU time, unknown before one is back).
pub fn scale(in_use: bool, full_gpu_ms: Option<f64>) -> u32 {
    if in_use && full_gpu_ms.is_some_and(|ms| ms > SLOW_FRAME_MS) {
        REDUCED_SCALE
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_reduced_only_while_in_use_on_a_slow_device() {
        assert_eq!(scale(true, Some(1500.0)), REDUCED_SCALE);
        assert_eq!(scale(false, Some(1500.0)), 1, "full quality after");
        assert_eq!(scale(true, Some(16.0)), 1, "a fast device keeps full resolution");
        assert_eq!(scale(true, None), 1, "until a full frame is measured");
    }

    #[test]
    fn an_idle_context_is_not_in_use() {
        let ctx = egui::Context::default();
        let _ = ctx.run_ui(egui::RawInput::default(), |_| {});
        assert!(!in_use(&ctx, false));
        assert!(in_use(&ctx, true));
    }
}
