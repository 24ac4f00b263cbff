//! Paintings lit from the eye (issue 11). With the light at the camera, θ_l, θ_h and θ_v
//! move together and one painting fixes only the product of the factors along that
//! diagonal; `fit` then draws the light factor to its physical shape
//! (`Settings::for_pattern`) and keeps the lobe's ambient only where the painting clearly
//! shows one (`Base::fit_any`). Judged against the clean truth on held-out lights and views,
//! and by light sweeps: a material painted lit from the front darkens when the light moves
//! behind it.

use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::factor::{Mapping, Pattern, Query, Settings};
use brdfpaint::read::Reading;
use brdfpaint::sample::SceneSampler;
use brdfpaint::scene::preset;
use brdfpaint::study::faults::{self, FaultyView, Faults, Row};
use brdfpaint::study::fidelity::{held_out_presets, StudyView};
use glam::DVec3;

const SIZE: usize = 128;

/// The faults study's rows for `models` painted under the `front` preset (the light at the
/// camera) with `f`, read and fitted as `brdfpaint fit` does.
fn headlit(f: &Faults, models: &[&str]) -> Vec<Row> {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let painted = [FaultyView::new(&mut sampler, &preset("front").unwrap(), SIZE, f.light_off_deg).unwrap()];
    let models: Vec<_> = faults::suite().into_iter().filter(|m| models.contains(&m.name().as_str())).collect();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(&painted, &held, &models, &Settings::default(), f, &plain, Reading::default(), BaseChoice::Auto).unwrap();
    for r in &rows {
        eprintln!("{:<16} train {:.4} held-out {:.4} worst view {:.3} sweep {:.2} {}", r.model, r.train, r.held_out, r.worst_view, r.sweep, r.map);
    }
    rows
}

/// A headlit Lambertian sphere with stray strokes, black ones among them. Without the light
/// prior the light and half-vector factors traded a slope (p rose ×3·10⁴ toward grazing
/// light, q fell as much), the bound cut one of them, and the fit missed its own samples
/// entirely (relative RMS 0.9986 with the identity mapping; held-out 1.03 with the mapping
/// `auto` kept).
#[test]
fn a_headlit_painting_with_black_strokes_does_not_collapse() {
    let rows = headlit(&Faults::strays(), &["lambert"]);
    // Collapsed, the fit was 1.03 held out; it holds 0.105 at 128² (BENCHMARKS.md: a headlit
    // painting's held-out blocks test no other light, so the lobe's choice is weakly judged).
    assert!(rows[0].held_out < 0.12, "held-out {}", rows[0].held_out);
    assert!(rows[0].sweep <= 0.5, "sweep {}", rows[0].sweep);
}

/// Every analytic model of the faults study but Gooch (whose cool unlit side is what it
/// should keep), painted lit from the front at 128², clean and with each fault of the study
/// and all of them together: the light sweep's darkest frame over its brightest, held at
/// what README states. At most 0.435 (README: 0.43; issue 11's target 0.5) except two:
/// painted with the light 10° off, Minnaert's 0.485 (README: 0.49); in six flat tones a
/// headlit Minnaert painting does not darken at all (1.00, held-out 0.60: README says so,
/// and this test fails when that changes, so README can follow). With brush texture or
/// every fault, the held-out error stays under 0.4 (without the prior and the headlit lobe
/// rule: 0.62–0.89).
#[test]
fn headlit_paintings_darken_when_the_light_moves_behind() {
    const DARKEST: f64 = 0.435;
    let names: Vec<String> = faults::suite().iter().map(|m| m.name()).filter(|n| n != "gooch").collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    assert_eq!(names.len(), 8, "{names:?}");
    let mut failures = Vec::new();
    for (case, f) in Faults::cases() {
        for r in headlit(&f, &names) {
            eprintln!("{case:<14} {:<16} sweep {:.4}", r.model, r.sweep);
            let ok = match (case, r.model.as_str()) {
                ("light 10° off", "minnaert-0.75") => r.sweep <= 0.49,
                ("6 levels", "minnaert-0.75") => r.sweep >= 0.995,
                _ => r.sweep <= DARKEST,
            };
            if !ok {
                failures.push(format!("{} ({case}): sweep {:.4}", r.model, r.sweep));
            }
            if matches!(case, "brush" | "all") {
                assert!(r.held_out < 0.4, "{} ({case}): held-out {}", r.model, r.held_out);
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The headlit rule, worked by hand: a pattern is headlit when most of its samples see the
/// light within 30° of the eye, and only then gets the light prior.
#[test]
fn headlit_samples_get_the_light_prior() {
    let at = |deg: f64| {
        let t = deg.to_radians();
        Query::at(DVec3::new(t.sin(), 0.0, t.cos()), DVec3::Z)
    };
    let pattern = |angles: &[f64]| Pattern::new(angles.iter().map(|&a| at(a)).collect(), false);
    let lit = pattern(&[0.0, 10.0, 29.0, 80.0]);
    let side = pattern(&[0.0, 10.0, 31.0, 80.0]);
    assert!(lit.headlit());
    assert!(!side.headlit(), "two of four within 30° is not most");
    let s = Settings::default();
    assert_eq!(s.for_pattern(&side), s);
    let prior = s.for_pattern(&lit);
    assert_eq!(prior.light_prior, Some(brdfpaint::factor::defaults::LIGHT_FLOOR));
    assert_eq!(prior.factors[0].damp, brdfpaint::factor::defaults::DAMP_HEADLIT);
    assert_eq!(prior.factors[1..], s.factors[1..]);
    // A prior the settings already have is kept (lit spheres choose their own).
    let sphere = brdfpaint::litsphere::settings(&s, brdfpaint::litsphere::LIGHT_FLOOR, 0.0);
    assert_eq!(sphere.for_pattern(&lit), sphere);
}

/// Stray strokes on headlit paintings are found and repainted: the detection's own fit
/// gets the light prior too. Without it, that fit missed the median sample of a headlit
/// painting by a log ratio of about 1, no stroke stood out, and 8 of the 9 models kept
/// every stroke (on GGX 0.2 the highlight was repainted instead).
#[test]
fn stray_strokes_on_headlit_paintings_are_repainted() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &preset("front").unwrap(), SIZE, 0.0).unwrap();
    for name in ["lambert", "blinn-phong-128"] {
        let model = faults::suite().into_iter().find(|m| m.name() == name).unwrap();
        let mut views = vec![faults::paint(&view, &model, &Faults::strays()).unwrap()];
        let found = brdfpaint::read::strays::repaint(&mut views, &Settings::default(), &[]).unwrap();
        let n = found.map_or(0, |f| f.per_view[0].len());
        eprintln!("{name}: {n} pixels repainted");
        // Measured at 128²: 231 and 209 pixels (0 and 0 without the prior).
        assert!(n > 50, "{name}: {n} pixels repainted");
    }
    let rows = headlit(&Faults::strays(), &["blinn-phong-128"]);
    // Measured: 0.0036 (0.148 at 256² with the strokes kept).
    assert!(rows[0].held_out < 0.05, "held-out {}", rows[0].held_out);
}

/// `fit` says when the paintings are headlit, and what would pin the material down: a note
/// in the material's provenance (and on the terminal). Front-left paintings get none.
#[test]
fn fit_says_when_the_paintings_are_headlit() {
    let mut sampler = SceneSampler::new().unwrap();
    let model = faults::suite().into_iter().find(|m| m.name() == "lambert").unwrap();
    for (name, headlit) in [("front", true), ("front-left", false)] {
        let view = FaultyView::new(&mut sampler, &preset(name).unwrap(), SIZE, 0.0).unwrap();
        let views = vec![faults::paint(&view, &model, &Faults::clean()).unwrap()];
        let opts = brdfpaint::pipeline::Options { base: BaseChoice::Auto, ..Default::default() };
        let fitted = brdfpaint::pipeline::fit(&views, &opts, None).unwrap();
        let notes = &fitted.material.provenance.notes;
        assert_eq!(notes.iter().any(|n| n.contains("lit from the eye") && n.contains("side light")), headlit, "{name}: {notes:#?}");
    }
}

/// A headlit painting's light is judged by `fit`'s own fit of it (with the light prior):
/// judged without, the fit of a headlit painting with stray strokes collapsed (relative RMS
/// 1.000) and any turn explained it "better": a sphere with four strokes was turned 20°, the
/// Oren-Nayar painting with the study's strokes 1° (0.909 → 0.015). Brushed and stroked
/// headlit paintings of rough diffuse materials keep the scene's light.
#[test]
fn a_headlit_painting_keeps_its_light() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &preset("front").unwrap(), SIZE, 0.0).unwrap();
    for f in [Faults::strays(), Faults::brush()] {
        for name in ["lambert", "oren-nayar-0.5", "minnaert-0.75"] {
            let model = faults::suite().into_iter().find(|m| m.name() == name).unwrap();
            let views = vec![faults::paint(&view, &model, &f).unwrap()];
            let gbuffers = [&view.view.gbuffer];
            let notes = brdfpaint::read::Reader::new(Reading::default(), &gbuffers).read(views).unwrap().notes;
            assert!(!notes.iter().any(|n| matches!(n, brdfpaint::note::Note::LightTurned { .. })), "{name} ({f:?}): {notes:#?}");
        }
    }
}
