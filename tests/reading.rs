//! Paintings read as evidence (issue 11, `read::Reader`): a shading painted a few degrees
//! off the scene's light is fitted with the painter's light (`read::register`), and flat
//! tones are read as the smooth shading between their edges (`read::tones`). Judged
//! against the clean truth: the painter's true light, the clean painting, held-out views.

use brdfpaint::brdf::Analytic;
use brdfpaint::brdf::lobe::Lobe;
use brdfpaint::factor::{Mapping, Settings};
use brdfpaint::read::Reading;
use brdfpaint::read::{register, strays, tones};
use brdfpaint::sample::SceneSampler;
use brdfpaint::scene::Light;
use brdfpaint::study::faults::{self, FaultyView, Faults};
use brdfpaint::study::fidelity::{held_out_presets, painted_presets, StudyView};
use brdfpaint::study::median;
use glam::DVec3;

const SIZE: usize = 128;

fn light_of(view: &StudyView) -> DVec3 {
    match view.scene.light {
        Light::Directional { direction, .. } => direction.as_dvec3().normalize(),
        Light::Point { .. } => panic!("the study's presets have directional lights"),
    }
}

fn held_out_median(f: &Faults, reading: Reading) -> f64 {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, f.light_off_deg).unwrap()];
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(&painted, &held, &faults::suite(), &Settings::default(), f, &plain, reading, brdfpaint::read::lobe::BaseChoice::Auto).unwrap();
    median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>())
}

#[test]
fn the_painters_light_is_found_within_two_degrees() {
    let mut sampler = SceneSampler::new().unwrap();
    let preset = painted_presets(1)[0];
    let view = FaultyView::new(&mut sampler, &preset, SIZE, 10.0).unwrap();
    let painter = light_of(&view.shading);
    let scene = light_of(&view.view);
    let off = scene.angle_between(painter).to_degrees();
    // The light turned 10° about the vertical axis is this far from the scene's.
    assert!(off > 6.0, "{off}");
    for model in [Analytic::Lambert { albedo: [0.8, 0.5, 0.3] }, Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 128.0 }] {
        let mut views = vec![faults::paint(&view, &model, &Faults::misregistered()).unwrap()];
        let turns = register::register(&mut views, &[&view.view.gbuffer], &Settings::default()).unwrap();
        let found = turns[0].rotation * scene;
        let error = found.angle_between(painter).to_degrees();
        eprintln!("{}: turned {:.2}°, {:.2}° from the painter's light; fit {:.4} -> {:.4}", model.name(), turns[0].degrees, error, turns[0].before, turns[0].after);
        assert!(turns[0].moved(), "{}", model.name());
        assert!(error < 2.0, "{}: {error}° from the painter's light", model.name());
        assert!(turns[0].after < 0.5 * turns[0].before, "{}: {:?}", model.name(), turns[0]);
    }
}


/// The views read as `fit` reads them (`read::Reader`), in place; the notes as lines.
fn read_views(views: &mut Vec<brdfpaint::sample::PaintedView>, gbuffers: &[&brdfpaint::render::GBuffer]) -> Vec<String> {
    let evidence = brdfpaint::read::Reader::new(Reading::default(), gbuffers).read(std::mem::take(views)).unwrap();
    *views = evidence.views;
    evidence.notes.iter().map(|n| n.to_string()).collect()
}

/// Minnaert and Oren-Nayar paintings shade their limbs by the view as well as the light,
/// which the proxy cannot: its light alone was 0.7–1.5° off, and the held-out error many
/// times a Lambertian painting's. Refined under the lobe family that holds them
/// (`register`'s `refine_on_lobe`), they are found as closely as the others.
#[test]
fn a_limb_shaded_paintings_light_is_found_closer_than_by_the_proxy() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 10.0).unwrap();
    let (painter, scene) = (light_of(&view.shading), light_of(&view.view));
    for model in faults::suite().into_iter().filter(|m| m.name().starts_with("minnaert") || m.name().starts_with("oren-nayar")) {
        let mut views = vec![faults::paint(&view, &model, &Faults::misregistered()).unwrap()];
        let turns = register::register(&mut views, &[&view.view.gbuffer], &Settings::default()).unwrap();
        let error = (turns[0].rotation * scene).angle_between(painter).to_degrees();
        eprintln!("{}: turned {:.2}°, {:.2}° from the painter's light", model.name(), turns[0].degrees, error);
        // Measured at 128²: Oren-Nayar 0.68° → 0.10°, Minnaert 1.48° → 0.53°.
        let bound = if model.name().starts_with("minnaert") { 0.65 } else { 0.3 };
        assert!(error < bound, "{}: {error}° from the painter's light", model.name());
    }
}

#[test]
fn a_consistent_painting_keeps_its_light() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 0.0).unwrap();
    for f in [Faults::clean(), Faults::brush()] {
        for model in faults::suite() {
            let mut views = vec![faults::paint(&view, &model, &f).unwrap()];
            let before = views[0].geometry.clone();
            let turns = register::register(&mut views, &[&view.view.gbuffer], &Settings::default()).unwrap();
            assert!(!turns[0].moved(), "{} ({f:?}) turned {:.2}°", model.name(), turns[0].degrees);
            assert_eq!(views[0].geometry, before, "{}", model.name());
        }
    }
}

#[test]
fn registered_paintings_generalize_to_held_out_views() {
    let f = Faults::misregistered();
    let as_given = held_out_median(&f, Reading { smooth_tones: false, register_light: false, repaint_strays: false });
    let read = held_out_median(&f, Reading::default());
    eprintln!("light 10° off: as given {as_given:.5}, registered {read:.5}");
    // README: "A painting shaded 10° off: held-out error 0.116 → 0.0015" (this study, the
    // nine models' median, 128²). The fits are deterministic: held at those values within
    // half their last digit plus 2%.
    let agrees = |measured: f64, stated: f64, digit: f64| (measured - stated).abs() <= digit / 2.0 + 0.02 * stated;
    assert!(agrees(as_given, 0.116, 1e-3), "as given {as_given:.5}, README 0.116");
    assert!(agrees(read, 0.0015, 1e-4), "registered {read:.5}, README 0.0015");
}

/// Flat tones painted under a light 10° off the scene's: the light is registered on the
/// steps as painted (`read::Reader`), where the interpolation between tone edges held it
/// back (5–7° found of the 8° the untoned painting gives) and the tones were then read
/// through families that make up for it (Minnaert 0.19 held out at 256²).
#[test]
fn toned_paintings_lit_off_the_scenes_light_are_registered_on_their_steps() {
    let f = Faults { levels: 6, ..Faults::misregistered() };
    let read = held_out_median(&f, Reading::default());
    eprintln!("6 levels, light 10° off: registered {read:.4}");
    // Measured at 128²: 0.0716 registered on the interpolation, 0.0333 on the steps (256²:
    // 0.0629 and 0.0276; 0.0273 with the painter's light).
    assert!(read < 0.045, "{read}");
}

/// A posterized painting of `model` (6 levels per channel) read as `read::Reader` reads
/// tones: between tone edges (`tones::smooth`), then through a lobe family or the proxy
/// (`tones::refine`). Returns what was read, the painting's relative RMS against the clean one
/// as painted, between edges and refined, and the family read through.
fn read_tones(view: &FaultyView, model: &Analytic) -> (tones::Toned, [f64; 3], Option<(Lobe, f64)>) {
    let clean = faults::paint(view, model, &Faults::clean()).unwrap();
    let mut toned = faults::paint(view, model, &Faults::posterized()).unwrap();
    let samples = toned.geometry.sample_pixels(&toned.painting);
    let error = |p: &brdfpaint::images::Painting| {
        let (mut se, mut s) = (0.0, 0.0);
        for &k in &samples {
            for c in 0..3 {
                se += (p.pixels[k][c] as f64 - clean.painting.pixels[k][c] as f64).powi(2);
                s += (clean.painting.pixels[k][c] as f64).powi(2);
            }
        }
        (se / s).sqrt()
    };
    let before = error(&toned.painting);
    let read = tones::smooth(&mut toned).expect("6 levels per channel are flat tones");
    let between = error(&toned.painting);
    let family = tones::refine(&mut toned, &read, None);
    let refined = error(&toned.painting);
    (read, [before, between, refined], family)
}

#[test]
fn flat_tones_are_read_as_the_smooth_shading() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 0.0).unwrap();
    let model = Analytic::Lambert { albedo: [0.8, 0.5, 0.3] };
    let (read, [before, after, refined], _) = read_tones(&view, &model);
    eprintln!("levels {:?}: relative RMS against the clean painting {before:.4} -> {after:.4} -> {refined:.4} (through the proxy)", read.levels);
    assert!(read.levels.iter().all(|&n| n <= 6), "{:?}", read.levels);
    // Measured at 128²: 0.190 -> 0.099 between edges (levels 6, 5, 4) -> 0.018 through the
    // proxy (a Lambertian painting is in its span).
    assert!(after < 0.6 * before, "{before} -> {after}");
    assert!(refined < 0.3 * after, "{after} -> {refined}");

    // Two tones are a toon style: kept as painted.
    let mut toon = faults::paint(&view, &model, &Faults { levels: 2, ..Faults::clean() }).unwrap();
    let pixels = toon.painting.pixels.clone();
    assert!(tones::smooth(&mut toon).is_none());
    assert_eq!(toon.painting.pixels, pixels);
    // A painted gradient is not toned.
    let mut smooth = faults::paint(&view, &model, &Faults::clean()).unwrap();
    assert!(tones::smooth(&mut smooth).is_none());
}

/// A highlight sharper than the proxy's Blinn-Phong lobes (GGX α = 0.04, 6 levels per
/// channel) is read with its own family's microfacet lobe (`read::tones`): the painting read closer to the
/// clean one than the tone edges alone say, and the fit from it closer to the truth on
/// held-out views.
#[test]
fn a_sharp_highlight_in_flat_tones_is_read_with_a_microfacet_lobe() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 0.0).unwrap();
    let model = Analytic::Ggx { diffuse: [0.40, 0.25, 0.12], f0: [0.50, 0.42, 0.35], roughness: 0.2 };
    let (_, [before, between, refined], family) = read_tones(&view, &model);
    assert_eq!(family.map(|f| f.0), Some(Lobe::Ggx), "{family:?}");
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(std::slice::from_ref(&view), &held, std::slice::from_ref(&model), &Settings::default(), &Faults::posterized(), &plain, Reading::default(), brdfpaint::read::lobe::BaseChoice::Auto).unwrap();
    eprintln!("ggx 0.2, 6 levels: relative RMS against the clean painting {before:.4} -> {between:.4} -> {refined:.4}; held-out {:.4}", rows[0].held_out);
    // Measured at 128²: the tone edges 0.263, through the Blinn-Phong lobes 0.294 (held-out
    // 0.294), through the microfacet lobe 0.100 (held-out 0.105).
    assert!(refined < 0.5 * between, "{between} -> {refined}");
    assert!(rows[0].held_out < 0.15, "held-out {}", rows[0].held_out);
}

/// A `size`² painting of `model` in 6 flat tones per channel, front-left: the notes reading
/// it gives, and the held-out error of the material `fit` makes of it.
fn posterized(model: &Analytic, size: usize) -> (Vec<String>, f64) {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], size, 0.0).unwrap();
    let mut views = vec![faults::paint(&view, model, &Faults::posterized()).unwrap()];
    let notes = read_views(&mut views, &[&view.view.gbuffer]);
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, size).unwrap()).collect();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(std::slice::from_ref(&view), &held, std::slice::from_ref(model), &Settings::default(), &Faults::posterized(), &plain, Reading::default(), brdfpaint::read::lobe::BaseChoice::Auto).unwrap();
    eprintln!("{}, 6 levels, {size}²: held-out {:.4}; {notes:#?}", model.name(), rows[0].held_out);
    (notes, rows[0].held_out)
}

/// Six flat tones of an Oren-Nayar sphere (a rough diffuse whose lit side is flatter than
/// Lambert's) are held by an Oren-Nayar lobe far better than by the proxy's Blinn-Phong lobes
/// (`read::tones`, lobe families): `fit` says so in a note, and the material from the
/// painting generalizes to held-out lights and views far better than read through the proxy.
#[test]
fn flat_tones_are_read_through_the_lobe_family_that_holds_them() {
    let (notes, held_out) = posterized(&Analytic::OrenNayar { albedo: [0.8, 0.55, 0.35], sigma: 0.5 }, SIZE);
    assert!(notes.iter().any(|n| n.contains("held best by the oren-nayar lobe: read through it")), "{notes:#?}");
    // Measured: 0.058 through the proxy (256², before lobe families), 0.0086 through the
    // Oren-Nayar lobe (256²), 0.0084 at 128².
    assert!(held_out < 0.025, "held-out {held_out}");
}

/// A posterized Minnaert sphere (limb darkening, which the proxy that registers the light
/// does not hold) painted under the scene's light: the interpolation between its tone edges
/// is explained better by a light turned 13°, but its tones are held far better under the
/// scene's own (`tones::held`), so the light is kept, and the material generalizes.
#[test]
fn a_toned_paintings_light_is_judged_on_its_tones() {
    // The faults study's painting (256²): at 128² the interpolation is not turned.
    let model = faults::suite().into_iter().find(|m| m.name() == "minnaert-0.75").unwrap();
    let (notes, held_out) = posterized(&model, 256);
    assert!(!notes.iter().any(|n| n.contains("looks lit")), "{notes:#?}");
    // Measured at 256²: 0.29 with the turned light, 0.026 with the scene's (read through
    // the Minnaert lobe).
    assert!(held_out < 0.2, "held-out {held_out}");
}

#[test]
fn toned_paintings_generalize_better_read_smooth() {
    let f = Faults::posterized();
    let as_given = held_out_median(&f, Reading { smooth_tones: false, register_light: false, repaint_strays: false });
    let read = held_out_median(&f, Reading { smooth_tones: true, register_light: false, repaint_strays: false });
    eprintln!("6 levels: as given {as_given:.4}, read smooth {read:.4}");
    // Measured at 256²: 0.181 as given, 0.086 read smooth (0.165 between tone edges alone,
    // before the physical proxy).
    assert!(read < 0.65 * as_given, "{read} against {as_given}");
}

#[test]
fn stray_strokes_are_repainted_and_clean_paintings_are_not() {
    let f = Faults::strays();
    let as_given = held_out_median(&f, Reading { smooth_tones: false, register_light: false, repaint_strays: false });
    let read = held_out_median(&f, Reading::default());
    eprintln!("strays: as given {as_given:.4}, repainted {read:.4}");
    // Measured at 256²: 0.106 as given, 0.013 repainted (0.073 and 0.0056 at 128²). Before
    // the ends of strokes across the outline counted as strays (`strays::keep_strokes`),
    // 0.052 and 0.025.
    assert!(read < 0.012, "{read}");
    assert!(read < 0.6 * as_given, "{read} against {as_given}");

    // Consistent paintings, brushed or not, keep every pixel as painted.
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 0.0).unwrap();
    for f in [Faults::clean(), Faults::brush(), Faults::noisy()] {
        for model in faults::suite() {
            let mut views = vec![faults::paint(&view, &model, &f).unwrap()];
            let pixels = views[0].painting.pixels.clone();
            let found = strays::repaint(&mut views, &Settings::default(), &[]).unwrap();
            assert!(found.is_none(), "{} ({f:?}): {found:?}", model.name());
            assert_eq!(views[0].painting.pixels, pixels, "{}", model.name());
        }
    }
    // Nor do single-view renders of the wide suite, under the standard and the side, rim
    // and headlight presets' lights.
    let preset = |name: &str| brdfpaint::scene::preset(name).unwrap();
    for preset in [painted_presets(1)[0], preset("side"), preset("rim"), preset("front")] {
        let view = FaultyView::new(&mut sampler, &preset, SIZE, 0.0).unwrap();
        for model in Analytic::wide_suite() {
            let mut views = vec![faults::paint(&view, &model, &Faults::clean()).unwrap()];
            let found = strays::repaint(&mut views, &Settings::default(), &[]).unwrap();
            assert!(found.is_none(), "{} ({preset:?}): {:?} strays", model.name(), found.map(|f| f.per_view[0].len()));
        }
    }
}

/// A glossy sphere in flat tones is a dark body round a few rings of highlight, which the
/// smooth tables miss by far more than the rest. Before `strays` kept highlights, the GGX
/// 0.2 painting with every fault had its highlight repainted at brush seeds 4, 5 and 6 of
/// eight (held-out error 0.96–1.03; all 137 of the highlight's pixels at seed 4): the
/// stray strokes at the outline must still be found, and at most a tenth of the highlight
/// (where the clean painting is above a tenth of its peak; 3 of 137 now, at its rim)
/// repainted.
#[test]
fn a_highlight_in_flat_tones_is_not_a_stray() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], 256, 10.0).unwrap();
    let model = faults::suite().into_iter().find(|m| m.name() == "ggx-0.2").unwrap();
    let clean = faults::paint(&view, &model, &Faults { brush: 0.0, strays: 0, noise: 0.0, levels: 0, ..Faults::all() }).unwrap();
    let peak = clean.painting.pixels.iter().map(|p| p[1]).fold(0.0, f32::max);
    let area = clean.painting.pixels.iter().filter(|p| p[1] > 0.1 * peak).count();
    for seed in [4, 5, 6] {
        let f = Faults { seed, ..Faults::all() };
        let mut views = vec![faults::paint(&view, &model, &f).unwrap()];
        let toned = tones::smooth(&mut views[0]).expect("toned");
        let found = strays::repaint(&mut views, &Settings::default(), &[Some(&toned)]).unwrap().expect("strays");
        let highlight = found.per_view[0].iter().filter(|&&k| clean.painting.pixels[k][1] > 0.1 * peak).count();
        let theta_h = |k: usize| views[0].geometry.pixels[k].as_ref().map(|p| (p.query.l + p.query.v).normalize().z.acos().to_degrees());
        let outline = found.per_view[0].iter().filter(|&&k| theta_h(k).is_some_and(|t| t > 40.0)).count();
        eprintln!("seed {seed}: {} repainted, {highlight} of the highlight's {area}, {outline} beyond 40° of θ_h", found.per_view[0].len());
        assert!(highlight * 10 <= area, "seed {seed}: {highlight} of {area}");
        assert!(outline > 500, "seed {seed}: {outline}");
    }
}

/// In flat tones, a stroke one tone off the shading under it (a black stroke over a dim rim,
/// a colour near the material's) changes a pixel by a few percent of the peak, under the log
/// ratio's floor: it is found through its tone, the fit lying outside the painted tone's
/// interval (`strays::TONE_TAIL`). Judged on the pixels the strokes put in another tone (the
/// painting with and without them, posterized alike), every fault but the light at 256²
/// (seed 11), summed over the nine models: the search misses 420 of the 7540 (1145 by the log
/// ratio alone), and takes 7390 others (3673), mostly the strokes' soft rims posterized to
/// the tone under them, which a toned view's strays widen into (`strays::TONED_RIM`): in flat
/// tones they are left out, where pixels taken too cost nothing and pixels missed cost
/// most (BENCHMARKS.md, "Strokes in flat tones"). Before that widening, 760 missed and 3939
/// others.
#[test]
fn strokes_one_tone_off_are_found_through_their_tones() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], 256, 0.0).unwrap();
    let f = Faults::all();
    let (mut visible, mut hits, mut base, mut false_hits, mut base_false) = (0, 0, 0, 0, 0);
    for model in faults::suite() {
        let without = faults::paint(&view, &model, &Faults { strays: 0, noise: 0.0, ..f.clone() }).unwrap();
        let with = faults::paint(&view, &model, &Faults { noise: 0.0, ..f.clone() }).unwrap();
        let stroked: std::collections::HashSet<usize> =
            (0..with.painting.pixels.len()).filter(|&k| with.geometry.usable[k] && with.painting.pixels[k] != without.painting.pixels[k]).collect();
        let mut by_tone = vec![faults::paint(&view, &model, &f).unwrap()];
        let toned = tones::smooth(&mut by_tone[0]).expect("toned");
        let mut by_ratio = by_tone.clone();
        let count = |found: Option<strays::Strays>| {
            let found = found.map(|s| s.per_view[0].clone()).unwrap_or_default();
            let hit = found.iter().filter(|k| stroked.contains(k)).count();
            (hit, found.len() - hit)
        };
        let (h, fh) = count(strays::repaint(&mut by_tone, &Settings::default(), &[Some(&toned)]).unwrap());
        let (b, fb) = count(strays::repaint(&mut by_ratio, &Settings::default(), &[]).unwrap());
        eprintln!("{}: {} stroked, through the tones {h} found ({fh} others), by the ratio alone {b} ({fb})", model.name(), stroked.len());
        (visible, hits, base, false_hits, base_false) = (visible + stroked.len(), hits + h, base + b, false_hits + fh, base_false + fb);
    }
    eprintln!("all: {visible} stroked, through the tones {hits} found ({false_hits} others), by the ratio alone {base} ({base_false})");
    assert!(((visible - hits) as f64) < 0.5 * (visible - base) as f64, "missed {} against {}", visible - hits, visible - base);
    // Rims, not regions: at most about one pixel round each stroke more.
    assert!((false_hits as f64) < 2.5 * base_false as f64, "{false_hits} others against {base_false}");
}

/// GGX 0.2 in flat tones with every fault. At brush seed 5 the proxy search finds the
/// painter's light (8° off the scene's), but the factored fit, its misfit dominated by the
/// stray strokes, gains only 8% from it (a turn needs 10%, and half when the fit stays
/// poor), and after the strays are repainted the search finds 2.5°; the tones' edges are
/// missed by 0.217 under the scene's light and 0.019 under the 8° turn. At seed 6 the fit
/// gains 31% from the 8° turn after the strays, the tones 40%: the two judges agree. At
/// seed 4 the search goes 20° the wrong way in both passes; the turn toward the light that
/// puts the brightest tone at the mirror point is judged on the tones instead. Taken, the
/// highlight sits where it was painted: held-out error 0.835 → 0.321 (seed 4), 0.852 →
/// 0.232 (5) and 0.996 → 0.460 (6). Since a toned painting's strays are left out and it is
/// read again (`read::Reader`), the factored fit sees the 8° turn itself at seeds 4 and 5
/// (0.134 and 0.183); at seed 6 the second reading explains nothing and the first is kept.
#[test]
fn a_toned_paintings_light_is_taken_from_its_tones_when_the_fit_cannot_tell() {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, 256).unwrap()).collect();
    for (seed, bound) in [(4, 0.45), (5, 0.35), (6, 0.6)] {
        let f = Faults { seed, ..Faults::all() };
        let painted = FaultyView::new(&mut sampler, &painted_presets(1)[0], 256, f.light_off_deg).unwrap();
        let model = faults::suite().into_iter().find(|m| m.name() == "ggx-0.2").unwrap();
        let mut views = vec![faults::paint(&painted, &model, &f).unwrap()];
        let notes = read_views(&mut views, &[&painted.view.gbuffer]);
        // Judged on the tones, or, once a toned painting's strays are left out and it is read
        // again (`read::Reader`), on the factored fit, which then sees the turn itself (seed
        // 4: 0.249 → 0.078 with the light turned 8°).
        let turn = notes.iter().find(|n| n.contains(" lit ") && n.contains("° away")).unwrap_or_else(|| panic!("seed {seed}: {notes:#?}"));
        let degrees: f64 = turn.split(" lit ").nth(1).and_then(|r| r.split('°').next()).and_then(|d| d.parse().ok()).unwrap();
        assert!((6.0..=10.0).contains(&degrees), "seed {seed}: {turn}");
        let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
        let rows = faults::measure(&[painted], &held, &[model], &Settings::default(), &f, &plain, Reading::default(), brdfpaint::read::lobe::BaseChoice::Auto).unwrap();
        eprintln!("seed {seed}: {turn}\nheld-out {:.4}", rows[0].held_out);
        assert!(rows[0].held_out < bound, "seed {seed}: {}", rows[0].held_out);
    }
}

#[test]
fn paintings_with_every_fault_generalize() {
    let mut sampler = SceneSampler::new().unwrap();
    let f = Faults::all();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, f.light_off_deg).unwrap()];
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(&painted, &held, &faults::suite(), &Settings::default(), &f, &plain, Reading::default(), brdfpaint::read::lobe::BaseChoice::Auto).unwrap();
    let held_out = median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
    let worst = rows.iter().map(|r| r.worst_view).fold(0.0, f64::max);
    eprintln!("all faults: held-out median {held_out:.4}, worst view {worst:.3}");
    // Measured: median 0.074, worst view 0.30 at 256² (0.074 and 0.46 at 128²); before the
    // proxy read tones and strays were repainted, 0.160 and 1.28 at 256².
    assert!(held_out < 0.09, "{held_out}");
    assert!(worst < 1.0, "{worst}");
}

/// The tones' reading is a least-squares fit to their intervals, and a few sites it cannot
/// hold (a stroke the stray search left, a highlight's core the brush brightened past every
/// lobe) bent it for all the rest; it now reads the tones again without the sites it misses
/// by more than their interval's width. Every fault at the brush seeds where that mattered
/// most at this size (128², the nine models' held-out medians): seeds 2, 5 and 6 0.118,
/// 0.083 and 0.089 before, 0.071, 0.057 and 0.084 now (the study's eight seeds at 256²:
/// 0.0713 → 0.0671, mean of medians).
#[test]
fn tones_the_shading_does_not_explain_do_not_bend_their_reading() {
    let medians: Vec<f64> = [2, 5, 6].iter().map(|&seed| held_out_median(&Faults { seed, ..Faults::all() }, Reading::default())).collect();
    eprintln!("every fault, brush seeds 2, 5 and 6: held-out medians {medians:.4?}");
    let mean = medians.iter().sum::<f64>() / 3.0;
    assert!(mean < 0.085, "{mean}");
}

#[test]
fn reading_notes_name_the_painting() {
    let mut sampler = SceneSampler::new().unwrap();
    let view = FaultyView::new(&mut sampler, &painted_presets(1)[0], SIZE, 10.0).unwrap();
    let model = Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.5; 3], exponent: 128.0 };
    let mut views = vec![faults::paint(&view, &model, &Faults::all()).unwrap()];
    let notes = read_views(&mut views, &[&view.view.gbuffer]);
    eprintln!("{notes:#?}");
    assert!(notes.iter().any(|n| n.starts_with(&views[0].name) && n.contains("flat tones")), "{notes:?}");
    assert!(notes.iter().any(|n| n.starts_with(&views[0].name) && n.contains("stray strokes")), "{notes:?}");
}
