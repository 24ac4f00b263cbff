//! The glTF metallic-roughness material closest to a reflectance: weighted least squares on
//! the shading over direction pairs ([`super::coverage`]).
//!
//! At fixed metallic $m$ and roughness $r$ the shading is affine in the base colour,
//! $S = a + b\,c$ ([`affine_in_base_color`]), so each channel's $c$ is one weighted linear
//! least-squares solve, clamped to $[0, 1]$. $(m, r)$ are searched on a grid, then on a
//! grid ten times finer about the best.
//!
//! The loss is the squared relative error on the covered directions alone when they are
//! known, else on all directions: elsewhere the factored material is extrapolation, and a
//! share of it in the loss pulled a painted GGX sphere's fit to roughness 0.8 and a base
//! colour 15% too bright (tests/export.rs). Physics extrapolates the PBR material instead.

use crate::brdf::Reflectance;
use crate::factor::Query;

use super::coverage::Directions;
use super::pbr::{affine_in_base_color, Pbr, MIN_ROUGHNESS};

/// Coarse grid steps of roughness and metallic.
const ROUGHNESS_STEP: f64 = 0.025;
const METALLIC_STEP: f64 = 0.05;

/// A set of direction pairs with the reference's values there and the set's share of the loss.
struct Target<'a> {
    queries: &'a [Query],
    /// Weight of each pair, the set's share divided by $\sum w S^2$ (so each set's term is
    /// its squared relative error).
    weights: Vec<f64>,
    values: Vec<[f64; 3]>,
}

impl<'a> Target<'a> {
    fn new(reference: &dyn Reflectance, dirs: &'a Directions, share: f64) -> Target<'a> {
        let values: Vec<[f64; 3]> = dirs.queries.iter().map(|q| reference.shading(q)).collect();
        let energy: f64 = values.iter().zip(&dirs.weights).map(|(v, w)| w * v.iter().map(|x| x * x).sum::<f64>()).sum();
        // A black reference has no relative error to speak of: weigh it as if unit.
        let scale = share / if energy > 0.0 { energy } else { 1.0 };
        Target { queries: &dirs.queries, weights: dirs.weights.iter().map(|w| w * scale).collect(), values }
    }
}

/// The result of [`fit`]: the material and its relative RMS against the reference.
#[derive(Clone, Copy, Debug)]
pub struct Approximation {
    pub pbr: Pbr,
    /// Relative RMS ($\sqrt{\sum w |P - S|^2 / \sum w |S|^2}$) over the covered directions
    /// (all directions when none are known).
    pub covered: f64,
    /// The same over all directions.
    pub all: f64,
}

/// The metallic-roughness material closest to `reference` (module documentation), judged
/// on `covered` (all directions when `None`) and on `all`.
pub fn fit(reference: &dyn Reflectance, covered: Option<&Directions>, all: &Directions) -> Approximation {
    let targets = vec![Target::new(reference, covered.unwrap_or(all), 1.0)];
    let coarse_r: Vec<f64> = grid(MIN_ROUGHNESS, 1.0, ROUGHNESS_STEP);
    let coarse_m: Vec<f64> = grid(0.0, 1.0, METALLIC_STEP);
    let (mut best, _) = search(&targets, &coarse_r, &coarse_m);
    let fine_r = grid((best.roughness - ROUGHNESS_STEP).max(MIN_ROUGHNESS), (best.roughness + ROUGHNESS_STEP).min(1.0), ROUGHNESS_STEP / 10.0);
    let fine_m = grid((best.metallic - METALLIC_STEP).max(0.0), (best.metallic + METALLIC_STEP).min(1.0), METALLIC_STEP / 10.0);
    best = search(&targets, &fine_r, &fine_m).0;
    let covered_error = relative_rms(&best, reference, covered.unwrap_or(all));
    Approximation { pbr: best, covered: covered_error, all: relative_rms(&best, reference, all) }
}

/// Relative RMS of `pbr` against `reference` over weighted directions.
pub fn relative_rms(pbr: &dyn Reflectance, reference: &dyn Reflectance, dirs: &Directions) -> f64 {
    let (mut se, mut sv) = (0.0, 0.0);
    for (q, w) in dirs.queries.iter().zip(&dirs.weights) {
        let (p, s) = (pbr.shading(q), reference.shading(q));
        for c in 0..3 {
            se += w * (p[c] - s[c]).powi(2);
            sv += w * s[c] * s[c];
        }
    }
    (se / sv.max(f64::MIN_POSITIVE)).sqrt()
}

/// `lo`, `lo + step`, … up to `hi` (inclusive, within rounding).
fn grid(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step + 1e-9).floor() as usize;
    (0..=n).map(|i| lo + i as f64 * step).collect()
}

/// The best material over a grid of roughness and metallic, and its loss.
fn search(targets: &[Target], roughness: &[f64], metallic: &[f64]) -> (Pbr, f64) {
    let mut best = (Pbr { base_color: [0.5; 3], metallic: 0.0, roughness: 1.0 }, f64::INFINITY);
    for &r in roughness {
        for &m in metallic {
            let parts: Vec<Vec<(f64, f64)>> =
                targets.iter().map(|t| t.queries.iter().map(|q| affine_in_base_color(m, r, q)).collect()).collect();
            let base_color = [0, 1, 2].map(|c| solve_channel(targets, &parts, c));
            let loss: f64 = (0..3).map(|c| channel_loss(targets, &parts, c, base_color[c])).sum();
            if loss < best.1 {
                best = (Pbr { base_color, metallic: m, roughness: r }, loss);
            }
        }
    }
    best
}

/// Channel `c`'s base colour: $\sum w b (S - a) / \sum w b^2$, clamped to $[0, 1]$.
fn solve_channel(targets: &[Target], parts: &[Vec<(f64, f64)>], c: usize) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (t, ab) in targets.iter().zip(parts) {
        for ((&(a, b), v), w) in ab.iter().zip(&t.values).zip(&t.weights) {
            num += w * b * (v[c] - a);
            den += w * b * b;
        }
    }
    if den > 0.0 { (num / den).clamp(0.0, 1.0) } else { 0.0 }
}

/// $\sum w (a + b c - S)^2$ over every target, channel `c`.
fn channel_loss(targets: &[Target], parts: &[Vec<(f64, f64)>], c: usize, base: f64) -> f64 {
    let mut loss = 0.0;
    for (t, ab) in targets.iter().zip(parts) {
        for ((&(a, b), v), w) in ab.iter().zip(&t.values).zip(&t.weights) {
            loss += w * (a + b * base - v[c]).powi(2);
        }
    }
    loss
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_pbr_material_from_its_own_shading() {
        let truth = Pbr { base_color: [0.8, 0.25, 0.1], metallic: 0.0, roughness: 0.5 };
        let all = Directions::all();
        let a = fit(&truth, None, &all);
        for c in 0..3 {
            assert!((a.pbr.base_color[c] - truth.base_color[c]).abs() < 0.01, "{:?}", a.pbr);
        }
        assert!((a.pbr.roughness - 0.5).abs() < 0.01 && a.pbr.metallic < 0.02, "{:?}", a.pbr);
        assert!(a.all < 1e-3, "{}", a.all);
    }

    #[test]
    fn recovers_a_metal() {
        let truth = Pbr { base_color: [0.95, 0.64, 0.54], metallic: 1.0, roughness: 0.3 };
        let a = fit(&truth, None, &Directions::all());
        assert!((a.pbr.metallic - 1.0).abs() < 0.02 && (a.pbr.roughness - 0.3).abs() < 0.01, "{:?}", a.pbr);
        assert!((a.pbr.base_color[1] - 0.64).abs() < 0.02, "{:?}", a.pbr);
    }
}
