//! Prepare once, solve many (thesis 3.2.2).
//!
//! [`prepare`] builds the normal equations $\mathbf G = \mathbf B^\top\mathbf B$ of eq. 3.4 for
//! a sample pattern and factors them. It never sees sample values. [`Prepared::solve`] then
//! maps values to log space, forms $\mathbf b = \mathbf A^\top \tilde{\mathbf f}$ (a sparse
//! scatter) and applies the prepared inverse to three right-hand sides at once (R, G, B).
//!
//! The default pre-factors $\mathbf G$ by Cholesky: dense for the smallest systems (the
//! inverse is kept, so a solve is one matrix product), sparse supernodal otherwise. The
//! thesis's pseudo-inverse variants are available as [`Method`]s; they use
//! the eigendecomposition $\mathbf G = \mathbf V \mathbf S^2 \mathbf V^\top$, whose
//! $\mathbf V$ are the right singular vectors of $\mathbf B$, and expose the change of basis
//! of eqs. 3.10–3.12 through [`Spectral`].

use std::time::Instant;

use faer::{Accum, Mat, Par, Side};

use super::chroma::{self, Coupled, Solve};
use super::mapping::{LogMap, Mapping, IDENTITY_FLOOR};
use super::pattern::{Pattern, Query};
use super::settings::{Channels, Method, Settings};
use super::sparse::{Order, SparseLlt};
use super::system::{self, Design, SymCsc};
use crate::error::{Error, Result};

/// Systems at most this large are factored densely. Above it a supernodal factor wins even
/// where G is a fifth full (three 1D tables): it keeps the fill a dense factor stores as
/// zeros, and needs no inverse, which costs twice the factorization.
const DENSE_MAX: usize = 128;

/// A factored system, ready to solve any values on its pattern.
pub struct Prepared {
    settings: Settings,
    design: Design,
    solver: Solver,
    /// Seconds spent assembling G and factoring it.
    pub prepare_s: f64,
    /// The chroma's system, when the channels are coupled ([`super::chroma`]).
    coupled: Option<Coupled>,
}

impl std::fmt::Debug for Prepared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Prepared")
            .field("samples", &self.samples())
            .field("unknowns", &self.unknowns())
            .field("solver", &self.solver_kind())
            .field("prepare_s", &self.prepare_s)
            .finish()
    }
}

pub(crate) enum Solver {
    /// $\mathbf G^{-1}$, dense.
    Dense(Mat<f64>),
    /// Sparse supernodal Cholesky of $\mathbf G$ (with $\mathbf G$ kept for the cache).
    Sparse(Box<SparseLlt>, SymCsc),
    /// A filtered pseudo-inverse.
    Spectral(Spectral),
}

/// The pseudo-inverse in the change-of-basis form of eqs. 3.10–3.12.
///
/// With $\mathbf B = \mathbf U \mathbf S \mathbf V^\top$ and the filtered weights $\phi_i$
/// of the chosen method, the solution is $\mathbf y^* = \sum_i \beta_i \mathbf v_i$ with
/// $\beta_i = (\phi_i / s_i)\,(\mathbf u_i' \cdot \tilde{\mathbf f})
///         = (\phi_i / s_i^2)\,\mathbf v_i^\top \mathbf A^\top \tilde{\mathbf f}$.
pub struct Spectral {
    /// Basis vectors $\mathbf v_i$ as columns, by descending singular value.
    pub basis: Mat<f64>,
    /// Singular values $s_i$ of $\mathbf B$, descending.
    pub singular: Vec<f64>,
    /// $\phi_i / s_i^2$: the weight of each coefficient.
    pub weight: Vec<f64>,
    /// $\mathbf V \operatorname{diag}(\phi/s^2) \mathbf V^\top$, applied by `solve`.
    operator: Mat<f64>,
}

impl Spectral {
    fn new(g: &SymCsc, method: Method) -> Result<Spectral> {
        let dense = g.to_dense();
        let evd = dense
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Numeric(format!("eigendecomposition failed: {e:?}")))?;
        let n = g.n;
        // faer sorts eigenvalues ascending; the thesis indexes singular values descending.
        let order: Vec<usize> = (0..n).rev().collect();
        let values = evd.S().column_vector();
        let singular: Vec<f64> = order.iter().map(|&i| values[i].max(0.0).sqrt()).collect();
        let basis = Mat::from_fn(n, n, |r, c| evd.U()[(r, order[c])]);
        let s0 = singular[0].max(f64::MIN_POSITIVE);
        let weight: Vec<f64> = singular
            .iter()
            .enumerate()
            .map(|(i, &s)| {
                let s2 = s * s;
                match method {
                    Method::TruncatedSvd { rel_tol } => {
                        if s > rel_tol * s0 && s2 > 0.0 {
                            1.0 / s2
                        } else {
                            0.0
                        }
                    }
                    // eq. 3.8: $s_i / (s_i^2 + \alpha^2)$ times $u_i \cdot g = v_i^\top b / s_i$.
                    Method::DampedSvd { alpha } => {
                        let a = alpha * s0;
                        if s2 + a * a > 0.0 {
                            1.0 / (s2 + a * a)
                        } else {
                            0.0
                        }
                    }
                    // eq. 3.9: $\mathrm{pos}(1 - i\gamma)/s_i$.
                    Method::LinearSvd { gamma } => {
                        let phi = (1.0 - i as f64 * gamma).max(0.0);
                        if s2 > 0.0 {
                            phi / s2
                        } else {
                            0.0
                        }
                    }
                    Method::Cholesky => unreachable!("Cholesky has no spectral form"),
                }
            })
            .collect();
        Ok(Spectral::with_weights(basis, singular, weight))
    }

    /// Assemble from a basis and its weights, forming the operator $\mathbf V
    /// \operatorname{diag}(w) \mathbf V^\top$.
    pub(crate) fn with_weights(basis: Mat<f64>, singular: Vec<f64>, weight: Vec<f64>) -> Spectral {
        let n = basis.nrows();
        let scaled = Mat::from_fn(n, n, |r, c| basis[(r, c)] * weight[c]);
        let mut operator = Mat::zeros(n, n);
        faer::linalg::matmul::matmul(&mut operator, Accum::Replace, &scaled, basis.transpose(), 1.0, Par::rayon(0));
        Spectral { basis, singular, weight, operator }
    }

    /// Coefficients $\beta$ (eq. 3.11) of a right-hand side $\mathbf b = \mathbf A^\top
    /// \tilde{\mathbf f}$ (n × 3).
    pub fn coefficients(&self, b: &Mat<f64>) -> Mat<f64> {
        let mut beta = self.basis.transpose() * b;
        for i in 0..beta.nrows() {
            for c in 0..beta.ncols() {
                beta[(i, c)] *= self.weight[i];
            }
        }
        beta
    }

    /// The solution $\mathbf y^* = \sum_i \beta_i \mathbf v_i$ (eq. 3.12).
    pub fn synthesize(&self, beta: &Mat<f64>) -> Mat<f64> {
        &self.basis * beta
    }
}

/// Prediction errors in linear space (thesis Table 5.4's metrics).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Errors {
    /// Root mean square error over all samples and channels.
    pub rms: f64,
    /// RMS error divided by the RMS of the values.
    pub rms_relative: f64,
    /// Largest absolute error.
    pub max: f64,
}

/// The result of a solve: linear-space factor tables and the mapping they approximate.
#[derive(Clone, Debug)]
pub struct Fit {
    /// Per factor, its table in linear space ($p_j = e^{\tilde p_j}$), RGB, row by row.
    pub tables: Vec<Vec<[f64; 3]>>,
    /// The mapping whose transformed values the product approximates.
    pub map: LogMap,
    /// Errors on the fitted samples.
    pub errors: Errors,
    /// Every mapping tried (one, or three for `auto`) and its errors.
    pub tried: Vec<(LogMap, Errors)>,
}

/// Under [`Mapping::Auto`], `inverted` is kept only when its RMS on the samples is at least
/// this fraction below every other candidate's (issue 11: gains of 0.002 bought hue flips).
pub const INVERTED_MARGIN: f64 = 0.15;

impl Prepared {
    /// The settings this system was prepared with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Number of samples of the pattern.
    pub fn samples(&self) -> usize {
        self.design.rows()
    }

    /// Unknowns per channel (columns of the system).
    pub fn unknowns(&self) -> usize {
        self.design.n
    }

    /// Which factorization was chosen: "dense", "sparse" or "spectral".
    pub fn solver_kind(&self) -> &'static str {
        match self.solver {
            Solver::Dense(_) => "dense",
            Solver::Sparse(..) => "sparse",
            Solver::Spectral(_) => "spectral",
        }
    }

    /// The change-of-basis form, when the method is a pseudo-inverse variant.
    pub fn spectral(&self) -> Option<&Spectral> {
        match &self.solver {
            Solver::Spectral(s) => Some(s),
            _ => None,
        }
    }

    /// Check values: one per sample, finite, non-negative, not all zero. Returns the
    /// per-channel maximum.
    pub(crate) fn check(&self, values: &[[f64; 3]]) -> Result<[f64; 3]> {
        if values.len() != self.samples() {
            return Err(Error::input(format!(
                "{} values for a pattern of {} samples",
                values.len(),
                self.samples()
            )));
        }
        // A branch-free pass first (it vectorizes); only a failure pays for finding the
        // offending sample, so the message can name it.
        let (mut min, mut max, mut probe) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
        for v in values {
            for c in 0..3 {
                // Selects rather than f64::min/max, whose NaN rules keep this loop from
                // vectorizing. `probe` becomes NaN if any value is NaN or infinite.
                min[c] = if v[c] < min[c] { v[c] } else { min[c] };
                max[c] = if v[c] > max[c] { v[c] } else { max[c] };
                probe[c] += v[c] * 0.0;
            }
        }
        let bad = (0..3).any(|c| min[c] < 0.0 || probe[c].is_nan());
        if bad {
            for (k, v) in values.iter().enumerate() {
                if let Some(&x) = v.iter().find(|x| !x.is_finite()) {
                    return Err(Error::input(format!("sample {k} has a non-finite value {x}")));
                }
                if let Some(&x) = v.iter().find(|&&x| x < 0.0) {
                    return Err(Error::input(format!("sample {k} has a negative value {x}")));
                }
            }
        }
        if max.iter().all(|&m| m == 0.0) {
            return Err(Error::input("every sample value is zero: there is nothing to fit"));
        }
        Ok(max)
    }

    /// The right-hand side $\mathbf b = \mathbf A^\top \tilde{\mathbf f}$ of mapped values.
    pub fn rhs(&self, values: &[[f64; 3]], map: &LogMap) -> Mat<f64> {
        self.rhs_with(values, map, true)
    }

    /// [`Prepared::rhs`], with the light prior's shape only when `prior` (and the settings
    /// have one); without it the light factor's damping pulls it flat.
    fn rhs_with(&self, values: &[[f64; 3]], map: &LogMap, prior: bool) -> Mat<f64> {
        let mut b = vec![[0.0; 4]; self.design.n];
        self.design.transpose_apply(values, &|c, x| map.forward_all(c, x), &mut b);
        let mut b = Mat::from_fn(self.design.n, 3, |r, c| b[r][c]);
        if let Some(floor) = self.settings.light_prior.filter(|_| prior) {
            // The light factor's regularization then acts on its deviation from the physical
            // shape (Settings::light_prior): only this side of the system moves.
            let mut max = [0.0f64; 3];
            for v in values {
                for c in 0..3 {
                    max[c] = max[c].max(v[c]);
                }
            }
            b += super::bound::light_prior_rhs(&self.settings, &self.design, map, max, floor);
        }
        b
    }

    /// Log-space tables $\tilde{\mathbf y}$ (n × 3) for a right-hand side: the channels
    /// coupled ([`super::chroma`]) or each on its own.
    pub fn apply(&self, b: &Mat<f64>) -> Mat<f64> {
        match &self.coupled {
            Some(c) => c.apply(self, b),
            None => self.solve_system(b),
        }
    }

    /// $\mathbf G^{-1}\mathbf b$ on this system's own factorization, each column alone.
    pub(crate) fn solve_system(&self, b: &Mat<f64>) -> Mat<f64> {
        let y = match &self.solver {
            Solver::Dense(inv) => {
                let mut y = Mat::zeros(self.design.n, 3);
                let par = if self.design.n > 1500 { Par::rayon(0) } else { Par::Seq };
                faer::linalg::matmul::matmul(&mut y, Accum::Replace, inv, b, 1.0, par);
                y
            }
            Solver::Sparse(llt, _) => {
                let mut y = b.clone();
                llt.solve_in_place(&mut y);
                y
            }
            Solver::Spectral(s) => &s.operator * b,
        };
        crate::util::clear_upper_vector_state();
        y
    }

    /// Solve for one mapping without computing errors: the fast path of live painting.
    /// Bounded like [`Prepared::solve`].
    pub fn solve_tables(&self, values: &[[f64; 3]], map: &LogMap) -> Result<Vec<Vec<[f64; 3]>>> {
        let max = self.check(values)?;
        let mut y = self.apply(&self.rhs(values, map));
        self.bound(&mut y, map, max);
        Ok(self.split(&y))
    }

    /// Keeps a fit from blowing up where the painting is silent (issue 11: two white strokes
    /// once drove q(h) to 1e10, a chrome bunny with black holes). When the product,
    /// evaluated over a grid of light and view directions ([`super::bound::peak`]),
    /// exceeds [`super::bound::BOUND`] × the painting's largest value (+ a for the offset
    /// mapping) in some channel, every node no sample reaches (data weight below 1: its
    /// value is the smoothing's extrapolation) is capped at the highest node the samples do
    /// reach; the fit on the samples stays as it was. If the product is still over, the
    /// samples themselves pull it up, and [`super::bound::bound_log`] bounds it at their
    /// expense. A fit within the bound, as the fit of a consistent painting is, is left
    /// exactly as solved. (Not under `inverted`, bounded by its a: a large product there
    /// means dark.)
    fn bound(&self, y: &mut Mat<f64>, map: &LogMap, max: [f64; 3]) {
        if matches!(map, LogMap::Inverted { .. }) {
            return;
        }
        let top = |c: usize| {
            let a = if let LogMap::Offset { a } = map { a[c] } else { 0.0 };
            (super::bound::BOUND * max[c].max(1e-12) + a).ln()
        };
        // Most fits are under the bound by their largest nodes alone, which is far cheaper
        // than the grid (0.8 ms of a 0.1 ms solve).
        let ceiling = super::bound::ceiling(y, &self.settings, &self.design);
        if (0..3).all(|c| ceiling[c] <= top(c)) {
            return;
        }
        let peaks = super::bound::peak(y, &self.settings, &self.design);
        if (0..3).all(|c| peaks[c] <= top(c)) {
            return;
        }
        let weight = self.design.node_weights();
        for (f, &o) in self.settings.factors.iter().zip(&self.design.offsets) {
            for c in 0..3 {
                let reached = (0..f.len()).filter(|&i| weight[o + i] >= 1.0).map(|i| y[(o + i, c)]).fold(f64::NEG_INFINITY, f64::max);
                if !reached.is_finite() {
                    continue;
                }
                for i in (0..f.len()).filter(|&i| weight[o + i] < 1.0) {
                    let v = &mut y[(o + i, c)];
                    *v = if v.is_nan() { reached } else { v.min(reached) };
                }
            }
        }
        // Still over: the samples themselves pull the product up where they never meet
        // (white strokes across a shaded painting). Then the fit gives way: factors are
        // kept within a range of their mean and the light factor is scaled under the bound.
        let peaks = super::bound::peak(y, &self.settings, &self.design);
        if (0..3).any(|c| peaks[c] > top(c)) {
            super::bound::bound_log(y, &self.settings, &self.design, map, max, super::bound::BOUND);
        }
    }

    /// Log-space tables $\tilde{\mathbf y} = \mathbf G^{-1} \mathbf A^\top \tilde{\mathbf f}$
    /// for values already in log space: for callers that build the log-space right-hand side
    /// themselves (the material-map clustering imputes samples outside a cluster with the
    /// cluster's own log-space prediction, so the fit converges to the cluster's alone).
    pub fn solve_log(&self, log_values: &[[f64; 3]]) -> Mat<f64> {
        let mut b = vec![[0.0; 4]; self.design.n];
        self.design.transpose_apply(log_values, &|_, _| {}, &mut b);
        self.apply(&Mat::from_fn(self.design.n, 3, |r, c| b[r][c]))
    }

    /// The log-space model $\mathbf A \tilde{\mathbf y}$ at every sample.
    pub fn predict_log(&self, y: &Mat<f64>) -> Vec<[f64; 3]> {
        use rayon::prelude::*;
        let d = &self.design;
        // Rows of y as RGB triples: one load per stencil entry instead of three strided ones.
        let yt: Vec<[f64; 3]> = (0..d.n).map(|c| [y[(c, 0)], y[(c, 1)], y[(c, 2)]]).collect();
        let row = |r: usize| {
            let (lo, hi) = (d.row_ptr[r] as usize, d.row_ptr[r + 1] as usize);
            let mut sum = [0.0; 3];
            for (&c, &a) in d.row_col[lo..hi].iter().zip(&d.row_val[lo..hi]) {
                let v = yt[c as usize];
                sum = [sum[0] + a * v[0], sum[1] + a * v[1], sum[2] + a * v[2]];
            }
            sum
        };
        // Threads pay off on large patterns only (as in the scatter of `transpose_apply`).
        if d.rows() < 32_768 {
            (0..d.rows()).map(row).collect()
        } else {
            (0..d.rows()).into_par_iter().with_min_len(8192).map(row).collect()
        }
    }

    /// Split the solution vector into per-factor linear-space tables.
    pub fn split(&self, y: &Mat<f64>) -> Vec<Vec<[f64; 3]>> {
        self.settings
            .factors
            .iter()
            .zip(&self.design.offsets)
            .map(|(f, &o)| (0..f.len()).map(|i| [0, 1, 2].map(|c| y[(o + i, c)].exp())).collect())
            .collect()
    }

    /// Solve: try the mapping's candidates and keep the one with the lowest linear-space
    /// RMS error on the samples (thesis 3.2.3: "try several mappings quickly with a single
    /// pseudo-inverse, and pick the one with the smallest error"), `inverted` only for a clear
    /// gain ([`INVERTED_MARGIN`]). The tables are bounded where the painting is silent
    /// ([`Prepared::bound`]).
    pub fn solve(&self, values: &[[f64; 3]], mapping: Mapping) -> Result<Fit> {
        self.solve_with(values, mapping, true)
    }

    /// [`Prepared::solve`] of a ratio to an analytic base ([`super::base`]): the base holds
    /// the light's falloff, so the light prior's shape ([`Settings::light_prior`]) is not
    /// pulled toward a second time; the light factor's damping pulls it flat instead.
    pub fn solve_ratio(&self, values: &[[f64; 3]], mapping: Mapping) -> Result<Fit> {
        self.solve_with(values, mapping, false)
    }

    fn solve_with(&self, values: &[[f64; 3]], mapping: Mapping, prior: bool) -> Result<Fit> {
        let max = self.check(values)?;
        let mut best: Option<Fit> = None;
        let mut tried = Vec::new();
        // `inverted` (f = a − ∏) must win clearly: its product falls where the data are
        // silent (a light behind the object), so a − ∏ brightens there, and its per-channel
        // clamp flips hues; for a small gain on the samples that is a worse material
        // everywhere else.
        let score = |m: &LogMap, e: &Errors| if matches!(m, LogMap::Inverted { .. }) { e.rms / (1.0 - INVERTED_MARGIN) } else { e.rms };
        for map in self.candidates(mapping, values, max)? {
            let mut y = self.apply(&self.rhs_with(values, &map, prior));
            self.bound(&mut y, &map, max);
            let tables = self.split(&y);
            let errors = self.errors(&tables, &map, values);
            tried.push((map, errors));
            // NaN errors (an overflowing exp) never win.
            if best.as_ref().is_none_or(|b| score(&map, &errors) < score(&b.map, &b.errors)) {
                best = Some(Fit { tables, map, errors, tried: Vec::new() });
            }
        }
        let mut fit = best.ok_or_else(|| Error::Numeric("no mapping gave a finite fit".into()))?;
        if !fit.errors.rms.is_finite() {
            return Err(Error::Numeric("the fit is not finite (values span too many orders of magnitude)".into()));
        }
        fit.tried = tried;
        Ok(fit)
    }

    /// Linear-space prediction at every sample: the product of linearly interpolated
    /// linear-space tables (exactly what the shader computes), mapped back.
    pub fn predict(&self, tables: &[Vec<[f64; 3]>], map: &LogMap) -> Vec<[f64; 3]> {
        let d = &self.design;
        // Which factor a column belongs to.
        let factor_of = |c: usize| d.offsets.partition_point(|&o| o <= c) - 1;
        (0..d.rows())
            .map(|r| {
                let mut prod = [1.0f64; 3];
                let mut current = usize::MAX;
                let mut sum = [0.0f64; 3];
                for k in d.row_ptr[r] as usize..d.row_ptr[r + 1] as usize {
                    let c = d.row_col[k] as usize;
                    let j = factor_of(c);
                    if j != current {
                        if current != usize::MAX {
                            prod = [0, 1, 2].map(|i| prod[i] * sum[i]);
                        }
                        current = j;
                        sum = [0.0; 3];
                    }
                    let t = &tables[j][c - d.offsets[j]];
                    for i in 0..3 {
                        sum[i] += d.row_val[k] * t[i];
                    }
                }
                prod = [0, 1, 2].map(|i| prod[i] * sum[i]);
                [0, 1, 2].map(|i| map.inverse(i, prod[i]))
            })
            .collect()
    }

    /// Errors of tables against values at the samples.
    pub fn errors(&self, tables: &[Vec<[f64; 3]>], map: &LogMap, values: &[[f64; 3]]) -> Errors {
        errors(&self.predict(tables, map), values)
    }

    /// The concrete mappings `mapping` tries for `values` (per-channel largest `max`):
    /// under coupled channels their constants are one colour, the painting's mean
    /// ([`super::chroma`]), so the constant applied after the product keeps the hue.
    pub fn candidates(&self, mapping: Mapping, values: &[[f64; 3]], max: [f64; 3]) -> Result<Vec<LogMap>> {
        match self.coupled {
            Some(_) => mapping.candidates_tinted(max, chroma::tint(values, IDENTITY_FLOOR)),
            None => mapping.candidates(max),
        }
    }

    /// How this system fits the colour channels.
    pub fn channels(&self) -> Channels {
        self.settings.channels
    }

    pub(crate) fn parts(&self) -> (&Settings, &Design, &Solver) {
        (&self.settings, &self.design, &self.solver)
    }

    pub(crate) fn from_parts(settings: Settings, design: Design, solver: Solver, prepare_s: f64) -> Prepared {
        Prepared { settings, design, solver, prepare_s, coupled: None }
    }

    /// The coupled system of `settings` from the luminance's and the chroma's
    /// ([`Settings::luminance`], [`Settings::chroma`]), prepared on the same pattern.
    pub(crate) fn couple(settings: &Settings, luminance: Prepared, chroma: Vec<Prepared>) -> Prepared {
        let prepare_s = luminance.prepare_s + chroma.iter().map(|p| p.prepare_s).sum::<f64>();
        let parts = chroma.into_iter().map(|p| Box::new(p) as Box<dyn Solve + Send + Sync>).collect();
        Prepared { settings: settings.clone(), coupled: Some(Coupled::new(parts)), prepare_s, ..luminance }
    }
}

impl Solve for Prepared {
    fn settings(&self) -> &Settings {
        &self.settings
    }

    fn design(&self) -> &Design {
        &self.design
    }

    fn solve_system(&self, b: &Mat<f64>) -> Mat<f64> {
        Prepared::solve_system(self, b)
    }
}

/// RMS, relative RMS and max error of predictions against values.
pub fn errors(predicted: &[[f64; 3]], values: &[[f64; 3]]) -> Errors {
    let (mut se, mut sv, mut max) = (0.0, 0.0, 0.0f64);
    for (p, v) in predicted.iter().zip(values) {
        for c in 0..3 {
            let e = p[c] - v[c];
            se += e * e;
            sv += v[c] * v[c];
            max = max.max(e.abs());
        }
    }
    let count = (3 * values.len()).max(1) as f64;
    Errors { rms: (se / count).sqrt(), rms_relative: (se / sv.max(f64::MIN_POSITIVE)).sqrt(), max }
}

/// Build and factor the system for a pattern. Depends only on where the samples are.
pub fn prepare(pattern: &Pattern, settings: &Settings) -> Result<Prepared> {
    let start = Instant::now();
    if settings.channels == Channels::Coupled {
        // One sample matrix for all: each chroma system's is one factor's columns of the
        // luminance's (the same stencils; only the regularization differs).
        let luminance = settings.luminance();
        let design = Design::new(pattern, &luminance)?;
        let blocks: Vec<Design> = (0..settings.factors.len()).map(|j| design.factor_block(j)).collect();
        let luminance = prepare_design(design, &luminance, start)?;
        let chroma = blocks.into_iter().zip(settings.chroma()).map(|(d, s)| prepare_design(d, &s, Instant::now())).collect::<Result<Vec<_>>>()?;
        return Ok(Prepared::couple(settings, luminance, chroma));
    }
    prepare_design(Design::new(pattern, settings)?, settings, start)
}

/// Assemble and factor the normal equations of a sample matrix; `start` is when the
/// preparing began (its time is reported).
fn prepare_design(design: Design, settings: &Settings, start: Instant) -> Result<Prepared> {
    let bar = progress_bar(&design);
    let g = system::normal_matrix(&design, settings, bar.as_ref());
    if let Some(bar) = &bar {
        bar.set_message("factoring");
        bar.enable_steady_tick(std::time::Duration::from_millis(100));
    }
    let solver = factor(&g, settings);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    Ok(Prepared { settings: settings.clone(), design, solver: solver?, prepare_s: start.elapsed().as_secs_f64(), coupled: None })
}

/// Unknowns from which a prepare takes long enough (a second or more) to deserve a bar.
const PROGRESS_UNKNOWNS: usize = 8192;

/// A progress bar over the normal matrix's columns, on a terminal and for large systems
/// only (DESIGN.md: long work shows progress, and stays quiet when output is not a terminal).
fn progress_bar(design: &Design) -> Option<indicatif::ProgressBar> {
    if design.n < PROGRESS_UNKNOWNS || !crate::util::progress_enabled() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(design.n as u64);
    let style = indicatif::ProgressStyle::with_template("preparing {bar:30} {pos}/{len} unknowns {msg} {elapsed}")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style);
    Some(bar)
}

/// The error for a Cholesky factorization that met a non-positive pivot.
fn not_spd<E>(_: E) -> Error {
    // The argument is the failing factorization's own error, which says nothing a user can act on.
    Error::Numeric(
        "the normal equations are not positive definite; add smoothing or damping, or check \
         that every factor's table is reached by samples"
            .into(),
    )
}

/// $\mathbf G^{-1}$ by dense Cholesky, on this thread: at these sizes (n ≤ [`DENSE_MAX`])
/// handing blocks to other threads costs more than the whole factorization.
fn dense_inverse(mut g: Mat<f64>) -> Result<Mat<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
    use faer::linalg::cholesky::llt;
    let n = g.nrows();
    let scratch = StackReq::any_of(&[
        llt::factor::cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default()),
        llt::inverse::inverse_scratch::<f64>(n, Par::Seq),
    ]);
    let mut mem = MemBuffer::new(scratch);
    let stack = MemStack::new(&mut mem);
    llt::factor::cholesky_in_place(g.as_mut(), Default::default(), Par::Seq, stack, Default::default()).map_err(not_spd)?;
    // L is the lower triangle; the upper still holds G.
    for j in 1..n {
        for i in 0..j {
            g[(i, j)] = 0.0;
        }
    }
    let mut inverse = Mat::zeros(n, n);
    llt::inverse::inverse(inverse.as_mut(), g.as_ref(), Par::Seq, stack);
    // The inverse fills the lower triangle; the solve multiplies by the whole matrix.
    for j in 0..n {
        for i in 0..j {
            inverse[(i, j)] = inverse[(j, i)];
        }
    }
    Ok(inverse)
}

/// Factor G by the method (and, for Cholesky, dense or sparse by size).
pub(crate) fn factor(g: &SymCsc, settings: &Settings) -> Result<Solver> {
    if settings.method != Method::Cholesky {
        return Ok(Solver::Spectral(Spectral::new(g, settings.method)?));
    }
    if g.n <= DENSE_MAX {
        return Ok(Solver::Dense(dense_inverse(g.to_dense())?));
    }
    let order = if settings.factors.iter().all(|f| f.dim() == 1) { Order::Degree } else { Order::Amd };
    let llt = SparseLlt::new(g.n, g.col_ptr.clone(), g.row.clone(), g.val.clone(), order)
        .map_err(|e| e.unwrap_or_else(|| not_spd(())))?;
    Ok(Solver::Sparse(Box::new(llt), g.clone()))
}

impl Fit {
    /// Evaluate the fitted product at a query (linear space, mapped back), with the same
    /// interpolation as the shader.
    pub fn eval(&self, settings: &Settings, q: &Query) -> [f64; 3] {
        let mut prod = [1.0; 3];
        for (spec, t) in settings.factors.iter().zip(&self.tables) {
            let s = system::stencil(spec, q);
            let mut sum = [0.0; 3];
            for (i, w) in s.iter() {
                for c in 0..3 {
                    sum[c] += w * t[i][c];
                }
            }
            prod = [0, 1, 2].map(|c| prod[c] * sum[c]);
        }
        [0, 1, 2].map(|c| self.map.inverse(c, prod[c]))
    }
}
