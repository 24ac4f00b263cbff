//! The viewer's state and its egui panel: models, materials, the camera and light, fit
//! settings, the painting tools, factor tables and timings. Window and GL plumbing live in
//! `app`; this module only needs a [`Renderer`] to upload to.

use std::path::{Path, PathBuf};
use std::time::Instant;

use egui::{Color32, ColorImage, PointerButton, Pos2, Rect, Sense, Stroke, TextureHandle, TextureOptions, Vec2};

use super::camera::{LightControl, Orbit};
use super::canvas::{Brush, Painting};
use super::display::PixelRect;
use super::paint::{read_painting_for, PaintSession, PaintView, Refit};
use super::watch::{WatchStatus, Watcher};
use crate::error::{Error, Result};
use crate::factor::{defaults, Domain, Input, Mapping, Settings};
use crate::images::linear_to_srgb;
use crate::material::Material;
use crate::render::{GpuScene, GpuShading, Renderer};
use crate::scene::{builtin_models, model_meshes, preset_names, BoundingSphere, CpuMesh, Scene};

/// What the central area shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The material on a model.
    View,
    /// A standard view to paint, beside the live material.
    Paint,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Tool {
    Brush,
    Eraser,
    Fill,
}

/// A model the 3D view can show.
struct ModelEntry {
    name: String,
    meshes: Vec<CpuMesh>,
}

/// A material the 3D view can show. `None`: the live painting's.
struct MaterialEntry {
    name: String,
    material: Option<Material>,
}

/// Rolling stroke → frame timings, milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Timings {
    pub stroke_ms: f64,
    pub values_ms: f64,
    pub solve_ms: f64,
    pub upload_ms: f64,
    /// The whole window frame: the 3D view and the egui panel, to `glFinish`.
    pub frame_ms: f64,
    /// The 3D view's part of the frame.
    pub view_ms: f64,
    pub total_ms: f64,
    /// Samples of the last refit.
    pub samples: usize,
    /// Refits measured.
    pub count: usize,
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
    /// [`super::display::View3d::draw`]).
    pub render_scale: f32,
}

/// Everything the window shows, and its controls.
pub struct Studio {
    pub mode: Mode,
    models: Vec<ModelEntry>,
    model: usize,
    pub gpu_model: GpuScene,
    bound: BoundingSphere,
    pub orbit: Orbit,
    pub light: LightControl,
    materials: Vec<MaterialEntry>,
    material: usize,
    pub shading: Option<GpuShading>,
    shading_dirty: bool,

    pub session: PaintSession,
    paint_model: String,
    size: usize,
    /// Preset name per session view (empty for a `--scene` view).
    view_names: Vec<String>,
    active: usize,
    scene_mode: bool,
    /// Per view: its canvas texture and the guides it was drawn with.
    canvas_tex: Vec<Option<(TextureHandle, (bool, bool))>>,
    brush: Brush,
    tool: Tool,
    show_outline: bool,
    show_reference: bool,
    canvas_changed: bool,
    stroke_ended: bool,
    refine_needed: bool,
    watcher: Option<Watcher>,

    dim: usize,
    res: usize,
    lambda: f64,
    mapping: Mapping,

    pub timings: Timings,
    stroke_ms: f64,
    pending_refit: Option<Refit>,
    last_refit: Option<Refit>,
    status: String,
    error: Option<String>,
    save_material: String,
    save_painting: String,
    tables: Vec<Option<TextureHandle>>,
    tables_dirty: bool,
    /// Where the 3D view is, in window pixels (set by the last [`Studio::ui`]).
    pub view_rect: Option<PixelRect>,
    /// The egui side panel's rectangle, window pixels.
    pub panel_rect: Option<PixelRect>,
    pixels_per_point: f32,
    /// Fraction of the window's resolution the 3D view renders at.
    pub render_scale: f32,
}

fn model_entry_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
}

/// The bundled default painting: glossy orange ceramic with a cool fill on its unlit side,
/// painted procedurally at the view's own samples. Its fit is the material a first run shows.
pub fn example_painting(view: &PaintView) -> Painting {
    // What a painter puts down: a base colour shaded by cos θ_l, a soft white highlight
    // around the mirror direction ($n \cdot h$), and a cool fill on the unlit side.
    let base = [0.80, 0.36, 0.12];
    let fill = [0.030, 0.040, 0.075];
    let mut p = super::canvas::blank(view.width, view.height).expect("a view has a valid size");
    for slot in &view.slots {
        let (l, v) = (slot.query.l, slot.query.v);
        let h = (l + v).normalize_or(glam::DVec3::Z);
        let lit = l.z.max(0.0);
        let highlight = 0.55 * h.z.max(0.0).powf(80.0) * lit.sqrt();
        // The painted colour is the shading function times the light.
        let c = [0, 1, 2].map(|k| ((base[k] * lit + highlight + fill[k] * (1.0 - 0.5 * lit)) * slot.light[k]) as f32);
        p.pixels[slot.pixel as usize] = c;
        p.alpha[slot.pixel as usize] = 1.0;
    }
    p
}

impl Studio {
    /// The starting state; renders the first paint view (and fits its example painting when
    /// there is no `--watch`).
    pub fn new(renderer: &mut Renderer, start: Start) -> Result<Studio> {
        let gl = renderer.gl().clone();
        let bound = BoundingSphere::of(&start.model.1).unwrap_or(BoundingSphere { center: glam::Vec3::ZERO, radius: 1.0 });
        let orbit = Orbit::framing(bound);
        let light = LightControl::key(&orbit);
        let scene = Scene { meshes: start.model.1.clone(), camera: orbit.camera(1.0), light: light.light() };
        let gpu_model = GpuScene::upload(&gl, &scene)?;
        let mut models: Vec<ModelEntry> =
            builtin_models().iter().map(|n| ModelEntry { name: n.to_string(), meshes: Vec::new() }).collect();
        let model = match models.iter().position(|m| m.name == start.model.0) {
            Some(k) => {
                models[k].meshes = start.model.1;
                k
            }
            None => {
                models.push(ModelEntry { name: start.model.0, meshes: start.model.1 });
                models.len() - 1
            }
        };
        let mut materials = vec![MaterialEntry { name: "painting (live)".into(), material: None }];
        let material = match start.material {
            Some((name, m)) => {
                materials.push(MaterialEntry { name, material: Some(m) });
                1
            }
            None => 0,
        };
        let settings = Settings::default();
        let mut studio = Studio {
            mode: start.mode,
            render_scale: start.render_scale,
            models,
            model,
            gpu_model,
            bound,
            orbit,
            light,
            materials,
            material,
            shading: None,
            shading_dirty: true,
            session: PaintSession::new(settings, Mapping::Auto),
            paint_model: start.paint_model,
            size: start.size,
            view_names: Vec::new(),
            active: 0,
            scene_mode: start.scene.is_some(),
            canvas_tex: Vec::new(),
            brush: Brush::default(),
            tool: Tool::Brush,
            show_outline: true,
            show_reference: true,
            canvas_changed: false,
            stroke_ended: false,
            refine_needed: false,
            watcher: None,
            dim: 1,
            res: defaults::RES_1D,
            lambda: defaults::SMOOTH_1D,
            mapping: Mapping::Auto,
            timings: Timings::default(),
            stroke_ms: 0.0,
            pending_refit: None,
            last_refit: None,
            status: String::new(),
            error: None,
            save_material: "material".into(),
            save_painting: "painting.png".into(),
            tables: Vec::new(),
            tables_dirty: true,
            view_rect: None,
            panel_rect: None,
            pixels_per_point: 1.0,
        };
        match start.scene {
            Some((name, scene)) => {
                // Size from the watched painting when it is readable, else from the camera.
                let (w, h) = match start.watch.as_deref().map(Painting::read) {
                    Some(Ok(p)) => (p.width, p.height),
                    _ => {
                        let aspect = crate::sample::scene::camera_aspect(&scene.camera).unwrap_or(1.0);
                        let h = start.size;
                        (((h as f64) * aspect).round().max(1.0) as usize, h)
                    }
                };
                let view = PaintView::new(renderer, &name, scene, w, h)?;
                studio.session.add_view(view);
                studio.view_names.push(String::new());
                studio.canvas_tex.push(None);
                if let Some(path) = start.watch {
                    let mut w = Watcher::new(path, 0);
                    w.check(&mut studio.session);
                    studio.status = studio.watch_line(&w);
                    studio.watcher = Some(w);
                }
            }
            None => {
                let k = studio.open_view(renderer, crate::scene::preset::presets()[0].name)?;
                let example = example_painting(&studio.session.views[k]);
                studio.session.views[k].canvas.set_painting(&example)?;
                studio.session.settle()?;
                studio.status = "example painting fitted: paint over it, or clear it and start anew".into();
            }
        }
        Ok(studio)
    }

    /// Opens (renders) the standard view `preset` of the paint model, or finds it; its index.
    fn open_view(&mut self, renderer: &mut Renderer, preset: &str) -> Result<usize> {
        if let Some(k) = self.view_names.iter().position(|n| n == preset) {
            return Ok(k);
        }
        let view = PaintView::standard(renderer, &self.paint_model, preset, self.size)?;
        let k = self.session.add_view(view);
        self.view_names.push(preset.to_string());
        self.canvas_tex.push(None);
        self.active = k;
        Ok(k)
    }

    fn watch_line(&self, w: &Watcher) -> String {
        match w.status() {
            WatchStatus::Waiting => format!("watching {}", w.path().display()),
            WatchStatus::Fitted { samples } => format!("watching {}: fitted {samples} samples", w.path().display()),
            WatchStatus::Failed(e) => format!("{e} (keeping the last good material)"),
        }
    }

    /// The material shown now.
    pub fn current_material(&self) -> Option<&Material> {
        match &self.materials[self.material].material {
            Some(m) => Some(m),
            None => self.session.material(),
        }
    }

    pub fn material_name(&self) -> &str {
        &self.materials[self.material].name
    }

    pub fn model_name(&self) -> &str {
        &self.models[self.model].name
    }

    /// The status line under the panel.
    pub fn status(&self) -> &str {
        &self.status
    }

    /// Work that does not wait for input: the watched file, a finished background prepare.
    pub fn tick(&mut self) {
        if let Some(mut w) = self.watcher.take() {
            if w.poll(&mut self.session).is_some() {
                self.status = self.watch_line(&w);
                if matches!(w.status(), WatchStatus::Fitted { .. }) {
                    self.live_changed();
                    self.last_refit = None;
                }
            }
            self.watcher = Some(w);
        }
        match self.session.poll() {
            Ok(true) => self.refine_needed = true,
            Ok(false) => {}
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// Whether frames should keep coming without input.
    pub fn busy(&self) -> bool {
        self.refine_needed || self.canvas_changed
    }

    /// Whether a prepare runs in the background (its result needs a frame when it lands).
    pub fn preparing(&self) -> bool {
        self.session.preparing()
    }

    pub fn watching(&self) -> bool {
        self.watcher.is_some()
    }

    fn live_changed(&mut self) {
        if self.materials[self.material].material.is_none() {
            self.shading_dirty = true;
        }
        self.tables_dirty = true;
    }

    fn fit_settings(&self) -> Settings {
        let mut s = Settings::uniform(self.dim, self.res);
        for f in &mut s.factors {
            f.smooth = self.lambda;
        }
        s
    }

    /// After the UI ran: refit what the strokes changed, upload the material.
    pub fn after(&mut self, renderer: &mut Renderer) {
        if self.canvas_changed || self.stroke_ended || self.refine_needed {
            let full = (self.stroke_ended || self.refine_needed) && !self.any_stroking();
            let result = if full { self.session.refine() } else { self.session.refit() };
            match result {
                Ok(Some(r)) => {
                    self.error = None;
                    // The stroke -> frame timing is the live path's: a full solve (every
                    // mapping, errors) runs once when a stroke ends and is not a stroke's cost.
                    if !full {
                        self.pending_refit = Some(r);
                    }
                    self.last_refit = Some(r);
                    self.live_changed();
                }
                Ok(None) => {}
                Err(e) => self.error = Some(format!("refit: {e} (keeping the last material)")),
            }
            self.canvas_changed = false;
            self.stroke_ended = false;
            self.refine_needed = false;
        }
        if self.shading_dirty {
            let t = Instant::now();
            self.shading = match self.current_material() {
                Some(m) => match renderer.upload(m) {
                    Ok(s) => Some(s),
                    Err(e) => {
                        self.error = Some(format!("cannot draw the material: {e}"));
                        None
                    }
                },
                None => None,
            };
            self.shading_dirty = false;
            if self.pending_refit.is_some() {
                self.timings.upload_ms = t.elapsed().as_secs_f64() * 1e3;
            }
        }
    }

    fn any_stroking(&self) -> bool {
        self.session.views.iter().any(|v| v.canvas.stroking())
    }

    /// Called with the measured frame time (draw + UI + finish). Completes the stroke → frame
    /// timing when this frame showed a refit.
    pub fn frame_done(&mut self, frame_ms: f64, view_ms: f64) {
        if let Some(r) = self.pending_refit.take() {
            let t = &mut self.timings;
            t.stroke_ms = self.stroke_ms;
            t.values_ms = r.values_ms;
            t.solve_ms = r.solve_ms;
            t.frame_ms = frame_ms;
            t.view_ms = view_ms;
            t.total_ms = t.stroke_ms + t.values_ms + t.solve_ms + t.upload_ms + t.frame_ms;
            t.samples = r.samples;
            t.count += 1;
        }
        self.stroke_ms = 0.0;
    }

    // ---------------------------------------------------------------- the UI

    /// Builds the whole UI for one frame.
    pub fn ui(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        self.pixels_per_point = ui.ctx().pixels_per_point();
        self.handle_drops(renderer, ui);
        self.shortcuts(ui);
        let panel = egui::Panel::left("controls").default_size(300.0).resizable(true).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.controls(renderer, ui));
        });
        self.panel_rect = Some(self.to_pixels(panel.response.rect));
        egui::Panel::bottom("tables").default_size(170.0).min_size(120.0).resizable(true).show(ui, |ui| self.tables_ui(ui));
        egui::CentralPanel::no_frame().show(ui, |ui| self.central(ui));
    }

    fn to_pixels(&self, r: Rect) -> PixelRect {
        let s = self.pixels_per_point;
        let (x0, y0) = ((r.min.x * s).round() as i32, (r.min.y * s).round() as i32);
        let (x1, y1) = ((r.max.x * s).round() as i32, (r.max.y * s).round() as i32);
        PixelRect { x: x0, y: y0, width: x1 - x0, height: y1 - y0 }
    }

    fn handle_drops(&mut self, renderer: &mut Renderer, ui: &egui::Ui) {
        let dropped: Vec<PathBuf> = ui.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()).collect());
        for path in dropped {
            if let Err(e) = self.open_file(renderer, &path) {
                self.error = Some(e.to_string());
            }
        }
    }

    /// Opens a dropped file: a model (.glb/.gltf), a material (directory or material.json),
    /// or a painting for the active view (.png/.jpg/.exr).
    pub fn open_file(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
        if path.is_dir() || path.file_name().is_some_and(|n| n == "material.json") {
            let m = Material::load(path)?;
            let dir = if path.is_dir() { path } else { path.parent().unwrap_or(path) };
            self.materials.push(MaterialEntry { name: model_entry_name(dir), material: Some(m) });
            self.material = self.materials.len() - 1;
            self.shading_dirty = true;
            self.tables_dirty = true;
            self.status = format!("opened material {}", dir.display());
            return Ok(());
        }
        match ext.as_str() {
            "glb" | "gltf" => {
                let meshes = model_meshes(path)?;
                self.models.push(ModelEntry { name: path.display().to_string(), meshes: Vec::new() });
                self.models.last_mut().expect("pushed").meshes = meshes;
                self.select_model(renderer, self.models.len() - 1)?;
                self.status = format!("opened model {}", path.display());
                Ok(())
            }
            "png" | "jpg" | "jpeg" | "exr" => {
                let view = self.session.views.get(self.active).ok_or_else(|| Error::input("no view to paint"))?;
                let p = read_painting_for(view, path)?;
                self.session.views[self.active].canvas.set_painting(&p)?;
                self.refine_needed = true;
                self.canvas_changed = true;
                self.mode = Mode::Paint;
                self.status = format!("painting {} loaded into view '{}'", path.display(), view_label(&self.view_names, self.active));
                Ok(())
            }
            _ => Err(Error::input(format!(
                "{}: not a model (.glb, .gltf), a material (directory or material.json) or a painting (.png, .jpg, .exr)",
                path.display()
            ))),
        }
    }

    fn select_model(&mut self, renderer: &mut Renderer, k: usize) -> Result<()> {
        if self.models[k].meshes.is_empty() {
            self.models[k].meshes = model_meshes(&self.models[k].name)?;
        }
        let meshes = self.models[k].meshes.clone();
        let bound = BoundingSphere::of(&meshes).unwrap_or(BoundingSphere { center: glam::Vec3::ZERO, radius: 1.0 });
        let scene = Scene { meshes, camera: self.orbit.camera(1.0), light: self.light.light() };
        self.gpu_model = GpuScene::upload(renderer.gl(), &scene)?;
        self.bound = bound;
        let (yaw, pitch) = (self.orbit.yaw, self.orbit.pitch);
        self.orbit = Orbit { yaw, pitch, ..Orbit::framing(bound) };
        self.model = k;
        Ok(())
    }

    fn shortcuts(&mut self, ui: &mut egui::Ui) {
        if ui.ctx().egui_wants_keyboard_input() {
            return;
        }
        use egui::{Key, Modifiers};
        let (undo, redo, redo2) = ui.input_mut(|i| {
            (
                i.consume_key(Modifiers::COMMAND, Key::Z),
                i.consume_key(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z),
                i.consume_key(Modifiers::COMMAND, Key::Y),
            )
        });
        if undo {
            self.undo();
        }
        if redo || redo2 {
            self.redo();
        }
        ui.input(|i| {
            if i.key_pressed(Key::B) {
                self.tool = Tool::Brush;
            }
            if i.key_pressed(Key::E) {
                self.tool = Tool::Eraser;
            }
            if i.key_pressed(Key::F) {
                self.tool = Tool::Fill;
            }
            if i.key_pressed(Key::OpenBracket) {
                self.brush.radius = (self.brush.radius / 1.25).max(1.0);
            }
            if i.key_pressed(Key::CloseBracket) {
                self.brush.radius = (self.brush.radius * 1.25).min(200.0);
            }
            if i.key_pressed(Key::Tab) {
                self.mode = if self.mode == Mode::View { Mode::Paint } else { Mode::View };
            }
        });
    }

    fn undo(&mut self) {
        if let Some(v) = self.session.views.get_mut(self.active) {
            if v.canvas.undo() {
                self.canvas_changed = true;
                self.refine_needed = true;
            }
        }
    }

    fn redo(&mut self) {
        if let Some(v) = self.session.views.get_mut(self.active) {
            if v.canvas.redo() {
                self.canvas_changed = true;
                self.refine_needed = true;
            }
        }
    }

    fn controls(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.mode, Mode::View, "View");
            ui.selectable_value(&mut self.mode, Mode::Paint, "Paint");
            ui.label("(Tab)");
        });
        ui.separator();

        egui::CollapsingHeader::new("Model and material").default_open(true).show(ui, |ui| {
            let mut pick = self.model;
            egui::ComboBox::from_label("model").selected_text(short(&self.models[self.model].name)).show_ui(ui, |ui| {
                for (k, m) in self.models.iter().enumerate() {
                    ui.selectable_value(&mut pick, k, short(&m.name));
                }
            });
            if pick != self.model {
                if let Err(e) = self.select_model(renderer, pick) {
                    self.error = Some(e.to_string());
                }
            }
            let mut pick = self.material;
            egui::ComboBox::from_label("material").selected_text(short(&self.materials[self.material].name)).show_ui(ui, |ui| {
                for (k, m) in self.materials.iter().enumerate() {
                    ui.selectable_value(&mut pick, k, short(&m.name));
                }
            });
            if pick != self.material {
                self.material = pick;
                self.shading_dirty = true;
                self.tables_dirty = true;
            }
            ui.small("Drop a .glb/.gltf model, a material directory or a painting on the window to open it.");
            ui.horizontal(|ui| {
                ui.add(egui::TextEdit::singleline(&mut self.save_material).desired_width(150.0));
                if ui.button("Save material").clicked() {
                    self.save_material_now();
                }
            });
        });

        egui::CollapsingHeader::new("Camera and light").default_open(true).show(ui, |ui| {
            ui.small("Drag: orbit · Shift/middle-drag: pan · wheel: zoom · right-drag: move the light");
            let mut az = self.light.azimuth.to_degrees();
            let mut el = self.light.elevation.to_degrees();
            let a = ui.add(egui::Slider::new(&mut az, -180.0..=180.0).text("light azimuth °"));
            let e = ui.add(egui::Slider::new(&mut el, -89.0..=89.0).text("light elevation °"));
            if a.changed() || e.changed() {
                self.light.azimuth = az.to_radians();
                self.light.elevation = el.to_radians();
            }
            ui.add(egui::Slider::new(&mut self.light.intensity, 0.0..=4.0).text("light intensity"));
            ui.add(egui::Slider::new(&mut self.render_scale, super::display::MIN_SCALE..=1.0).text("render scale"))
                .on_hover_text("Render the model at this fraction of the window's resolution: faster on software GL");
            if ui.button("Reset view").clicked() {
                self.orbit = Orbit::framing(self.bound);
                self.light = LightControl::key(&self.orbit);
            }
        });

        egui::CollapsingHeader::new("Fit").default_open(true).show(ui, |ui| self.fit_ui(ui));

        if self.mode == Mode::Paint {
            egui::CollapsingHeader::new("Paint").default_open(true).show(ui, |ui| self.paint_ui(renderer, ui));
        }

        egui::CollapsingHeader::new("Timing").default_open(true).show(ui, |ui| {
            let t = &self.timings;
            if t.count == 0 {
                ui.label("Paint a stroke to measure stroke -> frame.");
            } else {
                let frame = 1000.0 / 60.0;
                egui::Grid::new("timing").num_columns(2).show(ui, |ui| {
                    for (name, v) in [
                        ("stroke", t.stroke_ms),
                        ("samples", t.values_ms),
                        ("solve", t.solve_ms),
                        ("upload", t.upload_ms),
                        ("frame: 3D view", t.view_ms),
                        ("frame: whole window", t.frame_ms),
                    ] {
                        ui.label(name);
                        ui.label(format!("{v:.2} ms"));
                        ui.end_row();
                    }
                    ui.strong("stroke -> frame");
                    let c = if t.total_ms <= frame { Color32::from_rgb(90, 200, 110) } else { Color32::from_rgb(230, 120, 80) };
                    ui.colored_label(c, format!("{:.2} ms ({} samples)", t.total_ms, t.samples));
                    ui.end_row();
                });
            }
            if let Some(r) = &self.last_refit {
                let what = if r.exact { "exact" } else { "preparing the new pixels..." };
                ui.small(format!(
                    "{} samples, mapping {}, {what}{}",
                    r.samples,
                    r.map.map_or("-", |m| m.name()),
                    r.errors.map_or(String::new(), |e| format!(", relative RMS {:.3}", e.rms_relative))
                ));
            }
            if self.session.preparing() {
                ui.small("preparing the system for the painted pixels (background)...");
            }
        });

        ui.separator();
        if let Some(e) = &self.error {
            ui.colored_label(Color32::from_rgb(240, 110, 90), e);
        }
        if !self.status.is_empty() {
            ui.small(&self.status);
        }
    }

    fn save_material_now(&mut self) {
        let path = PathBuf::from(self.save_material.trim());
        match self.current_material() {
            Some(m) => match m.save(&path) {
                Ok(()) => self.status = format!("saved material to {}", path.display()),
                Err(e) => self.error = Some(format!("cannot save the material: {e}")),
            },
            None => self.error = Some("nothing to save: no material yet".into()),
        }
    }

    fn fit_ui(&mut self, ui: &mut egui::Ui) {
        let (mut dim, mut res, mut lambda, mut mapping) = (self.dim, self.res, self.lambda, self.mapping);
        ui.horizontal(|ui| {
            ui.label("factors");
            ui.selectable_value(&mut dim, 1, "1D");
            ui.selectable_value(&mut dim, 2, "2D");
        });
        if dim != self.dim {
            res = if dim == 1 { defaults::RES_1D } else { defaults::RES_2D };
            lambda = if dim == 1 { defaults::SMOOTH_1D } else { defaults::SMOOTH_2D };
        }
        let range = if dim == 1 { 8..=512 } else { 8..=64 };
        ui.add(egui::Slider::new(&mut res, range).text("resolution"));
        ui.add(egui::Slider::new(&mut lambda, 1e-8..=1e-1).logarithmic(true).text("λ (smoothing)"));
        egui::ComboBox::from_label("mapping").selected_text(mapping.to_string()).show_ui(ui, |ui| {
            for m in [Mapping::Auto, Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None)] {
                ui.selectable_value(&mut mapping, m, m.to_string());
            }
        });
        let changed = dim != self.dim || res != self.res || lambda != self.lambda;
        self.dim = dim;
        self.res = res;
        self.lambda = lambda;
        if changed {
            if let Err(e) = self.session.set_settings(self.fit_settings()) {
                self.error = Some(e.to_string());
            }
            self.refine_needed = true;
        }
        if mapping != self.mapping {
            self.mapping = mapping;
            self.session.set_mapping(mapping);
            self.refine_needed = true;
        }
        if ui.button("Refit now").clicked() {
            self.refine_needed = true;
        }
        ui.small(format!("{} unknowns per channel", self.session.settings().unknowns()));
    }

    fn paint_ui(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        if !self.scene_mode {
            let mut pick = self.paint_model.clone();
            egui::ComboBox::from_label("paint model").selected_text(pick.clone()).show_ui(ui, |ui| {
                for n in builtin_models() {
                    ui.selectable_value(&mut pick, n.to_string(), *n);
                }
            });
            if pick != self.paint_model {
                self.paint_model = pick;
                let settings = self.session.settings().clone();
                self.session = PaintSession::new(settings, self.mapping);
                self.view_names.clear();
                self.canvas_tex.clear();
                self.active = 0;
                if let Err(e) = self.open_view(renderer, preset_names()[0]) {
                    self.error = Some(e.to_string());
                }
            }
            ui.label("views (every painted view feeds the fit):");
            ui.horizontal_wrapped(|ui| {
                for name in preset_names() {
                    let open = self.view_names.iter().position(|n| n == name);
                    let painted =
                        open.is_some_and(|k| self.session.views[k].canvas.painting().alpha.iter().any(|&a| a > 0.0));
                    let label = if painted {
                        egui::RichText::new(format!("{name} *")).strong().color(Color32::from_rgb(250, 170, 80))
                    } else {
                        egui::RichText::new(name)
                    };
                    let selected = open == Some(self.active);
                    if ui.selectable_label(selected, label).clicked() {
                        match self.open_view(renderer, name) {
                            Ok(k) => self.active = k,
                            Err(e) => self.error = Some(e.to_string()),
                        }
                    }
                }
            });
        }
        ui.horizontal(|ui| {
            ui.selectable_value(&mut self.tool, Tool::Brush, "Brush (B)");
            ui.selectable_value(&mut self.tool, Tool::Eraser, "Eraser (E)");
            ui.selectable_value(&mut self.tool, Tool::Fill, "Fill (F)");
        });
        ui.horizontal(|ui| {
            ui.color_edit_button_rgb(&mut self.brush.color);
            ui.label("colour (right-click the canvas to pick)");
        });
        ui.add(egui::Slider::new(&mut self.brush.radius, 1.0..=200.0).logarithmic(true).text("size ([ ])"));
        ui.add(egui::Slider::new(&mut self.brush.hardness, 0.0..=1.0).text("hardness"));
        ui.add(egui::Slider::new(&mut self.brush.opacity, 0.0..=1.0).text("opacity"));
        ui.horizontal(|ui| {
            let (can_undo, can_redo) = self
                .session
                .views
                .get(self.active)
                .map_or((false, false), |v| (v.canvas.can_undo(), v.canvas.can_redo()));
            if ui.add_enabled(can_undo, egui::Button::new("Undo")).clicked() {
                self.undo();
            }
            if ui.add_enabled(can_redo, egui::Button::new("Redo")).clicked() {
                self.redo();
            }
            if ui.button("Fill all").clicked() {
                self.fill_all(false);
            }
            if ui.button("Clear").clicked() {
                self.fill_all(true);
            }
        });
        if ui.button("Start from the reference").clicked() {
            if let Some(v) = self.session.views.get_mut(self.active) {
                let p = v.reference_painting();
                if v.canvas.set_painting(&p).is_ok() {
                    self.canvas_changed = true;
                    self.refine_needed = true;
                }
            }
        }
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.show_outline, "outline");
            if ui.checkbox(&mut self.show_reference, "reference").changed() {}
        });
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.save_painting).desired_width(150.0));
            if ui.button("Save painting").clicked() {
                self.save_painting_now();
            }
        });
        ui.small("Saves the active view's painting and its scene (.gltf beside it) for `brdfpaint fit`.");
    }

    fn fill_all(&mut self, erase: bool) {
        if let Some(v) = self.session.views.get_mut(self.active) {
            let pixels = v.object_pixels();
            let mut b = self.brush;
            b.erase = erase;
            if erase {
                b.opacity = 1.0;
            }
            v.canvas.fill(b, &pixels);
            self.canvas_changed = true;
            self.refine_needed = true;
        }
    }

    fn save_painting_now(&mut self) {
        let path = PathBuf::from(self.save_painting.trim());
        let Some(v) = self.session.views.get(self.active) else { return };
        let result = v.canvas.painting().write(&path).and_then(|()| v.scene.write_gltf(path.with_extension("gltf")));
        match result {
            Ok(()) => {
                self.status = format!("saved {} and {}", path.display(), path.with_extension("gltf").display())
            }
            Err(e) => self.error = Some(format!("cannot save the painting: {e}")),
        }
    }

    fn central(&mut self, ui: &mut egui::Ui) {
        let avail = ui.available_rect_before_wrap();
        let view_area = if self.mode == Mode::Paint && !self.session.views.is_empty() {
            let v = &self.session.views[self.active];
            let aspect = v.width as f32 / v.height as f32;
            let h = avail.height().min(avail.width() * 0.5 / aspect);
            let canvas = Rect::from_min_size(avail.min, Vec2::new(h * aspect, h));
            self.canvas_ui(ui, canvas);
            Rect::from_min_max(Pos2::new(canvas.max.x + 4.0, avail.min.y), avail.max)
        } else {
            avail
        };
        self.view_ui(ui, view_area);
    }

    fn view_ui(&mut self, ui: &mut egui::Ui, rect: Rect) {
        let px = self.to_pixels(rect);
        if px.width <= 0 || px.height <= 0 {
            self.view_rect = None;
            return;
        }
        self.view_rect = Some(px);
        let response = ui.interact(rect, ui.scope_id().with("3d view"), Sense::click_and_drag());
        let d = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(PointerButton::Primary) && !shift {
            self.orbit.rotate(d.x * 0.01, d.y * 0.01);
        } else if response.dragged_by(PointerButton::Middle) || (response.dragged_by(PointerButton::Primary) && shift) {
            self.orbit.pan(d.x, d.y, rect.height());
        } else if response.dragged_by(PointerButton::Secondary) {
            self.light.drag(d.x * 0.01, -d.y * 0.01);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.orbit.zoom((-scroll * 0.002).exp());
            }
        }
        // The light's direction, drawn as a small sun beside the object.
        let camera = self.orbit.camera(rect.width() / rect.height());
        if let Ok(view) = crate::render::View::new(&camera, px.width as usize, px.height as usize) {
            let project = |p: glam::Vec3| {
                let c = view.view_proj * p.extend(1.0);
                (c.w > 0.0).then(|| {
                    Pos2::new(rect.min.x + (c.x / c.w * 0.5 + 0.5) * rect.width(), rect.min.y + (0.5 - c.y / c.w * 0.5) * rect.height())
                })
            };
            let centre = self.orbit.target;
            let sun = centre + self.light.direction() * self.orbit.radius * 1.35;
            if let (Some(a), Some(b)) = (project(centre), project(sun)) {
                let p = ui.painter_at(rect);
                p.line_segment([a, b], Stroke::new(1.0, Color32::from_rgba_unmultiplied(255, 220, 120, 90)));
                p.circle_filled(b, 6.0, Color32::from_rgb(255, 214, 90));
            }
        }
        let name = format!("{} · {}", short(self.model_name()), short(self.material_name()));
        let painter = ui.painter_at(rect);
        painter.text(
            rect.left_top() + Vec2::new(8.0, 6.0),
            egui::Align2::LEFT_TOP,
            name,
            egui::FontId::proportional(13.0),
            Color32::from_gray(200),
        );
        // The live-painting budget, where the eye is: the last stroke's way to the screen.
        if self.mode == Mode::Paint && self.timings.count > 0 {
            let t = &self.timings;
            let ok = t.total_ms <= 1000.0 / 60.0;
            let text = format!(
                "stroke -> frame {:.1} ms{}\nstroke {:.2} · samples {:.2} · solve {:.2} · upload {:.2} · frame {:.1} (3D {:.1}) · {} samples",
                t.total_ms,
                if ok { "" } else { " (over 16.7)" },
                t.stroke_ms,
                t.values_ms,
                t.solve_ms,
                t.upload_ms,
                t.frame_ms,
                t.view_ms,
                t.samples
            );
            let colour = if ok { Color32::from_rgb(120, 200, 130) } else { Color32::from_rgb(235, 140, 90) };
            let galley = painter.layout(text, egui::FontId::proportional(12.0), colour, rect.width() - 16.0);
            painter.galley(rect.left_top() + Vec2::new(8.0, 24.0), galley, colour);
        }
        // Errors, and in watch mode what the last look at the file found, along the bottom.
        let failed = self.watcher.as_ref().is_some_and(|w| matches!(w.status(), WatchStatus::Failed(_)));
        let line = match (&self.error, &self.watcher) {
            (Some(e), _) => Some((e.clone(), true)),
            (None, Some(_)) => Some((self.status.clone(), failed)),
            _ => None,
        };
        if let Some((text, bad)) = line {
            let colour = if bad { Color32::from_rgb(240, 110, 90) } else { Color32::from_gray(190) };
            let galley = painter.layout(text, egui::FontId::proportional(13.0), colour, rect.width() - 16.0);
            let pos = rect.left_bottom() + Vec2::new(8.0, -8.0 - galley.size().y);
            painter.galley(pos, galley, colour);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui, rect: Rect) {
        let k = self.active;
        self.update_canvas_texture(ui.ctx(), k);
        let response = ui.interact(rect, ui.scope_id().with("canvas"), Sense::click_and_drag());
        if let Some((tex, _)) = &self.canvas_tex[k] {
            ui.painter().image(tex.id(), rect, Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
        }
        let view = &self.session.views[k];
        let (w, h) = (view.width as f32, view.height as f32);
        let scale = rect.width() / w;
        let to_canvas = |p: Pos2| glam::Vec2::new((p.x - rect.min.x) / scale, (p.y - rect.min.y) / scale);
        let pointer = response.interact_pointer_pos().or(response.hover_pos());
        let down = ui.input(|i| i.pointer.button_down(PointerButton::Primary));
        match self.tool {
            Tool::Brush | Tool::Eraser => {
                if response.is_pointer_button_down_on() && down {
                    if let Some(p) = pointer {
                        let t = Instant::now();
                        let canvas = &mut self.session.views[k].canvas;
                        if !canvas.stroking() {
                            let mut b = self.brush;
                            b.erase = self.tool == Tool::Eraser;
                            canvas.begin_stroke(b);
                        }
                        canvas.stroke_to(to_canvas(p));
                        self.stroke_ms += t.elapsed().as_secs_f64() * 1e3;
                        self.canvas_changed = true;
                    }
                } else if self.session.views[k].canvas.stroking() {
                    self.session.views[k].canvas.end_stroke();
                    self.stroke_ended = true;
                }
            }
            Tool::Fill => {
                if response.clicked_by(PointerButton::Primary) {
                    if let Some(p) = pointer {
                        let c = to_canvas(p);
                        if c.x >= 0.0 && c.y >= 0.0 && c.x < w && c.y < h {
                            let t = Instant::now();
                            let region = self.session.views[k].fill_region(c.x as usize, c.y as usize);
                            self.session.views[k].canvas.fill(self.brush, &region);
                            self.stroke_ms += t.elapsed().as_secs_f64() * 1e3;
                            self.canvas_changed = true;
                            self.stroke_ended = true;
                        }
                    }
                }
            }
        }
        // Right-click: pick the painted colour (or the reference's) under the pointer.
        if response.clicked_by(PointerButton::Secondary) {
            if let Some(p) = pointer {
                let c = to_canvas(p);
                if c.x >= 0.0 && c.y >= 0.0 && c.x < w && c.y < h {
                    let view = &self.session.views[k];
                    let i = c.y as usize * view.width + c.x as usize;
                    let p = view.canvas.painting();
                    self.brush.color = if p.alpha[i] > 0.0 { p.pixels[i] } else { view.reference[i] };
                }
            }
        }
        if let Some(p) = response.hover_pos() {
            if self.tool != Tool::Fill {
                ui.painter_at(rect).circle_stroke(p, self.brush.radius * scale, Stroke::new(1.0, Color32::from_gray(90)));
            }
        }
        let label = format!("painting: view '{}'", view_label(&self.view_names, k));
        ui.painter_at(rect).text(
            rect.left_top() + Vec2::new(6.0, 4.0),
            egui::Align2::LEFT_TOP,
            label,
            egui::FontId::proportional(13.0),
            Color32::from_gray(90),
        );
    }

    /// Redraws the changed part of view `k`'s canvas texture: guides under the painting,
    /// outlines over it, sRGB-encoded.
    fn update_canvas_texture(&mut self, ctx: &egui::Context, k: usize) {
        let guides = (self.show_outline, self.show_reference);
        let view = &mut self.session.views[k];
        let full = self.canvas_tex[k].as_ref().is_none_or(|(_, g)| *g != guides);
        let dirty = view.canvas.take_dirty();
        let rect = if full {
            Some(super::canvas::PixelRect { x0: 0, y0: 0, x1: view.width, y1: view.height })
        } else {
            dirty
        };
        let Some(r) = rect else { return };
        let (w, h) = (r.x1 - r.x0, r.y1 - r.y0);
        let mut pixels = Vec::with_capacity(w * h);
        let painting = view.canvas.painting();
        for j in r.y0..r.y1 {
            for i in r.x0..r.x1 {
                let idx = j * view.width + i;
                let base = if guides.1 && view.hit[idx] {
                    // The reference, lightened, so paint stands out against it.
                    let c = view.reference[idx];
                    [0.55 + 0.45 * c[0], 0.55 + 0.45 * c[1], 0.55 + 0.45 * c[2]]
                } else {
                    [1.0; 3]
                };
                let p = painting.pixels[idx];
                let a = painting.alpha[idx].clamp(0.0, 1.0);
                let mut c = [0, 1, 2].map(|q| base[q] * (1.0 - a) + p[q] * a);
                if guides.0 && view.lines[idx] {
                    c = c.map(|x| x * 0.12);
                }
                let e = c.map(|x| (linear_to_srgb(x) * 255.0 + 0.5) as u8);
                pixels.push(Color32::from_rgb(e[0], e[1], e[2]));
            }
        }
        let image = ColorImage::new([w, h], pixels);
        match &mut self.canvas_tex[k] {
            Some((tex, _)) if !full => tex.set_partial([r.x0, r.y0], image, TextureOptions::LINEAR),
            slot => *slot = Some((ctx.load_texture(format!("canvas {k}"), image, TextureOptions::LINEAR), guides)),
        }
    }

    fn tables_ui(&mut self, ui: &mut egui::Ui) {
        let Some(material) = self.current_material().cloned() else {
            ui.label("No material yet.");
            return;
        };
        if self.tables_dirty {
            self.tables.clear();
            self.tables_dirty = false;
        }
        ui.horizontal(|ui| {
            ui.strong("Factor tables");
            ui.label(format!(
                "({:?}, {} term{}, mapping {})",
                material.kind,
                material.terms.len(),
                if material.terms.len() == 1 { "" } else { "s" },
                material.terms.first().map_or("-", |t| t.map.name())
            ));
        });
        let height = (ui.available_height() - 24.0).clamp(40.0, 400.0);
        egui::ScrollArea::horizontal().show(ui, |ui| {
            // Captions never wrap: past the panel's width (a material map's many factors)
            // they would wrap word by word into tall columns, and the panel, which grows to
            // its content, would push the 3D view out of the window.
            ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
            ui.horizontal(|ui| {
                let mut k = 0;
                for (ti, term) in material.terms.iter().enumerate() {
                    for f in &term.factors {
                        ui.vertical(|ui| {
                            let name = match f.spec.input {
                                Input::Light => "p(l)",
                                Input::Half => "q(h)",
                                Input::View => "r(v)",
                                Input::Uv => "s(uv)",
                                Input::Custom(_) => "custom",
                            };
                            let max = f.texels.iter().flat_map(|t| t.iter()).fold(0.0f32, |a, &b| a.max(b));
                            ui.small(format!("term {ti} {name}: {:?} {}D, {} nodes, max {max:.3}", f.spec.param, f.spec.dim(), f.spec.res));
                            if f.spec.dim() == 1 {
                                plot_curves(ui, &f.texels, max, f.spec.domain == Domain::Sphere, Vec2::new(height * 1.8, height - 18.0));
                            } else {
                                let tex = self.table_texture(ui.ctx(), k, f.spec.res, &f.texels, max);
                                let side = height - 18.0;
                                ui.image((tex, Vec2::splat(side)));
                            }
                        });
                        k += 1;
                    }
                }
            });
        });
    }

    fn table_texture(&mut self, ctx: &egui::Context, k: usize, res: usize, texels: &[[f32; 3]], max: f32) -> egui::TextureId {
        while self.tables.len() <= k {
            self.tables.push(None);
        }
        if self.tables[k].is_none() {
            let s = if max > 0.0 { 1.0 / max } else { 1.0 };
            // Row y of the table is its second coordinate: draw it upwards.
            let mut pixels = Vec::with_capacity(res * res);
            for y in (0..res).rev() {
                for x in 0..res {
                    let t = texels[y * res + x];
                    let e = t.map(|v| (linear_to_srgb(v * s) * 255.0 + 0.5) as u8);
                    pixels.push(Color32::from_rgb(e[0], e[1], e[2]));
                }
            }
            self.tables[k] = Some(ctx.load_texture(format!("table {k}"), ColorImage::new([res, res], pixels), TextureOptions::NEAREST));
        }
        self.tables[k].as_ref().expect("made above").id()
    }
}

/// RGB curves of a 1D table over its nodes, scaled to `max`.
fn plot_curves(ui: &mut egui::Ui, texels: &[[f32; 3]], max: f32, sphere: bool, size: Vec2) {
    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
    let p = ui.painter_at(rect);
    p.rect_filled(rect, 2.0, Color32::from_gray(24));
    let n = texels.len().max(2);
    let colours = [Color32::from_rgb(235, 90, 80), Color32::from_rgb(110, 210, 110), Color32::from_rgb(100, 150, 255)];
    let s = if max > 0.0 { 1.0 / max } else { 1.0 };
    for (c, colour) in colours.iter().enumerate() {
        let points: Vec<Pos2> = texels
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let x = rect.min.x + rect.width() * i as f32 / (n - 1) as f32;
                let y = rect.max.y - 2.0 - (rect.height() - 4.0) * (t[c] * s).clamp(0.0, 1.0);
                Pos2::new(x, y)
            })
            .collect();
        p.line(points, Stroke::new(1.5, *colour));
    }
    if sphere {
        // The horizon of the sphere domain sits at the middle of a radius table (ρ = 1 of 2).
        p.line_segment(
            [Pos2::new(rect.center().x, rect.min.y), Pos2::new(rect.center().x, rect.max.y)],
            Stroke::new(1.0, Color32::from_gray(60)),
        );
    }
}

fn short(s: &str) -> String {
    let n = s.chars().count();
    if n <= 32 {
        s.to_string()
    } else {
        format!("...{}", s.chars().skip(n - 29).collect::<String>())
    }
}

fn view_label(names: &[String], k: usize) -> String {
    match names.get(k) {
        Some(n) if !n.is_empty() => n.clone(),
        _ => "scene".into(),
    }
}
