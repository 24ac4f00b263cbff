//! A picture's colours, and the colours a material invents beyond them (issue 35; DESIGN.md:
//! rendered colours stay within the picture's own colours under any light).
//!
//! One measure: the fraction of an object's lit pixels whose rg-chromaticity
//! $(r, g) = (R, G) / (R + G + B)$ is farther than [`TOLERANCE`] from every chromaticity of
//! the painting. "Lit" is brighter than [`FLOOR`] × the brightest pixel (Rec. 709
//! luminance): below that a hue is invisible, and a rendered zero has none. A material
//! invents colours when more than [`INVENTED`] of the pixels are such.

use super::{luminance, Painting};

/// Chromaticity distance under which a rendered colour counts as the painting's (issue 35's
/// tolerance): a warm grey (0.55, 0.5, 0.45) is 0.034 from grey, an orange-grey (0.6, 0.45,
/// 0.3) 0.11 (the unit tests below).
pub const TOLERANCE: f64 = 0.05;
/// Pixels darker than this fraction of the brightest are not judged.
pub const FLOOR: f64 = 0.02;
/// A material invents colours when more than this fraction of its lit pixels are off the
/// painting's chromaticities.
pub const INVENTED: f64 = 0.05;
/// Frames of a light sweep around the vertical axis (`study::colour::sweep`, `litsphere::colours`).
pub const FRAMES: usize = 8;

/// Cells per axis of the chromaticity grid: cells of 0.005, so a distance is judged to
/// within a cell's diagonal, 0.007, a seventh of the tolerance.
const GRID: usize = 200;

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

    /// The fraction of an object's pixel colours `object` brighter than [`FLOOR`] × the
    /// brightest whose chromaticity the palette does not hold (0 for a black object).
    pub fn invented_among(&self, object: &[[f64; 3]]) -> f64 {
        let top = object.iter().map(|&p| luminance(p)).fold(0.0, f64::max);
        self.invented_above(object, FLOOR * top)
    }

    /// The fraction of `object`'s colours brighter than `floor` (Rec. 709 luminance) whose
    /// chromaticity the palette does not hold (0 when none is that bright).
    pub fn invented_above(&self, object: &[[f64; 3]], floor: f64) -> f64 {
        let lit: Vec<[f64; 2]> = object.iter().filter(|&&p| luminance(p) > floor).filter_map(|&p| chromaticity(p)).collect();
        if lit.is_empty() {
            return 0.0;
        }
        lit.iter().filter(|&&rg| !self.holds(rg)).count() as f64 / lit.len() as f64
    }
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
        // One blue pixel at 1% of the brightest, one grey: nothing invented.
        assert_eq!(p.invented_among(&[[1.0; 3], [0.0, 0.0, 0.01 / 0.0722 * 0.99]]), 0.0);
        assert_eq!(p.invented_among(&[[1.0; 3], [0.0, 0.0, 1.0]]), 0.5);
    }
}
