//! One view to paint: a scene rendered once into the guides the painter sees (outline,
//! reference) and the slots that can be samples, with the canvas painted on it.
//!
//! Size rule (the one `brdfpaint fit` applies, DESIGN.md): a painting belongs to a view when
//! its aspect is the camera's within 1% ([`crate::sample::check_aspect`]); its size need not be
//! the view's. A painting of another size is painted on the view rendered again at that size
//! ([`PaintView::resized`]), so its samples are exactly the ones `fit` takes from it.

use std::path::Path;
use std::sync::Arc;

use super::canvas::{Canvas, Painting};
use super::slots::{self, Slot};
use crate::error::{Error, Result};
use crate::render::{GBuffer, GpuScene, LightUniforms, ReferenceStyle, Renderer};
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
    /// The G-buffer the slots came from: what the full fit reads the painting against
    /// ([`crate::read::Reader`] turns the light on it). Shared, never changed.
    pub gbuffer: Arc<GBuffer>,
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
        let (slots, has_uv) = slots::slots(&g, &scene)?;
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
            gbuffer: Arc::new(g),
            canvas: Canvas::new(width, height)?,
        })
    }

    /// A standard view: `model` (a built-in name or a .glb/.gltf path) framed for `preset`
    /// (thesis 4.1), `size` × `size` pixels.
    pub fn standard(renderer: &mut Renderer, model: &str, preset: &str, size: usize) -> Result<PaintView> {
        let scene = Scene::from_preset(model, preset)?;
        Self::new(renderer, preset, scene, size, size)
    }

    /// The same view rendered again at `width` × `height`, with an empty canvas: what a
    /// painting of another size (of the camera's aspect) is painted on.
    pub fn resized(&self, renderer: &mut Renderer, width: usize, height: usize) -> Result<PaintView> {
        Self::new(renderer, &self.name, self.scene.clone(), width, height)
    }

    /// Indices into [`PaintView::slots`] of the painted ones.
    pub fn painted_slots(&self) -> Vec<u32> {
        let alpha = &self.canvas.painting().alpha;
        (0..self.slots.len() as u32).filter(|&s| alpha[self.slots[s as usize].pixel as usize] > 0.0).collect()
    }

    /// The sample value of slot `s` under the current painting (painted or not): the
    /// colour divided by the light, exactly as [`crate::sample::Samples::gather`] computes it.
    #[inline]
    pub(crate) fn value(&self, s: usize) -> [f64; 3] {
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
            for n in crate::images::neighbours4(k, w, w * h) {
                if !seen[n] && self.hit[n] {
                    seen[n] = true;
                    stack.push(n);
                }
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

/// Whether a `width` × `height` painting (named `painting` in messages) belongs to `view`
/// under the size rule of the module docs. Errors name the painting, its size, the camera's
/// aspect and the view's size.
pub fn check_painting_size(view: &PaintView, painting: &str, width: usize, height: usize) -> Result<()> {
    if (width, height) == (view.width, view.height) {
        return Ok(());
    }
    crate::images::check_size(width, height)?;
    crate::sample::check_aspect(&view.scene.camera, width, height, painting)
        .map_err(|e| Error::input(format!("{e} (the view is {}x{})", view.width, view.height)))
}

/// Reads a painting for `view` from a file, checking it against the size rule.
pub fn read_painting_for(view: &PaintView, path: &Path) -> Result<Painting> {
    let p = Painting::read(path)?;
    check_painting_size(view, &path.display().to_string(), p.width, p.height)?;
    Ok(p)
}
