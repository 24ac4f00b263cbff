//! Fidelity of painting → fit through the real path (G-buffer, 16-bit PNG, decode,
//! sampling, default settings), judged on held-out lights and views.
//!
//! `cargo run --release --example paint_fidelity [-- SIZE] [--exr] [--2d]`

use brdfpaint::brdf::Analytic;
use brdfpaint::factor::Settings;
use brdfpaint::study::fidelity::{held_out_median as median, held_out_presets, measure, painted_presets, PaintFormat, StudyView};
use brdfpaint::sample::SceneSampler;

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = args.iter().find_map(|a| a.parse().ok()).unwrap_or(256);
    let format = if args.iter().any(|a| a == "--exr") { PaintFormat::Exr } else { PaintFormat::Png16 };
    let settings = if args.iter().any(|a| a == "--2d") { Settings::uniform(2, 32) } else { Settings::default() };
    let mut sampler = SceneSampler::new()?;
    let held: Vec<StudyView> =
        held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, size)).collect::<Result<_, _>>()?;
    let painted: Vec<StudyView> =
        painted_presets(3).iter().map(|p| StudyView::new(&mut sampler, p, size)).collect::<Result<_, _>>()?;
    let suite = Analytic::suite();
    let one = measure(&painted[..1], &held, &suite, &settings, format)?;
    let three = measure(&painted, &held, &suite, &settings, format)?;
    println!("{size}x{size} paintings ({format:?}), held-out relative RMS:");
    println!("{:<16} {:>10} {:>10} {:>10} {:>10}", "model", "1 view", "3 views", "train 1", "train 3");
    for (a, b) in one.iter().zip(&three) {
        println!("{:<16} {:>10.4} {:>10.4} {:>10.4} {:>10.4}", a.model, a.held_out, b.held_out, a.train, b.train);
    }
    println!("{:<16} {:>10.4} {:>10.4}", "median", median(&one), median(&three));
    Ok(())
}
