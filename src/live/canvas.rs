//! The painting canvas: linear RGB with straight alpha, a round brush, an eraser, fill, and
//! an exact undo/redo history.
//!
//! Alpha 0 means "not painted" (DESIGN.md, Colour): such a pixel is not a sample. Any alpha
//! above 0 makes the pixel a sample whose value is its (straight, un-premultiplied) colour,
//! so the soft edge of a stroke on an empty canvas carries the stroke's colour.
//!
//! Blending is "over" in linear light. One stroke never darkens or thickens where its own dabs
//! overlap: each pixel keeps the largest brush coverage it received during the stroke and is
//! blended once from its value before the stroke,
//!
//! $$ a = o \max_k w(d_k),\qquad \alpha' = a + \alpha(1 - a),\qquad
//!    c' = \frac{a\,c_b + \alpha(1 - a)\,c}{\alpha'} $$
//!
//! with brush opacity $o$, dab profile $w$, brush colour $c_b$. The eraser scales alpha by
//! $1 - a$ and snaps values below [`ERASE_SNAP`] to exactly unpainted.

use glam::Vec2;

pub use crate::images::Painting;
use crate::error::{Error, Result};
use crate::images::check_size;

/// Alpha below this after erasing becomes exactly 0 (unpainted): one 8-bit step would
/// otherwise leave invisible samples behind.
pub const ERASE_SNAP: f32 = 1.0 / 512.0;
/// Most undo steps kept.
pub const HISTORY: usize = 200;

/// An unpainted (fully transparent) painting.
pub fn blank(width: usize, height: usize) -> Result<Painting> {
    check_size(width, height)?;
    let n = width * height;
    Ok(Painting { width, height, pixels: vec![[0.0; 3]; n], alpha: vec![0.0; n], saturated: vec![false; n] })
}

/// One pixel of a painting: linear RGB and straight alpha, and whether a file's value was
/// clipped (what [`Painting::saturated`] keeps; paint from the brush never is).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Texel {
    pub rgba: [f32; 4],
    pub saturated: bool,
}

fn texel(p: &Painting, k: usize) -> Texel {
    let c = p.pixels[k];
    Texel { rgba: [c[0], c[1], c[2], p.alpha[k]], saturated: p.saturated[k] }
}

fn set_texel(p: &mut Painting, k: usize, t: Texel) {
    p.pixels[k] = [t.rgba[0], t.rgba[1], t.rgba[2]];
    p.alpha[k] = t.rgba[3];
    p.saturated[k] = t.saturated;
}

/// A round brush. The same settings erase when `erase` is set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brush {
    /// Linear RGB.
    pub color: [f32; 3],
    /// Radius in pixels.
    pub radius: f32,
    /// The fraction of the radius painted at full strength; the rest falls off smoothly.
    pub hardness: f32,
    /// Strength of one stroke, 0..=1.
    pub opacity: f32,
    /// Remove paint instead of adding it.
    pub erase: bool,
}

impl Default for Brush {
    fn default() -> Self {
        Brush { color: [0.95, 0.88, 0.75], radius: 16.0, hardness: 0.7, opacity: 1.0, erase: false }
    }
}

impl Brush {
    /// Coverage $w(d) \in [0, 1]$ of a pixel whose centre is `d` pixels from the dab's centre:
    /// 1 inside `hardness × radius`, a smoothstep down to 0 at the radius.
    pub fn coverage(&self, d: f32) -> f32 {
        let r = self.radius.max(0.5);
        let inner = self.hardness.clamp(0.0, 1.0) * r;
        if d <= inner {
            1.0
        } else if d >= r {
            0.0
        } else {
            let t = (r - d) / (r - inner);
            t * t * (3.0 - 2.0 * t)
        }
    }
}

/// Blends `a` of the brush into pixel `t` (see the module docs).
fn blend(t: Texel, brush: &Brush, a: f32) -> Texel {
    if a <= 0.0 {
        return t;
    }
    let p = t.rgba;
    if brush.erase {
        let alpha = p[3] * (1.0 - a);
        return if alpha < ERASE_SNAP { Texel::default() } else { Texel { rgba: [p[0], p[1], p[2], alpha], ..t } };
    }
    let rest = p[3] * (1.0 - a);
    let alpha = a + rest;
    let c = brush.color;
    let rgba =
        [(a * c[0] + rest * p[0]) / alpha, (a * c[1] + rest * p[1]) / alpha, (a * c[2] + rest * p[2]) / alpha, alpha];
    Texel { rgba, saturated: false }
}

/// One undoable change: the pixels it touched, before and after.
#[derive(Clone, Debug, Default)]
struct Edit {
    pixels: Vec<u32>,
    before: Vec<Texel>,
    after: Vec<Texel>,
}

/// The stroke in progress.
struct Active {
    brush: Brush,
    last: Option<Vec2>,
    /// Per touched pixel: its index, value before the stroke, largest coverage so far.
    touched: Vec<u32>,
    before: Vec<Texel>,
    coverage: Vec<f32>,
}

/// A rectangle of canvas pixels `[x0, x1) × [y0, y1)` (what changed since the display last
/// looked; window rectangles are the viewer's `WindowRect`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CanvasRect {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl CanvasRect {
    fn union(self, o: CanvasRect) -> CanvasRect {
        CanvasRect { x0: self.x0.min(o.x0), y0: self.y0.min(o.y0), x1: self.x1.max(o.x1), y1: self.y1.max(o.y1) }
    }
}

/// A painting with its history. Every change goes through it, so it knows which pixels
/// changed (for display) and whether the set of painted pixels changed (for the prepared
/// system, which depends on that set only).
pub struct Canvas {
    painting: Painting,
    undo: Vec<Edit>,
    redo: Vec<Edit>,
    active: Option<Active>,
    /// Per pixel: its index in the active stroke's lists, or `u32::MAX`.
    index: Vec<u32>,
    mask_version: u64,
    version: u64,
    dirty: Option<CanvasRect>,
}

impl Canvas {
    /// An unpainted canvas.
    pub fn new(width: usize, height: usize) -> Result<Canvas> {
        Ok(Canvas::from_painting(blank(width, height)?))
    }

    /// A canvas holding `painting`, with an empty history.
    pub fn from_painting(painting: Painting) -> Canvas {
        let n = painting.pixels.len();
        let (w, h) = (painting.width, painting.height);
        debug_assert!(painting.alpha.len() == n && painting.saturated.len() == n);
        Canvas {
            painting,
            undo: Vec::new(),
            redo: Vec::new(),
            active: None,
            index: vec![u32::MAX; n],
            mask_version: 0,
            version: 0,
            dirty: Some(CanvasRect { x0: 0, y0: 0, x1: w, y1: h }),
        }
    }

    pub fn painting(&self) -> &Painting {
        &self.painting
    }

    pub fn width(&self) -> usize {
        self.painting.width
    }

    pub fn height(&self) -> usize {
        self.painting.height
    }

    /// Changes whenever any pixel changes.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Changes whenever some pixel becomes painted or unpainted.
    pub fn mask_version(&self) -> u64 {
        self.mask_version
    }

    /// The rectangle changed since the last call, if any.
    pub fn take_dirty(&mut self) -> Option<CanvasRect> {
        self.dirty.take()
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Whether a stroke is in progress.
    pub fn stroking(&self) -> bool {
        self.active.is_some()
    }

    /// Starts a stroke (ending any stroke in progress).
    pub fn begin_stroke(&mut self, brush: Brush) {
        self.end_stroke();
        self.active = Some(Active { brush, last: None, touched: Vec::new(), before: Vec::new(), coverage: Vec::new() });
    }

    /// Extends the stroke to `p` (pixels, x right, y down; pixel $(i, j)$ has its centre at
    /// $(i + 0.5, j + 0.5)$): dabs every fifth of the radius along the segment from the last
    /// point. Without a stroke in progress, nothing happens.
    pub fn stroke_to(&mut self, p: Vec2) {
        let Some(active) = self.active.as_ref() else { return };
        let spacing = (active.brush.radius * 0.2).max(0.5);
        let from = active.last;
        let dabs: Vec<Vec2> = match from {
            None => vec![p],
            Some(a) => {
                let n = ((p - a).length() / spacing).ceil().max(1.0) as usize;
                (1..=n).map(|k| a + (p - a) * (k as f32 / n as f32)).collect()
            }
        };
        for d in dabs {
            self.dab(d);
        }
        if let Some(a) = self.active.as_mut() {
            a.last = Some(p);
        }
    }

    fn dab(&mut self, c: Vec2) {
        let (w, h) = (self.painting.width, self.painting.height);
        let Some(active) = self.active.as_mut() else { return };
        let brush = active.brush;
        let r = brush.radius.max(0.5);
        let x0 = ((c.x - r - 0.5).floor().max(0.0)) as usize;
        let y0 = ((c.y - r - 0.5).floor().max(0.0)) as usize;
        let x1 = ((c.x + r + 0.5).ceil().max(0.0) as usize).min(w);
        let y1 = ((c.y + r + 0.5).ceil().max(0.0) as usize).min(h);
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        let mut changed_mask = false;
        for j in y0..y1 {
            for i in x0..x1 {
                let d = (Vec2::new(i as f32 + 0.5, j as f32 + 0.5) - c).length();
                let cov = brush.coverage(d);
                if cov <= 0.0 {
                    continue;
                }
                let k = j * w + i;
                let slot = match self.index[k] {
                    u32::MAX => {
                        let s = active.touched.len();
                        active.touched.push(k as u32);
                        active.before.push(texel(&self.painting, k));
                        active.coverage.push(0.0);
                        self.index[k] = s as u32;
                        s
                    }
                    s => s as usize,
                };
                if cov <= active.coverage[slot] {
                    continue;
                }
                active.coverage[slot] = cov;
                let old = self.painting.alpha[k];
                let new = blend(active.before[slot], &brush, brush.opacity.clamp(0.0, 1.0) * cov);
                changed_mask |= (old > 0.0) != (new.rgba[3] > 0.0);
                set_texel(&mut self.painting, k, new);
            }
        }
        self.touch(CanvasRect { x0, y0, x1, y1 }, changed_mask);
    }

    /// Ends the stroke in progress and records it for undo.
    pub fn end_stroke(&mut self) {
        let Some(active) = self.active.take() else { return };
        for &k in &active.touched {
            self.index[k as usize] = u32::MAX;
        }
        let after = active.touched.iter().map(|&k| texel(&self.painting, k as usize)).collect();
        self.record(Edit { pixels: active.touched, before: active.before, after });
    }

    /// A whole stroke: begin, the points, end.
    pub fn stroke(&mut self, brush: Brush, points: &[Vec2]) {
        self.begin_stroke(brush);
        for &p in points {
            self.stroke_to(p);
        }
        self.end_stroke();
    }

    /// Applies the brush at full coverage (its opacity still applies) to `pixels`, as one
    /// undoable edit: the fill tool, or "erase all" with an erasing brush.
    pub fn fill(&mut self, brush: Brush, pixels: &[u32]) {
        self.end_stroke();
        let a = brush.opacity.clamp(0.0, 1.0);
        let new: Vec<Texel> = pixels.iter().map(|&k| blend(texel(&self.painting, k as usize), &brush, a)).collect();
        self.replace(pixels, new);
    }

    /// Replaces the whole painting (same size), as one undoable edit.
    pub fn set_painting(&mut self, painting: &Painting) -> Result<()> {
        let n = painting.width * painting.height;
        if painting.pixels.len() != n || painting.alpha.len() != n || painting.saturated.len() != n {
            return Err(Error::input("the painting's pixel, alpha and saturation lists do not match its size"));
        }
        if painting.width != self.width() || painting.height != self.height() {
            return Err(Error::input(format!(
                "a {}x{} painting does not fit a {}x{} canvas",
                painting.width,
                painting.height,
                self.width(),
                self.height()
            )));
        }
        self.end_stroke();
        let pixels: Vec<u32> = (0..n as u32).collect();
        let values = (0..n).map(|k| texel(painting, k)).collect();
        self.replace(&pixels, values);
        Ok(())
    }

    /// Sets `pixels` to `values` as one undoable edit (pixels that do not change are left
    /// out of the record).
    fn replace(&mut self, pixels: &[u32], values: Vec<Texel>) {
        let mut edit = Edit::default();
        for (&k, v) in pixels.iter().zip(values) {
            let old = texel(&self.painting, k as usize);
            if old != v {
                edit.pixels.push(k);
                edit.before.push(old);
                edit.after.push(v);
            }
        }
        if edit.pixels.is_empty() {
            return;
        }
        self.apply(&edit.pixels, &edit.after);
        self.record(edit);
    }

    fn record(&mut self, edit: Edit) {
        if edit.pixels.is_empty() {
            return;
        }
        self.redo.clear();
        self.undo.push(edit);
        if self.undo.len() > HISTORY {
            self.undo.remove(0);
        }
    }

    /// Writes values to pixels, keeping the versions and the dirty rectangle.
    fn apply(&mut self, pixels: &[u32], values: &[Texel]) {
        let w = self.painting.width;
        let mut changed_mask = false;
        let mut rect: Option<CanvasRect> = None;
        for (&k, v) in pixels.iter().zip(values) {
            let k = k as usize;
            changed_mask |= (self.painting.alpha[k] > 0.0) != (v.rgba[3] > 0.0);
            set_texel(&mut self.painting, k, *v);
            let (i, j) = (k % w, k / w);
            let r = CanvasRect { x0: i, y0: j, x1: i + 1, y1: j + 1 };
            rect = Some(rect.map_or(r, |o| o.union(r)));
        }
        if let Some(r) = rect {
            self.touch(r, changed_mask);
        }
    }

    fn touch(&mut self, rect: CanvasRect, changed_mask: bool) {
        self.version += 1;
        if changed_mask {
            self.mask_version += 1;
        }
        self.dirty = Some(self.dirty.map_or(rect, |d| d.union(rect)));
    }

    /// Undoes the last edit (ending a stroke in progress first). `false` when there is none.
    pub fn undo(&mut self) -> bool {
        self.end_stroke();
        let Some(edit) = self.undo.pop() else { return false };
        self.apply(&edit.pixels, &edit.before);
        self.redo.push(edit);
        true
    }

    /// Redoes the last undone edit. `false` when there is none.
    pub fn redo(&mut self) -> bool {
        self.end_stroke();
        let Some(edit) = self.redo.pop() else { return false };
        self.apply(&edit.pixels, &edit.after);
        self.undo.push(edit);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brush(radius: f32) -> Brush {
        Brush { color: [1.0, 0.5, 0.25], radius, hardness: 1.0, opacity: 1.0, erase: false }
    }

    #[test]
    fn a_hard_dab_paints_a_disc_exactly_the_brush_colour() {
        let mut c = Canvas::new(20, 20).unwrap();
        c.stroke(brush(3.0), &[Vec2::new(10.0, 10.0)]);
        let p = c.painting();
        // Centres within 3 px of (10, 10): pixel (9, 9) has its centre at (9.5, 9.5).
        assert_eq!((p.pixels[9 * 20 + 9], p.alpha[9 * 20 + 9]), ([1.0, 0.5, 0.25], 1.0));
        assert_eq!(p.alpha[10 * 20 + 13], 0.0, "centre (13.5, 10.5) is 3.54 px away");
        let n = p.alpha.iter().filter(|&&a| a > 0.0).count();
        assert!((24..=32).contains(&n), "about pi r^2 = 28 pixels, got {n}");
    }

    #[test]
    fn overlapping_dabs_of_one_stroke_do_not_accumulate_opacity() {
        let mut soft = brush(4.0);
        soft.opacity = 0.5;
        let mut c = Canvas::new(30, 10).unwrap();
        c.stroke(soft, &[Vec2::new(5.0, 5.0), Vec2::new(25.0, 5.0)]);
        let a = c.painting().alpha[5 * 30 + 15];
        assert!((a - 0.5).abs() < 1e-6, "alpha {a}");
        // A second stroke does accumulate.
        c.stroke(soft, &[Vec2::new(5.0, 5.0), Vec2::new(25.0, 5.0)]);
        assert!((c.painting().alpha[5 * 30 + 15] - 0.75).abs() < 1e-6);
    }

    #[test]
    fn erasing_returns_to_exactly_unpainted_and_undo_redo_are_exact() {
        let mut c = Canvas::new(16, 16).unwrap();
        let empty = c.painting().clone();
        c.stroke(brush(5.0), &[Vec2::new(4.0, 4.0), Vec2::new(12.0, 12.0)]);
        let painted = c.painting().clone();
        let v = c.mask_version();
        let mut eraser = brush(8.0);
        eraser.erase = true;
        c.stroke(eraser, &[Vec2::new(8.0, 8.0)]);
        assert!(c.mask_version() > v);
        assert_eq!((c.painting().pixels[8 * 16 + 8], c.painting().alpha[8 * 16 + 8]), ([0.0; 3], 0.0));
        assert!(c.undo());
        assert_eq!(c.painting(), &painted);
        assert!(c.undo());
        assert_eq!(c.painting(), &empty);
        assert!(!c.undo());
        assert!(c.redo() && c.redo() && !c.redo());
        assert_eq!(c.painting().alpha[8 * 16 + 8], 0.0);
    }

    #[test]
    fn a_painting_round_trips_through_exr_exactly_and_undo_keeps_saturation_flags() {
        let dir = tempfile::tempdir().unwrap();
        let mut c = Canvas::new(9, 7).unwrap();
        let mut b = brush(3.0);
        b.hardness = 0.2;
        c.stroke(b, &[Vec2::new(4.0, 3.0)]);
        let exr = dir.path().join("p.exr");
        c.painting().write(&exr).unwrap();
        let back = Painting::read(&exr).unwrap();
        for k in 0..back.pixels.len() {
            assert_eq!(back.alpha[k], c.painting().alpha[k]);
            for q in 0..3 {
                let (x, y) = (back.pixels[k][q], c.painting().pixels[k][q]);
                assert!((x - y).abs() <= 1e-6 * y.abs(), "{x} vs {y}: premultiplied storage rounds");
            }
        }
        // A loaded painting's saturation flags survive a stroke and its undo.
        let mut loaded = blank(9, 7).unwrap();
        loaded.pixels[0] = [1.0; 3];
        loaded.alpha[0] = 1.0;
        loaded.saturated[0] = true;
        c.set_painting(&loaded).unwrap();
        c.stroke(brush(20.0), &[Vec2::new(0.0, 0.0)]);
        assert!(!c.painting().saturated[0], "paint is never clipped");
        assert!(c.undo());
        assert_eq!(c.painting(), &loaded);
    }
}
