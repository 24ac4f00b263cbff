//! Fits of hand-made paintings: a painting as noisy, stylized evidence of a plausible
//! material (issue 11), solved on the same prepared system as [`Prepared::solve`].
//!
//! The least-squares fit of eq. 3.4 treats every sample as exact. A painting is not: brush
//! texture, strokes over the outline, flat (posterized) tones and a highlight painted a few
//! degrees off are all in the samples. [`Prepared::solve_robust`] changes three things, none
//! of which changes the normal matrix $\mathbf G$ (so the prepare-once / solve-fast split of
//! thesis 3.2.2 holds; a solve is a handful of ~0.1 ms refits):
//!
//! 1. **A robust loss in log space**, by iteratively reweighted least squares in its
//!    *pseudo-observation* (imputation) form. Reweighting would change $\mathbf G$; instead
//!    each iteration replaces the log values $\tilde f_i$ by the prediction plus a clipped
//!    residual, $\tilde f^*_i = (\mathbf A\tilde{\mathbf y})_i + \sigma\,\psi(r_i/\sigma)$,
//!    and re-solves with the prepared $\mathbf G^{-1}$. A fixed point satisfies
//!    $\mathbf A^\top \sigma\psi(\mathbf r/\sigma) = \mathbf R\,\tilde{\mathbf y}$, the
//!    stationarity condition of $\sum_i \rho(r_i) + \tfrac12 \tilde{\mathbf y}^\top\mathbf R
//!    \tilde{\mathbf y}$: the M-estimator itself (Huber's "modified residuals" algorithm).
//!    Huber's $\psi$ first (convex, so the start does not matter), then Tukey's biweight,
//!    which gives a stroke of the wrong colour no weight at all. The scale $\sigma$ is
//!    $1.4826 \times$ the median absolute log residual.
//! 2. **Paint levels as intervals.** When a channel holds few distinct values (a posterized
//!    painting, or any 8-bit one), a sample only says that the true value lies between the
//!    levels' midpoints. The residual is the distance from the prediction to that interval
//!    (zero inside), so inside a flat tone the smoothing decides, and the steps between tones
//!    do not become rings in the tables.
//! 3. **A light prior and a bound.** The light factor's regularization rows (Laplacian and
//!    damping, eq. 3.4) act on $\tilde p - \tilde t$, its deviation from a physical shape
//!    $t(\theta_l)$ ($\cos\theta_l$ above the horizon, falling to a floor below it, in the
//!    mapping's log space) instead of on $\tilde p$. That moves only the right-hand side,
//!    $\mathbf b = \mathbf A^\top\tilde{\mathbf f} + \mathbf R_p \tilde{\mathbf t}$. Where the
//!    painting says nothing, the material then darkens as the light goes behind it; where it
//!    says otherwise (a Gooch painting's cool unlit side), the data wins. Finally every table
//!    is bounded ([`super::bound::bound_log`]): no factor and no rendered value beyond [`BOUND`] times the
//!    painting's largest value, in any refit.

use faer::Mat;

use super::bound::{bound_log, light_prior_rhs, BOUND};
use super::mapping::{LogMap, Mapping};
use super::prepared::{errors, Fit, Prepared};
use crate::error::{Error, Result};


/// How a painting is fitted by [`Prepared::solve_robust`]. `Robust::default()` is the
/// setting chosen by held-out error on faulty paintings (`cargo run --release --example
/// faults`; BENCHMARKS.md, "Hand-made paintings").
#[derive(Clone, Debug, PartialEq)]
pub struct Robust {
    /// IRLS iterations with Huber's $\psi$ ($\psi(r) = \max(-k, \min(k, r))$).
    pub huber: usize,
    /// Then this many with Tukey's biweight ($\psi(r) = r (1 - (r/c)^2)^2$ for $|r| < c$).
    /// Off by default: it rejected highlight samples as well as strokes (held-out median of
    /// the faulty paintings with 3 of them: strays 0.077 against 0.067, noise 0.041 against
    /// 0.026).
    pub tukey: usize,
    /// Huber's $k$, in units of the scale $\sigma$ (1.345: 95% efficiency on Gaussian noise).
    pub huber_k: f64,
    /// Tukey's $c$, in units of $\sigma$ (4.685: 95% efficiency).
    pub tukey_c: f64,
    /// Smallest scale $\sigma$ in natural-log units: a clean render has residuals near zero,
    /// and a small scale clips the residuals of narrow highlights the product cannot follow
    /// exactly (measured: 0.02 and 0.01 raised the worst held-out view of clean paintings
    /// from 0.11 to 0.21 and 0.34; 0.05 keeps it).
    pub min_scale: f64,
    /// Treat values as paint levels (intervals between midpoints) when a channel has at most
    /// this many distinct values; 0 turns it off.
    pub max_levels: usize,
    /// The light prior's floor $\epsilon$: $t(\theta_l) = \max(\cos\theta_l, 0)(1 - \epsilon) +
    /// \epsilon$ times the channel's largest value, mapped. `None`: no prior.
    pub light_prior: Option<f64>,
    /// `Mapping::Auto` keeps `inverted` only when its error is below (1 − margin) × the best
    /// of identity and offset: its per-channel clamp $\max(a - \prod, 0)$ flips hues under
    /// new lights, which no small gain on the painted samples is worth.
    pub inverted_margin: f64,
    /// The bound $K$ of [`super::bound::bound_log`].
    pub bound: f64,
    /// Every 1D factor of a direction holds its nearest reached value where no sample
    /// reaches it (a light further behind the surface, a half vector further from the normal
    /// than the paintings show), instead of the Laplacian's straight-line run in log space,
    /// which turns a toon's tones into colours it never had: for fits without the light
    /// prior, which would shape the light factor there.
    pub hold_unseen: bool,
}

impl Default for Robust {
    fn default() -> Self {
        Robust {
            huber: 8,
            tukey: 0,
            huber_k: 1.345,
            tukey_c: 4.685,
            min_scale: 0.05,
            max_levels: 256,
            light_prior: Some(0.02),
            inverted_margin: 0.15,
            bound: BOUND,
            hold_unseen: false,
        }
    }
}

impl Robust {
    /// No robust loss, no levels, no prior: least squares with the bound only (and the
    /// mapping margin). For comparisons.
    pub fn least_squares() -> Robust {
        Robust { huber: 0, tukey: 0, max_levels: 0, light_prior: None, ..Robust::default() }
    }

    fn validate(&self) -> Result<()> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !(ok(self.huber_k) && ok(self.tukey_c) && ok(self.min_scale) && self.bound.is_finite() && self.bound >= 1.0) {
            return Err(Error::input(format!("robust fit settings out of range: {self:?}")));
        }
        if let Some(e) = self.light_prior {
            if !(e.is_finite() && e > 0.0 && e <= 1.0) {
                return Err(Error::input(format!("light prior floor {e} must be in (0, 1]")));
            }
        }
        Ok(())
    }
}

impl Prepared {
    /// Fit a painting: the robust solve of every candidate mapping, the choice among them
    /// (by a trimmed error, with `inverted` kept only for a clear gain), and bounded tables.
    /// `Fit::errors` are the plain errors on the samples, as [`Prepared::solve`] reports.
    pub fn solve_robust(&self, values: &[[f64; 3]], mapping: Mapping, robust: &Robust) -> Result<Fit> {
        robust.validate()?;
        let max = self.check(values)?;
        let levels = Levels::detect(values, robust.max_levels);
        let mut tried = Vec::new();
        let mut scored: Vec<(f64, Fit)> = Vec::new();
        for map in self.candidates(mapping, values, max)? {
            let y = self.robust_log(values, &map, max, levels.as_ref(), robust);
            let tables = self.split(&y);
            let predicted = self.predict(&tables, &map);
            let errors = errors(&predicted, values);
            tried.push((map, errors));
            let score = trimmed_rms(&predicted, values);
            if score.is_finite() && errors.rms.is_finite() {
                scored.push((score, Fit { tables, map, errors, tried: Vec::new() }));
            }
        }
        let best_plain = scored
            .iter()
            .filter(|(_, f)| !matches!(f.map, LogMap::Inverted { .. }))
            .map(|(s, _)| *s)
            .fold(f64::INFINITY, f64::min);
        let pick = scored
            .into_iter()
            .map(|(s, f)| {
                // Inverted must win by the margin: compare it at its score inflated.
                let s = if matches!(f.map, LogMap::Inverted { .. }) && best_plain.is_finite() {
                    s / (1.0 - robust.inverted_margin).max(1e-6)
                } else {
                    s
                };
                (s, f)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let (_, mut fit) = pick.ok_or_else(|| Error::Numeric("no mapping gave a finite fit".into()))?;
        fit.tried = tried;
        Ok(fit)
    }

    /// The live-painting path: one mapping, robust, bounded, no error pass.
    pub fn solve_robust_tables(&self, values: &[[f64; 3]], map: &LogMap, robust: &Robust) -> Result<Vec<Vec<[f64; 3]>>> {
        robust.validate()?;
        let max = self.check(values)?;
        let levels = Levels::detect(values, robust.max_levels);
        Ok(self.split(&self.robust_log(values, map, max, levels.as_ref(), robust)))
    }

    /// Bounded log-space tables $\tilde{\mathbf y}$ (n × 3) of the robust fit for one mapping.
    fn robust_log(&self, values: &[[f64; 3]], map: &LogMap, max: [f64; 3], levels: Option<&Levels>, robust: &Robust) -> Mat<f64> {
        let (settings, design, _) = self.parts();
        let n = design.rows();
        // Log-space intervals [lo, hi] per sample; lo = hi unless the values are paint levels.
        let mut lo = vec![[0.0f64; 3]; n];
        let mut hi = vec![[0.0f64; 3]; n];
        for (k, v) in values.iter().enumerate() {
            for c in 0..3 {
                let (a, b) = levels.map_or((v[c], v[c]), |l| l.interval(c, v[c]));
                let (a, b) = (map.forward(c, a), map.forward(c, b));
                lo[k][c] = a.min(b);
                hi[k][c] = a.max(b);
            }
        }
        let prior = robust.light_prior.map(|eps| light_prior_rhs(settings, design, map, max, eps));
        let solve = |target: &[[f64; 3]]| -> Mat<f64> {
            let mut b = vec![[0.0; 4]; design.n];
            design.transpose_apply(target, &|_, _| {}, &mut b);
            let mut b = Mat::from_fn(design.n, 3, |r, c| b[r][c]);
            if let Some(p) = &prior {
                b += p;
            }
            self.apply(&b)
        };
        // Start from the midpoints of the intervals: the plain least-squares fit.
        let mid: Vec<[f64; 3]> = lo.iter().zip(&hi).map(|(a, b)| [0, 1, 2].map(|c| 0.5 * (a[c] + b[c]))).collect();
        let mut y = solve(&mid);
        let mut target = mid;
        let mut residual = vec![[0.0f64; 3]; n];
        for it in 0..robust.huber + robust.tukey {
            let pred = self.predict_log(&y);
            for k in 0..n {
                for c in 0..3 {
                    // Distance from the prediction to the sample's interval, signed.
                    residual[k][c] = pred[k][c].clamp(lo[k][c], hi[k][c]) - pred[k][c];
                }
            }
            let scale = mad_scale(&residual, robust.min_scale);
            let tukey = it >= robust.huber;
            for k in 0..n {
                for c in 0..3 {
                    let s = scale[c];
                    let r = residual[k][c] / s;
                    let psi = if tukey {
                        let u = r / robust.tukey_c;
                        if u.abs() < 1.0 { r * (1.0 - u * u).powi(2) } else { 0.0 }
                    } else {
                        r.clamp(-robust.huber_k, robust.huber_k)
                    };
                    target[k][c] = pred[k][c] + s * psi;
                }
            }
            y = solve(&target);
        }
        if robust.hold_unseen {
            hold_unseen(&mut y, settings, design);
        }
        bound_log(&mut y, settings, design, map, max, robust.bound);
        y
    }
}

/// Every 1D direction factor's nodes no sample reaches (data weight under 1, as
/// [`bound_log`] counts them) take the value of the nearest reached node
/// ([`Robust::hold_unseen`]).
fn hold_unseen(y: &mut Mat<f64>, settings: &super::Settings, design: &super::system::Design) {
    let weight = design.node_weights();
    for (j, spec) in settings.factors.iter().enumerate() {
        if spec.dim() != 1 || !matches!(spec.input, super::Input::Light | super::Input::Half | super::Input::View) {
            continue;
        }
        let o = design.offsets[j];
        let reached: Vec<usize> = (0..spec.len()).filter(|&i| weight[o + i] >= 1.0).collect();
        let (Some(&first), Some(&last)) = (reached.first(), reached.last()) else { continue };
        for i in (0..first).chain(last + 1..spec.len()) {
            let from = if i < first { first } else { last };
            for c in 0..3 {
                y[(o + i, c)] = y[(o + from, c)];
            }
        }
    }
}

/// $1.4826 \times$ the median absolute residual per channel (the normal-consistent MAD),
/// at least `floor`. Every fourth sample is enough for a median and a quarter of the cost.
fn mad_scale(residual: &[[f64; 3]], floor: f64) -> [f64; 3] {
    let step = if residual.len() > 4096 { 4 } else { 1 };
    [0, 1, 2].map(|c| {
        let mut a: Vec<f64> = residual.iter().step_by(step).map(|r| r[c].abs()).collect();
        if a.is_empty() {
            return floor;
        }
        let m = a.len() / 2;
        let (_, med, _) = a.select_nth_unstable_by(m, f64::total_cmp);
        (1.4826 * *med).max(floor)
    })
}

/// Linear-space RMS over the 90% of samples the prediction fits best (all channels of a
/// sample together): the mapping choice of a robust fit must not be decided by the strokes
/// it rejected.
fn trimmed_rms(predicted: &[[f64; 3]], values: &[[f64; 3]]) -> f64 {
    let mut e: Vec<f64> =
        predicted.iter().zip(values).map(|(p, v)| (0..3).map(|c| (p[c] - v[c]).powi(2)).sum::<f64>()).collect();
    if e.is_empty() {
        return 0.0;
    }
    let keep = (e.len() * 9).div_ceil(10).max(1);
    e.select_nth_unstable_by(keep - 1, f64::total_cmp);
    (e[..keep].iter().sum::<f64>() / (3 * keep) as f64).sqrt()
}

/// Paint levels: per channel, the sorted distinct values and the boundaries between them.
#[derive(Clone, Debug)]
struct Levels {
    /// Per channel: (value, lower boundary, upper boundary), sorted; empty when the channel
    /// has too many distinct values to be levels.
    channels: [Vec<(f64, f64, f64)>; 3],
}

impl Levels {
    /// Levels of channels with at most `max` distinct values (at least 2), or `None` when no
    /// channel qualifies.
    fn detect(values: &[[f64; 3]], max: usize) -> Option<Levels> {
        if max < 2 {
            return None;
        }
        let channels = [0, 1, 2].map(|c| {
            // Early exit: a smooth painting shows more than `max` values within its first few
            // hundred samples.
            let mut seen = std::collections::HashSet::new();
            for v in values {
                if seen.insert(v[c].to_bits()) && seen.len() > max {
                    return Vec::new();
                }
            }
            let mut x: Vec<f64> = seen.into_iter().map(f64::from_bits).collect();
            if x.len() < 2 {
                return Vec::new();
            }
            x.sort_by(f64::total_cmp);
            // Paint is quantized in display (sRGB) codes, whose midpoints are, nearly, the
            // midpoints of $f^{1/2.2}$. That power mean is homogeneous, so it does not matter
            // that the values were divided by the light's colour.
            const GAMMA: f64 = 2.2;
            let mean = |a: f64, b: f64| (0.5 * (a.powf(1.0 / GAMMA) + b.powf(1.0 / GAMMA))).powf(GAMMA);
            let n = x.len();
            (0..n)
                .map(|k| {
                    let below = if k > 0 { mean(x[k - 1], x[k]) } else { (2.0 * x[0].powf(1.0 / GAMMA) - mean(x[0], x[1]).powf(1.0 / GAMMA)).max(0.0).powf(GAMMA) };
                    let above = if k + 1 < n {
                        mean(x[k], x[k + 1])
                    } else {
                        (2.0 * x[k].powf(1.0 / GAMMA) - mean(x[k - 1], x[k]).powf(1.0 / GAMMA)).powf(GAMMA)
                    };
                    (x[k], below, above)
                })
                .collect()
        });
        channels.iter().any(|c| !c.is_empty()).then_some(Levels { channels })
    }

    /// The interval of value `f` of channel `c`: itself when the channel has no levels.
    fn interval(&self, c: usize, f: f64) -> (f64, f64) {
        let l = &self.channels[c];
        match l.binary_search_by(|x| x.0.total_cmp(&f)) {
            Ok(k) => (l[k].1, l[k].2),
            Err(_) => (f, f),
        }
    }
}
