//! The live-painting core, with no window: painted views, the prepared system, and the refit
//! a stroke triggers. The viewer's UI calls exactly this; tests and `brdfpaint bench` script
//! it.
//!
//! ```text
//! stroke ─► canvas ─► values of the prepared pattern ─► Prepared::solve_tables ─► material ─► upload ─► frame
//!                         ▲
//!   painted pixels ─► pattern ─► prepare (background thread, only when the set of painted pixels changes)
//! ```
//!
//! A prepared system depends only on *which* pixels are samples (thesis 3.2.2), so a stroke
//! over paint that is already there refits in a fraction of a millisecond through the system
//! prepared before. A stroke that paints new pixels (or erases some completely) changes the
//! pattern; it is prepared again on a background thread, and until it is ready every refit
//! still runs through the previous system: pixels painted since are left out, and pixels
//! erased since are given the current model's own prediction, so they pull the fit nowhere.
//! When the new system arrives, the fit is exact again. [`PaintSession::settle`] waits for
//! that and solves with the full mapping choice: the result is the fit of the final
//! paintings in one go ([`fit_views`]), to the last bit.
//!
//! Several painted views feed one fit: their patterns are concatenated (thesis 4.4).

use std::path::Path;
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec2;
use glow::HasContext;

use super::canvas::{Brush, Canvas, Painting};
use super::sample::{self, Slot};
use crate::error::{Error, Result};
use crate::factor::{self, Errors, Fit, LogMap, Mapping, Pattern, Prepared, Settings};
use crate::gl::{Framebuffer, HeadlessContext};
use crate::material::{Material, Provenance};
use crate::render::{GpuScene, LightUniforms, ReferenceStyle, Renderer};
use crate::scene::Scene;

/// Side of the standard painting.
pub const DEFAULT_SIZE: usize = 512;

/// One view to paint: a scene (camera and light), its coloring-book guides, the pixels that
/// are samples, and the canvas.
pub struct PaintView {
    /// What the UI calls it: the preset's name, or the scene file.
    pub name: String,
    pub scene: Scene,
    pub width: usize,
    pub height: usize,
    /// Pixels that may be samples, in pixel order.
    pub slots: Vec<Slot>,
    /// Whether the samples carry texture coordinates (every mesh has them).
    pub has_uv: bool,
    /// Per pixel: the pixel sees the object.
    pub hit: Vec<bool>,
    /// Per pixel: an outline (silhouette, crease or occlusion line) passes here.
    pub lines: Vec<bool>,
    /// The reference image (Lambert + Phong under the view's light; thesis 4.1), linear RGB.
    pub reference: Vec<[f32; 3]>,
    pub canvas: Canvas,
}

impl PaintView {
    /// Renders the view's G-buffer and guides at `width` × `height` and starts an empty
    /// canvas. Errors: the camera's aspectRatio disagrees with the size by more than 1%, GL
    /// failures, a bad camera or light.
    pub fn new(renderer: &mut Renderer, name: &str, scene: Scene, width: usize, height: usize) -> Result<PaintView> {
        crate::sample::check_aspect(&scene.camera, width, height, name)?;
        let gpu = GpuScene::upload(renderer.gl(), &scene)?;
        let g = renderer.gbuffer(&gpu, width, height)?;
        let reference = renderer.reference(&gpu, &ReferenceStyle::default(), width, height)?;
        LightUniforms::new(&scene.light)?;
        let (slots, has_uv) = sample::slots(&g, &scene)?;
        let lines = g.lines(&crate::render::OutlineStyle::default());
        let hit = g.pixels.iter().map(|p| p.hit).collect();
        Ok(PaintView {
            name: name.to_string(),
            scene,
            width,
            height,
            slots,
            has_uv,
            hit,
            lines,
            reference: reference.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect(),
            canvas: Canvas::new(width, height)?,
        })
    }

    /// A standard view: `model` (a built-in name or a .glb/.gltf path) framed for `preset`
    /// (thesis 4.1), `size` × `size` pixels.
    pub fn standard(renderer: &mut Renderer, model: &str, preset: &str, size: usize) -> Result<PaintView> {
        let scene = Scene::from_preset(model, preset)?;
        Self::new(renderer, preset, scene, size, size)
    }

    /// Indices into [`PaintView::slots`] of the painted ones.
    pub fn painted_slots(&self) -> Vec<u32> {
        let alpha = &self.canvas.painting().alpha;
        (0..self.slots.len() as u32).filter(|&s| alpha[self.slots[s as usize].pixel as usize] > 0.0).collect()
    }

    /// The sample value of slot `s` under the current painting (painted or not): the
    /// colour divided by the light, exactly as [`crate::sample::Samples::gather`] computes it.
    #[inline]
    fn value(&self, s: usize) -> [f64; 3] {
        let slot = &self.slots[s];
        let c = self.canvas.painting().pixels[slot.pixel as usize];
        [0, 1, 2].map(|i| c[i] as f64 / slot.light[i])
    }

    /// The region the fill tool fills from pixel `(i, j)`: the pixels of the object reachable
    /// without crossing an interior line (crease or occlusion), plus the lines bordering
    /// them. Outside the object: empty.
    pub fn fill_region(&self, i: usize, j: usize) -> Vec<u32> {
        let (w, h) = (self.width, self.height);
        if i >= w || j >= h || !self.hit[j * w + i] {
            return Vec::new();
        }
        let open = |k: usize| self.hit[k] && !self.lines[k];
        let mut seen = vec![false; w * h];
        let mut out = Vec::new();
        let start = j * w + i;
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(k) = stack.pop() {
            out.push(k as u32);
            if !open(k) && k != start {
                continue; // a line pixel is filled but does not spread
            }
            let (x, y) = (k % w, k / w);
            let mut push = |n: usize| {
                if !seen[n] && self.hit[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            };
            if x > 0 {
                push(k - 1);
            }
            if x + 1 < w {
                push(k + 1);
            }
            if y > 0 {
                push(k - w);
            }
            if y + 1 < h {
                push(k + w);
            }
        }
        out.sort_unstable();
        out
    }

    /// Every pixel of the object (for "fill all" and "erase all").
    pub fn object_pixels(&self) -> Vec<u32> {
        (0..self.hit.len() as u32).filter(|&k| self.hit[k as usize]).collect()
    }

    /// The reference image as a fully painted painting: a quick start, and the standard
    /// test painting.
    pub fn reference_painting(&self) -> Painting {
        let n = self.width * self.height;
        let pixels = self.reference.iter().zip(&self.hit).map(|(c, &hit)| if hit { *c } else { [0.0; 3] }).collect();
        let alpha = self.hit.iter().map(|&h| if h { 1.0 } else { 0.0 }).collect();
        Painting { width: self.width, height: self.height, pixels, alpha, saturated: vec![false; n] }
    }
}

/// The pattern of the given slots of the given views, views in order, slots in order: the
/// one definition both the live system and [`fit_views`] use.
fn pattern_of(views: &[&PaintView], masks: &[Vec<u32>]) -> Pattern {
    let queries = views
        .iter()
        .zip(masks)
        .flat_map(|(v, m)| m.iter().map(move |&s| v.slots[s as usize].query))
        .collect();
    Pattern::new(queries, views.iter().all(|v| v.has_uv))
}

/// Values of the painted slots, views in order.
fn painted_values(views: &[&PaintView], masks: &[Vec<u32>]) -> Vec<[f64; 3]> {
    views.iter().zip(masks).flat_map(|(v, m)| m.iter().map(move |&s| v.value(s as usize))).collect()
}

/// Fits the paintings of `views` in one go: samples from the painted pixels, prepare, solve.
/// What the live session converges to.
pub fn fit_views(views: &[&PaintView], settings: &Settings, mapping: Mapping) -> Result<(Fit, Material)> {
    let masks: Vec<Vec<u32>> = views.iter().map(|v| v.painted_slots()).collect();
    let pattern = pattern_of(views, &masks);
    if pattern.is_empty() {
        return Err(Error::input("nothing is painted: there are no samples"));
    }
    let prepared = factor::prepare(&pattern, settings)?;
    let values = painted_values(views, &masks);
    let start = Instant::now();
    let fit = prepared.solve(&values, mapping)?;
    let provenance = provenance(views, &prepared, Some(fit.errors), start.elapsed().as_secs_f64());
    let material = Material::from_fit(settings, &fit, provenance)?;
    Ok((fit, material))
}

fn provenance(views: &[&PaintView], prepared: &Prepared, errors: Option<Errors>, solve_s: f64) -> Provenance {
    Provenance {
        tool: format!("brdfpaint {}", env!("CARGO_PKG_VERSION")),
        sources: views.iter().map(|v| format!("painting of view '{}'", v.name)).collect(),
        errors,
        samples: prepared.samples(),
        prepare_s: prepared.prepare_s,
        solve_s,
    }
}

/// A prepared system and the painted slots (per view) it was prepared for.
struct System {
    prepared: Arc<Prepared>,
    masks: Vec<Vec<u32>>,
    /// The canvases' mask versions when the masks were taken.
    versions: Vec<u64>,
    /// Per view, per sample of the pattern: its pixel and the scale of its value, packed
    /// so the per-stroke gather streams 32 bytes a sample instead of whole slots.
    gather: Vec<Vec<(u32, [f64; 3])>>,
}

/// A prepare running on a background thread.
struct Pending {
    masks: Vec<Vec<u32>>,
    versions: Vec<u64>,
    settings: Settings,
    rx: mpsc::Receiver<Result<Prepared>>,
}

/// What one refit did, and how long its parts took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Refit {
    /// Samples of the prepared pattern.
    pub samples: usize,
    /// Painted pixels not yet in the prepared pattern (a prepare for them is running).
    pub waiting: usize,
    /// Pattern pixels erased since the prepare, given the model's own prediction.
    pub predicted: usize,
    /// The mapping used.
    pub map: Option<LogMap>,
    /// Errors on the samples (full solves only).
    pub errors: Option<Errors>,
    /// Gathering the values (painted colour / light) of the pattern's pixels.
    pub values_ms: f64,
    /// `solve_tables` (or the full solve) and building the material.
    pub solve_ms: f64,
    /// The fit is the exact least-squares fit of the current paintings.
    pub exact: bool,
}

/// Painted views, the prepared system, and the current fit.
pub struct PaintSession {
    pub views: Vec<PaintView>,
    settings: Settings,
    mapping: Mapping,
    system: Option<System>,
    pending: Option<Pending>,
    fit: Option<Fit>,
    material: Option<Material>,
    /// Under `Mapping::Auto`, the mapping the last full solve chose; live refits keep it.
    chosen: Option<LogMap>,
}

impl PaintSession {
    /// A session without views.
    pub fn new(settings: Settings, mapping: Mapping) -> PaintSession {
        PaintSession {
            views: Vec::new(),
            settings,
            mapping,
            system: None,
            pending: None,
            fit: None,
            material: None,
            chosen: None,
        }
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    pub fn mapping(&self) -> Mapping {
        self.mapping
    }

    /// New fit settings: the prepared system is dropped and prepared again at the next refit.
    pub fn set_settings(&mut self, settings: Settings) -> Result<()> {
        settings.validate()?;
        if settings != self.settings {
            self.settings = settings;
            self.system = None;
            self.pending = None;
            self.chosen = None;
        }
        Ok(())
    }

    /// A new mapping: takes effect at the next refit (no prepare needed).
    pub fn set_mapping(&mut self, mapping: Mapping) {
        self.mapping = mapping;
        self.chosen = None;
    }

    /// Adds a view; returns its index.
    pub fn add_view(&mut self, view: PaintView) -> usize {
        self.views.push(view);
        // The views changed: whatever was prepared no longer lines up.
        self.system = None;
        self.pending = None;
        self.views.len() - 1
    }

    /// The current material, if anything has been fitted.
    pub fn material(&self) -> Option<&Material> {
        self.material.as_ref()
    }

    /// The current fit (tables and mapping).
    pub fn fit(&self) -> Option<&Fit> {
        self.fit.as_ref()
    }

    /// Painted samples over all views.
    pub fn painted(&self) -> usize {
        self.views.iter().map(|v| v.painted_slots().len()).sum()
    }

    /// Whether a prepare is running in the background.
    pub fn preparing(&self) -> bool {
        self.pending.is_some()
    }

    /// Samples of the prepared system, if there is one.
    pub fn prepared_samples(&self) -> Option<usize> {
        self.system.as_ref().map(|s| s.prepared.samples())
    }

    fn versions(&self) -> Vec<u64> {
        self.views.iter().map(|v| v.canvas.mask_version()).collect()
    }

    fn masks(&self) -> Vec<Vec<u32>> {
        self.views.iter().map(|v| v.painted_slots()).collect()
    }

    /// Whether the prepared system is for exactly the painted pixels of now.
    fn system_is_current(&mut self) -> bool {
        let versions = self.versions();
        let Some(system) = self.system.as_mut() else { return false };
        if system.versions == versions {
            return true;
        }
        // The versions moved, but the set may be the same again (an undo, a recolouring fill).
        let masks: Vec<Vec<u32>> = self.views.iter().map(|v| v.painted_slots()).collect();
        if masks == system.masks {
            system.versions = versions;
            true
        } else {
            false
        }
    }

    /// Installs a finished background prepare. Returns `true` when a new system arrived.
    /// Errors: the prepare failed (the previous system stays).
    pub fn poll(&mut self) -> Result<bool> {
        let Some(p) = self.pending.as_ref() else { return Ok(false) };
        match p.rx.try_recv() {
            Ok(result) => self.install(result).map(|()| true),
            Err(mpsc::TryRecvError::Empty) => Ok(false),
            Err(mpsc::TryRecvError::Disconnected) => {
                self.pending = None;
                Err(Error::Numeric("the prepare thread stopped without a result".into()))
            }
        }
    }

    fn install(&mut self, result: Result<Prepared>) -> Result<()> {
        let p = self.pending.take().expect("a pending prepare");
        if p.settings != self.settings {
            return Ok(()); // settings changed meanwhile: stale
        }
        let prepared = result?;
        let gather = self
            .views
            .iter()
            .zip(&p.masks)
            .map(|(v, m)| {
                m.iter()
                    .map(|&s| {
                        let slot = &v.slots[s as usize];
                        (slot.pixel, slot.light)
                    })
                    .collect()
            })
            .collect();
        self.system = Some(System { prepared: Arc::new(prepared), masks: p.masks, versions: p.versions, gather });
        Ok(())
    }

    /// Starts a background prepare for the painted pixels of now, unless the system or the
    /// running prepare is already for them. Nothing painted: nothing to prepare.
    fn ensure_prepare(&mut self, current: bool) {
        if current {
            return;
        }
        if self.pending.is_some() {
            // Let the running prepare finish; the poll that installs it starts the next.
            return;
        }
        let versions = self.versions();
        let masks = self.masks();
        if masks.iter().all(|m| m.is_empty()) {
            return;
        }
        let views: Vec<&PaintView> = self.views.iter().collect();
        let pattern = pattern_of(&views, &masks);
        let settings = self.settings.clone();
        let (tx, rx) = mpsc::channel();
        let thread_settings = settings.clone();
        std::thread::spawn(move || {
            let _ = tx.send(factor::prepare(&pattern, &thread_settings));
        });
        self.pending = Some(Pending { masks, versions, settings, rx });
    }

    /// The mapping of a fast refit. The user's, with constants for these values; under
    /// `auto`, the one the last full solve chose, constants and all, so a stroke moves the
    /// material only as much as its paint does. An inverted mapping is kept only while every
    /// value stays below its constant with the default headroom: paint brighter than that
    /// would sit next to the singularity of $\log(a - f)$ and swing the whole fit, so those
    /// refits use the offset mapping until the full solve at the stroke's end chooses again.
    fn live_map(&self, max: [f64; 3]) -> Result<LogMap> {
        if self.mapping != Mapping::Auto {
            return Ok(self.mapping.candidates(max)?[0]);
        }
        match self.chosen {
            Some(LogMap::Inverted { a }) if (0..3).all(|c| max[c] * crate::factor::mapping::INVERTED_DEFAULT <= a[c]) => {
                Ok(LogMap::Inverted { a })
            }
            Some(m @ (LogMap::Identity { .. } | LogMap::Offset { .. })) => Ok(m),
            _ => Ok(Mapping::Offset(None).candidates(max)?[0]),
        }
    }

    /// The refit after a stroke: values of the prepared pattern → `solve_tables` →
    /// material. `Ok(None)` when there is nothing to solve yet (nothing painted, or the first
    /// prepare is still running). Errors leave the last material in place.
    pub fn refit(&mut self) -> Result<Option<Refit>> {
        self.poll()?;
        let current = self.system_is_current();
        if !current && self.views.iter().all(|v| v.canvas.painting().alpha.iter().all(|&a| a <= 0.0)) {
            // Everything was erased: keep the last material until something is painted.
            return Ok(None);
        }
        self.ensure_prepare(current);
        let Some(system) = self.system.as_ref() else { return Ok(None) };
        let t0 = Instant::now();
        // Values of the prepared pattern; erased pixels get the model's prediction.
        let mut values = Vec::with_capacity(system.prepared.samples());
        let mut erased = Vec::new();
        for (v, gather) in self.views.iter().zip(&system.gather) {
            let painting = v.canvas.painting();
            for &(pixel, light) in gather {
                if painting.alpha[pixel as usize] > 0.0 {
                    // Exactly `PaintView::value`, so a current system's solve is the one-go fit.
                    let c = painting.pixels[pixel as usize];
                    values.push([c[0] as f64 / light[0], c[1] as f64 / light[1], c[2] as f64 / light[2]]);
                } else {
                    erased.push(values.len());
                    values.push([0.0; 3]);
                }
            }
        }
        if !erased.is_empty() {
            if let Some(fit) = &self.fit {
                let predicted = system.prepared.predict(&fit.tables, &fit.map);
                for &k in &erased {
                    values[k] = predicted[k];
                }
            }
        }
        let mut max = [0.0f64; 3];
        for v in &values {
            for c in 0..3 {
                max[c] = max[c].max(v[c]);
            }
        }
        let t1 = Instant::now();
        let map = self.live_map(max)?;
        let tables = system.prepared.solve_tables(&values, &map)?;
        let fit = Fit { tables, map, errors: Errors::default(), tried: Vec::new() };
        let views: Vec<&PaintView> = self.views.iter().collect();
        let solve_s = t1.elapsed().as_secs_f64();
        let material = Material::from_fit(&self.settings, &fit, provenance(&views, &system.prepared, None, solve_s))?;
        let t2 = Instant::now();
        let waiting = if current { 0 } else { self.painted().saturating_sub(values.len() - erased.len()) };
        let report = Refit {
            samples: values.len(),
            waiting,
            predicted: erased.len(),
            map: Some(map),
            errors: None,
            values_ms: (t1 - t0).as_secs_f64() * 1e3,
            solve_ms: (t2 - t1).as_secs_f64() * 1e3,
            exact: current && erased.is_empty(),
        };
        self.fit = Some(fit);
        self.material = Some(material);
        Ok(Some(report))
    }

    /// A full solve (every candidate mapping under `auto`, with errors) when the prepared
    /// system is current; otherwise a fast refit. Run it when a stroke ends.
    pub fn refine(&mut self) -> Result<Option<Refit>> {
        self.poll()?;
        if !self.system_is_current() {
            return self.refit();
        }
        let system = self.system.as_ref().expect("current");
        let t0 = Instant::now();
        let views: Vec<&PaintView> = self.views.iter().collect();
        let values = painted_values(&views, &system.masks);
        let t1 = Instant::now();
        let fit = system.prepared.solve(&values, self.mapping)?;
        let solve_s = t1.elapsed().as_secs_f64();
        let material =
            Material::from_fit(&self.settings, &fit, provenance(&views, &system.prepared, Some(fit.errors), solve_s))?;
        let t2 = Instant::now();
        let report = Refit {
            samples: values.len(),
            waiting: 0,
            predicted: 0,
            map: Some(fit.map),
            errors: Some(fit.errors),
            values_ms: (t1 - t0).as_secs_f64() * 1e3,
            solve_ms: (t2 - t1).as_secs_f64() * 1e3,
            exact: true,
        };
        if self.mapping == Mapping::Auto {
            self.chosen = Some(fit.map);
        }
        self.fit = Some(fit);
        self.material = Some(material);
        Ok(Some(report))
    }

    /// Waits until the prepared system is the one for the current paintings, then solves in
    /// full: the same fit as [`fit_views`] on the current paintings. Errors: nothing painted,
    /// a failed prepare or solve.
    pub fn settle(&mut self) -> Result<Refit> {
        loop {
            if let Some(p) = self.pending.take() {
                let result = p.rx.recv().map_err(|_| Error::Numeric("the prepare thread stopped".into()))?;
                self.pending = Some(p);
                self.install(result)?;
            }
            if self.system_is_current() {
                break;
            }
            self.ensure_prepare(false);
            if self.pending.is_none() {
                return Err(Error::input("nothing is painted: there are no samples"));
            }
        }
        Ok(self.refine()?.expect("a current system solves"))
    }
}

/// The headless stroke → refit → frame measurement (DESIGN.md: live painting must fit in one
/// 60 Hz frame), medians in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StrokeTiming {
    /// Painting side in pixels.
    pub size: usize,
    /// Samples of the painting.
    pub samples: usize,
    /// Unknowns of the prepared system.
    pub unknowns: usize,
    pub strokes: usize,
    /// Applying the stroke to the canvas.
    pub stroke_ms: f64,
    /// Painted colours → sample values.
    pub values_ms: f64,
    /// `solve_tables` and the material.
    pub solve_ms: f64,
    /// Material → textures.
    pub upload_ms: f64,
    /// Drawing the model with the new material at `size`², to `glFinish`.
    pub frame_ms: f64,
    /// All of the above, per stroke.
    pub total_ms: f64,
    /// The background prepare for the painting (once per set of painted pixels).
    pub prepare_ms: f64,
}

/// Measures stroke → samples → solve → upload → frame on a headless context (Mesa's software
/// device): `model` (built-in name or file) in the front-left standard view, a `size`²
/// painting (the reference image, fully painted), then `strokes` short strokes over the
/// painted object, each refitting and drawing a `size`² frame of the model with the new
/// material.
pub fn measure_stroke_to_frame(model: &str, size: usize, strokes: usize) -> Result<StrokeTiming> {
    let ctx = HeadlessContext::new()?;
    let gl = ctx.gl().clone();
    let mut renderer = Renderer::new(&gl)?;
    let mut view = PaintView::standard(&mut renderer, model, "front-left", size)?;
    let painting = view.reference_painting();
    view.canvas.set_painting(&painting)?;
    let gpu = GpuScene::upload(&gl, &view.scene)?;
    let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
    session.add_view(view);
    let t = Instant::now();
    session.settle()?;
    let prepare_ms = t.elapsed().as_secs_f64() * 1e3;
    let target = Framebuffer::new(&gl, size, size)?;

    let warm = strokes / 10 + 2;
    let mut rows: Vec<[f64; 5]> = Vec::with_capacity(strokes);
    let s = size as f32;
    for k in 0..warm + strokes {
        // A short stroke across the middle of the object, its colour changing every time.
        let phase = k as f32 / (warm + strokes) as f32;
        let brush = Brush {
            color: [0.2 + 0.6 * phase, 0.3, 0.8 - 0.5 * phase],
            radius: s / 40.0,
            hardness: 0.6,
            opacity: 0.8,
            erase: false,
        };
        let y = s * (0.45 + 0.1 * phase);
        let t0 = Instant::now();
        session.views[0].canvas.stroke(brush, &[Vec2::new(0.42 * s, y), Vec2::new(0.58 * s, y)]);
        let t1 = Instant::now();
        let refit = session.refit()?.ok_or_else(|| Error::Numeric("no refit".into()))?;
        let t2 = Instant::now();
        let material = session.material().expect("refit made one");
        let shading = renderer.upload(material)?;
        let t3 = Instant::now();
        target.bind();
        // SAFETY: plain state calls on the current context.
        unsafe {
            gl.clear_color(0.0, 0.0, 0.0, 0.0);
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.enable(glow::DEPTH_TEST);
        }
        renderer.draw_factored(&gpu, &shading, size, size)?;
        // SAFETY: waits for the GPU on the current context.
        unsafe { gl.finish() };
        let t4 = Instant::now();
        if k >= warm {
            let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
            rows.push([ms(t0, t1), refit.values_ms, ms(t1, t2) - refit.values_ms, ms(t2, t3), ms(t3, t4)]);
        }
    }
    let median = |i: usize| {
        let mut x: Vec<f64> = rows.iter().map(|r| r[i]).collect();
        x.sort_by(f64::total_cmp);
        if x.is_empty() {
            0.0
        } else {
            x[x.len() / 2]
        }
    };
    let mut totals: Vec<f64> = rows.iter().map(|r| r.iter().sum()).collect();
    totals.sort_by(f64::total_cmp);
    let prepared = session.prepared_samples().unwrap_or(0);
    Ok(StrokeTiming {
        size,
        samples: prepared,
        unknowns: session.settings().unknowns(),
        strokes,
        stroke_ms: median(0),
        values_ms: median(1),
        solve_ms: median(2),
        upload_ms: median(3),
        frame_ms: median(4),
        total_ms: totals.get(totals.len() / 2).copied().unwrap_or(0.0),
        prepare_ms,
    })
}

/// Reads a painting for `view` from a file, checking its size against the view.
pub fn read_painting_for(view: &PaintView, path: &Path) -> Result<Painting> {
    let p = Painting::read(path)?;
    if p.width != view.width || p.height != view.height {
        return Err(Error::format(
            path,
            format!("the painting is {}x{} but the view is {}x{}", p.width, p.height, view.width, view.height),
        ));
    }
    Ok(p)
}
