//! The viewer's state and its egui panel. Window and GL plumbing live in `app`; this module
//! only needs a [`Renderer`] to upload to.
//!
//! The state is split by what it is, each part in its own module:
//! - [`catalogue`]: the models and materials the 3D view can show, and which it shows;
//! - [`stage`]: what the 3D view draws (the model on the GPU, camera, light, render scale);
//! - [`easel`]: the live painting (session, views, watched file, what changed);
//! - [`tools`]: the paint tools; [`fit_controls`]: the fit settings;
//! - [`sphere`]: a lit sphere or MatCap as the view to paint, and its movable light;
//! - [`status`]: the status line, errors and timings; [`tables`]: the factor-table plots.
//!
//! The UI that draws them: [`panel`] (the side panel), [`central`] (canvas and 3D view),
//! [`shortcuts`] (keys that work wherever the focus is).

mod catalogue;
mod central;
mod easel;
mod environment;
mod fit_controls;
mod panel;
pub mod shortcuts;
mod sphere;
mod stage;
mod status;
mod tables;
mod tools;

use std::path::{Path, PathBuf};

use egui::Rect;

use self::catalogue::{entry_name, Catalogue};
use self::central::CanvasTextures;
use self::easel::Easel;
use self::fit_controls::FitControls;
use self::shortcuts::{take_shortcuts, Shortcut};
use self::status::{Status, TimingMeter};
use self::tables::TablePlots;
use self::tools::PaintTools;
use super::display::WindowRect;
use super::render_scale::RenderScale;
use crate::error::{Error, Result};
use crate::factor::Settings;
use crate::live::{example_painting, Painting, PaintSession, PaintView, WatchStatus, Watcher};
use crate::material::Material;
use crate::render::Renderer;
use crate::scene::{model_meshes, CpuMesh, Scene};

pub use self::environment::{Env, EnvStart};
pub use self::stage::Stage;
pub use self::status::Timings;
pub use self::tools::Tool;

/// Width of the side panel, points. Fixed: a panel that grows with its text (timings
/// appearing after the first stroke) would move the canvas under the brush.
pub const PANEL_WIDTH: f32 = 320.0;

/// What the central area shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The material on a model.
    View,
    /// A standard view to paint, beside the live material.
    Paint,
}

/// How the viewer starts.
pub struct Start {
    pub model: (String, Vec<CpuMesh>),
    pub material: Option<(String, Material)>,
    /// `--scene` (and `--watch`): the one view to paint.
    pub scene: Option<(String, Scene)>,
    pub watch: Option<PathBuf>,
    pub paint_model: String,
    pub size: usize,
    pub mode: Mode,
    /// Fraction of the window's resolution the 3D view renders at (see
    /// [`super::display::View3d::draw`]); `None`: chosen from frame times
    /// ([`super::render_scale`]).
    pub render_scale: Option<f32>,
    /// Where models' texture coordinates come from.
    pub uv: crate::scene::UvRule,
}

/// Where things are in the window, from the last [`Studio::ui`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Layout {
    /// The 3D view, window pixels.
    pub view_rect: Option<WindowRect>,
    /// The egui side panel, window pixels.
    pub panel_rect: Option<WindowRect>,
    /// The View and Paint buttons, window pixels (scripted tests click them).
    pub mode_buttons: [Option<WindowRect>; 2],
    pub pixels_per_point: f32,
}

/// Everything the window shows, and its controls.
pub struct Studio {
    pub mode: Mode,
    catalogue: Catalogue,
    pub stage: Stage,
    easel: Easel,
    tools: PaintTools,
    fit: FitControls,
    status: Status,
    meter: TimingMeter,
    tables: TablePlots,
    canvas_textures: CanvasTextures,
    save_material: String,
    sphere: sphere::Sphere,
    env: Env,
    pub layout: Layout,
}

impl Studio {
    /// The starting state; renders the first paint view (and fits its example painting when
    /// there is no `--scene`).
    pub fn new(renderer: &mut Renderer, start: Start) -> Result<Studio> {
        let catalogue = Catalogue::new(start.model, start.material, start.uv);
        let render_scale = start.render_scale.map_or_else(RenderScale::automatic, RenderScale::fixed);
        let stage = Stage::new(renderer, &catalogue.models[catalogue.model].meshes, render_scale)?;
        let fit = FitControls::default();
        let session = PaintSession::new(Settings::default(), fit.mapping);
        let mut studio = Studio {
            mode: start.mode,
            catalogue,
            stage,
            easel: Easel::new(session, start.paint_model, start.size, start.scene.is_some()),
            tools: PaintTools::default(),
            fit,
            status: Status::default(),
            meter: TimingMeter::default(),
            tables: TablePlots::default(),
            canvas_textures: CanvasTextures::default(),
            save_material: "material".into(),
            sphere: Default::default(),
            env: Env::default(),
            layout: Layout { pixels_per_point: 1.0, ..Layout::default() },
        };
        match start.scene {
            Some((name, scene)) => {
                // Size from the watched painting when it is readable and of the camera's
                // aspect (the size rule), else from the camera.
                let aspect = crate::sample::scene::camera_aspect(&scene.camera).unwrap_or(1.0);
                let h = start.size;
                let from_camera = (((h as f64) * aspect).round().max(1.0) as usize, h);
                let (w, h) = match start.watch.as_deref().map(Painting::read) {
                    Some(Ok(p)) if crate::sample::check_aspect(&scene.camera, p.width, p.height, &name).is_ok() => {
                        (p.width, p.height)
                    }
                    _ => from_camera,
                };
                let view = PaintView::new(renderer, &name, scene, w, h)?;
                studio.easel.add_view("", view);
                if let Some(path) = start.watch {
                    let mut w = Watcher::new(path, 0);
                    w.check(&mut studio.easel.session, renderer);
                    studio.easel.watcher = Some(w);
                }
            }
            None => {
                let k = studio.easel.open_view(renderer, crate::scene::preset::presets()[0].name)?;
                let example = example_painting(&studio.easel.session.views[k]);
                studio.easel.session.views[k].canvas.set_painting(&example)?;
                studio.easel.session.settle()?;
                studio.note("example painting fitted: paint over it, or clear it and start anew");
            }
        }
        Ok(studio)
    }

    /// The material shown now.
    pub fn current_material(&self) -> Option<&Material> {
        self.catalogue.current(&self.easel.session)
    }

    pub fn material_name(&self) -> &str {
        self.catalogue.material_name()
    }

    pub fn model_name(&self) -> &str {
        self.catalogue.model_name()
    }

    /// The status line: the state the viewer is in, then the last thing that happened.
    pub fn status(&self) -> String {
        let state = self.state_line();
        match self.status.note_for(self.easel.stamp()) {
            Some(note) => format!("{state}\n{note}"),
            None => state,
        }
    }

    /// Tells what just happened, until the paintings change.
    fn note(&mut self, text: impl Into<String>) {
        self.status.note(text, self.easel.stamp());
    }

    /// The last error, if the last attempt at something failed.
    pub fn error(&self) -> Option<&str> {
        self.status.error.as_deref()
    }

    /// The stroke → frame timings of the last stroke.
    pub fn timings(&self) -> &Timings {
        &self.meter.timings
    }

    /// The live painting's session (views, canvases, fit).
    pub fn session(&self) -> &PaintSession {
        &self.easel.session
    }

    /// The scale the 3D view renders at now.
    pub fn render_scale(&self) -> f32 {
        self.stage.render_scale.scale()
    }

    /// Work that does not wait for input: the watched file, a finished background prepare.
    pub fn tick(&mut self, renderer: &mut Renderer) {
        self.sphere_tick(renderer);
        if let Some(mut w) = self.easel.watcher.take() {
            let generation = self.easel.session.views.first().map(|v| (v.width, v.height));
            if w.poll(&mut self.easel.session, renderer).is_some() && matches!(w.status(), WatchStatus::Fitted { .. }) {
                if self.easel.session.views.first().map(|v| (v.width, v.height)) != generation {
                    self.easel.generation += 1; // the view was rendered again at the painting's size
                }
                self.live_changed();
                self.meter.last = None;
            }
            self.easel.watcher = Some(w);
        }
        match self.easel.session.poll() {
            Ok(true) => self.easel.refine_needed = true,
            Ok(false) => {}
            Err(e) => self.status.fail(e.to_string()),
        }
        self.full_fit_tick();
    }

    /// Once the strokes pause, `brdfpaint fit`'s fit of the paintings (reading, base) runs on
    /// a worker; when it lands the window shows it, and the state line its notes.
    fn full_fit_tick(&mut self) {
        match self.easel.session.poll_full(std::time::Instant::now()) {
            Ok(true) => {
                self.status.error = None;
                self.live_changed();
            }
            Ok(false) => {}
            Err(e) => self.status.fail(format!("full fit: {e} (showing the live fit)")),
        }
    }

    /// Whether frames should keep coming without input.
    pub fn busy(&self) -> bool {
        self.easel.refine_needed || self.easel.canvas_changed || self.env.owed()
    }

    /// The 3D view was drawn (the environment's directions for the next frame).
    pub fn view_drawn(&mut self) {
        self.env.drawn();
    }

    /// Whether a prepare (or a lit sphere's view under a new light) is made in the
    /// background: its result needs a frame when it lands.
    pub fn preparing(&self) -> bool {
        self.easel.session.preparing() || self.sphere_waiting()
    }

    /// Whether the paintings wait for their full fit (the pause after the strokes, or the
    /// fit on its worker): a frame is needed to start it and to show it when it lands.
    pub fn settling(&self) -> bool {
        self.easel.session.full_owed()
    }

    pub fn watching(&self) -> bool {
        self.easel.watcher.is_some()
    }

    /// The live material changed: redraw it if shown, and its tables.
    fn live_changed(&mut self) {
        if self.catalogue.shows_live() {
            self.stage.shading_dirty = true;
            self.tables.dirty = true;
        }
    }

    /// Another material is shown.
    fn shown_material_changed(&mut self) {
        self.stage.shading_dirty = true;
        self.tables.dirty = true;
    }

    /// After the UI ran: refit what the strokes changed, upload the material.
    pub fn after(&mut self, renderer: &mut Renderer) {
        let e = &mut self.easel;
        if e.canvas_changed || e.stroke_ended || e.refine_needed {
            let full = (e.stroke_ended || e.refine_needed) && !e.any_stroking();
            let result = if full { e.session.refine() } else { e.session.refit() };
            e.canvas_changed = false;
            e.stroke_ended = false;
            e.refine_needed = false;
            match result {
                Ok(Some(r)) => {
                    self.status.error = None;
                    // The stroke -> frame timing is the live path's: a full solve (every
                    // mapping, errors) runs once when a stroke ends and is not a stroke's cost.
                    if !full {
                        self.meter.pending = Some(r);
                    }
                    self.meter.last = Some(r);
                    self.live_changed();
                }
                Ok(None) => {}
                Err(e) => self.status.fail(format!("refit: {e} (keeping the last material)")),
            }
        }
        // A stroke in progress redraws every frame: under an environment it takes the moving
        // count of directions, and the full count when the stroke ends.
        self.env.moving |= self.easel.any_stroking();
        let material = self.catalogue.current(&self.easel.session);
        match self.stage.upload(renderer, material) {
            Ok(Some(ms)) if self.meter.pending.is_some() => self.meter.timings.upload_ms = ms,
            Ok(_) => {}
            Err(e) => self.status.fail(format!("cannot draw the material: {e}")),
        }
    }

    /// Called with the measured frame: `frame_ms` the drawing (3D view and panel, to
    /// `glFinish`), `view_ms` the 3D view's part, `redraw_ms` the whole redraw (UI, refit,
    /// drawing, presenting). Completes the stroke → frame timing when this frame showed a
    /// refit, and feeds the render-scale choice.
    pub fn frame_done(&mut self, frame_ms: f64, view_ms: f64, redraw_ms: f64) {
        self.meter.frame_done(frame_ms, view_ms);
        self.stage.render_scale.record(redraw_ms, view_ms);
    }

    /// Takes the shortcuts out of this frame's input before egui sees it (see [`shortcuts`])
    /// and applies them. Call before running the UI with `input`.
    pub fn handle_input(&mut self, ctx: &egui::Context, input: &mut egui::RawInput) {
        let taken = take_shortcuts(&mut input.events, ctx.text_edit_focused());
        for s in taken {
            self.apply(s);
            if s == Shortcut::ToggleMode {
                // A focus ring left on a mode button would look like the mode.
                if let Some(id) = ctx.memory(|m| m.focused()) {
                    ctx.memory_mut(|m| m.surrender_focus(id));
                }
            }
        }
    }

    /// Does what a shortcut asks.
    pub fn apply(&mut self, s: Shortcut) {
        match s {
            Shortcut::ToggleMode => self.mode = if self.mode == Mode::View { Mode::Paint } else { Mode::View },
            Shortcut::Undo => {
                self.easel.undo();
            }
            Shortcut::Redo => {
                self.easel.redo();
            }
            Shortcut::Tool(t) => self.tools.tool = t,
            Shortcut::Smaller => self.tools.smaller(),
            Shortcut::Larger => self.tools.larger(),
            Shortcut::NextMaterial | Shortcut::PreviousMaterial => {
                self.catalogue.step(if s == Shortcut::NextMaterial { 1 } else { -1 });
                self.shown_material_changed();
            }
        }
    }

    /// Opens a library (`view LIB/`, its materials in order): the first is shown, and Page
    /// Up / Page Down (or ← / →) step through them.
    pub fn open_library(&mut self, name: &str, materials: Vec<(String, Material)>) {
        let count = materials.len();
        let first = self.catalogue.materials.len();
        for (n, m) in materials {
            self.catalogue.add_material(n, m);
        }
        self.catalogue.material = first.min(self.catalogue.materials.len() - 1);
        self.shown_material_changed();
        self.note(format!("library {name}: {count} materials; Page Up / Page Down (or ← / →) step through them"));
    }

    /// Builds the whole UI for one frame.
    pub fn ui(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        self.layout.pixels_per_point = ui.ctx().pixels_per_point();
        self.handle_drops(renderer, ui);
        self.sphere_ask(renderer, ui);
        let panel = egui::Panel::left("controls").exact_size(PANEL_WIDTH).resizable(false).show(ui, |ui| {
            // Status and timing are pinned to the panel's foot, always in sight; the controls
            // scroll above them.
            egui::Panel::bottom("status").show(ui, |ui| self.status_ui(ui));
            egui::ScrollArea::vertical().show(ui, |ui| self.controls(renderer, ui));
        });
        self.layout.panel_rect = Some(self.to_pixels(panel.response.rect));
        egui::Panel::bottom("tables").default_size(170.0).min_size(120.0).resizable(true).show(ui, |ui| {
            let material = self.catalogue.current(&self.easel.session);
            self.tables.ui(ui, material)
        });
        egui::CentralPanel::no_frame().show(ui, |ui| self.central(ui));
        self.apply_dropped_disk(renderer);
    }

    fn to_pixels(&self, r: Rect) -> WindowRect {
        let s = self.layout.pixels_per_point;
        let (x0, y0) = ((r.min.x * s).round() as i32, (r.min.y * s).round() as i32);
        let (x1, y1) = ((r.max.x * s).round() as i32, (r.max.y * s).round() as i32);
        WindowRect { x: x0, y: y0, width: x1 - x0, height: y1 - y0 }
    }

    fn handle_drops(&mut self, renderer: &mut Renderer, ui: &egui::Ui) {
        let dropped: Vec<PathBuf> = ui.input(|i| {
            i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()).collect()
        });
        for path in dropped {
            if let Err(e) = self.open_file(renderer, &path) {
                self.status.fail(e.to_string());
            }
        }
    }

    /// Opens a dropped file: a model (.glb/.gltf), a material (directory or material.json),
    /// a picture of a lit sphere or MatCap, or a painting for the active view (.png/.jpg/.exr;
    /// of the view's camera aspect, any size, as for `brdfpaint fit`); a picture that could
    /// be either is asked about ([`sphere`]).
    pub fn open_file(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
        if path.is_dir() || path.file_name().is_some_and(|n| n == "material.json") {
            let m = Material::load(path)?;
            let dir = if path.is_dir() { path } else { path.parent().unwrap_or(path) };
            self.catalogue.add_material(entry_name(dir), m);
            self.shown_material_changed();
            self.note(format!("opened material {}", dir.display()));
            return Ok(());
        }
        match ext.as_str() {
            "glb" | "gltf" => {
                let meshes = model_meshes(path)?;
                let k = self.catalogue.add_model(path.display().to_string(), meshes);
                self.select_model(renderer, k)?;
                self.note(format!("opened model {}", path.display()));
                Ok(())
            }
            "hdr" => self.open_environment(renderer, path),
            "exr" if self.is_panorama(path) => self.open_environment(renderer, path),
            "png" | "jpg" | "jpeg" | "exr" => self.open_picture(renderer, path),
            _ => Err(Error::input(format!(
                "{}: not a model (.glb, .gltf), a material (directory or material.json), a picture (.png, .jpg, .exr) or an environment (.hdr, .exr)",
                path.display()
            ))),
        }
    }

    /// A dropped EXR is an environment when it reads as one (2:1, HDR, valid) and the active
    /// view, not being 2:1 itself, could not take it as a painting.
    fn is_panorama(&self, path: &Path) -> bool {
        let view_is_2_to_1 = self.easel.session.views.get(self.easel.active).is_some_and(|v| v.width == 2 * v.height);
        !view_is_2_to_1 && crate::images::env::Environment::load(path).is_ok()
    }

    /// Loads a painting file into the active view.
    fn open_painting(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        self.easel.load_painting(renderer, path)?;
        self.mode = Mode::Paint;
        let label = self.easel.view_label(self.easel.active);
        self.note(format!("painting {} loaded into view '{label}'", path.display()));
        Ok(())
    }

    fn select_model(&mut self, renderer: &mut Renderer, k: usize) -> Result<()> {
        let meshes = self.catalogue.meshes(k)?;
        self.stage.show_model(renderer, meshes)?;
        self.catalogue.model = k;
        Ok(())
    }

    fn select_material(&mut self, k: usize) {
        if k != self.catalogue.material {
            self.catalogue.material = k;
            self.shown_material_changed();
            self.note(format!("showing material {}", self.catalogue.material_name()));
        }
    }

    /// What the viewer is doing now, in one line (the status line's first).
    fn state_line(&self) -> String {
        let e = &self.easel;
        if let Some(w) = &e.watcher {
            return match w.status() {
                WatchStatus::Waiting => format!("watching {}", w.path().display()),
                WatchStatus::Fitted { samples } => format!("watching {}: fitted {samples} samples", w.path().display()),
                WatchStatus::Failed(err) => format!("{err} (keeping the last good material)"),
            };
        }
        let painted: Vec<String> =
            (0..e.session.views.len()).filter(|&k| e.is_painted(k)).map(|k| e.view_label(k)).collect();
        let live = if painted.is_empty() {
            if e.session.material().is_some() {
                "nothing painted (the live material keeps its last fit)".to_string()
            } else {
                "nothing painted yet".to_string()
            }
        } else if e.session.preparing() {
            format!("painted {}: preparing the new pixels...", painted.join(", "))
        } else if let Some(full) = e.session.full_fit() {
            // The notes as the viewer tells them: each line alone, no option named.
            let notes = full.notes.iter().map(|n| format!("\n{n}")).collect::<String>();
            format!("fitted {} as `fit` reads them{notes}", painted.join(", "))
        } else {
            let samples = self.meter.last.map_or(String::new(), |r| format!("{} samples from ", r.samples));
            format!("fitted {samples}{}", painted.join(", "))
        };
        let name = self.catalogue.material_name();
        match (self.mode, self.catalogue.shows_live()) {
            (Mode::View, true) => format!("showing the live painting's material on {}: {live}", short(self.catalogue.model_name())),
            (Mode::View, false) => format!("showing material {} on {}", short(name), short(self.catalogue.model_name())),
            (Mode::Paint, true) => format!("painting view '{}': {live}", e.view_label(e.active)),
            (Mode::Paint, false) => format!(
                "painting view '{}': {live}; the 3D view shows material {}, not the painting's",
                e.view_label(e.active),
                short(name)
            ),
        }
    }
}

/// `s`, or its last 29 characters after "..." when longer than 32.
fn short(s: &str) -> String {
    let n = s.chars().count();
    if n <= 32 {
        s.to_string()
    } else {
        format!("...{}", s.chars().skip(n - 29).collect::<String>())
    }
}
