//! Reflectance functions that produce samples: analytic models (tests, demos, paintings),
//! measured data in the MERL binary format, published fits of the MERL materials, and
//! analytic views of a sphere that turn any of them into a sample pattern.

mod analytic;
mod fits;
mod merl;
mod sphere;

pub use analytic::Analytic;
pub use fits::{MerlFit, MerlFits};
pub use merl::Merl;
pub use sphere::SphereView;
