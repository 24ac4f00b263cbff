//! An analytic base under the factored product (issue 15): $S \approx B(l, v)\,
//! m^{-1}\big(\prod_j p_j\big)$.
//!
//! The thesis fits the product to $S$ itself (eq. 3.1). Where no painting has data (light
//! from behind, grazing views) the tables then hold whatever the smoothing and damping
//! extrapolate, and no product of isotropic $(l, h, v)$ tables holds a microfacet lobe's
//! Fresnel, masking and $1/(\cos\theta_l\cos\theta_v)$ (BENCHMARKS.md, "The wide suite").
//! Here a small physically based lobe $B$ is fitted to the samples first, and the product
//! is fitted to the ratio $S / B$ in the usual log space (eq. 3.2, with the mappings of
//! eqs. 3.13–3.16 applied to the ratio): where the paintings have data the tables correct
//! $B$, where they have none the damping pulls the tables toward a constant and $B$'s
//! physics extrapolates.
//!
//! The lobe, per colour channel $c$, in the local frame ($\cos\theta = z$):
//! $$ B_c = a_c + \cos^+\theta_l\,\Big(k_{d,c} + \big(k_{s,c} + k_{f,c}(1 - \cos\theta_d)^5\big)
//!    \frac{D(\theta_h; \alpha)\, G_1(\theta_l)\,G_1(\theta_v)}{4\cos\theta_l\cos\theta_v}\Big) $$
//! with GGX's $D$ and Smith's $G_1$, or, in place of that microfacet lobe, the lobe of
//! another classic family ([`Lobe`]: Blinn-Phong, Phong, Ward, Ashikhmin-Shirley, whose
//! diffuse shape replaces $\cos^+\theta_l$ too, and the rough-diffuse terms of Oren-Nayar
//! and Minnaert), each with at most one width $\alpha$; `auto` fits every family and keeps
//! the one that explains the samples best, when it explains them ([`choose`]). Schlick's
//! Fresnel $F = F_0 + (1 - F_0)(1 - \cos\theta_d)^5$ times a scale $k$ is $k_s + k_f (1 -
//! \cos\theta_d)^5$ with $k_s = k F_0$,
//! $k_f = k(1 - F_0)$: linear in both, so every channel has its own $F_0$ at no search cost.
//! $a$, $k_d$, $k_s$, $k_f \ge 0$ come from a weighted non-negative linear least-squares fit,
//! $\alpha$ (shared by the channels) from a one-dimensional search. $k_f$ is ridged toward
//! zero ([`FRESNEL_RIDGE`]; Ashikhmin-Shirley's toward its model's own Fresnel): paintings
//! under a light near the camera show $\theta_d$ below 30°, where $(1 - \cos\theta_d)^5 <
//! 10^{-4}$, and must not invent a Fresnel rise they cannot see. The ratio is softened
//! ([`RATIO_SOFTENING`]) so it stays finite where the lobe is zero (the unlit side).
//!
//! The prepared system depends only on where the samples are (thesis 3.2.2), so the base
//! changes nothing but the right-hand side: [`solve_based`] divides the values by $B$ and
//! calls the same [`Prepared::solve`]. Prepare once, solve fast, as before.

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::mapping::Mapping;
use super::pattern::{Pattern, Query};
use super::prepared::{errors, Errors, Fit, Prepared, INVERTED_MARGIN};
use crate::error::{Error, Result};

/// The product over a base is fitted to the softened ratio $(S + \varepsilon)/(B +
/// \varepsilon)$, $\varepsilon$ this fraction of the channel's largest value: finite where
/// the lobe is zero (the unlit side), near $S/B$ where the shading is bright, and near 1
/// where both are dark, so the tables learn nothing from the dark. The lobe's ambient was
/// floored at this level instead (until November 2026): where a lobe that fits has no
/// ambient, $S/B$ then fell below 1 toward the terminator, the tables learnt that dimming
/// along $\theta_l$ and carried it to rim light, whose highlight lies at grazing $\theta_l$
/// (wide suite, three paintings, median 0.0162 floored, 0.0060 softened; a Phong sphere's rim
/// view from one painting 0.10 → 0.0000). The level: the suite is the same from 0.001 to
/// 0.01; the faults study's noisy paintings are 0.0043 at 0.001 and 0.0033 at 0.01, but a
/// GGX lobe forced on the MERL set (`--base ggx`, three paintings) 0.124 and 0.149.
/// BENCHMARKS.md, "Lobe families".
pub const RATIO_SOFTENING: f64 = 0.001;

/// Under [`BaseChoice::Auto`] the lobe is used when its relative misfit on the samples
/// ($\sqrt{\sum w (B - S)^2 / \sum w S^2}$, [`Base::fit`]) beyond the painting's own
/// roughness ([`excess`]: brush texture, noise, grain) is at most this. On clean renders
/// the roughness is nil and the rule is the lobe's misfit alone. Measured on the wide suite
/// (BENCHMARKS.md, "Lobe families"): the truths of the seven families are fitted by their
/// own family to below 2e-4 from the standard paintings and 0.01 from the wide ones (the
/// Fresnel ridge's bias), with the right width; the models of no family miss by 0.039 or
/// more beyond the product's misfit (velvet from one painting, with an Oren-Nayar lobe; Gooch
/// 0.11 and up). With the GGX lobe alone the nearest were Oren-Nayar at 0.025 and Ward 0.4 at
/// 0.0197, a margin of 1.3 over the threshold. A lobe that does not fit extrapolates
/// its own grazing terms where the truth has none (with `ggx` always, Blinn-Phong 128's rim
/// view went 0.17 → 3.8). An 8-bit PNG painting of a GGX sphere (front and side light,
/// unclipped) measures 0.013, its quantization included (`tests/fit_cli.rs`; the
/// quantization is roughness the product misses too, so [`excess`] widens the margin there).
/// 0.025 rather than 0.015 (November 2026): brush texture leaves a painting's own family
/// about 0.02 beyond the product, which absorbs some of it in rings (faults study, brush:
/// GGX 0.7 0.089 → 0.032, Minnaert 0.078 → 0.033 with the lobe kept); on MERL `auto` keeps a
/// lobe for 30 / 23 / 32 materials (19 / 13 / 31 at 0.015), medians 0.2688 → 0.2514, 0.1647
/// → 0.1614, 0.1304 → 0.1221, none worse than the plain product by 10%; the wide suite is
/// unchanged. The models of no family stay 0.039 and more beyond.
pub const AUTO_MISFIT: f64 = 0.025;

/// The GGX widths $\alpha$ the fit tries: log-spaced from a near mirror to fully rough.
const ALPHAS: usize = 28;
const ALPHA_MIN: f64 = 0.01;
const ALPHA_MAX: f64 = 1.0;
/// Golden-section steps refining $\alpha$ after the grid (each shrinks the bracket by 0.618:
/// 12 take a ±19% bracket to ±0.1%).
const REFINE_STEPS: usize = 12;

/// The ridge on the Fresnel coefficient $k_f$, relative to the weighted energy of the
/// specular column: $k_f$ costs $\lambda \sum w\, s^2 k_f^2$ (with $s$ the lobe without
/// Fresnel). The Fresnel column is the specular one times $(1 - \cos\theta_d)^5$, below 2e-5
/// on front-lit paintings, so its energy there is far below the ridge and $k_f$ stays 0
/// (measured on the suite's standard paintings); under side and back light (the wide
/// paintings, θ_d to 77°) the data decide, and GGX's $1 - F_0$ comes back within 4%.
/// Ashikhmin-Shirley's ridge pulls toward its own coupled Fresnel instead ([`linear_fit`]).
const FRESNEL_RIDGE: f64 = 1e-4;

/// The relative weight's softening: samples are weighted by $1/(S + \delta)^2$ with
/// $\delta$ this fraction of the channel's largest value, so the fit is relative (dark and
/// bright parts of a painting count alike, as in log space) without dividing by zero.
const WEIGHT_SOFTENING: f64 = 0.05;

/// At most this many samples enter the search over $\alpha$ (every k-th sample).
const SEARCH_SAMPLES: usize = 4096;

/// At most this many samples (every k-th) enter the final linear fit of the colours and
/// the misfit `auto` judges: all of a 256² painting's, a quarter of a 512² one's (fitting
/// all 147k took about 40 ms, for four coefficients per channel).
const FIT_SAMPLES: usize = 40_000;

/// An analytic lobe under the factors. See the module documentation for the formula.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Base {
    /// Ambient $a$, per channel.
    pub ambient: [f64; 3],
    /// Diffuse $k_d$ (of the shading: $k_d \cos\theta_l$; a Lambertian albedo is $\pi k_d$).
    pub diffuse: [f64; 3],
    /// Specular $k_s$, the colour of the lobe at normal incidence (Schlick's $k F_0$).
    pub specular: [f64; 3],
    /// Fresnel $k_f$, what grazing $\theta_d$ adds (Schlick's $k (1 - F_0)$); 0 for none.
    pub fresnel: [f64; 3],
    /// The lobe's width $\alpha \in (0, 1]$: GGX's and Ward's $\alpha$, the Blinn-Phong,
    /// Phong and Ashikhmin-Shirley exponent through [`Lobe::exponent`], Minnaert's $k$;
    /// unused by Oren-Nayar (1).
    pub alpha: f64,
    /// The specular lobe's family (GGX unless told: version 3 files have only GGX).
    #[serde(default)]
    pub lobe: Lobe,
}

/// Which base a fit uses (`fit --base`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BaseChoice {
    /// The thesis's plain product.
    None,
    /// A GGX lobe under the product, always.
    Ggx,
    /// The lobe of the family ([`Lobe`]) that fits the samples best, when it fits them
    /// within [`AUTO_MISFIT`] beyond their roughness ([`excess`]), else none: the default.
    /// On the wide suite and the MERL ABC fits no material is more than 10% worse than with
    /// `None` (BENCHMARKS.md).
    #[default]
    Auto,
}

impl FromStr for BaseChoice {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "none" => Ok(BaseChoice::None),
            "ggx" => Ok(BaseChoice::Ggx),
            "auto" => Ok(BaseChoice::Auto),
            _ => Err(Error::input(format!("unknown base '{s}': expected auto, none or ggx"))),
        }
    }
}

impl fmt::Display for BaseChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BaseChoice::None => "none",
            BaseChoice::Ggx => "ggx",
            BaseChoice::Auto => "auto",
        })
    }
}

/// GGX's $D(\theta_h) = \alpha^2 / (\pi((\alpha^2 - 1)\cos^2\theta_h + 1)^2)$.
fn ggx_d(cos_h: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let t = (a2 - 1.0) * cos_h * cos_h + 1.0;
    // t >= min(a2, 1) > 0 for alpha > 0 (the fit never tries alpha = 0).
    a2 / (PI * t * t)
}

/// Smith's $G_1$ for GGX, divided by $2\cos\theta$: $1/(\cos\theta + \sqrt{\alpha^2 + (1 -
/// \alpha^2)\cos^2\theta})$. Dividing out the cosine keeps the lobe finite at grazing angles
/// where $G_1/\cos\theta$ is, and saves the division by $4\cos\theta_l\cos\theta_v$.
fn g1_over_2cos(cos: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    1.0 / (cos + (a2 + (1.0 - a2) * cos * cos).sqrt())
}

/// The lobe's specular shading at unit $k_s$, $s = \cos\theta_l\, D\, G_1 G_1 / (4
/// \cos\theta_l \cos\theta_v)$, and Schlick's $(1 - \cos\theta_d)^5$; both zero when
/// either direction is at or below the horizon.
pub fn specular_shape(l: DVec3, v: DVec3, alpha: f64) -> (f64, f64) {
    let (cl, cv) = (l.z, v.z);
    if cl <= 0.0 || cv <= 0.0 {
        return (0.0, 0.0);
    }
    // Both above the horizon, so l + v != 0.
    let h = (l + v).normalize();
    let x = 1.0 - l.dot(h).clamp(0.0, 1.0);
    // $\cos\theta_l \cdot D \cdot \frac{G_1(l)}{2 c_l} \frac{G_1(v)}{2 c_v}$.
    (cl * ggx_d(h.z, alpha) * g1_over_2cos(cl, alpha) * g1_over_2cos(cv, alpha), x.powi(5))
}

/// The family of a base's lobe. One width $\alpha \in (0, 1]$ serves every family that has
/// one: the Blinn-Phong, Phong and Ashikhmin-Shirley exponents are $e = 2/\alpha^2 - 2$, the
/// usual correspondence of a Blinn-Phong lobe with a Beckmann (and, near its peak, GGX) lobe
/// of width $\alpha$; Minnaert's $k$ is $\alpha$; Oren-Nayar has none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lobe {
    /// The microfacet lobe of the module documentation (GGX, Smith masking).
    #[default]
    Ggx,
    /// $\cos\theta_l\,(\mathbf n\cdot\mathbf h)^e$: the Blinn-Phong highlight, no masking
    /// and no $1/\cos$ rise at grazing angles.
    BlinnPhong,
    /// $\cos\theta_l\,\max(0, \mathbf r\cdot\mathbf v)^e$ with $\mathbf r$ the mirror of
    /// $\mathbf l$: Phong's highlight, which no table of $\theta_h$ holds (its isophotes are
    /// circles about the mirror direction, not about $\mathbf n$).
    Phong,
    /// Isotropic Ward (1992): $\cos\theta_l\, e^{-\tan^2\theta_h/\alpha^2} / (4\pi\alpha^2
    /// \sqrt{\cos\theta_l\cos\theta_v})$, a Gaussian highlight with a milder rise at
    /// grazing angles than the microfacet lobe's.
    Ward,
    /// Isotropic Ashikhmin-Shirley (2000): $\cos\theta_l\,(\mathbf n\cdot\mathbf h)^e /
    /// ((\mathbf h\cdot\mathbf l)\max(\cos\theta_l, \cos\theta_v))$, with its own diffuse
    /// shape in place of Lambert's, $\cos\theta_l\, g(\cos\theta_l)\, g(\cos\theta_v)$, $g(c)
    /// = 1 - (1 - c/2)^5$ (its Schlick Fresnel is the linear $k_s + k_f x^5$ as for the
    /// others, pulled to its own $F_0 = R_s$ where the data do not decide, [`linear_fit`];
    /// its $(1 - R_s)$ is in $k_d$).
    AshikhminShirley,
    /// Oren-Nayar's rough diffuse (qualitative model, 1994): Lambert ($k_d$, their $A$) plus
    /// $\cos\theta_l \max(0, \cos(\phi_l - \phi_v)) \sin\max(\theta_l, \theta_v)
    /// \tan\min(\theta_l, \theta_v)$ (their $B$ term, as $k_s$): the retro-reflection of
    /// clay, plaster and cloth. No width: $\sigma$ is in the ratio of the two coefficients.
    OrenNayar,
    /// Minnaert's limb darkening (1941): $\cos\theta_l\,(\cos\theta_l\cos\theta_v)^{k - 1}$
    /// with $k = \alpha$ (1 is Lambert), for the moon's flat disk and velvet.
    Minnaert,
}

impl Lobe {
    /// Every family, in the order a fit tries them (the first wins a tie).
    pub const ALL: [Lobe; 7] = [Lobe::Ggx, Lobe::BlinnPhong, Lobe::Phong, Lobe::Ward, Lobe::AshikhminShirley, Lobe::OrenNayar, Lobe::Minnaert];

    /// The name in `material.json` and in `fit`'s output.
    pub fn name(self) -> &'static str {
        match self {
            Lobe::Ggx => "ggx",
            Lobe::BlinnPhong => "blinn-phong",
            Lobe::Phong => "phong",
            Lobe::Ward => "ward",
            Lobe::AshikhminShirley => "ashikhmin-shirley",
            Lobe::OrenNayar => "oren-nayar",
            Lobe::Minnaert => "minnaert",
        }
    }

    /// The Blinn-Phong, Phong and Ashikhmin-Shirley exponent of width $\alpha$: $2/\alpha^2 - 2$.
    pub fn exponent(alpha: f64) -> f64 {
        2.0 / (alpha * alpha) - 2.0
    }

    /// Width $\alpha$ as a user reads it: the exponent, $\alpha$ or $k$ of the family.
    pub fn width_of(self, alpha: f64) -> String {
        match self {
            Lobe::BlinnPhong | Lobe::Phong | Lobe::AshikhminShirley => format!("exponent {:.1}", Lobe::exponent(alpha)),
            Lobe::Ggx | Lobe::Ward => format!("alpha {alpha:.4}"),
            Lobe::Minnaert => format!("k {alpha:.3}"),
            // σ is in the weights ([`Base::width`]).
            Lobe::OrenNayar => String::new(),
        }
    }

    /// Whether the family has a width to search (Oren-Nayar has none).
    pub fn has_width(self) -> bool {
        self != Lobe::OrenNayar
    }

    /// Whether only samples at grazing $\theta_d$ decide the lobe's Fresnel $k_f$ (the ridge
    /// holds it at 0 elsewhere, [`linear_fit`]): the specular families but Ashikhmin-Shirley,
    /// whose Fresnel is its own.
    pub fn fresnel_from_data(self) -> bool {
        matches!(self, Lobe::Ggx | Lobe::BlinnPhong | Lobe::Phong | Lobe::Ward)
    }

    /// The lobe's diffuse shading at unit $k_d$ ($\cos^+\theta_l$, but for
    /// Ashikhmin-Shirley), its specular shading at unit $k_s$, and Schlick's $(1 -
    /// \cos\theta_d)^5$; the last two zero when either direction is at or below the horizon.
    pub fn shape(self, l: DVec3, v: DVec3, alpha: f64) -> (f64, f64, f64) {
        let (cl, cv) = (l.z, v.z);
        if cl <= 0.0 || cv <= 0.0 {
            // Ashikhmin-Shirley's diffuse has g(cos θ_v) = 0 at the horizon and below.
            let lambert = if self == Lobe::AshikhminShirley { 0.0 } else { cl.max(0.0) };
            return (lambert, 0.0, 0.0);
        }
        // Both above the horizon, so l + v != 0.
        let h = (l + v).normalize();
        let x5 = (1.0 - l.dot(h).clamp(0.0, 1.0)).powi(5);
        // 0 at c = 0 even for the exponent 0 of α = 1, as the shader's pow is taken.
        let power = |c: f64, e: f64| if c > 0.0 { c.powf(e) } else { 0.0 };
        let (diffuse, spec) = match self {
            Lobe::Ggx => (cl, specular_shape(l, v, alpha).0),
            Lobe::BlinnPhong => (cl, cl * power(h.z, Lobe::exponent(alpha))),
            // r.v = 2 (n.l)(n.v) - l.v (symmetric in l and v).
            Lobe::Phong => (cl, cl * power(2.0 * cl * cv - l.dot(v), Lobe::exponent(alpha))),
            Lobe::Ward => {
                // tan²θ_h = (1 - cos²)/cos²; h.z > 0 for directions above the horizon.
                let c2 = (h.z * h.z).max(1e-300);
                let a2 = alpha * alpha;
                (cl, cl * (-(1.0 - c2) / (c2 * a2)).exp() / (4.0 * PI * a2 * (cl * cv).sqrt()))
            }
            Lobe::AshikhminShirley => {
                let g = |c: f64| 1.0 - (1.0 - c / 2.0).powi(5);
                // h.l = |l + v|/2 > 0 above the horizon.
                (cl * g(cl) * g(cv), cl * power(h.z, Lobe::exponent(alpha)) / (l.dot(h).max(1e-12) * cl.max(cv)))
            }
            Lobe::OrenNayar => {
                // cos(φ_l − φ_v) from the tangent-plane projections (0 where one is the normal,
                // where the sine or tangent below is 0 anyway). θ_max has the smaller cosine:
                // sin θ_max = √(1 − c_min²), tan θ_min = √(1 − c_max²)/c_max.
                let (pl, pv) = (l.x.hypot(l.y), v.x.hypot(v.y));
                let cos_phi = if pl > 1e-12 && pv > 1e-12 { ((l.x * v.x + l.y * v.y) / (pl * pv)).max(0.0) } else { 0.0 };
                let (c_max, c_min) = (cl.max(cv), cl.min(cv));
                (cl, cl * cos_phi * (1.0 - c_min * c_min).max(0.0).sqrt() * (1.0 - c_max * c_max).max(0.0).sqrt() / c_max)
            }
            Lobe::Minnaert => (cl, cl * (cl * cv).powf(alpha - 1.0)),
        };
        (diffuse, spec, x5)
    }
}

impl Base {
    /// $B(l, v)$ per channel (see the module documentation).
    pub fn shading(&self, q: &Query) -> [f64; 3] {
        let (d, s, x5) = self.lobe.shape(q.l, q.v, self.alpha);
        [0, 1, 2].map(|c| self.ambient[c] + d * self.diffuse[c] + s * (self.specular[c] + x5 * self.fresnel[c]))
    }

    /// Fit the lobe to values on a pattern: $\alpha$ by search, the rest by
    /// weighted non-negative least squares (weights $1/(S + \delta)^2$, so relative). Returns
    /// the lobe and its relative misfit $\sqrt{\sum w (B - S)^2 / \sum w S^2}$; `None` when
    /// the values are all zero.
    pub fn fit(pattern: &Pattern, values: &[[f64; 3]]) -> Option<(Base, f64)> {
        Base::fit_lobe(pattern, values, Lobe::Ggx)
    }

    /// [`Base::fit`] of every lobe family ([`Lobe::ALL`]): the one of least misfit.
    ///
    /// A headlit painting ([`Pattern::headlit`]) hardly tells an ambient from a shading that
    /// falls slowly toward the rim (Oren-Nayar's, Minnaert's), and an ambient stays lit with
    /// the light behind: a headlit Minnaert painting with brush texture was held best by a
    /// Blinn-Phong lobe over an ambient (misfit 0.0505; 0.0507 for the best lobe without
    /// one), and its material kept 53% of its brightness with the light behind (the truth:
    /// none). There the families are fitted without an ambient, and the best one with an
    /// ambient is kept only where it holds the painting clearly better
    /// ([`HEADLIT_AMBIENT_GAIN`]): a Gooch painting's cool rim.
    pub fn fit_any(pattern: &Pattern, values: &[[f64; 3]]) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        // The families on their own threads; the least misfit wins, the first of equals.
        let best = |ambient: bool| {
            Lobe::ALL
                .par_iter()
                .enumerate()
                .filter_map(|(n, &lobe)| Base::fit_with(pattern, values, delta, lobe, ambient).map(|fit| (n, fit)))
                .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1).then(a.0.cmp(&b.0)))
                .map(|(_, fit)| fit)
        };
        let lit = best(true)?;
        if !pattern.headlit() {
            return Some(lit);
        }
        match best(false) {
            Some(dark) if lit.1 >= HEADLIT_AMBIENT_GAIN * dark.1 => Some(dark),
            _ => Some(lit),
        }
    }

    /// [`Base::fit`] with a lobe of family `lobe`.
    pub fn fit_lobe(pattern: &Pattern, values: &[[f64; 3]], lobe: Lobe) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        Base::fit_with(pattern, values, delta, lobe, true)
    }

    /// [`Base::fit_lobe`] with the width given: `alpha` held, so that only the directions'
    /// fit is compared ([`crate::sample::register`] turns the light under it).
    pub fn fit_lobe_at(pattern: &Pattern, values: &[[f64; 3]], lobe: Lobe, alpha: f64) -> Option<(Base, f64)> {
        if values.len() != pattern.len() {
            return None;
        }
        let (_, delta) = softening(values)?;
        Some(Base::fit_at(pattern, values, delta, lobe, alpha, true))
    }

    /// [`Base::fit_lobe`] with or without an ambient.
    fn fit_with(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, ambient: bool) -> Option<(Base, f64)> {
        let alpha = if lobe.has_width() { Base::search_width(pattern, values, delta, lobe, ambient)? } else { 1.0 };
        Some(Base::fit_at(pattern, values, delta, lobe, alpha, ambient))
    }

    /// The lobe of family `lobe` and width `alpha`, its colours fitted, and its misfit.
    fn fit_at(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, alpha: f64, ambient: bool) -> (Base, f64) {
        // The colours from every sample up to [`FIT_SAMPLES`] (every k-th beyond).
        let fitted = fitted_samples(pattern.len());
        let (res, k, penalty) = linear_fit(pattern, values, &fitted, delta, lobe, alpha, ambient);
        let res = (res - penalty).max(0.0);
        // The misfit relative to the weighted values: $\sqrt{\sum w (B - S)^2 / \sum w S^2}$
        // (the data's part of the objective; the ridge's penalty is no misfit).
        let misfit = (res / weighted_energy(values, &fitted, delta).max(f64::MIN_POSITIVE)).sqrt();
        let ambient = k.map(|x| x[0]);
        (Base { ambient, diffuse: k.map(|x| x[1]), specular: k.map(|x| x[2]), fresnel: k.map(|x| x[3]), alpha, lobe }, misfit)
    }

    /// The width of `lobe` that fits `values` best: a log grid of [`ALPHAS`] on every k-th
    /// sample up to [`SEARCH_SAMPLES`], refined by golden section.
    fn search_width(pattern: &Pattern, values: &[[f64; 3]], delta: [f64; 3], lobe: Lobe, ambient: bool) -> Option<f64> {
        let stride = pattern.len().div_ceil(SEARCH_SAMPLES).max(1);
        let search: Vec<usize> = (0..pattern.len()).step_by(stride).collect();
        let mut best: Option<(f64, f64)> = None; // (residual, alpha)
        for i in 0..ALPHAS {
            let alpha = ALPHA_MIN * (ALPHA_MAX / ALPHA_MIN).powf(i as f64 / (ALPHAS - 1) as f64);
            let (res, ..) = linear_fit(pattern, values, &search, delta, lobe, alpha, ambient);
            if best.is_none_or(|b| res < b.0) {
                best = Some((res, alpha));
            }
        }
        let (_, alpha) = best?;
        // Refine $\alpha$ between the grid's neighbours by golden-section search on
        // $\log\alpha$: the grid's step (about 19%) alone leaves a GGX truth a misfit of a few
        // percent, which would hide it among the models of other families.
        let step = (ALPHA_MAX / ALPHA_MIN).ln() / (ALPHAS - 1) as f64;
        let at = |x: f64| linear_fit(pattern, values, &search, delta, lobe, x.exp(), ambient).0;
        let (mut lo, mut hi) = ((alpha.ln() - step).max(ALPHA_MIN.ln()), (alpha.ln() + step).min(ALPHA_MAX.ln()));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut f1, mut f2) = (at(x1), at(x2));
        for _ in 0..REFINE_STEPS {
            if f1 < f2 {
                hi = x2;
                (x2, f2) = (x1, f1);
                x1 = hi - g * (hi - lo);
                f1 = at(x1);
            } else {
                lo = x1;
                (x1, f1) = (x2, f2);
                x2 = lo + g * (hi - lo);
                f2 = at(x2);
            }
        }
        Some(if at(alpha.ln()) <= f1.min(f2) { alpha } else if f1 < f2 { x1.exp() } else { x2.exp() })
    }

    /// The lobe's width as a user reads it: the exponent of a Blinn-Phong, Phong or
    /// Ashikhmin-Shirley lobe, $\alpha$ of a GGX or Ward one, Minnaert's $k$, Oren-Nayar's
    /// $B/A$ (which says $\sigma$).
    pub fn width(&self) -> String {
        match self.lobe {
            // σ is in the ratio of the B term to the A term (Lambert).
            Lobe::OrenNayar => format!("B/A {:.3}", self.specular[1] / self.diffuse[1].max(1e-12)),
            lobe => lobe.width_of(self.alpha),
        }
    }

    /// Checks a stored lobe: colours finite and non-negative, $0 < \alpha \le 1$ (the range
    /// the fit searches; at 0 $D$ is a delta function).
    pub fn validate(&self) -> std::result::Result<(), String> {
        let colours = self.ambient.iter().chain(&self.diffuse).chain(&self.specular).chain(&self.fresnel);
        if colours.clone().any(|x| !x.is_finite() || *x < 0.0) {
            return Err("ambient, diffuse and specular must be finite and non-negative".into());
        }
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(format!("alpha {} must be in (0, 1]", self.alpha));
        }
        Ok(())
    }
}

/// Each channel's largest value and the relative weight's softening $\delta$
/// ([`WEIGHT_SOFTENING`] of it); `None` when every value is zero.
fn softening(values: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let mut max = [0.0f64; 3];
    for v in values {
        for c in 0..3 {
            max[c] = max[c].max(v[c]);
        }
    }
    (!max.iter().all(|&m| m <= 0.0)).then(|| (max, max.map(|m| (WEIGHT_SOFTENING * m).max(1e-12))))
}

/// $\sum w S^2$ over the samples `idx`, $w = 1/(S + \delta)^2$: the scale of a relative misfit.
fn weighted_energy(values: &[[f64; 3]], idx: &[usize], delta: [f64; 3]) -> f64 {
    idx.iter().map(|&i| &values[i]).map(|v| (0..3).map(|c| (v[c] / (v[c] + delta[c])).powi(2)).sum::<f64>()).sum()
}

/// On a headlit painting the lobe families keep an ambient only when the best of them with
/// one misfits less than this fraction of the best without ([`Base::fit_any`]).
pub const HEADLIT_AMBIENT_GAIN: f64 = 0.5;

/// The samples a misfit is measured on: every one up to [`FIT_SAMPLES`], every k-th beyond.
fn fitted_samples(n: usize) -> Vec<usize> {
    (0..n).step_by(n.div_ceil(FIT_SAMPLES).max(1)).collect()
}

/// The relative misfit of any prediction of the samples in the measure [`Base::fit`] reports
/// for its lobe, $\sqrt{\sum w (P - S)^2 / \sum w S^2}$ on the same samples: so a lobe's
/// misfit and the product's compare directly.
pub fn misfit(values: &[[f64; 3]], predicted: &[[f64; 3]]) -> f64 {
    let Some((_, delta)) = softening(values) else { return 0.0 };
    let idx = fitted_samples(values.len().min(predicted.len()));
    let res: f64 = idx.iter().map(|&i| (0..3).map(|c| (predicted[i][c] - values[i][c]).powi(2) / (values[i][c] + delta[c]).powi(2)).sum::<f64>()).sum();
    (res / weighted_energy(values, &idx, delta).max(f64::MIN_POSITIVE)).sqrt()
}

/// The most roughness [`excess`] credits a painting with: brush texture of ±8% measures
/// about 0.05, 1% sRGB noise (large, relatively, in the shadows) up to 0.26. A painting that
/// its own free product misses by more than this is not noisy but something else (stray
/// strokes, a misplaced light, a headlight view the product cannot split), and there a lobe
/// is judged on its own misfit: a headlit Oren-Nayar painting with every fault (product
/// 0.57, lobe 0.34) went from 0.94 to 1.80 held-out with its lobe (BENCHMARKS.md).
pub const ROUGHNESS_MAX: f64 = 0.1;

/// What a lobe misfits beyond the painting's own roughness: $\sqrt{\max(0, m_B^2 -
/// r^2)}$, with $r = \min(m_P, $ [`ROUGHNESS_MAX`]$)$ and $m_P$ the free product's misfit
/// ([`misfit`]). Brush texture, noise and grain that no smooth model holds add about
/// equally to both misfits (in quadrature, being independent of either), so the
/// difference is what the lobe itself gets wrong; the product absorbs a little of the
/// texture (its rings), which only makes this larger, the safe side.
pub fn excess(lobe: f64, product: f64) -> f64 {
    let roughness = product.min(ROUGHNESS_MAX);
    (lobe * lobe - roughness * roughness).max(0.0).sqrt()
}

/// Weighted non-negative least squares of $(a, k_d, k_s, k_f)$ per channel for a fixed
/// $\alpha$ over the samples `idx` ($k_f$ ridged, [`FRESNEL_RIDGE`]; $a = 0$ unless
/// `ambient`): the summed weighted
/// residual with the ridge's penalty (what the fit minimizes), the coefficients, and the
/// penalty alone (so a misfit can leave it out).
fn linear_fit(pattern: &Pattern, values: &[[f64; 3]], idx: &[usize], delta: [f64; 3], lobe: Lobe, alpha: f64, ambient: bool) -> (f64, [[f64; 4]; 3], f64) {
    // Normal equations per channel: G = Σ w x xᵀ, b = Σ w x s, c = Σ w s².
    let mut g = [[[0.0f64; N]; N]; 3];
    let mut b = [[0.0f64; N]; 3];
    let mut ss = [0.0f64; 3];
    for &i in idx {
        let q = &pattern.queries[i];
        let (diffuse, spec, x5) = lobe.shape(q.l, q.v, alpha);
        let x = [if ambient { 1.0 } else { 0.0 }, diffuse, spec, spec * x5];
        for c in 0..3 {
            let s = values[i][c];
            let w = 1.0 / (s + delta[c]).powi(2);
            for r in 0..N {
                for k in 0..N {
                    g[c][r][k] += w * x[r] * x[k];
                }
                b[c][r] += w * x[r] * s;
            }
            ss[c] += w * s * s;
        }
    }
    let (mut total, mut penalty) = (0.0, 0.0);
    let mut coef = [[0.0; N]; 3];
    // Ashikhmin-Shirley's Fresnel is part of its model: Schlick's with F_0 = R_s under its
    // normalization (n + 1)/(8π), so k_s = (n + 1)/(8π) R_s and k_f = (n + 1)/(8π)(1 − R_s)
    // for shading under a unit light (what samples are: the scene's light divided out). Its
    // ridge pulls k_s + k_f to (n + 1)/(8π) instead of k_f to 0, so paintings that show no
    // grazing θ_d get the model's own Fresnel, and those that do still decide it. (GGX's
    // k_s + k_f = 1 was tried and rejected: MERL's ABC lobes are not GGX's normalization, and
    // `auto` got worse than the plain product on 13 of them; no MERL material takes this
    // family, so none changes.) Wide suite, worst held-out view from three paintings:
    // Ashikhmin-Shirley's rim light 0.608 → 0.0001.
    let coupled = lobe == Lobe::AshikhminShirley;
    let target = if coupled { (Lobe::exponent(alpha) + 1.0) / (8.0 * PI) } else { 0.0 };
    for c in 0..3 {
        // The ridge is part of the objective (so of the residual that picks alpha too).
        let ridge = FRESNEL_RIDGE * g[c][2][2];
        g[c][3][3] += ridge;
        if coupled {
            // λ (k_s + k_f − t)²: the k_f² part is above.
            g[c][2][2] += ridge;
            g[c][2][3] += ridge;
            g[c][3][2] += ridge;
            b[c][2] += ridge * target;
            b[c][3] += ridge * target;
            ss[c] += ridge * target * target;
        }
        let (res, k) = nnls(&g[c], &b[c], ss[c]);
        total += res;
        penalty += if coupled { ridge * (k[2] + k[3] - target).powi(2) } else { ridge * k[3] * k[3] };
        coef[c] = k;
    }
    (total, coef, penalty)
}

/// Unknowns of the linear fit: ambient, diffuse, specular, Fresnel.
const N: usize = 4;

/// Non-negative least squares with [`N`] unknowns from its normal equations: every subset
/// of free unknowns (fifteen) is solved and the best feasible one kept. The residual is
/// $c - 2k^\top b + k^\top G k$.
fn nnls(g: &[[f64; N]; N], b: &[f64; N], c: f64) -> (f64, [f64; N]) {
    let residual = |k: &[f64; N]| {
        let mut r = c;
        for i in 0..N {
            r -= 2.0 * k[i] * b[i];
            for j in 0..N {
                r += k[i] * g[i][j] * k[j];
            }
        }
        r.max(0.0)
    };
    let mut best = ([0.0; N], residual(&[0.0; N]));
    for mask in 1u8..(1 << N) {
        let free: Vec<usize> = (0..N).filter(|&i| mask & (1 << i) != 0).collect();
        let n = free.len();
        let mut a = [[0.0f64; N + 1]; N];
        for (r, &i) in free.iter().enumerate() {
            for (k, &j) in free.iter().enumerate() {
                a[r][k] = g[i][j];
            }
            // A tiny ridge keeps a column that is zero on these samples (no lit sample, no
            // highlight) from making the system singular.
            a[r][r] += 1e-12 * (g[i][i] + 1e-300);
            a[r][n] = b[i];
        }
        let Some(x) = solve_small(&mut a, n) else { continue };
        if x.iter().take(n).any(|&v| v < 0.0 || !v.is_finite()) {
            continue;
        }
        let mut k = [0.0; N];
        for (r, &i) in free.iter().enumerate() {
            k[i] = x[r];
        }
        let res = residual(&k);
        if res < best.1 {
            best = (k, res);
        }
    }
    (best.1, best.0)
}

/// Gaussian elimination with partial pivoting on an n × (n+1) augmented system (n ≤ [`N`]),
/// the right-hand side in column n.
#[allow(clippy::needless_range_loop)] // index loops over a small array read best as the math
fn solve_small(a: &mut [[f64; N + 1]; N], n: usize) -> Option<[f64; N]> {
    for col in 0..n {
        let p = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, p);
        for r in col + 1..n {
            let f = a[r][col] / a[col][col];
            for k in col..=n {
                a[r][k] -= f * a[col][k];
            }
        }
    }
    let mut x = [0.0; N];
    for r in (0..n).rev() {
        let mut s = a[r][n];
        for k in r + 1..n {
            s -= a[r][k] * x[k];
        }
        x[r] = s / a[r][r];
    }
    Some(x)
}

/// A based fit: the lobe and the product fitted to $S / B$. [`Fit::errors`] are on $S$.
#[derive(Clone, Debug)]
pub struct BasedFit {
    pub base: Option<Base>,
    pub fit: Fit,
}

impl BasedFit {
    /// $B(l, v)\, m^{-1}(\prod p_j)$ at a query (the product alone without a base).
    pub fn eval(&self, settings: &super::Settings, q: &Query) -> [f64; 3] {
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

/// Fit a base of `choice` to `values` on `pattern`, then the product of `prepared` (which
/// must have been prepared on `pattern`) to $S / B$ under `mapping`. Under
/// [`Mapping::Auto`] each mapping is tried and the one with the lowest RMS on $S$ (not on
/// the ratio) kept, `inverted` only for a clear gain, as [`Prepared::solve`] does.
/// `one_view`: the samples are one painting's ([`choose`]).
pub fn solve_based(prepared: &Prepared, pattern: &Pattern, values: &[[f64; 3]], mapping: Mapping, choice: BaseChoice, one_view: bool) -> Result<BasedFit> {
    // Only `auto` judges the lobe against the free product, so only it needs that fit first.
    let plain = if choice == BaseChoice::Auto { Some(prepared.solve(values, mapping)?) } else { None };
    match choose_over(prepared, pattern, values, plain.as_ref(), choice, one_view) {
        Some((base, weight)) => solve_on_base(prepared, pattern, values, mapping, &base, weight),
        None => Ok(BasedFit { base: None, fit: match plain { Some(fit) => fit, None => prepared.solve(values, mapping)? } }),
    }
}

/// What the free product's fit tells of a painting, for [`choose`] under `auto`: the
/// roughness no smooth model holds, and the part of it that is texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Roughness {
    /// The free product's [`misfit`] on the values it was fitted to.
    pub misfit: f64,
    /// The part of the misfit the product can hold in its tables ([`texture`]), at most
    /// [`ROUGHNESS_MAX`].
    pub texture: f64,
}

/// The free product's [`Roughness`] on the values it was fitted to (`fit`, solved on
/// `prepared`).
pub fn product_roughness(prepared: &Prepared, pattern: &Pattern, values: &[[f64; 3]], fit: &Fit) -> Roughness {
    let predicted = prepared.predict(&fit.tables, &fit.map);
    let misfit = misfit(values, &predicted);
    Roughness { misfit, texture: texture(pattern, values, &predicted, misfit) }
}

/// [`choose`] for `values`, judged under `auto` against `plain`, the free product's fit of
/// them on `prepared` (its [`Roughness`]; read only under `auto`, the one choice that
/// judges a lobe against the product).
pub fn choose_over(prepared: &Prepared, pattern: &Pattern, values: &[[f64; 3]], plain: Option<&Fit>, choice: BaseChoice, one_view: bool) -> Option<(Base, f64)> {
    let product = plain.filter(|_| choice == BaseChoice::Auto).map_or(Roughness::default(), |fit| product_roughness(prepared, pattern, values, fit));
    choose(pattern, values, choice, product, one_view)
}

/// The lobe `choice` gives for `values` on `pattern`, and the weight of the product's
/// correction over it ([`solve_on_base`]): none for `none`; for `auto`, the lobe when what
/// it misfits beyond the painting's own roughness ([`excess`] over `product`, the free
/// product's [`Roughness`] on the same values; the default to judge the lobe alone) is at
/// most [`AUTO_MISFIT`], or, on one painting (`one_view`) not lit from the eye, at most
/// [`TEXTURE_CREDIT`] times its [`texture`]; the weight is 1 but there
/// ([`correction_weight`]).
pub fn choose(pattern: &Pattern, values: &[[f64; 3]], choice: BaseChoice, product: Roughness, one_view: bool) -> Option<(Base, f64)> {
    match choice {
        BaseChoice::None => None,
        BaseChoice::Ggx => Base::fit(pattern, values).map(|b| (b.0, 1.0)),
        BaseChoice::Auto => {
            // Not under a headlight, where every family holds the one angle a painting shows
            // through some function of it, and which is kept decides every other light.
            let one_view = one_view && !pattern.headlit();
            let roughness = product.misfit.min(ROUGHNESS_MAX);
            let limit = if one_view { AUTO_MISFIT.max(TEXTURE_CREDIT * product.texture) } else { AUTO_MISFIT };
            let (base, misfit) = Base::fit_any(pattern, values)?;
            let beyond = excess(misfit, product.misfit);
            let weight = if one_view { correction_weight(beyond, roughness) } else { 1.0 };
            (beyond <= limit).then_some((base, weight))
        }
    }
}

/// On one painting, l, h and v move together, and the free product holds the painting's
/// brush texture as well as its shading: rings in the tables along $\theta_h$ and
/// $\theta_l$ that a new light shows as bands. A lobe of a classic family cannot hold
/// them, so a painting with brush texture misfits a lobe of its own family by about as
/// much as the texture (0.05 at ±8%) beyond the product, and [`AUTO_MISFIT`] alone turned
/// most of them away. There a lobe is kept while [`excess`] is at most this many times the
/// painting's [`texture`] (what of its roughness the product can hold): faults study, brush
/// texture and the light 10° off, twelve brush seeds, nine models' held-out median (mean
/// over seeds) 0.0427 → 0.0214 with [`TEXTURE_SHRINK`]; every fault, sixteen seeds, 0.0593
/// → 0.0545 at 1.5 (BENCHMARKS.md, "Brush texture: the lobe over the rings"). 1.7 since
/// the texture is read through noise ([`texture`]): every fault, seeds 1–12, 0.0566 →
/// 0.0542, and 17–24 0.0529 → 0.0520; brush alone, strays, clean and MERL unchanged
/// (BENCHMARKS.md, "Brush texture through noise"). A Gooch painting, of no family, misses
/// by 2.3× its roughness with brush texture and 3.2× with every fault, and keeps the
/// product.
pub const TEXTURE_CREDIT: f64 = 1.7;

/// The texture in a painting's roughness: how much of the free product's misfit (`misfit`,
/// of `predicted` on `values`) is structure the product can hold in its tables, at most
/// [`ROUGHNESS_MAX`]. Grain independent from pixel to pixel is averaged away by every table
/// bin, so the product holds none of it, however strong. Two estimates, each blind where
/// the other sees, and the larger counts:
///
/// - the residual's covariance between neighbouring pixels ([`neighbours`]), in the
///   measure of [`misfit`]: brush texture runs along strokes, so its residual is alike from
///   one pixel to the next, and independent noise adds nothing to it (brush with 1% sRGB
///   noise reads 0.046 as without; the old reading, below alone, read 0 and kept no lobe:
///   held out 0.0374 → 0.0236, BENCHMARKS.md). But a sharp highlight a pixel or two wide,
///   whose residual changes sign from one pixel to the next, reads none;
/// - the misfit less [`GRAIN_WEIGHT`] times the [`grain`] (in quadrature), which reads
///   such sparse features as texture (a clean MERL painting's, where the lobe carries the
///   highlight to new lights: 0.2514 → 0.2320 from one painting), but counts dense noise
///   (heavy in the shadows) twice over, as more than the whole roughness.
pub fn texture(pattern: &Pattern, values: &[[f64; 3]], predicted: &[[f64; 3]], misfit: f64) -> f64 {
    let roughness = misfit.min(ROUGHNESS_MAX);
    let sparse = (roughness * roughness - (GRAIN_WEIGHT * grain(pattern, values)).powi(2)).max(0.0).sqrt();
    let Some((_, delta)) = softening(values) else { return 0.0 };
    let (mut covariance, mut energy) = (0.0, 0.0);
    for i in neighbours(pattern) {
        let (s, t, p, q) = (values[i], values[i + 1], predicted[i], predicted[i + 1]);
        for c in 0..3 {
            let w = 1.0 / ((s[c] + delta[c]) * (t[c] + delta[c]));
            covariance += (p[c] - s[c]) * (q[c] - t[c]) * w;
            energy += s[c] * t[c] * w;
        }
    }
    let alike = if energy > 0.0 { (covariance / energy).max(0.0).sqrt() } else { 0.0 };
    alike.min(ROUGHNESS_MAX).max(sparse)
}

/// The samples `i` whose next sample `i + 1` is its neighbouring pixel: their light and
/// view directions both lie within [`NEIGHBOUR_DEG`] (the next pixel of a painting's row;
/// not the first of the next row, nor of the next view).
fn neighbours(pattern: &Pattern) -> impl Iterator<Item = usize> + '_ {
    let near = NEIGHBOUR_DEG.to_radians().cos();
    pattern.queries.windows(2).enumerate().filter(move |(_, q)| q[0].l.dot(q[1].l) > near && q[0].v.dot(q[1].v) > near).map(|(i, _)| i)
}

/// The painting's grain: how much its values change from one pixel to the next, in the
/// relative measure of [`misfit`] ($(S_i - S_{i+1}) / (\bar S + \delta)$ per channel, of
/// [`neighbours`]), as a standard deviation per sample (the median absolute
/// difference over 0.6745, over $\sqrt 2$). Grain independent from pixel to pixel is
/// averaged away by every table bin, so the product holds none of it and its misfit is
/// the grain's; brush texture runs along strokes, changes little from one pixel to the next,
/// and the product holds part of it in rings. A velvet painting with 5% grain per pixel
/// misfits its best lobe (Oren-Nayar) by 0.039 beyond its product, as it does without the
/// grain: its sheen, of no family, not the grain.
pub fn grain(pattern: &Pattern, values: &[[f64; 3]]) -> f64 {
    let Some((_, delta)) = softening(values) else { return 0.0 };
    let mut d: Vec<f64> = Vec::with_capacity(3 * values.len());
    for i in neighbours(pattern) {
        let (s, t) = (values[i], values[i + 1]);
        d.extend((0..3).map(|c| (s[c] - t[c]).abs() / (0.5 * (s[c] + t[c]).max(0.0) + delta[c])));
    }
    if d.is_empty() {
        return 0.0;
    }
    let mid = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *median / 0.6745 / std::f64::consts::SQRT_2
}

/// How many times its [`grain`] a painting's roughness loses in [`texture`]'s second
/// estimate: the estimate reads low where the grain is strong (0.047 for
/// 5% grain per pixel, 0.086 for 10%), and a lobe of the wrong family taken for texture
/// costs more than a lobe left out (a velvet painting with 10% grain, with its Oren-Nayar
/// lobe: held out 0.176, against 0.028 with the product alone).
const GRAIN_WEIGHT: f64 = 2.0;

/// How close (degrees, in both the light's and the view's direction) consecutive samples
/// are neighbouring pixels ([`neighbours`]): a 128² sphere's pixels are 1–2° apart at its
/// centre.
const NEIGHBOUR_DEG: f64 = 5.0;

/// How much of the product's correction of a lobe is kept on one painting
/// ([`correction_weight`]): the roughness's power counts this many times against what the
/// lobe misses beyond it.
pub const TEXTURE_SHRINK: f64 = 2.0;

/// The weight $w$ of the product's correction over a lobe on one painting: the product is
/// fitted to $(S/B)^w$, its log-space correction scaled by
///
/// $$ w = \frac{e^2}{e^2 + k\,r^2}, $$
///
/// with $e$ the lobe's [`excess`] (what the lobe misses that the product holds), $r$ the
/// painting's roughness and $k$ = [`TEXTURE_SHRINK`]: the shrinkage of a correction
/// measured through noise of power $k r^2$ (a Wiener gain). Where the lobe misses nothing
/// beyond the texture the correction is texture, and goes; where it misses far more, the
/// correction is shading, and stays. A brushed Lambertian sphere kept its Phong lobe before
/// and its held-out error was 0.030, the product's rings; at this weight 0.015 (brush, 10°
/// off, seed 11). 1 when there is neither ($e = r = 0$).
pub fn correction_weight(excess: f64, roughness: f64) -> f64 {
    let (e2, r2) = (excess * excess, TEXTURE_SHRINK * roughness * roughness);
    if e2 + r2 > 0.0 {
        e2 / (e2 + r2)
    } else {
        1.0
    }
}

/// The product of `prepared` fitted to $S / B$ for a given lobe (the part of
/// [`solve_based`] after the lobe's fit): $B$ once per sample, then the prepared solve of
/// the ratio under each mapping, kept by its error on $S$. The ratio is raised to `weight`
/// ([`correction_weight`]; 1 fits it as it is), which scales the product's correction in
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
    let score = |m: &super::LogMap, e: &Errors| if matches!(m, super::LogMap::Inverted { .. }) { e.rms / (1.0 - INVERTED_MARGIN) } else { e.rms };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{Analytic, Reflectance, SphereView};

    /// A GGX sphere is recovered: the fitted lobe's $\alpha$ is the truth's within the
    /// search grid's step, and $B$ alone matches $S$ closely.
    #[test]
    fn fits_a_ggx_sphere() {
        let truth = Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.5, 0.5, 0.5], 0.2);
        let views: Vec<_> = [DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.6, 0.2, 0.8)].iter().map(|&l| SphereView::new(l, 64)).collect();
        let pattern = Pattern::concat(&views.iter().map(SphereView::pattern).collect::<Vec<_>>());
        let values = pattern.shade(|q| truth.shading(q));
        let (base, misfit) = Base::fit(&pattern, &values).expect("a fit");
        assert!(misfit < 1e-3, "misfit {misfit}");
        let step = (ALPHA_MAX / ALPHA_MIN).powf(1.0 / (ALPHAS - 1) as f64);
        assert!(base.alpha > 0.2 / step && base.alpha < 0.2 * step, "alpha {} for truth 0.2", base.alpha);
        let fitted = pattern.shade(|q| base.shading(q));
        let e = errors(&fitted, &values).rms_relative;
        assert!(e < 0.1, "relative RMS of the base alone {e}");
    }

    /// Each family's truth is told from the others and recovered: Blinn-Phong, Phong and
    /// Ashikhmin-Shirley (exponents 32, 50 and 100: α = √(2/(e + 2))), Ward, GGX,
    /// Oren-Nayar and Minnaert spheres from two views get their own lobe, their width within
    /// 2% and a misfit near zero; Oren-Nayar's σ = 0.5 comes back in its B/A.
    #[test]
    fn every_lobe_family_is_recovered_from_its_truth() {
        let views: Vec<_> = [DVec3::new(0.3, 0.4, 1.0), DVec3::new(-0.6, 0.2, 0.8)].iter().map(|&l| SphereView::new(l, 64)).collect();
        let pattern = Pattern::concat(&views.iter().map(SphereView::pattern).collect::<Vec<_>>());
        let cases = [
            (Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 32.0 }, Lobe::BlinnPhong, (2.0f64 / 34.0).sqrt()),
            (Analytic::Phong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 50.0 }, Lobe::Phong, (2.0f64 / 52.0).sqrt()),
            (Analytic::Ward { diffuse: [0.4, 0.3, 0.2], specular: [0.3; 3], alpha: 0.2 }, Lobe::Ward, 0.2),
            (Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.5, 0.5, 0.5], 0.04), Lobe::Ggx, 0.04),
            (Analytic::AshikhminShirley { diffuse: [0.5, 0.3, 0.15], specular: [0.1, 0.12, 0.15], exponent: 100.0 }, Lobe::AshikhminShirley, (2.0f64 / 102.0).sqrt()),
            // Oren-Nayar has no width (its σ is in B/A); the fit's nominal width is 1.
            (Analytic::OrenNayar { albedo: [0.6, 0.4, 0.3], sigma: 0.5 }, Lobe::OrenNayar, 1.0),
            (Analytic::Minnaert { albedo: [0.6, 0.4, 0.3], k: 0.75 }, Lobe::Minnaert, 0.75),
        ];
        for (truth, lobe, alpha) in cases {
            let values = pattern.shade(|q| truth.shading(q));
            let (base, misfit) = Base::fit_any(&pattern, &values).expect("a fit");
            assert_eq!(base.lobe, lobe, "{}", truth.name());
            assert!((base.alpha / alpha - 1.0).abs() < 0.02 && misfit < 1e-3, "{}: alpha {} for {alpha}, misfit {misfit}", truth.name(), base.alpha);
            if lobe == Lobe::OrenNayar {
                // A = 1 − 0.5σ²/(σ² + 0.33), B = 0.45σ²/(σ² + 0.09) at σ = 0.5: B/A = 0.4132.
                let (a, b) = (1.0 - 0.5 * 0.25 / 0.58, 0.45 * 0.25 / 0.34);
                assert!((base.specular[1] / base.diffuse[1] - b / a).abs() < 1e-3, "{base:?}");
            }
            if lobe == Lobe::AshikhminShirley {
                // Its own Fresnel, though these lights show θ_d ≤ 30°: k_f = (n + 1)/(8π)(1 − R_s)
                // = 101/(8π) × 0.9 = 3.617 in red, and k_s = 101/(8π) × 0.1 = 0.402.
                let norm = 101.0 / (8.0 * std::f64::consts::PI);
                for (c, rs) in [0.1, 0.12, 0.15].into_iter().enumerate() {
                    assert!((base.specular[c] / (norm * rs) - 1.0).abs() < 0.02, "{base:?}");
                    assert!((base.fresnel[c] / (norm * (1.0 - rs)) - 1.0).abs() < 0.02, "{base:?}");
                }
            }
        }
    }

    /// `excess`, worked by hand: 0.05 against a product's 0.04 is √(0.0025 − 0.0016) = 0.03;
    /// a lobe that fits better than the product has none; no product (0) leaves the lobe's
    /// own misfit; a product that misses by 0.5 is credited only [`ROUGHNESS_MAX`].
    #[test]
    fn excess_is_the_misfit_beyond_the_roughness() {
        assert!((excess(0.05, 0.04) - 0.03).abs() < 1e-12);
        assert_eq!(excess(0.03, 0.05), 0.0);
        assert_eq!(excess(0.012, 0.0), 0.012);
        assert!((excess(0.3, 0.5) - (0.09f64 - ROUGHNESS_MAX * ROUGHNESS_MAX).sqrt()).abs() < 1e-12);
        // `misfit` is relative: a prediction 10% high everywhere misfits by 0.1 whatever the
        // weights, and one 10% high on half the samples (of equal weight) by 0.1/√2.
        let values = vec![[1.0, 0.5, 0.25]; 10];
        let m = misfit(&values, &values.iter().map(|v| v.map(|x| 1.1 * x)).collect::<Vec<_>>());
        assert!((m - 0.1).abs() < 1e-12, "{m}");
        let half: Vec<[f64; 3]> = values.iter().enumerate().map(|(i, v)| if i % 2 == 0 { v.map(|x| 1.1 * x) } else { *v }).collect();
        assert!((misfit(&values, &half) - 0.1 / 2f64.sqrt()).abs() < 1e-12);
    }

    /// [`texture`] is what neighbouring pixels share: on a painting whose prediction is the
    /// truth, 10% noise independent per pixel misfits by 0.1 and is no texture; stripes of
    /// ±5% along the rows (32 pixels a period) misfit by 0.05/√2 and are all texture.
    #[test]
    fn texture_is_what_neighbours_share() {
        let truth = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let pattern = SphereView::new(DVec3::new(0.3, 0.4, 1.0), 128).pattern();
        let clean = pattern.shade(|q| truth.shading(q));
        let mut rng = crate::demo::brush::SplitMix::new(3);
        let noisy: Vec<[f64; 3]> = clean.iter().map(|v| v.map(|x| x * (1.0 + 0.1 * rng.normal()))).collect();
        let m = misfit(&noisy, &clean);
        let t = texture(&pattern, &noisy, &clean, m);
        assert!((m - 0.1).abs() < 0.01 && t < 0.02, "noise: misfit {m}, texture {t}");
        let striped: Vec<[f64; 3]> = clean.iter().enumerate().map(|(i, v)| v.map(|x| x * (1.0 + 0.05 * (std::f64::consts::TAU * i as f64 / 32.0).sin()))).collect();
        let m = misfit(&striped, &clean);
        let t = texture(&pattern, &striped, &clean, m);
        assert!((m - 0.05 / 2f64.sqrt()).abs() < 0.003 && (t - m).abs() < 0.05 * m, "stripes: misfit {m}, texture {t}");
    }

    /// nnls on a problem with a known non-negative solution and one with a clamped unknown.
    #[test]
    fn nnls_solves_and_clamps() {
        // G = I, b = (1, 2, 3, 4): k = b, residual c - |b|² = 0.
        let mut g = [[0.0; N]; N];
        for (i, row) in g.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        let (r, k) = nnls(&g, &[1.0, 2.0, 3.0, 4.0], 30.0);
        assert!(k.iter().zip([1.0, 2.0, 3.0, 4.0]).all(|(a, b)| (a - b).abs() < 1e-9) && r < 1e-9, "{k:?} {r}");
        // b = (1, -2, 3, 4): the second unknown is clamped at zero.
        let (_, k) = nnls(&g, &[1.0, -2.0, 3.0, 4.0], 30.0);
        assert!(k[1] == 0.0 && (k[0] - 1.0).abs() < 1e-9 && (k[2] - 3.0).abs() < 1e-9 && (k[3] - 4.0).abs() < 1e-9, "{k:?}");
    }
}
