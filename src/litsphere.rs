//! Lit spheres and MatCaps: a picture of a painted or photographed sphere becomes a view of
//! a known scene, so the one fit path ([`crate::pipeline`]) turns it into a material.
//!
//! ```text
//! image ──find_disk──► Disk (centre, radius: a circle fitted to alpha or a background key)
//! image + Disk ──estimate_light──► the key light (unless the user gives it)
//! Disk + light ──scene──► an orthographic view of the unit sphere that frames the disk exactly
//! scene + image ──pipeline::fit──► Material;  MAT/scene.gltf keeps the scene
//! ```
//!
//! **The light.** A painter's highlight sits higher than mirror geometry puts it, and a
//! MatCap's brightest pixels are often its rim light, so the light is not taken from the
//! brightest point. It is the direction that best explains the shading of the whole disk
//! under a physical prior: the luminance is modelled as
//!
//! $$ Y(n) \approx a + b \max(n \cdot l, 0) + c \min(n \cdot l, 0), \qquad b \ge 0,\ c \ge 0, $$
//!
//! a lit side brighter towards the light (Lambert with ambient: $c = 0$) and, for warm-to-cool
//! paintings, an unlit side that still brightens towards the terminator ($c > 0$, Gooch).
//! For every candidate $l$ the model is linear in $(a, b, c)$, so each candidate costs one
//! 3×3 solve; candidates cover the whole sphere but straight behind it ([`MIN_LIGHT_Z`]:
//! a light there lights none of the disk). Pixels the
//! model cannot explain (highlights, strokes) are left out by a robust reweighting (residuals
//! beyond 2.5 MAD), and the spread of the near-optimal directions says how sure it is. When
//! that spread is wide (a MatCap lit by its surroundings), the picture cannot decide: the
//! light taken is the plausible key light among those directions (upper front), and a note
//! says so.
//!
//! **Stylized pictures** (toon, cel) are read as drawn instead ([`style`]): the light from
//! their tone edges ([`estimate_tone_light`]), fine tables, no light prior, a robust solve.

use std::path::Path;

use glam::{DMat3, DVec3, Mat4, Vec3};

use crate::error::{Error, Result};
use crate::factor::cache::Cache;
use crate::factor::Settings;
use crate::images::{neighbours4, Painting, Shrink};
use crate::note::Note;
use crate::pipeline::{Fitted, Options};
use crate::scene::{sphere_mesh, Camera, Light, Projection, Scene};
use crate::sample::{Erosion, PaintedView, SceneSampler};

pub mod colours;
pub mod edges;
mod light;
mod segment;
pub mod style;
pub mod texture;

pub use light::{estimate_light, estimate_tone_light, highlight_lean, unlit_floor, LightEstimate, KEY, MIN_LIGHT_Z, UNDECIDED_DEG};
pub use style::Style;
use segment::{border_median, components, otsu, perceptual_distance};

/// Longest side a lit-sphere picture is fitted at: larger pictures are box-filtered down
/// (a 512² disk holds about 200k samples; more add time, not information).
pub const MAX_SIDE: usize = 512;

/// Fewest pixels on the shorter side of a picture once shrunk to [`MAX_SIDE`]: a disk is
/// found only with a radius of 4 pixels or more ([`find_disk`]), so 16 leaves room for it.
pub const MIN_SIDE: usize = 16;

/// The sphere's outline in the picture, pixels (x right, y down, pixel centres at +0.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    pub cx: f64,
    pub cy: f64,
    pub r: f64,
}

impl Disk {
    /// The unit normal at pixel (i, j) in the view frame (x right, y up, z to the viewer),
    /// or `None` outside `fraction` of the radius.
    pub fn normal(&self, i: usize, j: usize, fraction: f64) -> Option<DVec3> {
        let x = (i as f64 + 0.5 - self.cx) / self.r;
        let y = -(j as f64 + 0.5 - self.cy) / self.r;
        let d2 = x * x + y * y;
        (d2 < fraction * fraction).then(|| DVec3::new(x, y, (1.0 - d2).max(0.0).sqrt()))
    }
}

/// How the sphere's outline was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outline {
    /// A circle fitted to the picture's alpha channel.
    Alpha,
    /// A circle fitted to the pixels that differ from the background.
    Background,
    /// A circle fitted to the arc of the outline that the picture's edges show (a sphere in
    /// context: on a table, with its shadow, on a textured background).
    Edges,
    /// No clear outline in a square picture: the disk inscribed in it, as in every MatCap.
    Inscribed,
    /// Given by the user (`--disk`).
    Given,
}

/// A disk found in a picture, and how much of its outline the picture shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Located {
    pub disk: Disk,
    pub outline: Outline,
    /// Share of the whole outline (360°) on which the picture has an edge (alpha's, or
    /// colour's) within a pixel or so of the circle, with a gradient across it.
    pub seen: f64,
}

impl Located {
    /// The note that reports the disk of the picture `name`, in the file's pixels (`scale`
    /// of them to one of the picture as fitted).
    pub fn note(&self, name: &str, scale: f64) -> Note {
        let d = &self.disk;
        Note::Disk { picture: name.to_string(), cx: d.cx * scale, cy: d.cy * scale, r: d.r * scale, seen: self.seen, given: self.outline == Outline::Given }
    }
}

/// Least share of the outline inside the frame an edge-fitted circle must show to be taken
/// as the sphere: a square's inscribed circle gets about 40% from its four sides (radial
/// within 20°, within a pixel), a sphere whose shadow hides its lower third about 60%.
pub const MIN_SEEN: f64 = 0.5;

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

fn near(a: &Disk, b: &Disk, share: f64) -> bool {
    let tol = share * b.r;
    (a.cx - b.cx).hypot(a.cy - b.cy) <= tol && (a.r - b.r).abs() <= tol
}

/// Where the sphere is: [`find_disk`], with the share of the outline the picture shows.
pub fn locate(p: &Painting, name: &str) -> Result<Located> {
    let (w, h) = (p.width, p.height);
    let has_alpha = p.alpha.iter().any(|&a| a < 0.5) && p.alpha.iter().any(|&a| a >= 0.5);
    if has_alpha {
        let mask: Vec<bool> = p.alpha.iter().map(|&a| a >= 0.5).collect();
        let disk = outline_circle(&mask, Boundary::Coverage, w, h, name)?;
        let edges = edges::points(std::slice::from_ref(&p.alpha), w, h);
        return Ok(Located { disk, outline: Outline::Alpha, seen: edges::support(&edges, &disk, w, h).seen });
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
    let edges = edges::points(&perceptual_channels(p), w, h);
    let segmented = outline_circle(&mask, Boundary::Key, w, h, name);
    let square = w.abs_diff(h) <= 1;
    let inscribed = Disk { cx: w as f64 / 2.0, cy: h as f64 / 2.0, r: w.min(h) as f64 / 2.0 };
    let by_edges = edge_circle(&edges, w, h, name);
    match (segmented, by_edges) {
        (Ok(disk), Ok(Some(e))) => {
            let own = edges::support(&edges, &disk, w, h);
            Ok(if e.seen_in_frame > own.seen_in_frame + BETTER_BY {
                Located { disk: e.disk, outline: Outline::Edges, seen: e.seen }
            } else {
                Located { disk, outline: Outline::Background, seen: own.seen }
            })
        }
        (Ok(disk), _) => Ok(Located { disk, outline: Outline::Background, seen: edges::support(&edges, &disk, w, h).seen }),
        (Err(_), Ok(Some(e))) if !(square && near(&e.disk, &inscribed, MATCAP_MATCH)) => Ok(Located { disk: e.disk, outline: Outline::Edges, seen: e.seen }),
        (Err(_), Err(two)) => Err(two),
        (Err(_), _) if square => Ok(Located { disk: inscribed, outline: Outline::Inscribed, seen: edges::support(&edges, &inscribed, w, h).seen }),
        (Err(e), _) => Err(e),
    }
}

/// Where the sphere is: a circle fitted to the alpha channel when the picture has one, or
/// else to what is not background (the pixels like the border's median colour, split by
/// Otsu's threshold, that connect to the border), or, where that is not round (a sphere on
/// a table with its shadow, on a textured background), to the arc of the outline the edges
/// show ([`edges`]); a square picture without a clear outline is taken as a MatCap, whose
/// disk is inscribed in it. Errors, one line each: the picture is all background, no round
/// shape, two shapes.
pub fn find_disk(p: &Painting, name: &str) -> Result<(Disk, Outline)> {
    locate(p, name).map(|l| (l.disk, l.outline))
}

/// The circle the picture's edges support best, if it shows at least [`MIN_SEEN`] of its
/// outline inside the frame. Error: two disjoint circles both that well supported.
fn edge_circle(edges: &[edges::Edge], w: usize, h: usize, name: &str) -> Result<Option<edges::Support>> {
    // A sphere is at least a tenth of the picture's shorter side (smaller ones are not
    // exemplars), and may be cut by the frame: up to the longer side across.
    let (r_min, r_max) = ((w.min(h) as f64 / 10.0).max(4.0), w.max(h) as f64 / 2.0);
    let good: Vec<edges::Support> = edges::circles(edges, w, h, r_min, r_max)
        .into_iter()
        .filter(|s| s.seen_in_frame >= MIN_SEEN && edges::turning(edges, &s.disk) > STRAIGHT_TURNING)
        .collect();
    let Some(best) = good.first().copied() else { return Ok(None) };
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
    Ok(Some(best))
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
    if let Some(&(_, other)) = components.iter().filter(|c| c.0 != largest).max_by_key(|c| c.1) {
        if other * 5 > area {
            return Err(Error::input(format!(
                "{name}: two shapes ({area} and {other} pixels): give a picture of one sphere"
            )));
        }
    }
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
    if !(0.8..=1.1).contains(&(area as f64 / circle_area)) || disk.r < 4.0 {
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

/// The scene of a lit-sphere picture of `width` × `height`: the unit sphere seen from +Z by
/// an orthographic camera that puts its outline on `disk`, lit by a white directional light
/// from `light` (towards the light, view frame = world frame).
pub fn scene(disk: &Disk, width: usize, height: usize, light: DVec3) -> Scene {
    let (w, h, r) = (width as f64, height as f64, disk.r);
    // Pixel centre (cx, cy) is the world origin; r pixels are one world unit.
    let (tx, ty) = (-(disk.cx - w / 2.0) / r, (disk.cy - h / 2.0) / r);
    let world_from_camera = Mat4::from_translation(Vec3::new(tx as f32, ty as f32, 5.0));
    let projection = Projection::Orthographic { xmag: (w / (2.0 * r)) as f32, ymag: (h / (2.0 * r)) as f32, znear: 0.1, zfar: 20.0 };
    let towards = light.normalize().as_vec3();
    Scene {
        meshes: vec![sphere_mesh(128, 64)],
        camera: Camera { world_from_camera, projection },
        light: Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 },
    }
}

/// Refuses a picture whose shorter side, shrunk to `max_side`, is under [`MIN_SIDE`]
/// pixels: no sphere fits in it (a 1000×1 strip, say).
fn check_shape(name: &str, width: usize, height: usize, max_side: usize) -> Result<()> {
    let shorter = width.min(height) / Shrink::factor(width, height, max_side);
    if shorter < MIN_SIDE {
        return Err(Error::input(format!(
            "{name} is {width}x{height}: too small or too narrow to hold a sphere (shrunk to at most {max_side} pixels a side, its shorter side is {shorter} pixels; a sphere needs {MIN_SIDE})"
        )));
    }
    Ok(())
}

/// `p` box-filtered so its longer side is at most `max_side` (alpha-weighted colours,
/// [`Shrink`]), and the factor it was shrunk by.
pub fn shrink(p: &Painting, max_side: usize) -> (Painting, usize) {
    let mut shrink = Shrink::new(p.width, p.height, max_side);
    if shrink.f() == 1 {
        return (p.clone(), 1);
    }
    let mut row = Vec::with_capacity(p.width);
    for j in 0..p.height {
        row.clear();
        let k = j * p.width;
        row.extend((k..k + p.width).map(|k| (p.pixels[k], p.alpha[k], p.saturated[k])));
        shrink.row(j, &row);
    }
    let f = shrink.f();
    (shrink.finish(), f)
}

/// Damping of the light factor's deviation from its physical shape in a lit-sphere fit
/// ([`settings`]).
pub const LIGHT_DAMP: f64 = 1e-3;
/// The floor of that shape behind the surface, a fraction of the picture's largest value,
/// unless the picture shows it ([`light_floor`]).
pub const LIGHT_FLOOR: f64 = crate::factor::defaults::LIGHT_FLOOR;

/// The light prior's floor for `picture` lit from `light`: under a light behind the sphere
/// more than half the disk faces away from it and shows that floor directly, lit by what is
/// not the key light (an environment's sky, a fill light), so the picture's own
/// ([`unlit_floor`]) when brighter than [`LIGHT_FLOOR`]; otherwise the picture shows it at
/// most at the terminator, and [`LIGHT_FLOOR`] keeps the material darkening when relit from
/// behind. A floor below the picture's would set the prior against the data on the whole
/// front, and the smoothing of that gap carries it into the lit side no light in the picture
/// reaches: relit from the front, such a material blew out to white.
pub fn light_floor(picture: &Picture, light: DVec3) -> f64 {
    if light.z >= 0.0 {
        return LIGHT_FLOOR;
    }
    unlit_floor(&picture.painting, &picture.disk, light.normalize()).map_or(LIGHT_FLOOR, |f| f.max(LIGHT_FLOOR))
}

/// The fit settings of a lit sphere: `base` with the light factor drawn to its physical
/// shape where the picture leaves it free ([`Settings::light_prior`], with first-difference
/// damping [`LIGHT_DAMP`] of its deviation from $\cos\theta_l$).
///
/// Why: a lit sphere is one view, often lit from near the viewer, and with the light at the
/// viewer every pixel has $\theta_l = \theta_h = \theta_v$: the picture fixes only the product
/// $p\,q\,r$ along that diagonal, and the priors split it. Left to the Laplacian, the split
/// is arbitrary: Blender's `check_rim_dark` MatCap (shading by $n \cdot v$ alone) had its rim
/// falloff in $q(\theta_h)$ and $p(\theta_l)$ rising towards grazing light, so its material
/// was brighter under a side light than under a front one. With the prior the falloff is the
/// light's, as irradiance is, and a light behind the surface finds the floor; where the
/// picture shows otherwise (a Gooch sphere's lit unlit side) the data win. Measured on the 23
/// bundled MatCaps under a light sweep around the bunny (tests/lit_sphere.rs).
pub fn settings(base: &Settings, floor: f64) -> Settings {
    base.with_light_prior(LIGHT_DAMP, floor)
}

/// A lit-sphere picture made ready to fit: read, box-filtered to at most a given side, its
/// disk found, and everything but the sphere (the background, and the rim, which mixes with
/// it) made unpainted. What `fit --lit-sphere` and the viewer's lit-sphere session start from.
#[derive(Clone, Debug)]
pub struct Picture {
    /// The file, as the user gave it (errors and provenance name it).
    pub name: String,
    pub painting: Painting,
    pub disk: Disk,
    pub outline: Outline,
    /// Share of the outline the picture shows ([`Located::seen`]).
    pub seen: f64,
    /// The file's pixels to one of `painting` (the factor it was shrunk by).
    pub scale: f64,
}

impl Picture {
    /// Reads the picture at `path` (PNG, JPEG, EXR) at most `max_side` pixels a side and
    /// finds its disk. Errors, one line each: unreadable, all background, no disk, two shapes.
    /// The picture is decoded and shrunk in passing (a 4096² PNG is never held at full
    /// size), and its shape checked from its header.
    pub fn read(path: &Path, max_side: usize) -> Result<Picture> {
        Picture::read_in(path, max_side, None)
    }

    /// [`Picture::read`], with the disk `given` by the user (pixels of the file as it is,
    /// before any shrinking) instead of found. Errors, one line: a disk that is not a circle
    /// of a few pixels or more on the picture.
    pub fn read_in(path: &Path, max_side: usize, given: Option<Disk>) -> Result<Picture> {
        let name = path.display().to_string();
        let max_side = max_side.max(MIN_SIDE);
        let (painting, f) = Painting::read_shrunk(path, max_side, |w, h| check_shape(&name, w, h, max_side))?;
        let located = match given {
            Some(d) => {
                let f = f as f64;
                given_disk(&painting, Disk { cx: d.cx / f, cy: d.cy / f, r: d.r / f }, d, &name)?
            }
            None => locate(&painting, &name)?,
        };
        Ok(Picture::found(name, painting, located, f as f64))
    }

    /// [`Picture::read`] of a painting already in memory, named `name`.
    pub fn new(name: String, original: &Painting, max_side: usize) -> Result<Picture> {
        let max_side = max_side.max(MIN_SIDE);
        check_shape(&name, original.width, original.height, max_side)?;
        let (painting, f) = shrink(original, max_side);
        let located = locate(&painting, &name)?;
        Ok(Picture::found(name, painting, located, f as f64))
    }

    /// The picture of an already shrunk painting with its disk: the rest unpainted.
    fn found(name: String, mut painting: Painting, located: Located, scale: f64) -> Picture {
        let Located { disk, outline, seen } = located;
        // Only the sphere is paint: the background (and the rim, which mixes with it) is not.
        for j in 0..painting.height {
            for i in 0..painting.width {
                if disk.normal(i, j, 0.98).is_none() {
                    painting.alpha[j * painting.width + i] = 0.0;
                }
            }
        }
        Picture { name, painting, disk, outline, seen, scale }
    }

    /// The note that reports the disk ([`Located::note`]).
    pub fn disk_note(&self) -> Note {
        self.located().note(&self.name, self.scale)
    }

    /// The located disk ([`Located`]).
    pub fn located(&self) -> Located {
        Located { disk: self.disk, outline: self.outline, seen: self.seen }
    }

    /// The key light estimated from the shading ([`estimate_light`]).
    pub fn estimate_light(&self) -> Result<LightEstimate> {
        estimate_light(&self.painting, &self.disk)
    }

    /// The scene of this picture lit from `light` ([`scene`]).
    pub fn scene(&self, light: DVec3) -> Scene {
        scene(&self.disk, self.painting.width, self.painting.height, light)
    }
}

/// The disk a user gave (`as_given`, in the file's pixels; `disk`, the same in the shrunk
/// `painting`'s), checked: a circle of at least 4 pixels whose inside is mostly in the picture.
fn given_disk(painting: &Painting, disk: Disk, as_given: Disk, name: &str) -> Result<Located> {
    let Disk { cx, cy, r } = as_given;
    let shown = format!("--disk {cx},{cy},{r}");
    if !(cx.is_finite() && cy.is_finite() && r.is_finite()) || r <= 0.0 {
        return Err(Error::input(format!("{shown}: the disk needs a centre X,Y and a radius above 0, in pixels")));
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
    let seen = edges::support(&edges::points(&perceptual_channels(painting), w, h), &disk, w, h).seen;
    Ok(Located { disk, outline: Outline::Given, seen })
}

/// `light` as a unit direction. Errors: zero or not finite (one line).
pub fn direction(light: DVec3) -> Result<DVec3> {
    if !(light.is_finite() && light.length() > 1e-9) {
        return Err(Error::input(format!("light {light}: not a direction")));
    }
    Ok(light.normalize())
}

/// A lit-sphere fit: the material and everything a caller reports or writes.
pub struct LitSphere {
    pub fitted: Fitted,
    pub view: PaintedView,
    /// The scene the picture was fitted in (MAT/scene.gltf).
    pub scene: Scene,
    pub disk: Disk,
    pub outline: Outline,
    /// Share of the outline the picture shows ([`Located::seen`]).
    pub seen: f64,
    /// `None` when the user gave the light.
    pub estimate: Option<LightEstimate>,
    pub light: DVec3,
    /// Physical or stylized, and why.
    pub stylization: Stylization,
}

impl LitSphere {
    /// Writes the material, its report and the scene it was fitted in (`scene.gltf`) into
    /// `out`, in one commit: the folder appears whole or not at all, the user's files in it
    /// are kept, and the picture at `image` is never removed even if it lies there.
    pub fn save(&self, image: &Path, out: &Path) -> Result<()> {
        let mut staged = self.fitted.stage(std::slice::from_ref(&self.view), out)?;
        staged.write("scene.gltf", |p| self.scene.write_gltf(p))?;
        staged.keep_inputs([image]);
        staged.commit()
    }
}

/// What a user asks of a lit-sphere fit, beyond the pipeline's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ask {
    /// Towards the light, view frame; estimated when `None`.
    pub light: Option<DVec3>,
    /// The outline, pixels of the file as it is; found when `None`.
    pub disk: Option<Disk>,
    /// The longest side the picture is fitted at (larger ones are box-filtered down).
    pub max_side: usize,
    pub style: Style,
    /// The user chose the tables' resolution or their smoothing: a stylized fit keeps it.
    pub res_given: bool,
    pub smooth_given: bool,
    /// Keep the painting's detail over the material (`--texture keep`, [`texture`]).
    pub keep_texture: bool,
}

impl Default for Ask {
    fn default() -> Self {
        Ask { light: None, disk: None, max_side: MAX_SIDE, style: Style::Auto, res_given: false, smooth_given: false, keep_texture: false }
    }
}

/// How a picture was read, physical or stylized, and why ([`style::tones`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stylization {
    pub asked: Style,
    pub stylized: bool,
    pub tones: style::Tones,
}

impl Stylization {
    /// How `picture` is read when `asked` ([`style::tones`] decides `auto`).
    pub fn decide(asked: Style, picture: &Picture) -> Stylization {
        let tones = style::tones(&picture.painting, &picture.disk);
        let stylized = match asked {
            Style::Physical => false,
            Style::Stylized => true,
            Style::Auto => tones.stylized(),
        };
        Stylization { asked, stylized, tones }
    }

    /// The fit settings from the user's `base` for `picture` lit from `light`: the lit-sphere
    /// rule ([`settings`], [`light_floor`]), or a stylized fit's ([`style::settings`];
    /// `res_given`, `smooth_given`: the user chose them).
    pub fn settings(&self, base: &Settings, picture: &Picture, light: DVec3, res_given: bool, smooth_given: bool) -> Settings {
        match self.stylized {
            false => settings(base, light_floor(picture, light)),
            true => {
                // A picture too small to read a lean from draws its highlight at h.
                let lean = highlight_lean(&picture.painting, &picture.disk, light).unwrap_or(1.0);
                style::settings(base, &picture.disk, lean, res_given, smooth_given)
            }
        }
    }

    /// The robust solve of a stylized fit ([`style::robust`]); least squares otherwise.
    pub fn robust(&self) -> Option<crate::factor::Robust> {
        self.stylized.then(style::robust)
    }

    /// The key light of `picture`: from its shading, or from its tone edges when stylized.
    pub fn estimate_light(&self, picture: &Picture) -> Result<LightEstimate> {
        match self.stylized {
            false => picture.estimate_light(),
            true => estimate_tone_light(&picture.painting, &picture.disk),
        }
    }

    /// The note that says how the picture was read.
    pub fn note(&self, picture: &str) -> Note {
        let t = self.tones;
        Note::Style { picture: picture.to_string(), stylized: self.stylized, decided: self.asked == Style::Auto, tones: t.count, share: t.share }
    }
}

/// Fits a material to a lit-sphere picture or MatCap at `path` (PNG, JPEG, EXR), lit from
/// `light` (view frame, towards the light) or from the estimated light.
pub fn fit(path: &Path, light: Option<DVec3>, opts: &Options, cache: Option<&Cache>) -> Result<LitSphere> {
    fit_in(path, &Ask { light, ..Ask::default() }, opts, cache)
}

/// [`fit`], with the picture box-filtered to at most `max_side` pixels a side.
pub fn fit_sized(path: &Path, light: Option<DVec3>, opts: &Options, cache: Option<&Cache>, max_side: usize) -> Result<LitSphere> {
    fit_in(path, &Ask { light, max_side, ..Ask::default() }, opts, cache)
}

/// [`fit`] as `ask` says: the disk given or found, the picture read physically or as drawn
/// ([`style`]), the light given or estimated (from the tone edges when stylized).
pub fn fit_in(path: &Path, ask: &Ask, opts: &Options, cache: Option<&Cache>) -> Result<LitSphere> {
    let picture = Picture::read_in(path, ask.max_side, ask.disk)?;
    let stylization = Stylization::decide(ask.style, &picture);
    let (light, estimate) = match ask.light {
        Some(l) => (direction(l).map_err(|e| Error::input(format!("--{e}")))?, None),
        None => {
            let e = stylization.estimate_light(&picture)?;
            (e.direction, Some(e))
        }
    };
    let opts = &Options {
        settings: stylization.settings(&opts.settings, &picture, light, ask.res_given, ask.smooth_given),
        robust: stylization.robust(),
        ..opts.clone()
    };
    let scene = picture.scene(light);
    let notes = [picture.disk_note(), stylization.note(&picture.name)];
    let Picture { name, painting, disk, outline, seen, .. } = picture;
    let mut sampler = SceneSampler::new()?;
    let geometry = sampler.geometry(&scene, painting.width, painting.height, Erosion::default())?;
    let view = PaintedView { name: name.clone(), source: format!("{name} (lit sphere)"), geometry, painting };
    let mut fitted = colours::fit(&view, opts, cache)?;
    // Where the disk is, how the picture was read and how sure the light is come first,
    // with the material's provenance.
    let undecided = estimate.filter(|e| e.undecided).map(|e| Note::LightUndecided { picture: name.clone(), spread_deg: e.spread_deg });
    let behind = estimate.filter(|e| e.behind).map(|_| Note::LightBehind { picture: name.clone() });
    fitted.prepend_notes(&notes.into_iter().chain(undecided).chain(behind).collect::<Vec<_>>());
    if ask.keep_texture {
        fitted.material.detail = Some(texture::detail(&view, &disk, &fitted.material));
    }
    Ok(LitSphere { fitted, view, scene, disk, outline, seen, estimate, light, stylization })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disk_picture(w: usize, h: usize, d: Disk, soft: f64, bg: [f32; 3], alpha: bool) -> Painting {
        let mut p = Painting::opaque(w, h, vec![bg; w * h]).unwrap();
        for j in 0..h {
            for i in 0..w {
                let dist = ((i as f64 + 0.5 - d.cx).powi(2) + (j as f64 + 0.5 - d.cy).powi(2)).sqrt();
                let cover = ((d.r - dist) / soft.max(1e-3) + 0.5).clamp(0.0, 1.0) as f32;
                let k = j * w + i;
                let c = [0.8, 0.3, 0.2];
                if alpha {
                    p.alpha[k] = cover;
                    p.pixels[k] = c;
                } else {
                    p.pixels[k] = [0, 1, 2].map(|ch| c[ch] * cover + bg[ch] * (1.0 - cover));
                }
            }
        }
        p
    }

    #[test]
    fn finds_off_centre_scaled_soft_disks_on_white_and_on_transparent() {
        for (w, h, d, soft, alpha) in [
            (200, 160, Disk { cx: 70.3, cy: 90.1, r: 50.0 }, 1.0, false),
            (300, 300, Disk { cx: 150.0, cy: 150.0, r: 140.0 }, 4.0, false),
            (120, 200, Disk { cx: 60.0, cy: 120.5, r: 33.3 }, 2.0, true),
        ] {
            let p = disk_picture(w, h, d, soft, [1.0; 3], alpha);
            let (found, _) = find_disk(&p, "test").unwrap();
            assert!((found.cx - d.cx).abs() < 1.0 && (found.cy - d.cy).abs() < 1.0, "{found:?} vs {d:?}");
            assert!((found.r - d.r).abs() < 1.0, "{found:?} vs {d:?}");
        }
    }

    /// A hard alpha cut (alpha 1 where the disk covers the pixel centre) gives the radius
    /// to a tenth of a pixel: the inside centres alone read it half a pixel short.
    #[test]
    fn a_hard_alpha_cut_gives_the_radius_unbiased() {
        for d in [Disk { cx: 128.0, cy: 128.0, r: 128.0 }, Disk { cx: 90.3, cy: 101.7, r: 61.2 }, Disk { cx: 40.5, cy: 40.5, r: 20.4 }] {
            let p = disk_picture(256, 256, d, 1e-6, [0.0; 3], true);
            let (found, _) = find_disk(&p, "test").unwrap();
            assert!((found.r - d.r).abs() < 0.1, "{found:?} vs {d:?}");
            assert!((found.cx - d.cx).abs() < 0.1 && (found.cy - d.cy).abs() < 0.1, "{found:?} vs {d:?}");
        }
    }

    #[test]
    fn refuses_background_two_disks_and_non_round_shapes() {
        let blank = Painting::opaque(64, 64, vec![[0.5; 3]; 64 * 64]).unwrap();
        assert!(find_disk(&blank, "b.png").unwrap_err().to_string().contains("all background"));
        let mut two = disk_picture(200, 100, Disk { cx: 50.0, cy: 50.0, r: 30.0 }, 1.0, [0.0; 3], false);
        let other = disk_picture(200, 100, Disk { cx: 150.0, cy: 50.0, r: 30.0 }, 1.0, [0.0; 3], false);
        for (a, b) in two.pixels.iter_mut().zip(&other.pixels) {
            *a = [0, 1, 2].map(|c| a[c].max(b[c]));
        }
        assert!(find_disk(&two, "t.png").unwrap_err().to_string().contains("two shapes"));
        // (Not square: a square picture without a clear outline is taken as a MatCap.)
        let mut square = Painting::opaque(120, 100, vec![[0.0; 3]; 120 * 100]).unwrap();
        for j in 20..80 {
            for i in 20..80 {
                square.pixels[j * 120 + i] = [0.9; 3];
            }
        }
        assert!(find_disk(&square, "s.png").unwrap_err().to_string().contains("no disk"));
    }

    #[test]
    fn kasa_recovers_a_circle_from_three_points() {
        let d = kasa(&[glam::DVec2::new(1.0, 0.0), glam::DVec2::new(-1.0, 0.0), glam::DVec2::new(0.0, 1.0)]).unwrap();
        assert!(d.cx.abs() < 1e-9 && d.cy.abs() < 1e-9 && (d.r - 1.0).abs() < 1e-9, "{d:?}");
    }
}
