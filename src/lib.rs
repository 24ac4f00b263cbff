//! # brdfpaint
//!
//! Paint or photograph an object in a known scene, and recover a reflectance model stored as
//! small factor textures that render in real time (Jaroszkiewicz 2003, "Fast Extraction of
//! BRDFs and Material Maps from Images").
//!
//! The model is a homomorphic factorization (thesis eq. 3.1):
//!
//! $$ S(\omega_l, \omega_v) \approx \prod_{j=1}^{J} p_j(\pi_j(\omega_l, \omega_v)) $$
//!
//! where $S = f_r \cos\theta_l$ is the shading function a painting shows, and each $p_j$ is a
//! 1D or 2D lookup table. Taking logarithms turns the product into a linear least-squares
//! problem (eq. 3.2-3.4) whose matrix depends only on *where* the samples are, not on their
//! values. So the work splits in two:
//!
//! ```text
//! pattern + settings --prepare (once; cacheable)--> Prepared
//! values --log mapping--> Prepared::solve (milliseconds) --> factors --> Material
//! ```
//!
//! ```
//! use brdfpaint::factor::{prepare, Pattern, Settings, Mapping};
//! use brdfpaint::brdf::{Analytic, Reflectance, SphereView};
//!
//! // One painted view of a sphere, lit from the upper left.
//! let view = SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 48);
//! let pattern: Pattern = view.pattern();
//! let prepared = prepare(&pattern, &Settings::default()).unwrap();
//! let lambert = Analytic::Lambert { albedo: [0.8, 0.5, 0.2] };
//! let values = pattern.shade(|q| lambert.shading(q));
//! let fit = prepared.solve(&values, Mapping::Auto).unwrap();
//! assert!(fit.errors.rms_relative < 0.05);
//! ```

pub mod brdf;
pub mod commit;
pub mod demo;
pub mod error;
pub mod export;
pub mod factor;
pub mod fsio;
pub mod gl;
pub mod images;
pub mod library;
pub mod litsphere;
pub mod live;
pub mod material;
pub mod note;
pub mod pipeline;
pub mod read;
pub mod render;
pub mod sample;
pub mod scene;
pub mod study;
pub mod util;
#[cfg(feature = "viewer")]
pub mod viewer;

pub use error::{Error, Result};
