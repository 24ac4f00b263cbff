//! The sphere's outline from the picture's edges: a robust circle fit for a sphere in
//! context (on a table, with its cast shadow, on paper, a gradient or painted strokes,
//! cut by the frame, hidden at the bottom), where no segmentation separates the sphere.
//!
//! ```text
//! picture ──points──► edge points (sub-pixel, with the gradient's direction)
//! edge points ──hough──► candidate centres (each point votes along its gradient line)
//! candidate ──refine──► a geometric least-squares circle on the points near it whose
//!                       gradient is radial; its support: the share of the outline they cover
//! ```
//!
//! Only the arc where the outline is clear supports the circle: where the sphere's dark side
//! meets its shadow and the table there is no edge, so nothing pulls the circle there.

use glam::{DMat3, DVec2, DVec3};

use super::Disk;

/// An edge point: its position (pixel coordinates, centres at +0.5) and the unit direction
/// of the picture's gradient there.
#[derive(Clone, Copy, Debug)]
pub struct Edge {
    pub p: DVec2,
    pub g: DVec2,
}

/// A circle and how much of its outline the picture's edges show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Support {
    pub disk: Disk,
    /// Share of the whole outline (360°) with an edge point on it.
    pub seen: f64,
    /// Share of the outline inside the picture with an edge point on it.
    pub seen_in_frame: f64,
    /// The distance from the outline within which an edge point counted, pixels
    /// ([`outline_tolerance`]).
    pub tolerance: f64,
}

/// Blur of the coarse edges that propose circles ([`coarse_points`]), pixels: paper grain,
/// bristle marks and the ragged ends of strokes across a painted outline (1–3 pixels) turn
/// each fine edge point's gradient by several degrees, which moves its vote by r·sin of
/// that; at 4 pixels they average out, while a sphere of the smallest radius looked for
/// (a tenth of the shorter side, 25 pixels or more) keeps its outline as an edge.
const COARSE_SIGMA: f64 = 4.0;

/// Gaussian blur before the gradient, pixels: JPEG's 8×8 blocks and paper grain are noise
/// at the scale of one or two pixels; the outline is an edge at every scale.
const SIGMA: f64 = 1.2;

/// An edge point's gradient is "radial" within this angle of the circle's normal: a
/// sphere's outline is a step across the circle; the shadow's edge, the table's horizon
/// and strokes meet it at other angles.
const RADIAL_COS: f64 = 0.94; // cos 20°

/// Edge points (Canny's non-maximum suppression with a sub-pixel peak) of `channels`, each
/// `w` × `h` values. A gradient is an edge when it stands out of the picture's noise: more
/// than [`NOISE_FACTOR`] times the median gradient (the median pixel is flat: grain, JPEG).
pub fn points(channels: &[Vec<f32>], w: usize, h: usize) -> Vec<Edge> {
    points_at(channels, w, h, SIGMA)
}

/// [`points`] at a coarser scale ([`COARSE_SIGMA`]), where a painted outline's edge keeps its
/// direction: they vote for circles beside the fine ones ([`circles`]).
pub fn coarse_points(channels: &[Vec<f32>], w: usize, h: usize) -> Vec<Edge> {
    points_at(channels, w, h, COARSE_SIGMA)
}

fn points_at(channels: &[Vec<f32>], w: usize, h: usize, sigma: f64) -> Vec<Edge> {
    let blurred: Vec<Vec<f32>> = channels.iter().map(|c| blur(c, w, h, sigma)).collect();
    let (mag, dir) = gradient(&blurred, w, h);
    let mut sorted: Vec<f32> = mag.iter().copied().filter(|&m| m > 0.0).collect();
    if sorted.len() < 16 {
        return Vec::new();
    }
    sorted.sort_by(f32::total_cmp);
    let median = sorted[sorted.len() / 2];
    let top = sorted[sorted.len() * 999 / 1000];
    let threshold = (NOISE_FACTOR * median).max(CONTRAST_SHARE * top);
    let at = |x: f64, y: f64| bilinear(&mag, w, h, x, y);
    let mut out = Vec::new();
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            let m0 = mag[k];
            if m0 < threshold {
                continue;
            }
            let g = dir[k];
            let (x, y) = (i as f64, j as f64);
            let (m_minus, m_plus) = (at(x - g.x, y - g.y), at(x + g.x, y + g.y));
            if !(m0 as f64 >= m_minus && m0 as f64 > m_plus) {
                continue;
            }
            // The peak of the parabola through the three magnitudes along the gradient.
            let curvature = m_minus - 2.0 * m0 as f64 + m_plus;
            let t = if curvature < 0.0 { (0.5 * (m_minus - m_plus) / curvature).clamp(-0.5, 0.5) } else { 0.0 };
            out.push(Edge { p: DVec2::new(x + 0.5, y + 0.5) + g * t, g });
        }
    }
    out
}

/// Edge threshold over the median gradient: a flat area's gradient is noise whose
/// magnitude is Rayleigh-like, 99.9% of it below about 3× its median.
const NOISE_FACTOR: f32 = 4.0;
/// ...and over this share of the strongest edges (the 99.9th percentile), so that on a
/// picture without noise the outline is not buried under quantisation steps.
const CONTRAST_SHARE: f32 = 0.08;

/// Separable Gaussian blur with standard deviation `sigma` pixels (edges clamped).
pub(crate) fn blur(c: &[f32], w: usize, h: usize, sigma: f64) -> Vec<f32> {
    let radius = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f32> = (-radius..=radius).map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp() as f32).collect();
    let sum: f32 = kernel.iter().sum();
    let kernel: Vec<f32> = kernel.iter().map(|k| k / sum).collect();
    let pass = |src: &[f32], along_x: bool| -> Vec<f32> {
        let mut dst = vec![0.0; w * h];
        for j in 0..h {
            for i in 0..w {
                let mut acc = 0.0;
                for (t, k) in kernel.iter().enumerate() {
                    let d = t as isize - radius;
                    let (ii, jj) = if along_x { ((i as isize + d).clamp(0, w as isize - 1) as usize, j) } else { (i, (j as isize + d).clamp(0, h as isize - 1) as usize) };
                    acc += k * src[jj * w + ii];
                }
                dst[j * w + i] = acc;
            }
        }
        dst
    };
    pass(&pass(c, true), false)
}

/// Sobel gradient of the channel that changes most at each pixel: its magnitude and unit
/// direction (a colour edge between equally bright tones still counts).
fn gradient(channels: &[Vec<f32>], w: usize, h: usize) -> (Vec<f32>, Vec<DVec2>) {
    let (mut mag, mut dir) = (vec![0.0f32; w * h], vec![DVec2::ZERO; w * h]);
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            for c in channels {
                let v = |di: isize, dj: isize| c[(j as isize + dj) as usize * w + (i as isize + di) as usize];
                let gx = (v(1, -1) + 2.0 * v(1, 0) + v(1, 1) - v(-1, -1) - 2.0 * v(-1, 0) - v(-1, 1)) / 8.0;
                let gy = (v(-1, 1) + 2.0 * v(0, 1) + v(1, 1) - v(-1, -1) - 2.0 * v(0, -1) - v(1, -1)) / 8.0;
                let m = (gx * gx + gy * gy).sqrt();
                if m > mag[k] {
                    mag[k] = m;
                    dir[k] = DVec2::new(gx as f64, gy as f64) / m as f64;
                }
            }
        }
    }
    (mag, dir)
}

fn bilinear(v: &[f32], w: usize, h: usize, x: f64, y: f64) -> f64 {
    let (x, y) = (x.clamp(0.0, (w - 1) as f64), y.clamp(0.0, (h - 1) as f64));
    let (i, j) = ((x.floor() as usize).min(w - 2), (y.floor() as usize).min(h - 2));
    let (fx, fy) = (x - i as f64, y - j as f64);
    let at = |i: usize, j: usize| v[j * w + i] as f64;
    (at(i, j) * (1.0 - fx) + at(i + 1, j) * fx) * (1.0 - fy) + (at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx) * fy
}

/// Circles the edges support, best first: Hough candidates ([`hough`]) of the fine `edges`
/// and of the `coarse` ones ([`coarse_points`]), each refined on the fine edges
/// ([`refine`]), with radii from `r_min` to `r_max` pixels.
pub fn circles(edges: &[Edge], coarse: &[Edge], w: usize, h: usize, r_min: f64, r_max: f64) -> Vec<Support> {
    // Ranked by the arc a crisp outline shows: a wider, painted tolerance lets a larger
    // circle through the outline and the shadow's edge gather about as much.
    let crisp_arc = |s: &Support| seen_within(edges, &s.disk, tolerance(s.disk.r), w, h).0 * s.disk.r;
    let mut ranked: Vec<(f64, Support)> = [edges, coarse]
        .iter()
        .flat_map(|v| hough(v, w, h, r_min, r_max))
        .filter_map(|(c, r)| refine(edges, Disk { cx: c.x, cy: c.y, r }, w, h))
        .filter(|s| s.disk.r >= r_min && s.disk.r <= r_max)
        .map(|s| (crisp_arc(&s), s))
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    // The same circle found from two candidates counts once.
    let mut distinct: Vec<Support> = Vec::new();
    for (_, s) in ranked {
        if !distinct.iter().any(|d| same(&d.disk, &s.disk)) {
            distinct.push(s);
        }
    }
    distinct
}

fn same(a: &Disk, b: &Disk) -> bool {
    let scale = 0.05 * a.r.max(b.r);
    DVec2::new(a.cx - b.cx, a.cy - b.cy).length() < scale && (a.r - b.r).abs() < scale
}

/// Number of Hough candidates refined: the outline, the highlight, the shadow's and the
/// table's curves and a few from strokes.
const CANDIDATES: usize = 12;

/// The centres (with a radius) where most edge points' gradient lines meet: each point
/// votes at distance r from itself along $\pm g$ for every r in [r_min, r_max] (the sphere
/// may be lighter or darker than what is around it, and that changes along the outline).
fn hough(edges: &[Edge], w: usize, h: usize, r_min: f64, r_max: f64) -> Vec<(DVec2, f64)> {
    // Bins of a few pixels: the refinement, not the vote, gives the precision.
    let bin = (w.max(h) as f64 / 160.0).max(2.0);
    let (x0, y0) = (-0.5 * w as f64, -0.5 * h as f64);
    let (nx, ny) = ((2.0 * w as f64 / bin) as usize + 1, (2.0 * h as f64 / bin) as usize + 1);
    let mut acc = vec![0.0f32; nx * ny];
    let step = bin * 0.5;
    for e in edges {
        let mut r = r_min;
        while r <= r_max {
            for s in [-1.0, 1.0] {
                let c = e.p + e.g * (s * r);
                let (bx, by) = ((c.x - x0) / bin, (c.y - y0) / bin);
                if bx >= 0.0 && by >= 0.0 && (bx as usize) < nx && (by as usize) < ny {
                    // Weighted by 1/r: a circle of radius r has about 2πr points.
                    acc[by as usize * nx + bx as usize] += (1.0 / r) as f32;
                }
            }
            r += step;
        }
    }
    let smooth = box3(&acc, nx, ny);
    let mut peaks: Vec<(usize, f32)> = (0..nx * ny).filter(|&k| is_peak(&smooth, nx, ny, k)).map(|k| (k, smooth[k])).collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    peaks
        .into_iter()
        .take(CANDIDATES)
        .filter_map(|(k, _)| {
            let c = DVec2::new(x0 + ((k % nx) as f64 + 0.5) * bin, y0 + ((k / nx) as f64 + 0.5) * bin);
            radius_at(edges, c, r_min, r_max, bin).map(|r| (c, r))
        })
        .collect()
}

fn box3(a: &[f32], nx: usize, ny: usize) -> Vec<f32> {
    let mut out = vec![0.0; nx * ny];
    for j in 0..ny {
        for i in 0..nx {
            let mut s = 0.0;
            for dj in j.saturating_sub(1)..(j + 2).min(ny) {
                for di in i.saturating_sub(1)..(i + 2).min(nx) {
                    s += a[dj * nx + di];
                }
            }
            out[j * nx + i] = s;
        }
    }
    out
}

/// A strict local maximum over the 5×5 bins around `k` (ties to the first).
fn is_peak(a: &[f32], nx: usize, ny: usize, k: usize) -> bool {
    let (i, j, v) = (k % nx, k / nx, a[k]);
    if v <= 0.0 {
        return false;
    }
    for dj in j.saturating_sub(2)..(j + 3).min(ny) {
        for di in i.saturating_sub(2)..(i + 3).min(nx) {
            let o = dj * nx + di;
            if o != k && (a[o] > v || (a[o] == v && o < k)) {
                return false;
            }
        }
    }
    true
}

/// The radius about `c` at which most edge points with a radial gradient lie (a window of
/// `width` pixels, the Hough bin), weighted by 1/r as the vote.
fn radius_at(edges: &[Edge], c: DVec2, r_min: f64, r_max: f64, width: f64) -> Option<f64> {
    let n = (r_max.ceil() as usize) + 2;
    let mut hist = vec![0.0f64; n];
    for e in edges {
        let d = e.p - c;
        let r = d.length();
        if r >= r_min && r <= r_max && (e.g.dot(d) / r).abs() >= RADIAL_COS {
            hist[r as usize] += 1.0;
        }
    }
    let half = (width.ceil() as usize).max(1);
    (r_min as usize..n.saturating_sub(half))
        .map(|r| {
            let count: f64 = hist[r.saturating_sub(half)..=r + half].iter().sum();
            (r, count / r.max(1) as f64)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .filter(|&(_, score)| score > 0.0)
        .map(|(r, _)| r as f64 + 0.5)
}

/// Distance from a crisp outline within which an edge point is on it, pixels: the sub-pixel
/// edge's error under JPEG (about half a pixel) plus a wobble of 0.5% of the radius.
pub fn tolerance(r: f64) -> f64 {
    1.0 + 0.005 * r
}

/// The widest wobble allowed a painted outline, as a share of the radius: painters finish
/// an outline with their smallest brushes, of radius 2–4% of the sphere's (1.6–4.5% in the
/// MyPaint presets of tools/mypaint), and a stroke that crosses it moves it by about that.
const PAINTED_WOBBLE: f64 = 0.03;

/// Edge points within this many of the outline's own standard deviations are on it (99%
/// of a normal spread).
const WOBBLE_SDS: f64 = 2.5;

/// Distance from `disk`'s outline within which an edge point is on it, pixels: the crisp
/// [`tolerance`], widened to the outline's own measured spread where it is painted, up to
/// [`PAINTED_WOBBLE`]. The spread is a robust one (the median absolute deviation) of the
/// radial edge points' distances within the widest band, so strays and other curves
/// crossing the band do not set it.
pub fn outline_tolerance(edges: &[Edge], disk: &Disk) -> f64 {
    let (crisp, widest) = (tolerance(disk.r), 1.0 + PAINTED_WOBBLE * disk.r);
    let c = DVec2::new(disk.cx, disk.cy);
    let mut off: Vec<f64> = on_outline(edges, disk, widest).map(|p| p.distance(c) - disk.r).collect();
    if off.len() < 8 {
        return crisp;
    }
    off.sort_by(f64::total_cmp);
    let median = off[off.len() / 2];
    let mut dev: Vec<f64> = off.iter().map(|x| (x - median).abs()).collect();
    dev.sort_by(f64::total_cmp);
    let sd = 1.4826 * dev[dev.len() / 2];
    (WOBBLE_SDS * sd).clamp(crisp, widest)
}

/// `start` refined: geometric least squares on the edge points near it with a radial
/// gradient, the band narrowing from the Hough bin to [`tolerance`], then once more on the
/// outline's own spread ([`outline_tolerance`]). `None` when too few.
pub fn refine(edges: &[Edge], start: Disk, w: usize, h: usize) -> Option<Support> {
    let mut disk = start;
    for band in [6.0, 4.0, 2.0, 1.0] {
        let tol = tolerance(disk.r) * band;
        let near: Vec<DVec2> = on_outline(edges, &disk, tol).collect();
        if near.len() < 8 {
            return None;
        }
        disk = geometric(&near, disk)?;
    }
    // A painted outline spreads wider than a crisp one: fit it again on all of its spread.
    let tol = outline_tolerance(edges, &disk);
    if tol > tolerance(disk.r) {
        let near: Vec<DVec2> = on_outline(edges, &disk, tol).collect();
        disk = geometric(&near, disk)?;
    }
    Some(support(edges, &disk, w, h))
}

/// The edge points within `tol` of the outline of `disk` whose gradient is radial.
fn on_outline<'a>(edges: &'a [Edge], disk: &'a Disk, tol: f64) -> impl Iterator<Item = DVec2> + 'a {
    let c = DVec2::new(disk.cx, disk.cy);
    edges.iter().filter_map(move |e| {
        let d = e.p - c;
        let r = d.length();
        ((r - disk.r).abs() <= tol && r > 0.0 && (e.g.dot(d) / r).abs() >= RADIAL_COS).then_some(e.p)
    })
}

/// Gauss–Newton on $\sum_i (\lVert p_i - c\rVert - r)^2$ from `start` (a few steps: the
/// start is within a few pixels).
fn geometric(points: &[DVec2], start: Disk) -> Option<Disk> {
    let mut d = start;
    for _ in 0..10 {
        let (mut m, mut rhs) = (DMat3::ZERO, DVec3::ZERO);
        let c = DVec2::new(d.cx, d.cy);
        for p in points {
            let v = *p - c;
            let len = v.length().max(1e-9);
            // Residual f = |p - c| - r; its gradient in (cx, cy, r).
            let jac = DVec3::new(-v.x / len, -v.y / len, -1.0);
            let f = len - d.r;
            m += DMat3::from_cols(jac * jac.x, jac * jac.y, jac * jac.z);
            rhs -= jac * f;
        }
        if m.determinant().abs() < 1e-12 {
            return None;
        }
        let step = m.inverse() * rhs;
        d = Disk { cx: d.cx + step.x, cy: d.cy + step.y, r: d.r + step.z };
        if !(d.r > 0.0 && d.cx.is_finite() && d.cy.is_finite()) {
            return None;
        }
        if step.length() < 1e-4 {
            break;
        }
    }
    Some(d)
}

/// How much of `disk`'s outline the edge points cover: bins of about two pixels of arc,
/// each seen when an edge point within [`outline_tolerance`] with a radial gradient falls in it.
pub fn support(edges: &[Edge], disk: &Disk, w: usize, h: usize) -> Support {
    let tolerance = outline_tolerance(edges, disk);
    let (seen, seen_in_frame) = seen_within(edges, disk, tolerance, w, h);
    Support { disk: *disk, seen, seen_in_frame, tolerance }
}

/// The shares of `disk`'s whole outline and of its outline inside the frame with an edge
/// point within `tol` whose gradient is radial.
fn seen_within(edges: &[Edge], disk: &Disk, tol: f64, w: usize, h: usize) -> (f64, f64) {
    let n = ((std::f64::consts::TAU * disk.r / 2.0).round() as usize).clamp(16, 2048);
    let mut seen = vec![false; n];
    let c = DVec2::new(disk.cx, disk.cy);
    for p in on_outline(edges, disk, tol) {
        let a = (p - c).to_angle().rem_euclid(std::f64::consts::TAU);
        seen[((a / std::f64::consts::TAU * n as f64) as usize).min(n - 1)] = true;
    }
    let in_frame = |k: usize| {
        let a = (k as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
        let (x, y) = (disk.cx + disk.r * a.cos(), disk.cy + disk.r * a.sin());
        x > 1.0 && y > 1.0 && x < w as f64 - 1.0 && y < h as f64 - 1.0
    };
    let visible = (0..n).filter(|&k| in_frame(k)).count();
    let seen_visible = (0..n).filter(|&k| seen[k] && in_frame(k)).count();
    let all = seen.iter().filter(|&&s| s).count() as f64 / n as f64;
    (all, if visible == 0 { 0.0 } else { seen_visible as f64 / visible as f64 })
}

/// The share of `disk`'s outline in the frame its edges cover beyond chance: the share a
/// ring of the same centre and tolerance covers a little inside and outside the outline
/// (where only shading, strokes, grain and the shadow's edge are) is what texture alone
/// gives, and `seen_in_frame` counts only what exceeds it: $(s - s_0)/(1 - s_0)$.
pub fn seen_beyond_chance(edges: &[Edge], s: &Support, w: usize, h: usize) -> f64 {
    let rings = [0.85, 0.9, 1.1, 1.15];
    let chance = rings.iter().map(|k| seen_within(edges, &Disk { r: s.disk.r * k, ..s.disk }, s.tolerance, w, h).1).sum::<f64>() / rings.len() as f64;
    if chance >= 1.0 {
        return 0.0;
    }
    ((s.seen_in_frame - chance) / (1.0 - chance)).max(0.0)
}

/// How the edges' gradient turns along the seen arcs of `disk`'s outline, per radian of
/// arc: about 0 on a circle, whose gradient stays radial as the arc turns, and about -1 on
/// a straight edge passing within [`outline_tolerance`] of it (a polygon's side), whose gradient
/// keeps its direction, so its angle from the radial one falls as fast as the arc turns.
/// A least-squares slope pooled over the runs of points (each centred on its own mean), so
/// noise in the gradient's direction averages out; 0 when there is no run to measure.
pub fn turning(edges: &[Edge], disk: &Disk) -> f64 {
    let c = DVec2::new(disk.cx, disk.cy);
    let tol = outline_tolerance(edges, disk);
    let mut pts: Vec<(f64, f64)> = edges
        .iter()
        .filter_map(|e| {
            let d = e.p - c;
            let r = d.length();
            let cos = if r > 0.0 { e.g.dot(d) / r } else { 0.0 };
            if (r - disk.r).abs() > tol || cos.abs() < RADIAL_COS {
                return None;
            }
            // The gradient's signed angle from the radial direction (either way across).
            let g = e.g * cos.signum();
            Some((d.to_angle(), (d.x * g.y - d.y * g.x).atan2(d.dot(g))))
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    // A run ends where the arc has a gap of more than a few pixels.
    let gap = 4.0 / disk.r.max(1.0);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    let mut start = 0;
    for k in 1..=pts.len() {
        if k < pts.len() && pts[k].0 - pts[k - 1].0 <= gap {
            continue;
        }
        let run = &pts[start..k];
        let n = run.len() as f64;
        let (ma, md) = (run.iter().map(|p| p.0).sum::<f64>() / n, run.iter().map(|p| p.1).sum::<f64>() / n);
        sxy += run.iter().map(|p| (p.0 - ma) * (p.1 - md)).sum::<f64>();
        sxx += run.iter().map(|p| (p.0 - ma).powi(2)).sum::<f64>();
        start = k;
    }
    if sxx > 0.0 { sxy / sxx } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_fit_recovers_an_arc() {
        let truth = Disk { cx: 40.0, cy: -10.0, r: 75.0 };
        let pts: Vec<DVec2> = (0..60).map(|k| k as f64 * 0.03 + 0.4).map(|a| DVec2::new(truth.cx + truth.r * a.cos(), truth.cy + truth.r * a.sin())).collect();
        let d = geometric(&pts, Disk { cx: 45.0, cy: -5.0, r: 70.0 }).unwrap();
        assert!((d.cx - truth.cx).abs() < 1e-6 && (d.cy - truth.cy).abs() < 1e-6 && (d.r - truth.r).abs() < 1e-6, "{d:?}");
    }

    #[test]
    fn gradients_turn_with_a_circle_and_not_with_a_square() {
        let disk = Disk { cx: 50.0, cy: 50.0, r: 30.0 };
        let circle: Vec<Edge> = (0..180).map(|k| k as f64 / 180.0 * std::f64::consts::TAU).map(|a| Edge { p: DVec2::new(50.0 + 30.0 * a.cos(), 50.0 + 30.0 * a.sin()), g: DVec2::new(a.cos(), a.sin()) }).collect();
        assert!(turning(&circle, &disk).abs() < 0.05);
        // The square's sides, tangent to the circle, each seen over ±20°.
        let side: Vec<Edge> = (-11..=11).map(|t| Edge { p: DVec2::new(80.0, 50.0 + t as f64), g: DVec2::X }).collect();
        assert!(turning(&side, &disk) < -0.8, "{}", turning(&side, &disk));
    }
}
