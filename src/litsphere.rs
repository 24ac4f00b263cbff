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

use glam::{DVec3, Mat4, Vec3};

use crate::error::{Error, Result};
use crate::factor::cache::Cache;
use crate::factor::Settings;
use crate::images::{Painting, Shrink};
use crate::note::{DiskFrom, Note};
use crate::pipeline::{Fitted, Options};
use crate::scene::{sphere_mesh, Camera, Light, Projection, Scene};
use crate::sample::{Erosion, PaintedView, SceneSampler};

pub mod colours;
pub mod edges;
mod light;
mod locate;
pub mod occluder;
mod segment;
pub mod style;
pub mod texture;

pub use light::{estimate_light, estimate_tone_light, highlight_lean, light_size, unlit_floor, LightEstimate, ENVIRONMENT_KEY_DEG, KEY, MIN_LIGHT_Z, UNDECIDED_DEG};
pub use locate::{find_disk, locate, MIN_SEEN};
pub use style::Style;
use locate::given_disk;

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
    /// The best circle on the picture's edges where none shows a clear arc (less than
    /// [`MIN_SEEN`] of its outline, at least [`locate::MIN_FAINT`]): to be checked.
    Faint,
    /// A square picture without a clearly other outline: the disk inscribed in it, as in
    /// every MatCap.
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
        let from = match self.outline {
            Outline::Given => DiskFrom::Given,
            Outline::Faint => DiskFrom::Faint,
            Outline::Alpha | Outline::Background | Outline::Edges | Outline::Inscribed => DiskFrom::Found,
        };
        Note::Disk { picture: name.to_string(), cx: d.cx * scale, cy: d.cy * scale, r: d.r * scale, seen: self.seen, from }
    }
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

/// The light prior's floor for a picture lit from `light` whose unlit side shows `unlit`
/// ([`unlit_floor`]): under a light behind the sphere
/// more than half the disk faces away from it and shows that floor directly, lit by what is
/// not the key light (an environment's sky, a fill light), so the picture's own when
/// brighter than [`LIGHT_FLOOR`]; otherwise the picture shows it at
/// most at the terminator, and [`LIGHT_FLOOR`] keeps the material darkening when relit from
/// behind. A floor below the picture's would set the prior against the data on the whole
/// front, and the smoothing of that gap carries it into the lit side no light in the picture
/// reaches: relit from the front, such a material blew out to white.
pub fn light_floor(light: DVec3, unlit: f64) -> f64 {
    if light.z >= 0.0 {
        return LIGHT_FLOOR;
    }
    unlit.max(LIGHT_FLOOR)
}

/// The fit settings of a lit sphere: `base` with the light factor drawn to its physical
/// shape where the picture leaves it free ([`Settings::light_prior`], with first-difference
/// damping [`LIGHT_DAMP`] of its deviation from the irradiance of a key light of angular
/// radius `light_radius_deg`, [`light_size`]).
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
pub fn settings(base: &Settings, floor: f64, light_radius_deg: f64) -> Settings {
    Settings { light_radius_deg, ..base.with_light_prior(LIGHT_DAMP, floor) }
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
    /// The disk's pixels left out as something in front of the sphere ([`occluder`]).
    pub hidden: Option<Hidden>,
}

/// Pixels of a disk hidden by something in front of the sphere, and their share of the disk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hidden {
    /// The top edge of the thing in front.
    pub line: occluder::InFront,
    pub pixels: usize,
    pub share: f64,
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
        let (located, in_front) = match given {
            Some(d) => {
                let f = f as f64;
                given_disk(&painting, Disk { cx: d.cx / f, cy: d.cy / f, r: d.r / f }, d, &name)?
            }
            None => locate::locate_in_front(&painting, &name)?,
        };
        Ok(Picture::found(name, painting, located, in_front, f as f64))
    }

    /// [`Picture::read`] of a painting already in memory, named `name`.
    pub fn new(name: String, original: &Painting, max_side: usize) -> Result<Picture> {
        let max_side = max_side.max(MIN_SIDE);
        check_shape(&name, original.width, original.height, max_side)?;
        let (painting, f) = shrink(original, max_side);
        let (located, in_front) = locate::locate_in_front(&painting, &name)?;
        Ok(Picture::found(name, painting, located, in_front, f as f64))
    }

    /// The picture of an already shrunk painting with its disk: the rest, and what stands
    /// `in_front` of the sphere, unpainted.
    fn found(name: String, mut painting: Painting, located: Located, in_front: Option<occluder::InFront>, scale: f64) -> Picture {
        let Located { disk, outline, seen } = located;
        // Only the sphere is paint: the background (and the rim, which mixes with it) and
        // what stands in front of it are not.
        let (mut inside, mut hidden) = (0, 0);
        for j in 0..painting.height {
            for i in 0..painting.width {
                let k = j * painting.width + i;
                if disk.normal(i, j, 0.98).is_none() {
                    painting.alpha[k] = 0.0;
                    continue;
                }
                inside += 1;
                if in_front.is_some_and(|f| f.hides(glam::DVec2::new(i as f64 + 0.5, j as f64 + 0.5))) {
                    painting.alpha[k] = 0.0;
                    hidden += 1;
                }
            }
        }
        let hidden = in_front.filter(|_| hidden > 0).map(|line| Hidden { line, pixels: hidden, share: hidden as f64 / inside.max(1) as f64 });
        Picture { name, painting, disk, outline, seen, scale, hidden }
    }

    /// The note on what stands in front of the sphere, if anything does ([`occluder`]).
    pub fn in_front_note(&self) -> Option<Note> {
        self.hidden.map(|h| Note::InFront { picture: self.name.clone(), pixels: h.pixels, share: h.share })
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

/// How a picture was read, physical or stylized, and why ([`style::tones`],
/// [`style::profile`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stylization {
    pub asked: Style,
    pub stylized: bool,
    /// The disk's flat tones, pixel by pixel.
    pub tones: style::Tones,
    /// Where those are not a drawing's (a painted one's strokes and grain scatter its tones),
    /// its shading profile under the light its tone edges set, and that light, when the
    /// profile is a drawing's ([`style::Profile::drawn`]): they decided `auto`.
    pub painted: Option<(style::Profile, LightEstimate)>,
}

impl Stylization {
    /// How `picture` is read when `asked`: `auto` is stylized when its pixels are a few flat
    /// tones ([`style::tones`]), or else, in a painted picture ([`style::grain`]), its shading
    /// profile is a drawing's ([`style::profile`]).
    pub fn decide(asked: Style, picture: &Picture) -> Stylization {
        let tones = style::tones(&picture.painting, &picture.disk);
        let painted = || {
            let light = estimate_tone_light(&picture.painting, &picture.disk).ok()?;
            let profile = style::profile(&picture.painting, &picture.disk, light.direction);
            profile.drawn().then_some((profile, light))
        };
        let (stylized, painted) = match asked {
            Style::Physical => (false, None),
            Style::Stylized => (true, None),
            Style::Auto if tones.stylized() => (true, None),
            // A clean picture's tones are read pixel by pixel: it has no paint to see through.
            Style::Auto if style::grain(&picture.painting, &picture.disk) <= style::CLEAN_GRAIN => (false, None),
            Style::Auto => painted().map_or((false, None), |p| (true, Some(p))),
        };
        Stylization { asked, stylized, tones, painted }
    }

    /// The fit settings from the user's `base` for `picture` lit from `light`: the lit-sphere
    /// rule ([`settings`], [`light_floor`]), or a stylized fit's ([`style::settings`];
    /// `res_given`, `smooth_given`: the user chose them).
    pub fn settings(&self, base: &Settings, picture: &Picture, light: DVec3, res_given: bool, smooth_given: bool) -> Settings {
        match self.stylized {
            false => {
                // What the unlit side shows sets both the floor and the key light's size; a
                // picture whose shading cannot be read shows nothing there.
                let unlit = unlit_floor(&picture.painting, &picture.disk, light.normalize()).unwrap_or(0.0);
                settings(base, light_floor(light, unlit), light_size(unlit, LIGHT_FLOOR))
            }
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
        match (self.stylized, self.painted) {
            (false, _) => picture.estimate_light(),
            (true, Some((_, light))) => Ok(light),
            (true, None) => estimate_tone_light(&picture.painting, &picture.disk),
        }
    }

    /// The note that says how the picture was read.
    pub fn note(&self, picture: &str) -> Note {
        let (t, painted) = self.painted.map_or((self.tones, false), |(p, _)| (p.tones, true));
        Note::Style { picture: picture.to_string(), stylized: self.stylized, decided: self.asked == Style::Auto, tones: t.count, share: t.share, painted }
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
    let notes: Vec<Note> = [Some(picture.disk_note()), picture.in_front_note(), Some(stylization.note(&picture.name))].into_iter().flatten().collect();
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

    /// A two-tone sphere lit from the side, whose terminator band is a straight chord, on a
    /// wall above a table whose edge passes behind it; and with a box in front of it.
    fn side_lit_toon(box_from: Option<f64>) -> Painting {
        let (w, h) = (300, 240);
        let d = Disk { cx: 150.0, cy: 110.0, r: 80.0 };
        let px = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let y = j as f64 + 0.5;
                if box_from.is_some_and(|b| y > b) {
                    return [0.1, 0.15, 0.3];
                }
                match d.normal(i, j, 1.0) {
                    // n·l with the light along +x: the band's edge is the chord x = 0.3 r.
                    Some(n) => if n.x > 0.3 { [0.8, 0.3, 0.2] } else { [0.25, 0.08, 0.05] },
                    None if y < 150.0 => [0.7, 0.7, 0.65],
                    None => [0.4, 0.3, 0.2],
                }
            })
            .collect();
        Painting::opaque(w, h, px).unwrap()
    }

    #[test]
    fn a_box_in_front_is_left_out_and_a_straight_terminator_is_not() {
        let alone = Picture::new("toon.png".into(), &side_lit_toon(None), MAX_SIDE).unwrap();
        assert!(alone.hidden.is_none(), "{:?}", alone.hidden);
        let hidden = Picture::new("boxed.png".into(), &side_lit_toon(Some(160.0)), MAX_SIDE).unwrap();
        let h = hidden.hidden.expect("the box is found");
        // The box's top, y = 160: the line n·p = offset with n pointing down, level.
        let y = (h.line.offset - 150.0 * h.line.normal.x) / h.line.normal.y;
        assert!(h.line.normal.y > 0.9999 && (y - 160.0).abs() < 0.5, "{h:?}");
        assert!(h.line.hides(glam::DVec2::new(150.0, 165.0)) && !h.line.hides(glam::DVec2::new(150.0, 150.0)), "{h:?}");
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
        // A gradient splits at its middle tone into two large pieces; neither is a sphere.
        for (w, h) in [(320, 200), (200, 320)] {
            let ramp = (0..w * h).map(|k| [((k % w) as f32 / w as f32).powi(2); 3]).collect();
            let e = find_disk(&Painting::opaque(w, h, ramp).unwrap(), "g.png").unwrap_err().to_string();
            assert!(e.contains("no disk") && !e.contains("two shapes"), "{w}x{h}: {e}");
        }
    }
}
