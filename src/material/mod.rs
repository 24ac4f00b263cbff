//! Materials: what a fit produces, a renderer draws and a file stores.
//!
//! A material is a sum of terms, each a product of factor tables under a log mapping,
//! weighted by an optional coefficient texture over the surface (thesis 4.2.2):
//!
//! $$ S(l, v, uv) = \sum_k c_k(uv)\, B_k(l, v)\, m_k^{-1}\Big(\prod_j p_{kj}(\pi_{kj}(l, v, uv))\Big) $$
//!
//! where $B_k$ is the term's optional analytic base ([`crate::brdf::lobe`], [`based`], issue 15; 1
//! without one). A uniform material is one term without coefficients. Tables are stored as linear-space
//! values in `f32`, exactly as the shader samples them, so the CPU evaluation here is the
//! reference the GL renderer is tested against.

pub mod based;
pub mod detail;
pub mod map;
pub mod packed;
mod store;

use serde::{Deserialize, Serialize};

use crate::brdf::Reflectance;
use crate::error::{Error, Result};
use crate::factor::system::coordinate;
use crate::factor::table::{stencil_1d, stencil_2d};
use crate::brdf::lobe::Base;
use based::BasedFit;
pub use detail::Detail;
use crate::factor::{Errors, FactorSpec, Fit, Input, LogMap, Query, Settings};

/// The four kinds of the thesis (DESIGN.md, Material directory).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// $p(l)\,q(h)\,r(v)$, the same everywhere.
    Uniform,
    /// A uniform product times $s(u, v)$ (thesis 4.2.1).
    FourFactor,
    /// Several uniform terms blended by coefficient textures (4.2.2).
    MaterialMap,
    /// A material map whose terms are four-factor products (4.3).
    Hybrid,
}

impl Kind {
    /// The name material.json and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Uniform => "uniform",
            Kind::FourFactor => "four-factor",
            Kind::MaterialMap => "material-map",
            Kind::Hybrid => "hybrid",
        }
    }
}

/// One factor table of a term.
#[derive(Clone, Debug, PartialEq)]
pub struct Factor {
    /// What the table looks up, and how. Its smoothing weights record how it was fitted.
    pub spec: FactorSpec,
    /// Linear-space RGB values at the table's nodes, row by row (`res` or `res`² of them).
    pub texels: Vec<[f32; 3]>,
}

/// A coefficient texture over the surface's uv, bilinearly interpolated, nodes at
/// $t_i = i/(M-1)$ like every table. One coefficient per colour channel: the thesis's scalar
/// $c_j(u, v)$ (eq. 4.1) generalized, so a term fitted to a mixture of colours is not scaled
/// down to its worst channel everywhere.
#[derive(Clone, Debug, PartialEq)]
pub struct Coefficients {
    pub res: usize,
    pub texels: Vec<[f32; 3]>,
}

/// A product of factors under a log mapping, optionally over an analytic base and weighted
/// over the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    pub factors: Vec<Factor>,
    pub map: LogMap,
    pub coefficients: Option<Coefficients>,
    /// The analytic lobe $B(l, v)$ the mapped product multiplies, when the fit used one
    /// (`fit --base`; uniform materials only: material maps and the live refit fit none).
    pub base: Option<Base>,
}

/// What [`Provenance::tool`] says: this tool and its version.
pub const TOOL: &str = concat!("brdfpaint ", env!("CARGO_PKG_VERSION"));

/// Where a material came from: stored in material.json, not needed to render it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// `brdfpaint <version>`.
    pub tool: String,
    /// Input files (paintings, scenes, measured data).
    #[serde(default)]
    pub sources: Vec<String>,
    /// Errors on the fitted samples (thesis Table 5.4's metrics).
    #[serde(default)]
    pub errors: Option<Errors>,
    /// Samples fitted.
    #[serde(default)]
    pub samples: usize,
    /// Seconds spent preparing and solving.
    #[serde(default)]
    pub prepare_s: f64,
    #[serde(default)]
    pub solve_s: f64,
    /// What the fit said about its input, one line each: the painted coverage, the pixels
    /// left out and why, warnings with a next step.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// A complete material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub kind: Kind,
    pub terms: Vec<Term>,
    /// The painting's detail over the relit material (`fit --texture keep`), multiplying every
    /// term at the surface's view-space normal; `None` unless asked for.
    pub detail: Option<Detail>,
    pub provenance: Provenance,
}

impl Factor {
    /// Linearly (bilinearly) interpolated value at a query, as the shader computes it.
    pub fn lookup(&self, q: &Query) -> [f64; 3] {
        let t = coordinate(&self.spec, q);
        let stencil = if self.spec.dim() == 1 { stencil_1d(t[0], self.spec.res) } else { stencil_2d(t, self.spec.res) };
        let mut sum = [0.0; 3];
        for (i, w) in stencil.iter() {
            for (s, &x) in sum.iter_mut().zip(&self.texels[i]) {
                *s += w * x as f64;
            }
        }
        sum
    }
}

impl Coefficients {
    /// The same coefficient in every channel.
    pub fn grey(res: usize, values: &[f32]) -> Coefficients {
        Coefficients { res, texels: values.iter().map(|&c| [c; 3]).collect() }
    }

    /// Bilinearly interpolated coefficients at texture coordinates.
    pub fn lookup(&self, uv: glam::DVec2) -> [f64; 3] {
        let t = crate::factor::param::uv_forward(uv);
        let mut sum = [0.0; 3];
        for (i, w) in stencil_2d([t.x, t.y], self.res).iter() {
            for (s, &x) in sum.iter_mut().zip(&self.texels[i]) {
                *s += w * x as f64;
            }
        }
        sum
    }
}

impl Term {
    /// The term's value at a query (before its coefficient): $B(l, v)\, m^{-1}(\prod_j
    /// p_j)$, as `shaders/term.glsl` computes it.
    pub fn eval(&self, q: &Query) -> [f64; 3] {
        let mut prod = [1.0; 3];
        for f in &self.factors {
            let x = f.lookup(q);
            prod = [0, 1, 2].map(|c| prod[c] * x[c]);
        }
        let b = self.base.as_ref().map_or([1.0; 3], |b| b.shading(q));
        [0, 1, 2].map(|c| b[c] * self.map.inverse(c, prod[c]))
    }
}

impl Material {
    /// A material of `terms`, without provenance.
    pub fn new(kind: Kind, terms: Vec<Term>) -> Material {
        Material { kind, terms, detail: None, provenance: Provenance::default() }
    }

    /// A uniform (or four-factor) material from a fit of one product.
    pub fn from_fit(settings: &Settings, fit: &Fit, provenance: Provenance) -> Result<Material> {
        if let Some(f) = settings.factors.iter().find(|f| matches!(f.input, Input::Custom(_))) {
            return Err(Error::input(format!(
                "factor '{}' uses a custom projection, which a material cannot store",
                f.input.name()
            )));
        }
        let factors = settings
            .factors
            .iter()
            .zip(&fit.tables)
            .map(|(spec, t)| Factor { spec: spec.clone(), texels: t.iter().map(|x| x.map(|c| c as f32)).collect() })
            .collect();
        let kind = if settings.factors.iter().any(|f| f.input == Input::Uv) { Kind::FourFactor } else { Kind::Uniform };
        Ok(Material { kind, terms: vec![Term { base: None, factors, map: fit.map, coefficients: None }], detail: None, provenance })
    }

    /// A uniform (or four-factor) material from a fit over an analytic base
    /// ([`crate::read::lobe::solve_based`]): [`Material::from_fit`] with the base kept.
    pub fn from_based_fit(settings: &Settings, fit: &BasedFit, provenance: Provenance) -> Result<Material> {
        let mut material = Material::from_fit(settings, &fit.fit, provenance)?;
        material.terms[0].base = fit.base;
        Ok(material)
    }

    /// Whether any factor or coefficient texture looks up texture coordinates.
    pub fn needs_uv(&self) -> bool {
        self.terms.iter().any(|t| t.coefficients.is_some() || t.factors.iter().any(|f| f.spec.input == Input::Uv))
    }
}

impl Reflectance for Material {
    /// The shading function $S = f_r \cos\theta_l$ at a query: what a pixel shows under a
    /// unit white light. The reference the GL renderer is tested against.
    fn shading(&self, q: &Query) -> [f64; 3] {
        let mut sum = [0.0; 3];
        for term in &self.terms {
            let w = term.coefficients.as_ref().map_or([1.0; 3], |c| c.lookup(q.uv));
            let x = term.eval(q);
            for c in 0..3 {
                sum[c] += w[c] * x[c];
            }
        }
        sum
    }
}

pub use store::{FORMAT, READS, VERSION};
