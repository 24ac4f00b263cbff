//! The live painting: the session and its views, which view is painted, the watched file,
//! and what changed since the last refit.

use std::path::Path;

use crate::error::{Error, Result};
use crate::live::{read_painting_for, Brush, PaintSession, PaintView, Watcher};
use crate::render::Renderer;

pub(super) struct Easel {
    pub session: PaintSession,
    /// The model the standard views show.
    pub paint_model: String,
    /// Side of a standard view's painting.
    pub size: usize,
    /// Preset name per session view (empty for a `--scene` view).
    pub view_names: Vec<String>,
    /// The view painted now.
    pub active: usize,
    /// One `--scene` view instead of the standard ones.
    pub scene_mode: bool,
    pub watcher: Option<Watcher>,
    /// Changes whenever views are added, replaced or dropped (canvas textures follow it).
    pub generation: u64,
    /// A canvas changed since the last refit.
    pub canvas_changed: bool,
    /// A stroke ended: time for a full solve.
    pub stroke_ended: bool,
    /// A full solve is due (settings changed, a prepare arrived, an edit that is not a stroke).
    pub refine_needed: bool,
}

impl Easel {
    pub fn new(session: PaintSession, paint_model: String, size: usize, scene_mode: bool) -> Easel {
        Easel {
            session,
            paint_model,
            size,
            view_names: Vec::new(),
            active: 0,
            scene_mode,
            watcher: None,
            generation: 0,
            canvas_changed: false,
            stroke_ended: false,
            refine_needed: false,
        }
    }

    /// Adds `view` under `name` (a preset, or empty for a scene view) and paints it.
    pub fn add_view(&mut self, name: &str, view: PaintView) -> usize {
        let k = self.session.add_view(view);
        self.view_names.push(name.to_string());
        self.generation += 1;
        self.active = k;
        k
    }

    /// Opens (renders) the standard view `preset` of the paint model, or finds it, and paints
    /// it; its index.
    pub fn open_view(&mut self, renderer: &mut Renderer, preset: &str) -> Result<usize> {
        if let Some(k) = self.view_names.iter().position(|n| n == preset) {
            self.active = k;
            return Ok(k);
        }
        let view = PaintView::standard(renderer, &self.paint_model, preset, self.size)?;
        Ok(self.add_view(preset, view))
    }

    /// Starts over with the standard views of another model (same settings and mapping).
    pub fn restart(&mut self, renderer: &mut Renderer, paint_model: String, first_preset: &str) -> Result<()> {
        let settings = self.session.settings().clone();
        self.session = PaintSession::new(settings, self.session.mapping());
        self.paint_model = paint_model;
        self.view_names.clear();
        self.active = 0;
        self.generation += 1;
        self.open_view(renderer, first_preset).map(|_| ())
    }

    /// Changes whenever any painting changes or views come and go: what a note about the
    /// paintings is valid for.
    pub fn stamp(&self) -> u64 {
        self.session.views.iter().fold(self.generation.wrapping_mul(1_000_003), |s, v| s.wrapping_add(v.canvas.version()))
    }

    /// What the UI calls view `k`.
    pub fn view_label(&self, k: usize) -> String {
        match self.view_names.get(k) {
            Some(n) if !n.is_empty() => n.clone(),
            _ => "scene".into(),
        }
    }

    /// Whether view `k` has paint on it.
    pub fn is_painted(&self, k: usize) -> bool {
        self.session.views.get(k).is_some_and(|v| v.canvas.painting().alpha.iter().any(|&a| a > 0.0))
    }

    pub fn any_stroking(&self) -> bool {
        self.session.views.iter().any(|v| v.canvas.stroking())
    }

    /// An edit that is not a stroke in progress: refit, then solve in full.
    fn edited(&mut self) {
        self.canvas_changed = true;
        self.refine_needed = true;
    }

    /// Undoes the active view's last edit; `false` when there was none.
    pub fn undo(&mut self) -> bool {
        let done = self.session.views.get_mut(self.active).is_some_and(|v| v.canvas.undo());
        if done {
            self.edited();
        }
        done
    }

    pub fn redo(&mut self) -> bool {
        let done = self.session.views.get_mut(self.active).is_some_and(|v| v.canvas.redo());
        if done {
            self.edited();
        }
        done
    }

    /// Paints the whole object of the active view with `brush` at full coverage, or erases
    /// it completely.
    pub fn fill_all(&mut self, brush: Brush, erase: bool) {
        if let Some(v) = self.session.views.get_mut(self.active) {
            let pixels = v.object_pixels();
            let mut b = brush;
            b.erase = erase;
            if erase {
                b.opacity = 1.0;
            }
            v.canvas.fill(b, &pixels);
            self.edited();
        }
    }

    /// Replaces the active view's painting by its reference image.
    pub fn start_from_reference(&mut self) {
        if let Some(v) = self.session.views.get_mut(self.active) {
            let p = v.reference_painting();
            if v.canvas.set_painting(&p).is_ok() {
                self.edited();
            }
        }
    }

    /// Loads a painting file into the active view under the size rule of `brdfpaint fit`
    /// ([`crate::live::view`]): a painting of another size of the camera's aspect gets the view
    /// rendered again at its size.
    pub fn load_painting(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        let k = self.active;
        let view = self.session.views.get(k).ok_or_else(|| Error::input("no view to paint"))?;
        let p = read_painting_for(view, path)?;
        if (p.width, p.height) != (view.width, view.height) {
            let resized = view.resized(renderer, p.width, p.height)?;
            self.session.replace_view(k, resized);
            self.generation += 1;
        }
        self.session.views[k].canvas.set_painting(&p)?;
        self.edited();
        Ok(())
    }
}
