//! Which lobe, if any, a painting gets under the product ([`crate::material::based`]), and
//! how much of the product's correction over it is kept: the reading's judgement of what in
//! a painting is shading and what is the painting's own roughness (brush texture, noise).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::brdf::lobe::Base;
use crate::brdf::lobe_fit::{misfit, softening};
use crate::error::{Error, Result};
use crate::factor::{Fit, Mapping, Pattern, Prepared};
use crate::material::based::{solve_on_base, BasedFit};

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


/// A uniform material over an analytic base ([`crate::material::based`]): the lobe
/// of `choice` fitted to `values`, then the product of `prepared` (prepared on `pattern`
/// with `settings`) fitted to $S / B$. The prepared system is the one of the plain fit:
/// the base changes only the right-hand side. `None` when `choice` gives no base (`none`,
/// or `auto` when the lobe does not fit the samples): keep the plain fit then.
/// `plain` is the product's own fit of `values` on `prepared`: `auto` judges the lobe
/// against its misfit (the painting's roughness, [`excess`]).
/// `one_view`: the samples are one painting's, where the product holds brush texture as
/// well as shading ([`TEXTURE_CREDIT`]).
/// `provenance.errors` is replaced by the based fit's errors on $S$.
// The fit's inputs, each the caller's: bundling them would only rename them.
#[allow(clippy::too_many_arguments)]
pub fn fit_based(
    prepared: &crate::factor::Prepared,
    pattern: &crate::factor::Pattern,
    values: &[[f64; 3]],
    plain: &crate::factor::Fit,
    settings: &crate::factor::Settings,
    mapping: crate::factor::Mapping,
    choice: BaseChoice,
    one_view: bool,
    provenance: crate::material::Provenance,
) -> Result<Option<crate::material::Material>> {
    // No lobe, no second solve: the plain fit stands.
    let Some((base, weight)) = choose_over(prepared, pattern, values, Some(plain), choice, one_view) else {
        return Ok(None);
    };
    let fit = solve_on_base(prepared, pattern, values, mapping, &base, weight)?;
    let provenance = crate::material::Provenance { errors: Some(fit.fit.errors), ..provenance };
    crate::material::Material::from_based_fit(settings, &fit, provenance).map(Some)
}


#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{Analytic, Reflectance, SphereView};
    use glam::DVec3;

    /// `excess`, worked by hand: 0.05 against a product's 0.04 is √(0.0025 − 0.0016) = 0.03;
    /// a lobe that fits better than the product has none; no product (0) leaves the lobe's
    /// own misfit; a product that misses by 0.5 is credited only [`ROUGHNESS_MAX`].
    #[test]
    fn excess_is_the_misfit_beyond_the_roughness() {
        assert!((excess(0.05, 0.04) - 0.03).abs() < 1e-12);
        assert_eq!(excess(0.03, 0.05), 0.0);
        assert_eq!(excess(0.012, 0.0), 0.012);
        assert!((excess(0.3, 0.5) - (0.09f64 - ROUGHNESS_MAX * ROUGHNESS_MAX).sqrt()).abs() < 1e-12);
    }

    /// [`texture`] is what neighbouring pixels share: on a painting whose prediction is the
    /// truth, 10% noise independent per pixel misfits by 0.1 and is no texture; stripes of
    /// ±5% along the rows (32 pixels a period) misfit by 0.05/√2 and are all texture.
    #[test]
    fn texture_is_what_neighbours_share() {
        let truth = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let pattern = SphereView::new(DVec3::new(0.3, 0.4, 1.0), 128).pattern();
        let clean = pattern.shade(|q| truth.shading(q));
        let mut rng = crate::util::SplitMix::new(3);
        let noisy: Vec<[f64; 3]> = clean.iter().map(|v| v.map(|x| x * (1.0 + 0.1 * rng.normal()))).collect();
        let m = misfit(&noisy, &clean);
        let t = texture(&pattern, &noisy, &clean, m);
        assert!((m - 0.1).abs() < 0.01 && t < 0.02, "noise: misfit {m}, texture {t}");
        let striped: Vec<[f64; 3]> = clean.iter().enumerate().map(|(i, v)| v.map(|x| x * (1.0 + 0.05 * (std::f64::consts::TAU * i as f64 / 32.0).sin()))).collect();
        let m = misfit(&striped, &clean);
        let t = texture(&pattern, &striped, &clean, m);
        assert!((m - 0.05 / 2f64.sqrt()).abs() < 0.003 && (t - m).abs() < 0.05 * m, "stripes: misfit {m}, texture {t}");
    }
}
