//! The glTF metallic-roughness material closest to a reflectance: weighted least squares on
//! the shading over direction pairs ([`super::coverage`]).
//!
//! At fixed metallic $m$ and roughness $r$ the shading is affine in the base colour,
//! $S = a + b\,c$ ([`Pbr::affine`]), so each channel's $c$ is one weighted linear
//! least-squares solve, clamped to $[0, 1]$. $(m, r)$ are searched on a grid, then on a
//! grid ten times finer about the best; a dielectric's $F_0$ above core glTF's
//! (`KHR_materials_specular`) on a geometric grid at $m = 0$, kept only when it lowers the
//! loss (the grid holds core glTF's 0.04, so the extension never makes a fit worse); and a
//! clear coat (`KHR_materials_clearcoat`, [`super::pbr::Coat`]) over a core base, its factor
//! and roughness searched with the base's and kept on the same rule. The coat stays affine in
//! the base colour, so every node still solves its base colour in closed form. A sheen
//! (`KHR_materials_sheen`, cloth) over a dielectric base the same way, its colour solved with
//! the base colour per channel (two unknowns, [`box_least_squares`]).
//!
//! The loss is the squared relative error on the covered directions alone when they are
//! known, else on all directions: elsewhere the factored material is extrapolation, and a
//! share of it in the loss pulled a painted GGX sphere's fit to roughness 0.8 and a base
//! colour 15% too bright (tests/export.rs). Physics extrapolates the PBR material instead.

use crate::brdf::Reflectance;
use crate::factor::Query;

use super::coverage::Directions;
use super::pbr::{Coat, Pbr, Sheen, DIELECTRIC_F0, MIN_ROUGHNESS, MIN_SHEEN_ROUGHNESS};

/// Coarse grid steps of roughness and metallic.
const ROUGHNESS_STEP: f64 = 0.025;
const METALLIC_STEP: f64 = 0.05;
/// Ratio between neighbouring $F_0$ of the coarse grid: a highlight's strength is judged
/// in ratios (0.04 to 1 in 9 steps); the fine grid divides it in five.
const F0_RATIO: f64 = 1.5;

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
    let core = refine(&targets, search(&targets, nodes(&coarse_r, &grid(0.0, 1.0, METALLIC_STEP), &[DIELECTRIC_F0], None)).0);
    let specular = refine(&targets, search(&targets, nodes(&coarse_r, &[0.0], &f0_grid(DIELECTRIC_F0, 1.0, F0_RATIO), None)).0);
    let coated = coat(&targets);
    let sheened = sheen(&targets);
    let best = [specular, coated, sheened].into_iter().fold(core, |best, p| if loss(&targets, &p) < loss(&targets, &best) { p } else { best });
    let covered_error = relative_rms(&best, reference, covered.unwrap_or(all));
    Approximation { pbr: best, covered: covered_error, all: relative_rms(&best, reference, all) }
}

/// Coat factors and roughnesses of the coarse search, and the steps of its refinement: a
/// coat is a sharp layer over a rougher base, so its roughness is searched up to 0.5.
const COAT_FACTORS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];
const COAT_ROUGHNESS_STEP: f64 = 0.05;
const COAT_FACTOR_STEP: f64 = 0.025;

/// Coarse coated materials refined: a sharp coat over a rough base and a sharp base under a
/// rough coat can draw the same highlight under one light, so several are followed.
const COAT_CANDIDATES: usize = 6;

/// The best material with a clear coat over a core base: coat and base on coarse grids
/// together (base steps twice [`ROUGHNESS_STEP`] and [`METALLIC_STEP`]); then, from each of
/// the [`COAT_CANDIDATES`] best, the base refined at its coat and the coat at that base,
/// in turn, four times.
fn coat(targets: &[Target]) -> Pbr {
    let base_r = grid(MIN_ROUGHNESS, 1.0, 2.0 * ROUGHNESS_STEP);
    let base_m = grid(0.0, 1.0, 2.0 * METALLIC_STEP);
    let mut all = Vec::new();
    for &factor in &COAT_FACTORS {
        for roughness in grid(MIN_ROUGHNESS, 0.5, COAT_ROUGHNESS_STEP) {
            all.extend(nodes(&base_r, &base_m, &[DIELECTRIC_F0], Some(Coat { factor, roughness })));
        }
    }
    let refined = ranked(targets, all).into_iter().take(COAT_CANDIDATES).map(|(start, _)| refine_coated(targets, start));
    refined.min_by(|a, b| a.1.total_cmp(&b.1)).map_or(Pbr::core([0.5; 3], 0.0, 1.0), |(p, _)| p)
}

/// A coated material refined from `start` ([`coat`]), and its loss.
fn refine_coated(targets: &[Target], start: Pbr) -> (Pbr, f64) {
    let mut best = start;
    for _ in 0..4 {
        let r = around(best.roughness, 2.0 * ROUGHNESS_STEP, MIN_ROUGHNESS, ROUGHNESS_STEP / 5.0);
        let m = around(best.metallic, 2.0 * METALLIC_STEP, 0.0, METALLIC_STEP / 5.0);
        best = search(targets, nodes(&r, &m, &[DIELECTRIC_F0], best.coat)).0;
        let c = best.coat.expect("a coated search keeps its coat");
        let factors = around(c.factor, 0.125, COAT_FACTOR_STEP, COAT_FACTOR_STEP);
        let roughnesses = around(c.roughness, COAT_ROUGHNESS_STEP, MIN_ROUGHNESS, COAT_ROUGHNESS_STEP / 5.0);
        let coats = factors.iter().flat_map(|&factor| roughnesses.iter().map(move |&roughness| Coat { factor, roughness }));
        best = search(targets, coats.map(|coat| Pbr { coat: Some(coat), ..best }).collect()).0;
    }
    (best, loss(targets, &best))
}

/// Sheen strengths (the colour's largest channel, which sets how much the rest is dimmed)
/// and roughnesses of the coarse sheen search.
const SHEEN_STRENGTHS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];
const SHEEN_ROUGHNESS_STEP: f64 = 0.1;
/// Coarse sheened materials refined (as [`COAT_CANDIDATES`]).
const SHEEN_CANDIDATES: usize = 3;

/// A dielectric base under a sheen, before its colours are solved.
#[derive(Clone, Copy)]
struct SheenNode {
    roughness: f64,
    sheen_roughness: f64,
    strength: f64,
}

/// The best material with a sheen over a dielectric base (cloth): base roughness, sheen
/// roughness and strength on coarse grids, then from each of the [`SHEEN_CANDIDATES`] best,
/// the base refined at its sheen and the sheen at that base, in turn, three times. The base
/// colour and the sheen colour are solved together per channel at each node.
fn sheen(targets: &[Target]) -> Pbr {
    let mut coarse = Vec::new();
    for roughness in grid(MIN_ROUGHNESS, 1.0, 2.0 * ROUGHNESS_STEP) {
        for sheen_roughness in grid(SHEEN_ROUGHNESS_STEP, 1.0, SHEEN_ROUGHNESS_STEP) {
            for &strength in &SHEEN_STRENGTHS {
                coarse.push(SheenNode { roughness, sheen_roughness, strength });
            }
        }
    }
    let mut ranked = sheen_scored(targets, coarse);
    ranked.sort_by(|a, b| a.2.total_cmp(&b.2));
    let refined = ranked.into_iter().take(SHEEN_CANDIDATES).map(|(node, _, _)| {
        let mut best = node;
        for _ in 0..3 {
            let r = around(best.roughness, 2.0 * ROUGHNESS_STEP, MIN_ROUGHNESS, ROUGHNESS_STEP / 5.0);
            best = sheen_best(targets, r.iter().map(|&roughness| SheenNode { roughness, ..best }).collect()).0;
            let rs = around(best.sheen_roughness, SHEEN_ROUGHNESS_STEP, MIN_SHEEN_ROUGHNESS, SHEEN_ROUGHNESS_STEP / 10.0);
            let k = around(best.strength, 0.125, 0.025, 0.025);
            let nodes = rs.iter().flat_map(|&sheen_roughness| k.iter().map(move |&strength| SheenNode { sheen_roughness, strength, ..best })).collect();
            best = sheen_best(targets, nodes).0;
        }
        sheen_best(targets, vec![best]).1
    });
    refined.min_by(|a, b| loss(targets, a).total_cmp(&loss(targets, b))).unwrap_or(Pbr::core([0.5; 3], 0.0, 1.0))
}

/// The node of least loss among `nodes`, and its material.
fn sheen_best(targets: &[Target], nodes: Vec<SheenNode>) -> (SheenNode, Pbr) {
    // Ties go to the first node (`min_by` keeps the first of equal ones).
    let best = sheen_scored(targets, nodes).into_iter().min_by(|a, b| a.2.total_cmp(&b.2));
    best.map(|(n, p, _)| (n, p)).expect("a sheen search has nodes")
}

/// Each node with its material and loss: per channel, base colour $c$ and sheen colour
/// $\sigma$ minimize $\sum w (a + b c + \sigma g - S)^2$ (with $g$ the sheen's
/// [`Sheen::shape`]), $c$ in $[0, 1]$ and $\sigma$ in $[0, $ strength$]$.
fn sheen_scored(targets: &[Target], nodes: Vec<SheenNode>) -> Vec<(SheenNode, Pbr, f64)> {
    use rayon::prelude::*;
    nodes
        .into_par_iter()
        .map(|node| {
            let probe = Pbr { sheen: Some(Sheen { color: [node.strength; 3], roughness: node.sheen_roughness }), ..Pbr::core([0.0; 3], 0.0, node.roughness) };
            // Per channel: Σw b², Σw b g, Σw g², Σw b r, Σw g r, Σw r², r = S − a.
            let mut m = [[0.0f64; 6]; 3];
            for t in targets {
                for ((q, v), &w) in t.queries.iter().zip(&t.values).zip(&t.weights) {
                    let (a, b) = probe.affine(q);
                    let g = Sheen::shape(node.sheen_roughness, q);
                    for c in 0..3 {
                        let r = v[c] - a;
                        let s = &mut m[c];
                        s[0] += w * b * b;
                        s[1] += w * b * g;
                        s[2] += w * g * g;
                        s[3] += w * b * r;
                        s[4] += w * g * r;
                        s[5] += w * r * r;
                    }
                }
            }
            let mut base_color = [0.0; 3];
            let mut color = [0.0; 3];
            let mut loss = 0.0;
            for c in 0..3 {
                let (x, y, l) = box_least_squares(&m[c], node.strength);
                base_color[c] = x;
                color[c] = y;
                loss += l;
            }
            let pbr = Pbr { base_color, sheen: Some(Sheen { color, roughness: node.sheen_roughness }), ..probe };
            (node, pbr, loss)
        })
        .collect()
}

/// Least squares in two unknowns from their moments `[Σb², Σbg, Σg², Σbr, Σgr, Σr²]`, $x$ in
/// $[0, 1]$ and $y$ in $[0, y_{max}]$: the unconstrained solution clamped, then each
/// unknown solved again at the other's clamped value. Returns $(x, y)$ and the loss.
fn box_least_squares(m: &[f64; 6], y_max: f64) -> (f64, f64, f64) {
    let [bb, bg, gg, br, gr, rr] = *m;
    let det = bb * gg - bg * bg;
    let (mut x, mut y) = if det > 1e-12 * (bb * gg).max(f64::MIN_POSITIVE) { ((br * gg - gr * bg) / det, (gr * bb - br * bg) / det) } else { (0.0, 0.0) };
    x = x.clamp(0.0, 1.0);
    y = y.clamp(0.0, y_max);
    if gg > 0.0 {
        y = ((gr - x * bg) / gg).clamp(0.0, y_max);
    }
    if bb > 0.0 {
        x = ((br - y * bg) / bb).clamp(0.0, 1.0);
    }
    let loss = rr - 2.0 * x * br - 2.0 * y * gr + x * x * bb + 2.0 * x * y * bg + y * y * gg;
    (x, y, loss)
}

/// Every combination of roughness, metallic and $F_0$, with `coat` (base colour unset).
fn nodes(roughness: &[f64], metallic: &[f64], f0: &[f64], coat: Option<Coat>) -> Vec<Pbr> {
    let mut out = Vec::with_capacity(roughness.len() * metallic.len() * f0.len());
    for &r in roughness {
        for &m in metallic {
            for &f in f0 {
                out.push(Pbr { base_color: [0.0; 3], metallic: m, roughness: r, specular_f0: f, coat, sheen: None });
            }
        }
    }
    out
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

/// The best material on a grid ten times finer about `coarse` (in $F_0$, five times finer
/// in ratio), metallic held at 0 for a dielectric with its own $F_0$.
fn refine(targets: &[Target], coarse: Pbr) -> Pbr {
    let r = around(coarse.roughness, ROUGHNESS_STEP, MIN_ROUGHNESS, ROUGHNESS_STEP / 10.0);
    if coarse.specular_f0 > DIELECTRIC_F0 {
        let f0 = f0_grid((coarse.specular_f0 / F0_RATIO).max(DIELECTRIC_F0), (coarse.specular_f0 * F0_RATIO).min(1.0), F0_RATIO.powf(0.2));
        return search(targets, nodes(&r, &[coarse.metallic], &f0, coarse.coat)).0;
    }
    let m = around(coarse.metallic, METALLIC_STEP, 0.0, METALLIC_STEP / 10.0);
    search(targets, nodes(&r, &m, &[coarse.specular_f0], coarse.coat)).0
}

/// Each target's $(a, b)$ at `p` ([`Pbr::affine`]).
fn parts(targets: &[Target], p: &Pbr) -> Vec<Vec<(f64, f64)>> {
    targets.iter().map(|t| t.queries.iter().map(|q| p.affine(q)).collect()).collect()
}

/// The loss of a material over the targets.
fn loss(targets: &[Target], p: &Pbr) -> f64 {
    let mut sum = 0.0;
    for t in targets {
        for ((q, v), w) in t.queries.iter().zip(&t.values).zip(&t.weights) {
            let s = p.shading(q);
            sum += w * (0..3).map(|c| (s[c] - v[c]).powi(2)).sum::<f64>();
        }
    }
    sum
}

/// `lo`, `lo × ratio`, … up to `hi` (inclusive, within rounding).
pub(super) fn f0_grid(lo: f64, hi: f64, ratio: f64) -> Vec<f64> {
    let n = ((hi / lo).ln() / ratio.ln() + 1e-9).floor() as usize;
    let mut out: Vec<f64> = (0..=n).map(|i| lo * ratio.powi(i as i32)).collect();
    if out.last().is_some_and(|&x| x < hi * (1.0 - 1e-9)) {
        out.push(hi);
    }
    out
}

/// [`grid`] from `centre − half` to `centre + half`, kept within `[lo, 1]`.
fn around(centre: f64, half: f64, lo: f64, step: f64) -> Vec<f64> {
    grid((centre - half).max(lo), (centre + half).min(1.0), step)
}

/// `lo`, `lo + step`, … up to `hi` (inclusive, within rounding).
pub(super) fn grid(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step + 1e-9).floor() as usize;
    (0..=n).map(|i| lo + i as f64 * step).collect()
}

/// The best of `nodes` with its best base colour, and its loss.
fn search(targets: &[Target], nodes: Vec<Pbr>) -> (Pbr, f64) {
    // Ties go to the first node, as a sequential search would.
    scored(targets, nodes).into_iter().fold((Pbr::core([0.5; 3], 0.0, 1.0), f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a })
}

/// `nodes` with their best base colours, least loss first.
fn ranked(targets: &[Target], nodes: Vec<Pbr>) -> Vec<(Pbr, f64)> {
    let mut out = scored(targets, nodes);
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    out
}

/// Each node with its best base colour and its loss, in the nodes' order.
fn scored(targets: &[Target], nodes: Vec<Pbr>) -> Vec<(Pbr, f64)> {
    use rayon::prelude::*;
    nodes
        .into_par_iter()
        .map(|node| {
            let parts = parts(targets, &node);
            let base_color = [0, 1, 2].map(|c| solve_channel(targets, &parts, c));
            let loss: f64 = (0..3).map(|c| channel_loss(targets, &parts, c, base_color[c])).sum();
            (Pbr { base_color, ..node }, loss)
        })
        .collect()
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
        let truth = Pbr::core([0.8, 0.25, 0.1], 0.0, 0.5);
        let all = Directions::all();
        let a = fit(&truth, None, &all);
        for c in 0..3 {
            assert!((a.pbr.base_color[c] - truth.base_color[c]).abs() < 0.01, "{:?}", a.pbr);
        }
        assert!((a.pbr.roughness - 0.5).abs() < 0.01 && a.pbr.metallic < 0.02, "{:?}", a.pbr);
        assert!(a.all < 1e-3, "{}", a.all);
        assert_eq!(a.pbr.specular_color(), None, "{:?}", a.pbr);
        assert!(a.pbr.coat.is_none() && a.pbr.sheen.is_none(), "{:?}", a.pbr);
    }

    #[test]
    fn recovers_a_dielectric_brighter_than_core_gltf_allows() {
        // A varnish-like F0 of 0.2 (index of refraction about 2.6): KHR_materials_specular.
        let truth = Pbr { base_color: [0.1, 0.3, 0.6], metallic: 0.0, roughness: 0.3, specular_f0: 0.2, coat: None, sheen: None };
        let a = fit(&truth, None, &Directions::all());
        assert!(a.pbr.metallic < 0.02 && (a.pbr.roughness - 0.3).abs() < 0.02, "{:?}", a.pbr);
        assert!((a.pbr.specular_f0 / 0.2 - 1.0).abs() < 0.1, "{:?}", a.pbr);
        assert!((a.pbr.specular_color().unwrap() - 5.0).abs() < 0.5, "{:?}", a.pbr);
        assert!(a.all < 0.02, "{}", a.all);
    }

    #[test]
    fn recovers_a_clear_coat_over_a_rough_base() {
        let truth = Pbr { coat: Some(Coat { factor: 0.8, roughness: 0.1 }), ..Pbr::core([0.6, 0.1, 0.05], 0.0, 0.7) };
        let a = fit(&truth, None, &Directions::all());
        let c = a.pbr.coat.expect("a coat");
        assert!((c.factor - 0.8).abs() < 0.1 && (c.roughness - 0.1).abs() < 0.03, "{:?}", a.pbr);
        assert!((a.pbr.roughness - 0.7).abs() < 0.05 && a.pbr.metallic < 0.05, "{:?}", a.pbr);
        assert!(a.all < 0.02, "{}", a.all);
        // Without a coat in the truth, none is written.
        assert_eq!(fit(&Pbr::core([0.6, 0.1, 0.05], 0.0, 0.7), None, &Directions::all()).pbr.coat, None);
    }

    #[test]
    fn recovers_a_sheen_over_a_rough_base() {
        let truth = Pbr { sheen: Some(Sheen { color: [0.6, 0.35, 0.5], roughness: 0.6 }), ..Pbr::core([0.3, 0.05, 0.12], 0.0, 0.9) };
        let a = fit(&truth, None, &Directions::all());
        let s = a.pbr.sheen.expect("a sheen");
        assert!((s.roughness - 0.6).abs() < 0.05, "{:?}", a.pbr);
        for c in 0..3 {
            assert!((s.color[c] - truth.sheen.unwrap().color[c]).abs() < 0.05, "{:?}", a.pbr);
            assert!((a.pbr.base_color[c] - truth.base_color[c]).abs() < 0.03, "{:?}", a.pbr);
        }
        assert!(a.all < 0.02, "{}", a.all);
    }

    /// The analytic velvet (tests' `Analytic::Velvet`: Lambert plus this sheen lobe, without
    /// the dimming) is drawn much closer with a sheen than any material without one.
    #[test]
    fn velvet_takes_a_sheen() {
        let velvet = crate::brdf::Analytic::Velvet { diffuse: [0.30, 0.05, 0.12], sheen: [0.60, 0.35, 0.50], roughness: 0.35 };
        let all = Directions::all();
        let a = fit(&velvet, None, &all);
        let s = a.pbr.sheen.expect("a sheen");
        // The velvet's Charlie parameter is α: sheen roughness √0.35 = 0.59.
        assert!((s.roughness - 0.35f64.sqrt()).abs() < 0.1, "{:?}", a.pbr);
        let targets = vec![Target::new(&velvet, &all, 1.0)];
        let without = [
            refine(&targets, search(&targets, nodes(&grid(MIN_ROUGHNESS, 1.0, ROUGHNESS_STEP), &grid(0.0, 1.0, METALLIC_STEP), &[DIELECTRIC_F0], None)).0),
            coat(&targets),
        ];
        for p in without {
            let e = relative_rms(&p, &velvet, &all);
            eprintln!("velvet: with a sheen {:.4} ({:?}), without {e:.4}", a.all, a.pbr);
            assert!(a.all < 0.5 * e, "with a sheen {}, without {e}: {p:?}", a.all);
        }
    }

    #[test]
    fn recovers_a_metal() {
        let truth = Pbr::core([0.95, 0.64, 0.54], 1.0, 0.3);
        let a = fit(&truth, None, &Directions::all());
        assert!((a.pbr.metallic - 1.0).abs() < 0.02 && (a.pbr.roughness - 0.3).abs() < 0.01, "{:?}", a.pbr);
        assert!((a.pbr.base_color[1] - 0.64).abs() < 0.02, "{:?}", a.pbr);
    }
}
