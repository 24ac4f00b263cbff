//! Material maps by clustering: brdfpaint's default, beyond the thesis's greedy fit.
//!
//! The thesis's fit ([`super::greedy`]) explains each sample by whatever blend of terms
//! stays below it, so the first term is fitted to a mixture of every material and the
//! coefficient textures end up holding the painted light and view: on a two-material test
//! object the training error is small, but views nobody painted miss by 0.88 (relative
//! RMS; BENCHMARKS.md, Table 5.4). Real paintings are made of a few materials in regions,
//! so here every texel belongs to one term, and each term is fitted to its own samples:
//!
//! 1. One product is fitted to every sample (the uniform fit).
//! 2. The cluster with the largest log-space error is split in two along a principal
//!    direction of its samples' RGB log residuals (bisecting k-means; two candidate
//!    directions, the one that ends with the lower objective wins).
//! 3. k-means rounds: every cluster's product is refitted to its samples, and every sample
//!    moves to the product that explains it, and the other samples of its surface cell
//!    (all views), best in log space (the objective the fit minimizes); then it takes the
//!    label most of its pixel neighbours have, since materials come in regions, not in
//!    single pixels.
//! 4. Steps 2–3 repeat until there are `terms` clusters, or a split improves the error by
//!    less than `min_gain` times the uniform fit's.
//!
//! A cluster's product is the least-squares fit to its samples alone, yet it is solved
//! through the system prepared for all of them: samples outside the cluster take the
//! cluster's own log-space prediction as their value (the EM treatment of missing data), so
//! they pull the fit nowhere, and a few solves converge to the cluster's own fit. A refit
//! costs solves, never a prepare.
//!
//! The coefficient of a term is its gain where its cluster is and zero elsewhere. A
//! sample's gain is $f \hat f / \hat f^2$ per channel, pulled to 1 where $\hat f$ is tiny;
//! a texel averages the gains of its samples weighted by $\hat f^2$, so a sample in shadow
//! in one view does not dilute the same texel lit in another. The gain carries albedo
//! variation inside one material (a painted texture, wood grain); a texel on a region border
//! blends the two terms.

use faer::Mat;
use rayon::prelude::*;

use super::texture::{Combine, Layout};
use super::{term, Grid, MapOptions};
use crate::error::{Error, Result};
use crate::factor::{Errors, LogMap, Prepared};
use crate::material::{Coefficients, Term};

/// k-means rounds after each split.
const ROUNDS: usize = 6;
/// Imputation solves per cluster refit (warm-started from the previous round).
const INNER: usize = 2;
/// Over-relaxation of the imputation steps.
const OMEGA: f64 = 1.6;

/// One cluster's product in log space.
#[derive(Clone)]
struct Cluster {
    /// Whether its samples changed since it was last fitted.
    stale: bool,
    y: Mat<f64>,
    /// $\mathbf A \tilde{\mathbf y}$ at every sample, inside the cluster or not.
    log_pred: Vec<[f64; 3]>,
}

/// The state of the clustering.
#[derive(Clone)]
struct State {
    clusters: Vec<Cluster>,
    labels: Vec<u32>,
}

pub(super) fn fit(prepared: &Prepared, values: &[[f64; 3]], grids: &[Grid], layout: &Layout, opts: &MapOptions) -> Result<(Vec<Term>, Vec<Errors>)> {
    let n = values.len();
    // One mapping for every term, chosen on all samples as a uniform fit chooses it.
    let first = prepared.solve(values, opts.mapping)?;
    let map = first.map;
    let log_obs: Vec<[f64; 3]> = values.iter().map(|v| [0, 1, 2].map(|c| map.forward(c, v[c]))).collect();
    let near = Near::new(grids, layout, n);
    let y = prepared.solve_log(&log_obs);
    let mut state = State { clusters: vec![Cluster { stale: false, log_pred: prepared.predict_log(&y), y }], labels: vec![0; n] };
    let mut errors = vec![state.errors(prepared, &map, values)];
    while state.clusters.len() < opts.terms {
        // Every candidate split runs its k-means rounds; the lowest objective wins.
        let mut candidates = state.splits(&log_obs);
        candidates.par_iter_mut().for_each(|c| {
            for _ in 0..ROUNDS {
                c.refit(prepared, &log_obs);
                if c.reassign(&log_obs, &near) * 1000 < n {
                    break;
                }
            }
        });
        let Some(mut next) = candidates.into_iter().min_by(|a, b| a.sse(&log_obs).total_cmp(&b.sse(&log_obs))) else { break };
        next.drop_empty();
        next.refit(prepared, &log_obs);
        let e = next.errors(prepared, &map, values);
        let last = errors.last().expect("one fit at least").rms_relative;
        if next.clusters.len() <= state.clusters.len() || last - e.rms_relative < opts.min_gain * errors[0].rms_relative {
            break;
        }
        state = next;
        errors.push(e);
    }
    let terms = state.terms(prepared, &map, values, layout)?;
    Ok((terms, errors))
}

impl State {
    /// The cluster with the largest log-space error split in two across each of the two
    /// main principal directions of its samples' RGB log residuals, in turn: a split by
    /// brightness alone (the largest spread) can put a glossy region's highlight with a
    /// matte region, a split by colour separates them. (The third direction, the smallest
    /// spread, never won where measured, and two candidates run at once on two cores.)
    fn splits(&self, log_obs: &[[f64; 3]]) -> Vec<State> {
        let j = self.clusters.len();
        let mut sse = vec![0.0; j];
        for (i, &l) in self.labels.iter().enumerate() {
            sse[l as usize] += sq(residual(log_obs[i], self.clusters[l as usize].log_pred[i]));
        }
        let Some(worst) = (0..j).max_by(|&a, &b| sse[a].total_cmp(&sse[b])) else { return Vec::new() };
        let members: Vec<usize> = (0..self.labels.len()).filter(|&i| self.labels[i] == worst as u32).collect();
        let r: Vec<[f64; 3]> = members.iter().map(|&i| residual(log_obs[i], self.clusters[worst].log_pred[i])).collect();
        let mean = mean3(&r);
        let mut out = Vec::new();
        for dir in principal_axes(&r, mean).into_iter().take(2) {
            let mut next = self.clone();
            let mut moved = 0;
            for (&i, ri) in members.iter().zip(&r) {
                if (0..3).map(|c| (ri[c] - mean[c]) * dir[c]).sum::<f64>() > 0.0 {
                    next.labels[i] = j as u32;
                    moved += 1;
                }
            }
            if moved > 0 && moved < members.len() {
                next.clusters[worst].stale = true;
                next.clusters.push(Cluster { stale: true, ..self.clusters[worst].clone() });
                out.push(next);
            }
        }
        out
    }

    /// Log-space squared error of every sample against its cluster: the objective.
    fn sse(&self, log_obs: &[[f64; 3]]) -> f64 {
        self.labels.iter().enumerate().map(|(i, &l)| sq(residual(log_obs[i], self.clusters[l as usize].log_pred[i]))).sum()
    }

    /// Refit every cluster to its own samples: the others take the cluster's prediction.
    /// Only clusters whose samples changed are refitted, so a split costs the refits of the
    /// clusters it disturbs, not of all of them (fitting is linear in the number of terms).
    fn refit(&mut self, prepared: &Prepared, log_obs: &[[f64; 3]]) {
        let mut target = vec![[0.0; 3]; log_obs.len()];
        for (j, cluster) in self.clusters.iter_mut().enumerate() {
            if !std::mem::take(&mut cluster.stale) {
                continue;
            }
            for _ in 0..INNER {
                for (i, t) in target.iter_mut().enumerate() {
                    *t = if self.labels[i] == j as u32 { log_obs[i] } else { cluster.log_pred[i] };
                }
                // Over-relaxed: the EM step scaled by OMEGA (it is a contraction with
                // eigenvalues in [0, 1), so any factor below 2 converges, and the slow
                // directions, those the cluster has few samples on, go faster).
                let em = prepared.solve_log(&target);
                let y = &cluster.y;
                cluster.y = Mat::from_fn(y.nrows(), 3, |r, c| y[(r, c)] + OMEGA * (em[(r, c)] - y[(r, c)]));
                cluster.log_pred = prepared.predict_log(&cluster.y);
            }
        }
    }

    /// Move every sample to the cluster that explains it and its surface cell best, then to
    /// the label most of its pixel neighbourhood has. Returns how many samples changed
    /// cluster.
    ///
    /// The cell term is what ties views together: a point of the surface has one material
    /// whatever the light, so a glossy stripe's highlight in one view and the same stripe
    /// unlit in another must fall to one term. Without it the highlight alone can go to a
    /// matte region's term, which then shows a highlight under every new light.
    fn reassign(&mut self, log_obs: &[[f64; 3]], near: &Near) -> usize {
        let j = self.clusters.len();
        let mut err = vec![0.0; log_obs.len() * j];
        for (k, c) in self.clusters.iter().enumerate() {
            for (i, (o, p)) in log_obs.iter().zip(&c.log_pred).enumerate() {
                err[i * j + k] = sq(residual(*o, *p));
            }
        }
        let mut cell_err = vec![0.0; near.cells * j];
        let mut cell_count = vec![0u32; near.cells];
        for (i, &b) in near.cell.iter().enumerate() {
            cell_count[b as usize] += 1;
            for k in 0..j {
                cell_err[b as usize * j + k] += err[i * j + k];
            }
        }
        let best: Vec<u32> = (0..log_obs.len())
            .map(|i| {
                let b = near.cell[i] as usize;
                let score = |k: usize| err[i * j + k] + cell_err[b * j + k] / cell_count[b] as f64;
                (0..j).min_by(|&a, &b| score(a).total_cmp(&score(b))).unwrap_or(0) as u32
            })
            .collect();
        let neighbours = &near.pixels;
        let mut votes = vec![0u32; j];
        let mut changed = 0;
        for i in 0..log_obs.len() {
            let mut label = best[i];
            if !neighbours[i].is_empty() {
                votes.iter_mut().for_each(|v| *v = 0);
                votes[best[i] as usize] += 1;
                for &k in &neighbours[i] {
                    votes[best[k as usize] as usize] += 1;
                }
                let (top, &count) = votes.iter().enumerate().max_by_key(|&(_, v)| *v).expect("one cluster at least");
                if 2 * count > neighbours[i].len() as u32 + 1 {
                    label = top as u32;
                }
            }
            if label != self.labels[i] {
                changed += 1;
                self.clusters[label as usize].stale = true;
                self.clusters[self.labels[i] as usize].stale = true;
            }
            self.labels[i] = label;
        }
        changed
    }

    /// Remove clusters no sample belongs to.
    fn drop_empty(&mut self) {
        let mut count = vec![0usize; self.clusters.len()];
        self.labels.iter().for_each(|&l| count[l as usize] += 1);
        let mut renumber = vec![0u32; self.clusters.len()];
        let mut kept = Vec::new();
        for (j, c) in std::mem::take(&mut self.clusters).into_iter().enumerate() {
            renumber[j] = kept.len() as u32;
            if count[j] > 0 {
                kept.push(c);
            }
        }
        self.clusters = kept;
        self.labels.iter_mut().for_each(|l| *l = renumber[*l as usize]);
    }

    /// Linear-space errors of every sample against its cluster's product (no gains).
    fn errors(&self, prepared: &Prepared, map: &LogMap, values: &[[f64; 3]]) -> Errors {
        let predicted: Vec<Vec<[f64; 3]>> = self.clusters.iter().map(|c| prepared.predict(&prepared.split(&c.y), map)).collect();
        let mine: Vec<[f64; 3]> = self.labels.iter().enumerate().map(|(i, &l)| predicted[l as usize][i]).collect();
        crate::factor::errors(&mine, values)
    }

    /// The material's terms: each cluster's product, with its gain where the cluster is.
    fn terms(&self, prepared: &Prepared, map: &LogMap, values: &[[f64; 3]], layout: &Layout) -> Result<Vec<Term>> {
        let tables: Vec<_> = self.clusters.iter().map(|c| prepared.split(&c.y)).collect();
        if tables.iter().flatten().flatten().flatten().any(|x| !x.is_finite()) {
            return Err(Error::Numeric("a material-map term is not finite (values span too many orders of magnitude)".into()));
        }
        let predicted: Vec<Vec<[f64; 3]>> = tables.iter().map(|t| prepared.predict(t, map)).collect();
        // How much a sample says about its texel: a sample its own term predicts dark (a
        // shadow, a grazing light) fits any label and any gain, and must not dilute the
        // samples of other views that see the texel lit.
        let mut weight: Vec<f64> = self.labels.iter().enumerate().map(|(i, &l)| sq(predicted[l as usize][i])).collect();
        let mean_weight = weight.iter().sum::<f64>() / weight.len().max(1) as f64;
        weight.iter_mut().for_each(|w| *w += 1e-3 * mean_weight + 1e-300);
        // The terms' textures are independent: one per thread.
        let terms = tables
            .par_iter()
            .zip(&predicted)
            .enumerate()
            .map(|(j, (tables, predicted))| {
                // A sample whose prediction is tiny says nothing about the gain: the gain is
                // pulled to 1 there, not divided by nearly zero.
                let mut scale = [0.0f64; 3];
                let mut count = 0usize;
                for (i, p) in predicted.iter().enumerate() {
                    if self.labels[i] == j as u32 {
                        count += 1;
                        (0..3).for_each(|c| scale[c] += p[c] * p[c]);
                    }
                }
                let eps = scale.map(|s| 0.0025 * s / count.max(1) as f64 + 1e-300);
                let coefficient: Vec<[f64; 3]> = (0..values.len())
                    .map(|i| {
                        if self.labels[i] != j as u32 {
                            return [0.0; 3];
                        }
                        let (f, p) = (values[i], predicted[i]);
                        [0, 1, 2].map(|c| (f[c] * p[c] + eps[c]) / (p[c] * p[c] + eps[c]))
                    })
                    .collect();
                let coef = Coefficients { res: layout.res, texels: layout.texture(&coefficient, Combine::Mean(&weight)) };
                term(prepared, tables, *map, coef)
            })
            .collect();
        Ok(terms)
    }
}

/// What lies near each sample: its pixel neighbours, and its cell of a coarse uv grid that
/// all views share.
struct Near {
    pixels: Vec<Vec<u32>>,
    cell: Vec<u32>,
    cells: usize,
}

impl Near {
    fn new(grids: &[Grid], layout: &Layout, n: usize) -> Near {
        // About eight samples a cell where the paintings cover the texture evenly.
        let res = (((n / 8) as f64).sqrt().round() as usize).clamp(8, layout.res);
        let cell = (0..n).map(|i| crate::factor::param::uv_nearest_node(layout.uv(i), res) as u32).collect();
        Near { pixels: neighbours(grids, n), cell, cells: res * res }
    }
}

/// Each sample's pixel neighbours (8-neighbourhood) in the painted grids.
fn neighbours(grids: &[Grid], n: usize) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); n];
    for g in grids {
        if g.sample.len() != g.width * g.height {
            continue;
        }
        for k in 0..g.sample.len() {
            let Some(s) = g.sample[k].filter(|&s| (s as usize) < n) else { continue };
            for m in crate::images::neighbours8(k, g.width, g.sample.len()) {
                if let Some(t) = g.sample[m].filter(|&t| (t as usize) < n) {
                    out[s as usize].push(t);
                }
            }
        }
    }
    out
}

fn residual(o: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    [o[0] - p[0], o[1] - p[1], o[2] - p[2]]
}

fn sq(r: [f64; 3]) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

fn mean3(r: &[[f64; 3]]) -> [f64; 3] {
    let mut m = [0.0; 3];
    r.iter().for_each(|x| (0..3).for_each(|c| m[c] += x[c]));
    m.map(|x| x / r.len().max(1) as f64)
}

/// The principal axes of the rows of `r` about `mean`, largest spread first: power
/// iteration with deflation on their 3×3 covariance.
fn principal_axes(r: &[[f64; 3]], mean: [f64; 3]) -> Vec<[f64; 3]> {
    let mut cov = [[0.0; 3]; 3];
    for x in r {
        let d = residual(*x, mean);
        for a in 0..3 {
            for b in 0..3 {
                cov[a][b] += d[a] * d[b];
            }
        }
    }
    let mut axes: Vec<[f64; 3]> = Vec::new();
    for start in [[1.0, 1.0, 1.0], [1.0, -1.0, 0.0], [1.0, 1.0, -2.0]] {
        let mut v: [f64; 3] = start;
        for _ in 0..100 {
            // Remove the axes found so far, so the iteration finds the next one.
            for a in &axes {
                let d: f64 = (0..3).map(|c| v[c] * a[c]).sum();
                v = [0, 1, 2].map(|c| v[c] - d * a[c]);
            }
            let w = [0, 1, 2].map(|a| (0..3).map(|b| cov[a][b] * v[b]).sum::<f64>());
            let norm = sq(w).sqrt();
            if norm < 1e-300 {
                break;
            }
            v = w.map(|x| x / norm);
        }
        for a in &axes {
            let d: f64 = (0..3).map(|c| v[c] * a[c]).sum();
            v = [0, 1, 2].map(|c| v[c] - d * a[c]);
        }
        let norm = sq(v).sqrt();
        if norm > 1e-9 {
            axes.push(v.map(|x| x / norm));
        }
    }
    axes
}

