//! The window and its event loop (winit 0.30's `ApplicationHandler`): opens the window and the
//! renderer on it when the loop starts, turns input into view changes, and draws on demand —
//! only after something changed, or frame after frame while `--frames` runs.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use pelt_core::export::{PngOptions, save_png};
use pelt_core::pipeline::FurAsset;
use pelt_render::{AdapterChoice, FrameInfo, FurScene, PresentedFrame, Renderer, ShellMethod, WindowSurface};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::controls::{Action, Drag, HELP, Outcome, ViewState, key_action, wheel_lines};
use super::orbit::Sphere;
use super::readout::{FrameTimes, Refresh, Shown, title};
use super::{Size, os_message};

/// Consecutive frames the window may refuse (occluded, timed out) while `--frames` runs before
/// the viewer gives up.
const MAX_SKIPS: u32 = 600;

/// What `pelt view` was asked to do.
pub struct Options {
    pub adapter: AdapterChoice,
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    pub size: Size,
    pub object: String,
    pub asset: FurAsset,
}

/// The open window with its renderer and scene.
struct Viewer {
    window: Arc<Window>,
    renderer: Renderer,
    surface: WindowSurface,
    scene: FurScene,
    sphere: Sphere,
    state: ViewState,
    drag: Drag,
    times: FrameTimes,
    refresh: Refresh,
    /// What the last frame drew, for the title.
    last: Option<FrameInfo>,
    title_pending: bool,
}

pub struct App {
    options: Options,
    viewer: Option<Viewer>,
    error: Option<String>,
    /// Frames presented so far.
    presented: u32,
    /// Frames the window refused in a row.
    skips: u32,
    saved: bool,
}

impl App {
    pub fn new(options: Options) -> Self {
        App {
            options,
            viewer: None,
            error: None,
            presented: 0,
            skips: 0,
            saved: false,
        }
    }

    /// The outcome once the event loop has ended.
    pub fn finish(self) -> Result<(), String> {
        if let Some(error) = self.error {
            return Err(error);
        }
        if let Some(frames) = self.options.frames
            && self.presented < frames
        {
            return Err(format!(
                "the window closed after {} of {frames} frames",
                self.presented
            ));
        }
        match &self.options.screenshot {
            Some(path) if !self.saved => Err(format!(
                "{}: no frame was drawn, so no screenshot was saved",
                path.display()
            )),
            _ => Ok(()),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        self.error.get_or_insert(message);
        event_loop.exit();
    }

    /// Opens the window, the renderer on it and the scene.
    fn open(&self, event_loop: &ActiveEventLoop) -> Result<Viewer, String> {
        let Size { width, height } = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("pelt view")
            .with_inner_size(PhysicalSize::new(width, height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| format!("cannot open a window: {}", os_message(&e)))?,
        );
        // The window manager may not grant the size asked for.
        let size = window.inner_size();
        let (width, height) = match (size.width, size.height) {
            (0, _) | (_, 0) => (width, height),
            (w, h) => (w, h),
        };
        let (renderer, surface) = Renderer::for_window(
            self.options.adapter,
            Box::new(event_loop.owned_display_handle()),
            window.clone(),
            width,
            height,
        )
        .map_err(|e| e.to_string())?;
        let asset = &self.options.asset;
        let scene = FurScene::from_asset(&renderer, asset).map_err(|e| e.to_string())?;
        let fur_depth = asset.params.fur_depth();
        let tallest = asset
            .mesh
            .length()
            .map_or(1.0, |l| l.iter().copied().fold(0.0f32, f32::max));
        let sphere = Sphere::around(asset.mesh.positions(), fur_depth * f64::from(tallest));
        let mut state = ViewState::new(
            scene.layers(),
            scene.transfer_order().is_some(),
            scene.has_planes(),
        );
        // Start with the faster method on this adapter (marched on a CPU); M switches.
        state.marched = renderer.shell_method(ShellMethod::Auto) == ShellMethod::Marched;
        let adapter = renderer.adapter();
        println!(
            "pelt view: {} on {} ({}, {}), {}x{} {:?}",
            self.options.object,
            adapter.name,
            adapter.backend,
            adapter.device_type,
            width,
            height,
            surface.format()
        );
        println!("{HELP}");
        Ok(Viewer {
            window,
            renderer,
            surface,
            scene,
            sphere,
            state,
            drag: Drag::default(),
            times: FrameTimes::default(),
            refresh: Refresh::new(),
            last: None,
            title_pending: false,
        })
    }

    fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) {
        let Some(viewer) = &mut self.viewer else {
            return;
        };
        match viewer.state.apply(action) {
            Outcome::Redraw => viewer.window.request_redraw(),
            Outcome::Unchanged => {}
            Outcome::Refused(why) => println!("{why}"),
            Outcome::Quit => self.quit(event_loop),
        }
    }

    /// Ends the loop; without `--frames`, the screenshot is the view shown now.
    fn quit(&mut self, event_loop: &ActiveEventLoop) {
        if self.options.frames.is_none() && self.options.screenshot.is_some() && !self.saved {
            match self.draw(true) {
                Ok(Some(frame)) => {
                    if let Err(e) = self.save(frame) {
                        return self.fail(event_loop, e);
                    }
                }
                Ok(None) => {}
                Err(e) => return self.fail(event_loop, e),
            }
        }
        event_loop.exit();
    }

    /// Draws and presents a frame (read back with `capture`); `None` when the window had no
    /// texture for it.
    fn draw(&mut self, capture: bool) -> Result<Option<PresentedFrame>, String> {
        let Some(viewer) = &mut self.viewer else {
            return Ok(None);
        };
        let (width, height) = viewer.surface.size();
        let camera = viewer.state.orbit.camera(&viewer.sphere, width, height);
        let frame = viewer
            .surface
            .draw(
                &viewer.renderer,
                &viewer.scene,
                &camera,
                &viewer.state.lighting(),
                &viewer.state.settings(),
                capture,
            )
            .map_err(|e| e.to_string())?;
        if let Some(frame) = &frame {
            viewer.times.push(frame.seconds);
            viewer.last = Some(frame.info);
            viewer.title_pending = true;
        }
        Ok(frame)
    }

    fn save(&mut self, frame: PresentedFrame) -> Result<(), String> {
        let (Some(path), Some(image)) = (&self.options.screenshot, frame.image) else {
            return Ok(());
        };
        let options = PngOptions {
            srgb: true,
            ..PngOptions::default()
        };
        save_png(path, &image.view().map_err(|e| e.to_string())?, &options).map_err(|e| e.to_string())?;
        println!("pelt view: saved {}", path.display());
        self.saved = true;
        Ok(())
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let frames = self.options.frames;
        let capture = self.options.screenshot.is_some() && frames == Some(self.presented + 1);
        let frame = match self.draw(capture) {
            Ok(frame) => frame,
            Err(e) => return self.fail(event_loop, e),
        };
        let Some(frame) = frame else {
            self.skips += 1;
            // Outdated surfaces were configured again and draw on the next try; a window that
            // keeps refusing waits for an event (exposed, resized) unless frames are counted.
            if frames.is_some() && self.skips > MAX_SKIPS {
                return self.fail(
                    event_loop,
                    format!("the window refused {MAX_SKIPS} frames in a row (is it hidden?)"),
                );
            }
            if frames.is_some() || self.skips == 1 {
                self.request_redraw();
            }
            return;
        };
        self.skips = 0;
        self.presented += 1;
        if let Err(e) = self.save(frame) {
            return self.fail(event_loop, e);
        }
        match frames {
            Some(n) if self.presented >= n => event_loop.exit(),
            Some(_) => self.request_redraw(),
            None => {}
        }
    }

    fn request_redraw(&self) {
        if let Some(viewer) = &self.viewer {
            viewer.window.request_redraw();
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.viewer.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(viewer) => {
                viewer.window.request_redraw();
                self.viewer = Some(viewer);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => self.quit(event_loop),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::Resized(size) => {
                let Some(viewer) = &mut self.viewer else {
                    return;
                };
                // A minimized window has no size to draw at; it is drawn again once it has one.
                if size.width == 0 || size.height == 0 || (size.width, size.height) == viewer.surface.size() {
                    return;
                }
                match viewer.surface.resize(&viewer.renderer, size.width, size.height) {
                    Ok(()) => viewer.window.request_redraw(),
                    Err(e) => self.fail(event_loop, e.to_string()),
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if let Some(action) = key_action(&event.logical_key) {
                    self.act(event_loop, action);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                if let Some(viewer) = &mut self.viewer {
                    viewer.drag.button(button, state);
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let action = self
                    .viewer
                    .as_mut()
                    .and_then(|v| v.drag.moved(position.x, position.y));
                if let Some(action) = action {
                    self.act(event_loop, action);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => self.act(event_loop, Action::Zoom(wheel_lines(delta))),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(viewer) = &mut self.viewer else {
            return;
        };
        let flow = match (viewer.title_pending, viewer.last) {
            (true, Some(info)) => match viewer.refresh.due(Instant::now()) {
                None => {
                    let adapter = viewer.renderer.adapter();
                    let shown = Shown {
                        object: &self.options.object,
                        info: &info,
                        lod: viewer.state.lod,
                        fins: viewer.state.fins,
                        marched: viewer.state.marched,
                        model: viewer.state.model_name(),
                        adapter: &adapter.name,
                    };
                    viewer.window.set_title(&title(viewer.times.median(), &shown));
                    viewer.title_pending = false;
                    ControlFlow::Wait
                }
                Some(due) => ControlFlow::WaitUntil(due),
            },
            _ => ControlFlow::Wait,
        };
        event_loop.set_control_flow(flow);
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        // The surface must go before the display connection the loop closes.
        self.viewer = None;
    }
}
