//! The interactive viewer: a window whose swapchain shows the same HDR frame that
//! `argil render` writes, through the same display transform, with a UI over it to edit
//! materials and lights live, switch debug views and watch timings. The scene file is
//! reloaded when it changes on disk, and the scene read again, its edits kept, when a file
//! it reads changes; Save writes the edited scene back.

mod antialiasing_panel;
mod camera_control;
mod frames;
mod history;
mod legend;
mod occlusion_panel;
mod overlay;
mod panels;
mod path_completion;
mod rebuild;
mod reference_view;
pub mod responsive;
pub mod save;
mod shadow_panel;
mod soak;
mod split_view;
mod storm;
mod timings;
mod watch;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Context, Result};
use ash::vk;
use glam::Vec2;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::atomic::Existing;
use crate::error::Interrupted;
use crate::render::environment::equirect::{self, Equirect};
use crate::render::gpu_scene::FrameData;
use crate::render::DebugView;
use crate::scene::{Camera, Environment, PendingMaps, Scene};
use crate::vk::{Device, DeviceChoice, DeviceOptions, WindowHandles};
use camera_control::{
    floor_height, frame_sphere, movement_from_keys, object_bounds, objects_bounds, CameraControl, Input,
};
use frames::{gpu_pass_names, Capture, CaptureStage, FrameLoop, UiFrame};
use history::History;
use panels::{Actions, Question, ViewState};
use rebuild::Rebuild;
use save::{Document, Refused};
use soak::Soak;
use storm::StormStep;
use timings::{FrameTimes, Timings};
use watch::{inputs_watch, FileWatch};

pub use legend::curvature_legend_color;
pub use panels::PANEL_WIDTH;
pub use reference_view::reference_and_compare;
pub use soak::warmed_up as soak_warmed_up;
pub use split_view::parse_configuration as parse_split_configuration;
/// Redraws the resize storm lasts; `--frames` beyond it render at the storm's last size.
pub const RESIZE_STORM_TICKS: u64 = storm::DURATION;

/// Where Save writes the embedded default scene, which has no file of its own.
pub const DEFAULT_SAVE_PATH: &str = "argil-scene.toml";

/// How often the loop wakes while the window is minimised, to notice it coming back.
const IDLE_TICK: Duration = Duration::from_millis(100);
/// An auto exposure within this fraction of the one on screen is not drawn again.
const EXPOSURE_SETTLED: f32 = 0.02;
/// Camera steps are cut at this many seconds, so a stall does not fling the camera away.
const MAX_STEP_SECONDS: f32 = 0.1;

pub struct ViewOptions {
    pub device: DeviceChoice,
    pub validation: bool,
    /// Close after this many frames (for tests and scripted runs).
    pub frames: Option<u64>,
    pub exposure: f32,
    /// Initial inner size of the window in pixels.
    pub size: (u32, u32),
    /// Write what the window shows, UI included, after the last frame (with `seconds`, one
    /// drawn when they have passed).
    pub screenshot: Option<PathBuf>,
    /// Resize, minimise and restore the window while rendering (for tests).
    pub resize_storm: bool,
    /// Close this many seconds after the first frame, drawing only when something changes
    /// (for tests of the idle viewer); `frames` draws continuously instead.
    pub seconds: Option<f64>,
    /// Run the scripted leak hunt over `frames` and write its memory samples here.
    pub soak_log: Option<PathBuf>,
    /// What `screenshot` and `soak_log` do with a file at their paths (`--overwrite`).
    pub outputs: Existing,
    /// The debug view shown first.
    pub debug_view: DebugView,
    /// Start with the split view on, its right half in this bench configuration.
    pub split: Option<String>,
}

/// A scene the viewer can show, with its environment map as [`check_viewable`] decoded it,
/// which the renderer takes rather than decoding the file again.
pub struct Viewable {
    pub scene: Scene,
    map: Option<Equirect>,
    /// Its builtin maps while they are still to be made, stand-ins in their places in
    /// `scene` meanwhile: the first scene, which the window's start makes them for beside
    /// its warm-up frame (src/render/warm_up.rs).
    maps: Option<PendingMaps>,
}

impl Viewable {
    /// Checks `scene` as [`check_viewable`] does.
    fn check(scene: Scene) -> Result<Self> {
        let map = check_viewable(&scene)?;
        Ok(Self { scene, map, maps: None })
    }
}

/// The viewer's first scene: the file at `path` (as [`load_document`] reads it), or the
/// default scene, with stand-ins for its builtin maps, which are made when the window
/// starts.
pub fn open_document(path: Option<&Path>) -> Result<(Viewable, Document)> {
    let ((scene, maps), document) = match path {
        Some(path) if !crate::scene::is_model(path) => {
            let document = Document::read(path)?;
            let base_dir = path.parent().unwrap_or(Path::new(""));
            let (mut scene, maps) = PendingMaps::from_toml(&document.text, &path.display().to_string(), base_dir)?;
            scene.source = Some(path.to_path_buf());
            ((scene, maps), document)
        }
        // A model opens in the default scene's studio, whose text Save As starts from.
        _ => (PendingMaps::load(path)?, Document::default_scene()),
    };
    let viewable = Viewable::check(scene)?;
    Ok((Viewable { maps: Some(maps), ..viewable }, document))
}

/// Loads a scene file that the viewer can show: valid, within the renderer's limits, and
/// with an environment map that decodes, so that a bad edit is reported while the last good
/// scene stays on screen.
pub fn load_scene(path: &Path) -> Result<Scene> {
    load_document(path).map(|(viewable, _)| viewable.scene)
}

/// [`load_scene`], with the text it was read from, which Save edits.
pub fn load_document(path: &Path) -> Result<(Viewable, Document)> {
    let (mut viewable, document) = open_document(Some(path))?;
    if let Some(maps) = viewable.maps.take() {
        maps.finish(&mut viewable.scene)?;
    }
    Ok((viewable, document))
}

/// What the viewer checks beyond the scene file's own validation: the renderer's limits,
/// and an environment map that decodes (returned decoded).
fn check_viewable(scene: &Scene) -> Result<Option<Equirect>> {
    FrameData::new(scene, &scene.occluders(), 1.0)?;
    match &scene.environment {
        Environment::Map { path, .. } => {
            let map = equirect::load(path).map_err(|e| equirect::in_scene_file(e, scene))?;
            Ok(Some(map))
        }
        _ => Ok(None),
    }
}

/// What the panel says the scene file is.
fn file_label(document: &Document) -> String {
    match &document.path {
        Some(path) => std::path::absolute(path)
            .unwrap_or_else(|_| path.clone())
            .display()
            .to_string(),
        None => format!("none (the default scene; Save writes {DEFAULT_SAVE_PATH})"),
    }
}

/// Opens a window on the scene, read from `document`, and runs until it is closed.
pub fn run(viewable: Viewable, document: Document, options: ViewOptions) -> Result<()> {
    let event_loop = EventLoop::<Interrupt>::with_user_event()
        .build()
        .context("cannot open a window: no display?")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let proxy = event_loop.create_proxy();
    crate::interrupt::on_ctrl_c(move || {
        // Only a loop that has ended refuses it, and then there is nothing left to end.
        let _ = proxy.send_event(Interrupt);
    })?;
    let mut app = App::new(viewable, document, options, Instant::now());
    // Whatever stops the viewer, a bug's panic included, the scene's edits are kept.
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| event_loop.run_app(&mut app)));
    let stopped = !matches!((&ran, &app.error), (Ok(Ok(())), None));
    let kept = (stopped && app.history.modified(&app.scene)).then(|| match save::recover(&app.scene, &app.document) {
        Ok(path) => format!("the scene's changes not saved are in {}", path.display()),
        Err(lost) => format!("the scene's changes not saved could not be written ({lost:#})"),
    });
    let error = match ran {
        Err(panic) => {
            if let Some(kept) = &kept {
                eprintln!("argil: {kept}");
            }
            std::panic::resume_unwind(panic)
        }
        Ok(ran) => ran.context("the window's event loop failed").err().or(app.error.take()),
    };
    match (error, kept) {
        (None, _) => Ok(()),
        (Some(e), Some(kept)) => Err(e.context(kept)),
        (Some(e), None) => Err(e),
    }
}

/// Ctrl-C in the terminal (or SIGTERM, SIGHUP): the viewer closes as after its last frame.
struct Interrupt;

/// Keys and mouse since the last frame.
#[derive(Default)]
struct InputState {
    held: HashSet<KeyCode>,
    modifiers: ModifiersState,
    /// The right button went down over the scene and is still down.
    looking: bool,
    /// Where the cursor was last seen in the window, in pixels.
    cursor: Option<Vec2>,
    look: Vec2,
    wheel: f32,
}

impl InputState {
    /// Whether the camera moves while nothing else happens: a movement key held.
    fn moving(&self) -> bool {
        movement_from_keys(|k| self.held.contains(&k)) != glam::Vec3::ZERO
    }

    /// Whether the camera is being moved: looking around, or a movement key held.
    fn camera_moving(&self) -> bool {
        self.looking || self.moving()
    }

    /// This frame's camera input; mouse motion and wheel are consumed.
    fn take(&mut self) -> Input {
        let input = Input {
            movement: movement_from_keys(|k| self.held.contains(&k)),
            look: self.look,
            wheel: self.wheel,
            fast: self.modifiers.shift_key(),
        };
        self.look = Vec2::ZERO;
        self.wheel = 0.0;
        input
    }
}

struct Running {
    // Dropped first: it holds the device, whose surface must go before the window.
    frames: FrameLoop,
    egui: egui_winit::State,
    window: Arc<Window>,
}

struct App {
    /// The scripted leak hunt, when asked for.
    soak: Option<Soak>,
    scene: Scene,
    options: ViewOptions,
    view: ViewState,
    camera: CameraControl,
    input: InputState,
    /// Asked for by keys, done with the next frame.
    pending: Actions,
    egui: egui::Context,
    watch: Option<FileWatch>,
    /// The files the scene reads (meshes, textures, the environment map): when one changes,
    /// the scene as it stands is resolved again, its edits kept.
    inputs: Vec<FileWatch>,
    /// The environment map as loading decoded it, until the renderer takes it.
    map: Option<Equirect>,
    /// The first scene's builtin maps, until the window's start makes them.
    maps: Option<PendingMaps>,
    /// The text the scene was read from, which Save edits.
    document: Document,
    history: History,
    /// The camera of the file, for Reset view and to notice a camera edit on reload.
    file_camera: Camera,
    state: Option<Running>,
    error: Option<anyhow::Error>,
    last_frame: Option<Instant>,
    next_idle_tick: Instant,
    /// When the first frame was drawn: `seconds` counts from there.
    first_frame: Option<Instant>,
    /// Something changed since the last frame: input, an edit, a reload, egui asking.
    needs_redraw: bool,
    /// egui asked to draw again at this time (an animation, a tooltip's delay).
    repaint_at: Option<Instant>,
    /// Redraw requests so far, drawn or not: the resize storm's clock.
    ticks: u64,
    final_screenshot_written: bool,
    /// `seconds` have passed: the next frame drawn takes the screenshot and is the last.
    time_up: bool,
}

impl App {
    /// The viewer on `viewable`, read from `document`, before its window opens.
    fn new(viewable: Viewable, document: Document, options: ViewOptions, now: Instant) -> Self {
        let Viewable { scene, map, maps } = viewable;
        let mut view = ViewState::new(options.exposure, Timings::new(gpu_pass_names()), file_label(&document));
        view.selected_material = scene.objects[0].material;
        let soak = options
            .soak_log
            .clone()
            .zip(options.frames)
            .map(|(log, frames)| Soak::new(log, options.outputs, frames));
        view.debug_view = options.debug_view;
        if let Some(configuration) = &options.split {
            view.split.on = true;
            view.split.configuration.clone_from(configuration);
        }
        App {
            soak,
            view,
            watch: document.path.clone().map(|p| FileWatch::new(p, now)),
            inputs: inputs_watch(&scene, now),
            map,
            maps,
            history: History::new(&scene),
            file_camera: scene.camera,
            document,
            scene,
            options,
            camera: CameraControl::default(),
            input: InputState::default(),
            pending: Actions::default(),
            egui: egui::Context::default(),
            state: None,
            error: None,
            last_frame: None,
            next_idle_tick: now,
            first_frame: None,
            needs_redraw: true,
            repaint_at: None,
            ticks: 0,
            final_screenshot_written: false,
            time_up: false,
        }
    }

    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let title = match &self.document.path {
            Some(p) => format!("argil — {}", p.display()),
            None => "argil — default clay scene".to_owned(),
        };
        let (width, height) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(title)
            .with_inner_size(PhysicalSize::new(width, height));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot create a window")?);
        let handles = WindowHandles {
            display: window
                .display_handle()
                .context("window has no display handle")?
                .as_raw(),
            window: window.window_handle().context("window has no window handle")?.as_raw(),
        };
        let device = Arc::new(Device::new(
            DeviceOptions {
                choice: self.options.device.clone(),
                validation: self.options.validation,
            },
            Some(handles),
        )?);
        eprintln!("argil: rendering on {}", device.info.name);
        self.view.device_name = device.info.name.clone();
        let egui = egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &*window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(device.limits.max_image_dimension2_d as usize),
        );
        let size = window.inner_size();
        let mut frames = FrameLoop::new(
            device,
            &self.scene,
            vk::Extent2D {
                width: size.width,
                height: size.height,
            },
        )?;
        frames.use_environment_map(&self.scene, self.map.take());
        if let Some(maps) = self.maps.take() {
            frames.renderer.debug_view = self.view.debug_view;
            frames.warm_up(&mut self.scene, maps)?;
        }
        self.state = Some(Running { frames, egui, window });
        Ok(())
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.error = Some(error);
        self.state = None;
        event_loop.exit();
    }

    /// Finishes the last frames, writes what is pending and closes the window.
    fn close(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(mut state) = self.state.take() {
            let finished = state.frames.finish();
            self.report_screenshots(state.frames.take_screenshots());
            let (cpu_ms, gpu_ms) = self.view.timings.mean().unwrap_or_default();
            let gpu: Vec<String> = self
                .view
                .timings
                .pass_names
                .iter()
                .zip(&gpu_ms)
                .map(|(n, ms)| format!("{n} {ms:.2} ms"))
                .collect();
            let area = state.frames.frame_area();
            let idle = self.last_frame.map_or(0.0, |t| t.elapsed().as_secs_f64());
            eprintln!(
                "argil: {} frames, {} swapchain recreations; view {}x{} at x {}; idle {idle:.1} s at the end; last \
                 second: CPU work {cpu_ms:.2} ms a frame, GPU {}",
                state.frames.frame_count(),
                state.frames.recreations(),
                area.extent.width,
                area.extent.height,
                area.offset.x,
                gpu.join(", ")
            );
            eprintln!(
                "argil: {} frames at 1/{} resolution while the UI was in use; the last frame at 1/{}; GPU time of \
                 the last full frame {}, of the last reduced one {}",
                state.frames.reduced_frames(),
                responsive::REDUCED_SCALE,
                state.frames.scale(),
                milliseconds(state.frames.full_gpu_ms()),
                milliseconds(state.frames.reduced_gpu_ms()),
            );
            let source = if self.view.auto_exposed() { "auto" } else { "camera" };
            eprintln!("argil: exposure in use {} ({source})", self.view.exposure_in_use);
            if let Some(a) = state.frames.renderer.accumulated() {
                eprintln!(
                    "argil: sampled reflection: the last view's mean has {} frames × {} lookups = {} lookups per pixel",
                    a.frames,
                    a.lookups_per_frame,
                    a.lookups()
                );
            }
            if let Err(e) = finished {
                self.error.get_or_insert(e);
            }
            if self.options.screenshot.is_some() && !self.final_screenshot_written {
                self.error
                    .get_or_insert(anyhow!("the window closed before the screenshot was taken"));
            }
            // Everything on the device is gone with the frame loop; a device still held
            // would never be destroyed, and the validation layer never see its leaks.
            let device = Arc::downgrade(state.frames.device());
            drop(state);
            if device.strong_count() > 0 {
                self.error.get_or_insert(anyhow!(
                    "the Vulkan device outlived the viewer: something holding it leaked"
                ));
            }
            if let Some(Err(e)) = self.soak.as_ref().map(Soak::write) {
                self.error.get_or_insert(e);
            }
        }
        event_loop.exit();
    }

    fn key_pressed(&mut self, key: KeyCode) {
        let ctrl = self.input.modifiers.control_key();
        let shift = self.input.modifiers.shift_key();
        match key {
            KeyCode::Tab | KeyCode::KeyO => self.camera.toggle_mode(),
            KeyCode::KeyF => self.pending.frame_scene = true,
            KeyCode::KeyH | KeyCode::F1 => self.view.show_help = !self.view.show_help,
            KeyCode::F12 => self.pending.screenshot = true,
            KeyCode::KeyS if ctrl => self.pending.save = true,
            KeyCode::KeyZ if ctrl && shift => self.pending.redo = true,
            KeyCode::KeyZ if ctrl => self.pending.undo = true,
            KeyCode::KeyY if ctrl => self.pending.redo = true,
            KeyCode::KeyR if !ctrl => self.pending.reset_view = true,
            KeyCode::KeyU if !ctrl => self.view.hide_ui = !self.view.hide_ui,
            KeyCode::KeyV if !ctrl => self.view.split.on = !self.view.split.on,
            KeyCode::Escape if self.view.question.is_some() => self.view.question = None,
            KeyCode::Escape => self.pending.quit = Some(false),
            _ => {}
        }
    }

    /// The scene file changed on disk: it is read again, unless the scene has changes not
    /// saved, which reading it would lose: then the user is asked first (Save, which would
    /// overwrite the file's new text, refuses; Save As does not).
    fn scene_file_changed(&mut self) -> Result<()> {
        if !self.history.modified(&self.scene) {
            return self.reload();
        }
        if let Some(watch) = &self.watch {
            eprintln!(
                "argil: {} changed on disk; the scene has unsaved changes: asking before reading it",
                watch.path.display()
            );
        }
        self.view.question = Some(Question::Reload);
        self.needs_redraw = true;
        Ok(())
    }

    fn reload(&mut self) -> Result<()> {
        let Some(path) = self.watch.as_ref().map(|w| w.path.clone()) else {
            return Ok(());
        };
        match load_document(&path) {
            Ok((Viewable { mut scene, map, .. }, document)) => {
                // The viewer's camera stays unless the file's camera itself was edited.
                let camera_edited = scene.camera != self.file_camera;
                self.file_camera = scene.camera;
                if !camera_edited {
                    scene.camera = self.scene.camera;
                }
                self.set_scene(scene, map)?;
                self.document = document;
                self.history = History::new(&self.scene);
                self.view.clamp_selection(&self.scene);
                self.view.error = None;
                eprintln!("argil: reloaded {}", path.display());
                self.scene.print_warnings();
                self.view.notice = Some(if camera_edited {
                    format!("reloaded {}, with the file's new camera", path.display())
                } else {
                    format!("reloaded {}", path.display())
                });
            }
            Err(e) => {
                eprintln!("argil: {e:#}");
                self.view.error = Some(format!("{e:#} (the last good scene stays on screen)"));
            }
        }
        self.needs_redraw = true;
        Ok(())
    }

    /// Resolves the scene as it stands again, its edits kept, after `changed` (files it
    /// reads) changed on disk; a file that no longer loads is reported and the scene stays.
    fn read_inputs_again(&mut self, changed: &[PathBuf]) -> Result<()> {
        let names: Vec<String> = changed.iter().map(|p| p.display().to_string()).collect();
        let names = names.join(", ");
        self.rebuild(&Rebuild::ReadAgain)?;
        if self.view.error.is_none() {
            eprintln!("argil: read {names} again");
            self.view.notice = Some(format!("read {names} again"));
        }
        self.needs_redraw = true;
        Ok(())
    }

    /// Saves to `to`; `overwrite` replaces a file other than the scene's own (asked first).
    fn save_to(&mut self, to: PathBuf, overwrite: bool) {
        match save::save(&self.scene, &self.document, &to, overwrite) {
            Ok(saved) => {
                eprintln!("argil: saved {}", saved.path.display());
                self.view.error = None;
                self.view.notice = Some(format!("saved {}", saved.path.display()));
                let moved = saved.document.path != self.document.path;
                self.document = saved.document;
                self.view.file = file_label(&self.document);
                self.scene.source = Some(to.clone());
                self.history.mark_saved(&self.scene);
                match &mut self.watch {
                    Some(watch) if !moved => watch.mark_seen(),
                    _ => self.watch = Some(FileWatch::new(to, Instant::now())),
                }
            }
            Err(e) => {
                eprintln!("argil: {e:#}");
                match e.downcast_ref::<Refused>() {
                    Some(Refused::Exists { path }) => self.view.question = Some(Question::Overwrite(path.clone())),
                    Some(Refused::Changed { .. }) => {
                        self.view.error = Some(format!("{e:#}"));
                        self.view.question = Some(Question::Reload);
                    }
                    _ => self.view.error = Some(format!("{e:#}")),
                }
            }
        }
    }

    /// Makes an edit that changes what the scene loads, and uploads the new scene; a file
    /// that does not load is reported and the scene stays.
    fn rebuild(&mut self, edit: &Rebuild) -> Result<()> {
        let Viewable { scene, map, .. } = match rebuild::rebuild(&self.scene, edit) {
            Ok(viewable) => viewable,
            Err(e) => {
                eprintln!("argil: {e:#}");
                self.view.error = Some(format!("{e:#}"));
                return Ok(());
            }
        };
        self.set_scene(scene, map)?;
        self.view.error = None;
        match edit {
            Rebuild::ReadAgain => self.history.reread(&self.scene),
            _ => self.history.rebase(&self.scene),
        }
        Ok(())
    }

    /// Shows `scene`, checked with its environment map `map`, and watches the files it reads.
    fn set_scene(&mut self, scene: Scene, map: Option<Equirect>) -> Result<()> {
        if let Some(state) = &mut self.state {
            state.frames.set_scene(&scene, map)?;
        }
        self.scene = scene;
        self.inputs = inputs_watch(&self.scene, Instant::now());
        Ok(())
    }

    /// The camera framing what F frames, in the 3D view's aspect.
    fn frame_camera(&self, aspect: f32) -> Camera {
        let (centre, radius) = match self.camera.mode {
            camera_control::Mode::Orbit => object_bounds(&self.scene, self.view.selected_object),
            camera_control::Mode::Fly => objects_bounds(&self.scene),
        };
        frame_sphere(&self.scene.camera, centre, radius, aspect)
    }

    /// Does what the keys and the UI asked for that is not drawing.
    fn act(&mut self, event_loop: &ActiveEventLoop, actions: Actions, aspect: f32) -> Result<()> {
        if actions.frame_scene {
            self.scene.camera = self.frame_camera(aspect);
        }
        if actions.reset_view {
            self.scene.camera = self.file_camera;
        }
        if actions.undo {
            self.history.undo(&mut self.scene);
        }
        if actions.redo {
            self.history.redo(&mut self.scene);
        }
        if let Some(edit) = &actions.rebuild {
            self.rebuild(edit)?;
        }
        if actions.reload {
            self.reload()?;
        }
        if actions.save {
            let to = self
                .document
                .path
                .clone()
                .unwrap_or_else(|| PathBuf::from(DEFAULT_SAVE_PATH));
            self.save_to(to, false);
        }
        if actions.save_as {
            let to = PathBuf::from(self.view.save_as.trim());
            self.save_to(to, false);
        }
        if let Some(to) = actions.overwrite {
            self.save_to(to, true);
        }
        match actions.quit {
            Some(discard) if discard || !self.history.modified(&self.scene) => self.close(event_loop),
            Some(_) => self.view.question = Some(Question::Quit),
            None => {}
        }
        Ok(())
    }

    fn report_screenshots(&mut self, screenshots: Vec<(PathBuf, Result<()>)>) {
        for (path, written) in screenshots {
            let is_final = self.options.screenshot.as_ref() == Some(&path);
            match written {
                Ok(()) => {
                    eprintln!("argil: wrote {}", path.display());
                    self.view.notice = Some(format!("wrote {}", path.display()));
                    self.final_screenshot_written |= is_final;
                }
                Err(e) if is_final => {
                    self.error.get_or_insert(e);
                }
                Err(e) => self.view.error = Some(format!("{e:#}")),
            }
        }
    }

    fn storm_step(&mut self) {
        let Some(state) = &mut self.state else { return };
        match storm::step(self.ticks) {
            Some(StormStep::Resize(width, height)) => {
                // Applied at once on some platforms, which then send no Resized event.
                if let Some(size) = state.window.request_inner_size(PhysicalSize::new(width, height)) {
                    state.frames.resize(vk::Extent2D {
                        width: size.width,
                        height: size.height,
                    });
                }
            }
            Some(StormStep::Minimise) => state.window.set_minimized(true),
            Some(StormStep::Restore) => state.window.set_minimized(false),
            None => {}
        }
    }

    fn drawable(state: &Running) -> bool {
        state.frames.has_area() && state.window.is_minimized() != Some(true)
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let now = Instant::now();
        let dt = self.last_frame.map_or(0.0, |t| now.duration_since(t).as_secs_f32());
        self.ticks += 1;
        if self.options.resize_storm {
            self.storm_step();
        }
        let Some(state) = self.state.as_mut() else {
            return Ok(());
        };
        if !Self::drawable(state) {
            return Ok(());
        }
        self.last_frame = Some(now);
        self.first_frame.get_or_insert(now);
        self.needs_redraw = false;
        self.repaint_at = None;

        let pivot = object_bounds(&self.scene, self.view.selected_object).0;
        self.camera.floor = floor_height(&self.scene);
        self.camera.update(
            &mut self.scene.camera,
            pivot,
            &self.input.take(),
            dt.min(MAX_STEP_SECONDS),
        );
        if let Some(soak) = &mut self.soak {
            soak.before_frame(state.frames.frame_count(), &mut self.scene);
        }

        self.view.reference.poll(&self.egui, &self.scene);
        let raw = state.egui.take_egui_input(&state.window);
        let mut actions = std::mem::take(&mut self.pending);
        self.view.modified = self.history.modified(&self.scene);
        self.view.can_undo = self.history.can_undo();
        self.view.can_redo = self.history.can_redo();
        // The mean of the last frame drawn; this frame may take it further.
        self.view.accumulated = state.frames.renderer.accumulated();
        let output = self.egui.run_ui(raw, |ui| {
            actions.merge(panels::show(ui, &mut self.scene, &mut self.view, &mut self.camera));
        });
        let settled = !self.egui.input(|i| i.pointer.any_down());
        self.history.observe(&self.scene, settled);
        if let Some(viewport) = output.viewport_output.get(&egui::ViewportId::ROOT) {
            if viewport.repaint_delay.is_zero() {
                self.needs_redraw = true;
            } else if let Some(at) = now.checked_add(viewport.repaint_delay) {
                self.repaint_at = Some(at);
            }
        }
        state.egui.handle_platform_output(&state.window, output.platform_output);
        let primitives = self.egui.tessellate(output.shapes, output.pixels_per_point);

        // The 3D view is what the panel leaves of the window.
        let left = (self.view.view_rect.min.x * output.pixels_per_point).round().max(0.0) as u32;
        state.frames.set_frame_left(left);
        let area = state.frames.frame_area();
        self.view.frame_size = (area.extent.width, area.extent.height);
        let aspect = area.extent.width as f32 / area.extent.height.max(1) as f32;
        // The divider at the middle of the 3D view, as the UI draws it.
        let middle = (self.view.view_rect.center().x * output.pixels_per_point)
            .round()
            .max(0.0) as u32;
        state.frames.renderer.debug_view = self.view.debug_view;
        // The split view samples every map, and compares the scene with itself resolved
        // again, its maps made (split_view::derive).
        state.frames.make_sampled_maps(&mut self.scene, self.view.split.on)?;
        state.frames.renderer.split = self.view.split.split(&self.scene, middle.saturating_sub(left));

        let last_frame = self.time_up || self.options.frames.is_some_and(|n| state.frames.frame_count() + 1 >= n);
        let capture = match (&self.options.screenshot, last_frame) {
            (Some(path), true) => Some(Capture {
                path: path.clone(),
                existing: self.options.outputs,
                stage: CaptureStage::AfterUi,
            }),
            // A name no file had a moment ago.
            _ if actions.screenshot => Some(Capture {
                path: next_screenshot_path(),
                existing: Existing::Refuse,
                stage: CaptureStage::BeforeUi,
            }),
            _ => None,
        };
        state.frames.renderer.shadows = self.view.shadows;
        self.view.msaa_samples = state.frames.renderer.msaa_samples(&self.scene);
        state.frames.renderer.occlusion = self.view.occlusion;
        let renderer = &mut state.frames.renderer;
        renderer.measure_exposure = self.view.auto_exposed();
        self.view.exposure_in_use = renderer
            .auto_exposure()
            .filter(|_| renderer.measure_exposure)
            .unwrap_or(self.view.exposure);
        let ui = UiFrame {
            primitives,
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        };
        if self.view.reference.take_request() {
            let r = &self.view.reference;
            let settings = reference_view::settings((area.extent.width, area.extent.height), r.transport, r.spp);
            let extent = reference_view::frame_extent(&settings);
            match state
                .frames
                .render_still(&self.scene, extent, self.view.exposure_in_use)
            {
                Ok(frame) => self
                    .view
                    .reference
                    .start(&self.scene, frame, settings, self.view.exposure_in_use),
                Err(e) => self.view.error = Some(format!("{e:#}")),
            }
        }
        let in_use = responsive::in_use(&self.egui, self.input.camera_moving());
        let scale = responsive::scale(in_use, state.frames.full_gpu_ms());
        state.frames.set_scale(scale);
        let work = now.elapsed();
        let drawn = state.frames.draw(&self.scene, self.view.exposure_in_use, ui, capture)?;
        if !drawn {
            // Asked again with the next frame that is drawn.
            self.pending.screenshot |= actions.screenshot;
            self.needs_redraw = true;
        }
        self.view.timings.push(FrameTimes {
            at: now,
            cpu_ms: work.as_secs_f64() * 1e3,
            gpu_ms: state.frames.gpu_ms().map(<[f64]>::to_vec).unwrap_or_default(),
        });
        if let (true, Some(soak)) = (drawn, &mut self.soak) {
            soak.after_frame(state.frames.device(), state.frames.frame_count());
        }
        let screenshots = state.frames.take_screenshots();
        let done = (self.time_up && drawn) || self.options.frames.is_some_and(|n| state.frames.frame_count() >= n);
        self.report_screenshots(screenshots);
        actions.screenshot = false;
        if actions != Actions::default() {
            self.needs_redraw = true;
        }
        self.act(event_loop, actions, aspect)?;
        if done {
            self.close(event_loop);
        }
        Ok(())
    }
}

fn milliseconds(ms: Option<f64>) -> String {
    ms.map_or_else(|| "unknown".to_owned(), |ms| format!("{ms:.1} ms"))
}

/// `argil-screenshot-N.png` in the working directory, for the first N not taken.
fn next_screenshot_path() -> PathBuf {
    (1..)
        .map(|n| PathBuf::from(format!("argil-screenshot-{n}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| PathBuf::from("argil-screenshot.png"))
}

impl ApplicationHandler<Interrupt> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_none() {
            if let Err(e) = self.start(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, _: Interrupt) {
        self.error.get_or_insert(Interrupted("(Ctrl-C, SIGTERM or SIGHUP)".to_owned()).into());
        self.close(event_loop);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else { return };
        let tab = matches!(
            &event,
            WindowEvent::KeyboardInput {
                event: KeyEvent {
                    physical_key: PhysicalKey::Code(KeyCode::Tab),
                    ..
                },
                ..
            }
        );
        // egui moves its keyboard focus with Tab and then takes every key; here Tab toggles
        // the camera mode instead, unless a text field is being edited.
        let response = if tab && !self.egui.egui_wants_keyboard_input() {
            egui_winit::EventResponse::default()
        } else {
            state.egui.on_window_event(&state.window, &event)
        };
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            self.needs_redraw = true;
        }
        match event {
            WindowEvent::CloseRequested => self.pending.quit = Some(false),
            WindowEvent::Resized(size) => state.frames.resize(vk::Extent2D {
                width: size.width,
                height: size.height,
            }),
            WindowEvent::ModifiersChanged(m) => self.input.modifiers = m.state(),
            WindowEvent::Focused(false) => {
                self.input.held.clear();
                self.input.looking = false;
            }
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        physical_key: PhysicalKey::Code(key),
                        state: key_state,
                        repeat,
                        ..
                    },
                ..
            } => {
                self.needs_redraw = true;
                if key_state == ElementState::Released {
                    self.input.held.remove(&key);
                } else if !response.consumed {
                    // Ctrl+key is a shortcut, not movement.
                    if !self.input.modifiers.control_key() {
                        self.input.held.insert(key);
                    }
                    if !repeat {
                        self.key_pressed(key);
                    }
                }
            }
            // Cursor motion rather than raw device motion: it also arrives on Wayland and
            // from synthetic input (Xvfb), and looking stops at the window's edge anyway.
            WindowEvent::CursorMoved { position, .. } => {
                let position = Vec2::new(position.x as f32, position.y as f32);
                if let (true, Some(last)) = (self.input.looking, self.input.cursor) {
                    self.input.look += position - last;
                    self.needs_redraw = true;
                }
                self.input.cursor = Some(position);
            }
            WindowEvent::MouseInput {
                button: MouseButton::Right,
                state: button,
                ..
            } => {
                self.input.looking = button == ElementState::Pressed && self.over_view();
            }
            // Over the 3D view only: egui's own idea of where the pointer is lags a frame,
            // which at slow frame rates is a second or more.
            WindowEvent::MouseWheel { delta, .. } if self.over_view() => {
                self.needs_redraw = true;
                self.input.wheel += match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    // A wheel notch is about 40 pixels of touchpad scrolling.
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        if self.watch.as_mut().is_some_and(|w| w.poll(now)) {
            if let Err(e) = self.scene_file_changed() {
                self.fail(event_loop, e);
                return;
            }
        }
        // Every watch is polled, so that each takes in its file's change.
        let changed: Vec<PathBuf> = (self.inputs.iter_mut())
            .filter_map(|w| w.poll(now).then(|| w.path.clone()))
            .collect();
        if !changed.is_empty() {
            if let Err(e) = self.read_inputs_again(&changed) {
                self.fail(event_loop, e);
                return;
            }
        }
        let seconds = self.first_frame.map(|t| now.duration_since(t).as_secs_f64());
        if self.options.seconds.zip(seconds).is_some_and(|(limit, s)| s >= limit) {
            // A screenshot to take is one last frame, if the window can draw it.
            let last_frame = self.options.screenshot.is_some() && self.state.as_ref().is_some_and(Self::drawable);
            if !last_frame {
                self.close(event_loop);
                return;
            }
            self.time_up = true;
            self.needs_redraw = true;
        }
        let Some(state) = &self.state else { return };
        // Scripted runs of N frames draw continuously; otherwise a frame is drawn when
        // something changed, while the camera moves, when egui asks, and while a still
        // view of the sampled reflection refines (then once more, for the panel to say so).
        let continuous = self.options.frames.is_some() || self.options.resize_storm;
        let shown = self.view.accumulated;
        let renderer = &state.frames.renderer;
        let refining = renderer
            .accumulated()
            .is_some_and(|a| a.converging() || shown != Some(a));
        // Auto exposure: until a measured frame is back, and while it asks for another exposure.
        let exposing = renderer.measure_exposure
            && (renderer.luminance_histogram().is_none()
                || renderer
                    .auto_exposure()
                    .is_some_and(|e| (e / self.view.exposure_in_use - 1.0).abs() > EXPOSURE_SETTLED));
        // A frame reduced while the UI was in use is followed by a full one.
        let restoring = state.frames.scale() > 1 && !responsive::in_use(&self.egui, self.input.camera_moving());
        let wanted = continuous
            || restoring
            || refining
            || exposing
            || self.needs_redraw
            || self.input.looking && self.input.look != Vec2::ZERO
            || self.input.moving()
            || self.repaint_at.is_some_and(|t| t <= now);
        if Self::drawable(state) && wanted {
            event_loop.set_control_flow(ControlFlow::Poll);
            state.window.request_redraw();
            return;
        }
        // Idle, or minimised: no frames, but a tick now and then for the file watch, the
        // storm, egui's next repaint and the time limit.
        if now >= self.next_idle_tick {
            self.next_idle_tick = now + IDLE_TICK;
            if !Self::drawable(state) {
                state.window.request_redraw();
            }
        }
        let wake = self
            .repaint_at
            .map_or(self.next_idle_tick, |t| t.min(self.next_idle_tick));
        event_loop.set_control_flow(ControlFlow::WaitUntil(wake));
    }
}

impl App {
    /// Whether the cursor is over the 3D view rather than the UI.
    fn over_view(&self) -> bool {
        let Some(cursor) = self.input.cursor else { return false };
        let ppp = self.egui.pixels_per_point();
        self.view.view_rect.contains(egui::pos2(cursor.x / ppp, cursor.y / ppp))
            && !self.egui.is_pointer_over_egui()
            && self.view.question.is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view_options() -> ViewOptions {
        ViewOptions {
            device: DeviceChoice::Best,
            validation: false,
            frames: None,
            exposure: 1.0,
            size: (320, 180),
            screenshot: None,
            resize_storm: false,
            seconds: None,
            soak_log: None,
            outputs: Existing::Refuse,
            debug_view: DebugView::default(),
            split: None,
        }
    }

    /// A scene file changed on disk is read again at once, unless the scene has unsaved
    /// changes: then they stay until the user asks for the file, and Save, which would
    /// write over its new text, asks again.
    #[test]
    fn a_scene_file_changed_on_disk_asks_before_losing_unsaved_changes() {
        let dir = crate::scene::tests::TempDir::new();
        let text = |roughness| {
            let object = "[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"clay\"\n";
            format!("{object}[materials.clay]\nroughness = {roughness}\n")
        };
        let path = dir.write("scene.toml", &text(0.5));
        let (viewable, document) = load_document(&path).unwrap();
        let mut app = App::new(viewable, document, view_options(), Instant::now());
        let roughness = |app: &App| app.scene.materials[0].roughness;

        std::fs::write(&path, text(0.7)).unwrap();
        app.scene_file_changed().unwrap();
        assert_eq!((roughness(&app), &app.view.question), (0.7, &None), "nothing to lose: read");

        app.scene.materials[0].roughness = 0.2;
        std::fs::write(&path, text(0.9)).unwrap();
        app.scene_file_changed().unwrap();
        assert_eq!(app.view.question, Some(Question::Reload));
        assert_eq!(roughness(&app), 0.2, "the unsaved change stays");
        // Kept, it is not saved over the file's new text: Save asks again.
        app.view.question = None;
        app.save_to(path.clone(), false);
        assert_eq!(app.view.question, Some(Question::Reload));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text(0.9));
        app.reload().unwrap();
        assert_eq!(roughness(&app), 0.9);
    }

    /// A texture rewritten on disk is read again without losing the edits' undo steps,
    /// which still apply: the scene names the same files.
    #[test]
    fn reading_a_rewritten_texture_again_keeps_the_undo_steps() {
        let dir = crate::scene::tests::TempDir::new();
        let texture = dir.0.join("colour.png");
        let colour = |rgb| image::RgbImage::from_pixel(2, 2, image::Rgb(rgb)).save(&texture).unwrap();
        colour([255, 0, 0]);
        let path = dir.write(
            "scene.toml",
            "[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"clay\"\n\n\
             [materials.clay]\nroughness = 0.5\n[materials.clay.base_color_map]\ntexture = \"colour.png\"\n",
        );
        let (viewable, document) = load_document(&path).unwrap();
        let mut app = App::new(viewable, document, view_options(), Instant::now());
        app.scene.materials[0].roughness = 0.2;
        app.history.observe(&app.scene, true);

        colour([0, 255, 0]);
        app.read_inputs_again(std::slice::from_ref(&texture)).unwrap();
        assert_eq!(&app.scene.textures[0].pixels[..4], &[0, 255, 0, 255], "the new texels");
        assert_eq!(app.scene.materials[0].roughness, 0.2, "the edit is kept");
        app.history.undo(&mut app.scene);
        assert_eq!(app.scene.materials[0].roughness, 0.5, "and can be undone");
    }
}
