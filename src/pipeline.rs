//! The one path from paintings to a material (DESIGN.md, Data flow). `brdfpaint fit` (scenes
//! and lit spheres) and the demo go through here; the command line only parses and prints.
//! Live painting ([`crate::live`]) refits on a prepared system it keeps current in the
//! background, with this module's settings rule and provenance; once the strokes pause it
//! runs [`Loaded::read_and_fit`] on a worker thread, so the window settles on the material
//! `brdfpaint fit` writes (tests/live_full_fit.rs).
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
use crate::factor::{defaults, difference_range, DifferenceChoice, DIFFERENCE_REACH_DEG, Errors, Fit, Mapping, Prepared, Robust, Settings};
use crate::images::Rgb;
use crate::material::map::{self, MapOptions, MapReport};
use crate::material::{Kind, Material, Provenance};
use crate::render::GBuffer;
use crate::note::Note;
use crate::read::lobe::{fit_based, Blocks, Judged};
use crate::read::{Reader, Reading};
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
    /// `None` by default (the demo and lit spheres fit the plain product); `brdfpaint fit`
    /// passes its `--base`, `auto` unless told, and live painting settles on `auto`.
    pub base: BaseChoice,
    /// Whether the product gets a factor of $\theta_d$ ([`DifferenceChoice`], issue 15):
    /// `auto` adds it to a uniform fit whose paintings show side or back light.
    pub difference: DifferenceChoice,
    /// A robust solve of the product ([`Prepared::solve_robust`]) instead of least squares:
    /// `None` by default; a stylized lit sphere asks for one.
    pub robust: Option<Robust>,
    /// Whether a lit sphere whose fit takes colours the picture does not have under moved
    /// lights is fitted again with coupled channels and with the identity mapping
    /// ([`crate::litsphere::colours`]). On by default; `brdfpaint fit` turns it off when
    /// told the channels or the mapping.
    pub keep_colours: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options { kind: Kind::Uniform, settings: Settings::default(), mapping: Mapping::Auto, map: MapOptions::default(), base: BaseChoice::None, difference: DifferenceChoice::Auto, robust: None, keep_colours: true }
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
        Ok(Options { kind, settings, mapping: Mapping::Auto, map, ..Options::default() })
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
    /// What was left out of a painting and why, and how it was read.
    pub notes: Vec<Note>,
}

impl Loaded {
    /// Reads the paintings for a fit of `kind` as evidence ([`Reader`]); the notes join the
    /// load's. A spatially varying painting is not one product: its residual says nothing
    /// about the light and its regions' tones are not one shading, so only the uniform kinds
    /// are read.
    pub fn read(&mut self, reading: &Reading, kind: Kind) -> Result<()> {
        if !matches!(kind, Kind::Uniform | Kind::FourFactor) {
            return Ok(());
        }
        let gbuffers: Vec<&GBuffer> = self.gbuffers.iter().collect();
        let evidence = Reader::new(*reading, &gbuffers).read(std::mem::take(&mut self.views))?;
        self.views = evidence.views;
        self.notes.extend(evidence.notes);
        Ok(())
    }

    /// Reads the paintings ([`Loaded::read`]) and fits them ([`fit`]), the load's and the
    /// reading's notes before the fit's: what `brdfpaint fit` makes of loaded views, and
    /// what live painting settles on. Returns the views as read.
    pub fn read_and_fit(mut self, reading: &Reading, opts: &Options, cache: Option<&Cache>) -> Result<(Vec<PaintedView>, Fitted)> {
        self.read(reading, opts.kind)?;
        let mut fitted = fit(&self.views, opts, cache)?;
        fitted.prepend_notes(&self.notes);
        Ok((self.views, fitted))
    }
}

/// Loads each (scene, painting) pair as a view and checks they paint one model (thesis
/// 4.4). A painting made on the sheet's page loses the page's own pixels (its lines and its
/// untouched white: [`crate::sample::page`]). Errors name the file.
pub fn load_views(sampler: &mut SceneSampler, pairs: &[(PathBuf, PathBuf)], erosion: Erosion) -> Result<Loaded> {
    let mut loaded = Loaded { views: Vec::new(), gbuffers: Vec::new(), notes: Vec::new() };
    let mut first = None;
    for (scene_path, image_path) in pairs {
        let (scene, view, gbuffer, left) = sampler.load_painted_view(scene_path, image_path, erosion)?;
        if let Some(left) = left {
            loaded.notes.push(left.note(&view.name));
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
    solve_as(samples, settings, mapping, None, cache)
}

/// [`solve`], robust when `robust` is given (its light prior the settings').
fn solve_as(samples: &Samples, settings: &Settings, mapping: Mapping, robust: Option<&Robust>, cache: Option<&Cache>) -> Result<Solved> {
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
    let fit = match robust {
        Some(r) => prepared.solve_robust(&samples.values, mapping, &Robust { light_prior: settings.light_prior, ..r.clone() })?,
        None => prepared.solve(&samples.values, mapping)?,
    };
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
    /// What the fit tells the user (also in the material's provenance, as lines).
    pub notes: Vec<Note>,
}

impl Fitted {
    /// Sets the fit's notes, in the material's provenance too.
    pub fn set_notes(&mut self, notes: Vec<Note>) {
        self.material.provenance.notes = notes.iter().map(Note::to_string).collect();
        self.notes = notes;
    }

    /// Puts `notes` (how the paintings were read) before the fit's own.
    pub fn prepend_notes(&mut self, notes: &[Note]) {
        let mut all = notes.to_vec();
        all.append(&mut self.notes);
        self.set_notes(all);
    }

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
            "{scene}: the model has no texture coordinates, which a {} material needs (a uv table or coefficient textures)",
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
    let solved = solve_as(&samples, &settings, opts.mapping, opts.robust.as_ref(), cache)?;
    let provenance = provenance(sources(views), Some(solved.fit.errors), samples.len(), solved.prepare_s, solved.solve_s);
    let mut uniform = Material::from_fit(&settings, &solved.fit, provenance.clone())?;
    if opts.kind == Kind::Uniform {
        // The base re-solves on the same prepared system: one more solve, and the lobe's
        // own fit (BENCHMARKS.md: about 58 ms for 7.6k samples, seven lobe families).
        let (p, s) = (&solved.prepared, &samples);
        let widths: Vec<usize> = views.iter().map(|v| v.geometry.width).collect();
        let blocks = Blocks::of_pixels(&s.origin, &widths);
        let judged = Judged { pattern: &s.pattern, values: &s.values, blocks: &blocks };
        if let Some(based) = fit_based(p, judged, &settings, opts.mapping, opts.base, cache, provenance.clone())? {
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
    let mut fitted = Fitted { material, samples, solved, map, notes: Vec::new() };
    let mut notes = diagnose(views, &fitted, opts.kind);
    if headlit {
        notes.push(Note::Headlit);
    }
    notes.extend(fresnel_unseen(&fitted));
    if added && opts.difference == DifferenceChoice::Auto {
        let [lo, hi] = difference_range(&fitted.samples.pattern);
        notes.push(Note::DifferenceFactor { lo_deg: lo, hi_deg: hi });
    }
    fitted.set_notes(notes);
    Ok(fitted)
}

/// A note when the material's highlight is a lobe whose Fresnel the paintings cannot show:
/// Schlick's $(1 - \cos\theta_d)^5$ is 4e-5 at 30° and 0.002 at 45°
/// ([`DIFFERENCE_REACH_DEG`]), so paintings lit near the camera leave $k_f$ at 0 and the
/// highlight under rim light too dim, or at a dielectric's where the lobe reads as one
/// ([`crate::brdf::lobe_fit`]). Measured on a GGX $\alpha = 0.05$ sphere with a coloured
/// $F_0$ (docs/notes/history.md, "The sharp highlight's rim"): the rim view's peak 0.769 of
/// the truth from the three standard paintings, 0.998 from three that include side and back
/// light.
fn fresnel_unseen(fitted: &Fitted) -> Option<Note> {
    let base = fitted.material.terms.first().and_then(|t| t.base)?;
    let [_, reach] = difference_range(&fitted.samples.pattern);
    let lobe = base.specular.iter().sum::<f64>() > 0.0 && base.lobe.fresnel_from_data();
    // The lobe fit gave a dielectric's rise, k_f = 24 k_s; a conductor's k_f/k_s = (1 − F_0)/F_0
    // is at most 1 (F_0 ≥ 0.5).
    let dielectric = (0..3).all(|c| base.fresnel[c] > base.specular[c]);
    (lobe && reach < DIFFERENCE_REACH_DEG).then(|| Note::FresnelUnseen { reach_deg: reach, lobe: base.lobe.name(), dielectric })
}

/// What a user can act on, one line each (they go into the material's provenance): per
/// view, the samples among the pixels that see the object and why the others are not
/// samples; and a warning with a next step when one uniform material does not explain the
/// painting: its error is organized by region on the surface.
pub fn diagnose(views: &[PaintedView], fitted: &Fitted, kind: Kind) -> Vec<Note> {
    let mut notes = Vec::new();
    for (k, v) in views.iter().enumerate() {
        let g = &v.geometry;
        let object = g.pixels.iter().filter(|p| p.is_some()).count();
        let usable = g.usable_count();
        let unpainted = (0..g.pixels.len()).filter(|&i| g.usable[i] && !v.painting.painted(i)).count();
        let samples = fitted.samples.per_view.get(k).copied().unwrap_or(0);
        let silhouette = object - usable - g.left_out;
        notes.push(Note::Samples { painting: v.name.clone(), samples, object, silhouette, unpainted, strays: g.left_out });
    }
    notes.extend(regional_warning(fitted, kind));
    notes
}

/// The residual of a uniform fit, log(painting / fit) averaged over cells of a 12² uv
/// grid: when the cells' means hold most of its variance and the relative error is
/// large, the painting shows different materials in different places.
fn regional_warning(fitted: &Fitted, kind: Kind) -> Option<Note> {
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
    (total > 0.0 && between / total > 0.5).then(|| Note::Regional { percent: 100.0 * between / total, rms: e.rms_relative })
}
