//! Brush texture kept (issue 36, `fit --lit-sphere --texture keep`): the painting's detail
//! over its fitted material, as a [`Detail`] the renderer multiplies at the view-space
//! normal.
//!
//! The detail is the painting's residual against the material re-rendered in its own scene,
//! in log space, high-passed:
//!
//! $$ d = \exp\big(r - G_\sigma * r\big), \qquad r = \ln\frac{p + \epsilon}{f + \epsilon} $$
//!
//! per channel, with $p$ the painting and $f$ the fit. What is left at the scale of the
//! shading ($G_\sigma * r$) is the fit's misfit of the light's falloff, which must move with
//! the light and so stays out of a texture fixed in view space; what is finer is paint. The renderer
//! applies it as [`Detail::apply`] does, so in its own scene it gives the painting back,
//! strokes in the shadows included.

use super::edges::blur;
use super::Disk;
use crate::brdf::Reflectance;
use crate::material::detail::MAX_DETAIL_RES;
use crate::material::{Detail, Material};
use crate::sample::PaintedView;

/// Below this linear value the residual's ratio is noise, not paint: an 8-bit picture's codes
/// near black are 3e-4 apart and JPEG's error is several codes, so at 0.01 (sRGB code 25) a
/// code is 4% of the value, under the contrast of a stroke.
pub(crate) const DARK: f64 = 0.01;

/// The scale of the shading, as a share of the disk's radius: a painted sphere's narrowest
/// lobe (a highlight) spans about a quarter of the radius, so the Gaussian that holds the
/// material's part of the residual has a standard deviation of an eighth.
const SHADING_SCALE: f64 = 1.0 / 8.0;

/// The detail of `view` (a lit-sphere picture with `disk`) over `material`: one texel per
/// pixel of the disk's diameter, at most [`MAX_DETAIL_RES`].
pub fn detail(view: &PaintedView, disk: &Disk, material: &Material) -> Detail {
    let (w, h) = (view.geometry.width, view.geometry.height);
    let (residual, weight) = residual(view, material);
    let sigma = (SHADING_SCALE * disk.r).max(1.0);
    let blurred_weight = blur(&weight, w, h, sigma);
    let high: Vec<[f32; 3]> = {
        let smooth: Vec<Vec<f32>> = (0..3)
            .map(|c| {
                let weighted: Vec<f32> = residual.iter().zip(&weight).map(|(r, w)| r[c] * w).collect();
                blur(&weighted, w, h, sigma)
            })
            .collect();
        (0..w * h).map(|k| [0, 1, 2].map(|c| residual[k][c] - smooth[c][k] / blurred_weight[k].max(1e-6))).collect()
    };
    let res = ((2.0 * disk.r).round() as usize).clamp(2, MAX_DETAIL_RES);
    let mut texels: Vec<Option<[f32; 3]>> = (0..res * res)
        .map(|t| {
            let n = Detail::texel_normal(res, t % res, t / res);
            let (x, y) = (disk.cx + n.x * disk.r - 0.5, disk.cy - n.y * disk.r - 0.5);
            (n.length() <= 1.0).then(|| sample(&high, &weight, w, h, x, y)).flatten()
        })
        .collect();
    fill_from_neighbours(&mut texels, res);
    Detail { res, floor: DARK as f32, texels: texels.into_iter().map(|t| t.unwrap_or([0.0; 3]).map(f32::exp)).collect() }
}

/// Per pixel: the log residual $r$ and 1 where it is a sample (usable and painted), else 0.
fn residual(view: &PaintedView, material: &Material) -> (Vec<[f32; 3]>, Vec<f32>) {
    let g = &view.geometry;
    let p = &view.painting;
    let mut residual = vec![[0.0f32; 3]; g.width * g.height];
    let mut weight = vec![0.0f32; g.width * g.height];
    for k in 0..g.pixels.len() {
        let Some(px) = g.pixels[k].filter(|_| g.usable[k] && p.painted(k)) else { continue };
        let s = material.shading(&px.query);
        residual[k] = [0, 1, 2].map(|c| (((p.pixels[k][c] as f64).max(0.0) + DARK) / (s[c] * px.light[c] + DARK)).ln() as f32);
        weight[k] = 1.0;
    }
    (residual, weight)
}

/// Bilinear sample of `values` at pixel coordinates (x, y) (pixel centres at integers) from
/// the neighbours that are samples; `None` where none is.
fn sample(values: &[[f32; 3]], weight: &[f32], w: usize, h: usize, x: f64, y: f64) -> Option<[f32; 3]> {
    let (i0, j0) = (x.floor() as isize, y.floor() as isize);
    let (fx, fy) = ((x - i0 as f64) as f32, (y - j0 as f64) as f32);
    let mut sum = [0.0f32; 3];
    let mut total = 0.0f32;
    for (di, dj, c) in [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)] {
        let (i, j) = (i0 + di, j0 + dj);
        if i < 0 || j < 0 || i >= w as isize || j >= h as isize {
            continue;
        }
        let k = j as usize * w + i as usize;
        let c = c * weight[k];
        if c > 0.0 {
            for (s, v) in sum.iter_mut().zip(values[k]) {
                *s += c * v;
            }
            total += c;
        }
    }
    (total > 1e-6).then(|| sum.map(|s| s / total))
}

/// Gives every empty texel the lookup can read (within two texels of the disk: it clamps
/// to the disk and filters bilinearly) the mean of its filled 8-neighbours, ring by ring
/// outward from the filled ones, so the rim the picture's outline hides continues the
/// nearest paint rather than reading 1. The corners beyond stay empty (they read 1).
fn fill_from_neighbours(texels: &mut [Option<[f32; 3]>], res: usize) {
    let reach = 1.0 + 4.0 / res as f64;
    let read: Vec<usize> = (0..res * res).filter(|&t| Detail::texel_normal(res, t % res, t / res).length() <= reach).collect();
    loop {
        let empty: Vec<usize> = read.iter().copied().filter(|&t| texels[t].is_none()).collect();
        let before = texels.to_vec();
        let mut filled = 0;
        for &t in &empty {
            let (i, j) = ((t % res) as isize, (t / res) as isize);
            let mut sum = [0.0f32; 3];
            let mut n = 0.0f32;
            for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (a, b) = (i + di, j + dj);
                if a < 0 || b < 0 || a >= res as isize || b >= res as isize {
                    continue;
                }
                if let Some(v) = before[b as usize * res + a as usize] {
                    for (s, x) in sum.iter_mut().zip(v) {
                        *s += x;
                    }
                    n += 1.0;
                }
            }
            if n > 0.0 {
                texels[t] = Some(sum.map(|s| s / n));
                filled += 1;
            }
        }
        // Done, or nothing left to grow from (a picture without samples).
        if filled == 0 {
            return;
        }
    }
}
