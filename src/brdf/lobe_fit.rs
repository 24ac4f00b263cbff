//! Fitting a lobe of the analytic base ([`super::lobe`]) to samples: the width $\alpha$
//! (shared by the channels) by a one-dimensional search, $a$, $k_d$, $k_s$, $k_f \ge 0$ per
//! channel by weighted non-negative linear least squares, relative weights (dark and bright
//! samples count alike, as in log space). $k_f$ is ridged ([`FRESNEL_RIDGE`]): paintings
//! under a light near the camera show $\theta_d$ below 30°, where $(1 - \cos\theta_d)^5 <
//! 10^{-4}$, and cannot show a Fresnel rise, so there the ridge says what it is: a
//! dielectric's (plastic, paint: a neutral highlight over a body colour, [`dielectric`])
//! for $F_0 = 0.04$, a conductor's none (its $F_0$ is high, its rise small),
//! Ashikhmin-Shirley's its model's own.

use std::f64::consts::PI;

use rayon::prelude::*;

use super::lobe::{Base, Lobe, DIELECTRIC_F0};
use crate::factor::Pattern;

/// The GGX widths $\alpha$ the fit tries: log-spaced from a near mirror to fully rough.
const ALPHAS: usize = 28;
const ALPHA_MIN: f64 = 0.01;
const ALPHA_MAX: f64 = 1.0;
/// Golden-section steps refining $\alpha$ after the grid (each shrinks the bracket by 0.618:
/// 12 take a ±19% bracket to ±0.1%).
const REFINE_STEPS: usize = 12;

/// The ridge on the Fresnel coefficient $k_f$, relative to the weighted energy of the
/// specular column: $k_f$ costs $\lambda \sum w\, s^2 k_f^2$ (with $s$ the lobe without
/// Fresnel). The Fresnel column is the specular one times $(1 - \cos\theta_d)^5$, below 2e-5
/// on front-lit paintings, so its energy there is far below the ridge and $k_f$ stays at
/// the ridge's target (0, or a dielectric's: [`DIELECTRIC_FRESNEL`]); under side and back
/// light (the wide paintings, θ_d to 77°) the data decide, and GGX's $1 - F_0$ comes back
/// within 4%. Ashikhmin-Shirley's ridge pulls toward its own coupled Fresnel instead
/// ([`solve_ridged`]).
const FRESNEL_RIDGE: f64 = 1e-4;

/// Schlick's $(1 - F_0)/F_0$ of a dielectric ([`DIELECTRIC_F0`]): where a painting shows no
/// grazing $\theta_d$, a dielectric's $k_f$ is ridged toward this times its grey $k_s$ (its
/// Fresnel rise is the light's colour), not toward 0.
const DIELECTRIC_FRESNEL: f64 = (1.0 - DIELECTRIC_F0) / DIELECTRIC_F0;

/// A dielectric's $F_0$ changes by under 5% across the visible (dispersion), and a light's
/// colour calibration adds a few percent per channel: a specular colour farther than this
/// from grey (once the part that follows the body colour is taken out) is a conductor's.
const NEUTRAL_SPECULAR: f64 = 0.1;

/// A conductor has no body (diffuse) reflection; most dielectrics' body albedo is several
/// times their $F_0$ of 0.04. Where the body is darker than $F_0$ (black plastic: 0.02) the
/// lobe could as well be a metal's with a tail the diffuse took, and a rise invented for a
/// metal (×24) costs more than one missed on black plastic, so those keep none.
const BODY_OVER_F0: f64 = 1.0;

/// The relative weight's softening: samples are weighted by $1/(S + \delta)^2$ with
/// $\delta$ this fraction of the channel's largest value, so the fit is relative (dark and
/// bright parts of a painting count alike, as in log space) without dividing by zero.
const WEIGHT_SOFTENING: f64 = 0.05;

/// At most this many samples enter the search over $\alpha$ (every k-th sample).
const SEARCH_SAMPLES: usize = 4096;

/// At most this many samples (every k-th) enter the final linear fit of the colours and
/// the misfit `auto` judges: all of a 256² painting's, a quarter of a 512² one's (fitting
/// all 147k took about 40 ms, for four coefficients per channel).
const FIT_SAMPLES: usize = 40_000;

impl Base {
    /// Fit the lobe to values on a pattern: $\alpha$ by search, the rest by
    /// weighted non-negative least squares (weights $1/(S + \delta)^2$, so relative). Returns
    /// the lobe and its relative misfit $\sqrt{\sum w (B - S)^2 / \sum w S^2}$; `None` when
    /// the values are all zero.
    pub fn fit(pattern: &Pattern, values: &[[f64; 3]]) -> Option<(Base, f64)> {
        Base::fit_lobe(pattern, values, Lobe::Ggx)
    }

    /// [`Base::fit`] of every lobe family ([`Lobe::ALL`]): the one of least misfit.
    ///
    /// A headlit painting ([`Pattern::headlit`]) hardly tells an ambient from a shading that
    /// falls slowly toward the rim (Oren-Nayar's, Minnaert's), and an ambient stays lit with
    /// the light behind: a headlit Minnaert painting with brush texture was held best by a
    /// Blinn-Phong lobe over an ambient (misfit 0.0505; 0.0507 for the best lobe without
    /// one), and its material kept 53% of its brightness with the light behind (the truth:
    /// none). There the families are fitted without an ambient, and the best one with an
    /// ambient is kept only where it holds the painting clearly better
    /// ([`HEADLIT_AMBIENT_GAIN`]): a Gooch painting's cool rim.
    pub fn fit_any(pattern: &Pattern, values: &[[f64; 3]]) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        // The families on their own threads; the least misfit wins, the first of equals.
        let best = |ambient: bool| {
            Lobe::ALL
                .par_iter()
                .enumerate()
                .filter_map(|(n, &lobe)| Base::fit_with(pattern, values, delta, lobe, ambient).map(|fit| (n, fit)))
                .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1).then(a.0.cmp(&b.0)))
                .map(|(_, fit)| fit)
        };
        let lit = best(true)?;
        if !pattern.headlit() {
            return Some(lit);
        }
        match best(false) {
            Some(dark) if lit.1 >= HEADLIT_AMBIENT_GAIN * dark.1 => Some(dark),
            _ => Some(lit),
        }
    }

    /// [`Base::fit`] with a lobe of family `lobe`.
    pub fn fit_lobe(pattern: &Pattern, values: &[[f64; 3]], lobe: Lobe) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        Base::fit_with(pattern, values, delta, lobe, true)
    }

    /// [`Base::fit_lobe`] with the width given: `alpha` held, so that only the directions'
    /// fit is compared ([`crate::read::register`] turns the light under it).
    pub fn fit_lobe_at(pattern: &Pattern, values: &[[f64; 3]], lobe: Lobe, alpha: f64) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        Some(Base::fit_at(pattern, values, delta, lobe, alpha, true))
    }

    /// [`Base::fit_lobe`] with or without an ambient.
    fn fit_with(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, ambient: bool) -> Option<(Base, f64)> {
        let alpha = if lobe.has_width() { Base::search_width(pattern, values, delta, lobe, ambient)? } else { 1.0 };
        Some(Base::fit_at(pattern, values, delta, lobe, alpha, ambient))
    }

    /// The lobe of family `lobe` and width `alpha`, its colours fitted, and its misfit.
    fn fit_at(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, alpha: f64, ambient: bool) -> (Base, f64) {
        // The colours from every sample up to [`FIT_SAMPLES`] (every k-th beyond).
        let fitted = fitted_samples(pattern.len());
        let eq = normal_equations(pattern, values, &fitted, delta, lobe, alpha, ambient);
        let mut fit = solve_ridged(eq, lobe, alpha, None);
        // A dielectric's Fresnel where the samples cannot show it ([`DIELECTRIC_FRESNEL`]):
        // the same equations, the ridge's target moved.
        let grey = if lobe.fresnel_from_data() { dielectric(lobe, alpha, &fit.1) } else { None };
        if let Some(grey) = grey {
            fit = solve_ridged(eq, lobe, alpha, Some(DIELECTRIC_FRESNEL * grey));
        }
        let (res, k, penalty) = fit;
        let res = (res - penalty).max(0.0);
        // The misfit relative to the weighted values: $\sqrt{\sum w (B - S)^2 / \sum w S^2}$
        // (the data's part of the objective; the ridge's penalty is no misfit).
        let misfit = (res / weighted_energy(values, &fitted, delta).max(f64::MIN_POSITIVE)).sqrt();
        let ambient = k.map(|x| x[0]);
        (Base { ambient, diffuse: k.map(|x| x[1]), specular: k.map(|x| x[2]), fresnel: k.map(|x| x[3]), alpha, lobe }, misfit)
    }

    /// The width of `lobe` that fits `values` best: a log grid of [`ALPHAS`] on every k-th
    /// sample up to [`SEARCH_SAMPLES`], refined by golden section.
    fn search_width(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, ambient: bool) -> Option<f64> {
        let stride = pattern.len().div_ceil(SEARCH_SAMPLES).max(1);
        let search: Vec<usize> = (0..pattern.len()).step_by(stride).collect();
        let mut best: Option<(f64, f64)> = None; // (residual, alpha)
        for i in 0..ALPHAS {
            let alpha = ALPHA_MIN * (ALPHA_MAX / ALPHA_MIN).powf(i as f64 / (ALPHAS - 1) as f64);
            let (res, ..) = linear_fit(pattern, values, &search, delta, lobe, alpha, ambient);
            if best.is_none_or(|b| res < b.0) {
                best = Some((res, alpha));
            }
        }
        let (_, alpha) = best?;
        // Refine $\alpha$ between the grid's neighbours by golden-section search on
        // $\log\alpha$: the grid's step (about 19%) alone leaves a GGX truth a misfit of a few
        // percent, which would hide it among the models of other families.
        let step = (ALPHA_MAX / ALPHA_MIN).ln() / (ALPHAS - 1) as f64;
        let at = |x: f64| linear_fit(pattern, values, &search, delta, lobe, x.exp(), ambient).0;
        let (mut lo, mut hi) = ((alpha.ln() - step).max(ALPHA_MIN.ln()), (alpha.ln() + step).min(ALPHA_MAX.ln()));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut f1, mut f2) = (at(x1), at(x2));
        for _ in 0..REFINE_STEPS {
            if f1 < f2 {
                hi = x2;
                (x2, f2) = (x1, f1);
                x1 = hi - g * (hi - lo);
                f1 = at(x1);
            } else {
                lo = x1;
                (x1, f1) = (x2, f2);
                x2 = lo + g * (hi - lo);
                f2 = at(x2);
            }
        }
        Some(if at(alpha.ln()) <= f1.min(f2) { alpha } else if f1 < f2 { x1.exp() } else { x2.exp() })
    }
}

/// The grey part $n$ of the specular colour when a fitted lobe reads as a dielectric
/// (plastic, paint, glaze): $k_s \approx n + m\,k_d$ (a fit lends the lobe some of the
/// body's colour, $m \ge 0$) with what is left within [`NEUTRAL_SPECULAR`] of $n$, and a
/// body at least [`BODY_OVER_F0`] times the lobe's $F_0$. `None` for a conductor, whose
/// Fresnel is left to the data: its $F_0$ is 0.5–0.95, so its rise is small.
fn dielectric(lobe: Lobe, alpha: f64, k: &[[f64; 4]; 3]) -> Option<f64> {
    let (ks, kd) = (k.map(|x| x[2]), k.map(|x| x[1]));
    let mean = |x: [f64; 3]| x.iter().sum::<f64>() / 3.0;
    let (ms, md) = (mean(ks), mean(kd));
    // Least squares of k_s = n + m k_d over the channels.
    let var: f64 = kd.iter().map(|d| (d - md).powi(2)).sum();
    let cov: f64 = kd.iter().zip(&ks).map(|(d, s)| (d - md) * (s - ms)).sum();
    let m = if var > 0.0 { (cov / var).max(0.0) } else { 0.0 };
    let n = ms - m * md;
    if n <= 0.0 || (0..3).any(|c| (ks[c] - n - m * kd[c]).abs() > NEUTRAL_SPECULAR * n) {
        return None;
    }
    // F_0 as the lobe's reflectance at normal view: k_s times its specular albedo there.
    let f0 = ms * specular_albedo(lobe, alpha);
    (PI * md >= BODY_OVER_F0 * f0).then_some(n)
}

/// The lobe's specular shading at unit $k_s$ integrated over the light's hemisphere, seen
/// along the normal: $2\pi \int s(\theta_l) \sin\theta_l\, d\theta_l$ (every family
/// that has a Fresnel is isotropic about the normal there). Nodes at $\theta = \frac\pi2
/// t^2$ crowd near the normal, where a sharp lobe lies.
fn specular_albedo(lobe: Lobe, alpha: f64) -> f64 {
    const NODES: usize = 1024;
    let v = glam::DVec3::Z;
    (0..NODES)
        .map(|i| {
            let t = (i as f64 + 0.5) / NODES as f64;
            let theta = 0.5 * PI * t * t;
            let l = glam::DVec3::new(theta.sin(), 0.0, theta.cos());
            // dθ = π t dt.
            2.0 * PI * lobe.shape(l, v, alpha).1 * theta.sin() * PI * t / NODES as f64
        })
        .sum()
}

/// Each channel's largest value and the relative weight's softening $\delta$
/// ([`WEIGHT_SOFTENING`] of it); `None` when every value is zero.
pub(crate) fn softening(values: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let mut max = [0.0f64; 3];
    for v in values {
        for c in 0..3 {
            max[c] = max[c].max(v[c]);
        }
    }
    (!max.iter().all(|&m| m <= 0.0)).then(|| (max, max.map(|m| (WEIGHT_SOFTENING * m).max(1e-12))))
}

/// $\sum w S^2$ over the samples `idx`, $w = 1/(S + \delta)^2$: the scale of a relative misfit.
fn weighted_energy(values: &[[f64; 3]], idx: &[usize], delta: [f64; 3]) -> f64 {
    idx.iter().map(|&i| &values[i]).map(|v| (0..3).map(|c| (v[c] / (v[c] + delta[c])).powi(2)).sum::<f64>()).sum()
}

/// On a headlit painting the lobe families keep an ambient only when the best of them with
/// one misfits less than this fraction of the best without ([`Base::fit_any`]).
pub const HEADLIT_AMBIENT_GAIN: f64 = 0.5;

/// The samples a misfit is measured on: every one up to [`FIT_SAMPLES`], every k-th beyond.
fn fitted_samples(n: usize) -> Vec<usize> {
    (0..n).step_by(n.div_ceil(FIT_SAMPLES).max(1)).collect()
}

/// The relative misfit of any prediction of the samples in the measure [`Base::fit`] reports
/// for its lobe, $\sqrt{\sum w (P - S)^2 / \sum w S^2}$ on the same samples: so a lobe's
/// misfit and the product's compare directly.
pub fn misfit(values: &[[f64; 3]], predicted: &[[f64; 3]]) -> f64 {
    let Some((_, delta)) = softening(values) else { return 0.0 };
    let idx = fitted_samples(values.len().min(predicted.len()));
    let res: f64 = idx.iter().map(|&i| (0..3).map(|c| (predicted[i][c] - values[i][c]).powi(2) / (values[i][c] + delta[c]).powi(2)).sum::<f64>()).sum();
    (res / weighted_energy(values, &idx, delta).max(f64::MIN_POSITIVE)).sqrt()
}

/// Weighted non-negative least squares of $(a, k_d, k_s, k_f)$ per channel for a fixed
/// $\alpha$ over the samples `idx` ($k_f$ ridged toward 0, [`FRESNEL_RIDGE`]; $a = 0$ unless
/// `ambient`): [`solve_ridged`] of [`normal_equations`].
fn linear_fit(pattern: &Pattern, values: &[[f64; 3]], idx: &[usize], delta: [f64; 3], lobe: Lobe, alpha: f64, ambient: bool) -> (f64, [[f64; 4]; 3], f64) {
    solve_ridged(normal_equations(pattern, values, idx, delta, lobe, alpha, ambient), lobe, alpha, None)
}

/// The weighted linear fit's normal equations per channel: $G = \sum w x x^\top$,
/// $b = \sum w x s$, $c = \sum w s^2$ (what [`solve_ridged`] solves, under any ridge).
#[derive(Clone, Copy)]
struct NormalEquations {
    g: [[[f64; N]; N]; 3],
    b: [[f64; N]; 3],
    ss: [f64; 3],
}

/// [`NormalEquations`] of $(a, k_d, k_s, k_f)$ for a fixed $\alpha$ over the samples `idx`
/// (weights $1/(S + \delta)^2$; $a = 0$ unless `ambient`).
fn normal_equations(pattern: &Pattern, values: &[[f64; 3]], idx: &[usize], delta: [f64; 3], lobe: Lobe, alpha: f64, ambient: bool) -> NormalEquations {
    let mut eq = NormalEquations { g: [[[0.0f64; N]; N]; 3], b: [[0.0f64; N]; 3], ss: [0.0f64; 3] };
    for &i in idx {
        let q = &pattern.queries[i];
        let (diffuse, spec, x5) = lobe.shape(q.l, q.v, alpha);
        let x = [if ambient { 1.0 } else { 0.0 }, diffuse, spec, spec * x5];
        for c in 0..3 {
            let s = values[i][c];
            let w = 1.0 / (s + delta[c]).powi(2);
            for r in 0..N {
                for k in 0..N {
                    eq.g[c][r][k] += w * x[r] * x[k];
                }
                eq.b[c][r] += w * x[r] * s;
            }
            eq.ss[c] += w * s * s;
        }
    }
    eq
}

/// The non-negative solution of `eq` with $k_f$ ridged ([`FRESNEL_RIDGE`]) toward 0, or
/// toward `rise` in every channel: the summed weighted residual with the ridge's penalty
/// (what the fit minimizes), the coefficients, and the penalty alone (so a misfit can leave
/// it out).
fn solve_ridged(eq: NormalEquations, lobe: Lobe, alpha: f64, rise: Option<f64>) -> (f64, [[f64; 4]; 3], f64) {
    let NormalEquations { mut g, mut b, mut ss } = eq;
    let (mut total, mut penalty) = (0.0, 0.0);
    let mut coef = [[0.0; N]; 3];
    // Ashikhmin-Shirley's Fresnel is part of its model: Schlick's with F_0 = R_s under its
    // normalization (n + 1)/(8π), so k_s = (n + 1)/(8π) R_s and k_f = (n + 1)/(8π)(1 − R_s)
    // for shading under a unit light (what samples are: the scene's light divided out). Its
    // ridge pulls k_s + k_f to (n + 1)/(8π) instead of k_f to 0, so paintings that show no
    // grazing θ_d get the model's own Fresnel, and those that do still decide it. (GGX's
    // k_s + k_f = 1 was tried and rejected: MERL's ABC lobes are not GGX's normalization, and
    // `auto` got worse than the plain product on 13 of them; no MERL material takes this
    // family, so none changes.)
    let coupled = lobe == Lobe::AshikhminShirley;
    let target = if coupled { (Lobe::exponent(alpha) + 1.0) / (8.0 * PI) } else { 0.0 };
    for c in 0..3 {
        // The ridge is part of the objective (so of the residual that picks alpha too).
        let ridge = FRESNEL_RIDGE * g[c][2][2];
        g[c][3][3] += ridge;
        if coupled {
            // λ (k_s + k_f − t)²: the k_f² part is above.
            g[c][2][2] += ridge;
            g[c][2][3] += ridge;
            g[c][3][2] += ridge;
            b[c][2] += ridge * target;
            b[c][3] += ridge * target;
            ss[c] += ridge * target * target;
        } else if let Some(t) = rise {
            // λ (k_f − t)²: the k_f² part is above.
            b[c][3] += ridge * t;
            ss[c] += ridge * t * t;
        }
        let (res, k) = nnls(&g[c], &b[c], ss[c]);
        total += res;
        penalty += match (coupled, rise) {
            (true, _) => ridge * (k[2] + k[3] - target).powi(2),
            (false, Some(t)) => ridge * (k[3] - t).powi(2),
            (false, None) => ridge * k[3] * k[3],
        };
        coef[c] = k;
    }
    (total, coef, penalty)
}

/// Unknowns of the linear fit: ambient, diffuse, specular, Fresnel.
const N: usize = 4;

/// Non-negative least squares with [`N`] unknowns from its normal equations: every subset
/// of free unknowns (fifteen) is solved and the best feasible one kept. The residual is
/// $c - 2k^\top b + k^\top G k$.
fn nnls(g: &[[f64; N]; N], b: &[f64; N], c: f64) -> (f64, [f64; N]) {
    let residual = |k: &[f64; N]| {
        let mut r = c;
        for i in 0..N {
            r -= 2.0 * k[i] * b[i];
            for j in 0..N {
                r += k[i] * g[i][j] * k[j];
            }
        }
        r.max(0.0)
    };
    let mut best = ([0.0; N], residual(&[0.0; N]));
    for mask in 1u8..(1 << N) {
        let free: Vec<usize> = (0..N).filter(|&i| mask & (1 << i) != 0).collect();
        let n = free.len();
        let mut a = [[0.0f64; N + 1]; N];
        for (r, &i) in free.iter().enumerate() {
            for (k, &j) in free.iter().enumerate() {
                a[r][k] = g[i][j];
            }
            // A tiny ridge keeps a column that is zero on these samples (no lit sample, no
            // highlight) from making the system singular.
            a[r][r] += 1e-12 * (g[i][i] + 1e-300);
            a[r][n] = b[i];
        }
        let Some(x) = solve_small(&mut a, n) else { continue };
        if x.iter().take(n).any(|&v| v < 0.0 || !v.is_finite()) {
            continue;
        }
        let mut k = [0.0; N];
        for (r, &i) in free.iter().enumerate() {
            k[i] = x[r];
        }
        let res = residual(&k);
        if res < best.1 {
            best = (k, res);
        }
    }
    (best.1, best.0)
}

/// Gaussian elimination with partial pivoting on an n × (n+1) augmented system (n ≤ [`N`]),
/// the right-hand side in column n.
#[allow(clippy::needless_range_loop)] // index loops over a small array read best as the math
fn solve_small(a: &mut [[f64; N + 1]; N], n: usize) -> Option<[f64; N]> {
    for col in 0..n {
        let p = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, p);
        for r in col + 1..n {
            let f = a[r][col] / a[col][col];
            for k in col..=n {
                a[r][k] -= f * a[col][k];
            }
        }
    }
    let mut x = [0.0; N];
    for r in (0..n).rev() {
        let mut s = a[r][n];
        for k in r + 1..n {
            s -= a[r][k] * x[k];
        }
        x[r] = s / a[r][r];
    }
    Some(x)
}


#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{Analytic, Reflectance, SphereView};
    use crate::factor::errors;
    use glam::DVec3;

    /// A GGX sphere is recovered: the fitted lobe's $\alpha$ is the truth's within the
    /// search grid's step, and $B$ alone matches $S$ closely.
    #[test]
    fn fits_a_ggx_sphere() {
        let truth = Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.5, 0.5, 0.5], 0.2);
        let views: Vec<_> = [DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.6, 0.2, 0.8)].iter().map(|&l| SphereView::new(l, 64)).collect();
        let pattern = Pattern::concat(&views.iter().map(SphereView::pattern).collect::<Vec<_>>());
        let values = pattern.shade(|q| truth.shading(q));
        let (base, misfit) = Base::fit(&pattern, &values).expect("a fit");
        assert!(misfit < 1e-3, "misfit {misfit}");
        let step = (ALPHA_MAX / ALPHA_MIN).powf(1.0 / (ALPHAS - 1) as f64);
        assert!(base.alpha > 0.2 / step && base.alpha < 0.2 * step, "alpha {} for truth 0.2", base.alpha);
        let fitted = pattern.shade(|q| base.shading(q));
        let e = errors(&fitted, &values).rms_relative;
        assert!(e < 0.1, "relative RMS of the base alone {e}");
    }

    /// Each family's truth is told from the others and recovered: Blinn-Phong, Phong and
    /// Ashikhmin-Shirley (exponents 32, 50 and 100: α = √(2/(e + 2))), Ward, GGX,
    /// Oren-Nayar and Minnaert spheres from two views get their own lobe, their width within
    /// 2% and a misfit near zero; Oren-Nayar's σ = 0.5 comes back in its B/A.
    #[test]
    fn every_lobe_family_is_recovered_from_its_truth() {
        let views: Vec<_> = [DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.6, 0.2, 0.8)].iter().map(|&l| SphereView::new(l, 64)).collect();
        let pattern = Pattern::concat(&views.iter().map(SphereView::pattern).collect::<Vec<_>>());
        let cases = [
            (Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 32.0 }, Lobe::BlinnPhong, (2.0f64 / 34.0).sqrt()),
            (Analytic::Phong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 50.0 }, Lobe::Phong, (2.0f64 / 52.0).sqrt()),
            (Analytic::Ward { diffuse: [0.4, 0.3, 0.2], specular: [0.3; 3], alpha: 0.2 }, Lobe::Ward, 0.2),
            (Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.5, 0.5, 0.5], 0.04), Lobe::Ggx, 0.04),
            (Analytic::AshikhminShirley { diffuse: [0.5, 0.3, 0.15], specular: [0.1, 0.12, 0.15], exponent: 100.0 }, Lobe::AshikhminShirley, (2.0f64 / 102.0).sqrt()),
            // Oren-Nayar has no width (its σ is in B/A); the fit's nominal width is 1.
            (Analytic::OrenNayar { albedo: [0.6, 0.4, 0.3], sigma: 0.5 }, Lobe::OrenNayar, 1.0),
            (Analytic::Minnaert { albedo: [0.6, 0.4, 0.3], k: 0.75 }, Lobe::Minnaert, 0.75),
        ];
        for (truth, lobe, alpha) in cases {
            let values = pattern.shade(|q| truth.shading(q));
            let (base, misfit) = Base::fit_any(&pattern, &values).expect("a fit");
            assert_eq!(base.lobe, lobe, "{}", truth.name());
            assert!((base.alpha / alpha - 1.0).abs() < 0.02 && misfit < 1e-3, "{}: alpha {} for {alpha}, misfit {misfit}", truth.name(), base.alpha);
            if lobe == Lobe::OrenNayar {
                // A = 1 − 0.5σ²/(σ² + 0.33), B = 0.45σ²/(σ² + 0.09) at σ = 0.5: B/A = 0.4132.
                let (a, b) = (1.0 - 0.5 * 0.25 / 0.58, 0.45 * 0.25 / 0.34);
                assert!((base.specular[1] / base.diffuse[1] - b / a).abs() < 1e-3, "{base:?}");
            }
            if lobe == Lobe::AshikhminShirley {
                // Its own Fresnel, though these lights show θ_d ≤ 30°: k_f = (n + 1)/(8π)(1 − R_s)
                // = 101/(8π) × 0.9 = 3.617 in red, and k_s = 101/(8π) × 0.1 = 0.402.
                let norm = 101.0 / (8.0 * std::f64::consts::PI);
                for (c, rs) in [0.1, 0.12, 0.15].into_iter().enumerate() {
                    assert!((base.specular[c] / (norm * rs) - 1.0).abs() < 0.02, "{base:?}");
                    assert!((base.fresnel[c] / (norm * (1.0 - rs)) - 1.0).abs() < 0.02, "{base:?}");
                }
            }
        }
    }

    /// Front-lit paintings (θ_d ≤ 30°, where Schlick's rise is under 2e-4) cannot show a
    /// Fresnel rise; the fit gives a plastic's (a grey $F_0 = 0.04$ over a red body) the
    /// dielectric's $k_f = 1 - F_0 = 0.96$ of its truth, and a conductor (gold's $F_0$, no
    /// body) or a coloured highlight over a body (the suite's GGX, $F_0$ 0.5–0.35) none.
    #[test]
    fn a_dielectrics_fresnel_is_given_where_paintings_cannot_show_it() {
        let views: Vec<_> = [DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.6, 0.2, 0.8)].iter().map(|&l| SphereView::new(l, 64)).collect();
        let pattern = Pattern::concat(&views.iter().map(SphereView::pattern).collect::<Vec<_>>());
        let fit = |truth: &Analytic| Base::fit(&pattern, &pattern.shade(|q| truth.shading(q))).expect("a fit").0;
        let plastic = fit(&Analytic::ggx_alpha([0.6, 0.08, 0.05], [0.04; 3], 0.1));
        assert!(plastic.fresnel.iter().all(|&f| (f / 0.96 - 1.0).abs() < 0.1), "{plastic:?}");
        for truth in [Analytic::ggx_alpha([0.0; 3], [1.0, 0.78, 0.34], 0.2), Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.50, 0.42, 0.35], 0.2)] {
            let base = fit(&truth);
            assert!((0..3).all(|c| base.fresnel[c] < 0.01 * base.specular[c]), "{}: {base:?}", truth.name());
        }
    }

    /// nnls on a problem with a known non-negative solution and one with a clamped unknown.
    #[test]
    fn nnls_solves_and_clamps() {
        // G = I, b = (1, 2, 3, 4): k = b, residual c - |b|² = 0.
        let mut g = [[0.0; N]; N];
        for (i, row) in g.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        let (r, k) = nnls(&g, &[1.0, 2.0, 3.0, 4.0], 30.0);
        assert!(k.iter().zip([1.0, 2.0, 3.0, 4.0]).all(|(a, b)| (a - b).abs() < 1e-9) && r < 1e-9, "{k:?} {r}");
        // b = (1, -2, 3, 4): the second unknown is clamped at zero.
        let (_, k) = nnls(&g, &[1.0, -2.0, 3.0, 4.0], 30.0);
        assert!(k[1] == 0.0 && (k[0] - 1.0).abs() < 1e-9 && (k[2] - 3.0).abs() < 1e-9 && (k[3] - 4.0).abs() < 1e-9, "{k:?}");
    }

    /// `misfit` is relative: a prediction 10% high everywhere misfits by 0.1 whatever the
    /// weights, and one 10% high on half the samples (of equal weight) by 0.1/√2.
    #[test]
    fn misfit_is_relative() {
        let values = vec![[1.0, 0.5, 0.25]; 10];
        let m = misfit(&values, &values.iter().map(|v| v.map(|x| 1.1 * x)).collect::<Vec<_>>());
        assert!((m - 0.1).abs() < 1e-12, "{m}");
        let half: Vec<[f64; 3]> = values.iter().enumerate().map(|(i, v)| if i % 2 == 0 { v.map(|x| 1.1 * x) } else { *v }).collect();
        assert!((misfit(&values, &half) - 0.1 / 2f64.sqrt()).abs() < 1e-12);
    }
}
