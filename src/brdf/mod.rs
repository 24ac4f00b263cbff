//! Reflectance functions that produce samples: analytic models (tests, demos, paintings),
//! measured data in the MERL binary format, and analytic views of a sphere that turn any of
//! them into a sample pattern.

mod analytic;
mod fits;
mod merl;
mod sphere;
mod striped;

pub use analytic::Analytic;
pub use fits::{fresnel_dielectric, Abc};
pub use merl::Merl;
pub use sphere::{held_out_views, painted_views, relative_rms, SpherePixel, SphereView};
pub use striped::Striped;
