//! Something in front of the sphere: an exemplar's sphere partly hidden at the bottom by the
//! table's front edge or a box. Inside the disk that thing is not the sphere, and fitted as
//! shading it would paint the sphere's lower normals its colour.
//!
//! The model: the top of a thing in front is a straight edge that crosses the disk and
//! continues beyond the outline, since the thing is wider than where it meets the sphere.
//! Nothing the sphere itself shows is such an edge: a terminator, a toon band or a highlight
//! is the picture of a circle on the sphere, and ends at the outline; a straight edge behind
//! the sphere (the table's back edge, a wall's corner) is hidden by it and leaves no edge
//! across the disk. Of the two sides of the edge, the thing is on the one without the centre
//! (a sphere mostly hidden is no exemplar).
//!
//! ```text
//! edge points ──hough (θ, ρ)──► straight lines
//! line ──across: edge points along its chord inside the disk, beyond chance──┐
//!      ──beyond: edge points along it outside the outline, beyond chance─────┤
//!      ──continues: the same colour beyond it inside the disk as outside─────┴──► InFront
//!                   (refitted by least squares on its edge points)
//! ```

use glam::{DVec2, DVec3};

use super::edges::Edge;
use super::Disk;

/// A straight edge in front of the sphere: the pixels beyond it are not the sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InFront {
    /// Unit normal of the edge, pointing away from the disk's centre (towards the thing).
    pub normal: DVec2,
    /// The edge is the points $p$ with $\text{normal} \cdot p = \text{offset}$.
    pub offset: f64,
}

/// Pixels within this distance of the edge, on the sphere's side, may mix the two (a painted
/// edge wanders by about a pixel each way, and JPEG rings beside it): they go with the thing.
const MIXED: f64 = 2.0;

impl InFront {
    /// Whether the pixel centred at `p` (pixel coordinates) shows the thing in front.
    pub fn hides(&self, p: DVec2) -> bool {
        self.normal.dot(p) > self.offset - MIXED
    }
}

/// An edge point lies on a line when within this distance of it and when its gradient is
/// within [`ALONG_DEG`] of the line's normal: a painted edge wanders by about a pixel.
const NEAR: f64 = 1.5;
const ALONG_DEG: f64 = 20.0;

/// Least share of the chord inside the disk (and of the line just beyond the outline) with
/// an edge point on it, beyond the share texture gives any line there ([`CHANCE_SHIFT`]): a
/// thing in front shows its top across the whole sphere, where a stroke's edge that happens
/// to be straight covers a short piece of it.
const MIN_ACROSS: f64 = 0.4;
const MIN_BEYOND: f64 = 0.3;

/// Fewer edge points than this on a line are no line worth scoring.
const MIN_VOTES: u32 = 8;

/// The edge's distance from the disk's centre, in radii: at least this much (which side hides
/// the sphere is told by the centre), and short of the outline.
const OFFSET_RANGE: std::ops::RangeInclusive<f64> = 0.1..=0.95;

/// Chance: the same line moved this far each way (beyond an edge's own spread, [`NEAR`] and
/// [`MIXED`]) meets texture's edge points only.
const CHANCE_SHIFT: f64 = 6.0;

/// Edge points within this many pixels of the frame are not read: the gradient there sees
/// past the picture's edge, and a scan's margin is not in the scene.
const FRAME_MARGIN: f64 = 4.0;

/// Straight lines tried, by votes.
const CANDIDATES: usize = 12;

/// The thing in front of the sphere in `disk`, if the picture's `edges` (of a `w` × `h`
/// picture) show one.
pub fn find(channels: &[Vec<f32>], edges: &[Edge], disk: &Disk, w: usize, h: usize) -> Option<InFront> {
    let grid = Grid::new(edges, w, h);
    lines(edges, w, h)
        .into_iter()
        .filter_map(|(n, rho)| grid.refine(n, rho, disk))
        .filter(|s| s.across >= MIN_ACROSS && s.beyond >= MIN_BEYOND && continues(channels, w, h, &s.line, disk))
        .max_by(|a, b| a.across.total_cmp(&b.across))
        .map(|s| grid.fit(&s.line).unwrap_or(s.line))
}

/// Depth of the strips beside the edge whose colours [`continues`] compares, in pixels.
const STRIP: f64 = 8.0;

/// Whether what lies beyond the edge inside the disk is the thing that lies beyond it outside
/// the outline: its mean colour (in `channels`) nearer that outside than the sphere's just on
/// this side of the edge. A thing in front is one surface on both sides of the sphere; a
/// terminator or a stroke that happens to line up with an edge outside has the sphere beyond it.
fn continues(channels: &[Vec<f32>], w: usize, h: usize, line: &InFront, disk: &Disk) -> bool {
    let centre = DVec2::new(disk.cx, disk.cy);
    // Colour sums and counts: the sphere's side inside the disk, the far side inside, and
    // the far side outside the outline (out to a radius beyond it).
    let (mut sphere, mut inside, mut outside) = ((DVec3::ZERO, 0.0), (DVec3::ZERO, 0.0), (DVec3::ZERO, 0.0));
    for j in 0..h {
        for i in 0..w {
            let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
            let t = line.normal.dot(p) - line.offset;
            let d = p.distance(centre) / disk.r;
            let near_side = (-MIXED - STRIP..-MIXED).contains(&t);
            let far_side = t > MIXED && t <= MIXED + STRIP;
            let strip = match (near_side, far_side) {
                (true, _) if d < 0.95 => &mut sphere,
                (_, true) if d < 0.95 => &mut inside,
                (_, true) if d > 1.05 && d < 2.0 => &mut outside,
                _ => continue,
            };
            let k = j * w + i;
            strip.0 += DVec3::new(channels[0][k] as f64, channels[1][k] as f64, channels[2][k] as f64);
            strip.1 += 1.0;
        }
    }
    if [sphere.1, inside.1, outside.1].contains(&0.0) {
        return false;
    }
    let (sphere, inside, outside) = (sphere.0 / sphere.1, inside.0 / inside.1, outside.0 / outside.1);
    inside.distance(outside) < inside.distance(sphere)
}

/// A line and how much more of it the edges cover than of its neighbours (texture's chance).
#[derive(Clone, Copy, Debug)]
struct Scored {
    line: InFront,
    across: f64,
    beyond: f64,
}

/// The line $n \cdot p = \rho$ as an [`InFront`] facing away from the disk's centre, when it
/// crosses the disk within [`OFFSET_RANGE`].
fn oriented(n: DVec2, rho: f64, disk: &Disk) -> Option<InFront> {
    let centre = DVec2::new(disk.cx, disk.cy);
    let signed = n.dot(centre) - rho;
    if !OFFSET_RANGE.contains(&(signed.abs() / disk.r)) {
        return None;
    }
    // The thing lies on the side without the centre.
    let s = -signed.signum();
    Some(InFront { normal: n * s, offset: rho * s })
}

/// The most voted straight lines $(n, \rho)$: each edge point votes for the line through it
/// across its gradient, in bins of 1° and 1 pixel; peaks are local maxima of their 3 × 3.
fn lines(edges: &[Edge], w: usize, h: usize) -> Vec<(DVec2, f64)> {
    const ANGLES: usize = 180;
    let reach = (w as f64).hypot(h as f64).ceil() as usize;
    let rhos = 2 * reach + 1;
    let mut votes = vec![0u32; ANGLES * rhos];
    for e in edges {
        let mut a = e.g.y.atan2(e.g.x);
        if a < 0.0 {
            a += std::f64::consts::PI;
        }
        // Every line through the point within ALONG_DEG of its gradient: a painted edge's
        // gradient wanders by several degrees along it.
        let centre = a.to_degrees().round() as isize;
        for t in centre - ALONG_DEG as isize..=centre + ALONG_DEG as isize {
            let t = t.rem_euclid(ANGLES as isize) as usize;
            let n = DVec2::from_angle((t as f64).to_radians());
            let rho = (n.dot(e.p).round() as isize + reach as isize).clamp(0, rhos as isize - 1);
            votes[t * rhos + rho as usize] += 1;
        }
    }
    let at = |t: isize, r: isize| votes[(t.rem_euclid(ANGLES as isize)) as usize * rhos + r.clamp(0, rhos as isize - 1) as usize];
    let mut peaks: Vec<(u32, usize, usize)> = Vec::new();
    for t in 0..ANGLES {
        for r in 1..rhos - 1 {
            let v = votes[t * rhos + r];
            if v < MIN_VOTES {
                continue;
            }
            let peak = (-1..=1).all(|dt| (-1..=1).all(|dr| (dt == 0 && dr == 0) || at(t as isize + dt, r as isize + dr) <= v));
            if peak {
                peaks.push((v, t, r));
            }
        }
    }
    peaks.sort_by(|a, b| b.0.cmp(&a.0));
    peaks.into_iter().take(CANDIDATES).map(|(_, t, r)| (DVec2::from_angle((t as f64).to_radians()), r as f64 - reach as f64)).collect()
}

/// Whether edge point `e` lies on `line`: within [`NEAR`] of it, its gradient within
/// [`ALONG_DEG`] of the line's normal.
fn lies_on(e: &Edge, line: &InFront) -> bool {
    (line.normal.dot(e.p) - line.offset).abs() <= NEAR && e.g.dot(line.normal).abs() >= ALONG_DEG.to_radians().cos()
}

/// Edge points by pixel, for looking them up along a line.
struct Grid<'a> {
    edges: &'a [Edge],
    /// Per pixel, the index of its edge point (at most one: they are local maxima).
    at: Vec<Option<u32>>,
    w: usize,
    h: usize,
}

impl<'a> Grid<'a> {
    fn new(edges: &'a [Edge], w: usize, h: usize) -> Grid<'a> {
        let mut at = vec![None; w * h];
        for (k, e) in edges.iter().enumerate() {
            let (i, j) = (e.p.x.floor(), e.p.y.floor());
            if i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h {
                at[j as usize * w + i as usize] = Some(k as u32);
            }
        }
        Grid { edges, at, w, h }
    }

    /// Whether an edge point near `p` lies on `line` ([`lies_on`]).
    fn on(&self, line: &InFront, p: DVec2) -> bool {
        let (ci, cj) = (p.x.floor() as isize, p.y.floor() as isize);
        (-2..=2).any(|dj| {
            (-2..=2).any(|di| {
                let (i, j) = (ci + di, cj + dj);
                if i < 0 || j < 0 || i >= self.w as isize || j >= self.h as isize {
                    return false;
                }
                self.at[j as usize * self.w + i as usize].is_some_and(|k| lies_on(&self.edges[k as usize], line))
            })
        })
    }

    /// The best line near $n \cdot p = \rho$ (within a degree and two pixels: the vote's
    /// bins), scored beyond chance; none outside [`OFFSET_RANGE`].
    fn refine(&self, n: DVec2, rho: f64, disk: &Disk) -> Option<Scored> {
        let mut best: Option<Scored> = None;
        for dt in [-1.0f64, 0.0, 1.0] {
            let n = DVec2::from_angle(n.to_angle() + dt.to_radians());
            for dr in [-2.0, -1.0, 0.0, 1.0, 2.0] {
                let Some(line) = oriented(n, rho + dr, disk) else { continue };
                let (across, beyond) = self.coverage(&line, disk);
                let shifted = |d: f64| self.coverage(&InFront { offset: line.offset + d, ..line }, disk);
                let (a1, b1) = shifted(-CHANCE_SHIFT);
                let (a2, b2) = shifted(CHANCE_SHIFT);
                let scored = Scored { line, across: across - 0.5 * (a1 + a2), beyond: beyond - 0.5 * (b1 + b2) };
                if best.is_none_or(|b| scored.across > b.across) {
                    best = Some(scored);
                }
            }
        }
        best
    }

    /// The least-squares line (orthogonal regression) through the edge points on `line`,
    /// facing the same way: the vote's bins place it to a degree and a pixel.
    fn fit(&self, line: &InFront) -> Option<InFront> {
        let on: Vec<DVec2> = self.edges.iter().filter(|e| lies_on(e, line)).map(|e| e.p).collect();
        if on.len() < 8 {
            return None;
        }
        let mean = on.iter().copied().sum::<DVec2>() / on.len() as f64;
        let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
        for p in &on {
            let d = *p - mean;
            (sxx, sxy, syy) = (sxx + d.x * d.x, sxy + d.x * d.y, syy + d.y * d.y);
        }
        // The normal is the direction of least spread: the smaller eigenvector of the scatter.
        let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy) + std::f64::consts::FRAC_PI_2;
        let mut normal = DVec2::from_angle(angle);
        if normal.dot(line.normal) < 0.0 {
            normal = -normal;
        }
        Some(InFront { normal, offset: normal.dot(mean) })
    }

    /// Shares of the line with an edge point on it: across the disk (its chord, short of the
    /// outline, whose own edge crosses there), and beyond the outline (up to a radius on
    /// each side, inside the picture; 0 where no pixel of it is).
    fn coverage(&self, line: &InFront, disk: &Disk) -> (f64, f64) {
        let centre = DVec2::new(disk.cx, disk.cy);
        let foot = centre + line.normal * (line.offset - line.normal.dot(centre));
        let along = line.normal.perp();
        let half = (disk.r * disk.r - (foot - centre).length_squared()).max(0.0).sqrt();
        let share = |from: f64, to: f64| {
            let (mut seen, mut all) = (0usize, 0usize);
            let mut t = from;
            while t <= to {
                let p = foot + along * t;
                let m = FRAME_MARGIN;
                if p.x >= m && p.y >= m && p.x < self.w as f64 - m && p.y < self.h as f64 - m {
                    all += 1;
                    seen += usize::from(self.on(line, p));
                }
                t += 1.0;
            }
            (seen, all)
        };
        // Across: the second least of the chord's quarters, so a curve that is straight over
        // part of it (a terminator's flattest arc) does not pass for an edge that crosses,
        // and an edge lost in one quarter (the sphere's dark side as dark as the thing) does.
        let inner = half - 2.0 * NEAR;
        let mut quarters: Vec<f64> = (0..4)
            .map(|q| {
                let from = -inner + 0.5 * inner * q as f64;
                let (seen, all) = share(from, from + 0.5 * inner);
                if all == 0 { 0.0 } else { seen as f64 / all as f64 }
            })
            .collect();
        quarters.sort_by(f64::total_cmp);
        let across = quarters[1];
        let (s1, a1) = share(-half - disk.r, -half - 2.0 * NEAR);
        let (s2, a2) = share(half + 2.0 * NEAR, half + disk.r);
        let beyond = if a1 + a2 == 0 { 0.0 } else { (s1 + s2) as f64 / (a1 + a2) as f64 };
        (across, beyond)
    }
}

