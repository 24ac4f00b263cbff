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
//!
//! That fit is the plain product. Once the strokes pause, [`PaintSession::poll_full`] runs
//! `brdfpaint fit`'s full path (reading, base) on a worker thread ([`super::full`]);
//! [`PaintSession::material`] shows its material while the paintings are the ones it read.

use std::sync::mpsc;
use std::sync::Arc;
use std::time::Instant;

use super::full::{self, FullFit, FullFits, Landed, Stamp};
use super::view::PaintView;
use crate::error::{Error, Result};
use crate::factor::{self, Errors, Fit, LogMap, Mapping, Pattern, Prepared, Robust, Settings};
use crate::material::{Material, Provenance};

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
    let prepared = factor::prepare(&pattern, &settings_for(settings, &pattern))?;
    let values = painted_values(views, &masks);
    let start = Instant::now();
    let fit = prepared.solve(&values, mapping)?;
    let provenance = provenance(views, &prepared, Some(fit.errors), start.elapsed().as_secs_f64());
    let material = Material::from_fit(prepared.settings(), &fit, provenance)?;
    Ok((fit, material))
}

/// The settings the views are fitted with, as `brdfpaint fit` has them: the session's, a
/// factor of θ_d when the painted views show side or back light
/// ([`factor::DifferenceChoice::Auto`]), and the light prior when they are headlit
/// ([`Settings::for_pattern`]).
fn settings_for(settings: &Settings, pattern: &factor::Pattern) -> Settings {
    factor::DifferenceChoice::Auto.apply(settings, pattern).0.for_pattern(pattern)
}

fn provenance(views: &[&PaintView], prepared: &Prepared, errors: Option<Errors>, solve_s: f64) -> Provenance {
    let sources = views.iter().map(|v| format!("painting of view '{}'", v.name)).collect();
    crate::pipeline::provenance(sources, errors, prepared.samples(), prepared.prepare_s, solve_s)
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

/// A prepare running on a background thread. It is always for the session's current
/// settings and views: [`PaintSession::set_settings`], [`PaintSession::add_view`] and
/// [`PaintSession::replace_view`] drop it (the thread's send then fails and its result is
/// discarded), so nothing that arrives can be stale.
struct Pending {
    masks: Vec<Vec<u32>>,
    versions: Vec<u64>,
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
    /// Moves whenever the views, the settings or the mapping change ([`Stamp`]).
    epoch: u64,
    /// `brdfpaint fit`'s fit of the paintings, on a worker once the strokes pause.
    full: FullFits,
    /// A robust solve instead of least squares (a stylized lit sphere's), its light prior
    /// the prepared settings'.
    robust: Option<Robust>,
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
            epoch: 0,
            full: FullFits::default(),
            robust: None,
        }
    }

    /// Solves robustly with `robust` from now on (`None`: least squares), as
    /// `pipeline::Options::robust` has `brdfpaint fit` solve.
    pub fn set_robust(&mut self, robust: Option<Robust>) {
        if robust != self.robust {
            self.robust = robust;
            self.chosen = None;
            self.epoch += 1;
        }
    }

    /// The robust settings for a solve of `prepared` ([`PaintSession::set_robust`]).
    fn robust_for(&self, prepared: &Prepared) -> Option<Robust> {
        self.robust.clone().map(|r| Robust { light_prior: prepared.settings().light_prior, ..r })
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
            self.epoch += 1;
        }
        Ok(())
    }

    /// A new mapping: takes effect at the next refit (no prepare needed).
    pub fn set_mapping(&mut self, mapping: Mapping) {
        self.mapping = mapping;
        self.chosen = None;
        self.epoch += 1;
    }

    /// Adds a view; returns its index.
    pub fn add_view(&mut self, view: PaintView) -> usize {
        self.views.push(view);
        // The views changed: whatever was prepared no longer lines up.
        self.system = None;
        self.pending = None;
        self.epoch += 1;
        self.views.len() - 1
    }

    /// Puts `view` in place of view `k` (the same scene at another size: a painting of
    /// another size arrived) and returns the old one. `None` when there is no view `k`.
    pub fn replace_view(&mut self, k: usize, view: PaintView) -> Option<PaintView> {
        let old = std::mem::replace(self.views.get_mut(k)?, view);
        // The slots changed: whatever was prepared no longer lines up.
        self.system = None;
        self.pending = None;
        self.epoch += 1;
        Some(old)
    }

    /// The current material, if anything has been fitted: `brdfpaint fit`'s of the
    /// paintings as they are ([`PaintSession::full_fit`]) when it has landed, else the live
    /// refit's plain product.
    pub fn material(&self) -> Option<&Material> {
        self.full_fit().map(|f| &f.material).or(self.material.as_ref())
    }

    /// The live refit's material (the plain product on the prepared system), full fit or not.
    pub fn live_material(&self) -> Option<&Material> {
        self.material.as_ref()
    }

    /// The state of the paintings: the epoch and every canvas's version.
    pub fn stamp(&self) -> Stamp {
        Stamp { epoch: self.epoch, versions: self.views.iter().map(|v| v.canvas.version()).collect() }
    }

    /// The full fit (reading, base, notes) of the paintings as they are, if it has landed.
    pub fn full_fit(&self) -> Option<&FullFit> {
        self.full.current(&self.stamp())
    }

    /// Turns the full fit on (the default) or off (a session `fit` does not fit as scenes:
    /// a lit sphere's).
    pub fn set_full_fit(&mut self, on: bool) {
        self.full.off = !on;
    }

    /// Whether the paintings as they are still wait for a full fit (one runs, or one starts
    /// after the pause): a caller keeps polling.
    pub fn full_owed(&self) -> bool {
        self.any_paint() && self.full.owed(&self.stamp())
    }

    /// The full fit's step at `now`: takes a finished fit (shown when it is of the paintings
    /// as they are, dropped otherwise), and starts one when the paintings have not changed
    /// for [`full::PAUSE`] and no stroke is in progress. `Ok(true)` when a fit landed that
    /// [`PaintSession::material`] now shows. Errors: the fit failed (the live material stays).
    pub fn poll_full(&mut self, now: Instant) -> Result<bool> {
        let stamp = self.stamp();
        let landed = self.full.take(&stamp, false)?;
        self.full.observe(&stamp, now);
        let stroking = self.views.iter().any(|v| v.canvas.stroking());
        if !stroking && self.any_paint() && self.full.due(&stamp, now) {
            self.start_full();
        }
        Ok(matches!(landed, Landed::Current))
    }

    /// Starts the full fit of the paintings as they are now, without waiting for a pause
    /// (nothing when one runs already). Nothing painted: the fit fails with that error.
    pub fn start_full(&mut self) {
        let opts = full::options(&self.settings, self.mapping);
        self.full.start(self.stamp(), &self.views, opts);
    }

    /// Takes a finished full fit without waiting: `Ok(true)` when it is of the paintings as
    /// they are and is now shown; `Ok(false)` when none has finished, or it is stale (dropped).
    pub fn take_full(&mut self) -> Result<bool> {
        Ok(matches!(self.full.take(&self.stamp(), false)?, Landed::Current))
    }

    /// Waits for the running full fit, if any. `Ok(true)` when it is of the paintings as
    /// they are and is now shown; `Ok(false)` when there was none or the paintings changed
    /// since it started (dropped). For tests and benchmarks; the viewer polls.
    pub fn wait_full(&mut self) -> Result<bool> {
        Ok(matches!(self.full.take(&self.stamp(), true)?, Landed::Current))
    }

    /// The current fit (tables and mapping).
    pub fn fit(&self) -> Option<&Fit> {
        self.fit.as_ref()
    }

    /// Painted samples over all views.
    pub fn painted(&self) -> usize {
        self.views.iter().map(|v| v.painted_slots().len()).sum()
    }

    /// Whether some pixel of some view is painted.
    fn any_paint(&self) -> bool {
        self.views.iter().any(|v| v.canvas.painting().alpha.iter().any(|&a| a > 0.0))
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
        let Some(p) = self.pending.take() else { return Ok(()) };
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
        let settings = settings_for(&self.settings, &pattern);
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            // A dropped receiver (settings or views changed meanwhile) discards the result.
            let _ = tx.send(factor::prepare(&pattern, &settings));
        });
        self.pending = Some(Pending { masks, versions, rx });
    }

    /// The mapping of a fast refit. The user's, with constants for these values; under
    /// `auto`, the one the last full solve chose, constants and all, so a stroke moves the
    /// material only as much as its paint does. An inverted mapping is kept only while every
    /// value stays below its constant with the default headroom: paint brighter than that
    /// would sit next to the singularity of $\log(a - f)$ and swing the whole fit, so those
    /// refits use the offset mapping until the full solve at the stroke's end chooses again.
    fn live_map(&self, prepared: &factor::Prepared, values: &[[f64; 3]], max: [f64; 3]) -> Result<LogMap> {
        if self.mapping != Mapping::Auto {
            return Ok(prepared.candidates(self.mapping, values, max)?[0]);
        }
        match self.chosen {
            Some(LogMap::Inverted { a }) if (0..3).all(|c| max[c] * crate::factor::mapping::INVERTED_DEFAULT <= a[c]) => {
                Ok(LogMap::Inverted { a })
            }
            Some(m @ (LogMap::Identity { .. } | LogMap::Offset { .. })) => Ok(m),
            _ => Ok(prepared.candidates(Mapping::Offset(None), values, max)?[0]),
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
        let map = self.live_map(&system.prepared, &values, max)?;
        let tables = match self.robust_for(&system.prepared) {
            Some(r) => system.prepared.solve_robust_tables(&values, &map, &r)?,
            None => system.prepared.solve_tables(&values, &map)?,
        };
        let fit = Fit { tables, map, errors: Errors::default(), tried: Vec::new() };
        let views: Vec<&PaintView> = self.views.iter().collect();
        let solve_s = t1.elapsed().as_secs_f64();
        let material = Material::from_fit(system.prepared.settings(), &fit, provenance(&views, &system.prepared, None, solve_s))?;
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
        let fit = match self.robust_for(&system.prepared) {
            Some(r) => system.prepared.solve_robust(&values, self.mapping, &r)?,
            None => system.prepared.solve(&values, self.mapping)?,
        };
        let solve_s = t1.elapsed().as_secs_f64();
        let material =
            Material::from_fit(system.prepared.settings(), &fit, provenance(&views, &system.prepared, Some(fit.errors), solve_s))?;
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
