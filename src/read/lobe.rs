//! Which lobe, if any, a painting gets under the product ([`crate::material::based`]), and
//! how much of the product's correction over it is kept: told apart by how well each
//! candidate predicts parts of the painting it was not fitted to.
//!
//! A painting departs from any smooth material: brush texture, paper grain, noise. That
//! departure is spatially correlated (strokes run across many pixels) and it is the
//! painting's, not the material's: a new light does not move it. So the model of a painting
//! is *a smooth material plus correlated paint noise of unknown scale*, and the material is
//! the candidate that best predicts blocks of the painting held out from its fit
//! (spatial-block cross-validation, [`Blocks`]): noise a candidate fitted in one block does
//! not recur in another, while shading does. The candidates, simplest first:
//!
//! - the lobe of the family that fits best ([`crate::brdf::lobe_fit`]), alone;
//! - the lobe with the product's correction over it at weight $w$: the product fitted to
//!   $(S/B)^w$, for $w$ in [`WEIGHTS`];
//! - the product alone (the thesis's).
//!
//! Prepare stays free of pixel values (DESIGN.md): the held-out fits of the product are
//! solved on one prepared system ([`crate::factor::Prepared::solve_log`]), each block's
//! values imputed by the fit's own prediction until it is the fit without them.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::brdf::lobe::Base;
use crate::brdf::lobe_fit::misfit;
use crate::error::{Error, Result};
use crate::factor::cache::Cache;
use crate::factor::{prepare, Mapping, Pattern, Prepared, Settings};
use crate::material::based::{solve_on_base, BasedFit, RATIO_SOFTENING};

/// Which base a fit uses (`fit --base`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BaseChoice {
    /// The thesis's plain product.
    None,
    /// A GGX lobe under the product, always.
    Ggx,
    /// The candidate (module documentation) that predicts held-out blocks of the paintings
    /// best: the default.
    #[default]
    Auto,
}

impl FromStr for BaseChoice {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "none" => Ok(BaseChoice::None),
            "ggx" => Ok(BaseChoice::Ggx),
            "auto" => Ok(BaseChoice::Auto),
            _ => Err(Error::input(format!("unknown base '{s}': expected auto, none or ggx"))),
        }
    }
}

impl fmt::Display for BaseChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BaseChoice::None => "none",
            BaseChoice::Ggx => "ggx",
            BaseChoice::Auto => "auto",
        })
    }
}

/// The weights of the product's correction over the lobe that are tried (0, the lobe alone,
/// is tried too): a quarter of the correction in log space up to all of it.
pub const WEIGHTS: [f64; 3] = [0.25, 0.5, 1.0];

/// Folds of the cross-validation: each holds a fifth of the cells, so every fit sees four
/// fifths of the painting.
const FOLDS: usize = 5;

/// Cells across a view: a cell spans an eighth of the picture, wider than the strokes that
/// paint an object filling it (a stroke is a few percent of the object), so a stroke's
/// noise stays in one cell and cannot be predicted from another.
const CELLS_ACROSS: usize = 8;

/// At most this many samples (every k-th) judge the candidates: every sample of a 128²
/// painting, every second of a 256² one.
const JUDGED_SAMPLES: usize = 20_000;

/// Rounds of imputation per held-out fit: the held-out fifth's values are a fifth of the
/// information, so each round shrinks the error of the imputed fit about fivefold.
const IMPUTATION_ROUNDS: usize = 8;

/// Which fold each sample is held out in.
#[derive(Clone, Debug, PartialEq)]
pub struct Blocks {
    fold: Vec<u8>,
}

impl Blocks {
    /// Cells of [`CELLS_ACROSS`] per view's width, from each sample's view and pixel
    /// (`origin`, as [`crate::sample::Samples::origin`]) in views `widths` wide; the folds
    /// assigned in a Latin pattern, so each fold's cells are spread over every view.
    pub fn of_pixels(origin: &[(usize, usize)], widths: &[usize]) -> Blocks {
        let fold = origin
            .iter()
            .map(|&(v, p)| {
                let w = widths.get(v).copied().unwrap_or(1).max(1);
                let cell = w.div_ceil(CELLS_ACROSS).max(1);
                let (x, y) = ((p % w) / cell, (p / w) / cell);
                ((x + 2 * y + 3 * v) % FOLDS) as u8
            })
            .collect();
        Blocks { fold }
    }

    /// For samples without pixels (measured data, sample lists): cells of the half
    /// vector's direction, eight across its parabolic map, in the same Latin pattern.
    pub fn of_directions(pattern: &Pattern) -> Blocks {
        let fold = pattern
            .queries
            .iter()
            .map(|q| {
                let h = (q.l + q.v).normalize_or(glam::DVec3::Z);
                let cell = |x: f64| ((x / (1.0 + h.z.abs()) + 1.0) * 0.5 * CELLS_ACROSS as f64).floor().max(0.0) as usize;
                ((cell(h.x) + 2 * cell(h.y)) % FOLDS) as u8
            })
            .collect();
        Blocks { fold }
    }

    /// The blocks of every `stride`-th sample.
    fn every(&self, stride: usize) -> Blocks {
        Blocks { fold: self.fold.iter().step_by(stride).copied().collect() }
    }

    fn held(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        self.fold.iter().enumerate().filter(move |(_, &g)| g as usize == f).map(|(i, _)| i)
    }
}

/// What [`choose`] keeps: a lobe and the weight of the product's correction over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    pub base: Base,
    pub weight: f64,
}

/// A candidate of [`choose`] (`None`: the product alone) with its held-out predictions
/// (`None`: a fold could not be fitted).
type Candidate = (Option<Chosen>, Option<Vec<[f64; 3]>>);

/// The lobe `choice` gives for `values` on `pattern`, with the weight of the product's
/// correction over it; `None` for the product alone. Under `auto`, the candidate whose fits
/// without each fold of `blocks` predict that fold best, in the relative measure of
/// [`misfit`](crate::brdf::lobe_fit::misfit); the held-out fits are judged on a default product prepared through `cache`.
pub fn choose(pattern: &Pattern, values: &[[f64; 3]], blocks: &Blocks, choice: BaseChoice, cache: Option<&Cache>) -> Result<Option<Chosen>> {
    match choice {
        BaseChoice::None => Ok(None),
        BaseChoice::Ggx => Ok(Base::fit(pattern, values).map(|(base, _)| Chosen { base, weight: 1.0 })),
        BaseChoice::Auto => {
            let Some((base, _)) = Base::fit_any(pattern, values) else { return Ok(None) };
            let judge = Judge::new(pattern, values, blocks, cache)?;
            // Simplest first: the lobe alone, more and more of the product's correction, the
            // product alone.
            let mut candidates: Vec<Candidate> = Vec::new();
            for weight in std::iter::once(0.0).chain(WEIGHTS) {
                candidates.push((Some(Chosen { base, weight }), judge.lobe(&base, weight)));
            }
            candidates.push((None, Some(judge.product())));
            let scores = judge.scores(&candidates);
            let scored: Vec<(Option<Chosen>, f64)> = candidates.iter().map(|c| c.0).zip(scores).collect();
            Ok(best_predictor(&scored))
        }
    }
}

/// The candidate that predicts the held-out paint best; of candidates that tie, the
/// simplest.
fn best_predictor<T: Copy>(candidates: &[(T, f64)]) -> T {
    let best = candidates.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    // Misfits closer than a tenth of a 16-bit code (1.5e-5 of white) differ by rounding
    // alone: clean paintings.
    candidates.iter().find(|c| c.1 <= best + 1e-6).map_or(candidates[0].0, |c| c.0)
}

/// The cross-validation of [`choose`] on every k-th sample ([`JUDGED_SAMPLES`]).
struct Judge {
    pattern: Pattern,
    values: Vec<[f64; 3]>,
    blocks: Blocks,
    prepared: Prepared,
    /// The ratio's softening per channel ([`RATIO_SOFTENING`] of the largest value).
    eps: [f64; 3],
}

impl Judge {
    fn new(pattern: &Pattern, values: &[[f64; 3]], blocks: &Blocks, cache: Option<&Cache>) -> Result<Judge> {
        let stride = pattern.len().div_ceil(JUDGED_SAMPLES).max(1);
        let sub = Pattern::new(pattern.queries.iter().step_by(stride).copied().collect(), pattern.has_uv);
        let values: Vec<[f64; 3]> = values.iter().step_by(stride).copied().collect();
        let settings = Settings::default().for_pattern(&sub);
        let prepared = match cache {
            Some(c) => c.prepare(&sub, &settings)?.0,
            None => prepare(&sub, &settings)?,
        };
        let max = values.iter().fold([0.0f64; 3], |m, v| [0, 1, 2].map(|c| m[c].max(v[c])));
        let eps = max.map(|m| (RATIO_SOFTENING * m).max(f64::MIN_POSITIVE));
        Ok(Judge { pattern: sub, values, blocks: blocks.every(stride), prepared, eps })
    }

    /// Every sample as predicted by the product alone fitted without its fold.
    fn product(&self) -> Vec<[f64; 3]> {
        let logs: Vec<[f64; 3]> = self.values.iter().map(|v| [0, 1, 2].map(|c| (v[c] + self.eps[c]).ln())).collect();
        let held = self.held_out_logs(&logs);
        held.iter().map(|h| [0, 1, 2].map(|c| (h[c].exp() - self.eps[c]).max(0.0))).collect()
    }

    /// Every sample as predicted by the lobe of `base`'s family and width, its colours
    /// fitted without the sample's fold, with the product's correction over it at `weight`;
    /// `None` where a fold leaves the lobe nothing to fit.
    fn lobe(&self, base: &Base, weight: f64) -> Option<Vec<[f64; 3]>> {
        let mut predicted = vec![[0.0; 3]; self.values.len()];
        for f in 0..FOLDS {
            let train: Vec<usize> = (0..self.values.len()).filter(|&i| self.blocks.fold[i] as usize != f).collect();
            let pattern = Pattern::new(train.iter().map(|&i| self.pattern.queries[i]).collect(), self.pattern.has_uv);
            let values: Vec<[f64; 3]> = train.iter().map(|&i| self.values[i]).collect();
            let (lobe, _) = Base::fit_lobe_at(&pattern, &values, base.lobe, base.alpha)?;
            let shading: Vec<[f64; 3]> = self.pattern.queries.iter().map(|q| lobe.shading(q)).collect();
            let correction = if weight > 0.0 {
                let logs: Vec<[f64; 3]> =
                    self.values.iter().zip(&shading).map(|(v, b)| [0, 1, 2].map(|c| weight * ((v[c] + self.eps[c]) / (b[c] + self.eps[c])).ln())).collect();
                Some(self.held_out_logs_of(&logs, f))
            } else {
                None
            };
            for i in self.blocks.held(f) {
                let b = shading[i];
                predicted[i] = match &correction {
                    Some(r) => [0, 1, 2].map(|c| ((b[c] + self.eps[c]) * r[i][c].exp() - self.eps[c]).max(0.0)),
                    None => b,
                };
            }
        }
        Some(predicted)
    }

    /// Each candidate's held-out misfit ([`misfit`]), pooled over the folds; a candidate
    /// without predictions scores infinity.
    fn scores(&self, candidates: &[Candidate]) -> Vec<f64> {
        candidates.iter().map(|c| c.1.as_ref().map_or(f64::INFINITY, |p| misfit(&self.values, p))).collect()
    }

    /// Every sample's log value as predicted by the product fitted to `logs` without the
    /// sample's fold.
    fn held_out_logs(&self, logs: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; logs.len()];
        for f in 0..FOLDS {
            let fitted = self.held_out_logs_of(logs, f);
            for i in self.blocks.held(f) {
                out[i] = fitted[i];
            }
        }
        out
    }

    /// The product fitted to `logs` without fold `f`, at every sample: fold `f`'s values
    /// imputed by the fit's own prediction, [`IMPUTATION_ROUNDS`] times (the fixed point is
    /// the least-squares fit without them).
    fn held_out_logs_of(&self, logs: &[[f64; 3]], f: usize) -> Vec<[f64; 3]> {
        let p = &self.prepared;
        let mut y = logs.to_vec();
        let mut predicted = p.predict_log(&p.solve_log(&y));
        for _ in 0..IMPUTATION_ROUNDS {
            for i in self.blocks.held(f) {
                y[i] = predicted[i];
            }
            predicted = p.predict_log(&p.solve_log(&y));
        }
        predicted
    }
}

/// Fit a base of `choice` to `values` on `pattern` ([`choose`], judged on `blocks`), then the
/// product of `prepared` (which must have been prepared on `pattern`) to $S / B$ under
/// `mapping`; the product alone where no lobe is chosen.
pub fn solve_based(prepared: &Prepared, pattern: &Pattern, values: &[[f64; 3]], mapping: Mapping, choice: BaseChoice, blocks: &Blocks) -> Result<BasedFit> {
    match choose(pattern, values, blocks, choice, None)? {
        Some(c) => solve_on_base(prepared, pattern, values, mapping, &c.base, c.weight),
        None => Ok(BasedFit { base: None, fit: prepared.solve(values, mapping)? }),
    }
}

/// The samples of a fit: where they are and what they show, and the blocks they are judged in.
pub struct Judged<'a> {
    pub pattern: &'a Pattern,
    pub values: &'a [[f64; 3]],
    pub blocks: &'a Blocks,
}

/// A uniform material over an analytic base ([`crate::material::based`]): the lobe
/// [`choose`] keeps for `samples`, then the product of `prepared` (prepared on their pattern
/// with `settings`) fitted to $S / B$: the prepared system is the plain fit's, the base
/// changes only the right-hand side. `None` when no lobe is kept: keep the plain fit then.
/// `provenance.errors` is replaced by the based fit's errors on $S$.
pub fn fit_based(
    prepared: &Prepared,
    samples: Judged<'_>,
    settings: &Settings,
    mapping: Mapping,
    choice: BaseChoice,
    cache: Option<&Cache>,
    provenance: crate::material::Provenance,
) -> Result<Option<crate::material::Material>> {
    let Some(c) = choose(samples.pattern, samples.values, samples.blocks, choice, cache)? else {
        return Ok(None);
    };
    let fit = solve_on_base(prepared, samples.pattern, samples.values, mapping, &c.base, c.weight)?;
    let provenance = crate::material::Provenance { errors: Some(fit.fit.errors), ..provenance };
    crate::material::Material::from_based_fit(settings, &fit, provenance).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{Analytic, Reflectance, SphereView};
    use glam::DVec3;

    /// Blocks spread each fold over the picture: every fold holds about a fifth of a
    /// painting's samples, and no cell is split between folds.
    #[test]
    fn blocks_hold_a_fifth_each_in_whole_cells() {
        let w = 64;
        let origin: Vec<(usize, usize)> = (0..w * w).map(|p| (0, p)).collect();
        let blocks = Blocks::of_pixels(&origin, &[w]);
        for f in 0..FOLDS {
            let n = blocks.held(f).count();
            assert!((n as f64 / (w * w) as f64 - 0.2).abs() < 0.03, "fold {f}: {n}");
        }
        // Pixels 0 and 7 share a cell (8 px), pixels 0 and 8 do not.
        assert_eq!(blocks.fold[0], blocks.fold[7]);
        assert_ne!(blocks.fold[0], blocks.fold[8]);
    }

    /// A clean painting of a lobe family's member keeps its lobe with the product's
    /// correction at most a quarter; a painting of no family (Gooch's tone shading) keeps
    /// the product, or a full correction over the lobe.
    #[test]
    fn the_lobe_is_kept_for_its_family_and_not_for_others() {
        let view = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 96);
        let pattern = view.pattern();
        let origin: Vec<(usize, usize)> = view.pixels().into_iter().map(|p| (0, p.pixel[1] * 96 + p.pixel[0])).collect();
        let blocks = Blocks::of_pixels(&origin, &[96]);
        let lambert = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let values = pattern.shade(|q| lambert.shading(q));
        let kept = choose(&pattern, &values, &blocks, BaseChoice::Auto, None).unwrap().expect("a lobe");
        assert!(kept.weight <= 0.25, "{kept:?}");
        let gooch = Analytic::Gooch { warm: [0.9, 0.6, 0.2], cool: [0.1, 0.2, 0.6] };
        let values = pattern.shade(|q| gooch.shading(q));
        let kept = choose(&pattern, &values, &blocks, BaseChoice::Auto, None).unwrap();
        assert!(kept.is_none_or(|k| k.weight == 1.0), "{kept:?}");
    }
}
