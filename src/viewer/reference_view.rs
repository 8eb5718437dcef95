//! The reference of the current view: `argil reference` of the camera and scene on screen,
//! at a quarter of the view's size, rendered on a background thread (its samples on rayon's
//! pool) while the viewer stays live, then shown beside the real-time frame of the same
//! size and the ꟻLIP map of the two (`argil compare`'s figures). A change of the scene or
//! camera cancels a reference in progress.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

use anyhow::{anyhow, Result};
use ash::vk;
use egui::{Color32, RichText, Ui};

use crate::brdf::tonemap::display_srgb8;
use crate::compare::metrics::{compare, Comparison, Rgba32};
use crate::reference::{self, Filter, Progress, Reference, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use crate::render::OffscreenFrame;
use crate::scene::Scene;

/// The reference's size is the view's divided by this.
pub const SCALE_DOWN: u32 = 4;
/// Samples per pixel the panel starts with.
const FIRST_SPP: u32 = 64;
/// How often the viewer draws while a reference renders, to show its progress.
pub const PROGRESS_INTERVAL: std::time::Duration = std::time::Duration::from_millis(1000);

/// The reference and the frame compared.
pub struct Compared {
    pub reference: Reference,
    pub comparison: Comparison,
}

/// Renders the reference of `scene` with `settings` (the frame's size) and compares `frame`,
/// the linear RGBA of the real-time frame of the same view, with it; both are scaled by
/// `exposure` first, so that the figures are of what the window shows.
pub fn reference_and_compare(
    scene: &Scene,
    frame: &[f32],
    settings: &Settings,
    exposure: f32,
    progress: &dyn Progress,
) -> Result<Compared> {
    let reference = reference::render(scene, settings, progress)?;
    let exposed = |rgba: &[f32]| Rgba32 {
        width: settings.width as usize,
        height: settings.height as usize,
        pixels: rgba
            .chunks_exact(4)
            .map(|p| [p[0] * exposure, p[1] * exposure, p[2] * exposure, p[3]])
            .collect(),
    };
    let comparison = compare(&exposed(frame), &exposed(&reference.rgba))?;
    Ok(Compared { reference, comparison })
}

/// The settings of the reference of a view of `view` pixels.
pub fn settings(view: (u32, u32), transport: Transport, spp: u32) -> Settings {
    Settings {
        width: (view.0 / SCALE_DOWN).max(1),
        height: (view.1 / SCALE_DOWN).max(1),
        transport,
        filter: Filter::Box,
        sampling: Sampling::Mis,
        subsurface: SubsurfaceTransport::Model,
        stop: Stop::Samples(spp),
        seed: 1,
        max_depth: Settings::DEFAULT_MAX_DEPTH,
        max_time: None,
    }
}

/// Progress shared with the thread; cancelling it stops the reference.
#[derive(Default)]
struct Shared {
    done: AtomicU64,
    total: AtomicU64,
    cancel: AtomicBool,
}

impl Progress for Shared {
    fn update(&self, done: u64, total: u64) {
        self.done.store(done, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

struct Job {
    /// The scene (camera included) the reference is of.
    scene: Scene,
    /// The real-time frame's display image, RGBA8.
    frame: Vec<u8>,
    settings: Settings,
    exposure: f32,
    shared: Arc<Shared>,
    thread: JoinHandle<Result<Compared>>,
}

/// A finished comparison as the panel shows it.
struct Shown {
    textures: [egui::TextureHandle; 3],
    summary: String,
}

/// The panel's reference: its settings, the job in progress, the last result.
pub struct ReferenceView {
    pub transport: Transport,
    pub spp: u32,
    requested: bool,
    job: Option<Job>,
    shown: Option<Shown>,
    status: Option<String>,
}

impl Default for ReferenceView {
    fn default() -> Self {
        Self {
            transport: Transport::Shadows,
            spp: FIRST_SPP,
            requested: false,
            job: None,
            shown: None,
            status: None,
        }
    }
}

impl ReferenceView {
    /// Whether the button asked for a reference since the last call.
    pub fn take_request(&mut self) -> bool {
        std::mem::take(&mut self.requested)
    }

    /// Whether a reference is rendering.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts the reference of `scene` beside `frame`, its real-time frame at the
    /// reference's size (see [`settings`]); a reference in progress is cancelled.
    pub fn start(&mut self, scene: &Scene, frame: OffscreenFrame, settings: Settings, exposure: f32) {
        self.cancel();
        let shared = Arc::new(Shared::default());
        let (thread_scene, hdr, thread_shared) = (scene.clone(), frame.hdr, shared.clone());
        let thread = std::thread::spawn(move || {
            reference_and_compare(&thread_scene, &hdr, &settings, exposure, &*thread_shared)
        });
        self.status = None;
        self.job = Some(Job {
            scene: scene.clone(),
            frame: frame.display,
            settings,
            exposure,
            shared,
            thread,
        });
    }

    fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.shared.cancel.store(true, Ordering::Relaxed);
            // Its rows stop at once; the thread ends on its own.
            drop(job.thread);
        }
    }

    /// Cancels the reference when the view (scene or camera) changed, and shows it when it
    /// has finished.
    pub fn poll(&mut self, ctx: &egui::Context, scene: &Scene) {
        let Some(job) = &self.job else { return };
        if job.scene != *scene {
            self.cancel();
            self.status = Some("reference cancelled: the view changed".to_owned());
            return;
        }
        if !job.thread.is_finished() {
            return;
        }
        let Some(Job {
            frame,
            settings,
            exposure,
            thread,
            ..
        }) = self.job.take()
        else {
            return;
        };
        let finished = thread
            .join()
            .unwrap_or_else(|_| Err(anyhow!("the reference's thread panicked")));
        match finished {
            Ok(compared) => {
                self.shown = Some(show(ctx, &frame, &settings, exposure, &compared));
                self.status = None;
            }
            Err(e) => self.status = Some(format!("{e:#}")),
        }
    }
}

/// The three images as textures, and the line that says what they are.
fn show(ctx: &egui::Context, frame: &[u8], settings: &Settings, exposure: f32, compared: &Compared) -> Shown {
    let (w, h) = (settings.width as usize, settings.height as usize);
    let reference: Vec<u8> = compared
        .reference
        .rgba
        .chunks_exact(4)
        .flat_map(|p| {
            let [r, g, b] = display_srgb8([0, 1, 2].map(|c| f64::from(p[c] * exposure)));
            [r, g, b, 255]
        })
        .collect();
    let heat = compared
        .comparison
        .heat_map
        .pixels()
        .flat_map(|p| [p[0], p[1], p[2], 255]);
    let heat: Vec<u8> = heat.collect();
    let texture = |name: &str, rgba: &[u8]| {
        let image = egui::ColorImage::from_rgba_unmultiplied([w, h], rgba);
        ctx.load_texture(name, image, egui::TextureOptions::NEAREST)
    };
    let m = &compared.comparison.metrics;
    let r = &compared.reference;
    let summary = format!(
        "mean ꟻLIP {:.4} (p95 {:.3}), rel-MSE {:.3e} over {} covered pixels, at {}×{}; reference: {} transport, \
         {} filter, {} spp, noise {:.2e}, {:.1} s",
        m.flip.mean,
        m.flip.p95,
        m.rel_mse,
        m.covered_pixels,
        w,
        h,
        settings.transport,
        settings.filter,
        r.samples,
        r.noise,
        r.elapsed.as_secs_f64()
    );
    Shown {
        textures: [
            texture("argil-reference", &reference),
            texture("argil-reference-frame", frame),
            texture("argil-reference-flip", &heat),
        ],
        summary,
    }
}

/// The panel's "Reference" section.
pub fn section(ui: &mut Ui, view: &mut ReferenceView) {
    ui.horizontal(|ui| {
        ui.label("transport");
        egui::ComboBox::from_id_salt("reference transport")
            .selected_text(view.transport.to_string())
            .show_ui(ui, |ui| {
                for t in [Transport::Direct, Transport::Shadows, Transport::Full] {
                    ui.selectable_value(&mut view.transport, t, t.to_string());
                }
            })
            .response
            .on_hover_text(
                "direct: each light through the material without visibility; shadows: with visibility (the point \
                 lights' shadows, the environment's occlusion); full: paths of any length",
            );
        ui.add(egui::DragValue::new(&mut view.spp).range(1..=4096).suffix(" spp"));
    });
    let label = if view.running() {
        "restart the reference"
    } else {
        "reference of this view"
    };
    if ui
        .button(label)
        .on_hover_text(format!(
            "argil reference of this camera and scene at 1/{SCALE_DOWN} of the view's size, on the CPU, then its \
             ꟻLIP map against the real-time frame of the same size (argil compare); moving or editing cancels it"
        ))
        .clicked()
    {
        view.requested = true;
    }
    if let Some(job) = &view.job {
        let (done, total) = (
            job.shared.done.load(Ordering::Relaxed),
            job.shared.total.load(Ordering::Relaxed),
        );
        let fraction = if total > 0 { done as f32 / total as f32 } else { 0.0 };
        ui.add(egui::ProgressBar::new(fraction).show_percentage());
        ui.ctx().request_repaint_after(PROGRESS_INTERVAL);
    }
    if let Some(status) = &view.status {
        ui.label(RichText::new(status).color(Color32::LIGHT_RED));
    }
    if let Some(shown) = &view.shown {
        ui.label(&shown.summary);
        for (texture, caption) in shown.textures.iter().zip(["reference", "real-time frame", "ꟻLIP map"]) {
            ui.label(caption);
            let size = texture.size_vec2();
            let scale = (ui.available_width() / size.x).min(2.0);
            ui.image((texture.id(), size * scale));
        }
    }
}

/// The size of the real-time frame compared: the reference's.
pub fn frame_extent(settings: &Settings) -> vk::Extent2D {
    vk::Extent2D {
        width: settings.width,
        height: settings.height,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Cancelled;
    impl Progress for Cancelled {
        fn update(&self, _: u64, _: u64) {}
        fn cancelled(&self) -> bool {
            true
        }
    }

    #[test]
    fn a_cancelled_reference_stops_with_an_error() {
        let scene = Scene::default_scene();
        let settings = settings((64, 36), Transport::Direct, 1_000_000);
        let error = reference::render(&scene, &settings, &Cancelled)
            .err()
            .expect("cancelled");
        assert!(error.to_string().contains("cancelled"), "{error:#}");
    }

    /// A frame of uniform grey, as if rendered at `settings`' size.
    fn grey_frame(settings: &Settings) -> OffscreenFrame {
        let n = (settings.width * settings.height) as usize;
        OffscreenFrame {
            width: settings.width,
            height: settings.height,
            hdr: [0.2, 0.2, 0.2, 1.0].repeat(n),
            display: [128, 128, 128, 255].repeat(n),
            gpu_ms: None,
            frames: 1,
        }
    }

    #[test]
    fn a_finished_reference_is_shown_with_its_flip_and_settings() {
        let ctx = egui::Context::default();
        let scene = Scene::default_scene();
        let settings = settings((96, 56), Transport::Direct, 2);
        let mut view = ReferenceView::default();
        view.start(&scene, grey_frame(&settings), settings, 1.0);
        while view.running() {
            std::thread::sleep(std::time::Duration::from_millis(20));
            view.poll(&ctx, &scene);
        }
        assert_eq!(view.status, None);
        let shown = view.shown.as_ref().expect("shown");
        assert!(shown.summary.starts_with("mean ꟻLIP 0."), "{}", shown.summary);
        assert!(
            shown.summary.contains("direct transport, box filter, 2 spp"),
            "{}",
            shown.summary
        );
        assert!(shown.textures.iter().all(|t| t.size() == [24, 14]));
    }

    #[test]
    fn moving_the_camera_cancels_the_reference() {
        let ctx = egui::Context::default();
        let mut scene = Scene::default_scene();
        let settings = settings((96, 56), Transport::Full, 100_000);
        let mut view = ReferenceView::default();
        view.start(&scene, grey_frame(&settings), settings, 1.0);
        scene.camera.position.x += 0.5;
        view.poll(&ctx, &scene);
        assert!(!view.running() && view.shown.is_none());
        assert_eq!(view.status.as_deref(), Some("reference cancelled: the view changed"));
    }

    #[test]
    fn the_reference_is_a_quarter_of_the_view() {
        let s = settings((640, 360), Transport::Shadows, 16);
        assert_eq!((s.width, s.height, s.stop), (160, 90, Stop::Samples(16)));
        assert_eq!(settings((2, 3), Transport::Direct, 1).width, 1);
    }
}
