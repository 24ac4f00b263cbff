//! The fit of hand-made paintings (issue 11): `Prepared::solve_robust` on paintings with the
//! faults of real ones (`brdfpaint::study::faults`), judged on held-out lights and views against
//! the clean truth; bounded refits under random strokes; the mapping choice.

use brdfpaint::brdf::{held_out_views, Analytic, SphereView};
use brdfpaint::demo::brush::SplitMix;
use brdfpaint::factor::{prepare, LogMap, Mapping, Robust, Settings, BOUND};
use brdfpaint::brdf::Reflectance;
use brdfpaint::read::Reading;
use brdfpaint::study::median;
use brdfpaint::study::faults::{self, FaultyView, Faults};
use brdfpaint::study::fidelity::{held_out_presets, painted_presets, StudyView};
use brdfpaint::sample::SceneSampler;
use glam::DVec3;

const SIZE: usize = 128;

/// The study's held-out views and its one painted view (painted `light_off_deg` off the
/// scene's light), `size` pixels a side.
fn views(size: usize, light_off_deg: f64) -> (Vec<StudyView>, [FaultyView; 1]) {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, size).unwrap()).collect();
    let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], size, light_off_deg).unwrap()];
    (held, painted)
}

fn study(f: &Faults) -> (Vec<faults::Row>, Vec<faults::Row>) {
    let (held, painted) = views(SIZE, f.light_off_deg);
    let models = faults::suite();
    let settings = Settings::default();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let robust = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve_robust(v, Mapping::Auto, &Robust::default());
    (
        faults::measure(&painted, &held, &models, &settings, f, &plain, Reading { smooth_tones: false, register_light: false, repaint_strays: false }, brdfpaint::read::lobe::BaseChoice::None).unwrap(),
        faults::measure(&painted, &held, &models, &settings, f, &robust, Reading { smooth_tones: false, register_light: false, repaint_strays: false }, brdfpaint::read::lobe::BaseChoice::None).unwrap(),
    )
}

fn table(rows: &[faults::Row]) -> String {
    rows.iter().map(|r| format!("{:<16} {:.4} worst view {:.3} {}\n", r.model, r.held_out, r.worst_view, r.map)).collect()
}

#[test]
fn stray_strokes_barely_move_a_robust_fit() {
    let (plain, robust) = study(&Faults::strays());
    let (mp, mr) = (median(&plain.iter().map(|r| r.held_out).collect::<Vec<_>>()), median(&robust.iter().map(|r| r.held_out).collect::<Vec<_>>()));
    eprintln!("least squares {mp:.4}\n{}robust {mr:.4}\n{}", table(&plain), table(&robust));
    // Measured at 256²: least squares 0.108, robust 0.067.
    assert!(mr < 0.09, "robust median {mr}");
    assert!(mr < 0.8 * mp, "robust {mr} against least squares {mp}");
}

#[test]
fn clean_and_brushed_paintings_stay_close_to_the_truth() {
    for (name, f, bound) in [("clean", Faults::clean(), 0.05), ("brush", Faults::brush(), 0.06)] {
        let (_, robust) = study(&f);
        let m = median(&robust.iter().map(|r| r.held_out).collect::<Vec<_>>());
        let worst = robust.iter().map(|r| r.worst_view).fold(0.0, f64::max);
        eprintln!("{name}: {m:.4}\n{}", table(&robust));
        // Measured at 256²: clean 0.040 (worst view 0.11), brush 0.045 (0.12).
        assert!(m < bound, "{name}: median {m}");
        assert!(worst < 0.3, "{name}: worst view {worst}");
    }
}

/// A painted sphere view of `model` as a pattern and values, with pixel positions.
fn sphere(model: &Analytic, res: usize) -> (Vec<SphereView>, brdfpaint::factor::Pattern, Vec<[f64; 3]>, Vec<[usize; 2]>) {
    let view = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), res);
    let px = view.pixels();
    let values = px.iter().map(|p| model.shading(&p.query)).collect();
    (vec![view], view.pattern(), values, px.iter().map(|p| p.pixel).collect())
}

#[test]
fn random_strokes_keep_every_refit_finite_and_bounded() {
    let model = Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 32.0 };
    let res = 64;
    let (_, pattern, clean, pixels) = sphere(&model, res);
    let settings = Settings::default();
    let prepared = prepare(&pattern, &settings).unwrap();
    let held: Vec<_> = held_out_views(32).iter().flat_map(|v| v.pixels()).map(|p| p.query).collect();
    let mut rng = SplitMix::new(2024);
    let mut values = clean.clone();
    for stroke in 0..40 {
        // A stroke: a disc of random size and position (partly off the object), a random
        // colour including white and black, or erasing back to the clean painting.
        let (cx, cy, r) = (rng.range(-8.0, res as f64 + 8.0), rng.range(-8.0, res as f64 + 8.0), rng.range(1.0, 12.0));
        let colour = match stroke % 4 {
            0 => Some([1.0; 3]),
            1 => Some([0.0; 3]),
            2 => Some([rng.uniform(), rng.uniform(), rng.uniform()].map(|x| 3.0 * x * x)),
            _ => None,
        };
        for (k, p) in pixels.iter().enumerate() {
            if (p[0] as f64 - cx).hypot(p[1] as f64 - cy) < r {
                values[k] = colour.unwrap_or(clean[k]);
            }
        }
        if values.iter().all(|v| v == &[0.0; 3]) {
            continue;
        }
        let max = [0, 1, 2].map(|c| values.iter().map(|v| v[c]).fold(0.0, f64::max));
        for mapping in [Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None), Mapping::Auto] {
            let fit = prepared.solve_robust(&values, mapping, &Robust::default()).unwrap();
            let a = if let LogMap::Offset { a } = fit.map { a } else { [0.0; 3] };
            for (j, t) in fit.tables.iter().enumerate() {
                for x in t.iter().flatten() {
                    assert!(x.is_finite() && *x >= 0.0, "stroke {stroke} {mapping}: factor {j} value {x}");
                }
            }
            for q in pattern.queries.iter().chain(&held) {
                let m = fit.eval(&settings, q);
                for c in 0..3 {
                    assert!(m[c].is_finite(), "stroke {stroke} {mapping}: {m:?}");
                    assert!(m[c] <= BOUND * max[c].max(1e-12) + a[c] + 1e-9, "stroke {stroke} {mapping}: {m:?} above {BOUND} x {max:?} at {q:?}");
                }
            }
        }
    }
}

#[test]
fn auto_does_not_buy_a_tiny_gain_with_inverted() {
    // A Lambert painting: every mapping fits it almost exactly, and least squares keeps
    // inverted for a gain of a fraction of its tiny error.
    let model = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
    let (_, pattern, values, _) = sphere(&model, 64);
    let prepared = prepare(&pattern, &Settings::default()).unwrap();
    let plain = prepared.solve(&values, Mapping::Auto).unwrap();
    let robust = prepared.solve_robust(&values, Mapping::Auto, &Robust::default()).unwrap();
    let rms = |name: &str| plain.tried.iter().find(|(m, _)| m.name() == name).unwrap().1.rms;
    let best_plain = rms("identity").min(rms("offset"));
    eprintln!("least squares chose {} ({:?}); robust chose {}", plain.map.name(), plain.tried, robust.map.name());
    if plain.map.name() == "inverted" {
        assert!(rms("inverted") > (1.0 - Robust::default().inverted_margin) * best_plain, "the gain is clear: not the case this test needs");
    }
    assert_ne!(robust.map.name(), "inverted", "{:?}", robust.tried);
}

/// `faults` painted on one view `size` pixels a side, read and fitted as `fit` does with the
/// analytic base `auto` and with none (the product alone), judged on held-out lights and
/// views against the clean truth: the nine models' rows, and the median of each.
fn brushed(size: usize, faults: &Faults) -> ((Vec<faults::Row>, f64), (Vec<faults::Row>, f64)) {
    use brdfpaint::read::lobe::BaseChoice;
    let (held, painted) = views(size, faults.light_off_deg);
    let models = faults::suite();
    let settings = Settings::default();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = |base| {
        let rows = faults::measure(&painted, &held, &models, &settings, faults, &plain, Reading::default(), base).unwrap();
        let m = median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
        (rows, m)
    };
    (rows(BaseChoice::Auto), rows(BaseChoice::None))
}

/// Brush texture on one painting goes to no table: `fit`'s path (the painting read, the
/// analytic base under `auto`) keeps the lobe of the painting's family over the product's
/// rings (`read::lobe::TEXTURE_CREDIT`, `correction_weight`). Judged on held-out lights
/// and views against the clean truth, nine models, against the same fit with the product
/// alone. Measured at 128² (seed 11): 0.0242 with the lobe, 0.0551 with the product alone
/// (Lambert 0.011 against 0.026, Oren-Nayar 0.013 against 0.058).
#[test]
fn brush_texture_goes_to_no_table() {
    let ((auto, ma), (none, mn)) = brushed(SIZE, &Faults::brush());
    eprintln!("auto {ma:.4}\n{}product alone {mn:.4}\n{}", table(&auto), table(&none));
    assert!(ma < 0.03, "auto: median {ma}");
    assert!(ma < 0.6 * mn, "auto {ma} against the product alone {mn}");
    let worst = auto.iter().map(|r| r.worst_view).fold(0.0, f64::max);
    assert!(worst < 0.3, "auto: worst view {worst}");
}

/// Noise over the brush texture (1% of sRGB per channel, as a scan or a photographed canvas
/// has) is not texture: independent from pixel to pixel, every table bin averages it away,
/// so the lobe is kept as without it (`read::lobe::texture` reads the residual's
/// covariance between neighbouring pixels, which the noise does not change). Measured at
/// 128², brush seed 2: 0.0321 with the lobe, 0.0575 with the product alone; before the
/// covariance the noise read as more than all the texture and no lobe was kept (0.0575).
#[test]
fn noise_over_brush_texture_keeps_the_lobe() {
    let ((auto, ma), (none, mn)) = brushed(SIZE, &Faults { seed: 2, noise: 0.01, ..Faults::brush() });
    eprintln!("auto {ma:.4}\n{}product alone {mn:.4}\n{}", table(&auto), table(&none));
    assert!(ma < 0.04, "auto: median {ma}");
    assert!(ma < 0.7 * mn, "auto {ma} against the product alone {mn}");
}

/// A white stroke in the shadow makes the stray search's own fit collapse (its light factor
/// drawn up at the terminator, every sample missed, no stroke standing out), and then no stray
/// is found; the search is fitted again with the light prior (`read::strays`).
/// Brush seed 20 with strays and the light 10° off, at 256² (at 128² the fit does not
/// collapse), judged on held-out lights and views against the clean truth: Blinn-Phong 8
/// 0.0097 and Ward 0.0241 (worst view 0.039); without the refit no stray was found, 0.402
/// and 0.573 (worst view 1.09).
#[test]
fn a_collapsed_stray_search_still_finds_the_strokes() {
    let ((auto, ma), _) = brushed(256, &Faults { seed: 20, strays: 8, light_off_deg: 10.0, ..Faults::brush() });
    eprintln!("median {ma:.4}\n{}", table(&auto));
    for name in ["blinn-phong-8", "ward-0.2"] {
        let row = auto.iter().find(|r| r.model == name).unwrap();
        assert!(row.held_out < 0.05 && row.worst_view < 0.1, "{name}: held out {:.4}, worst view {:.3}", row.held_out, row.worst_view);
    }
}

/// Stray strokes in flat tones are left out, and the painting read again without them
/// (`read::Reader`, `read::strays`' toned rim): a stroke in flat tones is tones of its own,
/// which the interpolation between edges and the light's registration read before the stray
/// search finds it. 256², six tones and eight strokes (seed 1), judged on held-out lights and
/// views against the clean truth. Measured: GGX 0.2 0.105, GGX 0.7 0.018, Oren-Nayar 0.008;
/// repainted in place as before, 0.205, 0.084 and 0.023.
#[test]
fn strokes_in_flat_tones_are_read_again_without_them() {
    use brdfpaint::read::lobe::BaseChoice;
    let f = Faults { seed: 1, strays: 8, levels: 6, ..Faults::clean() };
    let (held, painted) = views(256, 0.0);
    let models: Vec<Analytic> = faults::suite().into_iter().filter(|m| ["ggx-0.2", "ggx-0.7", "oren-nayar-0.5"].contains(&m.name().as_str())).collect();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    let rows = faults::measure(&painted, &held, &models, &Settings::default(), &f, &plain, Reading::default(), BaseChoice::Auto).unwrap();
    eprintln!("{}", table(&rows));
    for (name, bound) in [("ggx-0.2", 0.15), ("ggx-0.7", 0.04), ("oren-nayar-0.5", 0.015)] {
        let row = rows.iter().find(|r| r.model == name).unwrap();
        assert!(row.held_out < bound, "{name}: held out {:.4}", row.held_out);
    }
    // What the user reads: the strokes left out, and counted apart from the silhouette band.
    let mut view = vec![faults::paint(&painted[0], &models[1], &f).unwrap()];
    let band = view[0].geometry.pixels.iter().filter(|p| p.is_some()).count() - view[0].geometry.usable_count();
    let notes = read_views(&mut view, &[&painted[0].view.gbuffer]);
    let g = &view[0].geometry;
    assert!(g.left_out > 300, "left out {}", g.left_out);
    assert_eq!(g.pixels.iter().filter(|p| p.is_some()).count() - g.usable_count() - g.left_out, band);
    assert!(notes.iter().any(|n| n.contains(&format!("{} painted pixels read as stray strokes", g.left_out)) && n.contains("left out")), "{notes:#?}");
}

/// The views read as `fit` reads them (`read::Reader`), in place; the notes as lines.
fn read_views(views: &mut Vec<brdfpaint::sample::PaintedView>, gbuffers: &[&brdfpaint::render::GBuffer]) -> Vec<String> {
    let evidence = brdfpaint::read::Reader::new(Reading::default(), gbuffers).read(std::mem::take(views)).unwrap();
    *views = evidence.views;
    evidence.notes.iter().map(|n| n.to_string()).collect()
}
