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

use super::{band_rows, GBuffer, GpuScene, LineTracer, OutlineStyle, ReferenceStyle, Renderer};
use crate::error::{Error, Result};
use crate::images::encode_srgb8;
use crate::scene::{Light, Scene};

/// The files of a sheet directory, in the order they are written.
pub const SHEET_FILES: [&str; 4] = ["outline.png", "reference.png", "mask.png", "scene.gltf"];
/// The page to paint on: the outline's lines, opaque black, on a transparent layer. Written
/// with the others; a sheet written before it existed lacks it.
pub const PAGE_FILE: &str = "page.png";

/// The pictures of a sheet, kept as what their files hold (bits and 8-bit codes), row 0 at
/// the top. A 4096² sheet is 84 MB here; its G-buffer, 1.7 GB, is never held whole (it is
/// drawn and used in bands, [`Sheet::render`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    pub width: usize,
    pub height: usize,
    /// Per pixel: the pixel centre sees the object (white in `mask.png`).
    pub hit: Vec<bool>,
    /// Per pixel: an outline passes here (the lines of `outline.png` and `page.png`).
    pub lines: Vec<bool>,
    /// `reference.png`'s pixels: 8-bit sRGB, R, G, B per pixel.
    pub reference: Vec<u8>,
    /// The factor [`ReferenceStyle::exposure`] the reference was drawn with
    /// ([`reference_exposure`]).
    pub exposure: f32,
    /// Pixels whose centre sees the object.
    pub coverage: usize,
}

/// The exposure that maps the brightest light reaching the visible object to 1:
/// $1 / \max_{\text{pixels}} \big(\text{falloff} \cdot \max_c(\text{colour}_c \cdot \text{intensity})\big)$.
/// glTF intensities are physical (a point light of 100 cd a few metres away), and the
/// reference image only has to show where light comes from, so it is normalized rather than
/// clipped: with the default [`ReferenceStyle`] no pixel exceeds $0.04 + 0.6 + 0.35 = 0.99$.
/// A white directional light of intensity 1 gets exposure 1. Returns 1 when no pixel sees the
/// object or the light is black.
pub fn reference_exposure(g: &GBuffer, light: &Light) -> f32 {
    let mut brightest = Brightest::new(light);
    brightest.add(g);
    brightest.exposure()
}

/// The running maximum of [`reference_exposure`] over the bands of a G-buffer.
struct Brightest {
    peak: f32,
    max: f32,
}

impl Brightest {
    fn new(light: &Light) -> Brightest {
        let (Light::Directional { color, intensity, .. } | Light::Point { color, intensity, .. }) = *light;
        Brightest { peak: (color * intensity).max_element(), max: 0.0 }
    }

    fn add(&mut self, g: &GBuffer) {
        self.max = g.pixels.iter().filter(|p| p.hit).map(|p| p.falloff * self.peak).fold(self.max, f32::max);
    }

    fn exposure(&self) -> f32 {
        let b = self.max;
        if b > 0.0 && b.is_finite() && (1.0 / b).is_finite() {
            1.0 / b
        } else {
            1.0
        }
    }
}

impl Sheet {
    /// Draws the sheet of `scene` at `width` × `height`: the G-buffer (outline and mask come
    /// from it), then the reference at [`reference_exposure`], each in bands of
    /// [`band_rows`] rows.
    pub fn render(renderer: &mut Renderer, scene: &Scene, width: usize, height: usize) -> Result<Sheet> {
        Sheet::render_in_bands(renderer, scene, width, height, band_rows(width))
    }

    /// [`Sheet::render`] in bands of `rows` rows. Memory is the sheet's pictures plus one
    /// band's G-buffer: each band is used (mask bits, lines, brightest pixel) and dropped.
    /// Any band height gives the same sheet (the bands are exact: [`Renderer::gbuffer_bands`]).
    pub fn render_in_bands(renderer: &mut Renderer, scene: &Scene, width: usize, height: usize, rows: usize) -> Result<Sheet> {
        // The size is checked against the renderer's limits before anything is allocated.
        renderer.begin(width, height)?;
        let gpu = GpuScene::upload(renderer.gl(), scene)?;
        let n = width * height;
        let mut hit = Vec::with_capacity(n);
        let mut tracer = LineTracer::new(width, height, OutlineStyle::default());
        let mut brightest = Brightest::new(&scene.light);
        renderer.gbuffer_bands(&gpu, width, height, rows, |_, band| {
            hit.extend(band.pixels.iter().map(|p| p.hit));
            brightest.add(&band);
            tracer.push(&band.pixels);
            Ok(())
        })?;
        let exposure = brightest.exposure();
        let style = ReferenceStyle { exposure, ..ReferenceStyle::default() };
        let mut reference = Vec::with_capacity(3 * n);
        renderer.reference_bands(&gpu, &style, width, height, rows, |_, band| {
            reference.extend(band.pixels.iter().flat_map(|p| [p[0], p[1], p[2]].map(encode_srgb8)));
            Ok(())
        })?;
        let coverage = hit.iter().filter(|&&h| h).count();
        Ok(Sheet { width, height, hit, lines: tracer.finish(), reference, exposure, coverage })
    }

    /// Writes the sheet and `scene` into `dir` ([`SHEET_FILES`]). Everything is written into
    /// a temporary sibling directory first, which then replaces `dir` in one atomic step
    /// ([`crate::commit::StagedDir`]): the four files appear together or not at all, and
    /// other files there, such as paintings, are kept. Anything else at `dir` is refused, and
    /// a failure leaves `dir` as it was.
    pub fn save(&self, scene: &Scene, dir: &Path) -> Result<()> {
        Target::of(dir)?;
        // The four files appear together in one atomic step, the user's other files kept.
        let fixed: Vec<&str> = SHEET_FILES.iter().chain([&PAGE_FILE]).copied().collect();
        let claim = crate::commit::Claim::new(&fixed, crate::commit::Legacy::Paths(Default::default()));
        let staged = crate::commit::StagedDir::new(dir, claim)?;
        staged.fill(|tmp| self.write_into(scene, tmp))?;
        staged.commit()
    }

    /// The files, one picture at a time: each one's 8-bit pixels are made, encoded and
    /// dropped before the next (a 4096² RGB picture is 50 MB).
    fn write_into(&self, scene: &Scene, dir: &Path) -> Result<()> {
        let rgb = |bit: &[bool], on: u8, off: u8| -> Vec<u8> { bit.iter().flat_map(|&b| [if b { on } else { off }; 3]).collect() };
        // outline.png: black lines on white.
        self.write_png(&dir.join(SHEET_FILES[0]), image::ColorType::Rgb8, &rgb(&self.lines, 0, 255))?;
        self.write_png(&dir.join(SHEET_FILES[1]), image::ColorType::Rgb8, &self.reference)?;
        // mask.png: white where the object is seen.
        self.write_png(&dir.join(SHEET_FILES[2]), image::ColorType::Rgb8, &rgb(&self.hit, 255, 0))?;
        scene.write_gltf(dir.join(SHEET_FILES[3]))?;
        // page.png: 8-bit RGBA, black and opaque on the lines, transparent elsewhere, so a
        // painting program opens it as a layer of lines over nothing.
        let page: Vec<u8> = self.lines.iter().flat_map(|&l| [0, 0, 0, if l { 255 } else { 0 }]).collect();
        self.write_png(&dir.join(PAGE_FILE), image::ColorType::Rgba8, &page)
    }

    /// Encodes 8-bit `pixels` of this sheet's size as a PNG at `path`, atomically.
    fn write_png(&self, path: &Path, color: image::ColorType, pixels: &[u8]) -> Result<()> {
        use image::ImageEncoder;
        let mut out = Vec::new();
        image::codecs::png::PngEncoder::new(&mut out)
            .write_image(pixels, self.width as u32, self.height as u32, color.into())
            .map_err(|e| Error::format(path, e.to_string()))?;
        crate::commit::write_atomic(path, &out)
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
