//! Material maps (thesis 4.2.2): several products blended by coefficient textures,
//! $S \approx \sum_j c_j(u, v)\, \hat f_j(l, v)$ (eq. 4.1); a hybrid (4.3) when the products
//! carry the uv factor $s(u, v)$ too.
//!
//! Two fits: [`Method::Cluster`] (the default: every texel belongs to one term, each term
//! fitted to its own samples; see [`cluster`]) and [`Method::Greedy`], the thesis's
//! iteration on positive residuals (eqs. 4.2–4.4, see [`greedy`]). Both fill texels no
//! sample falls on by rasterizing the painted pixel grid in uv ([`texture`]).

mod cluster;
mod greedy;
mod texture;

use std::time::Instant;

use rayon::prelude::*;

use super::{Coefficients, Factor, Kind, Material, Provenance, Term};
use crate::brdf::Reflectance;
use crate::error::{Error, Result};
use crate::factor::{Errors, Input, LogMap, Mapping, Pattern, Prepared};

pub use crate::factor::Grid;

/// How the terms and their coefficients are found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Regions of one material each, a product per region ([`cluster`]).
    #[default]
    Cluster,
    /// The thesis's greedy fit on positive residuals, eqs. 4.2–4.4 ([`greedy`]).
    Greedy,
}

/// How to fit a material map.
#[derive(Clone, Copy, Debug)]
pub struct MapOptions {
    /// Most terms. Fitting stops earlier when a term improves the relative RMS by less than
    /// `min_gain` times the one-term fit's, or when nothing is left to fit.
    pub terms: usize,
    pub min_gain: f64,
    /// Coefficient texture nodes per side.
    pub coef_res: usize,
    pub mapping: Mapping,
    pub method: Method,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions { terms: 5, min_gain: 0.01, coef_res: 256, mapping: Mapping::Auto, method: Method::default() }
    }
}

/// Largest coefficient texture side.
pub const MAX_COEF_RES: usize = 4096;

/// How a material-map fit went.
#[derive(Clone, Debug, Default)]
pub struct MapReport {
    /// Errors on the samples with 1, 2, … terms: the material's for [`Method::Greedy`];
    /// each sample against its own term's product, without texel gains, for
    /// [`Method::Cluster`] (how well that many BRDFs explain the painting).
    pub errors: Vec<Errors>,
    /// The fitted material's errors on the samples.
    pub fitted: Errors,
    pub seconds: f64,
}

/// Fit a material map (uniform products; a hybrid when the prepared system has a uv factor)
/// to `values` on the prepared pattern, whose samples must carry uv. `grids` give the
/// painted pixel layout of each view, for gap filling and the neighbourhoods of the
/// clustering; with none, gaps take the nearest sampled texel.
pub fn fit(
    prepared: &Prepared,
    pattern: &Pattern,
    values: &[[f64; 3]],
    grids: &[Grid],
    opts: &MapOptions,
) -> Result<(Material, MapReport)> {
    let start = Instant::now();
    if opts.terms == 0 {
        return Err(Error::input("a material map needs at least one term"));
    }
    if !(2..=MAX_COEF_RES).contains(&opts.coef_res) {
        return Err(Error::input(format!("coefficient texture resolution {} is outside 2..={MAX_COEF_RES}", opts.coef_res)));
    }
    if pattern.len() != prepared.samples() || values.len() != pattern.len() {
        return Err(Error::input(format!(
            "{} samples and {} values for a system prepared on {} samples",
            pattern.len(),
            values.len(),
            prepared.samples()
        )));
    }
    if !pattern.has_uv {
        return Err(Error::input("a material map needs samples with texture coordinates"));
    }
    let layout = texture::Layout::new(opts.coef_res, pattern, grids);
    let (terms, errors) = match opts.method {
        Method::Greedy => greedy::fit(prepared, values, &layout, opts)?,
        Method::Cluster => cluster::fit(prepared, values, grids, &layout, opts)?,
    };
    let hybrid = prepared.settings().factors.iter().any(|f| f.input == Input::Uv);
    let mut material = Material { kind: if hybrid { Kind::Hybrid } else { Kind::MaterialMap }, terms, detail: None, provenance: Provenance::default() };
    let predicted: Vec<[f64; 3]> = pattern.queries.par_iter().map(|q| material.shading(q)).collect();
    let fitted = crate::factor::errors(&predicted, values);
    let seconds = start.elapsed().as_secs_f64();
    material.provenance = Provenance {
        tool: super::TOOL.to_string(),
        errors: Some(fitted),
        samples: values.len(),
        prepare_s: prepared.prepare_s,
        solve_s: seconds,
        ..Default::default()
    };
    Ok((material, MapReport { errors, fitted, seconds }))
}

/// A term from linear-space tables.
fn term(prepared: &Prepared, tables: &[Vec<[f64; 3]>], map: LogMap, coefficients: Coefficients) -> Term {
    let factors = prepared
        .settings()
        .factors
        .iter()
        .zip(tables)
        .map(|(spec, t)| Factor { spec: spec.clone(), texels: t.iter().map(|x| x.map(|v| v as f32)).collect() })
        .collect();
    Term { base: None, factors, map, coefficients: Some(coefficients) }
}
