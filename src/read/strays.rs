//! Stray strokes (issue 11): paint that does not belong to the shading, repainted.
//!
//! People paint over the outline, drop a white or black accent, try a colour and leave it.
//! Fitted as samples, such strokes go into the tables like shading does: eight strokes across
//! the outline of a sphere painting take the held-out error from 0.026 to 0.106, and a white
//! stroke over a sharp highlight's neighbourhood makes the highlight 1.3× too wide and bright
//! (BENCHMARKS.md, faults). A robust loss at solve time (`Prepared::solve_robust`) halves it but
//! costs clean paintings (its mapping choice on trimmed errors), so strays are instead found
//! once, while the painting is read, and repainted with the physical proxy fitted to the
//! rest ([`fill`]: left out, they would leave holes where the tables extrapolate).
//!
//! A sample is a stray when the factored least-squares fit of the painting (thesis eq. 3.9,
//! offset mapping; with the light prior when the painting is headlit, as `fit` has it:
//! without, that fit of a headlit painting missed its median sample by a log ratio of about
//! 1 and no stroke stood out; and again with it when the free fit collapses, [`COLLAPSED`])
//! misses it by far more than it misses the painting as a whole:
//! its largest per-channel log ratio $|\ln((y + \epsilon) / (f + \epsilon))|$ (the floor
//! $\epsilon$ is [`FLOOR`] of the brightest value) exceeds [`SPREAD`] robust standard
//! deviations of all samples' (from their median absolute value) and at least
//! [`MIN_RATIO`]. Strokes are connected and their rims blend into the shading, so the set
//! grows into neighbours missed by half as much, up to three pixels. Strays pull the fit towards themselves, so the search
//! runs twice, the second time without the first's strays. A painting whose
//! misses gather in blobs smaller than 0.2% of its samples has none there (a render's
//! misfit along a highlight's or a rim crescent's edge) unless the blob (at least 8 pixels)
//! reaches the outline of a painting not lit from the eye: the end of a stroke painted across
//! it. A bright blob
//! at the view's mirror point is its highlight ([`keep_strokes`]); one whose misses
//! are more than [`MAX_FRACTION`] of its samples does not have strays: it disagrees
//! with itself (several materials, another light), and nothing is repainted (the fit's
//! diagnostics say what to do).
//!
//! In flat tones a painted level is a bound, not a value ([`super::tones`]), and a stroke one
//! level off the shading under it hides in the log ratio behind the steps' own error. So in a
//! toned view that has strays, a sample is one too when the fit lies outside its tone's
//! interval by more than [`TONE_TAIL`] times the view's 99th percentile of that distance
//! (in the interval's widths, at least [`MIN_OFF_TONE`]; [`off_tone`]). A toned stroke's rim
//! is one tone off, under both tests, so a toned view's strays widen by [`TONED_RIM`]; and
//! they are then left out, not repainted, and the painting read again without them
//! ([`super::Reader::read`]).

use super::tones::Toned;
use super::proxy;
use crate::sample::{PaintedView, Samples};
use crate::error::Result;
use crate::images::{components, neighbours8};
use crate::factor::{defaults, Mapping, Settings};

/// Robust standard deviations a stray's miss exceeds.
pub const SPREAD: f64 = 5.0;
/// The smallest miss (log ratio, about ±40%) that makes a stray, whatever the spread.
pub const MIN_RATIO: f64 = 0.35;
/// Most of the samples that may be strays.
pub const MAX_FRACTION: f64 = 0.1;
/// The floor $\epsilon$ of the log ratio, as a fraction of the painting's brightest value: a
/// shadow's small misses (a terminator a pixel off) are not strokes.
pub const FLOOR: f64 = 0.1;
/// The spread (robust standard deviation of the log ratios) beyond which the search's fit
/// has collapsed rather than met strays, and is fitted again with the light prior
/// ([`Settings::with_light_prior`], as a headlit painting's is). A white stroke in the
/// shadow, at the terminator, drew the free fit's p(θ_l) up ×40 there and q(θ_h) down to
/// 2e-10 at grazing: it missed the median sample by 0.43, nothing stood out, and no stray was
/// found (brush seed 20, Blinn-Phong 8 and Ward: held out 0.40 and 0.57; with the prior
/// 0.0097 and 0.024, as with the strays known). The other models' first fits there spread
/// 0.03–0.14, the collapsed ones 0.42–0.64, and no search over brush seeds 1–12 and 17–24
/// (every fault) but seed 20's spread beyond 0.3.
pub const COLLAPSED: f64 = 0.3;
/// How far (pixels) a stray grows into its neighbours: a brush's soft rim, not a region.
const GROWTH: usize = 3;
/// How far (pixels) a toned view's strays widen beyond their growth, whatever the fit
/// misses there. Posterized, a stroke's soft rim (the stroke blended with the shading under
/// it) lands one tone off the shading, a miss under both tests that the steps' own error
/// hides: after the search, 6 flat tones with eight strokes (seed 1) kept 50–120 stroke
/// pixels of a thousand, nearly all one pixel from a found stray. Those few pixels cost most
/// of what strays cost a toned painting: held out with the found strays and the strokes known
/// 0.0174, with only the found ones 0.0659 (nine models' median, seeds 1–4; strays alone
/// 0.0048, tones alone 0.026). Not about the mirror point ([`HIGHLIGHT_DEG`]): widened into a
/// sharp highlight's few pixels, a stroke beside it takes the material's highlight away.
/// Two pixels: every fault, seeds 1–24, 0.0487 against one's 0.0477 (BENCHMARKS.md,
/// "Strokes in flat tones"). Not under a headlight, where strays are not left out
/// ([`super::Reader::read`]).
const TONED_RIM: usize = 1;
/// A neighbour joins a stray when the fit misses it by this fraction of the threshold.
const RIM: f64 = 0.5;
/// The smallest stroke, as a fraction of a view's samples, and in pixels: the second is the
/// smallest end of a stroke across the outline ([`keep_strokes`]).
const MIN_STROKE: f64 = 0.002;
const MIN_STROKE_PIXELS: usize = 8;
/// How far (pixels) a stroke's end on the object may lie from the background: the silhouette
/// band left out of the samples ([`crate::sample::Erosion`]) and a soft rim.
const OUTLINE_REACH: usize = 3;
/// Searches: each refits without the strays found so far.
const PASSES: usize = 2;
/// A toned view's samples are strays too when the fit lies outside their tones by more than
/// this many times the view's 99th percentile of that distance, and by at least
/// [`MIN_OFF_TONE`] of the tone's width ([`off_tone`]). A stroke one tone off the shading (a
/// black stroke over a dim rim, a colour near the material's) changes a pixel by a few
/// percent of the peak, under the log ratio's floor, and the steps' own error hides the
/// rest. After the first pass, in the faults study's painting with every fault (seed 11),
/// the missed stroke pixels lie a median 0.27–0.57 tone widths outside their tones for seven
/// of the nine models, while the other pixels' 99th percentile is 0.02–0.47. Only in views
/// that have strays (found by the log ratio): a view without strokes has only the tones'
/// own interpolation error along the outline, which this rule would take for strokes. Not
/// about the mirror point ([`HIGHLIGHT_DEG`]), where a glossy highlight a few degrees off
/// the fit's is a tone off on both sides. The factor sits above the other pixels' tail so
/// that a stroke is a pixel the tones cannot explain; the study that chose 1.2 is in
/// docs/notes/history.md, "Source comments".
const TONE_TAIL: f64 = 1.2;
/// The least distance outside a tone (in its widths) that makes a toned sample a stray.
const MIN_OFF_TONE: f64 = 0.2;
/// A bright blob this close (degrees of $\theta_h$) to the view's mirror point is its
/// highlight, not a stroke: where a light within the registration's reach
/// ([`super::register::RADIUS_DEG`]) puts it, since $h$ turns half as far as $l$.
const HIGHLIGHT_DEG: f64 = super::register::RADIUS_DEG / 2.0;

/// A pixel's tone: per channel, the linear interval its true value lies in.
type Bounds = [[f64; 2]; 3];

/// The strays found.
#[derive(Clone, Debug, PartialEq)]
pub struct Strays {
    /// Their pixels, per view.
    pub per_view: Vec<Vec<usize>>,
    /// Whether some view is in flat tones and not headlit (its strays are then left out, and
    /// the painting read again without them: [`super::Reader::read`]).
    pub toned: bool,
    /// Whether they were left out rather than repainted.
    pub left_out: bool,
}

impl Strays {
    /// The notes a user reads, one per view with strays.
    pub fn notes(&self, views: &[PaintedView]) -> Vec<crate::note::Note> {
        views
            .iter()
            .zip(&self.per_view)
            .filter(|(_, p)| !p.is_empty())
            .map(|(v, p)| crate::note::Note::Strays { painting: v.name.clone(), pixels: p.len(), left_out: self.left_out })
            .collect()
    }
}

/// Finds the strays of `views` (module doc) and repaints them; `None`, with nothing changed,
/// when there are none or too many to be strays. `toned[v]`, when given, is view v's flat
/// tones ([`super::tones::smooth`]). Only a single view is searched: the joint
/// fit of several views under different lights misses renders of physical materials by up
/// to ×2.9 in places (a GGX lobe under three lights, which no product of (l, h, v) tables
/// holds), as much as it misses paint.
pub fn repaint(views: &mut [PaintedView], settings: &Settings, toned: &[Option<&Toned>]) -> Result<Option<Strays>> {
    if views.len() != 1 {
        return Ok(None);
    }
    let intervals = tone_intervals(views, toned);
    let mut found: Vec<Vec<usize>> = vec![Vec::new(); views.len()];
    let mut lit_aside = true;
    for _ in 0..PASSES {
        let samples = Samples::gather(views)?;
        let n = samples.len();
        if n == 0 {
            break;
        }
        let pass = Pass::fit(views, samples, settings, &intervals)?;
        lit_aside &= !pass.headlit;
        let strays = pass.strays(&intervals, &found);
        let total: usize = strays.iter().map(Vec::len).sum();
        if total == 0 {
            break;
        }
        let before: usize = found.iter().map(Vec::len).sum();
        if (total + before) as f64 > MAX_FRACTION * (n + before) as f64 {
            if before == 0 {
                return Ok(None);
            }
            break;
        }
        for ((view, s), f) in views.iter_mut().zip(&strays).zip(found.iter_mut()) {
            for &k in s {
                view.geometry.usable[k] = false;
            }
            f.extend_from_slice(s);
        }
    }
    if found.iter().all(Vec::is_empty) {
        return Ok(None);
    }
    fill(views, &found)?;
    Ok(Some(Strays { per_view: found, toned: lit_aside && intervals.iter().any(Option::is_some), left_out: false }))
}

/// Per view with flat tones (`toned[v]`), per pixel: its tone's interval per channel.
fn tone_intervals(views: &[PaintedView], toned: &[Option<&Toned>]) -> Vec<Option<Vec<Option<Bounds>>>> {
    views
        .iter()
        .enumerate()
        .map(|(v, view)| {
            toned.get(v).copied().flatten().map(|t| {
                let mut at = vec![None; view.geometry.pixels.len()];
                for &(k, b) in &t.bounds {
                    at[k] = Some(b);
                }
                at
            })
        })
        .collect()
}

/// One pass of the search: the samples of the views as they stand, and how far the search's
/// fit misses each.
struct Pass<'a> {
    views: &'a [PaintedView],
    samples: Samples,
    headlit: bool,
    /// Per sample, the fit's largest per-channel log ratio, signed ([`search_fit`]).
    signed: Vec<f64>,
    /// Per sample, its absolute value.
    miss: Vec<f64>,
    /// Per sample of a toned view, how far the fit lies outside its tone ([`off_tone`]).
    off: Vec<f64>,
    /// The miss that makes a stray.
    threshold: f64,
}

impl<'a> Pass<'a> {
    /// Fits `samples` (gathered from `views`) as the search does, once more with the light
    /// prior when the fit collapses.
    fn fit(views: &'a [PaintedView], samples: Samples, settings: &Settings, intervals: &[Option<Vec<Option<Bounds>>>]) -> Result<Pass<'a>> {
        let n = samples.len();
        let headlit = samples.pattern.headlit();
        // As the fit has it: a headlit painting's light factor drawn to its physical shape.
        let search = settings.for_pattern(&samples.pattern);
        let peak = samples.values.iter().flatten().copied().fold(0.0, f64::max);
        let eps = FLOOR * peak.max(1e-12);
        let (mut predicted, mut signed, mut sigma) = search_fit(&samples, &search, eps)?;
        // A collapsed fit ([`COLLAPSED`]) is searched again with the light prior.
        if sigma > COLLAPSED && search.light_prior.is_none() {
            (predicted, signed, sigma) = search_fit(&samples, &settings.with_light_prior(defaults::DAMP_HEADLIT, defaults::LIGHT_FLOOR), eps)?;
        }
        let miss: Vec<f64> = signed.iter().map(|r| r.abs()).collect();
        // Only toned views read it ([`TONE_TAIL`]).
        let toned_views = intervals.iter().any(Option::is_some);
        let off: Vec<f64> = (0..if toned_views { n } else { 0 })
            .map(|i| {
                let (v, k) = samples.origin[i];
                let bounds = intervals[v].as_ref().and_then(|at| at[k]);
                let light = views[v].geometry.pixels[k].as_ref().map(|p| p.light);
                match (bounds, light) {
                    (Some(b), Some(light)) => off_tone(&predicted[i], light, &b),
                    _ => 0.0,
                }
            })
            .collect();
        let threshold = (SPREAD * sigma).max(MIN_RATIO);
        Ok(Pass { views, samples, headlit, signed, miss, off, threshold })
    }

    /// Per view: the strays this pass finds, with the neighbours they grow into (`found`: the
    /// earlier passes').
    fn strays(&self, intervals: &[Option<Vec<Option<Bounds>>>], found: &[Vec<usize>]) -> Vec<Vec<usize>> {
        let mut offset = 0;
        (0..self.views.len())
            .map(|v| {
                let range = offset..offset + self.samples.per_view[v];
                offset = range.end;
                self.view_strays(v, range, intervals[v].is_some(), !found[v].is_empty())
            })
            .collect()
    }

    /// The strays of view `v`, whose samples are `range`; `toned`: the view is in flat tones;
    /// `found_before`: an earlier pass found strays in it.
    fn view_strays(&self, v: usize, range: std::ops::Range<usize>, toned: bool, found_before: bool) -> Vec<usize> {
        let (samples, view, headlit) = (&self.samples, &self.views[v], self.headlit);
        let count = range.len();
        let (w, h) = (view.geometry.width, view.geometry.height);
        // Per pixel: its miss, whether it is brighter than the fit, and its $\theta_h$.
        let mut at = vec![f64::NAN; w * h];
        let mut brighter = vec![false; w * h];
        let mut theta_h = vec![f64::NAN; w * h];
        for i in range.clone() {
            let k = samples.origin[i].1;
            at[k] = self.miss[i];
            brighter[k] = self.signed[i] > 0.0;
            theta_h[k] = samples.pattern.queries[i].h().z.clamp(-1.0, 1.0).acos().to_degrees();
        }
        let mut stray: Vec<bool> = at.iter().map(|&m| m > self.threshold).collect();
        let least = (MIN_STROKE * count as f64).max(MIN_STROKE_PIXELS as f64) as usize;
        // Not under a headlight: there the outline is the terminator, where the shading
        // falls to black all round and the fit's misses are the limb's as much as any
        // stroke's. With its blobs there repainted, a headlit Oren-Nayar sphere with every
        // fault (128², seed 11) was read to a held-out error of 0.62 and a light sweep of
        // 0.94, its fit taking the inverted mapping (0.34 and under 0.5 without:
        // tests/headlit.rs).
        let outline = (!headlit).then_some(&view.geometry);
        // In flat tones, once the view has strays: the samples whose tones the fit misses
        // far more than the rest ([`TONE_TAIL`]).
        let has_strays = || {
            let mut kept = stray.clone();
            keep_strokes(&mut kept, least, outline, &at, &brighter, &theta_h, w);
            found_before || kept.contains(&true)
        };
        if count > 0 && toned && has_strays() {
            let mut scratch = self.off[range.clone()].to_vec();
            let p99 = *scratch.select_nth_unstable_by(count * 99 / 100, f64::total_cmp).1;
            let limit = (TONE_TAIL * p99).max(MIN_OFF_TONE);
            // Not about the view's mirror point, where a highlight a few degrees off the
            // fit's is a tone or two off on both sides ([`keep_strokes`]).
            let mirror = mirror_point(&theta_h);
            for i in range {
                let k = samples.origin[i].1;
                if self.off[i] > limit && theta_h[k] > mirror + HIGHLIGHT_DEG {
                    stray[k] = true;
                }
            }
        }
        keep_strokes(&mut stray, least, outline, &at, &brighter, &theta_h, w);
        grow(&mut stray, &at, w, RIM * self.threshold);
        if toned && !headlit {
            widen(&mut stray, &theta_h, w);
        }
        (0..w * h).filter(|&k| stray[k]).collect()
    }
}

/// The stray search's fit of `samples` under `settings` (offset mapping): its prediction,
/// per sample the largest per-channel log ratio of value to fit, signed (positive: brighter
/// than the fit; `eps` the floor, [`FLOOR`] of the brightest value), and the robust
/// standard deviation of those ratios (from their median absolute value).
fn search_fit(samples: &Samples, settings: &Settings, eps: f64) -> Result<(Vec<[f64; 3]>, Vec<f64>, f64)> {
    // Per channel, as the thesis fits: strays are found by their brightness in any channel,
    // and one system prepares in half the time of the coupled pair.
    let prepared = crate::factor::prepare(&samples.pattern, &settings.luminance())?;
    let fit = prepared.solve(&samples.values, Mapping::Offset(None))?;
    let predicted = prepared.predict(&fit.tables, &fit.map);
    let signed: Vec<f64> = samples
        .values
        .iter()
        .zip(&predicted)
        .map(|(y, f)| (0..3).map(|c| ((y[c].max(0.0) + eps) / (f[c].max(0.0) + eps)).ln()).fold(0.0, |m: f64, r| if r.abs() > m.abs() { r } else { m }))
        .collect();
    let mut sorted: Vec<f64> = signed.iter().map(|r| r.abs()).collect();
    let mid = sorted.len() / 2;
    let (_, median, _) = sorted.select_nth_unstable_by(mid, f64::total_cmp);
    let sigma = *median / 0.6745;
    Ok((predicted, signed, sigma))
}

/// How far `fit` (a sample's predicted values, per unit of `light`) lies outside the tone
/// intervals `bounds` (linear, as painted), in each interval's widths: the largest channel's.
fn off_tone(fit: &[f64; 3], light: [f64; 3], bounds: &Bounds) -> f64 {
    (0..3)
        .map(|c| {
            let [lo, hi] = bounds[c];
            super::tones::distance_outside(fit[c].max(0.0) * light[c], bounds[c]) / (hi - lo).max(1e-9)
        })
        .fold(0.0, f64::max)
}

/// Clears the blobs of `stray` (a mask `w` to a row) that are not strokes. A stroke is a blob
/// of at least `least` pixels; a render's misfit is a few pixels along a highlight's or a
/// crescent's edge. A smaller blob of at least [`MIN_STROKE_PIXELS`] that reaches the outline
/// of `outline` ([`reaches_outline`]) is a stroke too: people paint across the outline, and
/// what lands on the object is often only a stroke's end, too small alone to tell from a
/// render's misfit but not shaped like one (a misfit follows the shading's edges, not the
/// outline). The measurements are in docs/notes/history.md, "Source comments".
/// And a blob that is the view's highlight is none: brighter than the fit
/// where it misses it most (`at`, `brighter`), and reaching within [`HIGHLIGHT_DEG`] of the
/// view's smallest $\theta_h$ (`theta_h`, NaN off the samples).
/// The fit misses a sharp highlight in flat tones by far more than the rest (the smooth
/// tables cannot hold a plateau a few pixels wide); repainted, it is gone, and the material
/// with it: a GGX 0.2 sphere painted with every fault lost its highlight at three of eight
/// brush seeds (BENCHMARKS.md; held-out 0.96–1.03 then; with it kept, and the light judged
/// on the tones, 0.32, 0.23 and 0.46). A dark stroke over the highlight is still a stray,
/// and so is a bright one far from it.
fn keep_strokes(stray: &mut [bool], least: usize, outline: Option<&crate::sample::Geometry>, at: &[f64], brighter: &[bool], theta_h: &[f64], w: usize) {
    let mirror = mirror_point(theta_h);
    for blob in components(stray, w) {
        let Some(&worst) = blob.iter().max_by(|&&a, &&b| at[a].total_cmp(&at[b])) else { continue };
        let nearest = blob.iter().map(|&k| theta_h[k]).fold(f64::INFINITY, f64::min);
        let end = || blob.len() >= MIN_STROKE_PIXELS && outline.is_some_and(|g| blob.iter().any(|&k| reaches_outline(g, k)));
        if (blob.len() < least && !end()) || (brighter[worst] && nearest <= mirror + HIGHLIGHT_DEG) {
            for k in blob {
                stray[k] = false;
            }
        }
    }
}

/// The view's smallest $\theta_h$ (degrees; `theta_h` is NaN off the samples): where its
/// mirror point, and a highlight, lies.
fn mirror_point(theta_h: &[f64]) -> f64 {
    theta_h.iter().copied().filter(|t| t.is_finite()).fold(f64::INFINITY, f64::min)
}

/// Whether pixel `k` of `geometry` lies within [`OUTLINE_REACH`] pixels (8-neighbour steps)
/// of one that does not see the object: on the band along the outline, where a stroke across
/// it ends on the object. Only small blobs ask, so the band is never built.
fn reaches_outline(geometry: &crate::sample::Geometry, k: usize) -> bool {
    let (w, h) = (geometry.width as i64, geometry.height as i64);
    let (i, j) = ((k % geometry.width) as i64, (k / geometry.width) as i64);
    let r = OUTLINE_REACH as i64;
    ((j - r).max(0)..=(j + r).min(h - 1)).any(|y| ((i - r).max(0)..=(i + r).min(w - 1)).any(|x| geometry.pixels[(y * w + x) as usize].is_none()))
}

/// Grows `stray` (a mask `w` to a row) [`GROWTH`] pixels into its 8-neighbours whose miss `at`
/// exceeds `rim`: a stroke's soft edge, where it blends with the shading under it.
fn grow(stray: &mut [bool], at: &[f64], w: usize, rim: f64) {
    let mut frontier: Vec<usize> = (0..stray.len()).filter(|&k| stray[k]).collect();
    for _ in 0..GROWTH {
        let mut next = Vec::new();
        for k in frontier.drain(..) {
            for m in neighbours8(k, w, stray.len()) {
                if !stray[m] && at[m] > rim {
                    stray[m] = true;
                    next.push(m);
                }
            }
        }
        frontier = next;
    }
}

/// Widens `stray` (a mask `w` to a row) [`TONED_RIM`] pixels into its 8-neighbours that are
/// samples (`theta_h` finite), but not within [`HIGHLIGHT_DEG`] of the mirror point: a
/// toned stroke's rim.
fn widen(stray: &mut [bool], theta_h: &[f64], w: usize) {
    let mirror = mirror_point(theta_h);
    for _ in 0..TONED_RIM {
        let rim: Vec<usize> = (0..stray.len())
            .filter(|&k| stray[k])
            .flat_map(|k| neighbours8(k, w, stray.len()))
            .filter(|&m| theta_h[m] > mirror + HIGHLIGHT_DEG)
            .collect();
        for m in rim {
            stray[m] = true;
        }
    }
}

/// Paints the strays (`found[v]`: pixels of view v, unusable until now) with the physical
/// proxy ([`super::proxy`], non-negative lobes) fitted per channel to the other samples,
/// and makes them samples again. Left out, they would leave holes at the outline and in the
/// shadow, where the tables then extrapolate freely: a Lambertian sphere with its strays left
/// out no longer darkens when the light goes behind it (light sweep 0.47). The factored fit
/// of the other samples, as the paint instead, does worse (faults, strays: 0.054 against the
/// proxy's 0.046): where it would interpolate, strays have bent it.
fn fill(views: &mut [PaintedView], found: &[Vec<usize>]) -> Result<()> {
    let samples = Samples::gather(views)?;
    let peak = samples.values.iter().flatten().copied().fold(0.0, f64::max).max(1e-12);
    for c in 0..3 {
        let points: Vec<_> = samples
            .pattern
            .queries
            .iter()
            .zip(&samples.values)
            .map(|(q, y)| (proxy::basis(q.l, q.v), y[c], 1.0 / (y[c].max(0.0) + 0.05 * peak)))
            .collect();
        let Some(x) = proxy::fit_plausible(&points) else { continue };
        for (view, pixels) in views.iter_mut().zip(found) {
            for &k in pixels {
                if let Some(px) = view.geometry.pixels[k].as_ref() {
                    let s = proxy::eval(&proxy::basis(px.query.l, px.query.v), &x).max(0.0);
                    view.painting.pixels[k][c] = (s * px.light[c]) as f32;
                }
            }
        }
    }
    for (view, pixels) in views.iter_mut().zip(found) {
        for &k in pixels {
            view.geometry.usable[k] = true;
        }
    }
    Ok(())
}
