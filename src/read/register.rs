//! The painter's light (issue 11): where a painting was shaded from, near the scene's light.
//!
//! People paint a highlight a little off and a terminator a few degrees round from where the
//! scene's light puts them. Fitted with the scene's light, that shift goes into the factors:
//! on one view l, h and v move together, so the tables bend to put the highlight where it
//! was painted, and under any other light the material is wrong (held-out error 0.116 for a
//! shading painted 10° off: BENCHMARKS.md, faults).
//!
//! So the light is *registered*, as one registers two images. Candidates are the scene's
//! light turned by a small rotation $R$ (about axes perpendicular to it, within
//! [`RADIUS_DEG`]); for each, every sample's light direction becomes $R\,l$ in world space
//! (the G-buffer keeps each pixel's frame).
//!
//! - **Search: a physical proxy, not the factors.** The factored product cannot pick the
//!   light: on one view a diffuse painting is explained almost as well by any light on the
//!   great circle through the light and the eye, since $p(l)\,q(h)\,r(v)$ bends to follow
//!   (a Lambertian sphere painted 10° off was fitted best 18° off, the wrong way). A small
//!   physical basis does not bend: luminance as the physical proxy ([`super::proxy`]:
//!   ambient, diffuse, a Gooch painting's cool side and Blinn-Phong lobes), fitted by linear
//!   least squares with relative weights. Its isophotes are circles about $l$ and its highlight sits at $h$, so its best
//!   light is where the painting's shading and highlight say the light was.
//! - **Refinement: a lobe family.** The proxy has no view-dependent diffuse, and puts a
//!   Minnaert or Oren-Nayar painting's light a degree or so off. Near its light, the light
//!   is moved under the classic lobe family that holds the painting best
//!   ([`refine_on_lobe`]), which cannot bend either.
//! - **Acceptance: the factors.** The proxy is not the material and is biased by a degree or
//!   two on materials it cannot express (retro-reflection, masking), so its light is kept
//!   only when the factored fit itself explains the painting better with it than with the
//!   scene's light ([`MIN_GAIN`]), and explains it as one material ([`MAX_RESIDUAL`]). A
//!   render of a physical material is explained best by its own light, so it is never moved.
//!
//! A point light is turned the same way: every sample's direction to it is rotated, which is
//! the light moved on a sphere about each point (exact for a distant light; the falloff is
//! kept).

use glam::{DQuat, DVec3};
use rayon::prelude::*;

use super::proxy;
use crate::sample::{Geometry, PaintedView, Samples};
use crate::error::Result;
use crate::brdf::lobe::Base;
use crate::factor::{Mapping, Settings};
use crate::render::GBuffer;

/// The largest turn searched, in degrees: painters' errors, not another lighting.
pub const RADIUS_DEG: f64 = 20.0;
/// A turn is kept only when the factored fit's relative RMS with it is at least this
/// fraction below its RMS with the scene's light.
/// (10%: at 5% a clean render of a GGX sphere from two views, whose joint fit misses it
/// structurally, was turned 5° for a 6% gain.)
pub const MIN_GAIN: f64 = 0.1;
/// A turn is kept only when the painting, lit from there, looks like one material: the
/// factored fit's relative RMS at most this (or it gains [`CLEAR_GAIN`]). A painting of several materials (bands of
/// albedo) is explained better by some light or other, never well, and its light is the
/// scene's to keep (`fit` warns that it is not one material instead).
pub const MAX_RESIDUAL: f64 = 0.15;
/// A turn that leaves the painting poorly explained is still kept when it halves the
/// factored fit's error: stray strokes and flat tones keep a painting from being explained
/// well by any light, and a painting of several materials never gains this much (a banded
/// painting of two albedos gains a few percent at best).
pub const CLEAR_GAIN: f64 = 0.5;
/// Turns smaller than this (degrees) are not worth a note or a different scene.
const MIN_TURN_DEG: f64 = 1.0;

/// One view's light as registered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// The rotation applied to the scene's light (identity: kept as given).
    pub rotation: DQuat,
    /// Its angle in degrees.
    pub degrees: f64,
    /// Relative RMS of the factored fit with the scene's light, and with the turned one;
    /// for a turn judged on a toned painting's tones (`by_tones`), how far the tones' best
    /// reading leaves their intervals ([`crate::read::tones::Luminance::outside`]).
    pub before: f64,
    pub after: f64,
    /// Whether the turn was judged on the tones rather than on the factored fit.
    pub by_tones: bool,
    /// The search's best rotation, kept or not (identity when it found no turn worth one),
    /// and `after` over `before` for it (the factored fit's; 1 for none).
    pub proposed: DQuat,
    pub proposed_gain: f64,
}

impl Turn {
    /// The scene's light, kept.
    pub(crate) fn kept(score: f64) -> Turn {
        Turn { rotation: DQuat::IDENTITY, degrees: 0.0, before: score, after: score, by_tones: false, proposed: DQuat::IDENTITY, proposed_gain: 1.0 }
    }

    /// A turn by `rotation` that took the painting's misfit from `before` to `after`
    /// (`by_tones`: the tones' misfit).
    pub(crate) fn by(rotation: DQuat, before: f64, after: f64, by_tones: bool) -> Turn {
        let degrees = rotation.to_axis_angle().1.to_degrees();
        Turn { rotation, degrees, before, after, by_tones, proposed: rotation, proposed_gain: after / before.max(f64::MIN_POSITIVE) }
    }

    /// Whether the light was moved.
    pub fn moved(&self) -> bool {
        self.degrees > 0.0
    }
}

/// The local frame of a G-buffer pixel in world space: tangent, bitangent
/// $= \mathrm{sign}\,(n \times t)$, normal (shaders/surface.glsl), the axes of its queries.
fn frame(g: &GBuffer, k: usize) -> [DVec3; 3] {
    let p = &g.pixels[k];
    let n = p.normal.as_dvec3();
    let t = p.tangent.truncate().as_dvec3();
    let sign = if p.tangent.w < 0.0 { -1.0 } else { 1.0 };
    [t, n.cross(t) * sign, n]
}

/// A local-frame direction `d` (a G-buffer pixel's light or view) in world space, through
/// that pixel's [`frame`].
fn to_world([t, b, n]: [DVec3; 3], d: DVec3) -> DVec3 {
    t * d.x + b * d.y + n * d.z
}

/// `geometry` with the light turned by `rotation`: each pixel's light direction, taken to
/// world space through its G-buffer frame, rotated and taken back. Views, uvs and the light
/// delivered are kept.
pub fn turned(g: &GBuffer, geometry: &Geometry, rotation: DQuat) -> Geometry {
    let mut out = geometry.clone();
    for (k, px) in out.pixels.iter_mut().enumerate() {
        let Some(px) = px else { continue };
        let [t, b, n] = frame(g, k);
        let world = rotation * to_world([t, b, n], g.pixels[k].l.as_dvec3());
        px.query.l = DVec3::new(world.dot(t), world.dot(b), world.dot(n)).normalize_or(DVec3::Z);
    }
    out
}

/// Where a painting's brightest paint says the light is: turns of the scene's light toward
/// the lights that put the brightest pixels (`brightest`, G-buffer pixels) at their mean
/// normal $n$ and view $v$: a highlight's, the mirror direction $2(n \cdot v)\,n - v$; a
/// diffuse glow's, $n$ itself. Only turns of [`MIN_TURN_DEG`] to [`RADIUS_DEG`] are returned.
/// A toned painting's top tone is a small region whose centre the proxy search can miss
/// where brush and stray strokes mislead it (a glossy sphere with every fault was searched
/// 20° the wrong way); [`crate::pipeline`] judges these turns on the tones.
pub fn brightest_turns(g: &GBuffer, brightest: &[usize]) -> Vec<DQuat> {
    let world = |k: usize, d: glam::Vec3| to_world(frame(g, k), d.as_dvec3());
    let (mut n, mut v, mut l) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for &k in brightest.iter().filter(|&&k| g.pixels[k].hit) {
        n += g.pixels[k].normal.as_dvec3();
        v += world(k, g.pixels[k].v);
        l += world(k, g.pixels[k].l);
    }
    let (Some(n), Some(v), Some(l)) = (n.try_normalize(), v.try_normalize(), l.try_normalize()) else { return Vec::new() };
    [2.0 * n.dot(v) * n - v, n]
        .into_iter()
        .filter_map(|target| target.try_normalize())
        .map(|target| DQuat::from_rotation_arc(l, target))
        .filter(|q| (MIN_TURN_DEG..=RADIUS_DEG).contains(&q.to_axis_angle().1.to_degrees()))
        .collect()
}

/// How well the factored product of `settings` explains `samples`: relative RMS of its
/// least-squares fit with the offset mapping, over all but the [`TRIM`] worst-fitted
/// samples (stray strokes hide what a light explains).
fn explained(samples: &Samples, settings: &Settings) -> Result<f64> {
    // Every k-th sample: the same for the light as given and turned, so their ratio is fair.
    let stride = samples.len().div_ceil(EXPLAINED_SAMPLES).max(1);
    let pattern = crate::factor::Pattern::new(samples.pattern.queries.iter().step_by(stride).copied().collect(), samples.pattern.has_uv);
    let values: Vec<[f64; 3]> = samples.values.iter().step_by(stride).copied().collect();
    // Per channel, as the thesis fits: the light is found by the shading's shape, and one
    // system prepares in half the time of the coupled pair.
    let prepared = crate::factor::prepare(&pattern, &settings.luminance())?;
    let fit = prepared.solve(&values, Mapping::Offset(None))?;
    let predicted = prepared.predict(&fit.tables, &fit.map);
    let mut errors: Vec<(f64, f64)> = values
        .iter()
        .zip(&predicted)
        .map(|(y, f)| ((0..3).map(|c| (f[c] - y[c]).powi(2)).sum(), (0..3).map(|c| y[c] * y[c]).sum()))
        .collect();
    errors.sort_by(|a, b| a.0.total_cmp(&b.0));
    let kept = &errors[..errors.len() - (TRIM * errors.len() as f64) as usize];
    let (se, sy) = kept.iter().fold((0.0, 0.0), |(a, b), (e, y)| (a + e, b + y));
    Ok((se / sy.max(1e-300)).sqrt())
}

/// Most samples [`explained`] fits (every k-th of a larger painting): its relative RMS is a
/// mean over the painting, which this many estimate far closer than the gains it is judged
/// by ([`MIN_GAIN`]); fitting all of a 512² painting's 147k took 60 ms a check.
const EXPLAINED_SAMPLES: usize = 40_000;

/// The fraction of worst-fitted samples [`explained`] leaves out.
const TRIM: f64 = 0.05;

/// Most samples the proxy search fits (every k-th; seven unknowns need few).
const SEARCH_SAMPLES: usize = 8000;

/// The search's samples with one view's light free: the others' queries as they are, and
/// for the free view's the frame and world-space light direction of each, with each
/// sample's luminance.
struct Search {
    fixed: Vec<(DVec3, DVec3, f64)>,
    free: Vec<([DVec3; 3], DVec3, DVec3, f64)>,
    /// The free view's mean world-space light direction.
    light: DVec3,
    /// 5% of the largest luminance: the proxy's weights are 1 / (value + this).
    floor: f64,
}

impl Search {
    fn new(samples: &Samples, free_view: usize, g: &GBuffer) -> Search {
        let stride = samples.len().div_ceil(SEARCH_SAMPLES).max(1);
        let mut search = Search { fixed: Vec::new(), free: Vec::new(), light: DVec3::ZERO, floor: 0.0 };
        let mut sum = DVec3::ZERO;
        let mut max = 0.0f64;
        for k in (0..samples.len()).step_by(stride) {
            let (q, c) = (&samples.pattern.queries[k], samples.values[k]);
            let y = crate::images::luminance(c);
            max = max.max(y);
            let (view, pixel) = samples.origin[k];
            if view == free_view {
                let [t, b, n] = frame(g, pixel);
                let world = to_world([t, b, n], g.pixels[pixel].l.as_dvec3());
                sum += world;
                search.free.push(([t, b, n], world, q.v, y));
            } else {
                search.fixed.push((q.l, q.v, y));
            }
        }
        search.light = sum.normalize_or(DVec3::Z);
        search.floor = 0.05 * max.max(1e-12);
        search
    }

    /// The samples with the free view's light turned by `rotation`, as a pattern and their
    /// luminance (in each channel).
    fn luminance(&self, rotation: DQuat) -> (crate::factor::Pattern, Vec<[f64; 3]>) {
        let (queries, values) = self.turned(rotation).map(|(l, v, y)| (crate::factor::Query::at(l, v), [y; 3])).unzip();
        (crate::factor::Pattern::new(queries, false), values)
    }

    /// Every sample's (l, v, luminance) with the free view's light turned by `rotation`.
    fn turned(&self, rotation: DQuat) -> impl Iterator<Item = (DVec3, DVec3, f64)> + Clone + '_ {
        let turned = self.free.iter().map(move |&([t, b, n], world, v, y)| {
            let w = rotation * world;
            (DVec3::new(w.dot(t), w.dot(b), w.dot(n)), v, y)
        });
        self.fixed.iter().copied().chain(turned)
    }

    /// The proxy's relative RMS with the free view's light turned by `rotation`.
    fn score(&self, rotation: DQuat) -> f64 {
        proxy(self.turned(rotation), self.floor)
    }
}

/// Relative RMS of a robust fit of luminance by the physical proxy ([`super::proxy`]) to
/// (l, v, luminance) samples. Each is weighted by 1 / (its value + `floor`), so dark and
/// bright regions count alike, as in the relative RMS a fit reports; then twice reweighted
/// by Huber's weights (residuals beyond twice their robust spread count linearly), and
/// scored with those weights, so stray strokes do not choose the light.
fn proxy(samples: impl Iterator<Item = (DVec3, DVec3, f64)> + Clone, floor: f64) -> f64 {
    let points: Vec<([f64; proxy::BASIS], f64, f64)> = samples.map(|(l, v, y)| (proxy::basis(l, v), y, 1.0 / (y + floor))).collect();
    let mut huber = vec![1.0f64; points.len()];
    let mut score = f64::INFINITY;
    for _ in 0..3 {
        let Some(x) = proxy::fit(points.iter().zip(&huber).map(|(&(b, y, w), h)| (b, y, w * h.sqrt()))) else {
            return f64::INFINITY;
        };
        let residual: Vec<f64> = points.iter().map(|&(b, y, w)| ((proxy::eval(&b, &x) - y) * w).abs()).collect();
        let (mut se, mut sy) = (0.0, 0.0);
        for ((&(_, y, w), r), h) in points.iter().zip(&residual).zip(&huber) {
            se += h * r * r;
            sy += h * (y * w).powi(2);
        }
        score = (se / sy.max(1e-300)).sqrt();
        // The median by selection (the same element a sort would put there, in linear time).
        let mut scratch = residual.clone();
        let half = scratch.len() / 2;
        let spread = 2.0 * 1.4826 * *scratch.select_nth_unstable_by(half, f64::total_cmp).1;
        for (h, r) in huber.iter_mut().zip(&residual) {
            *h = if *r > spread && spread > 0.0 { spread / r } else { 1.0 };
        }
    }
    score
}

/// The proxy's light refined under the lobe of the classic family that fits the painting
/// best there ([`Base::fit_any`], on the search's luminance), within [`REFINE_DEG`] of it:
/// the light moved by a pattern search under that lobe (from [`REFINE_STEP_DEG`] down to a
/// quarter of that), its width fitted again there, until it stays. The proxy has no term
/// for a view-dependent diffuse and puts a Minnaert or Oren-Nayar painting's light a degree
/// or so off, which their held-out error shows many times over (docs/notes/history.md,
/// "The light refined under a lobe family"). Only
/// where the family's misfit is at most [`REFINE_GATE`] times the proxy's (a Gooch
/// painting's cool side is in no family, and a lobe moved it 2° for nothing), and not under
/// a headlight, where the lobes hold the painting's one angle under any light.
fn refine_on_lobe(search: &Search, (a, b, score): (f64, f64, f64), rotation: &(impl Fn(f64, f64) -> DQuat + Sync)) -> (f64, f64) {
    let (pattern, values) = search.luminance(rotation(a, b));
    if pattern.headlit() {
        return (a, b);
    }
    let Some((mut base, misfit)) = Base::fit_any(&pattern, &values) else { return (a, b) };
    if misfit > REFINE_GATE * score {
        return (a, b);
    }
    let mut best = (a, b, misfit);
    for _ in 0..REFINE_PASSES {
        let misfit = |x: f64, y: f64| {
            let (pattern, values) = search.luminance(rotation(x, y));
            Base::fit_lobe_at(&pattern, &values, base.lobe, base.alpha).map_or(f64::INFINITY, |(_, m)| m)
        };
        let start = best;
        let mut step = REFINE_STEP_DEG;
        for _ in 0..REFINE_ROUNDS {
            let candidates: Vec<(f64, f64)> = [-1.0, 0.0, 1.0]
                .into_iter()
                .flat_map(|da| [-1.0, 0.0, 1.0].into_iter().map(move |db| (da, db)))
                .filter(|&(da, db)| da != 0.0 || db != 0.0)
                .map(|(da, db)| (best.0 + da * step, best.1 + db * step))
                .filter(|&(x, y)| (x - a).hypot(y - b) <= REFINE_DEG * 1.001 && x.hypot(y) <= RADIUS_DEG * 1.001)
                .collect();
            let scores: Vec<f64> = candidates.par_iter().map(|&(x, y)| misfit(x, y)).collect();
            let before = best;
            for ((x, y), s) in candidates.into_iter().zip(scores) {
                if s < best.2 {
                    best = (x, y, s);
                }
            }
            if best == before {
                step /= 2.0;
                if step < REFINE_STEP_DEG / 4.0 {
                    break;
                }
            }
        }
        if (best.0, best.1) == (start.0, start.1) {
            break;
        }
        // The width again under the light moved (the family kept: choosing it again costs
        // six times as much).
        let (pattern, values) = search.luminance(rotation(best.0, best.1));
        match Base::fit_lobe(&pattern, &values, base.lobe) {
            Some((again, misfit)) if again.alpha != base.alpha => (base, best.2) = (again, misfit),
            _ => break,
        }
    }
    (best.0, best.1)
}

/// How far [`refine_on_lobe`] may move the proxy's light, and its first step (degrees).
const REFINE_DEG: f64 = 2.0;
const REFINE_STEP_DEG: f64 = 1.0;
/// Most rounds of [`refine_on_lobe`]'s pattern search, and most times it fits the width.
const REFINE_ROUNDS: usize = 16;
const REFINE_PASSES: usize = 3;
/// [`refine_on_lobe`] refines only where the lobe's misfit is at most this many times the
/// proxy's score at the proxy's light (their measures alike: relative, softened by 5% of
/// the brightest value).
const REFINE_GATE: f64 = 2.0;

/// Registers each view's light (one pass over the views, each searched with the others as
/// registered so far) and turns the views' geometry to it. `gbuffers[i]` is the G-buffer
/// view `i` was sampled from. Returns one [`Turn`] per view.
pub fn register(views: &mut [PaintedView], gbuffers: &[&GBuffer], settings: &Settings) -> Result<Vec<Turn>> {
    let mut turns = Vec::with_capacity(views.len());
    for i in 0..views.len() {
        let g = gbuffers[i];
        let original = views[i].geometry.clone();
        // The views as given: searched, then explained before any turn.
        let gathered = Samples::gather(views)?;
        let search = Search::new(&gathered, i, g);
        // Two axes perpendicular to the light: turning about them moves the light's
        // direction; turning about the light itself would not.
        let (u, w) = search.light.any_orthonormal_pair();
        let rotation = |a: f64, b: f64| {
            let axis = u * a + w * b;
            let angle = axis.length();
            if angle == 0.0 { DQuat::IDENTITY } else { DQuat::from_axis_angle(axis / angle, angle.to_radians()) }
        };
        let evaluate = |a: f64, b: f64| search.score(rotation(a, b));
        let mut best = (0.0, 0.0, evaluate(0.0, 0.0));
        // A coarse grid, then a pattern search halving the step about the best point.
        let coarse = RADIUS_DEG / 4.0;
        let mut candidates: Vec<(f64, f64)> = Vec::new();
        for a in -4..=4 {
            for b in -4..=4 {
                candidates.push((a as f64 * coarse, b as f64 * coarse));
            }
        }
        let mut step = coarse;
        loop {
            // Scored in parallel, kept in order (the first of equals, as one by one).
            candidates.retain(|&(a, b)| !(a == 0.0 && b == 0.0) && a.hypot(b) <= RADIUS_DEG * 1.001);
            let scores: Vec<f64> = candidates.par_iter().map(|&(a, b)| evaluate(a, b)).collect();
            for ((a, b), s) in candidates.drain(..).zip(scores) {
                if s < best.2 {
                    best = (a, b, s);
                }
            }
            step /= 2.0;
            if step < MIN_TURN_DEG / 2.0 {
                break;
            }
            for da in [-1.0, 0.0, 1.0] {
                for db in [-1.0, 0.0, 1.0] {
                    if da != 0.0 || db != 0.0 {
                        candidates.push((best.0 + da * step, best.1 + db * step));
                    }
                }
            }
        }
        // A light the proxy would not turn is not refined: the scene's light kept costs
        // nothing more.
        let best = match best.0.hypot(best.1) >= MIN_TURN_DEG {
            true => refine_on_lobe(&search, best, &rotation),
            false => (best.0, best.1),
        };
        let degrees = best.0.hypot(best.1);
        // The fit that judges the turn is `fit`'s: under a headlight, with the light prior
        // (without it a headlit painting with black strokes was explained to 1.000 and turned
        // 20° for 0.054), the same settings before and after.
        let settings = &settings.for_pattern(&gathered.pattern);
        let before = explained(&gathered, settings)?;
        let mut turn = Turn::kept(before);
        if degrees >= MIN_TURN_DEG {
            let rotation = rotation(best.0, best.1);
            views[i].geometry = turned(g, &original, rotation);
            let after = explained(&Samples::gather(views)?, settings)?;
            if after <= (1.0 - MIN_GAIN) * before && (after <= MAX_RESIDUAL || after <= CLEAR_GAIN * before) {
                turn = Turn::by(rotation, before, after, false);
            } else {
                views[i].geometry = original;
                turn.proposed = rotation;
                turn.proposed_gain = after / before.max(f64::MIN_POSITIVE);
            }
        }
        turns.push(turn);
    }
    Ok(turns)
}

/// What the user hears about a view whose light was moved.
pub fn note(view: &PaintedView, turn: &Turn) -> crate::note::Note {
    crate::note::Note::LightTurned { painting: view.name.clone(), degrees: turn.degrees, before: turn.before, after: turn.after, by_tones: turn.by_tones }
}
