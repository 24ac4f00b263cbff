//! Measuring the product (DESIGN.md, Quality bars): how well materials generalize to lights
//! and views nobody painted, and how fast the pieces run. One definition of each measure:
//!
//! - [`relative_rms`]: $\sqrt{\sum (m - t)^2 / \sum t^2}$ over every channel of every pair;
//! - [`median`]: the middle value, the mean of the middle two for an even count;
//! - [`held_out_error`]: a material against the truth at the G-buffer queries of held-out
//!   views ([`fidelity`] paints and judges the analytic suite through the real path;
//!   [`suite`](mod@suite) judges the wide suite on analytic sphere views, rim light included);
//! - [`rendered_error`]: a material against rendered views, where the truth is a picture
//!   ([`rendered`]: the suite another renderer made; [`photos`]: photographs held out by
//!   light);
//! - [`bench`](mod@bench): `brdfpaint bench`, the thesis's tables and the shader frame times;
//!   [`measure_stroke_to_frame`]: the live painting loop, stroke to frame;
//! - [`texture`](mod@texture): brush texture kept, the painting's against a render's.

pub mod bench;
pub mod colour;
pub mod faults;
pub mod fidelity;
pub mod front;
pub mod painted;
pub mod photos;
pub mod rendered;
mod stroke;
pub mod suite;
pub mod systems;
pub mod texture;

use crate::brdf::{Reflectance, SphereView};
use crate::error::Result;
use crate::factor::Query;
use crate::sample::{Erosion, PaintedView, Samples};

pub use fidelity::StudyView;
pub use stroke::{measure_stroke_to_frame, StrokeTiming};

/// Relative RMS $\sqrt{\sum (m - t)^2 / \sum t^2}$ of (model, truth) pairs, all channels:
/// thesis Table 5.4's relative error.
pub fn relative_rms(pairs: impl IntoIterator<Item = ([f64; 3], [f64; 3])>) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (m, t) in pairs {
        for c in 0..3 {
            num += (m[c] - t[c]).powi(2);
            den += t[c] * t[c];
        }
    }
    (num / den.max(f64::MIN_POSITIVE)).sqrt()
}

/// [`relative_rms`] of `model` against `truth` at every pixel of analytic sphere views.
pub fn sphere_rms(views: &[SphereView], truth: impl Fn(&Query) -> [f64; 3], model: impl Fn(&Query) -> [f64; 3]) -> f64 {
    relative_rms(views.iter().flat_map(|v| v.pixels()).map(|p| (model(&p.query), truth(&p.query))))
}

/// The median of `x` (NaN when empty): the middle value, or the mean of the middle two.
pub fn median(x: &[f64]) -> f64 {
    let mut x = x.to_vec();
    x.sort_by(f64::total_cmp);
    match x.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => x[n / 2],
        n => 0.5 * (x[n / 2 - 1] + x[n / 2]),
    }
}

/// [`relative_rms`] of `material` against `truth` over every usable pixel of the held-out
/// views, both at the pixel's whole query (uv included: a spatially varying truth and a
/// material map are compared point by point). With `painted`, only pixels whose surface
/// point some painting saw count.
pub fn held_out_error(
    material: &dyn Reflectance,
    truth: &dyn Reflectance,
    held_out: &[StudyView],
    painted: Option<&Coverage>,
) -> Result<f64> {
    let mut pairs = Vec::new();
    for view in held_out {
        for q in view.queries()? {
            if painted.is_none_or(|c| c.covers(q.uv)) {
                pairs.push((material.shading(&q), truth.shading(&q)));
            }
        }
    }
    Ok(relative_rms(pairs))
}

/// [`relative_rms`] of `material` against each of `views`, where the truth is the picture:
/// at every sample (a usable, painted pixel), the material's shading against the pixel
/// divided by the light (S = BRDF × cos θ_l, DESIGN.md), as [`Samples::gather`] reads it.
pub fn rendered_error(material: &dyn Reflectance, views: &[PaintedView]) -> Result<Vec<f64>> {
    views
        .iter()
        .map(|v| {
            let s = Samples::gather(std::slice::from_ref(v))?;
            Ok(relative_rms(s.pattern.queries.iter().zip(&s.values).map(|(q, &t)| (material.shading(q), t))))
        })
        .collect()
}

/// [`held_out_error`] over all of `held_out` together, and the largest over each view
/// alone (the worst held-out view): the two figures the painting studies report.
pub fn held_out_and_worst(material: &dyn Reflectance, truth: &dyn Reflectance, held_out: &[StudyView]) -> Result<(f64, f64)> {
    let all = held_out_error(material, truth, held_out, None)?;
    let worst = held_out.chunks(1).map(|v| held_out_error(material, truth, v, None)).collect::<Result<Vec<f64>>>()?;
    Ok((all, worst.into_iter().fold(0.0, f64::max)))
}

/// Where on the surface paintings have samples: cells of a 64² uv grid.
pub struct Coverage {
    cells: Vec<bool>,
}

impl Coverage {
    const RES: usize = 64;

    /// The cells the samples of `views` fall in.
    pub fn of(views: &[PaintedView]) -> Coverage {
        let mut cells = vec![false; Self::RES * Self::RES];
        for v in views {
            for (px, _) in v.geometry.pixels.iter().zip(&v.geometry.usable).filter(|(_, &u)| u) {
                if let Some(px) = px {
                    cells[Self::cell(px.query.uv)] = true;
                }
            }
        }
        Coverage { cells }
    }

    fn cell(uv: glam::DVec2) -> usize {
        crate::factor::param::uv_nearest_node(uv, Self::RES)
    }

    /// Whether texture coordinates fall in a painted cell.
    pub fn covers(&self, uv: glam::DVec2) -> bool {
        self.cells[Self::cell(uv)]
    }
}

/// The usable queries of a view with the default erosion (what the held-out judge reads).
fn usable_queries(geometry: &crate::sample::Geometry) -> Vec<Query> {
    geometry.pixels.iter().zip(&geometry.usable).filter(|(_, &u)| u).filter_map(|(px, _)| px.map(|p| p.query)).collect()
}

impl StudyView {
    /// The queries of the view's usable pixels (default erosion).
    pub fn queries(&self) -> Result<Vec<Query>> {
        let white = crate::scene::Light::Directional { direction: -glam::Vec3::Z, color: glam::Vec3::ONE, intensity: 1.0 };
        let g = crate::sample::scene::geometry_from_gbuffer(&self.gbuffer, &white, true, Erosion::default())?;
        Ok(usable_queries(&g))
    }
}
