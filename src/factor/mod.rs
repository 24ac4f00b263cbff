//! Homomorphic factorization (thesis chapter 3).
//!
//! A shading function is approximated by a product of low-dimensional lookup tables,
//! $S \approx \prod_j p_j(\pi_j(l, v, uv))$ (eq. 3.1). In log space this is linear (eq. 3.2),
//! and with Laplacian smoothing rows it becomes the overdetermined system of eq. 3.4,
//! solved in the least-squares sense.
//!
//! - [`param`]: the parameterizations $\pi_j$ (parabolic, radius, hemispherical, uv), each a
//!   forward/inverse pair, with a representation of directions below the horizon.
//! - [`table`]: tables, interpolation stencils (the rows of $\mathbf A_j$), Laplacian rows.
//! - [`Pattern`]: where the samples are. [`Settings`]: which factors, how to solve.
//! - [`prepare`] → [`Prepared`]: the factored system; [`Prepared::solve`] per set of values.
//! - [`Mapping`]: linear-to-log mappings (3.2.3).
//! - [`robust`]: [`Prepared::solve_robust`], the fit of a hand-made painting (robust loss,
//!   paint levels, a light prior, bounded tables) on the same prepared system.
//! - [`base`]: an analytic lobe under the product; the product is fitted to $S / B$.
//! - [`cache`]: prepared systems saved to disk, keyed by pattern and settings.
//! - [`chroma`]: the colour channels fitted together: luminance and a smoother chroma.

pub mod bound;
pub mod cache;
pub mod chroma;
pub mod mapping;
pub mod param;
mod pattern;
mod prepared;
pub mod robust;
mod sparse;
mod settings;
pub mod system;
pub mod table;

pub use mapping::{LogMap, Mapping};
pub use param::{Domain, Param};
pub use pattern::{headlit, leaned_half, Grid, Pattern, Query, Sample, HEADLIT_DEG};
pub use prepared::{errors, prepare, Errors, Fit, Prepared, Spectral, INVERTED_MARGIN};
pub use bound::BOUND;
pub use robust::Robust;
pub use settings::{defaults, Channels, difference_range, CustomInput, DifferenceChoice, DIFFERENCE_REACH_DEG, FactorSpec, Input, Method, Settings, LEAN_RANGE, MAX_RES_1D, MAX_RES_2D, MAX_UNKNOWNS, MAX_WARP};
