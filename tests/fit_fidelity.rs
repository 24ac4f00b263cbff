//! The product's core promise, measured through the real path (DESIGN.md, Quality bars):
//! the analytic suite painted on the built-in sphere in framed scenes (G-buffer queries,
//! 16-bit PNG or EXR, decoded again), fitted with the default settings, and judged on
//! held-out lights and views. `cargo run --release --example paint_fidelity` prints the
//! table.

use brdfpaint::brdf::Analytic;
use brdfpaint::factor::Settings;
use brdfpaint::study::fidelity::{held_out_median as median, held_out_presets, measure, painted_presets, PaintFormat, Row, StudyView};
use brdfpaint::sample::SceneSampler;

const SIZE: usize = 256;

fn study(format: PaintFormat) -> (Vec<Row>, Vec<Row>) {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let painted: Vec<StudyView> = painted_presets(3).iter().map(|p| StudyView::new(&mut sampler, p, SIZE).unwrap()).collect();
    let suite = Analytic::suite();
    let settings = Settings::default();
    let one = measure(&painted[..1], &held, &suite, &settings, format).unwrap();
    let three = measure(&painted, &held, &suite, &settings, format).unwrap();
    (one, three)
}

fn table(one: &[Row], three: &[Row]) -> String {
    let mut s = String::from("model            1 view   3 views\n");
    for (a, b) in one.iter().zip(three) {
        s += &format!("{:<16} {:.4}   {:.4}\n", a.model, a.held_out, b.held_out);
    }
    s + &format!("median           {:.4}   {:.4}", median(one), median(three))
}

/// BENCHMARKS.md's table ("From paintings: held-out fidelity"), model by model: held-out
/// relative RMS from one painting and from three. `cargo run --release --example
/// paint_fidelity` prints the same study.
const STATED: [(&str, f64, f64); 11] = [
    ("lambert", 0.0002, 0.0002),
    ("blinn-phong-8", 0.0010, 0.0010),
    ("blinn-phong-32", 0.0016, 0.0018),
    ("blinn-phong-128", 0.0035, 0.0039),
    ("ggx-0.2", 0.0648, 0.0573),
    ("ggx-0.4", 0.1236, 0.0477),
    ("ggx-0.7", 0.0665, 0.0106),
    ("ward-0.2", 0.0255, 0.0134),
    ("oren-nayar-0.5", 0.0505, 0.0349),
    ("minnaert-0.75", 0.0560, 0.0042),
    ("gooch", 0.0001, 0.0000),
];
/// The table's medians.
const STATED_MEDIAN: (f64, f64) = (0.0255, 0.0042);

/// A stated four-decimal figure and a measured one agree: within half the last digit plus 1%
/// (the fit is deterministic; the 1% is float rounding across machines and libm).
fn agrees(measured: f64, stated: f64) -> bool {
    (measured - stated).abs() <= 5e-5 + 0.01 * stated
}

#[test]
fn paintings_generalize_to_held_out_lights_and_views() {
    let (one, three) = study(PaintFormat::Png16);
    let t = table(&one, &three);
    eprintln!("{t}");
    // Targets: median <= 0.05 from one painting, <= 0.03 from three; BENCHMARKS.md states
    // the measured medians and every model's figure, held here at those values.
    assert!(median(&one) <= 0.05 && median(&three) <= 0.03, "targets:\n{t}");
    assert!(agrees(median(&one), STATED_MEDIAN.0) && agrees(median(&three), STATED_MEDIAN.1), "medians against {STATED_MEDIAN:?}:\n{t}");
    assert_eq!(one.len(), STATED.len(), "{t}");
    for ((a, b), (model, s1, s3)) in one.iter().zip(&three).zip(STATED) {
        assert_eq!(a.model, model, "{t}");
        assert!(agrees(a.held_out, s1) && agrees(b.held_out, s3), "{model}: {:.4} / {:.4}, stated {s1} / {s3}\n{t}", a.held_out, b.held_out);
    }
    // More views help: the median and the worst model both improve.
    assert!(median(&three) < median(&one), "{t}");
    let worst = |r: &[Row]| r.iter().map(|x| x.held_out).fold(0.0, f64::max);
    assert!(worst(&three) < worst(&one), "{t}");
}

#[test]
fn exr_and_16_bit_png_paintings_fit_alike() {
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, 128).unwrap()).collect();
    let painted: Vec<StudyView> = painted_presets(1).iter().map(|p| StudyView::new(&mut sampler, p, 128).unwrap()).collect();
    let models: Vec<Analytic> = Analytic::suite().into_iter().take(4).collect();
    let settings = Settings::default();
    let png = measure(&painted, &held, &models, &settings, PaintFormat::Png16).unwrap();
    let exr = measure(&painted, &held, &models, &settings, PaintFormat::Exr).unwrap();
    for (a, b) in png.iter().zip(&exr) {
        assert!((a.held_out - b.held_out).abs() < 2e-3, "{}: PNG {} vs EXR {}", a.model, a.held_out, b.held_out);
    }
}
