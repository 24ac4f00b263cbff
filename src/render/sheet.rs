//! The coloring-book sheet (thesis 4.1): what an artist paints on, and the scene it belongs
//! to, in one directory.
//!
//! ```text
//! DIR/outline.png     black lines on white: silhouettes, creases, occlusion contours
//! DIR/page.png        the same lines on a transparent layer: the page to paint on
//! DIR/reference.png   Lambert + Phong under the scene's light, to show where light comes from
//! DIR/mask.png        white where a pixel centre sees the object, black elsewhere
//! DIR/scene.gltf      the exact scene (meshes, camera, light) of the three images
//! ```
//!
//! All three images cover exactly the pixels the sampler of a painting of this size sees
//! (same vertex stage, same pixel centres). A painting made on `page.png` (or on the opaque
//! `outline.png`), gaps and lines left in, is fitted with `brdfpaint fit --scene
//! DIR/scene.gltf --image painting.png`: the fit leaves out what the page put there
//! ([`crate::sample::page`]).

use std::path::Path;

use super::{GBuffer, GpuScene, Image, OutlineStyle, ReferenceStyle, Renderer};
use crate::error::{Error, Result};
use crate::images::Rgb;
use crate::scene::{Light, Scene};

/// The files of a sheet directory, in the order they are written.
pub const SHEET_FILES: [&str; 4] = ["outline.png", "reference.png", "mask.png", "scene.gltf"];
/// The page to paint on: the outline's lines, opaque black, on a transparent layer. Written
/// with the others; a sheet written before it existed lacks it.
pub const PAGE_FILE: &str = "page.png";

/// The images of a sheet, linear RGBA, row 0 at the top.
#[derive(Clone, Debug)]
pub struct Sheet {
    pub outline: Image,
    pub reference: Image,
    pub mask: Image,
    /// Per pixel: an outline passes here (the lines of `outline.png` and `page.png`).
    pub lines: Vec<bool>,
    /// The factor [`ReferenceStyle::exposure`] the reference was drawn with
    /// ([`reference_exposure`]).
    pub exposure: f32,
    /// Pixels whose centre sees the object.
    pub coverage: usize,
}

impl Image {
    /// The RGB channels (alpha dropped), as [`Rgb`] for writing PNG or EXR.
    pub fn to_rgb(&self) -> Rgb {
        Rgb { width: self.width, height: self.height, pixels: self.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect() }
    }
}

/// The exposure that maps the brightest light reaching the visible object to 1:
/// $1 / \max_{\text{pixels}} \big(\text{falloff} \cdot \max_c(\text{colour}_c \cdot \text{intensity})\big)$.
/// glTF intensities are physical (a point light of 100 cd a few metres away), and the
/// reference image only has to show where light comes from, so it is normalized rather than
/// clipped: with the default [`ReferenceStyle`] no pixel exceeds $0.04 + 0.6 + 0.35 = 0.99$.
/// A white directional light of intensity 1 gets exposure 1. Returns 1 when no pixel sees the
/// object or the light is black.
pub fn reference_exposure(g: &GBuffer, light: &Light) -> f32 {
    let (Light::Directional { color, intensity, .. } | Light::Point { color, intensity, .. }) = *light;
    let peak = (color * intensity).max_element();
    let brightest = g.pixels.iter().filter(|p| p.hit).map(|p| p.falloff * peak).fold(0.0f32, f32::max);
    if brightest > 0.0 && brightest.is_finite() && (1.0 / brightest).is_finite() {
        1.0 / brightest
    } else {
        1.0
    }
}

impl Sheet {
    /// Draws the sheet of `scene` at `width` × `height`: one G-buffer (outline and mask come
    /// from it) and the reference at [`reference_exposure`].
    pub fn render(renderer: &mut Renderer, scene: &Scene, width: usize, height: usize) -> Result<Sheet> {
        let gpu = GpuScene::upload(renderer.gl(), scene)?;
        let g = renderer.gbuffer(&gpu, width, height)?;
        let exposure = reference_exposure(&g, &scene.light);
        let style = ReferenceStyle { exposure, ..ReferenceStyle::default() };
        let reference = renderer.reference(&gpu, &style, width, height)?;
        Ok(Sheet {
            outline: g.outline(&OutlineStyle::default()),
            lines: g.lines(&OutlineStyle::default()),
            reference,
            mask: g.mask(),
            exposure,
            coverage: g.coverage(),
        })
    }

    /// Writes the sheet and `scene` into `dir` ([`SHEET_FILES`]). Everything is written into
    /// a temporary sibling directory first, which then replaces `dir` in one atomic step
    /// ([`crate::commit::StagedDir`]): the four files appear together or not at all, and
    /// other files there, such as paintings, are kept. Anything else at `dir` is refused, and
    /// a failure leaves `dir` as it was.
    pub fn save(&self, scene: &Scene, dir: &Path) -> Result<()> {
        Target::of(dir)?;
        // The four files appear together in one atomic step, the user's other files kept.
        let staged = crate::commit::StagedDir::new(dir, Box::new(|name| name == PAGE_FILE || SHEET_FILES.iter().any(|f| name == *f)))?;
        staged.fill(|tmp| self.write_into(scene, tmp))?;
        staged.commit()
    }

    fn write_into(&self, scene: &Scene, dir: &Path) -> Result<()> {
        self.outline.to_rgb().write_png(&dir.join(SHEET_FILES[0]))?;
        self.reference.to_rgb().write_png(&dir.join(SHEET_FILES[1]))?;
        self.mask.to_rgb().write_png(&dir.join(SHEET_FILES[2]))?;
        scene.write_gltf(dir.join(SHEET_FILES[3]))?;
        self.write_page(&dir.join(PAGE_FILE))
    }

    /// `page.png`: 8-bit RGBA, black and opaque on the lines, transparent elsewhere, so a
    /// painting program opens it as a layer of lines over nothing.
    fn write_page(&self, path: &Path) -> Result<()> {
        let (w, h) = (self.outline.width, self.outline.height);
        let bytes: Vec<u8> = self.lines.iter().flat_map(|&l| if l { [0, 0, 0, 255] } else { [0, 0, 0, 0] }).collect();
        let img = image::RgbaImage::from_raw(w as u32, h as u32, bytes).ok_or_else(|| Error::format(path, "page size mismatch"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).map_err(|e| Error::format(path, e.to_string()))?;
        crate::commit::write_atomic(path, out.get_ref())
    }
}

/// Checks, before any work, that a sheet may be written to `dir`: nothing is there, an empty
/// directory, or a sheet directory (one holding every file of [`SHEET_FILES`]).
pub fn check_output(dir: &Path) -> Result<()> {
    Target::of(dir).map(|_| ())
}

/// What is at the output path of a sheet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// Nothing, or an empty directory.
    Fresh,
    /// A directory holding every file of [`SHEET_FILES`].
    Sheet,
}

impl Target {
    /// Refuses files and non-empty directories that are not sheets.
    fn of(dir: &Path) -> Result<Target> {
        if crate::commit::output_dir_is_fresh(dir)? {
            Ok(Target::Fresh)
        } else if SHEET_FILES.iter().all(|f| dir.join(f).is_file()) {
            Ok(Target::Sheet)
        } else {
            Err(Error::input(format!(
                "{} exists and is not a sheet directory (one holding {}); not overwriting it",
                dir.display(),
                SHEET_FILES.join(", ")
            )))
        }
    }

}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::GPixel;
    use glam::Vec3;

    #[test]
    fn exposure_normalizes_the_brightest_lit_pixel() {
        let px = |falloff: f32| GPixel { hit: true, falloff, ..Default::default() };
        let g = GBuffer {
            width: 3,
            height: 1,
            pixels: vec![px(0.01), px(0.04), GPixel { falloff: 9.0, ..Default::default() }],
        };
        let point = Light::Point { position: Vec3::ZERO, color: Vec3::new(1.0, 0.5, 0.25), intensity: 100.0 };
        assert!((reference_exposure(&g, &point) - 1.0 / (0.04 * 100.0)).abs() < 1e-7);
        let sun = Light::Directional { direction: -Vec3::Y, color: Vec3::ONE, intensity: 1.0 };
        let g1 = GBuffer { width: 1, height: 1, pixels: vec![px(1.0)] };
        assert_eq!(reference_exposure(&g1, &sun), 1.0);
        let empty = GBuffer { width: 1, height: 1, pixels: vec![GPixel::default()] };
        assert_eq!(reference_exposure(&empty, &point), 1.0);
    }

    #[test]
    fn only_fresh_or_sheet_directories_are_written() {
        let root = tempfile::tempdir().unwrap();
        assert_eq!(Target::of(&root.path().join("new")).unwrap(), Target::Fresh);
        assert_eq!(Target::of(root.path()).unwrap(), Target::Fresh);
        std::fs::write(root.path().join("notes.txt"), "mine").unwrap();
        let e = Target::of(root.path()).unwrap_err().to_string();
        assert!(e.contains("not a sheet directory"), "{e}");
        assert!(Target::of(&root.path().join("notes.txt")).is_err());
        for f in SHEET_FILES {
            std::fs::write(root.path().join(f), "x").unwrap();
        }
        assert_eq!(Target::of(root.path()).unwrap(), Target::Sheet);
    }
}
