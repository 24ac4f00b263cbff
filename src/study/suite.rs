//! The wide suite of issue 15 ([`Analytic::wide_suite`]) painted on the analytic sphere and
//! judged on views nobody painted, rim and side light among them: the study that chooses
//! factor settings (`cargo run --release --example suite`; BENCHMARKS.md, "The wide suite").
//!
//! Paintings are the first one or three of [`painted_views`] at 100² (about 7.9k samples
//! each, the size of the thesis's Table 5.1). Each model is fitted with
//! [`Mapping::Auto`] on one prepared system, and its fit is compared with the true shading
//! function at every pixel of [`held_out`]: the relative RMS over all of them pooled, and per
//! view, since a rim-lit view's few bright pixels weigh little in the pool.

use glam::DVec3;

use super::{median, relative_rms};
use crate::brdf::{held_out_views, painted_views, Analytic, Reflectance, SphereView};
use crate::error::Result;
use crate::read::lobe::{solve_based, BaseChoice};
use crate::factor::{prepare, Mapping, Pattern, Settings};

/// Pixels per side of a painted view.
pub const PAINTED_RES: usize = 100;
/// Pixels per side of a held-out view.
pub const HELD_OUT_RES: usize = 48;

/// The held-out views, named: the three of [`held_out_views`], then light from behind the
/// object (the "rim" preset's light, 150° from the camera) and from the side (82°).
pub fn held_out(res: usize) -> Vec<(&'static str, SphereView)> {
    let mut out: Vec<(&'static str, SphereView)> = ["held-1", "held-2", "held-3"].into_iter().zip(held_out_views(res)).collect();
    out.push(("rim", SphereView::new(DVec3::new(0.3, 0.5, -1.0), res)));
    out.push(("side", SphereView::new(DVec3::new(1.0, 0.3, 0.15), res)));
    out
}

/// One model of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub model: String,
    /// Relative RMS on the painted samples.
    pub train: f64,
    /// Relative RMS over every held-out view's pixels together.
    pub held_out: f64,
    /// Relative RMS per held-out view, in the order of [`held_out`].
    pub views: Vec<f64>,
}

impl Row {
    /// The largest per-view error and its view's name.
    pub fn worst_view(&self) -> (&'static str, f64) {
        let names = held_out(2);
        self.views.iter().zip(&names).map(|(&e, (n, _))| (*n, e)).fold(("", f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a })
    }
}

/// The standard paintings: the first `n` (1 to 3) of [`painted_views`]. Their lights are
/// 35°, 44° and 57° from the camera; with a distant light and camera each painting shows one
/// $\theta_d$, half that angle (18°, 22°, 28°).
pub fn paintings(n: usize) -> Vec<SphereView> {
    painted_views(n, PAINTED_RES)
}

/// Three paintings that also see grazing light: the standard key light, then light from the
/// side (101° from the camera) and from behind (153°), so $\theta_d$ reaches 77°. What a
/// factor of $\theta_d$ needs to learn a Fresnel or grazing term (none of the held-out views
/// uses these lights).
pub fn wide_paintings() -> Vec<SphereView> {
    vec![
        painted_views(1, PAINTED_RES)[0],
        SphereView::new(DVec3::new(-1.0, 0.2, -0.2), PAINTED_RES),
        SphereView::new(DVec3::new(-0.4, -0.3, -1.0), PAINTED_RES),
    ]
}

/// Fit every model from `painted` views with `settings` and judge it.
pub fn measure(models: &[Analytic], settings: &Settings, painted: &[SphereView]) -> Result<Vec<Row>> {
    measure_based(models, settings, painted, BaseChoice::None)
}

/// [`measure`] with an analytic base under the product ([`crate::brdf::lobe`]).
pub fn measure_based(models: &[Analytic], settings: &Settings, painted: &[SphereView], base: BaseChoice) -> Result<Vec<Row>> {
    let pattern = Pattern::concat(&painted.iter().map(SphereView::pattern).collect::<Vec<_>>());
    let named: Vec<(String, &dyn Reflectance)> = models.iter().map(|m| (m.name(), m as &dyn Reflectance)).collect();
    measure_on_based(&pattern, &named, settings, base, painted.len() == 1)
}

/// MERL-style dense sampling: the (light, view) grid of `fit --merl` at density `k`
/// ([`crate::brdf::merl_grid`], $2k^3$ pairs; 16 gives about 8k).
pub fn dense(k: usize) -> Result<Pattern> {
    Ok(Pattern::new(crate::brdf::merl_grid(k)?.into_iter().map(|(l, v)| crate::factor::Query::at(l, v)).collect(), false))
}

/// Fit every named reflectance from its values on `pattern` with `settings`, and judge it on
/// [`held_out`].
pub fn measure_on(pattern: &Pattern, models: &[(String, &dyn Reflectance)], settings: &Settings) -> Result<Vec<Row>> {
    measure_on_based(pattern, models, settings, BaseChoice::None, false)
}

/// [`measure_on`] with a base under the product: one prepared system for every model and
/// both choices, since the base changes only the values (the right-hand side).
/// `one_view`: `pattern` is one painting's ([`crate::read::lobe::choose`]).
pub fn measure_on_based(pattern: &Pattern, models: &[(String, &dyn Reflectance)], settings: &Settings, base: BaseChoice, one_view: bool) -> Result<Vec<Row>> {
    let prepared = prepare(pattern, settings)?;
    let views: Vec<Vec<crate::factor::Query>> =
        held_out(HELD_OUT_RES).iter().map(|(_, v)| v.pixels().into_iter().map(|p| p.query).collect()).collect();
    let mut rows = Vec::new();
    for (name, model) in models {
        let values = pattern.shade(|q| model.shading(q));
        let fit = solve_based(&prepared, pattern, &values, Mapping::Auto, base, one_view)?;
        let pairs = |qs: &[crate::factor::Query]| qs.iter().map(|q| (fit.eval(settings, q), model.shading(q))).collect::<Vec<_>>();
        let per_view: Vec<f64> = views.iter().map(|qs| relative_rms(pairs(qs))).collect();
        let pooled = relative_rms(views.iter().flat_map(|qs| pairs(qs)));
        rows.push(Row { model: name.clone(), train: fit.fit.errors.rms_relative, held_out: pooled, views: per_view });
    }
    Ok(rows)
}

/// The sharp case of issue 15: GGX with $\alpha = 0.05$, a highlight about 2° wide in
/// $\theta_h$.
pub fn sharp_model() -> Analytic {
    Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.50, 0.42, 0.35], 0.05)
}

/// Pixels per side of the held-out views that judge a highlight's peak: fine enough that
/// the 2° highlight of [`sharp_model`] covers several pixels.
pub const PEAK_RES: usize = 160;

/// The highlight's peak on each held-out view of [`held_out`] (at [`PEAK_RES`]): the
/// largest fitted and true value of $S$ (the sum of its channels) over the view's pixels,
/// as (view, fitted, true). The fit is from `painted` views with `settings`.
pub fn peaks(model: &Analytic, settings: &Settings, painted: &[SphereView]) -> Result<Vec<(&'static str, f64, f64)>> {
    peaks_based(model, settings, painted, BaseChoice::None)
}

/// [`peaks`] with a base under the product.
pub fn peaks_based(model: &Analytic, settings: &Settings, painted: &[SphereView], base: BaseChoice) -> Result<Vec<(&'static str, f64, f64)>> {
    let pattern = Pattern::concat(&painted.iter().map(SphereView::pattern).collect::<Vec<_>>());
    let values = pattern.shade(|q| model.shading(q));
    let fit = solve_based(&prepare(&pattern, settings)?, &pattern, &values, Mapping::Auto, base, painted.len() == 1)?;
    let sum = |x: [f64; 3]| x[0] + x[1] + x[2];
    Ok(held_out(PEAK_RES)
        .into_iter()
        .map(|(name, view)| {
            let (mut fitted, mut truth) = (0.0f64, 0.0f64);
            for p in view.pixels() {
                fitted = fitted.max(sum(fit.eval(settings, &p.query)));
                truth = truth.max(sum(model.shading(&p.query)));
            }
            (name, fitted, truth)
        })
        .collect())
}

/// Summary of a study: the median of the pooled held-out errors and the worst view of any
/// model.
pub fn summary(rows: &[Row]) -> (f64, f64) {
    let med = median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
    let worst = rows.iter().map(|r| r.worst_view().1).fold(0.0, f64::max);
    (med, worst)
}

/// The named factor settings the study compares (the example's argument).
pub fn candidates() -> Vec<(&'static str, Settings)> {
    vec![
        ("default", Settings::default()),
        ("unwarped", Settings::warped(1.0)),
        ("theta-d", Settings::with_difference(32)),
        ("half-difference-32", Settings::half_difference(32)),
        ("half-difference-64", Settings::half_difference(64)),
        ("half-difference-32-warped", {
            let mut s = Settings::half_difference(32);
            s.factors[1].warp = crate::factor::defaults::WARP_HALF;
            s
        }),
        ("warp-2", Settings::warped(2.0)),
        ("warp-3", Settings::warped(3.0)),
        ("warp-4", Settings::warped(4.0)),
    ]
}
