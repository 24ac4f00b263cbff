//! The factored product over an analytic base (issue 15): $S \approx B(l, v)\,
//! m^{-1}\big(\prod_j p_j\big)$.
//!
//! The thesis fits the product to $S$ itself (eq. 3.1). Where no painting has data (light
//! from behind, grazing views) the tables then hold whatever the smoothing and damping
//! extrapolate, and no product of isotropic $(l, h, v)$ tables holds a microfacet lobe's
//! Fresnel, masking and $1/(\cos\theta_l\cos\theta_v)$. Here a small physically based lobe
//! $B$ ([`crate::brdf::lobe`]) is fitted to the samples first, and the product is fitted to
//! the ratio $S / B$ in the usual log space (eq. 3.2, with the mappings of eqs. 3.13–3.16
//! applied to the ratio): where the paintings have data the tables correct $B$, where they
//! have none the damping pulls the tables toward a constant and $B$'s physics extrapolates.
//!
//! The prepared system depends only on where the samples are (thesis 3.2.2), so the base
//! changes nothing but the right-hand side: [`solve_on_base`] divides the values by $B$ and
//! calls the same prepared solve. Prepare once, solve fast, as before. Which lobe, if any, a
//! painting gets is the reading's choice ([`crate::read::lobe`]).

use crate::brdf::lobe::Base;
use crate::brdf::lobe_fit::softening;
use crate::error::{Error, Result};
use crate::factor::{errors, Errors, Fit, LogMap, Mapping, Pattern, Prepared, Query, Settings, INVERTED_MARGIN};

/// The product over a base is fitted to the softened ratio $(S + \varepsilon)/(B +
/// \varepsilon)$, $\varepsilon$ this fraction of the channel's largest value: finite where
/// the lobe is zero (the unlit side), near $S/B$ where the shading is bright, and near 1
/// where both are dark, so the tables learn nothing from the dark. (Flooring the lobe's
/// ambient instead makes $S/B$ fall below 1 toward the terminator wherever a lobe that fits
/// has no ambient; the tables learn that dimming along $\theta_l$ and carry it to rim light,
/// whose highlight lies at grazing $\theta_l$.) The level: small against any lit value (a
/// tenth of a percent of the largest), large against a 16-bit painting's quantization step
/// (1.5e-5); the measurements that chose it are in docs/notes/history.md, "Source comments".
pub const RATIO_SOFTENING: f64 = 0.001;

/// A based fit: the lobe and the product fitted to $S / B$. [`Fit::errors`] are on $S$.
#[derive(Clone, Debug)]
pub struct BasedFit {
    pub base: Option<Base>,
    pub fit: Fit,
}

impl BasedFit {
    /// $B(l, v)\, m^{-1}(\prod p_j)$ at a query (the product alone without a base).
    pub fn eval(&self, settings: &Settings, q: &Query) -> [f64; 3] {
        let x = self.fit.eval(settings, q);
        match &self.base {
            Some(b) => {
                let s = b.shading(q);
                [0, 1, 2].map(|c| s[c] * x[c])
            }
            None => x,
        }
    }
}

/// The product of `prepared` fitted to $S / B$ for a given lobe (the part of
/// [`crate::read::lobe::solve_based`] after the lobe's fit): $B$ once per sample, then the prepared solve of
/// the ratio under each mapping, kept by its error on $S$. The ratio is raised to `weight`
/// ([`crate::read::lobe::choose`]; 1 fits it as it is), which scales the product's correction in
/// log space.
pub fn solve_on_base(prepared: &Prepared, pattern: &Pattern, values: &[[f64; 3]], mapping: Mapping, base: &Base, weight: f64) -> Result<BasedFit> {
    let bs: Vec<[f64; 3]> = pattern.queries.iter().map(|q| base.shading(q)).collect();
    // The softened ratio (S + ε)/(B + ε): finite where the lobe is zero, and 1 where the
    // painting and the lobe are both dark ([`RATIO_SOFTENING`]).
    let eps = softening(values).map_or([f64::MIN_POSITIVE; 3], |(max, _)| max.map(|m| (RATIO_SOFTENING * m).max(f64::MIN_POSITIVE)));
    let ratio: Vec<[f64; 3]> = values.iter().zip(&bs).map(|(v, b)| [0, 1, 2].map(|c| ((v[c] + eps[c]) / (b[c] + eps[c])).powf(weight))).collect();
    let on_s = |fit: &Fit| -> Errors {
        let p = prepared.predict(&fit.tables, &fit.map);
        let p: Vec<[f64; 3]> = p.iter().zip(&bs).map(|(p, b)| [0, 1, 2].map(|c| p[c] * b[c])).collect();
        errors(&p, values)
    };
    let singles = match mapping {
        Mapping::Auto => vec![Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None)],
        m => vec![m],
    };
    let score = |m: &LogMap, e: &Errors| if matches!(m, LogMap::Inverted { .. }) { e.rms / (1.0 - INVERTED_MARGIN) } else { e.rms };
    let mut best: Option<Fit> = None;
    let mut tried = Vec::new();
    for m in singles {
        let mut fit = prepared.solve_ratio(&ratio, m)?;
        fit.errors = on_s(&fit);
        tried.push((fit.map, fit.errors));
        if best.as_ref().is_none_or(|b| score(&fit.map, &fit.errors) < score(&b.map, &b.errors)) {
            best = Some(fit);
        }
    }
    let mut fit = best.ok_or_else(|| Error::Numeric("no mapping gave a finite fit".into()))?;
    fit.tried = tried;
    Ok(BasedFit { base: Some(*base), fit })
}

