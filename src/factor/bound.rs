//! The light prior and the bound of a fit's log tables ([`super::robust`], eq. 3.4's
//! regularization moved onto a physical shape): shared by [`super::Prepared::solve`] and the
//! robust solve, so neither imports the other.

use std::sync::{Arc, Mutex};

use faer::Mat;

use super::mapping::LogMap;
use super::param::{self, Param};
use super::settings::{FactorSpec, Input, Settings};
use super::system::{self, Design};
use super::table::Stencil;

/// No factor and no rendered value of a robust fit exceeds `BOUND` × the painting's largest
/// value (per channel; plus the offset constant $a$ for the offset mapping, whose product is
/// $f + a$). Held-out views of the analytic suite peak at up to ~3× what one painting of it
/// shows (grazing GGX and Minnaert highlights), so 8 leaves room for them and still keeps two
/// white strokes from making a highlight of $10^{10}$.
pub const BOUND: f64 = 8.0;

/// The physical shape of the light factor, $t(\theta_l)$ in the mapping's log space, at a
/// node of a light-factor table.
fn light_shape(spec: &FactorSpec, node: usize, map: &LogMap, c: usize, max: f64, eps: f64, radius_deg: f64) -> f64 {
    let cos = match spec.param {
        Param::Radius => param::radius_inverse(param::warp_inverse(node as f64 / (spec.res - 1) as f64, spec.warp), spec.domain).cos(),
        Param::Parabolic | Param::Hemispherical => {
            let (i, j) = (node % spec.res, node / spec.res);
            let t = glam::DVec2::new(i as f64, j as f64) / (spec.res - 1) as f64;
            param::planar_inverse(spec.param, t, spec.domain).z
        }
        // Not light parameterizations (Settings::validate): no shape to pull toward.
        Param::Uv | Param::Radii => 1.0,
    };
    let s = max.max(1e-12) * (key_irradiance(cos, radius_deg) * (1.0 - eps) + eps);
    map.forward(c, s)
}

/// Irradiance from a spherical light of angular radius `radius_deg` at $\cos\theta_l$,
/// relative to its value facing it: $\cos\theta_l$ where the whole light is above the
/// horizon, 0 where none of it is, and between them the usual quadratic approximation
/// $(\cos\theta_l + \sin\alpha)^2 / (4 \sin\alpha)$, whose value and slope meet both. A
/// point light (radius 0) is $\max(\cos\theta_l, 0)$, with its corner at the terminator.
pub fn key_irradiance(cos: f64, radius_deg: f64) -> f64 {
    let s = radius_deg.to_radians().sin();
    if cos >= s {
        cos
    } else if cos <= -s {
        0.0
    } else {
        (cos + s).powi(2) / (4.0 * s)
    }
}

/// $\mathbf R_p \tilde{\mathbf t}$: the light factor's regularization applied to its prior
/// shape (n × 3; zero outside the light factor). Adding it to $\mathbf A^\top \tilde{\mathbf
/// f}$ makes those rows penalize $\tilde p - \tilde t$ instead of $\tilde p$.
pub(super) fn light_prior_rhs(settings: &Settings, design: &Design, map: &LogMap, max: [f64; 3], eps: f64) -> Mat<f64> {
    let mut b = Mat::zeros(design.n, 3);
    for (j, spec) in settings.factors.iter().enumerate() {
        if spec.input != Input::Light {
            continue;
        }
        let rows = system::factor_regularization(spec, design.rows() as f64);
        let o = design.offsets[j];
        for c in 0..3 {
            let t: Vec<f64> = (0..spec.len()).map(|i| light_shape(spec, i, map, c, max[c], eps, settings.light_radius_deg)).collect();
            for row in &rows {
                let rt: f64 = row.iter().map(|&(i, w)| w * t[i]).sum();
                for &(i, w) in row {
                    b[(o + i, c)] += w * rt;
                }
            }
        }
    }
    b
}

/// Bound log-space tables in place, so that no factor and no rendered value exceeds `k` ×
/// the channel's largest value `max` (plus $a$ for the offset mapping, whose product is
/// $f + a$), whatever the values were.
///
/// 1. The gauge (a constant moved between factors changes nothing): every factor but the
///    first is scaled so its data-weighted mean log value is 0, the first takes the
///    constant. The product is unchanged.
/// 2. Factors after the first are clamped to [`FACTOR_RANGE`] × that mean, and their nodes
///    no sample reaches (extrapolated by the smoothing: where $10^{10}$ came from) to the
///    highest reached node; the first factor to the bound.
/// 3. The product is evaluated on a grid of light and view directions ([`peak`]); where it
///    exceeds the bound, the first factor is scaled down so it does not (measured on the
///    faulty paintings: held-out median with strays 0.074 against 0.067 without this step,
///    clean and all faults unchanged).
pub fn bound_log(y: &mut Mat<f64>, settings: &Settings, design: &Design, map: &LogMap, max: [f64; 3], k: f64) {
    let j_count = settings.factors.len();
    if j_count == 0 {
        return;
    }
    let weight = design.node_weights();
    let range = FACTOR_RANGE.ln();
    let mut tops = [0.0; 3];
    for c in 0..3 {
        let mut shift = 0.0;
        for (j, spec) in settings.factors.iter().enumerate().skip(1) {
            let o = design.offsets[j];
            let (mut sw, mut swy) = (0.0, 0.0);
            for i in 0..spec.len() {
                sw += weight[o + i];
                swy += weight[o + i] * y[(o + i, c)];
            }
            let m = if sw > 0.0 && swy.is_finite() { swy / sw } else { 0.0 };
            shift += m;
            // Nodes the data reaches may rise to the range; nodes it does not (extrapolated
            // by the smoothing) no higher than the highest reached one.
            let reached = (0..spec.len()).filter(|&i| weight[o + i] >= 1.0).map(|i| y[(o + i, c)] - m).fold(f64::NEG_INFINITY, f64::max);
            let reached = reached.min(range);
            for i in 0..spec.len() {
                let x = y[(o + i, c)] - m;
                let cap = if weight[o + i] >= 1.0 { range } else { reached };
                // NaN (never expected: values are checked finite) becomes the ceiling.
                y[(o + i, c)] = if x.is_nan() { cap } else { x.min(cap) };
            }
        }
        let top = (k * max[c].max(1e-12) + if let LogMap::Offset { a } = map { a[c] } else { 0.0 }).ln();
        let o = design.offsets[0];
        for i in 0..settings.factors[0].len() {
            let x = y[(o + i, c)] + shift;
            y[(o + i, c)] = if x.is_nan() { top } else { x.min(top) };
        }
        tops[c] = top;
    }
    let peaks = peak(y, settings, design);
    let o = design.offsets[0];
    for c in 0..3 {
        let over = peaks[c] - tops[c];
        if over > 0.0 {
            for i in 0..settings.factors[0].len() {
                y[(o + i, c)] -= over;
            }
        }
    }
}

/// How far a factor after the first may rise above its data-weighted mean: 1000, more
/// than the sharpest highlight of the analytic suite (GGX, roughness 0.2) over its base.
pub const FACTOR_RANGE: f64 = 1e3;

/// An upper bound of [`peak`] per channel, for any directions: the log of the product of
/// every factor's largest node (a lookup interpolates nodes linearly, so it never exceeds
/// the largest). A few hundred comparisons where [`peak`] makes six thousand lookups; a fit
/// under the bound by this measure is under it by [`peak`]'s too.
pub(crate) fn ceiling(y: &Mat<f64>, settings: &Settings, design: &Design) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for (f, &o) in settings.factors.iter().zip(&design.offsets) {
        for (c, s) in sum.iter_mut().enumerate() {
            *s += (0..f.len()).map(|i| y[(o + i, c)]).fold(f64::NEG_INFINITY, f64::max);
        }
    }
    sum
}

/// Polar angles of the light over the whole sphere, of the view over the upper hemisphere,
/// and azimuth differences, in [`peak`]'s grid.
const GRID: [usize; 3] = [32, 16, 12];

/// The stencils of [`peak`]'s grid of queries for every factor but a uv one, query by
/// query. They depend only on the factors, so they are made once per set of factors (a
/// session sees a handful) and kept: made afresh, they were 0.8 ms of every 0.1 ms refit.
fn grid_stencils(factors: &[FactorSpec]) -> Arc<Vec<Stencil>> {
    /// The grid's stencils kept, per set of factors.
    type Kept = Vec<(Vec<FactorSpec>, Arc<Vec<Stencil>>)>;
    static MADE: Mutex<Kept> = Mutex::new(Vec::new());
    // A caller's projection is known by its name alone: not kept.
    let keep = !factors.iter().any(|f| matches!(f.input, Input::Custom(_)));
    let mut made = MADE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, s)) = made.iter().find(|(f, _)| keep && f == factors) {
        return s.clone();
    }
    use glam::{DVec2, DVec3};
    let dir = |theta: f64, phi: f64| DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
    let mut stencils = Vec::new();
    for a in 0..GRID[0] {
        let tl = std::f64::consts::PI * a as f64 / (GRID[0] - 1) as f64;
        for b in 0..GRID[1] {
            let tv = 0.5 * std::f64::consts::PI * b as f64 / (GRID[1] - 1) as f64;
            for d in 0..GRID[2] {
                let q = super::Query { l: dir(tl, 0.0), v: dir(tv, std::f64::consts::TAU * d as f64 / GRID[2] as f64), uv: DVec2::ZERO };
                stencils.extend(factors.iter().filter(|f| f.input != Input::Uv).map(|f| system::stencil(f, &q)));
            }
        }
    }
    let stencils = Arc::new(stencils);
    if !keep {
        return stencils;
    }
    if made.len() >= 8 {
        made.remove(0);
    }
    made.push((factors.to_vec(), stencils.clone()));
    stencils
}

/// The largest log product per channel over a grid of light directions (the whole sphere,
/// 32 polar angles), view directions (the upper hemisphere, 16) and 12 azimuth
/// differences, factors looked up as the shader does (linear interpolation of linear
/// values). A uv factor counts at its largest node.
pub(crate) fn peak(y: &Mat<f64>, settings: &Settings, design: &Design) -> [f64; 3] {
    let tables: Vec<Vec<[f64; 3]>> = settings
        .factors
        .iter()
        .zip(&design.offsets)
        .map(|(f, &o)| (0..f.len()).map(|i| [0, 1, 2].map(|c| y[(o + i, c)].exp())).collect())
        .collect();
    let mut base = [1.0f64; 3];
    for (f, t) in settings.factors.iter().zip(&tables) {
        if f.input == Input::Uv {
            for c in 0..3 {
                base[c] *= t.iter().map(|x| x[c]).fold(0.0, f64::max);
            }
        }
    }
    let looked: Vec<&Vec<[f64; 3]>> = settings.factors.iter().zip(&tables).filter(|(f, _)| f.input != Input::Uv).map(|(_, t)| t).collect();
    let mut best = [0.0f64; 3];
    if looked.is_empty() {
        return base.map(|x| x.ln());
    }
    for query in grid_stencils(&settings.factors).chunks(looked.len()) {
        let mut prod = base;
        for (stencil, t) in query.iter().zip(&looked) {
            let mut sum = [0.0; 3];
            for (i, w) in stencil.iter() {
                for c in 0..3 {
                    sum[c] += w * t[i][c];
                }
            }
            prod = [0, 1, 2].map(|c| prod[c] * sum[c]);
        }
        best = [0, 1, 2].map(|c| best[c].max(prod[c]));
    }
    best.map(|x| x.ln())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::{Pattern, Query};
    use glam::DVec3;

    /// The key light: a cosine away from the terminator, nothing behind the light's own
    /// size, and value and slope continuous across both joins (no corner for the light
    /// table to take); a point light keeps its corner.
    #[test]
    fn a_sized_key_light_meets_the_cosine_and_the_dark_without_a_corner() {
        let radius = 10.0;
        let s = f64::to_radians(radius).sin();
        let e = |x: f64| key_irradiance(x, radius);
        assert_eq!(e(0.7), 0.7);
        assert_eq!(e(-s - 1e-9), 0.0);
        let h = 1e-7;
        let slope = |x: f64| (e(x + h) - e(x - h)) / (2.0 * h);
        for join in [s, -s] {
            assert!((e(join + h) - e(join - h)).abs() < 3e-7, "value jumps at {join}");
            assert!((slope(join - 10.0 * h) - slope(join + 10.0 * h)).abs() < 1e-4, "slope jumps at {join}");
        }
        // At the horizon the light is half up: a quarter of its size's sine, not 0.
        assert!((e(0.0) - s / 4.0).abs() < 1e-12);
        assert_eq!((key_irradiance(1e-3, 0.0), key_irradiance(-1e-3, 0.0)), (1e-3, 0.0));
    }

    /// The ceiling bounds the grid's peak from above, and is reached when every factor's
    /// largest node is the one the grid looks up: p, q and r peaked at θ = 0, where the
    /// grid's query l = v = n looks up node 0 of each. Made twice (the second time from
    /// the kept stencils), the peak is the same.
    #[test]
    fn the_ceiling_bounds_the_peak_and_meets_it_when_the_maxima_coincide() {
        let settings = Settings::default();
        let pattern = Pattern::new(vec![Query::at(DVec3::Z, DVec3::Z), Query::at(DVec3::X, DVec3::Z)], false);
        let design = Design::new(&pattern, &settings).unwrap();
        // Peaked at node 0, falling: the maxima coincide.
        let y = Mat::from_fn(design.n, 3, |r, c| -0.01 * (r - design.offsets.iter().rfind(|&&o| o <= r).unwrap()) as f64 * (c + 1) as f64);
        let (top, grid) = (ceiling(&y, &settings, &design), peak(&y, &settings, &design));
        for c in 0..3 {
            assert!((top[c] - grid[c]).abs() < 1e-12, "{top:?} {grid:?}");
        }
        // Rough tables: the ceiling stays above, and the kept stencils give the same peak.
        let y = Mat::from_fn(design.n, 3, |r, c| ((r * 7 + c * 3) % 11) as f64 * 0.1);
        let (top, first) = (ceiling(&y, &settings, &design), peak(&y, &settings, &design));
        assert_eq!(first, peak(&y, &settings, &design));
        for c in 0..3 {
            assert!(top[c] >= first[c] - 1e-12, "{top:?} {first:?}");
        }
    }
}
