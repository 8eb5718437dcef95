//! The interactive viewer: a window whose swapchain shows the same HDR frame that
//! `argil render` writes, through the same display transform, with a UI over it to edit
//! materials and lights live, switch debug views and watch timings. The scene file is
//! reloaded when it changes on disk; Save writes the edited scene back.

mod camera_control;
mod frames;
mod overlay;
mod panels;
mod shadow_panel;
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

use crate::render::environment::equirect;
use crate::render::gpu_scene::FrameData;
use crate::scene::{Environment, Scene};
use crate::vk::{Device, DeviceChoice, DeviceOptions, WindowHandles};
use camera_control::{frame_sphere, movement_from_keys, object_bounds, scene_bounds, CameraControl, Input};
use frames::{gpu_pass_names, Capture, CaptureStage, FrameLoop, UiFrame};
use panels::{Actions, ViewState};
use storm::StormStep;
use timings::{FrameTimes, Timings};
use watch::FileWatch;

pub use panels::PANEL_WIDTH;
/// Redraws the resize storm lasts; `--frames` beyond it render at the storm's last size.
pub const RESIZE_STORM_TICKS: u64 = storm::DURATION;

/// Where Save writes the embedded default scene, which has no file of its own.
pub const DEFAULT_SAVE_PATH: &str = "argil-scene.toml";

/// How often the loop wakes while the window is minimised, to notice it coming back.
const IDLE_TICK: Duration = Duration::from_millis(100);
/// Camera steps are cut at this many seconds, so a stall does not fling the camera away.
const MAX_STEP_SECONDS: f32 = 0.1;

pub struct ViewOptions {
    pub device: DeviceChoice,
    pub validation: bool,
    /// Close after this many frames (for tests and scripted runs).
    pub frames: Option<u64>,
    pub exposure: f32,
    pub scene_path: Option<PathBuf>,
    /// Initial inner size of the window in pixels.
    pub size: (u32, u32),
    /// Write what the window shows, UI included, after the last frame.
    pub screenshot: Option<PathBuf>,
    /// Resize, minimise and restore the window while rendering (for tests).
    pub resize_storm: bool,
}

/// Writes `scene` to `path` as a scene file.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<()> {
    let text = scene.to_file().to_toml().context("cannot write the scene as TOML")?;
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// Loads a scene file that the viewer can show: valid, within the renderer's limits, and
/// with an environment map that decodes, so that a bad edit is reported while the last good
/// scene stays on screen.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let scene = Scene::load(path)?;
    FrameData::new(&scene, 1.0)?;
    if let Environment::Map { path, .. } = &scene.environment {
        equirect::load(path)?;
    }
    Ok(scene)
}

/// Opens a window on the scene and runs until it is closed.
pub fn run(scene: Scene, options: ViewOptions) -> Result<()> {
    let event_loop = EventLoop::new().context("cannot open a window: no display?")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let now = Instant::now();
    let save_path = options
        .scene_path
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SAVE_PATH));
    let mut app = App {
        view: ViewState {
            debug_view: Default::default(),
            shadows: true,
            exposure: options.exposure,
            selected_object: 0,
            selected_material: scene.objects[0].material,
            show_help: false,
            error: None,
            notice: None,
            timings: Timings::new(gpu_pass_names()),
            device_name: String::new(),
            save_path: save_path.display().to_string(),
        },
        watch: options.scene_path.clone().map(|p| FileWatch::new(p, now)),
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
        ticks: 0,
        final_screenshot_written: false,
    };
    event_loop.run_app(&mut app).context("the window's event loop failed")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

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
    scene: Scene,
    options: ViewOptions,
    view: ViewState,
    camera: CameraControl,
    input: InputState,
    /// Asked for by keys, done with the next frame.
    pending: Actions,
    egui: egui::Context,
    watch: Option<FileWatch>,
    state: Option<Running>,
    error: Option<anyhow::Error>,
    last_frame: Option<Instant>,
    next_idle_tick: Instant,
    /// Redraw requests so far, drawn or not: the resize storm's clock.
    ticks: u64,
    final_screenshot_written: bool,
}

impl App {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let title = match &self.options.scene_path {
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
        let frames = FrameLoop::new(
            device,
            &self.scene,
            vk::Extent2D {
                width: size.width,
                height: size.height,
            },
        )?;
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
            let mean = self.view.timings.mean();
            let gpu: Vec<String> = self
                .view
                .timings
                .pass_names
                .iter()
                .zip(&mean.gpu_ms)
                .map(|(n, ms)| format!("{n} {ms:.2} ms"))
                .collect();
            eprintln!(
                "argil: {} frames, {} swapchain recreations; mean CPU frame {:.2} ms, GPU {}",
                state.frames.frame_count(),
                state.frames.recreations(),
                mean.cpu_ms,
                gpu.join(", ")
            );
            if let Err(e) = finished {
                self.error.get_or_insert(e);
            }
            if self.options.screenshot.is_some() && !self.final_screenshot_written {
                self.error
                    .get_or_insert(anyhow!("the window closed before the screenshot was taken"));
            }
        }
        event_loop.exit();
    }

    fn key_pressed(&mut self, key: KeyCode) {
        let ctrl = self.input.modifiers.control_key();
        match key {
            KeyCode::Tab | KeyCode::KeyO => self.camera.toggle_mode(),
            KeyCode::KeyF => self.pending.frame_scene = true,
            KeyCode::KeyH | KeyCode::F1 => self.view.show_help = !self.view.show_help,
            KeyCode::F12 => self.pending.screenshot = true,
            KeyCode::KeyS if ctrl => self.pending.save = true,
            _ => {}
        }
    }

    fn reload(&mut self) -> Result<()> {
        let Some(path) = self.watch.as_ref().map(|w| w.path.clone()) else {
            return Ok(());
        };
        match load_scene(&path) {
            Ok(mut scene) => {
                scene.camera = self.scene.camera;
                if let Some(state) = &mut self.state {
                    state.frames.set_scene(&scene)?;
                }
                self.scene = scene;
                self.view.clamp_selection(&self.scene);
                self.view.error = None;
                eprintln!("argil: reloaded {}", path.display());
                self.view.notice = Some(format!("reloaded {}", path.display()));
            }
            Err(e) => {
                eprintln!("argil: {e:#}");
                self.view.error = Some(format!("{e:#}"));
            }
        }
        Ok(())
    }

    fn save(&mut self) {
        let path = PathBuf::from(&self.view.save_path);
        match save_scene(&self.scene, &path) {
            Ok(()) => {
                self.view.error = None;
                self.view.notice = Some(format!("saved {}", path.display()));
                match &mut self.watch {
                    Some(watch) => watch.mark_seen(),
                    None => {
                        self.scene.source = Some(path.clone());
                        self.watch = Some(FileWatch::new(path, Instant::now()));
                    }
                }
            }
            Err(e) => self.view.error = Some(format!("{e:#}")),
        }
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
        if self.watch.as_mut().is_some_and(|w| w.poll(now)) {
            self.reload()?;
        }
        let Some(state) = self.state.as_mut() else {
            return Ok(());
        };
        if !Self::drawable(state) {
            return Ok(());
        }
        self.last_frame = Some(now);

        let pivot = object_bounds(&self.scene, self.view.selected_object).0;
        self.camera.update(
            &mut self.scene.camera,
            pivot,
            &self.input.take(),
            dt.min(MAX_STEP_SECONDS),
        );

        let raw = state.egui.take_egui_input(&state.window);
        let mut actions = std::mem::take(&mut self.pending);
        let output = self.egui.run_ui(raw, |ui| {
            let clicked = panels::show(ui, &mut self.scene, &mut self.view, &mut self.camera);
            actions.save |= clicked.save;
            actions.screenshot |= clicked.screenshot;
            actions.frame_scene |= clicked.frame_scene;
        });
        state.egui.handle_platform_output(&state.window, output.platform_output);
        let primitives = self.egui.tessellate(output.shapes, output.pixels_per_point);

        if actions.frame_scene {
            let size = state.window.inner_size();
            let (centre, radius) = scene_bounds(&self.scene);
            self.scene.camera = frame_sphere(
                &self.scene.camera,
                centre,
                radius,
                size.width as f32 / size.height as f32,
            );
        }
        let last_frame = self.options.frames.is_some_and(|n| state.frames.frame_count() + 1 >= n);
        let capture = match (&self.options.screenshot, last_frame) {
            (Some(path), true) => Some(Capture {
                path: path.clone(),
                stage: CaptureStage::AfterUi,
            }),
            _ if actions.screenshot => Some(Capture {
                path: next_screenshot_path(),
                stage: CaptureStage::BeforeUi,
            }),
            _ => None,
        };
        state.frames.renderer.debug_view = self.view.debug_view;
        state.frames.renderer.shadows = self.view.shadows;
        let ui = UiFrame {
            primitives,
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
        };
        let drawn = state.frames.draw(&self.scene, self.view.exposure, ui, capture)?;
        if !drawn {
            // Asked again with the next frame that is drawn.
            self.pending.screenshot |= actions.screenshot;
        }
        self.view.timings.push(FrameTimes {
            cpu_ms: f64::from(dt) * 1e3,
            gpu_ms: state.frames.gpu_ms().map(<[f64]>::to_vec).unwrap_or_default(),
        });
        let screenshots = state.frames.take_screenshots();
        let done = self.options.frames.is_some_and(|n| state.frames.frame_count() >= n);
        self.report_screenshots(screenshots);
        if actions.save {
            self.save();
        }
        if done {
            self.close(event_loop);
        }
        Ok(())
    }
}

/// `argil-screenshot-N.png` in the working directory, for the first N not taken.
fn next_screenshot_path() -> PathBuf {
    (1..)
        .map(|n| PathBuf::from(format!("argil-screenshot-{n}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| PathBuf::from("argil-screenshot.png"))
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_none() {
            if let Err(e) = self.start(event_loop) {
                self.fail(event_loop, e);
            }
        }
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
        match event {
            WindowEvent::CloseRequested => self.close(event_loop),
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
                }
                self.input.cursor = Some(position);
            }
            WindowEvent::MouseInput {
                button: MouseButton::Right,
                state: button,
                ..
            } => {
                self.input.looking = button == ElementState::Pressed && !self.egui.egui_wants_pointer_input();
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed && !self.egui.egui_wants_pointer_input() => {
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
        let Some(state) = &self.state else { return };
        if Self::drawable(state) {
            event_loop.set_control_flow(ControlFlow::Poll);
            state.window.request_redraw();
            return;
        }
        // Minimised: no frames, but a tick now and then for the file watch and the storm.
        let now = Instant::now();
        if now >= self.next_idle_tick {
            self.next_idle_tick = now + IDLE_TICK;
            state.window.request_redraw();
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.next_idle_tick));
    }
}
