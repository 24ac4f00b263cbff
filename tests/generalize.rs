//! Fidelity on views that were not painted (DESIGN.md, Quality bars): the analytic suite is
//! painted on a sphere, fitted with the default settings, and compared with the true BRDF
//! under held-out lights and cameras.

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{held_out_views, painted_views, Analytic};
use brdfpaint::study::sphere_rms;
use brdfpaint::factor::{prepare, Mapping, Pattern, Settings};

/// Held-out relative RMS of every suite model fitted from `views` painted views with the
/// default 1D factors.
fn suite_errors(views: usize) -> Vec<(String, f64)> {
    suite_errors_with(views, &Settings::default())
}

fn suite_errors_with(views: usize, settings: &Settings) -> Vec<(String, f64)> {
    let patterns: Vec<Pattern> = painted_views(views, 100).iter().map(|v| v.pattern()).collect();
    let pattern = Pattern::concat(&patterns);
    let prepared = prepare(&pattern, settings).unwrap();
    Analytic::suite()
        .into_iter()
        .map(|model| {
            let values = pattern.shade(|q| model.shading(q));
            let fit = prepared.solve(&values, Mapping::Auto).unwrap();
            let e = sphere_rms(&held_out_views(40), |q| model.shading(q), |q| fit.eval(settings, q));
            (model.name(), e)
        })
        .collect()
}

fn median(errors: &[(String, f64)]) -> f64 {
    let mut e: Vec<f64> = errors.iter().map(|x| x.1).collect();
    e.sort_by(f64::total_cmp);
    e[e.len() / 2]
}

#[test]
fn one_painted_view_generalizes_to_new_lights_and_views() {
    let errors = suite_errors(1);
    // Bounds from the conditioning study (BENCHMARKS.md), with headroom: the median over
    // the suite, the models that are exact products, and a cap on the worst.
    assert!(median(&errors) < 0.04, "{errors:?}");
    for (name, e) in &errors {
        let bound = match name.as_str() {
            "lambert" | "gooch" => 0.01,
            _ => 0.2,
        };
        assert!(*e < bound, "{name}: held-out relative RMS {e} (bound {bound}); all: {errors:?}");
    }
}

#[test]
fn three_painted_views_generalize_better_than_one() {
    let (one, three) = (suite_errors(1), suite_errors(3));
    assert!(median(&three) < 0.02, "{three:?}");
    assert!(median(&three) < median(&one), "one {one:?} three {three:?}");
}

#[test]
fn two_dimensional_factors_generalize_from_three_views() {
    // 2D tables have far more freedom than one view constrains (BENCHMARKS.md: the median
    // is near 0.9 from one view), so they are judged with three.
    let errors = suite_errors_with(3, &Settings::uniform(2, brdfpaint::factor::defaults::RES_2D));
    assert!(median(&errors) < 0.08, "{errors:?}");
}

/// Issue 15's sharp case: GGX with α = 0.05 (a highlight about 2° wide) fitted from the
/// three standard paintings with the default settings. On the three held-out views that see
/// the highlight near the normal, the fitted peak must be within 15% of the true one
/// (measured 1.049, 0.956, 0.929; BENCHMARKS.md, "The wide suite"). The thesis's unwarped
/// q(h) puts the 2° on one node and misses held-1 by 31% (asserted below, so this test
/// tells the two tables apart). The rim and side views' grazing highlights are out of reach
/// of any table the paintings determine (0.2 and 0.8 of the truth) and are not judged here;
/// the next test reaches them with the lobe and paintings that show grazing light.
#[test]
fn a_sharp_highlight_peaks_within_15_percent_on_held_out_views() {
    use brdfpaint::study::suite::{paintings, peaks, sharp_model};
    let model = sharp_model();
    let ratios = |settings: &Settings| -> Vec<(&'static str, f64)> {
        peaks(&model, settings, &paintings(3)).unwrap().into_iter().take(3).map(|(v, fit, truth)| (v, fit / truth)).collect()
    };
    for (view, r) in ratios(&Settings::default()) {
        assert!((r - 1.0).abs() <= 0.15, "{view}: fitted peak / true peak = {r:.3}");
    }
    let unwarped = ratios(&Settings::warped(1.0));
    assert!(unwarped.iter().any(|(_, r)| (r - 1.0).abs() > 0.15), "{unwarped:?}");
}

/// The same sphere with the default base (`auto`, a GGX lobe under the product): the peak
/// is within 15% on every held-out view, the rim and side light too, when one of the three
/// paintings is lit from the side and one from behind (`wide_paintings`: θ_d up to 77°, so
/// the paintings show the Fresnel). Measured: 0.999 / 1.000 / 1.000 / 0.998 / 1.000. From
/// the standard three (θ_d ≤ 28°) the rim's peak is 0.769 of the truth, since no painting
/// shows how much brighter the highlight grows at grazing θ_d (asserted: the test sees the
/// difference; `fit` says so in a note).
#[test]
fn a_sharp_highlight_peaks_within_15_percent_on_every_view_from_paintings_that_show_grazing_light() {
    use brdfpaint::read::lobe::BaseChoice;
    use brdfpaint::study::suite::{paintings, peaks_based, sharp_model, wide_paintings};
    let model = sharp_model();
    let ratios = |painted: Vec<brdfpaint::brdf::SphereView>| -> Vec<(&'static str, f64)> {
        peaks_based(&model, &Settings::default(), &painted, BaseChoice::Auto).unwrap().into_iter().map(|(v, fit, truth)| (v, fit / truth)).collect()
    };
    let wide = ratios(wide_paintings());
    assert_eq!(wide.len(), 5);
    for (view, r) in &wide {
        assert!((r - 1.0).abs() <= 0.15, "{view}: fitted peak / true peak = {r:.3}");
    }
    let standard = ratios(paintings(3));
    assert!(standard.iter().any(|(v, r)| *v == "rim" && *r < 0.85), "{standard:?}");
}

/// Issue 15's analytic base (`brdf::lobe`): a GGX sphere (roughness 0.2, α = 0.04) from
/// the three standard paintings, judged on the rim-light view no painting resembles. With
/// the default `auto` base the lobe fits the paintings (misfit below 1e-4) and carries the
/// masking and 1/(cos θ_l cos θ_v) to the rim: measured rim error 0.23 (all five views
/// pooled 0.025) against 0.71 (0.128) for the plain product. The bounds leave margin on
/// both and tell the two apart; the rim keeps 0.23 because the paintings (θ_d ≤ 28°) cannot
/// show the truth's Fresnel, so the base has none.
#[test]
fn an_analytic_base_carries_a_ggx_sphere_to_rim_light() {
    use brdfpaint::brdf::Analytic;
    use brdfpaint::read::lobe::BaseChoice;
    use brdfpaint::study::suite::{measure_based, paintings};
    let model = [Analytic::Ggx { diffuse: [0.40, 0.25, 0.12], f0: [0.50, 0.42, 0.35], roughness: 0.2 }];
    let rim = 3; // study::suite::held_out's order: held-1..3, rim, side
    let based = &measure_based(&model, &Settings::default(), &paintings(3), BaseChoice::Auto).unwrap()[0];
    let plain = &measure_based(&model, &Settings::default(), &paintings(3), BaseChoice::None).unwrap()[0];
    assert!(based.views[rim] < 0.45 && based.held_out < 0.06, "based: rim {:.3}, pooled {:.3}", based.views[rim], based.held_out);
    assert!(plain.views[rim] > 0.6, "plain: rim {:.3}", plain.views[rim]);
}

/// Issue 11 on issue 15's base: a painting with grain is evidence of a lobe too. One
/// painting of a GGX sphere (roughness 0.7) with 5% multiplicative grain per pixel misfits
/// its own lobe by the grain, but the grain does not recur from one block of the painting to
/// another, so the lobe predicts held-out blocks as well as the product does and `auto` keeps
/// it (`read::lobe::choose`): the fit carries it to lights and views nobody painted. A grainy
/// velvet painting (a sheen of no lobe family) is fitted no worse than by the product alone.
/// Judged against the clean truth on the suite's five held-out views.
#[test]
fn a_grainy_painting_keeps_the_lobe_its_grain_explains() {
    use brdfpaint::read::lobe::{solve_based, BaseChoice, Blocks};
use brdfpaint::brdf::lobe::Base;
    use brdfpaint::study::relative_rms;
    use brdfpaint::study::suite::{held_out, paintings};
    let settings = Settings::default();
    let pattern = Pattern::concat(&paintings(1).iter().map(|v| v.pattern()).collect::<Vec<_>>());
    let prepared = prepare(&pattern, &settings).unwrap();
    let views: Vec<Vec<brdfpaint::factor::Query>> = held_out(48).iter().map(|(_, v)| v.pixels().into_iter().map(|p| p.query).collect()).collect();
    let mut rng = brdfpaint::demo::brush::SplitMix::new(11);
    let mut judge = |model: &Analytic, grain: f64| {
        let values: Vec<[f64; 3]> = pattern.shade(|q| model.shading(q)).into_iter().map(|v| v.map(|x| x * (grain * rng.normal()).exp())).collect();
        let (_, lobe) = Base::fit(&pattern, &values).unwrap();
        let held = |choice| {
            let fit = solve_based(&prepared, &pattern, &values, Mapping::Auto, choice, &Blocks::of_directions(&pattern)).unwrap();
            let e = relative_rms(views.iter().flatten().map(|q| (fit.eval(&settings, q), model.shading(q))));
            (fit.base.is_some(), e)
        };
        (lobe, held(BaseChoice::Auto), held(BaseChoice::None).1)
    };
    let ggx = Analytic::Ggx { diffuse: [0.40, 0.25, 0.12], f0: [0.50, 0.42, 0.35], roughness: 0.7 };
    let (lobe, (kept, auto), none) = judge(&ggx, 0.05);
    eprintln!("ggx: lobe misfit {lobe:.4}, kept {kept}, held-out auto {auto:.4}, none {none:.4}");
    assert!(lobe > 0.04, "the grain should misfit the lobe alone: {lobe:.4}");
    assert!(kept && auto < 0.5 * none, "ggx: kept {kept}, held-out auto {auto:.4}, none {none:.4}");
    let velvet = Analytic::Velvet { diffuse: [0.30, 0.05, 0.12], sheen: [0.60, 0.35, 0.50], roughness: 0.35 };
    for grain in [0.05, 0.10] {
        let (lobe, (kept, auto), none) = judge(&velvet, grain);
        eprintln!("velvet, {grain} grain: lobe misfit {lobe:.4}, kept {kept}, held-out auto {auto:.4}, none {none:.4}");
        assert!(auto <= 1.1 * none, "velvet, {grain} grain: kept {kept}, held-out auto {auto:.4}, none {none:.4}");
    }
}

/// Issue 15's targets on the 23-model wide suite, with the default `auto` base (a lobe of
/// the family that explains the paintings, when one does: `brdf::lobe::Lobe`), judged on
/// the five held-out views pooled: one painting median ≤ 0.03, three paintings ≤ 0.015 (the
/// issue's targets); BENCHMARKS.md states 0.0001 and 0.0000, held here to their printed
/// digits (the plain product: 0.0843 and 0.0330). A Phong sphere, which no
/// table of θ_h holds, is carried to the rim light by its Phong lobe from one painting
/// (measured rim view 0.0000, plain 0.687).
#[test]
fn the_wide_suite_meets_its_one_and_three_painting_targets() {
    use brdfpaint::read::lobe::BaseChoice;
    use brdfpaint::study::suite::{measure_based, paintings};
    let models = Analytic::wide_suite();
    let median_of = |rows: &[brdfpaint::study::suite::Row]| brdfpaint::study::median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
    let one = measure_based(&models, &Settings::default(), &paintings(1), BaseChoice::Auto).unwrap();
    let three = measure_based(&models, &Settings::default(), &paintings(3), BaseChoice::Auto).unwrap();
    let (m1, m3) = (median_of(&one), median_of(&three));
    eprintln!("wide suite, auto base: median held-out from one painting {m1:.4}, from three {m3:.4}");
    assert!(m1 < 1.5e-4 && m3 < 5e-5, "one painting {m1:.4}, three {m3:.4} (stated 0.0001, 0.0000)");
    let phong = one.iter().find(|r| r.model == "phong-50").unwrap();
    let plain = &measure_based(&[models.iter().find(|m| m.name() == "phong-50").unwrap().clone()], &Settings::default(), &paintings(1), BaseChoice::None).unwrap()[0];
    let rim = 3; // study::suite::held_out's order: held-1..3, rim, side
    eprintln!("phong-50 from one painting: rim view {:.4} with its lobe, {:.4} plain", phong.views[rim], plain.views[rim]);
    assert!(phong.views[rim] < 0.01 && plain.views[rim] > 0.4, "rim {:.4} vs plain {:.4}", phong.views[rim], plain.views[rim]);
    // The worst held-out view from three paintings (issue 15: ≤ 0.3). Ashikhmin-Shirley's
    // rim light is its Fresnel, which the standard paintings (θ_d ≤ 28°) do not show: the
    // family's own, coupled to R_s, carries it (0.608 when its lobe had none).
    let worst = three.iter().map(|r| r.worst_view()).fold(("", 0.0), |a, b| if b.1 > a.1 { b } else { a });
    let ashikhmin = three.iter().find(|r| r.model == "ashikhmin-shirley-100").unwrap();
    eprintln!("worst view from three paintings: {worst:?}; ashikhmin-shirley-100 rim {:.4}", ashikhmin.views[rim]);
    assert!(worst.1 <= 0.3 && ashikhmin.views[rim] < 0.01, "worst {worst:?}, ashikhmin-shirley-100 rim {:.4}", ashikhmin.views[rim]);
}

/// README: from the wide suite's three wide paintings (key, side and back light) the median
/// held-out error with the default base is 0.0000 whether a factor of θ_d is added or not
/// (printed to four decimals: below 5e-5), and the 20 models of a lobe family (all but
/// velvet and the two Gooch models) are within 0.001 (measured: GGX 0.0004–0.0010, the rest
/// below 1e-4). The fits are deterministic; the bounds are the stated precision.
#[test]
fn the_wide_suite_from_wide_paintings_is_exact_with_the_base() {
    use brdfpaint::factor::{DifferenceChoice, Pattern};
    use brdfpaint::read::lobe::BaseChoice;
    use brdfpaint::study::suite::{measure_based, wide_paintings};
    let models = Analytic::wide_suite();
    let wide = wide_paintings();
    let pattern = Pattern::concat(&wide.iter().map(|v| v.pattern()).collect::<Vec<_>>());
    for choice in [DifferenceChoice::Off, DifferenceChoice::Auto] {
        let (settings, added) = choice.apply(&Settings::default(), &pattern);
        let rows = measure_based(&models, &settings, &wide, BaseChoice::Auto).unwrap();
        let m = brdfpaint::study::median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
        let of_no_family = |name: &str| matches!(name, "velvet-0.35" | "gooch" | "gooch-specular");
        let family: Vec<(&str, f64)> = rows.iter().filter(|r| !of_no_family(&r.model)).map(|r| (r.model.as_str(), r.held_out)).collect();
        let worst = family.iter().cloned().fold(("", 0.0), |a, b| if b.1 > a.1 { b } else { a });
        eprintln!("wide paintings, θ_d {choice:?} (added: {added}): median {m:.6}; worst of a family {worst:?}");
        assert!(m < 5e-5, "θ_d {choice:?}: median {m}");
        assert_eq!(family.len(), 20);
        assert!(worst.1 < 1e-3, "θ_d {choice:?}: {worst:?}");
    }
}
