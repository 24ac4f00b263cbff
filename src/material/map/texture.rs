//! Coefficient textures from per-sample values, with the gaps filled (thesis 4.2.2, Figure
//! 4.1).
//!
//! Texels no sample falls on are filled by rasterizing the painted pixel grid, triangulated
//! in uv space: two triangles per 2×2 block of valid pixels, one for a block with three. A
//! triangle whose uv edges are much longer than the grid's typical edge joins points that
//! are not neighbours on the surface (a uv seam, or a silhouette where one part of the model
//! passes in front of another) and is skipped. Texels no triangle covers take the nearest
//! filled texel's value, so a render never meets a hole.

use std::collections::VecDeque;

use super::Grid;
use crate::factor::Pattern;

/// A triangle of samples, by sample index.
pub(super) type Triangle = [u32; 3];

/// How the values of several samples (or overlapping triangles of several views) that meet
/// on one texel combine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Combine<'w> {
    /// The smallest: keeps a term below every sample (eq. 4.3, thesis 4.4).
    Min,
    /// The mean, weighted per sample (positive weights).
    Mean(&'w [f64]),
}

/// Sample positions on a coefficient texture of `res`² nodes.
pub(super) struct Layout<'a> {
    pub res: usize,
    /// Nearest node of every sample.
    pub node: Vec<usize>,
    pub triangles: Vec<Triangle>,
    pattern: &'a Pattern,
}

impl<'a> Layout<'a> {
    pub fn new(res: usize, pattern: &'a Pattern, grids: &[Grid]) -> Layout<'a> {
        let node = pattern.queries.iter().map(|q| crate::factor::param::uv_nearest_node(q.uv, res)).collect();
        Layout { res, node, triangles: triangulate(grids, pattern), pattern }
    }

    /// Texture coordinates of sample `i`.
    pub fn uv(&self, i: usize) -> glam::DVec2 {
        self.pattern.queries[i].uv
    }

    /// The texture of per-sample `values`: combined on the nodes samples fall on, gaps
    /// rasterized from the triangulated grids, the rest from the nearest filled node.
    pub fn texture(&self, values: &[[f64; 3]], combine: Combine) -> Vec<[f32; 3]> {
        let res = self.res;
        let mut sum = vec![[0.0f64; 3]; res * res];
        // Total weight on each node; zero where nothing fell yet.
        let mut weight = vec![0.0f64; res * res];
        let add = |sum: &mut [[f64; 3]], weight: &mut [f64], k: usize, v: [f64; 3], w: f64| match combine {
            Combine::Min => {
                sum[k] = if weight[k] == 0.0 { v } else { [0, 1, 2].map(|c| sum[k][c].min(v[c])) };
                weight[k] = 1.0;
            }
            Combine::Mean(_) => {
                (0..3).for_each(|c| sum[k][c] += w * v[c]);
                weight[k] += w;
            }
        };
        let w_of = |s: usize| if let Combine::Mean(w) = combine { w[s] } else { 1.0 };
        for (s, (&k, v)) in self.node.iter().zip(values).enumerate() {
            add(&mut sum, &mut weight, k, *v, w_of(s));
        }
        let direct: Vec<bool> = weight.iter().map(|&w| w > 0.0).collect();
        // Rasterize: each node inside a triangle gets the barycentric blend of its corners.
        let scale = (res - 1) as f64;
        for t in &self.triangles {
            let p = t.map(|s| {
                let u = crate::factor::param::uv_forward(self.pattern.queries[s as usize].uv);
                (u.x * scale, u.y * scale)
            });
            let m = t.map(|s| values[s as usize]);
            let wt = t.map(|s| w_of(s as usize));
            let (x0, x1) = (p.iter().map(|q| q.0).fold(f64::MAX, f64::min), p.iter().map(|q| q.0).fold(f64::MIN, f64::max));
            let (y0, y1) = (p.iter().map(|q| q.1).fold(f64::MAX, f64::min), p.iter().map(|q| q.1).fold(f64::MIN, f64::max));
            let area = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[2].0 - p[0].0) * (p[1].1 - p[0].1);
            if area.abs() < 1e-12 {
                continue;
            }
            for y in (y0.ceil().max(0.0) as usize)..=(y1.floor().min(scale) as usize) {
                for x in (x0.ceil().max(0.0) as usize)..=(x1.floor().min(scale) as usize) {
                    let (px, py) = (x as f64, y as f64);
                    let w1 = ((px - p[0].0) * (p[2].1 - p[0].1) - (p[2].0 - p[0].0) * (py - p[0].1)) / area;
                    let w2 = ((p[1].0 - p[0].0) * (py - p[0].1) - (px - p[0].0) * (p[1].1 - p[0].1)) / area;
                    let w0 = 1.0 - w1 - w2;
                    if w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9 {
                        continue;
                    }
                    let k = y * res + x;
                    // Where triangles of several views overlap, they combine like samples.
                    if !direct[k] {
                        let b = [w0 * wt[0], w1 * wt[1], w2 * wt[2]];
                        let w = b[0] + b[1] + b[2];
                        if w > 0.0 {
                            add(&mut sum, &mut weight, k, [0, 1, 2].map(|c| (b[0] * m[0][c] + b[1] * m[1][c] + b[2] * m[2][c]) / w), w);
                        }
                    }
                }
            }
        }
        let mut tex: Vec<[f64; 3]> = sum
            .iter()
            .zip(&weight)
            .map(|(s, &w)| match combine {
                _ if w == 0.0 => [f64::INFINITY; 3],
                Combine::Min => *s,
                Combine::Mean(_) => s.map(|x| x / w),
            })
            .collect();
        fill_nearest(&mut tex, res);
        tex.into_iter().map(|x| x.map(|v| v as f32)).collect()
    }
}

/// Triangles of the painted pixel grids whose uv edges are all short: neighbours on the
/// surface, not across a seam or a silhouette.
fn triangulate(grids: &[Grid], pattern: &Pattern) -> Vec<Triangle> {
    let n = pattern.len();
    let uv = |s: u32| pattern.queries[s as usize].uv;
    let mut candidates = Vec::new();
    for g in grids {
        if g.sample.len() != g.width * g.height {
            continue;
        }
        let at = |i: usize, j: usize| g.sample[j * g.width + i].filter(|&s| (s as usize) < n);
        for j in 0..g.height.saturating_sub(1) {
            for i in 0..g.width.saturating_sub(1) {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                match (a, b, c, d) {
                    (Some(a), Some(b), Some(c), Some(d)) => {
                        candidates.push([a, b, d]);
                        candidates.push([a, d, c]);
                    }
                    (Some(a), Some(b), Some(c), None) => candidates.push([a, b, c]),
                    (Some(a), Some(b), None, Some(d)) => candidates.push([a, b, d]),
                    (Some(a), None, Some(c), Some(d)) => candidates.push([a, d, c]),
                    (None, Some(b), Some(c), Some(d)) => candidates.push([b, d, c]),
                    _ => {}
                }
            }
        }
    }
    let longest = |t: &Triangle| {
        let (p, q, r) = (uv(t[0]), uv(t[1]), uv(t[2]));
        p.distance(q).max(q.distance(r)).max(r.distance(p))
    };
    let mut lengths: Vec<f64> = candidates.iter().map(longest).collect();
    if lengths.is_empty() {
        return candidates;
    }
    let mid = lengths.len() / 2;
    let typical = *lengths.select_nth_unstable_by(mid, f64::total_cmp).1;
    // A pixel step covers a few texels at most on a continuous surface; eight typical
    // edges is far beyond that and far below any seam (which jumps across the texture).
    let limit = 8.0 * typical.max(1e-9);
    candidates.retain(|t| longest(t) <= limit);
    candidates
}

/// Give every unset (infinite) node the value of the nearest set one, by a breadth-first
/// sweep from all set nodes at once.
fn fill_nearest(tex: &mut [[f64; 3]], res: usize) {
    let mut queue: VecDeque<usize> = (0..tex.len()).filter(|&k| tex[k][0].is_finite()).collect();
    if queue.is_empty() {
        tex.iter_mut().for_each(|x| *x = [0.0; 3]);
        return;
    }
    while let Some(k) = queue.pop_front() {
        let (x, y) = (k % res, k / res);
        let neighbours = [(x > 0).then(|| k - 1), (x + 1 < res).then(|| k + 1), (y > 0).then(|| k - res), (y + 1 < res).then(|| k + res)];
        for nb in neighbours.into_iter().flatten() {
            if !tex[nb][0].is_finite() {
                tex[nb] = tex[k];
                queue.push_back(nb);
            }
        }
    }
}
