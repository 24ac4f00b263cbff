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

#[test]
fn paintings_generalize_to_held_out_lights_and_views() {
    let (one, three) = study(PaintFormat::Png16);
    let t = table(&one, &three);
    eprintln!("{t}");
    // Targets: median <= 0.05 from one painting, <= 0.03 from three (measured 0.026 and
    // 0.011 at 256², 16-bit PNG).
    assert!(median(&one) <= 0.05, "one view:\n{t}");
    assert!(median(&three) <= 0.03, "three views:\n{t}");
    // More views help: the median and the worst model both improve.
    assert!(median(&three) < median(&one), "{t}");
    let worst = |r: &[Row]| r.iter().map(|x| x.held_out).fold(0.0, f64::max);
    assert!(worst(&three) < worst(&one), "{t}");
    // Per model: exact products (Lambert, Gooch) and Blinn-Phong nearly exact; nothing
    // wild (measured worst: GGX 0.4 at 0.127 with one view, GGX 0.2 at 0.093 with three).
    for (a, b) in one.iter().zip(&three) {
        let bound = match a.model.as_str() {
            "lambert" | "gooch" => 0.005,
            m if m.starts_with("blinn-phong") => 0.03,
            _ => 0.2,
        };
        assert!(a.held_out < bound && b.held_out < bound, "{}: bound {bound}\n{t}", a.model);
    }
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
