//! The constraint system of eq. 3.4, $\mathbf g = \mathbf B \mathbf y$, and its normal
//! equations $\mathbf G = \mathbf B^\top \mathbf B$.
//!
//! $\mathbf B$ stacks the sample rows $[\mathbf A_1 \cdots \mathbf A_J]$ (one row per sample,
//! 2 or 4 interpolation weights per factor) over the regularization rows (Laplacian
//! smoothing, damping, ridge) and a gauge row per factor. Only the sample rows have a
//! nonzero right-hand side, so $\mathbf B^\top \mathbf g = \mathbf A^\top \tilde{\mathbf f}$.

use glam::DVec2;

use super::param::{self, Domain, Param};
use super::pattern::{Pattern, Query};
use super::settings::{FactorSpec, Input, Settings};
use super::table::{self, Rows, Stencil};
use crate::error::{Error, Result};

/// Table coordinate of a query for one factor.
#[inline]
pub fn coordinate(spec: &FactorSpec, q: &Query) -> [f64; 2] {
    let [x, y] = unwarped(spec, q);
    // The node warp acts on the radius axis (Settings::validate allows it nowhere else).
    [param::warp_forward(x, spec.warp), y]
}

/// Table coordinate before the node warp.
#[inline]
fn unwarped(spec: &FactorSpec, q: &Query) -> [f64; 2] {
    let d = match &spec.input {
        Input::Light => q.l,
        Input::Half => super::leaned_half(q.l, q.v, spec.lean),
        Input::View => q.v,
        Input::Uv => {
            let t = param::uv_forward(q.uv);
            return [t.x, t.y];
        }
        Input::Difference => param::difference(q.l, q.h()),
        Input::HalfDifference => {
            // $(\theta_h, \theta_d)$: the domain is the half vector's; $\theta_d \le \pi/2$
            // always ($l \cdot h = |l + v|/2 \ge 0$), so d needs only the hemisphere.
            let h = q.h();
            let d = param::difference(q.l, h);
            return [param::radius_forward(h, spec.domain), param::radius_forward(d, Domain::Hemisphere)];
        }
        Input::Custom(c) => return (c.project)(q),
    };
    match spec.param {
        Param::Radius => [param::radius_forward(d, spec.domain), 0.0],
        Param::Parabolic | Param::Hemispherical => {
            let t = param::planar_forward(spec.param, d, spec.domain);
            [t.x, t.y]
        }
        Param::Uv => {
            let t = param::uv_forward(DVec2::new(d.x, d.y));
            [t.x, t.y]
        }
        // Only the (h, d) pair, returned above, uses two radii (Settings::validate).
        Param::Radii => [param::radius_forward(d, spec.domain), 0.0],
    }
}

/// Interpolation stencil of a query in one factor's table.
#[inline]
pub fn stencil(spec: &FactorSpec, q: &Query) -> Stencil {
    let t = coordinate(spec, q);
    if spec.dim() == 1 {
        table::stencil_1d(t[0], spec.res)
    } else {
        table::stencil_2d(t, spec.res)
    }
}

/// The sample matrix $\mathbf A$ (N × n), stored by rows (to predict, and to scatter
/// $\mathbf A^\top \tilde{\mathbf f}$), with each node's data weight; by columns too, made
/// the first time they are asked for (only the sparse assembly of $\mathbf G$ needs them).
#[derive(Clone, Debug, Default)]
pub struct Design {
    /// Unknowns (columns).
    pub n: usize,
    /// Column offset of each factor.
    pub offsets: Vec<usize>,
    pub row_ptr: Vec<u32>,
    pub row_col: Vec<u32>,
    pub row_val: Vec<f64>,
    /// Each node's summed interpolation weight over the samples.
    weights: Vec<f64>,
    columns: std::sync::OnceLock<Columns>,
}

/// $\mathbf A$ in compressed columns: each column's samples (rows) and weights.
#[derive(Clone, Debug, Default)]
pub struct Columns {
    pub ptr: Vec<u32>,
    pub row: Vec<u32>,
    pub val: Vec<f64>,
}

/// Patterns from which the sample rows are built on several threads.
const PARALLEL_SAMPLES: usize = 4096;

/// The sample rows of $\mathbf A$ in compressed form (row pointers, columns, weights).
/// Zero weights carry no information and are left out, which keeps G sparser.
///
/// Every row has the same stencil lengths, so the rows are first written at a fixed stride
/// straight into their place (chunks of rows on several threads, factor by factor so each
/// factor's parametrization is chosen once per chunk), then compacted where a weight is
/// zero (a sample exactly on a node).
fn sample_rows(pattern: &Pattern, settings: &Settings, offsets: &[usize]) -> (Vec<u32>, Vec<u32>, Vec<f64>) {
    use rayon::prelude::*;
    let widths: Vec<usize> = settings.factors.iter().map(|f| if f.dim() == 1 { 2 } else { 4 }).collect();
    let stride: usize = widths.iter().sum();
    let rows = pattern.len();
    let mut cols = vec![0u32; rows * stride];
    let mut vals = vec![0.0f64; rows * stride];
    let fill = |queries: &[Query], cols: &mut [u32], vals: &mut [f64]| {
        let mut at = 0;
        for ((f, &width), &offset) in settings.factors.iter().zip(&widths).zip(offsets) {
            for (k, q) in queries.iter().enumerate() {
                let s = stencil(f, q);
                let row = k * stride + at;
                for e in 0..width {
                    cols[row + e] = offset as u32 + s.index[e];
                    vals[row + e] = s.weight[e];
                }
            }
            at += width;
        }
    };
    if rows >= PARALLEL_SAMPLES {
        let per = rows.div_ceil(rayon::current_num_threads().max(1));
        pattern
            .queries
            .par_chunks(per)
            .zip(cols.par_chunks_mut(per * stride).zip(vals.par_chunks_mut(per * stride)))
            .for_each(|(q, (c, v))| fill(q, c, v));
    } else {
        fill(&pattern.queries, &mut cols, &mut vals);
    }
    let row_ptr = if vals.contains(&0.0) {
        compact(&mut cols, &mut vals, stride)
    } else {
        (0..=rows).map(|r| (r * stride) as u32).collect()
    };
    (row_ptr, cols, vals)
}

/// Drops the zero weights of fixed-stride rows in place; the rows' pointers.
fn compact(cols: &mut Vec<u32>, vals: &mut Vec<f64>, stride: usize) -> Vec<u32> {
    let rows = vals.len() / stride;
    let mut row_ptr = Vec::with_capacity(rows + 1);
    row_ptr.push(0u32);
    let mut kept = 0;
    for k in 0..rows * stride {
        if vals[k] != 0.0 {
            cols[kept] = cols[k];
            vals[kept] = vals[k];
            kept += 1;
        }
        if k % stride == stride - 1 {
            row_ptr.push(kept as u32);
        }
    }
    cols.truncate(kept);
    vals.truncate(kept);
    row_ptr
}

impl Design {
    /// Each node's data weight: the sum of its interpolation weights over the samples. Below
    /// 1, no sample really reaches the node: its value is the smoothing's extrapolation.
    pub fn node_weights(&self) -> &[f64] {
        &self.weights
    }

    /// $\mathbf A$ by columns (a counting sort of the rows, made once).
    pub fn columns(&self) -> &Columns {
        self.columns.get_or_init(|| {
            let mut ptr = vec![0u32; self.n + 1];
            for &c in &self.row_col {
                ptr[c as usize + 1] += 1;
            }
            for c in 0..self.n {
                ptr[c + 1] += ptr[c];
            }
            let mut fill = ptr.clone();
            let mut row = vec![0u32; self.row_col.len()];
            let mut val = vec![0.0; self.row_col.len()];
            for r in 0..self.rows() {
                for k in self.row_ptr[r] as usize..self.row_ptr[r + 1] as usize {
                    let c = self.row_col[k] as usize;
                    let dst = fill[c] as usize;
                    row[dst] = r as u32;
                    val[dst] = self.row_val[k];
                    fill[c] += 1;
                }
            }
            Columns { ptr, row, val }
        })
    }

    /// Build $\mathbf A$ for a pattern. Errors: empty pattern, uv factors without uv, a
    /// factor no sample reaches.
    pub fn new(pattern: &Pattern, settings: &Settings) -> Result<Design> {
        settings.validate()?;
        if pattern.is_empty() {
            return Err(Error::input("no samples: the sample set is empty"));
        }
        if pattern.len() > u32::MAX as usize / 16 {
            return Err(Error::input(format!("{} samples is too many", pattern.len())));
        }
        for (j, f) in settings.factors.iter().enumerate() {
            if f.input == Input::Uv && !pattern.has_uv {
                return Err(Error::input(format!(
                    "factor {j} looks up texture coordinates, but the samples have none"
                )));
            }
        }
        let mut offsets = Vec::with_capacity(settings.factors.len());
        let mut n = 0;
        for f in &settings.factors {
            offsets.push(n);
            n += f.len();
        }
        let (row_ptr, row_col, row_val) = sample_rows(pattern, settings, &offsets);
        let mut weights = vec![0.0; n];
        for (&c, &w) in row_col.iter().zip(&row_val) {
            weights[c as usize] += w;
        }
        for (j, f) in settings.factors.iter().enumerate() {
            if weights[offsets[j]..offsets[j] + f.len()].iter().sum::<f64>() <= 0.0 {
                return Err(Error::input(format!("factor {j} ({}) receives no samples", f.input.name())));
            }
        }
        Ok(Design { n, offsets, row_ptr, row_col, row_val, weights, columns: Default::default() })
    }

    /// Factor `j`'s columns alone, numbered from 0: the sample matrix of a system of that
    /// factor by itself (the same as building it from the pattern, without the stencils).
    pub fn factor_block(&self, j: usize) -> Design {
        let end = self.offsets.get(j + 1).copied().unwrap_or(self.n);
        let cols = self.offsets[j] as u32..end as u32;
        let mut row_ptr = Vec::with_capacity(self.row_ptr.len());
        row_ptr.push(0u32);
        let (mut row_col, mut row_val) = (Vec::new(), Vec::new());
        for r in 0..self.rows() {
            for k in self.row_ptr[r] as usize..self.row_ptr[r + 1] as usize {
                if cols.contains(&self.row_col[k]) {
                    row_col.push(self.row_col[k] - cols.start);
                    row_val.push(self.row_val[k]);
                }
            }
            row_ptr.push(row_col.len() as u32);
        }
        let weights = self.weights[cols.start as usize..end].to_vec();
        Design { n: cols.len(), offsets: vec![0], row_ptr, row_col, row_val, weights, columns: Default::default() }
    }

    /// Number of samples (rows).
    pub fn rows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// `rhs` less $\mathbf A_j^\top \mathbf A_k \mathbf y_k$ on every column outside `block`:
    /// what the other factors' right-hand sides keep once the unknowns `block` (one factor's,
    /// `y` of them) explain their part of the samples. The samples' share is gathered per row,
    /// then scattered as a right-hand side is ([`Design::transpose_apply`]).
    pub fn subtract_cross(&self, rhs: &mut faer::Mat<f64>, block: std::ops::Range<usize>, y: &faer::Mat<f64>) {
        use rayon::prelude::*;
        let explained: Vec<[f64; 3]> = (0..self.rows())
            .into_par_iter()
            .map(|i| {
                let span = self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize;
                let mut p = [0.0; 3];
                for (&col, &w) in self.row_col[span.clone()].iter().zip(&self.row_val[span]) {
                    let col = col as usize;
                    if block.contains(&col) {
                        for c in 0..3 {
                            p[c] += w * y[(col - block.start, c)];
                        }
                    }
                }
                p
            })
            .collect();
        let mut cross = vec![[0.0; 4]; self.n];
        self.transpose_apply(&explained, &|_, _| {}, &mut cross);
        for (col, x) in cross.iter().enumerate().filter(|(col, _)| !block.contains(col)) {
            for c in 0..3 {
                rhs[(col, c)] -= x[c];
            }
        }
    }

    /// $\mathbf b = \mathbf A^\top \tilde{\mathbf f}$ for three channels, with the log
    /// mapping fused in: `logs(c, x)` replaces `x` (linear values of channel `c`) with their
    /// log-space values. `out[i]` holds unknown `i`'s three channels (and a zero pad lane).
    ///
    /// Samples are processed in chunks whose values are mapped in one tight loop per channel
    /// (so the logarithm vectorizes) and then scattered into `out` row by row, all three
    /// channels in one 4-lane operation; `out` is small enough to stay in cache. Large
    /// patterns split the chunks across threads, each with its own partial sum.
    pub fn transpose_apply(&self, values: &[[f64; 3]], logs: &(dyn Fn(usize, &mut [f64]) + Sync), out: &mut [[f64; 4]]) {
        use rayon::prelude::*;
        let n = self.n;
        out.iter_mut().for_each(|x| *x = [0.0; 4]);
        // Threads pay off only for large patterns: rayon's fork and the partial sums cost
        // tens of microseconds.
        if values.len() < 32 * SCATTER_CHUNK {
            for (k, vals) in values.chunks(SCATTER_CHUNK).enumerate() {
                self.scatter(k * SCATTER_CHUNK, vals, logs, out);
            }
            return;
        }
        let per_thread = values.len().div_ceil(rayon::current_num_threads().max(1)).div_ceil(SCATTER_CHUNK) * SCATTER_CHUNK;
        let partials: Vec<Vec<[f64; 4]>> = values
            .par_chunks(per_thread)
            .enumerate()
            .map(|(t, part)| {
                let mut acc = vec![[0.0; 4]; n];
                for (k, vals) in part.chunks(SCATTER_CHUNK).enumerate() {
                    self.scatter(t * per_thread + k * SCATTER_CHUNK, vals, logs, &mut acc);
                }
                acc
            })
            .collect();
        for p in partials {
            for (o, x) in out.iter_mut().zip(p) {
                for c in 0..4 {
                    o[c] += x[c];
                }
            }
        }
    }

    /// One chunk of [`Design::transpose_apply`]: at most [`SCATTER_CHUNK`] samples starting
    /// at row `first`.
    fn scatter(&self, first: usize, vals: &[[f64; 3]], logs: &(dyn Fn(usize, &mut [f64]) + Sync), acc: &mut [[f64; 4]]) {
        let mut channel = [0.0f64; SCATTER_CHUNK];
        let mut f = [[0.0f64; 4]; SCATTER_CHUNK];
        for c in 0..3 {
            for (x, v) in channel.iter_mut().zip(vals) {
                *x = v[c];
            }
            logs(c, &mut channel[..vals.len()]);
            for (dst, x) in f.iter_mut().zip(&channel[..vals.len()]) {
                dst[c] = *x;
            }
        }
        let rows = RowSpan { ptr: &self.row_ptr[first..=first + vals.len()], col: &self.row_col, val: &self.row_val };
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU has AVX2 and FMA, checked just above.
            unsafe { scatter_avx2(&rows, &f[..vals.len()], acc) };
            return;
        }
        scatter_rows(&rows, &f[..vals.len()], acc);
    }
}

/// Samples per chunk of the fused log-and-scatter.
const SCATTER_CHUNK: usize = 256;

/// A run of consecutive rows of the design: `ptr` has one more entry than there are rows.
struct RowSpan<'a> {
    ptr: &'a [u32],
    col: &'a [u32],
    val: &'a [f64],
}

/// `acc[col] += w · f[row]` over the rows' entries, all lanes at once.
#[inline(always)]
fn scatter_rows(rows: &RowSpan<'_>, f: &[[f64; 4]], acc: &mut [[f64; 4]]) {
    for (i, fi) in f.iter().enumerate() {
        let span = rows.ptr[i] as usize..rows.ptr[i + 1] as usize;
        for (&col, &w) in rows.col[span.clone()].iter().zip(&rows.val[span]) {
            let a = &mut acc[col as usize];
            for c in 0..4 {
                a[c] += w * fi[c];
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn scatter_avx2(rows: &RowSpan<'_>, f: &[[f64; 4]], acc: &mut [[f64; 4]]) {
    scatter_rows(rows, f, acc);
}

/// A symmetric sparse matrix in compressed columns (full storage, rows sorted).
#[derive(Clone, Debug, Default)]
pub struct SymCsc {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row: Vec<usize>,
    pub val: Vec<f64>,
}

impl SymCsc {
    /// Dense copy, column-major.
    pub fn to_dense(&self) -> faer::Mat<f64> {
        let mut m = faer::Mat::<f64>::zeros(self.n, self.n);
        for c in 0..self.n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                m[(self.row[k], c)] = self.val[k];
            }
        }
        m
    }
}

/// The smoothing, damping and ridge rows of one factor, in its own node numbering, each
/// with its weight applied, for a pattern of `n_samples` samples. [`crate::factor::robust`]
/// applies them to a prior shape (a regularization that pulls toward a shape instead of a
/// constant moves only the right-hand side, so the prepared system is unchanged).
pub(crate) fn factor_regularization(f: &FactorSpec, n_samples: f64) -> Rows {
    let dim = f.dim();
    let h = 1.0 / (f.res - 1) as f64;
    // Quadrature weight of one node: the rows approximate integrals over the unit domain.
    let cell = h.powi(dim as i32);
    let mut out: Rows = Vec::new();
    let mut push = |rows: Rows, scale: f64| out.extend(rows.into_iter().map(|r| r.into_iter().map(|(i, c)| (i, c * scale)).collect()));
    if f.smooth > 0.0 {
        push(table::laplacian(f.res, dim), (f.smooth * f.smooth * n_samples * cell).sqrt());
    }
    if f.damp > 0.0 {
        push(table::gradient(f.res, dim), (f.damp * n_samples * cell).sqrt());
    }
    if f.ridge > 0.0 {
        let s = (f.ridge * n_samples * cell).sqrt();
        push((0..f.len()).map(|i| vec![(i, s)]).collect(), 1.0);
    }
    out
}

/// Regularization rows of every factor, in global unknown numbering, each with its weight
/// already applied (so $\mathbf R = \sum_{\text{rows}} \mathbf r \mathbf r^\top$).
pub(crate) fn regularization(settings: &Settings, design: &Design) -> Rows {
    let offsets = &design.offsets;
    let n_samples = design.rows() as f64;
    let mut out: Rows = Vec::new();
    let mut push = |rows: Rows, scale: f64, offset: usize| {
        for r in rows {
            out.push(r.into_iter().map(|(i, c)| (offset + i, c * scale)).collect());
        }
    };
    for (j, f) in settings.factors.iter().enumerate() {
        push(factor_regularization(f, n_samples), 1.0, offsets[j]);
        // Gauge: a constant moved from one factor to another changes nothing (the exact null
        // directions of the log-space system: data, smoothing and damping rows all ignore a
        // constant). Pinning one node of every factor but the first to log 1 = 0 removes
        // them without biasing the fit, and, unlike fixing a factor's mean, adds no dense
        // block to G. The pinned node is the one the samples weigh most. A ridged factor
        // has no null direction.
        if j > 0 && f.ridge == 0.0 {
            let weight = design.node_weights();
            let anchor = (0..f.len()).max_by(|&a, &b| weight[offsets[j] + a].total_cmp(&weight[offsets[j] + b])).unwrap_or(0);
            push(vec![vec![(anchor, n_samples.sqrt() / f.len() as f64)]], 1.0, offsets[j]);
        }
    }
    out
}

/// Systems at most this large may assemble $\mathbf G$ in a dense matrix whose lower
/// triangle is used (n² values, 19 MB at 1536).
const DENSE_ASSEMBLY: usize = 1536;
/// Samples from which the dense assembly splits the rows between threads, each with its own
/// triangle (below, zeroing a second triangle costs more than it saves).
const PARALLEL_ROWS: usize = 16_384;

/// The normal matrix $\mathbf G = \mathbf A^\top \mathbf A + \mathbf R$ in sparse symmetric
/// form. `progress`, when given, advances by one per column.
pub fn normal_matrix(design: &Design, settings: &Settings, progress: Option<&indicatif::ProgressBar>) -> SymCsc {
    let reg = regularization(settings, design);
    // A unit-less floor on the diagonal: 1e-12 of the data's weight per unknown. It only
    // matters for directions nothing else determines (a 2D table sampled along a curve),
    // which it sets to zero instead of letting the factorization fail.
    let floor = 1e-12 * design.rows() as f64 / design.n as f64;
    // Cost model (measured): clearing and scanning the dense matrix costs about as much per
    // entry as the column-by-column product costs per sample product (a row of k entries
    // makes k²), and adding a product into the dense matrix is nearly free; so dense when
    // the samples' products outnumber its entries.
    let products: usize = design.row_ptr.windows(2).map(|w| ((w[1] - w[0]) as usize).pow(2)).sum();
    if design.n <= DENSE_ASSEMBLY && design.n * design.n < products {
        dense_normal_matrix(design, &reg, floor)
    } else {
        sparse_normal_matrix(design, &reg, floor, progress)
    }
}

/// [`normal_matrix`] through a dense lower triangle, column-major (entry (a, b), a ≥ b, at
/// `b·n + a`), rows split between threads for large patterns.
fn dense_normal_matrix(design: &Design, reg: &Rows, floor: f64) -> SymCsc {
    use rayon::prelude::*;
    let n = design.n;
    let add_rows = |rows: std::ops::Range<usize>, lower: &mut [f64]| {
        for r in rows {
            let span = design.row_ptr[r] as usize..design.row_ptr[r + 1] as usize;
            let (cols, vals) = (&design.row_col[span.clone()], &design.row_val[span]);
            // A row's columns ascend (factor by factor, each stencil in order).
            for (q, (&b, &wb)) in cols.iter().zip(vals).enumerate() {
                let column = &mut lower[b as usize * n..];
                for (&a, &wa) in cols[q..].iter().zip(&vals[q..]) {
                    column[a as usize] += wa * wb;
                }
            }
        }
    };
    let rows = design.rows();
    let threads = rayon::current_num_threads().max(1);
    let mut lower = if rows >= PARALLEL_ROWS && threads > 1 {
        let per = rows.div_ceil(threads);
        let parts: Vec<Vec<f64>> = (0..threads)
            .into_par_iter()
            .map(|t| {
                let mut part = vec![0.0; n * n];
                add_rows(t * per..((t + 1) * per).min(rows), &mut part);
                part
            })
            .collect();
        let mut parts = parts.into_iter();
        let mut sum = parts.next().unwrap_or_else(|| vec![0.0; n * n]);
        for p in parts {
            sum.par_chunks_mut(n).zip(p.par_chunks(n)).for_each(|(s, p)| s.iter_mut().zip(p).for_each(|(s, p)| *s += p));
        }
        sum
    } else {
        let mut lower = vec![0.0; n * n];
        add_rows(0..rows, &mut lower);
        lower
    };
    for row in reg {
        for &(i, x) in row {
            for &(j, y) in row {
                if i >= j {
                    lower[j * n + i] += x * y;
                }
            }
        }
    }
    for c in 0..n {
        lower[c * n + c] += floor;
    }
    lower_to_sym(n, &lower)
}

/// Full symmetric compressed columns of a dense lower triangle (entry (a, b) at `b·n + a`),
/// zeros left out. Column c lists rows above c (the transposed entries of columns before
/// it) and then its own lower entries, so its rows ascend.
fn lower_to_sym(n: usize, lower: &[f64]) -> SymCsc {
    let mut count = vec![0usize; n];
    for b in 0..n {
        for a in b..n {
            if lower[b * n + a] != 0.0 {
                count[b] += 1;
                if a > b {
                    count[a] += 1;
                }
            }
        }
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    for c in 0..n {
        col_ptr.push(col_ptr[c] + count[c]);
    }
    let nnz = col_ptr[n];
    let (mut row, mut val) = (vec![0usize; nnz], vec![0.0; nnz]);
    let mut fill = col_ptr[..n].to_vec();
    for b in 0..n {
        for a in b..n {
            let x = lower[b * n + a];
            if x != 0.0 {
                row[fill[b]] = a;
                val[fill[b]] = x;
                fill[b] += 1;
                if a > b {
                    row[fill[a]] = b;
                    val[fill[a]] = x;
                    fill[a] += 1;
                }
            }
        }
    }
    SymCsc { n, col_ptr, row, val }
}

/// [`normal_matrix`] by Gustavson's column-by-column product with a dense accumulator,
/// columns split between threads.
fn sparse_normal_matrix(design: &Design, reg: &Rows, floor: f64, progress: Option<&indicatif::ProgressBar>) -> SymCsc {
    use rayon::prelude::*;
    let n = design.n;
    // Regularization rows grouped by the columns they touch.
    let mut reg_by_col: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (r, row) in reg.iter().enumerate() {
        for &(i, _) in row {
            reg_by_col[i].push(r as u32);
        }
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let block = 256;
    let blocks: Vec<(Vec<usize>, Vec<usize>, Vec<f64>)> = (0..n.div_ceil(block))
        .into_par_iter()
        .map(|k| {
            let columns = k * block..((k + 1) * block).min(n);
            let part = gustavson_columns(design, reg, &reg_by_col, floor, columns);
            let finished = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            if let Some(bar) = progress {
                bar.set_position((finished * block).min(n) as u64);
            }
            part
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let nnz = blocks.iter().map(|b| b.1.len()).sum();
    let (mut row, mut val) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
    for (lens, rows, vals) in blocks {
        for len in lens {
            col_ptr.push(col_ptr[col_ptr.len() - 1] + len);
        }
        row.extend(rows);
        val.extend(vals);
    }
    SymCsc { n, col_ptr, row, val }
}

/// Columns `columns` of $\mathbf G$: each column's length, and the rows and values of all.
fn gustavson_columns(design: &Design, reg: &Rows, reg_by_col: &[Vec<u32>], floor: f64, columns: std::ops::Range<usize>) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let n = design.n;
    let by_column = design.columns();
    let mut acc = vec![0.0f64; n];
    let mut mark = vec![usize::MAX; n];
    let mut touched: Vec<usize> = Vec::new();
    let (mut lens, mut row, mut val) = (Vec::with_capacity(columns.len()), Vec::new(), Vec::new());
    for c in columns {
        touched.clear();
        let mut add = |i: usize, x: f64, touched: &mut Vec<usize>| {
            if mark[i] != c {
                mark[i] = c;
                acc[i] = 0.0;
                touched.push(i);
            }
            acc[i] += x;
        };
        for k in by_column.ptr[c] as usize..by_column.ptr[c + 1] as usize {
            let (r, w) = (by_column.row[k] as usize, by_column.val[k]);
            for k2 in design.row_ptr[r] as usize..design.row_ptr[r + 1] as usize {
                add(design.row_col[k2] as usize, w * design.row_val[k2], &mut touched);
            }
        }
        for &r in &reg_by_col[c] {
            let row_r = &reg[r as usize];
            let w = row_r.iter().filter(|(i, _)| *i == c).map(|(_, x)| x).sum::<f64>();
            for &(i, x) in row_r {
                add(i, w * x, &mut touched);
            }
        }
        add(c, floor, &mut touched);
        lens.push(touched.len());
        // Rows ascend: sorted (about k·log₂k steps for k rows, log₂k ≈ 8 at these sizes), or
        // read off the marks in order (n steps) for a column touching much of G, such as a 1D
        // table's node reached by samples all over a 2D table.
        if touched.len() * 8 < n {
            touched.sort_unstable();
            for &i in &touched {
                row.push(i);
                val.push(acc[i]);
            }
        } else {
            for i in (0..n).filter(|&i| mark[i] == c) {
                row.push(i);
                val.push(acc[i]);
            }
        }
    }
    (lens, row, val)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::SphereView;

    /// $\mathbf A^\top \mathbf A + \mathbf R^\top \mathbf R + \epsilon \mathbf I$ by the
    /// definition, entry by entry, densely.
    fn by_definition(design: &Design, reg: &Rows, floor: f64) -> Vec<f64> {
        let n = design.n;
        let mut g = vec![0.0; n * n];
        let mut add_row = |row: &[(usize, f64)]| {
            for &(i, x) in row {
                for &(j, y) in row {
                    g[i * n + j] += x * y;
                }
            }
        };
        for r in 0..design.rows() {
            let span = design.row_ptr[r] as usize..design.row_ptr[r + 1] as usize;
            let row: Vec<(usize, f64)> = design.row_col[span.clone()].iter().map(|&c| c as usize).zip(design.row_val[span].iter().copied()).collect();
            add_row(&row);
        }
        reg.iter().for_each(|r| add_row(r));
        (0..n).for_each(|i| g[i * n + i] += floor);
        g
    }

    fn check(g: &SymCsc, truth: &[f64]) {
        let n = g.n;
        let dense = g.to_dense();
        let scale = truth.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            for j in 0..n {
                assert!((dense[(i, j)] - truth[i * n + j]).abs() <= 1e-12 * scale, "G[{i}, {j}] = {} against {}", dense[(i, j)], truth[i * n + j]);
            }
            let rows = &g.row[g.col_ptr[i]..g.col_ptr[i + 1]];
            assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {i}: rows must ascend");
        }
    }

    #[test]
    fn both_assemblies_of_g_match_its_definition() {
        let pattern = SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 24).pattern();
        for settings in [Settings::uniform(1, 16), Settings::uniform(2, 6), Settings::four_factor(1, 8, 6)] {
            let design = Design::new(&pattern, &settings).unwrap();
            let reg = regularization(&settings, &design);
            let truth = by_definition(&design, &reg, 1e-9);
            check(&dense_normal_matrix(&design, &reg, 1e-9), &truth);
            check(&sparse_normal_matrix(&design, &reg, 1e-9, None), &truth);
        }
    }

    #[test]
    fn a_factor_block_is_the_sample_matrix_of_that_factor_alone() {
        // A pattern large enough to build its rows on several threads.
        let pattern = SphereView::new(glam::DVec3::new(0.0, 0.0, 1.0), 80).pattern();
        for settings in [Settings::uniform(1, 16), Settings::four_factor(1, 8, 6)] {
            let whole = Design::new(&pattern, &settings).unwrap();
            for (j, alone) in settings.chroma().iter().enumerate() {
                let (block, fresh) = (whole.factor_block(j), Design::new(&pattern, alone).unwrap());
                assert_eq!((block.n, &block.offsets, &block.row_ptr, &block.row_col), (fresh.n, &fresh.offsets, &fresh.row_ptr, &fresh.row_col));
                assert_eq!((&block.row_val, block.node_weights()), (&fresh.row_val, fresh.node_weights()));
                assert_eq!(block.columns().val, fresh.columns().val);
            }
        }
    }
}
