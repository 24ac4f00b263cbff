//! Sampling: paintings and photographs of a known geometry become samples of the shading
//! function (thesis 4.1, 4.4).
//!
//! Every pixel of a view has a geometry: where it sees the object, the light and view
//! directions in the local shading frame, the surface's uv, and how much light arrives
//! there. A painting (or photograph) of the view gives the pixel's colour. A pixel is a
//! sample when it sees a front-facing surface ($v_z > 0$), lies off the eroded silhouette
//! band (DESIGN.md: silhouette pixels mix object and background paint) and is painted
//! (alpha > 0). Its value is the shading function
//!
//! $$ S(l, v) = \frac{\text{pixel}}{E}, \qquad E = \text{colour} \times \text{intensity}
//! \times \text{falloff} $$
//!
//! with the falloff $1/d^2$ for point lights (DESIGN.md, Shading function).
//!
//! Two geometry sources:
//! - [`scene`]: a glTF scene rasterized by the renderer's G-buffer, exactly the pixels the
//!   outline and reference passes cover ([`SceneSampler`]);
//! - [`photo`]: a photograph with known normals, no mesh: a normal map, a mask, and one
//!   image per directional light ([`Photo`]); [`photoset`] reads them pair by pair or as a
//!   photometric-stereo folder ([`PhotoInput`]).
//!
//! Several views concatenate into one pattern ([`Samples::gather`], thesis 4.4). The
//! pattern depends only on the geometry and the alpha mask, never on the colours, so a
//! repainted view of the same scene reuses its prepared system ([`crate::pipeline::solve`],
//! through [`crate::factor::cache`]).
//!
//! ```no_run
//! use brdfpaint::sample::{PaintedView, Samples, SceneSampler, Erosion};
//! use brdfpaint::factor::{cache::Cache, Mapping, Settings};
//! use brdfpaint::pipeline::solve;
//! use std::path::Path;
//!
//! let mut sampler = SceneSampler::new()?;
//! let (_scene, view) = sampler.load_view(Path::new("scene.gltf"), Path::new("painting.png"), Erosion::default())?;
//! let samples = Samples::gather(&[view])?;
//! let fitted = solve(&samples, &Settings::default(), Mapping::Auto, Cache::user().as_ref())?;
//! println!("relative RMS on the samples: {}", fitted.fit.errors.rms_relative);
//! # Ok::<(), brdfpaint::Error>(())
//! ```

pub mod page;
pub mod photo;
pub mod photoset;
pub mod report;
pub mod scene;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::factor::{Pattern, Query};
use crate::images::Painting;
use crate::material::map::Grid;

pub use photo::{Encoding, LeftOut, MapFrame, NormalMap, Photo, PhotoCamera, PhotoLight};
pub use photoset::{PhotoFolder, PhotoInput, Photographs, Shot};
pub use scene::{check_aspect, check_same_model, SceneSampler};

/// Which neighbours of a pixel count when eroding the silhouette band.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Neighbours {
    /// Left, right, up, down.
    Four,
    /// The four and the diagonals (the default).
    #[default]
    Eight,
}

/// Silhouette erosion: a pixel within `radius` steps of a background pixel (one that does
/// not see the object, or lies outside the image) is not a sample. Radius 0 keeps every
/// pixel that sees the object. The default is 1 px over 8 neighbours: a pixel any of
/// whose 8 neighbours is background is dropped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Erosion {
    pub radius: usize,
    pub neighbours: Neighbours,
}

impl Default for Erosion {
    fn default() -> Self {
        Erosion { radius: 1, neighbours: Neighbours::Eight }
    }
}

impl Erosion {
    /// No erosion.
    pub const NONE: Erosion = Erosion { radius: 0, neighbours: Neighbours::Eight };

    /// Which pixels of a `width` × `height` grid survive: `object` pixels further than
    /// `radius` steps from every background pixel and from the image's edge.
    pub fn apply(&self, object: &[bool], width: usize, height: usize) -> Vec<bool> {
        let mut keep = object.to_vec();
        for _ in 0..self.radius {
            let prev = keep.clone();
            let at = |i: isize, j: isize| -> bool {
                i >= 0 && j >= 0 && (i as usize) < width && (j as usize) < height && prev[j as usize * width + i as usize]
            };
            for j in 0..height as isize {
                for i in 0..width as isize {
                    let k = j as usize * width + i as usize;
                    if !prev[k] {
                        continue;
                    }
                    let four = at(i - 1, j) && at(i + 1, j) && at(i, j - 1) && at(i, j + 1);
                    let eight = four
                        && (self.neighbours == Neighbours::Four
                            || at(i - 1, j - 1) && at(i + 1, j - 1) && at(i - 1, j + 1) && at(i + 1, j + 1));
                    keep[k] = eight;
                }
            }
        }
        keep
    }
}

/// The geometry of one pixel that sees a front-facing surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelGeometry {
    /// Light and view directions in the local frame, and uv.
    pub query: Query,
    /// World position of the surface point (scenes); `None` for photographs.
    pub position: Option<DVec3>,
    /// What the light delivers here, per channel: colour × intensity × falloff. A pixel
    /// value divided by it is the shading function $S$.
    pub light: [f64; 3],
}

/// The geometry of one view: per pixel, what it sees. Pattern-only: no colours.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    pub width: usize,
    pub height: usize,
    /// Row by row, row 0 at the top: the geometry where the pixel centre sees a
    /// front-facing surface ($v_z > 0$); `None` for background and back-facing pixels.
    pub pixels: Vec<Option<PixelGeometry>>,
    /// Pixels that may be samples: they see the object and survive the erosion, and were
    /// not left out while the painting was read.
    pub usable: Vec<bool>,
    /// How many of the pixels that survive the erosion were left out while the painting was
    /// read (stray strokes in flat tones: [`crate::read::Reader::read`]).
    pub left_out: usize,
    /// Whether the queries carry meaningful texture coordinates.
    pub has_uv: bool,
}

impl Geometry {
    /// Number of usable pixels.
    pub fn usable_count(&self) -> usize {
        self.usable.iter().filter(|&&u| u).count()
    }

    /// Pixel indices ($j \cdot W + i$) that are samples of `painting`: usable and painted.
    pub fn sample_pixels(&self, painting: &Painting) -> Vec<usize> {
        (0..self.pixels.len()).filter(|&k| self.usable[k] && painting.painted(k)).collect()
    }
}

/// One view with its painting: what [`Samples::gather`] takes.
#[derive(Clone, Debug)]
pub struct PaintedView {
    /// How errors and reports name the view: the painting's path, as the user gave it.
    pub name: String,
    /// The scene (or normal map) the view was sampled from, as the user gave it.
    pub source: String,
    pub geometry: Geometry,
    pub painting: Painting,
}

/// Samples of one or more views, concatenated (thesis 4.4).
#[derive(Clone, Debug)]
pub struct Samples {
    pub pattern: Pattern,
    /// Shading-function values $S$ (linear RGB), one per query.
    pub values: Vec<[f64; 3]>,
    /// Per sample: the view's index and the pixel's index $j \cdot W + i$.
    pub origin: Vec<(usize, usize)>,
    /// Samples per view.
    pub per_view: Vec<usize>,
}

impl Samples {
    /// Gather the samples of `views`. Errors, one line naming the painting: its size
    /// differs from the geometry's, it is transparent everywhere, none of its painted
    /// pixels lies on the object, every sample is saturated; and, over all views, every
    /// sample is black.
    pub fn gather(views: &[PaintedView]) -> Result<Samples> {
        if views.is_empty() {
            return Err(Error::input("no views to sample"));
        }
        let mut out = Samples { pattern: Pattern::default(), values: Vec::new(), origin: Vec::new(), per_view: Vec::new() };
        let mut queries = Vec::new();
        let mut has_uv = true;
        for (v, view) in views.iter().enumerate() {
            let (g, p) = (&view.geometry, &view.painting);
            if (g.width, g.height) != (p.width, p.height) {
                return Err(Error::input(format!(
                    "{} is {}x{} but its geometry is {}x{}",
                    view.name, p.width, p.height, g.width, g.height
                )));
            }
            if !p.alpha.iter().any(|&a| a > 0.0) {
                return Err(Error::input(format!("{} is transparent everywhere (alpha 0): nothing is painted", view.name)));
            }
            let pixels = g.sample_pixels(p);
            if pixels.is_empty() {
                let reason = if g.usable_count() == 0 {
                    format!("{} does not see the object (no usable pixel in {})", view.source, view.name)
                } else {
                    format!("{} misses the object: none of its painted pixels lies on it (see {})", view.name, view.source)
                };
                return Err(Error::input(format!("{reason}; there are no samples")));
            }
            if pixels.iter().all(|&k| p.saturated[k]) {
                return Err(Error::input(format!(
                    "{}: every painted pixel on the object is saturated (white): the values are clipped",
                    view.name
                )));
            }
            has_uv &= g.has_uv;
            for &k in &pixels {
                let px = g.pixels[k].expect("usable pixels have geometry");
                let c = p.pixels[k];
                queries.push(px.query);
                out.values.push([0, 1, 2].map(|i| c[i] as f64 / px.light[i]));
                out.origin.push((v, k));
            }
            out.per_view.push(pixels.len());
        }
        if out.values.iter().all(|v| v.iter().all(|&x| x == 0.0)) {
            let names: Vec<&str> = views.iter().map(|v| v.name.as_str()).collect();
            return Err(Error::input(format!(
                "{}: every painted pixel on the object is black: there is nothing to fit",
                names.join(", ")
            )));
        }
        out.pattern = Pattern::new(queries, has_uv);
        Ok(out)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The pixel grid of each of `views` (the views these samples were gathered from): which
    /// sample each pixel holds. A material map rasterizes them to fill the gaps of its
    /// coefficient textures ([`crate::material::map::fit`]).
    pub fn grids(&self, views: &[PaintedView]) -> Vec<Grid> {
        let mut grids: Vec<Grid> = views
            .iter()
            .map(|v| Grid { width: v.geometry.width, height: v.geometry.height, sample: vec![None; v.geometry.width * v.geometry.height] })
            .collect();
        for (k, &(view, pixel)) in self.origin.iter().enumerate() {
            // Samples of other views than those given have no grid to go in.
            if let Some(cell) = grids.get_mut(view).and_then(|g| g.sample.get_mut(pixel)) {
                *cell = Some(k as u32);
            }
        }
        grids
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(w: usize, h: usize, f: impl Fn(usize, usize) -> bool) -> Vec<bool> {
        (0..w * h).map(|k| f(k % w, k / w)).collect()
    }

    #[test]
    fn erosion_removes_the_border_ring_of_a_square() {
        let object = grid(8, 8, |i, j| (1..7).contains(&i) && (1..7).contains(&j));
        for neighbours in [Neighbours::Four, Neighbours::Eight] {
            let kept = Erosion { radius: 1, neighbours }.apply(&object, 8, 8);
            assert_eq!(kept, grid(8, 8, |i, j| (2..6).contains(&i) && (2..6).contains(&j)), "{neighbours:?}");
        }
        assert_eq!(Erosion::NONE.apply(&object, 8, 8), object);
        // The image edge counts as background.
        let full = vec![true; 25];
        assert_eq!(Erosion::default().apply(&full, 5, 5), grid(5, 5, |i, j| (1..4).contains(&i) && (1..4).contains(&j)));
    }

    #[test]
    fn four_and_eight_neighbours_differ_at_a_diagonal_notch() {
        // A 5x5 object with its corner (1, 1) missing: (2, 2) touches it only diagonally.
        let object = grid(7, 7, |i, j| (1..6).contains(&i) && (1..6).contains(&j) && (i, j) != (1, 1));
        let four = Erosion { radius: 1, neighbours: Neighbours::Four }.apply(&object, 7, 7);
        let eight = Erosion::default().apply(&object, 7, 7);
        assert!(four[2 * 7 + 2] && !eight[2 * 7 + 2]);
        let square = grid(7, 7, |i, j| (1..6).contains(&i) && (1..6).contains(&j));
        let two = Erosion { radius: 2, neighbours: Neighbours::Eight }.apply(&square, 7, 7);
        assert_eq!(two, grid(7, 7, |i, j| i == 3 && j == 3));
    }
}
