//! Reflectance functions that produce samples: analytic models (tests, demos, paintings),
//! measured data in the MERL binary format, and analytic views of a sphere that turn any of
//! them into a sample pattern.

mod analytic;
mod fits;
pub mod lobe;
pub mod lobe_fit;
mod merl;
mod sphere;
mod striped;

pub use analytic::Analytic;
pub use fits::{fresnel_dielectric, Abc};
pub use merl::{grid as merl_grid, Merl};
pub use sphere::{held_out_views, painted_views, SpherePixel, SphereView};
pub use striped::Striped;

use crate::factor::Query;

/// Anything that answers "what is the shading at (l, v)?": the shading function
/// $S = f_r \cos\theta_l$ (DESIGN.md, Shading function) at a query in the local frame, linear
/// RGB, under a unit white light. Spatially varying ones read the query's uv. Analytic
/// models, the ABC fits, the striped test object, MERL data and fitted materials all
/// implement it, so judging and painting code take any of them.
pub trait Reflectance {
    fn shading(&self, q: &Query) -> [f64; 3];
}
