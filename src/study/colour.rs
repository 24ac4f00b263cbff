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
pub use crate::images::palette::{chromaticity, Palette, FLOOR, FRAMES, INVENTED, TOLERANCE};
use crate::images::luminance;
use crate::render::{GpuScene, GpuShading, Image, Renderer};
use crate::scene::Light;

/// The fraction of `image`'s object pixels (alpha 1) brighter than [`FLOOR`] × the frame's
/// brightest whose chromaticity `palette` does not hold (0 for a black frame).
pub fn invented(palette: &Palette, image: &Image) -> f64 {
    let object: Vec<[f64; 3]> = image.pixels.iter().filter(|p| p[3] >= 1.0).map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect();
    palette.invented_among(&object)
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
    /// The direction towards the darkest frame's light (world).
    pub darkest_towards: Vec3,
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
    let key = invented(palette, &renderer.factored(scene, shading, size, size)?);
    let view = scene.camera.forward();
    let mut frames = Vec::with_capacity(FRAMES);
    for k in 0..FRAMES {
        let a = std::f32::consts::TAU * k as f32 / FRAMES as f32;
        scene.light = light(glam::Quat::from_rotation_y(a) * -view);
        let image = renderer.factored(scene, shading, size, size)?;
        frames.push((object_luminance(&image), invented(palette, &image), glam::Quat::from_rotation_y(a) * -view));
    }
    let dark = (0..frames.len()).min_by(|&a, &b| frames[a].0.total_cmp(&frames[b].0)).unwrap_or(0);
    let brightest = frames.iter().map(|f| f.0).fold(0.0, f64::max);
    let (mean, darkest, darkest_towards) = frames[dark];
    Ok(Sweep { key, darkest, darkest_over_brightest: mean / brightest.max(f64::MIN_POSITIVE), darkest_towards })
}
