//! Colours a material invents (issue 35; DESIGN.md: rendered colours stay within the
//! picture's own colours under any light).
//!
//! One measure: the fraction of an object's lit pixels whose rg-chromaticity
//! $(r, g) = (R, G) / (R + G + B)$ is farther than [`TOLERANCE`] from every chromaticity of
//! the painting. "Lit" is brighter than [`FLOOR`] × the frame's brightest pixel (Rec. 709
//! luminance): below that a hue is invisible, and a rendered zero has none. A material
//! invents colours when more than [`INVENTED`] of the pixels are such.
//!
//! [`sweep`] measures it on the bunny under the picture's key light and under a white light
//! moved around the vertical axis in 8 steps (the darkest frame is the one that shows what
//! the painting did not say), as `tests/colour.rs` and `examples/colours.rs` do.

use glam::Vec3;

use crate::error::Result;
use crate::images::Painting;
use crate::render::{GpuScene, GpuShading, Image, Renderer};
use crate::scene::Light;

/// Chromaticity distance under which a rendered colour counts as the painting's (issue 35's
/// tolerance): a warm grey (0.55, 0.5, 0.45) is 0.034 from grey, an orange-grey (0.6, 0.45,
/// 0.3) 0.11 (the unit tests below).
pub const TOLERANCE: f64 = 0.05;
/// Pixels darker than this fraction of the frame's brightest are not judged.
pub const FLOOR: f64 = 0.02;
/// A material invents colours when more than this fraction of its lit pixels are off the
/// painting's chromaticities.
pub const INVENTED: f64 = 0.05;
/// Frames of the light sweep.
pub const FRAMES: usize = 8;

/// Cells per axis of the chromaticity grid: cells of 0.005, so a distance is judged to
/// within a cell's diagonal, 0.007, a seventh of the tolerance.
const GRID: usize = 200;

/// Rec. 709 luminance of linear RGB.
pub fn luminance(p: [f64; 3]) -> f64 {
    crate::factor::chroma::LUMA.iter().zip(p).map(|(w, x)| w * x).sum()
}

/// rg-chromaticity of a colour; `None` for black (no hue).
pub fn chromaticity(p: [f64; 3]) -> Option<[f64; 2]> {
    let sum = p[0].max(0.0) + p[1].max(0.0) + p[2].max(0.0);
    (sum > 0.0 && sum.is_finite()).then(|| [p[0].max(0.0) / sum, p[1].max(0.0) / sum])
}

fn cell(rg: [f64; 2]) -> (usize, usize) {
    let at = |x: f64| ((x * GRID as f64) as usize).min(GRID - 1);
    (at(rg[0]), at(rg[1]))
}

/// The chromaticities of a painting, and every chromaticity within [`TOLERANCE`] of one.
#[derive(Clone, Debug)]
pub struct Palette {
    near: Vec<bool>,
    /// Distinct grid cells the painting's colours fall in.
    pub cells: usize,
}

impl Palette {
    /// The chromaticities of `colours` brighter than [`FLOOR`] × the brightest.
    pub fn new(colours: &[[f64; 3]]) -> Palette {
        let top = colours.iter().map(|&p| luminance(p)).fold(0.0, f64::max);
        let mut own = vec![false; GRID * GRID];
        for &p in colours.iter().filter(|&&p| luminance(p) > FLOOR * top) {
            if let Some(rg) = chromaticity(p) {
                let (i, j) = cell(rg);
                own[j * GRID + i] = true;
            }
        }
        let reach = (TOLERANCE * GRID as f64) as isize;
        let mut near = vec![false; GRID * GRID];
        let mut cells = 0;
        for j in 0..GRID {
            for i in (0..GRID).filter(|&i| own[j * GRID + i]) {
                cells += 1;
                for dj in -reach..=reach {
                    for di in -reach..=reach {
                        let (x, y) = (i as isize + di, j as isize + dj);
                        if di * di + dj * dj <= reach * reach && (0..GRID as isize).contains(&x) && (0..GRID as isize).contains(&y) {
                            near[y as usize * GRID + x as usize] = true;
                        }
                    }
                }
            }
        }
        Palette { near, cells }
    }

    /// The palette of a painting's painted pixels (alpha above zero).
    pub fn of_painting(p: &Painting) -> Palette {
        let colours: Vec<[f64; 3]> =
            p.pixels.iter().zip(&p.alpha).filter(|(_, &a)| a > 0.0).map(|(c, _)| c.map(|x| x as f64)).collect();
        Palette::new(&colours)
    }

    /// Whether `rg` is within [`TOLERANCE`] of the painting's chromaticities.
    pub fn holds(&self, rg: [f64; 2]) -> bool {
        let (i, j) = cell(rg);
        self.near[j * GRID + i]
    }

    /// The fraction of `image`'s object pixels (alpha 1) brighter than [`FLOOR`] × the
    /// frame's brightest whose chromaticity the palette does not hold (0 for a black frame).
    pub fn invented(&self, image: &Image) -> f64 {
        let object: Vec<[f64; 3]> = image.pixels.iter().filter(|p| p[3] >= 1.0).map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect();
        let top = object.iter().map(|&p| luminance(p)).fold(0.0, f64::max);
        let lit: Vec<[f64; 2]> = object.iter().filter(|&&p| luminance(p) > FLOOR * top).filter_map(|&p| chromaticity(p)).collect();
        if lit.is_empty() {
            return 0.0;
        }
        lit.iter().filter(|&&rg| !self.holds(rg)).count() as f64 / lit.len() as f64
    }
}

/// Mean luminance of an image's object pixels.
pub fn object_luminance(image: &Image) -> f64 {
    let (sum, n) = image.pixels.iter().filter(|p| p[3] >= 1.0).fold((0.0, 0usize), |(s, n), p| (s + luminance([p[0] as f64, p[1] as f64, p[2] as f64]), n + 1));
    sum / n.max(1) as f64
}

/// What [`sweep`] measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    /// Invented fraction under the key light.
    pub key: f64,
    /// Invented fraction in the sweep's darkest frame.
    pub darkest: f64,
    /// The darkest frame's mean luminance over the brightest's.
    pub darkest_over_brightest: f64,
}

impl Sweep {
    /// The larger of the two invented fractions.
    pub fn worst(&self) -> f64 {
        self.key.max(self.darkest)
    }
}

/// Renders `shading` in `scene` (`size`² pixels) under a white light towards `key` (world
/// space) and then from [`FRAMES`] directions around the vertical axis, starting at the
/// camera; measures the invented fraction of the key frame and of the darkest sweep frame.
pub fn sweep(renderer: &mut Renderer, scene: &mut GpuScene, shading: &GpuShading, palette: &Palette, key: Vec3, size: usize) -> Result<Sweep> {
    let light = |towards: Vec3| Light::Directional { direction: -towards.normalize(), color: Vec3::ONE, intensity: 1.0 };
    scene.light = light(key);
    let key = palette.invented(&renderer.factored(scene, shading, size, size)?);
    let view = scene.camera.forward();
    let mut frames = Vec::with_capacity(FRAMES);
    for k in 0..FRAMES {
        let a = std::f32::consts::TAU * k as f32 / FRAMES as f32;
        scene.light = light(glam::Quat::from_rotation_y(a) * -view);
        let image = renderer.factored(scene, shading, size, size)?;
        frames.push((object_luminance(&image), palette.invented(&image)));
    }
    let (dark, _) = frames.iter().enumerate().min_by(|a, b| a.1 .0.total_cmp(&b.1 .0)).unwrap_or((0, &(0.0, 0.0)));
    let brightest = frames.iter().map(|f| f.0).fold(0.0, f64::max);
    Ok(Sweep { key, darkest: frames[dark].1, darkest_over_brightest: frames[dark].0 / brightest.max(f64::MIN_POSITIVE) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grey_palette_holds_greys_and_not_orange() {
        let p = Palette::new(&[[0.5, 0.5, 0.5], [0.1, 0.1, 0.1], [0.0, 0.0, 0.0]]);
        assert_eq!(p.cells, 1);
        assert!(p.holds(chromaticity([0.3, 0.3, 0.3]).unwrap()));
        // rg of (0.55, 0.5, 0.45) is (0.367, 0.333): 0.034 from grey's (1/3, 1/3).
        assert!(p.holds(chromaticity([0.55, 0.5, 0.45]).unwrap()));
        // rg of (0.6, 0.45, 0.3) is (0.444, 0.333): 0.11 from grey.
        assert!(!p.holds(chromaticity([0.6, 0.45, 0.3]).unwrap()));
    }

    #[test]
    fn dark_pixels_are_not_judged() {
        let p = Palette::new(&[[0.5, 0.5, 0.5]]);
        let px = |c: [f32; 3]| [c[0], c[1], c[2], 1.0];
        // One blue pixel at 1% of the brightest, one grey: nothing invented.
        let image = Image { width: 2, height: 1, pixels: vec![px([1.0; 3]), px([0.0, 0.0, 0.01 / 0.0722 * 0.99])] };
        assert_eq!(p.invented(&image), 0.0);
        let image = Image { width: 2, height: 1, pixels: vec![px([1.0; 3]), px([0.0, 0.0, 1.0])] };
        assert_eq!(p.invented(&image), 0.5);
    }
}
