//! Where the sphere is in a lit-sphere picture: a circle fitted to its alpha, to what is
//! not background, or to the arc its edges show ([`locate`]); or the circle a user gave,
//! checked ([`given_disk`]).

use glam::{DMat3, DVec3};

use super::edges;
use super::occluder::{self, InFront};
use super::segment::{border_median, components, otsu, perceptual_distance};
use super::{Disk, Located, Outline};
use crate::error::{Error, Result};
use crate::images::{neighbours4, Painting};

/// Least share of the outline inside the frame an edge-fitted circle must show, beyond what
/// the picture's texture gives any ring ([`edges::seen_beyond_chance`]), to be taken as the
/// sphere: a square's inscribed circle gets about 40% from its four sides (radial within
/// 20°, within a pixel), a sphere whose shadow hides its lower third about 60%.
pub const MIN_SEEN: f64 = 0.5;

/// Least share beyond chance of a circle taken when no circle shows [`MIN_SEEN`]: a painted
/// sphere whose dark side merges with its shadow and the table shows only its lit half
/// (about 45%), and a third of its outline, the lit arc above the terminator, still fixes
/// the circle (three points do). The outline is then reported as faint, for the user to check.
pub const MIN_FAINT: f64 = 1.0 / 3.0;

/// A circle's edge gradients turn with its arc (a turning of 0, [`edges::turning`]); a
/// polygon's sides tangent to a circle keep their direction (-1): halfway tells them apart.
/// (A square's sides cover half of its inscribed circle within tolerance, as a sphere does.)
const STRAIGHT_TURNING: f64 = -0.5;

/// A circle the edges support better than the segmentation's by this share of the outline
/// replaces it: a clean MatCap's segmented circle has its whole outline and stays as it was.
const BETTER_BY: f64 = 0.15;

/// An edge circle this close to a square picture's inscribed one (a share of its radius,
/// centre and radius) is the MatCap layout, and the disk is the inscribed circle exactly.
const MATCAP_MATCH: f64 = 0.02;

/// The smallest radius a sphere found in a picture may have: a tenth of its shorter side
/// (a smaller round shape is a highlight or a detail, not an exemplar's sphere), and 4 pixels.
fn min_radius(w: usize, h: usize) -> f64 {
    (w.min(h) as f64 / 10.0).max(4.0)
}

fn near(a: &Disk, b: &Disk, share: f64) -> bool {
    let tol = share * b.r;
    (a.cx - b.cx).hypot(a.cy - b.cy) <= tol && (a.r - b.r).abs() <= tol
}

/// Where the sphere is: [`find_disk`], with the share of the outline the picture shows.
pub fn locate(p: &Painting, name: &str) -> Result<Located> {
    locate_reading(p, name).map(|(located, _)| located)
}

/// [`locate`], and what stands in front of the sphere ([`in_front`]), read from the edges
/// the finder computed.
pub(super) fn locate_in_front(p: &Painting, name: &str) -> Result<(Located, Option<InFront>)> {
    let (located, reading) = locate_reading(p, name)?;
    let front = reading.and_then(|r| in_front(&r.channels, &r.coarse, &located, p.width, p.height));
    Ok((located, front))
}

/// What the finder computed from a picture without alpha, which the occluder reads too.
struct Reading {
    channels: Vec<Vec<f32>>,
    coarse: Vec<edges::Edge>,
}

/// [`locate`], with the picture's channels and coarse edges (none where an alpha channel
/// gave the disk).
fn locate_reading(p: &Painting, name: &str) -> Result<(Located, Option<Reading>)> {
    let (w, h) = (p.width, p.height);
    let has_alpha = p.alpha.iter().any(|&a| a < 0.5) && p.alpha.iter().any(|&a| a >= 0.5);
    if has_alpha {
        let mask: Vec<bool> = p.alpha.iter().map(|&a| a >= 0.5).collect();
        let disk = outline_circle(&mask, Boundary::Coverage, w, h, name)?;
        let edges = edges::points(std::slice::from_ref(&p.alpha), w, h);
        return Ok((Located { disk, outline: Outline::Alpha, seen: edges::support(&edges, &disk, w, h).seen }, None));
    }
    let key = border_median(p);
    let distance: Vec<f32> = p.pixels.iter().map(|c| perceptual_distance(c, &key)).collect();
    let max = distance.iter().cloned().fold(0.0f32, f32::max);
    if max < 0.02 {
        return Err(Error::input(format!("{name} is all background: no sphere to find")));
    }
    let t = otsu(&distance, max);
    let like_border: Vec<bool> = distance.iter().map(|&d| d <= t).collect();
    let background = connected_to_border(&like_border, w, h);
    let mask: Vec<bool> = background.iter().map(|&b| !b).collect();
    let channels = perceptual_channels(p);
    let edges = edges::points(&channels, w, h);
    let coarse = edges::coarse_points(&channels, w, h);
    let segmented = outline_circle(&mask, Boundary::Key, w, h, name);
    let square = w.abs_diff(h) <= 1;
    let inscribed = Disk { cx: w as f64 / 2.0, cy: h as f64 / 2.0, r: w.min(h) as f64 / 2.0 };
    let by_edges = edge_circle(&edges, &coarse, w, h, name);
    let located = match (segmented, by_edges) {
        (Ok(disk), Ok(EdgeCircle::Clear(e))) => {
            let own = edges::support(&edges, &disk, w, h);
            Ok(if e.seen_in_frame > own.seen_in_frame + BETTER_BY {
                Located { disk: e.disk, outline: Outline::Edges, seen: e.seen }
            } else {
                Located { disk, outline: Outline::Background, seen: own.seen }
            })
        }
        (Ok(disk), _) => Ok(Located { disk, outline: Outline::Background, seen: edges::support(&edges, &disk, w, h).seen }),
        (Err(_), Ok(EdgeCircle::Clear(e))) if !(square && near(&e.disk, &inscribed, MATCAP_MATCH)) => Ok(Located { disk: e.disk, outline: Outline::Edges, seen: e.seen }),
        (Err(_), Err(two)) => Err(two),
        (Err(_), _) if square => Ok(Located { disk: inscribed, outline: Outline::Inscribed, seen: edges::support(&edges, &inscribed, w, h).seen }),
        (Err(_), Ok(EdgeCircle::Faint(e))) => Ok(Located { disk: e.disk, outline: Outline::Faint, seen: e.seen }),
        (Err(e), _) => Err(e),
    }?;
    let located = if square { matcap_layout(located, &edges, w, h) } else { located };
    Ok((located, Some(Reading { channels, coarse })))
}

/// A square picture is a MatCap, its sphere inscribed, unless the circle found shows more
/// of an outline than the inscribed one by [`BETTER_BY`]: a sphere whose unlit side is as
/// dark as the background shows only its lit arc, to which a smaller circle nearer the
/// light fits as well as the inscribed one, and a rendered sphere's last pixel ring of
/// the outline lies half a pixel inside it.
fn matcap_layout(found: Located, edges: &[edges::Edge], w: usize, h: usize) -> Located {
    let inscribed = Disk { cx: w as f64 / 2.0, cy: h as f64 / 2.0, r: w.min(h) as f64 / 2.0 };
    if found.outline == Outline::Inscribed {
        return found;
    }
    // `found.seen` is its support on the same edges (every branch of locate_reading).
    let matcap = edges::support(edges, &inscribed, w, h);
    if found.seen > matcap.seen + BETTER_BY {
        found
    } else {
        Located { disk: inscribed, outline: Outline::Inscribed, seen: matcap.seen }
    }
}

/// Where the sphere is: a circle fitted to the alpha channel when the picture has one, or
/// else to what is not background (the pixels like the border's median colour, split by
/// Otsu's threshold, that connect to the border), or, where that is not round (a sphere on
/// a table with its shadow, on a textured background), to the arc of the outline the edges
/// show ([`edges`]); a square picture without a clear outline is taken as a MatCap, whose
/// disk is inscribed in it; another takes the best circle on a faint arc ([`MIN_FAINT`]).
/// Errors, one line each: the picture is all background, no round shape, two shapes.
pub fn find_disk(p: &Painting, name: &str) -> Result<(Disk, Outline)> {
    locate(p, name).map(|l| (l.disk, l.outline))
}

/// What stands in front of the sphere `located` in a `w` × `h` picture of `channels`
/// ([`perceptual_channels`]) and `coarse` edges ([`edges::coarse_points`], where grain and
/// bristle marks along the thing's top blur away) ([`occluder`]): nothing in a MatCap (a disk
/// inscribed in its square, alone) or where an alpha channel says what the sphere is.
fn in_front(channels: &[Vec<f32>], coarse: &[edges::Edge], located: &Located, w: usize, h: usize) -> Option<InFront> {
    if matches!(located.outline, Outline::Inscribed | Outline::Alpha) {
        return None;
    }
    occluder::find(channels, coarse, &located.disk, w, h)
}

/// The circles the picture's edges support: the best one that shows at least [`MIN_SEEN`]
/// of its outline inside the frame (beyond chance), and the best that shows at least
/// [`MIN_FAINT`], when no circle shows more. Error: two disjoint circles both well supported.
fn edge_circle(edges: &[edges::Edge], coarse: &[edges::Edge], w: usize, h: usize, name: &str) -> Result<EdgeCircle> {
    // A sphere may be cut by the frame: up to the longer side across.
    let (r_min, r_max) = (min_radius(w, h), w.max(h) as f64 / 2.0);
    let round: Vec<(f64, edges::Support)> = edges::circles(edges, coarse, w, h, r_min, r_max)
        .into_iter()
        .filter(|s| edges::turning(edges, &s.disk) > STRAIGHT_TURNING)
        .map(|s| (edges::seen_beyond_chance(edges, &s, w, h), s))
        .collect();
    let good: Vec<edges::Support> = round.iter().filter(|c| c.0 >= MIN_SEEN).map(|c| c.1).collect();
    let Some(best) = good.first().copied() else {
        return Ok(round.iter().find(|c| c.0 >= MIN_FAINT).map_or(EdgeCircle::None, |c| EdgeCircle::Faint(c.1)));
    };
    let apart = |a: &Disk, b: &Disk| ((a.cx - b.cx).powi(2) + (a.cy - b.cy).powi(2)).sqrt() >= 0.95 * (a.r + b.r);
    // A second sphere shows most of its own outline (not just a short arc inside the frame,
    // as a circle through the horizon or the frame's corner can) and about as much of it.
    let rival = |s: &edges::Support| apart(&s.disk, &best.disk) && s.seen >= MIN_SEEN && s.seen * s.disk.r >= 0.5 * best.seen * best.disk.r;
    if let Some(other) = good.iter().skip(1).find(|s| rival(s)) {
        return Err(Error::input(format!(
            "{name}: two shapes (circles of radius {:.0} and {:.0} pixels): give a picture of one sphere",
            best.disk.r, other.disk.r
        )));
    }
    Ok(EdgeCircle::Clear(best))
}

/// What the edges say about the sphere's outline ([`edge_circle`]).
enum EdgeCircle {
    /// A circle showing at least [`MIN_SEEN`] of its outline.
    Clear(edges::Support),
    /// The best circle, showing less than that but at least [`MIN_FAINT`].
    Faint(edges::Support),
    None,
}

/// The picture's channels as square roots of linear values (roughly perceptual, as
/// [`perceptual_distance`]).
fn perceptual_channels(p: &Painting) -> Vec<Vec<f32>> {
    (0..3).map(|c| p.pixels.iter().map(|x| x[c].max(0.0).sqrt()).collect()).collect()
}

/// The pixels of `mask` connected (4-neighbours) to the picture's border through `mask`.
fn connected_to_border(mask: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut seen = vec![false; w * h];
    let mut stack: Vec<usize> = (0..w).flat_map(|i| [i, (h - 1) * w + i]).chain((0..h).flat_map(|j| [j * w, j * w + w - 1])).collect();
    while let Some(k) = stack.pop() {
        if seen[k] || !mask[k] {
            continue;
        }
        seen[k] = true;
        stack.extend(neighbours4(k, w, w * h));
    }
    seen
}

/// Where a mask's outline lies between its last inside pixel and the first outside one.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Boundary {
    /// Alpha of half or more: a pixel is in when the shape covers its centre, so the outline
    /// crosses the segment to the outside centre at a point uniform along it, on average
    /// its midpoint.
    Coverage,
    /// A background colour key: its threshold sits anywhere in the antialiased ramp, and a
    /// rim as dark as the background falls outside; the last inside centre is the outline.
    Key,
}

/// The circle of the one large shape of `mask`.
fn outline_circle(mask: &[bool], boundary: Boundary, w: usize, h: usize, name: &str) -> Result<Disk> {
    let (labels, components) = components(mask, w, h);
    let Some(&(largest, area)) = components.iter().max_by_key(|c| c.1) else {
        return Err(Error::input(format!("{name} is all background: no sphere to find")));
    };
    if area < (w * h / 400).max(64) {
        return Err(Error::input(format!("{name}: no disk found (the largest shape is {area} pixels)")));
    }
    // A second shape of comparable size makes the picture ambiguous only when the largest is
    // a sphere: a gradient or a lit wall splits into large pieces none of which is round.
    let rival = components.iter().filter(|c| c.0 != largest).map(|c| c.1).max().filter(|&other| other * 5 > area);
    let inside = |i: isize, j: isize| i >= 0 && j >= 0 && (i as usize) < w && (j as usize) < h && labels[j as usize * w + i as usize] == largest;
    let mut edge = Vec::new();
    for j in 0..h as isize {
        for i in 0..w as isize {
            if !inside(i, j) {
                continue;
            }
            let centre = glam::DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
            for step in [glam::DVec2::NEG_X, glam::DVec2::X, glam::DVec2::NEG_Y, glam::DVec2::Y] {
                if inside(i + step.x as isize, j + step.y as isize) {
                    continue;
                }
                match boundary {
                    Boundary::Coverage => edge.push(centre + 0.5 * step),
                    Boundary::Key => {
                        edge.push(centre);
                        break;
                    }
                }
            }
        }
    }
    // The picture's edge is not the sphere's: a disk cropped by the frame keeps only its
    // own boundary.
    let own: Vec<_> = edge.iter().copied().filter(|e| e.x > 1.0 && e.y > 1.0 && e.x < w as f64 - 1.0 && e.y < h as f64 - 1.0).collect();
    let disk = fit_envelope(if own.len() >= 8 { &own } else { &edge })
        .ok_or_else(|| Error::input(format!("{name}: no disk found (the shape's outline is not a circle)")))?;
    // Round: the shape fills its circle.
    let circle_area = std::f64::consts::PI * disk.r * disk.r;
    let round = (0.8..=1.1).contains(&(area as f64 / circle_area)) && disk.r >= 4.0;
    if let Some(other) = rival.filter(|_| round) {
        return Err(Error::input(format!("{name}: two shapes ({area} and {other} pixels): give a picture of one sphere")));
    }
    // An alpha says where the sphere is, whatever its size; a colour key may find a highlight.
    if boundary == Boundary::Key && disk.r < min_radius(w, h) {
        return Err(Error::input(format!("{name}: no disk found (the round shape, {:.0} pixels across, is too small for a sphere)", 2.0 * disk.r)));
    }
    if !round {
        return Err(Error::input(format!(
            "{name}: no disk found (the shape is not round: it fills {:.0}% of its circle)",
            100.0 * area as f64 / circle_area
        )));
    }
    Ok(disk)
}

/// The circle through the outer envelope of boundary points: an algebraic (Kåsa) fit,
/// repeated without points well inside it, so a rim as dark as the background (which eats
/// into the shape) does not shrink the circle.
fn fit_envelope(points: &[glam::DVec2]) -> Option<Disk> {
    let mut keep: Vec<glam::DVec2> = points.to_vec();
    let mut disk = None;
    for _ in 0..6 {
        let d = kasa(&keep)?;
        let tolerance = (0.01 * d.r).max(1.0);
        let next: Vec<_> = points.iter().copied().filter(|p| (p.distance(glam::DVec2::new(d.cx, d.cy)) - d.r) > -tolerance).collect();
        disk = Some(d);
        if next.len() < 8 || next.len() == keep.len() {
            break;
        }
        keep = next;
    }
    disk
}

/// Least-squares circle $x^2 + y^2 + Dx + Ey + F = 0$ through `points`.
fn kasa(points: &[glam::DVec2]) -> Option<Disk> {
    if points.len() < 3 {
        return None;
    }
    let (mut m, mut rhs) = (DMat3::ZERO, DVec3::ZERO);
    for p in points {
        let row = DVec3::new(p.x, p.y, 1.0);
        m += DMat3::from_cols(row * row.x, row * row.y, row * row.z);
        rhs += row * -(p.x * p.x + p.y * p.y);
    }
    if m.determinant().abs() < 1e-9 {
        return None;
    }
    let s = m.inverse() * rhs;
    let (cx, cy) = (-s.x / 2.0, -s.y / 2.0);
    let r2 = cx * cx + cy * cy - s.z;
    (r2 > 0.0 && r2.is_finite()).then(|| Disk { cx, cy, r: r2.sqrt() })
}

/// The disk a user gave (`as_given`, in the file's pixels; `disk`, the same in the shrunk
/// `painting`'s), checked: a circle of at least 4 pixels whose inside is mostly in the picture;
/// and what stands in front of the sphere ([`in_front`]).
pub(super) fn given_disk(painting: &Painting, disk: Disk, as_given: Disk, name: &str) -> Result<(Located, Option<InFront>)> {
    let Disk { cx, cy, r } = as_given;
    let shown = format!("the disk at ({cx}, {cy}) of radius {r}");
    if !(cx.is_finite() && cy.is_finite() && r.is_finite()) || r <= 0.0 {
        return Err(Error::input(format!("{shown}: a disk needs a finite centre and a radius above 0, in pixels")));
    }
    if disk.r < 4.0 {
        return Err(Error::input(format!("{shown}: a radius of {:.1} pixels in the picture as fitted (shrunk to {} pixels a side) is too small for a sphere: it needs 4", disk.r, painting.width.max(painting.height))));
    }
    let (w, h) = (painting.width, painting.height);
    let inside = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).filter(|&(i, j)| disk.normal(i, j, 1.0).is_some()).count();
    let area = std::f64::consts::PI * disk.r * disk.r;
    if (inside as f64) < 0.5 * area {
        return Err(Error::input(format!("{shown}: less than half of that disk lies on {name} ({}x{} pixels)", painting.width, painting.height)));
    }
    let channels = perceptual_channels(painting);
    let seen = edges::support(&edges::points(&channels, w, h), &disk, w, h).seen;
    let located = Located { disk, outline: Outline::Given, seen };
    let front = in_front(&channels, &edges::coarse_points(&channels, w, h), &located, w, h);
    Ok((located, front))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kasa_recovers_a_circle_from_three_points() {
        let d = kasa(&[glam::DVec2::new(1.0, 0.0), glam::DVec2::new(-1.0, 0.0), glam::DVec2::new(0.0, 1.0)]).unwrap();
        assert!(d.cx.abs() < 1e-9 && d.cy.abs() < 1e-9 && (d.r - 1.0).abs() < 1e-9, "{d:?}");
    }
}
