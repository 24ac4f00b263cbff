//! Brush texture kept (issue 36, `fit --texture keep`), measured: the painting's high-pass
//! contrast against a render's, and how far a light sweep still darkens the render.
//!
//! Texture is measured as a ratio, so the shading and the model's own creases stay out: the
//! painting over its fit re-rendered in its scene, the render with the detail over the same
//! render without it.

use glam::{Quat, Vec3};

use crate::brdf::Reflectance;
use crate::error::Result;
use crate::material::Material;
use crate::litsphere::edges::blur;
use crate::render::{GpuScene, GpuShading, Image, Renderer};
use crate::sample::PaintedView;
use crate::scene::Light;

/// Standard deviation, in pixels, of the blur a high-pass contrast removes: a stroke a few
/// pixels wide passes, the shading's gradient does not.
pub const HIGH_PASS_SIGMA: f64 = 3.0;

/// The blurs of the strokes' scale ([`Texture::scale`]): 1.5 pixels keeps only grain and
/// stroke edges, 6 keeps whole strokes.
pub const FINE_SIGMA: f64 = 1.5;
pub const COARSE_SIGMA: f64 = 6.0;

/// A texture's statistics: its contrast, and the share of it at the finest scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texture {
    /// [`high_pass_contrast`] at [`HIGH_PASS_SIGMA`].
    pub contrast: f64,
    /// The contrast at [`FINE_SIGMA`] over that at [`COARSE_SIGMA`]: near 1 for grain finer
    /// than a pixel or two, smaller the wider the strokes.
    pub scale: f64,
}

impl Texture {
    fn of(log: &[f32], mask: &[bool], w: usize, h: usize) -> Texture {
        let at = |sigma| high_pass_contrast(log, mask, w, h, sigma);
        Texture { contrast: at(HIGH_PASS_SIGMA), scale: at(FINE_SIGMA) / at(COARSE_SIGMA).max(1e-12) }
    }
}

/// Linear offset under the log: below it an 8-bit picture's codes are noise (the floor the
/// detail is measured above).
const DARK: f32 = crate::litsphere::texture::DARK as f32;

/// The standard deviation of `log` minus its Gaussian blur of `sigma` pixels, over the
/// pixels of `mask` whose blur window lies inside the mask (the outline's step is not
/// texture).
pub fn high_pass_contrast(log: &[f32], mask: &[bool], w: usize, h: usize, sigma: f64) -> f64 {
    let m: Vec<f32> = mask.iter().map(|&b| b as i32 as f32).collect();
    let inside = blur(&m, w, h, sigma);
    let masked: Vec<f32> = log.iter().zip(&m).map(|(l, m)| l * m).collect();
    let smooth = blur(&masked, w, h, sigma);
    let values: Vec<f64> =
        (0..w * h).filter(|&k| mask[k] && inside[k] > 0.999).map(|k| (log[k] - smooth[k] / inside[k]) as f64).collect();
    if values.len() < 2 {
        return 0.0;
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

/// [`crate::images::luminance`] of the RGB of a painting's or a render's pixel.
fn luminance(c: &[f32]) -> f32 {
    crate::images::luminance([c[0], c[1], c[2]].map(f64::from)) as f32
}

/// The log of a luminance ratio, offset by [`DARK`] where noise rules.
fn log_ratio(a: f32, b: f32) -> f32 {
    ((a.max(0.0) + DARK) / (b.max(0.0) + DARK)).ln()
}

/// The texture of a painting: [`Texture`] of its log luminance over that of
/// `material` re-rendered in its scene, over its samples (usable and painted pixels).
pub fn painting_texture(view: &PaintedView, material: &Material) -> Texture {
    let (g, p) = (&view.geometry, &view.painting);
    let mut log = vec![0.0f32; g.pixels.len()];
    let mut mask = vec![false; g.pixels.len()];
    for (k, px) in g.pixels.iter().enumerate() {
        let Some(px) = px.filter(|_| g.usable[k] && p.painted(k)) else { continue };
        let s = material.shading(&px.query);
        let fit = [0, 1, 2].map(|c| (s[c] * px.light[c]) as f32);
        log[k] = log_ratio(luminance(&p.pixels[k]), luminance(&fit));
        mask[k] = true;
    }
    Texture::of(&log, &mask, g.width, g.height)
}

/// The texture of a render: [`Texture`] of its log luminance over that of the
/// same render without the detail, over the object (alpha 1).
pub fn render_texture(with: &Image, without: &Image) -> Texture {
    let log: Vec<f32> = with.pixels.iter().zip(&without.pixels).map(|(a, b)| log_ratio(luminance(a), luminance(b))).collect();
    let mask: Vec<bool> = with.pixels.iter().map(|c| c[3] == 1.0).collect();
    Texture::of(&log, &mask, with.width, with.height)
}

/// The darkest frame's mean over the brightest's as a directional light, raised 22° above
/// the view's horizontal, orbits the vertical axis in `frames` steps (the camera stays): how
/// far the relit material still follows the light.
pub fn sweep_ratio(renderer: &mut Renderer, scene: &mut GpuScene, shading: &GpuShading, size: usize, frames: usize) -> Result<f64> {
    let view = scene.camera.forward();
    let mut means = Vec::with_capacity(frames);
    for k in 0..frames {
        let angle = k as f32 / frames as f32 * std::f32::consts::TAU;
        let towards = (Quat::from_rotation_y(angle) * -view + Vec3::Y * 0.4).normalize();
        scene.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
        let image = renderer.factored(scene, shading, size, size)?;
        let object: Vec<f32> = image.pixels.iter().filter(|c| c[3] == 1.0).map(|c| luminance(c)).collect();
        means.push(object.iter().sum::<f32>() as f64 / object.len().max(1) as f64);
    }
    let brightest = means.iter().cloned().fold(0.0, f64::max);
    Ok(means.iter().cloned().fold(f64::INFINITY, f64::min) / brightest.max(1e-12))
}
