//! The one path from paintings to a material (DESIGN.md, Data flow). `brdfpaint fit` (scenes
//! and lit spheres) and the demo go through here; the command line only parses and prints.
//! Live painting ([`crate::live`]) refits on a prepared system it keeps current in the
//! background, with this module's settings rule and provenance, and its settled fit is this
//! path's to the last bit (tests/viewer_paint.rs).
//!
//! ```text
//! scene + painting ──load_views──► PaintedView ─┐            (sample: G-buffer → l, v, uv per pixel)
//! scene + painting ──load_views──► PaintedView ─┴─► Samples    (thesis 4.4: views concatenate)
//! Samples.pattern + Settings ──solve──► Prepared (cache) + Fit (factor: thesis 3.2)
//! Fit ──material──► Material (uniform, four-factor)
//! Prepared + Samples + Grids ──material::map::fit──► Material (material map, hybrid: thesis 4.2)
//! Material + views ──Fitted::report──► report.png; Fitted::save ──► MAT/
//! ```
//!
//! The prepared system depends only on where the samples are and on the settings, never on
//! the colours (thesis 3.2.2), so [`solve`] prepares through the cache and a repainted view
//! of a known scene only solves.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::commit::StagedDir;
use crate::error::{Error, Result};
use crate::factor::cache::{Cache, Outcome};
use crate::read::lobe::BaseChoice;
use crate::factor::{defaults, difference_range, DifferenceChoice, DIFFERENCE_REACH_DEG, Errors, Fit, Mapping, Prepared, Settings};
use crate::images::Rgb;
use crate::material::map::{self, MapOptions, MapReport};
use crate::material::{Kind, Material, Provenance};
use crate::render::GBuffer;
use crate::sample::{register, strays, tones};
use crate::sample::{check_same_model, report, Erosion, PaintedView, Samples, SceneSampler};

/// What to fit: the material's kind, its factor tables, the log mapping, and for material
/// maps and hybrids how their terms are found.
#[derive(Clone, Debug)]
pub struct Options {
    pub kind: Kind,
    /// The factors of one product, the uv factor included for four-factor and hybrid kinds.
    pub settings: Settings,
    pub mapping: Mapping,
    /// Terms, coefficient resolution and method of a material map or hybrid.
    pub map: MapOptions,
    /// The analytic base under a uniform product ([`crate::brdf::lobe`], issue 15).
    /// `None` by default (the demo, lit spheres and live painting fit the plain product);
    /// `brdfpaint fit` passes its `--base`, `auto` unless told.
    pub base: BaseChoice,
    /// Whether the product gets a factor of $\theta_d$ ([`DifferenceChoice`], issue 15):
    /// `auto` adds it to a uniform fit whose paintings show side or back light.
    pub difference: DifferenceChoice,
}

impl Default for Options {
    fn default() -> Self {
        Options { kind: Kind::Uniform, settings: Settings::default(), mapping: Mapping::Auto, map: MapOptions::default(), base: BaseChoice::None, difference: DifferenceChoice::Auto }
    }
}

impl Options {
    /// Options of the given kind from the common knobs: `dim` (1 or 2) sets the tables of
    /// p(l), q(h), r(v) ([`settings`]); `uv_res` is the uv factor's resolution (four-factor,
    /// hybrid) and the coefficient textures' (material map, hybrid).
    pub fn new(kind: Kind, dim: usize, res: Option<usize>, lambda: Option<f64>, uv_res: Option<usize>) -> Result<Options> {
        let mut settings = settings(dim, res, lambda)?;
        if matches!(kind, Kind::FourFactor | Kind::Hybrid) {
            let four = Settings::four_factor(1, 2, uv_res.unwrap_or(defaults::RES_UV));
            let mut uv = four.factors[3].clone();
            if kind == Kind::Hybrid {
                uv.smooth = defaults::SMOOTH_UV_HYBRID;
            }
            settings.factors.push(uv);
            settings.validate()?;
        }
        let mut map = MapOptions::default();
        // A hybrid's uv resolution is that of its uv factors and its coefficient textures.
        if matches!(kind, Kind::MaterialMap | Kind::Hybrid) {
            map.coef_res = uv_res.unwrap_or(map.coef_res);
        }
        Ok(Options { kind, settings, mapping: Mapping::Auto, map, base: BaseChoice::None, difference: DifferenceChoice::Auto })
    }
}

/// The settings of p(l) q(h) r(v) with `dim`-dimensional tables of `res` nodes per axis
/// (default 128 for 1D, 32 for 2D) and Laplacian weight `lambda` on every factor (default:
/// each factor's own, README "Defaults"). The one rule for the command line and the viewer.
pub fn settings(dim: usize, res: Option<usize>, lambda: Option<f64>) -> Result<Settings> {
    if !(1..=2).contains(&dim) {
        return Err(Error::input(format!("factor tables are 1D or 2D, not {dim}D")));
    }
    let default_res = if dim == 1 { defaults::RES_1D } else { defaults::RES_2D };
    let mut s = Settings::uniform(dim, res.unwrap_or(default_res));
    if let Some(l) = lambda {
        for f in &mut s.factors {
            f.smooth = l;
        }
    }
    s.validate()?;
    Ok(s)
}

/// Where a material came from: this tool, its inputs, its errors and timings.
pub fn provenance(sources: Vec<String>, errors: Option<Errors>, samples: usize, prepare_s: f64, solve_s: f64) -> Provenance {
    Provenance { tool: crate::material::TOOL.to_string(), sources, errors, samples, prepare_s, solve_s, notes: Vec::new() }
}

/// The inputs of `views` as provenance lists them: each view's scene, then its painting.
pub fn sources(views: &[PaintedView]) -> Vec<String> {
    views.iter().flat_map(|v| [v.source.clone(), v.name.clone()]).collect()
}

/// Views loaded for a fit, and what the user should hear about them.
pub struct Loaded {
    pub views: Vec<PaintedView>,
    /// The G-buffer each view was sampled from (its pixels' frames: [`Loaded::read`]).
    pub gbuffers: Vec<GBuffer>,
    /// One line each: what was left out of a painting and why, and how it was read.
    pub notes: Vec<String>,
}

impl Loaded {
    /// Reads the paintings for a fit of `kind` as evidence ([`read`]); the notes join the
    /// load's. A spatially varying painting is not one product: its residual says nothing
    /// about the light and its regions' tones are not one shading, so only the uniform kinds
    /// are read.
    pub fn read(&mut self, reading: &Reading, kind: Kind) -> Result<()> {
        if !matches!(kind, Kind::Uniform | Kind::FourFactor) {
            return Ok(());
        }
        let gbuffers: Vec<&GBuffer> = self.gbuffers.iter().collect();
        let notes = read(&mut self.views, &gbuffers, reading)?;
        self.notes.extend(notes);
        Ok(())
    }
}

/// How paintings are read before a uniform fit (issue 11: a painting is noisy, stylized
/// evidence of a plausible material).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reading {
    /// Flat tones become the smooth shading between their edges ([`crate::sample::tones`]).
    pub smooth_tones: bool,
    /// Each view's light is registered to where the painting was shaded from
    /// ([`crate::sample::register`]).
    pub register_light: bool,
    /// Strokes that do not belong to the shading are repainted with the shading around them
    /// ([`crate::sample::strays`]).
    pub repaint_strays: bool,
}

impl Default for Reading {
    fn default() -> Self {
        Reading { smooth_tones: true, register_light: true, repaint_strays: true }
    }
}

/// Reads painted views as `reading` says, in place, with the 1D default product judging
/// each step. One note per change. The order matters: flat tones are interpolated first
/// (every later step fits the painting and a staircase misleads it); the light registered
/// (a toned painting's first on its steps as painted, [`register_as_painted`]); stray
/// strokes repainted, and if there were any the light registered again (they hide the
/// painter's light); last the tones read again through the physical proxy under that light.
///
/// Strays found in flat tones are left out instead, and the views read again from the
/// start without them. A stroke in flat tones is tones of its own: the interpolation
/// between edges ([`tones::smooth`]) runs to it from the shading round it, and the light
/// is registered on its steps, before the stray search can find it. Read again without
/// the strokes, every fault held out at 0.0542 → 0.0505 (nine models' median, mean of
/// brush seeds 1–12) and 0.0481 → 0.0448 (seeds 13–24), GGX 0.2 0.285 → 0.146, Oren-Nayar
/// 0.037 → 0.018 ([`strays`]' `TONED_RIM` with it; BENCHMARKS.md, "Strokes in flat
/// tones"). Left out rather than repainted: the proxy's paint is Lambertian where the
/// material is not (Oren-Nayar 0.041 repainted, 0.019 left out, every fault, seeds 1–12,
/// a rim of two pixels).
/// Not under a headlight, where the light factor has only the painting's one angle to go
/// by and the holes let it stay up as the light goes behind: a headlit Minnaert sphere with
/// every fault (seed 11) swept to 0.60 of its brightest frame, against 0.24 repainted.
pub fn read(views: &mut [PaintedView], gbuffers: &[&GBuffer], reading: &Reading) -> Result<Vec<String>> {
    // The views as given, for the second reading (strays are searched in a single view).
    let given: Option<Vec<PaintedView>> = (views.len() == 1 && reading.smooth_tones && reading.repaint_strays).then(|| views.to_vec());
    let (first_notes, strays, _) = read_once(views, gbuffers, reading)?;
    let (Some(given), Some(mut strays)) = (given, strays) else { return Ok(first_notes) };
    if !strays.toned {
        return Ok(first_notes);
    }
    // The views as given go back in; `given` keeps the first reading, restored if the
    // second explains nothing.
    let mut first = given;
    views.swap_with_slice(&mut first);
    for (view, pixels) in views.iter_mut().zip(&strays.per_view) {
        for &k in pixels {
            if std::mem::replace(&mut view.geometry.usable[k], false) {
                view.geometry.left_out += 1;
            }
        }
    }
    let (mut notes, _, turns) = read_once(views, gbuffers, &Reading { repaint_strays: false, ..*reading })?;
    // A second reading the factored fit cannot explain at all (it misses by more than the
    // painting's own values, [`UNEXPLAINED_FIT`]) is not kept.
    if turns.iter().any(|t| !t.by_tones && t.after > UNEXPLAINED_FIT) {
        views.swap_with_slice(&mut first);
        return Ok(first_notes);
    }
    strays.left_out = true;
    notes.extend(strays.describe(views));
    Ok(notes)
}

/// The second reading of a toned painting without its strays ([`read`]) is kept only when
/// the factored fit, under the light it registered, misses the painting by at most this
/// relative RMS: beyond 1 it explains less than a black material would. Read again, GGX 0.2
/// with every fault lost a tone to its strays at brush seeds 6, 15 and 23 (6, 5 and 5
/// levels) and the fit missed it by 1.10–1.23 (held out 0.80–0.81, against 0.24–0.33 as
/// first read); every other second reading over seeds 1–24 missed by at most 0.47.
const UNEXPLAINED_FIT: f64 = 1.0;

/// One reading ([`read`]): its notes, the strays it repainted, and each view's light.
fn read_once(views: &mut [PaintedView], gbuffers: &[&GBuffer], reading: &Reading) -> Result<(Vec<String>, Option<strays::Strays>, Vec<register::Turn>)> {
    let mut repainted = None;
    let mut notes = Vec::new();
    let mut toned = Vec::new();
    // The paintings as painted, for a toned painting's first registration.
    let as_painted: Option<Vec<_>> = (reading.smooth_tones && reading.register_light).then(|| views.iter().map(|v| v.painting.clone()).collect());
    if reading.smooth_tones {
        for (i, view) in views.iter_mut().enumerate() {
            if let Some(t) = tones::smooth(view) {
                notes.push(t.describe(&view.name));
                toned.push((i, t));
            }
        }
    }
    let register = |views: &mut [PaintedView]| -> Result<Vec<register::Turn>> {
        match reading.register_light {
            true => register::register(views, gbuffers, &Settings::default()),
            false => Ok(Vec::new()),
        }
    };
    let scene_geometry: Vec<_> = views.iter().map(|v| v.geometry.clone()).collect();
    let clear = match as_painted {
        Some(painted) if !toned.is_empty() => register_as_painted(views, painted, gbuffers)?,
        _ => None,
    };
    let mut turns = match clear {
        Some(turns) => turns,
        None => register(views)?,
    };
    // Every pass's proposal per view, for toned views to judge on their tones below.
    let mut proposals: Vec<Vec<(glam::DQuat, f64)>> = turns.iter().map(|t| vec![(t.proposed, t.proposed_gain)]).collect();
    if reading.repaint_strays {
        let tones_of: Vec<Option<&tones::Toned>> = (0..views.len()).map(|v| toned.iter().find(|(i, _)| *i == v).map(|(_, t)| t)).collect();
        if let Some(found) = strays::repaint(views, &Settings::default(), &tones_of)? {
            notes.extend(found.describe(views));
            // A repainted stray's tone interval is the stroke's, not the shading's.
            for (i, t) in toned.iter_mut() {
                let stray: std::collections::HashSet<usize> = found.per_view[*i].iter().copied().collect();
                t.bounds.retain(|(k, _)| !stray.contains(k));
            }
            repainted = Some(found);
            // Without the strays the painter's light may show more clearly: searched again
            // (about the scene's light), a view keeps its first turn unless the new one
            // explains it better.
            for ((turn, again), proposed) in turns.iter_mut().zip(register(views)?).zip(proposals.iter_mut()) {
                proposed.push((again.proposed, again.proposed_gain));
                if again.moved() {
                    *turn = again;
                }
            }
        }
    }
    // A toned view's light is registered on the interpolation between its tone edges, a
    // guess; the edges themselves are the evidence. The turn is undone when the scene's light
    // holds the tones clearly better (`tones::held`): a posterized Minnaert sphere was turned
    // 13° on the interpolation (its tones left by 0.0013 under the scene's light, 0.044
    // under the turn), and its held-out error went 0.01 → 0.29. Where the tones cannot tell
    // (a Gooch painting's two or three, under a headlight), the turn stays.
    // A toned view whose light the factored fit would not turn may still be turned on its
    // tones ([`turn_on_tones`]).
    // The reading under the light kept, for `tones::refine` below (a search not repeated).
    let mut held: Vec<Option<tones::Luminance>> = toned.iter().map(|_| None).collect();
    for ((i, t), kept) in toned.iter().zip(held.iter_mut()) {
        // No turns at all when the light is not registered.
        if turns.get(*i).is_none() {
            continue;
        }
        if !turns[*i].moved() {
            if let Some((turn, reading)) = turn_on_tones(&mut views[*i], t, gbuffers[*i], &scene_geometry[*i], &proposals[*i]) {
                turns[*i] = turn.unwrap_or(turns[*i]);
                *kept = Some(reading);
            }
            continue;
        }
        let turned = tones::held(&views[*i], t);
        let registered = std::mem::replace(&mut views[*i].geometry, scene_geometry[*i].clone());
        let scene = tones::held(&views[*i], t);
        match (turned, scene) {
            (Some(turned), Some(scene)) if scene.outside() < (1.0 - register::MIN_GAIN) * turned.outside() => {
                turns[*i] = register::Turn::kept(turns[*i].before);
                *kept = Some(scene);
            }
            (turned, _) => {
                views[*i].geometry = registered;
                *kept = turned;
            }
        }
    }
    for (view, turn) in views.iter().zip(&turns) {
        if turn.moved() {
            notes.push(register::describe(view, turn));
        }
    }
    for ((i, t), held) in toned.iter().zip(held) {
        if let Some((lobe, alpha)) = tones::refine(&mut views[*i], t, held) {
            let width = if lobe.has_width() { format!(" ({})", lobe.width_of(alpha)) } else { String::new() };
            notes.push(format!("{}: its tones are held best by the {} lobe{width}: read through it", views[*i].name, lobe.name()));
        }
    }
    Ok((notes, repainted, turns))
}

/// The light of toned paintings registered on their steps as painted (`painted`: the
/// paintings of `views` before their tones were smoothed), when that is clear: every view's
/// turn is kept by [`register::register`]'s own test. Then `views` take the turned geometry and the turns
/// are returned; else `None`, nothing changed, and the light is registered on the smoothed
/// tones as for any painting. A step's quantization error sits about the shading on both
/// sides of its edge, while the interpolation between edges ([`tones::smooth`]) is a guess
/// that holds the light back: the same toned paintings with the light 10° off were turned
/// 5–7° on the interpolation and 8° here, as the untoned painting is (faults study scratch
/// harness, seed 11: nine models' held-out median 0.0629 → 0.0276, 0.0273 with the
/// painter's light; with brush texture too, eight seeds, 0.0647 → 0.0487; every fault
/// 0.0671 → 0.0662; BENCHMARKS.md, "The light on toned paintings"). Not under a headlight,
/// where one painting shows one angle and its steps cannot place the light: headlit
/// paintings with every fault went 0.1995 → 0.2111 (Minnaert 0.165 → 0.356 at seed 11).
/// Costs one more registration where it is not clear (the bench's toned case 0.65–0.71 s →
/// 0.72–0.81 s).
fn register_as_painted(views: &mut [PaintedView], painted: Vec<crate::images::Painting>, gbuffers: &[&GBuffer]) -> Result<Option<Vec<register::Turn>>> {
    let headlit = views.iter().any(|v| crate::factor::headlit(v.geometry.pixels.iter().flatten().map(|p| (p.query.l, p.query.v))));
    if headlit {
        return Ok(None);
    }
    // The smoothed paintings are not copied, only what registration reads beside them.
    let mut painted: Vec<PaintedView> = views
        .iter()
        .zip(painted)
        .map(|(v, painting)| PaintedView { name: v.name.clone(), source: v.source.clone(), geometry: v.geometry.clone(), painting })
        .collect();
    let turns = register::register(&mut painted, gbuffers, &Settings::default())?;
    if !turns.iter().all(register::Turn::moved) {
        return Ok(None);
    }
    for (view, p) in views.iter_mut().zip(painted) {
        view.geometry = p.geometry;
    }
    Ok(Some(turns))
}

/// The light of a toned view the factored fit did not turn (its geometry the scene's,
/// `scene`), judged on its tones: the search's proposals (`proposals`, one per pass, about
/// the scene's light) and the lights its brightest tone points to
/// ([`register::brightest_turns`]; seed 4 below, where the search went 20° the wrong way in
/// both passes) are read under each ([`tones::held`]), and the best is taken when its
/// tones' misfit is under [`register::CLEAR_GAIN`] of the scene's light's (the margin a fit
/// that stays poor needs), or [`register::MIN_GAIN`] under it where the factored fit gained
/// as much from the same turn (the two judges agree). The factored fit's misfit is the
/// painting's, strays and brush included, and a glossy painting in flat tones is missed by
/// it anyway; the tones' edges are where the painter put the shading. GGX 0.2 with every
/// fault, brush seed 5 (the strays still in the first pass's fit, which gained 8% from the
/// 8° turn; after them the search found 2.5°): the edges are missed by 0.217 under the
/// scene's light, 0.019 turned, and the held-out error went 0.852 → 0.232; seed 6 (fit and
/// tones 31% and 40% better turned) 0.996 → 0.460; seed 4 (0.186 → 0.019 toward the
/// brightest tone's mirror light) 0.835 → 0.321 (BENCHMARKS.md). Returns the turn taken
/// (`None`: the light stays) and the reading under the light kept, for [`tones::refine`];
/// `None` when the tones give no reading.
fn turn_on_tones(
    view: &mut PaintedView,
    toned: &tones::Toned,
    g: &GBuffer,
    scene: &crate::sample::Geometry,
    proposals: &[(glam::DQuat, f64)],
) -> Option<(Option<register::Turn>, tones::Luminance)> {
    let at_scene = tones::held(view, toned)?;
    // The search's proposals, and where the brightest tone says the light is (a fit's gain
    // of 1: judged on the tones alone) when the scene's light leaves the tones unexplained.
    let brightest = match at_scene.outside() > UNEXPLAINED_TONES {
        true => register::brightest_turns(g, &toned.brightest()),
        false => Vec::new(),
    };
    let candidates = proposals.iter().copied().chain(brightest.into_iter().map(|q| (q, 1.0)));
    let mut best: Option<(glam::DQuat, tones::Luminance, f64, f64)> = None;
    for (q, fit_gain) in candidates.filter(|(q, _)| q.to_axis_angle().1 > 0.0) {
        view.geometry = register::turned(g, scene, q);
        if let Some(reading) = tones::held(view, toned) {
            let outside = reading.outside();
            if best.as_ref().is_none_or(|b| outside < b.2) {
                best = Some((q, reading, outside, fit_gain));
            }
        }
    }
    let gain = (1.0 - register::MIN_GAIN) * at_scene.outside();
    match best {
        // Strictly less: a painting whose tones every reading holds exactly cannot tell.
        Some((q, reading, outside, fit_gain))
            if outside < register::CLEAR_GAIN * at_scene.outside() || (outside < gain && fit_gain <= 1.0 - register::MIN_GAIN) =>
        {
            view.geometry = register::turned(g, scene, q);
            Some((Some(register::Turn::by(q, at_scene.outside(), outside, true)), reading))
        }
        _ => {
            view.geometry = scene.clone();
            Some((None, at_scene))
        }
    }
}

/// How far a toned view's tones may be left under the scene's light ([`tones::Luminance::outside`])
/// before [`turn_on_tones`] also tries the lights its brightest tone points to (each costs a
/// reading of the tones, 0.12–0.14 s at 512²). Clean toned paintings are held to
/// 0.0000–0.0006, brushed ones with every fault to 0.02–0.05, and the glossy ones painted 10°
/// off to 0.19–0.36 (the faults study).
const UNEXPLAINED_TONES: f64 = 0.1;

/// Loads each (scene, painting) pair as a view and checks they paint one model (thesis
/// 4.4). A painting made on the sheet's page loses the page's own pixels (its lines and its
/// untouched white: [`crate::sample::page`]). Errors name the file.
pub fn load_views(sampler: &mut SceneSampler, pairs: &[(PathBuf, PathBuf)], erosion: Erosion) -> Result<Loaded> {
    let mut loaded = Loaded { views: Vec::new(), gbuffers: Vec::new(), notes: Vec::new() };
    let mut first = None;
    for (scene_path, image_path) in pairs {
        let (scene, view, gbuffer, left) = sampler.load_painted_view(scene_path, image_path, erosion)?;
        if let Some(left) = left {
            loaded.notes.push(left.describe(&view.name));
        }
        match &first {
            None => first = Some((scene, scene_path.display().to_string())),
            Some((f, name)) => check_same_model(f, name, &scene, &scene_path.display().to_string())?,
        }
        loaded.views.push(view);
        loaded.gbuffers.push(gbuffer);
    }
    Ok(loaded)
}

/// A prepared system and one solve on it.
pub struct Solved {
    pub prepared: Prepared,
    pub fit: Fit,
    /// What the cache did (`Uncached` when no cache was given).
    pub outcome: Outcome,
    /// Seconds to prepare (or load from the cache) and to solve.
    pub prepare_s: f64,
    pub solve_s: f64,
}

/// Prepare (through `cache` when given: a standard scene is prepared once, ever) and solve
/// one product. The prepared system depends only on `samples.pattern` and `settings`.
pub fn solve(samples: &Samples, settings: &Settings, mapping: Mapping, cache: Option<&Cache>) -> Result<Solved> {
    settings.validate()?;
    if samples.is_empty() {
        return Err(Error::input("there are no samples to fit"));
    }
    let start = Instant::now();
    let (prepared, outcome) = match cache {
        Some(c) => c.prepare(&samples.pattern, settings)?,
        None => (crate::factor::prepare(&samples.pattern, settings)?, Outcome::Uncached("no cache".into())),
    };
    let prepare_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let fit = prepared.solve(&samples.values, mapping)?;
    let solve_s = start.elapsed().as_secs_f64();
    Ok(Solved { prepared, fit, outcome, prepare_s, solve_s })
}

/// A fitted material and everything a caller reports about it.
pub struct Fitted {
    pub material: Material,
    pub samples: Samples,
    /// The uniform product's system and solve (a material map's terms are fitted on it).
    pub solved: Solved,
    /// For a material map or hybrid: how its terms were found, and the one-product material
    /// of the same samples, for comparison.
    pub map: Option<(MapReport, Material)>,
}

impl Fitted {
    /// The material's errors on the samples (a material map's own, not its first product's).
    pub fn errors(&self) -> Errors {
        self.material.provenance.errors.unwrap_or(self.solved.fit.errors)
    }

    /// Seconds the material's solve took (a material map's whole term fit).
    pub fn solve_s(&self) -> f64 {
        self.map.as_ref().map_or(self.solved.solve_s, |(r, _)| r.seconds)
    }

    /// Errors of the material against each view's samples.
    pub fn view_errors(&self, views: &[PaintedView]) -> Vec<Errors> {
        report::view_errors(&self.samples, views, &self.material)
    }

    /// The report image: per view, painting | fit | residual.
    pub fn report(&self, views: &[PaintedView]) -> Result<Rgb> {
        report::image(views, &self.material)
    }

    /// The material and its `report.png`, staged for `out`: add files, then commit, and the
    /// directory appears whole or not at all (the user's other files in it are kept).
    pub fn stage(&self, views: &[PaintedView], out: &Path) -> Result<StagedDir> {
        let image = self.report(views)?;
        let staged = stage_material(&self.material, out)?;
        staged.write("report.png", |p| image.write_png(p))?;
        Ok(staged)
    }

    /// Writes the material and its `report.png` into `out`, keeping the run's `inputs` there
    /// ([`StagedDir::keep_inputs`]); the report's path.
    pub fn save(&self, views: &[PaintedView], out: &Path, inputs: &[&Path]) -> Result<PathBuf> {
        let mut staged = self.stage(views, out)?;
        staged.keep_inputs(inputs.iter().copied());
        staged.commit()?;
        Ok(out.join("report.png"))
    }
}

/// Saves a material, keeping the run's `inputs` in `out` and naming `out` in errors that do
/// not name a file themselves.
pub fn save_material(material: &Material, out: &Path, inputs: &[&Path]) -> Result<()> {
    let mut staged = stage_material(material, out)?;
    staged.keep_inputs(inputs.iter().copied());
    staged.commit()
}

/// A material staged for `out` ([`Material::stage`]).
fn stage_material(material: &Material, out: &Path) -> Result<StagedDir> {
    material.stage(out).map_err(|e| match e {
        Error::Io { .. } | Error::Format { .. } => e,
        other => Error::input(format!("{}: {other}", out.display())),
    })
}

/// Fits a material of `opts.kind` to the paintings of `views` (thesis 4.1-4.4), preparing
/// through `cache`. A spatially varying kind needs a mesh with texture coordinates.
pub fn fit(views: &[PaintedView], opts: &Options, cache: Option<&Cache>) -> Result<Fitted> {
    let samples = Samples::gather(views)?;
    if opts.kind != Kind::Uniform && !samples.pattern.has_uv {
        let scene = views.first().map_or("the scene", |v| v.source.as_str());
        return Err(Error::input(format!(
            "{scene}: the model has no texture coordinates, which --kind {} needs (a uv table or coefficient textures)",
            opts.kind.name()
        )));
    }
    // Paintings under side or back light show the angle between light and half vector, which
    // carries Fresnel and grazing terms: a uniform fit of them gets a factor of it.
    let choice = match (opts.difference, opts.kind) {
        (DifferenceChoice::Auto, Kind::Uniform) | (DifferenceChoice::On, _) => opts.difference,
        _ => DifferenceChoice::Off,
    };
    let (settings, added) = choice.apply(&opts.settings, &samples.pattern);
    // Headlit paintings get the light prior (Settings::for_pattern); a material map's terms
    // are not one shading, so their light factors stay free.
    let settings = match opts.kind {
        Kind::Uniform | Kind::FourFactor => settings.for_pattern(&samples.pattern),
        Kind::MaterialMap | Kind::Hybrid => settings,
    };
    let headlit = settings.light_prior.is_some() && opts.settings.light_prior.is_none();
    let solved = solve(&samples, &settings, opts.mapping, cache)?;
    let provenance = provenance(sources(views), Some(solved.fit.errors), samples.len(), solved.prepare_s, solved.solve_s);
    let mut uniform = Material::from_fit(&settings, &solved.fit, provenance.clone())?;
    if opts.kind == Kind::Uniform {
        // The base re-solves on the same prepared system: one more solve, and the lobe's
        // own fit (BENCHMARKS.md: about 58 ms for 7.6k samples, seven lobe families).
        let (p, s) = (&solved.prepared, &samples);
        if let Some(based) = crate::read::lobe::fit_based(p, &s.pattern, &s.values, &solved.fit, &settings, opts.mapping, opts.base, views.len() == 1, provenance.clone())? {
            uniform = based;
        }
    }
    let (material, map) = match opts.kind {
        Kind::Uniform | Kind::FourFactor => (uniform, None),
        Kind::MaterialMap | Kind::Hybrid => {
            // The terms are fitted on the system prepared (and cached) for the uniform fit,
            // with the painted pixel grids filling texture gaps.
            let grids = samples.grids(views);
            let map_opts = MapOptions { mapping: opts.mapping, ..opts.map };
            let (mut m, report) = map::fit(&solved.prepared, &samples.pattern, &samples.values, &grids, &map_opts)?;
            m.provenance = Provenance { errors: Some(report.fitted), solve_s: report.seconds, ..provenance };
            (m, Some((report, uniform)))
        }
    };
    let mut fitted = Fitted { material, samples, solved, map };
    fitted.material.provenance.notes = diagnose(views, &fitted, opts.kind);
    if headlit {
        fitted.material.provenance.notes.push(
            "the paintings are lit from the eye: they show each point under one angle between light, view and normal, so the shading's falloff was given to the light (as cos θ_l) where they leave it open; a second view painted under a side light (--scene S2 --image P2) shows how the material answers a moving light".to_string(),
        );
    }
    if let Some(note) = fresnel_unseen(&fitted) {
        fitted.material.provenance.notes.push(note);
    }
    if added && opts.difference == DifferenceChoice::Auto {
        let [lo, hi] = difference_range(&fitted.samples.pattern);
        fitted.material.provenance.notes.push(format!(
            "the paintings show side or back light: the angle between light and half vector goes from {lo:.0}° to {hi:.0}°, so a factor s(θ_d) was added for Fresnel and grazing terms (--theta-d off leaves it out)"
        ));
    }
    Ok(fitted)
}

/// A note when the material's highlight is a lobe whose Fresnel the paintings cannot show:
/// Schlick's $(1 - \cos\theta_d)^5$ is 4e-5 at 30° and 0.002 at 45°
/// ([`DIFFERENCE_REACH_DEG`]), so paintings lit near the camera leave $k_f$ at 0 and the
/// highlight under rim light too dim. Measured on a GGX $\alpha = 0.05$ sphere (BENCHMARKS.md,
/// "The sharp highlight's rim"): the rim view's peak 0.769 of the truth from the three
/// standard paintings, 0.998 from three that include side and back light.
fn fresnel_unseen(fitted: &Fitted) -> Option<String> {
    let base = fitted.material.terms.first().and_then(|t| t.base)?;
    let [_, reach] = difference_range(&fitted.samples.pattern);
    let lobe = base.specular.iter().sum::<f64>() > 0.0 && base.lobe.fresnel_from_data();
    (lobe && reach < DIFFERENCE_REACH_DEG).then(|| {
        format!(
            "the paintings show light and half vector at most {reach:.0}° apart, too close to see Fresnel: the {} highlight was given none, so under light from the side or behind it stays as bright as head-on where a real glossy material grows brighter; a view painted under side or back light shows by how much",
            base.lobe.name()
        )
    })
}

/// What a user can act on, one line each (they go into the material's provenance): per
/// view, the samples among the pixels that see the object and why the others are not
/// samples; and a warning with a next step when one uniform material does not explain the
/// painting: its error is organized by region on the surface.
pub fn diagnose(views: &[PaintedView], fitted: &Fitted, kind: Kind) -> Vec<String> {
    let mut notes = Vec::new();
    for (k, v) in views.iter().enumerate() {
        let g = &v.geometry;
        let object = g.pixels.iter().filter(|p| p.is_some()).count();
        let usable = g.usable_count();
        let unpainted = (0..g.pixels.len()).filter(|&i| g.usable[i] && !v.painting.painted(i)).count();
        let samples = fitted.samples.per_view.get(k).copied().unwrap_or(0);
        let strays = match g.left_out {
            0 => String::new(),
            n => format!("; {n} left out as stray strokes"),
        };
        notes.push(format!(
            "{}: {samples} samples of the {object} pixels that see the object ({} in the silhouette band, --erode; {unpainted} unpainted{strays})",
            v.name,
            object - usable - g.left_out
        ));
    }
    if let Some(w) = regional_warning(fitted, kind) {
        notes.push(w);
    }
    notes
}

/// The residual of a uniform fit, log(painting / fit) averaged over cells of a 12² uv
/// grid: when the cells' means hold most of its variance and the relative error is
/// large, the painting shows different materials in different places.
fn regional_warning(fitted: &Fitted, kind: Kind) -> Option<String> {
    const CELLS: usize = 12;
    let e = fitted.errors();
    if kind != Kind::Uniform || !fitted.samples.pattern.has_uv || e.rms_relative < 0.1 {
        return None;
    }
    let m = &fitted.material;
    let mut sums = vec![(0.0f64, 0usize); CELLS * CELLS];
    let mut all = Vec::new();
    for (q, v) in fitted.samples.pattern.queries.iter().zip(&fitted.samples.values) {
        let f = crate::brdf::Reflectance::shading(m, q);
        let (a, b) = (v.iter().sum::<f64>(), f.iter().sum::<f64>());
        if a <= 1e-6 || b <= 1e-6 {
            continue;
        }
        let r = (a / b).ln();
        let cell = crate::factor::param::uv_nearest_node(q.uv, CELLS);
        sums[cell].0 += r;
        sums[cell].1 += 1;
        all.push((cell, r));
    }
    if all.len() < 100 {
        return None;
    }
    let mean = all.iter().map(|x| x.1).sum::<f64>() / all.len() as f64;
    let total: f64 = all.iter().map(|x| (x.1 - mean).powi(2)).sum();
    let between: f64 = all.iter().map(|&(c, _)| (sums[c].0 / sums[c].1 as f64 - mean).powi(2)).sum();
    (total > 0.0 && between / total > 0.5).then(|| {
        format!(
            "warning: this does not look like one uniform material: {:.0}% of the error is organized by region on the surface (relative RMS {:.2}); try --kind material-map, with a second view (thesis 4.2, 4.4)",
            100.0 * between / total,
            e.rms_relative
        )
    })
}
