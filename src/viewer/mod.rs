//! The interactive viewer: a window whose swapchain shows the same HDR frame that
//! `argil render` writes, through the same display transform.

mod frames;

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result};
use ash::vk;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use crate::scene::Scene;
use crate::vk::{Device, DeviceChoice, DeviceOptions, WindowHandles};
use frames::FrameLoop;

pub struct ViewOptions {
    pub device: DeviceChoice,
    pub validation: bool,
    /// Close after this many frames (for tests and scripted runs).
    pub frames: Option<u64>,
    pub exposure: f32,
    pub scene_path: Option<PathBuf>,
}

/// Opens a window on the scene and runs until it is closed.
pub fn run(scene: Scene, options: ViewOptions) -> Result<()> {
    let event_loop = EventLoop::new().context("cannot open a window: no display?")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { scene, options, state: None, error: None };
    event_loop.run_app(&mut app).context("the window's event loop failed")?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct Running {
    // Dropped first: everything in it holds the device.
    frames: FrameLoop,
    window: Arc<Window>,
}

struct App {
    scene: Scene,
    options: ViewOptions,
    state: Option<Running>,
    error: Option<anyhow::Error>,
}

impl App {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let title = match &self.options.scene_path {
            Some(p) => format!("argil — {}", p.display()),
            None => "argil — default clay scene".to_owned(),
        };
        let attributes = Window::default_attributes().with_title(title).with_inner_size(PhysicalSize::new(1280, 720));
        let window = Arc::new(event_loop.create_window(attributes).context("cannot create a window")?);
        let handles = WindowHandles {
            display: window.display_handle().context("window has no display handle")?.as_raw(),
            window: window.window_handle().context("window has no window handle")?.as_raw(),
        };
        let device = Arc::new(Device::new(
            DeviceOptions { choice: self.options.device.clone(), validation: self.options.validation },
            Some(handles),
        )?);
        eprintln!("argil: rendering on {}", device.info.name);
        let size = window.inner_size();
        let frames = FrameLoop::new(device, &self.scene, vk::Extent2D { width: size.width, height: size.height })?;
        self.state = Some(Running { frames, window });
        Ok(())
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.error = Some(error);
        self.state = None;
        event_loop.exit();
    }
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
        match event {
            WindowEvent::CloseRequested => {
                self.state = None;
                event_loop.exit();
            }
            WindowEvent::Resized(size) => state.frames.resize(vk::Extent2D { width: size.width, height: size.height }),
            WindowEvent::RedrawRequested => {
                let drawn = state.frames.draw(&self.scene, self.options.exposure);
                match drawn {
                    Err(e) => self.fail(event_loop, e),
                    Ok(()) => {
                        if self.options.frames.is_some_and(|n| state.frames.frame_count() >= n) {
                            let result = state.frames.finish();
                            self.state = None;
                            if let Err(e) = result {
                                self.error = Some(e);
                            }
                            event_loop.exit();
                        }
                    }
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }
}
