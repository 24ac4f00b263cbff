//! Brush-like noise for the synthetic paintings: soft strokes of slight colour and intensity
//! variation laid over the true shading, and a few short unpainted gaps, so a bundled
//! painting looks (and fits) like a careful hand painting rather than a render.
//!
//! A stroke is a quadratic Bézier curve swept by a round brush. Its coverage at a pixel is
//! a soft edge across the stroke times a taper along it; strokes are laid one over the other
//! like paint, so the multiplicative gain field is
//!
//! $$ m \leftarrow (1 - w)\, m + w\, g_k $$
//!
//! for stroke $k$ with coverage $w$ and per-channel gain $g_k \approx 1$. Faint bristle
//! lines across each stroke add a little texture. Everything is seeded: the same seed gives
//! the same painting on every machine.

use glam::DVec2;

pub use crate::util::SplitMix;

/// How a painting is brushed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brush {
    pub seed: u64,
    /// Number of colour strokes.
    pub strokes: usize,
    /// Stroke half-width range, pixels.
    pub half_width: (f64, f64),
    /// Stroke length range, pixels.
    pub length: (f64, f64),
    /// Standard deviation of a stroke's intensity gain (shared by the channels).
    pub intensity: f64,
    /// Standard deviation of a stroke's per-channel tint.
    pub tint: f64,
    /// Number of unpainted gaps (alpha 0).
    pub gaps: usize,
}

impl Default for Brush {
    /// Sixty strokes 5-12 px wide, ±5% intensity and ±3% tint, four gaps.
    fn default() -> Self {
        Brush {
            seed: 1,
            strokes: 60,
            half_width: (5.0, 12.0),
            length: (30.0, 90.0),
            intensity: 0.05,
            tint: 0.03,
            gaps: 4,
        }
    }
}

/// One stroke: a quadratic Bézier from `p0` through control `p1` to `p2` (pixels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    pub p0: DVec2,
    pub p1: DVec2,
    pub p2: DVec2,
    pub half_width: f64,
    /// Peak coverage, in (0, 1].
    pub opacity: f64,
    pub gain: [f64; 3],
    /// Phase of the bristle lines.
    pub phase: f64,
}

/// Points along a stroke for the distance query.
const SEGMENTS: usize = 24;

impl Stroke {
    fn point(&self, t: f64) -> DVec2 {
        let s = 1.0 - t;
        s * s * self.p0 + 2.0 * s * t * self.p1 + t * t * self.p2
    }

    /// Bounding box, grown by the half-width.
    fn bounds(&self) -> (DVec2, DVec2) {
        let lo = self.p0.min(self.p1).min(self.p2) - DVec2::splat(self.half_width);
        let hi = self.p0.max(self.p1).max(self.p2) + DVec2::splat(self.half_width);
        (lo, hi)
    }

    /// Coverage at point `p` and the signed distance across the stroke, or `None` off it.
    fn coverage(&self, p: DVec2, polyline: &[DVec2; SEGMENTS + 1]) -> Option<(f64, f64)> {
        // Nearest point on the polyline: its parameter t and the distance.
        let (mut best, mut best_t, mut side) = (f64::INFINITY, 0.0, 0.0);
        for k in 0..SEGMENTS {
            let (a, b) = (polyline[k], polyline[k + 1]);
            let ab = b - a;
            // A zero-length segment (a stroke that doubles back) projects onto its start.
            let u =
                if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
            let d = (p - (a + u * ab)).length();
            if d < best {
                best = d;
                best_t = (k as f64 + u) / SEGMENTS as f64;
                side = ab.perp_dot(p - a).signum() * d;
            }
        }
        if best >= self.half_width {
            return None;
        }
        // Soft edge: full inside half the width, smoothstep to zero at the rim.
        let x = ((self.half_width - best) / (0.5 * self.half_width)).clamp(0.0, 1.0);
        let edge = x * x * (3.0 - 2.0 * x);
        // Taper: the brush lands and lifts.
        let taper = (std::f64::consts::PI * best_t).sin().max(0.0).sqrt();
        Some((self.opacity * edge * taper, side))
    }

    fn polyline(&self) -> [DVec2; SEGMENTS + 1] {
        std::array::from_fn(|k| self.point(k as f64 / SEGMENTS as f64))
    }
}

/// The strokes of a painting whose object covers the pixels marked in `object`
/// (`width` × `height`, row 0 at the top): colour strokes first, then the gap strokes.
/// Strokes start on the object and run roughly around its centre, the way one paints a
/// round form. A mask of the wrong size, or an empty one, gets no strokes.
pub fn strokes(brush: &Brush, object: &[bool], width: usize, height: usize) -> (Vec<Stroke>, Vec<Stroke>) {
    let mut rng = SplitMix::new(brush.seed);
    if object.len() != width * height {
        return (Vec::new(), Vec::new());
    }
    let on: Vec<usize> = (0..object.len()).filter(|&k| object[k]).collect();
    if on.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let centre =
        on.iter().fold(DVec2::ZERO, |c, &k| c + DVec2::new((k % width) as f64, (k / width) as f64)) / on.len() as f64;
    let make = |rng: &mut SplitMix, half_width: (f64, f64), length: (f64, f64), gap: bool| {
        let k = on[(rng.uniform() * on.len() as f64) as usize % on.len()];
        let start = DVec2::new((k % width) as f64 + 0.5, (k / width) as f64 + 0.5);
        // Around the centre (tangent to a circle), turned by up to ±35°.
        let radial = start - centre;
        let tangent = if radial.length() > 1e-6 { radial.perp().normalize() } else { DVec2::X };
        let turn = rng.range(-0.6, 0.6);
        let dir = DVec2::from_angle(turn).rotate(tangent);
        let len = rng.range(length.0, length.1);
        let bend = rng.range(-0.25, 0.25) * len;
        let p0 = start - 0.5 * len * dir;
        let p2 = start + 0.5 * len * dir;
        let p1 = start + bend * dir.perp();
        let half_width = rng.range(half_width.0, half_width.1);
        let opacity = if gap { 1.0 } else { rng.range(0.45, 0.9) };
        let g = 1.0 + brush.intensity * rng.normal();
        let gain = [0, 1, 2].map(|_| (g * (1.0 + brush.tint * rng.normal())).max(0.0));
        Stroke { p0, p1, p2, half_width, opacity, gain, phase: rng.range(0.0, std::f64::consts::TAU) }
    };
    let colour = (0..brush.strokes).map(|_| make(&mut rng, brush.half_width, brush.length, false)).collect();
    let gaps = (0..brush.gaps).map(|_| make(&mut rng, (2.0, 3.5), (10.0, 24.0), true)).collect();
    (colour, gaps)
}

/// Calls `f(pixel index, coverage, side)` for every pixel centre of a `width` × `height`
/// image (row 0 at the top) that `stroke` covers.
fn for_each_covered(stroke: &Stroke, width: usize, height: usize, mut f: impl FnMut(usize, f64, f64)) {
    let line = stroke.polyline();
    let (lo, hi) = stroke.bounds();
    let (i0, j0) = (lo.x.floor().max(0.0) as usize, lo.y.floor().max(0.0) as usize);
    let (i1, j1) = ((hi.x.ceil().max(0.0) as usize).min(width), (hi.y.ceil().max(0.0) as usize).min(height));
    for j in j0..j1 {
        for i in i0..i1 {
            let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
            if let Some((w, side)) = stroke.coverage(p, &line) {
                f(j * width + i, w, side);
            }
        }
    }
}

/// The multiplicative gain field of `strokes` over a `width` × `height` image (row 0 at the
/// top), starting from 1.
pub fn gain_field(strokes: &[Stroke], width: usize, height: usize) -> Vec<[f64; 3]> {
    let mut m = vec![[1.0; 3]; width * height];
    for s in strokes {
        for_each_covered(s, width, height, |k, w, side| {
            // Bristle lines: ±1.5% ripples across the stroke, about 2 px apart.
            let bristle = 1.0 + 0.015 * (side * 3.1 + s.phase).sin();
            for (x, g) in m[k].iter_mut().zip(s.gain) {
                *x = (1.0 - w) * *x + w * g * bristle;
            }
        });
    }
    m
}

/// Pixels a gap stroke covers by more than half: the unpainted ones.
pub fn gap_mask(gaps: &[Stroke], width: usize, height: usize) -> Vec<bool> {
    let mut out = vec![false; width * height];
    for s in gaps {
        for_each_covered(s, width, height, |k, w, _| {
            if w > 0.5 {
                out[k] = true;
            }
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeded_and_bounded() {
        let (w, h) = (64, 64);
        let object: Vec<bool> =
            (0..w * h).map(|k| ((k % w) as f64 - 32.0).hypot((k / w) as f64 - 32.0) < 25.0).collect();
        let brush = Brush { strokes: 20, ..Brush::default() };
        let (a, gaps) = strokes(&brush, &object, w, h);
        assert_eq!(a, strokes(&brush, &object, w, h).0, "same seed, same strokes");
        assert_ne!(a, strokes(&Brush { seed: 2, ..brush }, &object, w, h).0);
        let m = gain_field(&a, w, h);
        // A mix of gains near 1 stays near 1: 6 standard deviations of intensity and tint.
        assert!(m.iter().flatten().all(|&g| (g - 1.0).abs() < 0.4), "gain out of range");
        assert!(m.iter().any(|p| p != &[1.0; 3]), "strokes left no mark");
        let holes = gap_mask(&gaps, w, h);
        let n = holes.iter().filter(|&&x| x).count();
        assert!(n > 10 && n < w * h / 10, "{n} gap pixels");
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut rng = SplitMix::new(7);
        let xs: Vec<f64> = (0..20_000).map(|_| rng.normal()).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64;
        assert!(mean.abs() < 0.03 && (var - 1.0).abs() < 0.05, "mean {mean} var {var}");
    }
}
