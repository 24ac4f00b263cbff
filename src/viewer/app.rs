//! The window: winit event loop, a glutin GL context on the window, egui through egui_glow,
//! and the frame loop that ties the [`Studio`] to the renderer.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glow::HasContext;
use glutin::config::{Config, ConfigTemplateBuilder, GlConfig};
use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, NotCurrentGlContext, PossiblyCurrentContext, Version};
use glutin::display::{GetGlDisplay, GlDisplay};
use glutin::surface::{GlSurface, Surface, SwapInterval, WindowSurface};
use glutin_winit::GlWindow;
use raw_window_handle::HasWindowHandle;
use winit::application::ApplicationHandler;
use winit::event::{StartCause, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use super::display::{read_window, Subject, WindowRect, View3d};
use super::studio::EnvStart;
use super::studio::{Mode, Start, Studio};
use crate::error::{Error, Result};
use crate::gl::Gl;
use crate::render::Renderer;
use crate::scene::{Camera, Light, Projection};

/// How `brdfpaint view` runs.
pub struct Options {
    pub start: Start,
    /// `view --lit-sphere`: a lit sphere opened (its light estimated) to start with.
    pub lit_sphere: Option<crate::live::SphereSession>,
    /// `view --env`: an environment to start with.
    pub env: Option<EnvStart>,
    /// `view LIB/`: a library's name and its materials, in order, to step through.
    pub library: Option<(String, Vec<(String, crate::material::Material)>)>,
    /// Initial window size, physical pixels.
    pub window: [u32; 2],
    /// Exit after this many frames (tests).
    pub frames: Option<u64>,
    /// Save the window's pixels after the last frame (with a JSON of the camera and light
    /// beside it).
    pub screenshot: Option<PathBuf>,
    /// Keep the window up this long after the screenshot (so an X screenshot can be taken).
    pub hold: Duration,
}

/// What was drawn in a screenshot, for checking it (written as `OUT.json` beside `OUT.png`).
#[derive(serde::Serialize)]
pub struct ScreenshotInfo {
    /// Window size, pixels.
    pub window: [u32; 2],
    /// The 3D view's rectangle, window pixels from the top-left corner.
    pub view_rect: Option<WindowRect>,
    /// The egui side panel's rectangle.
    pub panel_rect: Option<WindowRect>,
    /// World from camera, column-major.
    pub world_from_camera: [f32; 16],
    pub yfov: f32,
    pub znear: f32,
    pub zfar: f32,
    /// The direction the light travels (glTF), its colour and intensity.
    pub light_direction: [f32; 3],
    pub light_color: [f32; 3],
    pub light_intensity: f32,
    pub model: String,
    pub material: String,
    /// The window's title (it names the material shown).
    pub title: String,
    /// sRGB-encoded background of the 3D view, 0..255.
    pub background: [u8; 3],
    pub frames: u64,
    /// The environment ("none", a bundled name or a file), its rotation in degrees, the
    /// exposure in stops and the directions per pixel of the last frame.
    pub environment: String,
    pub env_rotate_deg: f32,
    pub exposure: f32,
    pub env_samples: usize,
    /// The 3D view's render scale at the last frame.
    pub render_scale: f32,
    /// Whether the render scale was chosen from frame times.
    pub render_scale_auto: bool,
    /// Median whole-redraw time of the last window of frames, milliseconds (what the
    /// render scale is chosen from; BENCHMARKS.md, "Viewer frame time").
    pub frame_ms: Option<f64>,
    /// "view" or "paint".
    pub mode: String,
    /// The View and Paint buttons, window pixels.
    pub mode_buttons: [Option<WindowRect>; 2],
    /// The status line, as the panel shows it.
    pub status: String,
    /// Undo steps of the painted view.
    pub can_undo: bool,
    /// Samples painted over all views.
    pub painted: usize,
    pub gl_renderer: String,
    pub gl_version: String,
}

/// Opens the window and runs until it is closed (or `frames` have been drawn).
pub fn run(options: Options) -> Result<()> {
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Gl(format!("cannot open a window: {e} (is there an X display? try `xvfb-run -a brdfpaint view`)"))
    })?;
    let mut app = App { options: Some(options), running: None, result: Ok(()), repaint_at: Arc::new(Mutex::new(None)) };
    event_loop.run_app(&mut app).map_err(|e| Error::Gl(format!("the window's event loop failed: {e}")))?;
    app.result
}

struct App {
    options: Option<Options>,
    running: Option<Running>,
    result: Result<()>,
    /// When egui asked for its next frame.
    repaint_at: Arc<Mutex<Option<Instant>>>,
}

/// The window and everything drawn in it. Field order is drop order: GL objects go before
/// the context that owns them.
struct Running {
    studio: Studio,
    view3d: View3d,
    renderer: Renderer,
    egui: egui_glow::EguiGlow,
    gl: Gl,
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    window: Window,
    frames: u64,
    max_frames: Option<u64>,
    screenshot: Option<PathBuf>,
    hold: Duration,
    exit_at: Option<Instant>,
    gl_renderer: String,
    gl_version: String,
    last_camera: Option<(Camera, Light)>,
    repaint_at: Arc<Mutex<Option<Instant>>>,
    /// The window's title now.
    title: String,
}

/// The window's title: the material shown, then the tool.
fn window_title(material: &str) -> String {
    format!("{material} — brdfpaint")
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(options) = self.options.take() else { return };
        match Running::new(event_loop, options, self.repaint_at.clone()) {
            Ok(r) => self.running = Some(r),
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn new_events(&mut self, _: &ActiveEventLoop, cause: StartCause) {
        if let (StartCause::ResumeTimeReached { .. }, Some(r)) = (cause, &self.running) {
            r.window.request_redraw();
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else { return };
        match &event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => {
                event_loop.exit();
                return;
            }
            WindowEvent::RedrawRequested => {
                match r.redraw() {
                    Ok(true) => event_loop.exit(),
                    Ok(false) => {}
                    Err(e) => {
                        self.result = Err(e);
                        event_loop.exit();
                    }
                }
                return;
            }
            WindowEvent::Resized(size) => {
                if let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) {
                    r.surface.resize(&r.context, w, h);
                }
                r.window.request_redraw();
            }
            _ => {}
        }
        if r.egui.on_window_event(&r.window, &event).repaint {
            r.window.request_redraw();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(r) = self.running.as_ref() else { return };
        let now = Instant::now();
        if let Some(t) = r.exit_at {
            // Holding the finished window for an X screenshot: nothing more to draw.
            if now >= t {
                event_loop.exit();
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(t));
            }
            return;
        }
        if r.max_frames.is_some_and(|n| r.frames < n) || r.studio.busy() {
            r.window.request_redraw();
            event_loop.set_control_flow(ControlFlow::Poll);
            return;
        }
        let mut next = self.repaint_at.lock().map(|g| *g).unwrap_or(None);
        // Look at a watched file five times a second, for a background prepare's result
        // fifty times (without spinning: the prepare needs the CPU), and for the full fit ten
        // times: a quarter of the pause it follows, and frames left to the worker's CPU.
        for (on, every) in [(r.studio.watching(), 200), (r.studio.preparing(), 20), (r.studio.settling(), 100)] {
            if on {
                let t = now + Duration::from_millis(every);
                next = Some(next.map_or(t, |n| n.min(t)));
            }
        }
        match next {
            Some(t) if t <= now => {
                r.window.request_redraw();
                event_loop.set_control_flow(ControlFlow::Poll);
            }
            Some(t) => event_loop.set_control_flow(ControlFlow::WaitUntil(t)),
            None => event_loop.set_control_flow(ControlFlow::Wait),
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        if let Some(mut r) = self.running.take() {
            r.egui.destroy();
            // GL objects are deleted while the context is still current.
            drop(r);
        }
    }
}

/// A config that draws to windows: a hardware-accelerated one when there is one, else the
/// first (Mesa's software rasterizer, under Xvfb).
fn pick_config(configs: Box<dyn Iterator<Item = Config> + '_>) -> Config {
    let all: Vec<Config> = configs.collect();
    let score = |c: &Config| (c.hardware_accelerated() as u8, c.srgb_capable() as u8 ^ 1, u8::MAX - c.num_samples());
    all.iter().max_by_key(|c| score(c)).cloned().or_else(|| all.into_iter().next()).expect("glutin returns at least one config")
}

/// The window, `size` physical pixels, with a GL config that draws to it ([`pick_config`]).
fn open_window(event_loop: &ActiveEventLoop, size: [u32; 2]) -> Result<(Window, Config)> {
    let attributes = Window::default_attributes()
        .with_title("brdfpaint")
        .with_inner_size(winit::dpi::PhysicalSize::new(size[0], size[1]));
    let template = ConfigTemplateBuilder::new().with_alpha_size(8).with_depth_size(0).with_stencil_size(0);
    let (window, config) = glutin_winit::DisplayBuilder::new()
        .with_preference(glutin_winit::ApiPreference::FallbackEgl)
        .with_window_attributes(Some(attributes.clone()))
        .build(event_loop, template, |configs| {
            let mut configs = configs.peekable();
            if configs.peek().is_none() {
                // Never reached in practice; keeps the picker total.
                panic!("no GL config");
            }
            pick_config(Box::new(configs))
        })
        .map_err(|e| Error::Gl(format!("cannot find a GL configuration for a window: {e}")))?;
    let window = match window {
        Some(w) => w,
        None => glutin_winit::finalize_window(event_loop, attributes, &config)
            .map_err(|e| Error::Gl(format!("cannot create the window: {e}")))?,
    };
    Ok((window, config))
}

/// The window's surface and a GL context made current on it, vsync where the driver has it.
fn current_context(
    display: &glutin::display::Display,
    config: &Config,
    window: &Window,
) -> Result<(Surface<WindowSurface>, PossiblyCurrentContext)> {
    let handle = window.window_handle().map_err(|e| Error::Gl(format!("no window handle: {e}")))?.as_raw();
    // GL 3.3 core (what the shaders are written for), else GLES 3.0, else whatever the
    // driver gives.
    let attempts = [
        ContextAttributesBuilder::new()
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .with_profile(GlProfile::Core)
            .build(Some(handle)),
        ContextAttributesBuilder::new().with_context_api(ContextApi::Gles(Some(Version::new(3, 0)))).build(Some(handle)),
        ContextAttributesBuilder::new().build(Some(handle)),
    ];
    let mut failures = Vec::new();
    let mut not_current = None;
    for a in &attempts {
        // SAFETY: the handle belongs to a live window.
        match unsafe { display.create_context(config, a) } {
            Ok(c) => {
                not_current = Some(c);
                break;
            }
            Err(e) => failures.push(e.to_string()),
        }
    }
    let not_current = not_current
        .ok_or_else(|| Error::Gl(format!("cannot create a GL context for the window: {}", failures.join("; "))))?;
    let surface_attributes = window
        .build_surface_attributes(Default::default())
        .map_err(|e| Error::Gl(format!("cannot describe the window surface: {e}")))?;
    // SAFETY: the attributes refer to the live window.
    let surface = unsafe { display.create_window_surface(config, &surface_attributes) }
        .map_err(|e| Error::Gl(format!("cannot create the window surface: {e}")))?;
    let context =
        not_current.make_current(&surface).map_err(|e| Error::Gl(format!("cannot make the GL context current: {e}")))?;
    // Vsync where the driver has it; not an error where it does not.
    let _ = surface.set_swap_interval(&context, SwapInterval::Wait(NonZeroU32::MIN));
    Ok((surface, context))
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, options: Options, repaint_at: Arc<Mutex<Option<Instant>>>) -> Result<Running> {
        let (window, config) = open_window(event_loop, options.window)?;
        let display = config.display();
        let (surface, context) = current_context(&display, &config, &window)?;

        let load = |s: &std::ffi::CStr| display.get_proc_address(s);
        // SAFETY: the context is current; the loader returns its functions.
        let glow_ours = unsafe { glow::Context::from_loader_function_cstr(load) };
        // SAFETY: as above; egui gets its own function table for the same context.
        let glow_egui = unsafe { glow::Context::from_loader_function_cstr(load) };
        // SAFETY: plain string queries on the current context.
        let (gl_renderer, gl_version) =
            unsafe { (glow_ours.get_parameter_string(glow::RENDERER), glow_ours.get_parameter_string(glow::VERSION)) };
        let gl = Gl::from_glow(glow_ours);
        let egui = egui_glow::EguiGlow::new(event_loop, Arc::new(glow_egui), None, None, true);
        let flag = repaint_at.clone();
        egui.egui_ctx.set_request_repaint_callback(move |info| {
            if let Ok(mut g) = flag.lock() {
                let t = Instant::now() + info.delay;
                *g = Some(g.map_or(t, |o: Instant| o.min(t)));
            }
        });
        let mut renderer = Renderer::new(&gl)?;
        let view3d = View3d::new(&gl)?;
        let mut studio = Studio::new(&mut renderer, options.start)?;
        if let Some(sphere) = options.lit_sphere {
            studio.start_lit_sphere(&mut renderer, sphere)?;
        }
        if let Some(env) = options.env {
            studio.start_environment(&renderer, env)?;
        }
        if let Some((name, materials)) = options.library {
            studio.open_library(&name, materials);
        }
        window.set_visible(true);
        window.request_redraw();
        Ok(Running {
            studio,
            view3d,
            renderer,
            egui,
            gl,
            surface,
            context,
            window,
            frames: 0,
            max_frames: options.frames,
            screenshot: options.screenshot,
            hold: options.hold,
            exit_at: None,
            gl_renderer,
            gl_version,
            last_camera: None,
            repaint_at,
            title: "brdfpaint".into(),
        })
    }

    /// One frame. `Ok(true)`: the frames asked for are done; exit.
    fn redraw(&mut self) -> Result<bool> {
        // egui asks again during this frame if it needs another.
        if let Ok(mut g) = self.repaint_at.lock() {
            *g = None;
        }
        let redraw_start = Instant::now();
        self.studio.tick(&mut self.renderer);
        // Shortcuts work wherever egui's focus is: taken out of the input before egui sees it.
        self.studio.handle_input(&self.egui.egui_ctx, self.egui.egui_winit.egui_input_mut());
        let (studio, renderer) = (&mut self.studio, &mut self.renderer);
        self.egui.run(&self.window, |ui| studio.ui(renderer, ui));
        self.studio.after(&mut self.renderer);
        let title = window_title(self.studio.material_name());
        if title != self.title {
            self.window.set_title(&title);
            self.title = title;
        }

        let size = self.window.inner_size();
        let (w, h) = (size.width.max(1), size.height.max(1));
        let start = Instant::now();
        let gl = &self.gl;
        // SAFETY: state changes on the current context; the default framebuffer is 0.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            gl.viewport(0, 0, w as i32, h as i32);
            gl.disable(glow::SCISSOR_TEST);
            let b = self.view3d.background;
            gl.clear_color(b[0], b[1], b[2], 1.0);
            gl.clear(glow::COLOR_BUFFER_BIT);
        }
        if let Some(rect) = self.studio.layout.view_rect {
            let aspect = rect.width.max(1) as f32 / rect.height.max(1) as f32;
            let stage = &mut self.studio.stage;
            let camera = stage.orbit.camera(aspect);
            let light = stage.light.light();
            stage.gpu_model.camera = camera;
            stage.gpu_model.light = light;
            self.last_camera = Some((camera, light));
            let scale = stage.render_scale.scale();
            let (stage, env) = (&self.studio.stage, self.studio.environment());
            let subject = Subject { scene: &stage.gpu_model, shading: stage.shading.as_ref(), lighting: env.lighting() };
            self.view3d.develop = env.develop();
            self.view3d.draw(&mut self.renderer, &subject, rect, h as i32, scale)?;
            self.studio.view_drawn();
            // SAFETY: waits for the GPU, to split the frame time into the view and the panel.
            unsafe { self.gl.finish() };
        }
        let view_ms = start.elapsed().as_secs_f64() * 1e3;
        self.egui.paint(&self.window);
        // SAFETY: waits for the GPU, so the frame time is the real one.
        unsafe { self.gl.finish() };
        let frame_ms = start.elapsed().as_secs_f64() * 1e3;
        self.frames += 1;

        let mut done = false;
        if self.max_frames == Some(self.frames) {
            if let Some(path) = self.screenshot.clone() {
                self.save_screenshot(&path, [w, h])?;
            }
            if self.hold.is_zero() {
                done = true;
            } else {
                self.exit_at = Some(Instant::now() + self.hold);
            }
        }
        self.surface
            .swap_buffers(&self.context)
            .map_err(|e| Error::Gl(format!("cannot present the frame: {e}")))?;
        self.studio.frame_done(frame_ms, view_ms, redraw_start.elapsed().as_secs_f64() * 1e3);
        Ok(done)
    }

    fn save_screenshot(&self, path: &std::path::Path, size: [u32; 2]) -> Result<()> {
        let image = read_window(&self.gl, size[0], size[1])?;
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write_to(&mut bytes, image::ImageFormat::Png).map_err(|e| Error::format(path, e.to_string()))?;
        crate::commit::write_atomic(path, bytes.get_ref())?;
        let stage = &self.studio.stage;
        let (camera, light) = self.last_camera.unwrap_or((stage.orbit.camera(1.0), stage.light.light()));
        let (yfov, znear, zfar) = match camera.projection {
            Projection::Perspective { yfov, znear, zfar, .. } => (yfov, znear, zfar.unwrap_or(f32::INFINITY)),
            Projection::Orthographic { znear, zfar, .. } => (0.0, znear, zfar),
        };
        let Light::Directional { direction, color, intensity } = light else {
            return Err(Error::Gl("the viewer's light is directional".into()));
        };
        let b = self.view3d.background.map(|x| (x * 255.0 + 0.5) as u8);
        let info = ScreenshotInfo {
            window: size,
            view_rect: self.studio.layout.view_rect,
            panel_rect: self.studio.layout.panel_rect,
            world_from_camera: camera.world_from_camera.to_cols_array(),
            yfov,
            znear,
            zfar,
            light_direction: direction.to_array(),
            light_color: color.to_array(),
            light_intensity: intensity,
            model: self.studio.model_name().to_string(),
            material: self.studio.material_name().to_string(),
            title: self.title.clone(),
            background: b,
            frames: self.frames,
            environment: self.studio.environment().name().to_string(),
            env_rotate_deg: self.studio.environment().rotate_deg,
            exposure: self.studio.environment().ev,
            env_samples: self.studio.environment().samples_now(),
            render_scale: stage.render_scale.scale(),
            render_scale_auto: stage.render_scale.is_auto(),
            frame_ms: stage.render_scale.median_frame_ms(),
            mode: if self.studio.mode == Mode::View { "view" } else { "paint" }.into(),
            mode_buttons: self.studio.layout.mode_buttons,
            status: self.studio.status(),
            can_undo: self.studio.session().views.iter().any(|v| v.canvas.can_undo()),
            painted: self.studio.session().painted(),
            gl_renderer: self.gl_renderer.clone(),
            gl_version: self.gl_version.clone(),
        };
        let json = serde_json::to_string_pretty(&info).map_err(|e| Error::format(path, e.to_string()))?;
        crate::commit::write_atomic(&path.with_extension("json"), json.as_bytes())
    }
}
