//! The fit report: per view, the painting, the fitted material at the same pixels, and the
//! residual, side by side (`report.png` beside a fitted material).
//!
//! The fit panel is the CPU evaluation of the material (its [`Reflectance::shading`](crate::brdf::Reflectance), the reference
//! the GL factored pass is tested against) at each pixel's G-buffer query, times the
//! light that reaches the pixel: what the scene shows with the material applied. The
//! residual panel shows $4\,|\text{fit} - \text{painting}|$ per channel at the samples;
//! pixels on the object that are not samples (silhouette band, unpainted, back-facing) are
//! dark blue, background is black. Unpainted pixels of the painting show a grey
//! checkerboard.

use super::{PaintedView, Samples};
use crate::error::Result;
use crate::factor::{errors, Errors};
use crate::images::Rgb;
use crate::brdf::Reflectance;
use crate::material::Material;

/// Gain of the residual panel.
pub const RESIDUAL_GAIN: f32 = 4.0;
/// Pixels between panels and rows.
const GAP: usize = 4;

/// Errors of `material` against each view's samples, in shading-function units (thesis
/// Table 5.4's metrics: RMS, relative RMS, max).
pub fn view_errors(samples: &Samples, views: &[PaintedView], material: &Material) -> Vec<Errors> {
    (0..views.len())
        .map(|v| {
            let (mut predicted, mut values) = (Vec::new(), Vec::new());
            for (s, &(view, _)) in samples.origin.iter().enumerate() {
                if view == v {
                    predicted.push(material.shading(&samples.pattern.queries[s]));
                    values.push(samples.values[s]);
                }
            }
            errors(&predicted, &values)
        })
        .collect()
}

/// The report image (linear RGB): one row per view, painting | fit | residual.
pub fn image(views: &[PaintedView], material: &Material) -> Result<Rgb> {
    let w = views.iter().map(|v| v.geometry.width).max().unwrap_or(1);
    let h: usize = views.iter().map(|v| v.geometry.height).sum::<usize>() + GAP * views.len().saturating_sub(1);
    let mut out = Rgb::new(3 * w + 2 * GAP, h.max(1))?;
    out.pixels.fill([0.5, 0.5, 0.5]);
    let mut top = 0;
    for view in views {
        let g = &view.geometry;
        let p = &view.painting;
        for j in 0..g.height {
            for i in 0..g.width {
                let k = j * g.width + i;
                let painted = if p.painted(k) {
                    p.pixels[k]
                } else if (i / 8 + j / 8) % 2 == 0 {
                    [0.15; 3]
                } else {
                    [0.3; 3]
                };
                let (fit, residual) = match g.pixels[k] {
                    None => ([0.0; 3], [0.0; 3]),
                    Some(px) => {
                        let s = material.shading(&px.query);
                        let fit = [0, 1, 2].map(|c| (s[c] * px.light[c]) as f32);
                        let residual = if g.usable[k] && p.painted(k) {
                            [0, 1, 2].map(|c| RESIDUAL_GAIN * (fit[c] - p.pixels[k][c]).abs())
                        } else {
                            [0.0, 0.0, 0.03]
                        };
                        (fit, residual)
                    }
                };
                let row = (top + j) * out.width;
                out.pixels[row + i] = painted;
                out.pixels[row + w + GAP + i] = fit;
                out.pixels[row + 2 * (w + GAP) + i] = residual;
            }
        }
        top += g.height + GAP;
    }
    Ok(out)
}
