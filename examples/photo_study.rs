//! Photographs held out by light (issue 37; `brdfpaint::study::photos`): each
//! photometric-stereo folder under DIR (made by `tools/mitsuba/render_photos.py`, or real
//! ones in the same layout) is fitted on three of its twelve lights as `brdfpaint fit
//! --photos` fits it and judged on the other nine: relative RMS over the unsaturated, lit,
//! not near-black object pixels of each held-out photograph, the median over them.
//!
//! `cargo run --release --example photo_study [-- --dir tests/data/photos] [--base auto|none|ggx]`
//!   prints the table with the chosen base (`auto`, `fit`'s default, unless told) and with
//!   `--base none` beside it, and the time of each fit (reading the three photographs, then
//!   prepare, solve and the base: no prepare cache).

use std::path::{Path, PathBuf};

use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::study::median;
use brdfpaint::study::photos::{self, Row};

fn name(b: BaseChoice) -> &'static str {
    match b {
        BaseChoice::Auto => "auto",
        BaseChoice::None => "none",
        BaseChoice::Ggx => "ggx",
    }
}

/// The photon noise's own relative RMS the generator recorded (set.json), if any.
fn noise(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join("set.json")).ok()?;
    serde_json::from_str::<serde_json::Value>(&text).ok()?["noise_relative_rms"].as_f64()
}

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let root = PathBuf::from(value("--dir").unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/photos").into()));
    let base: BaseChoice = value("--base").as_deref().unwrap_or("auto").parse()?;
    let bases = if base == BaseChoice::None { vec![base] } else { vec![base, BaseChoice::None] };
    let mut sets: Vec<PathBuf> = std::fs::read_dir(&root)
        .map_err(|e| brdfpaint::Error::io(&root, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("filenames.txt").is_file())
        .collect();
    sets.sort();
    println!(
        "fit on lights {:?} of twelve, judged on the other nine: median relative RMS (worst photograph); fit seconds (read + fit)",
        photos::FIT_LIGHTS
    );
    let mut header = format!("{:<22} {:>6}", "set", "noise");
    for b in &bases {
        header += &format!("  {:<16} {:<12} {:<13}", format!("base {}", name(*b)), "lobe", "seconds");
    }
    println!("{header}");
    let mut columns: Vec<Vec<Row>> = bases.iter().map(|_| Vec::new()).collect();
    for dir in &sets {
        let set = dir.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let mut line = format!("{set:<22} {:>6}", noise(dir).map_or("-".into(), |n| format!("{n:.4}")));
        for (b, column) in bases.iter().zip(&mut columns) {
            let row = photos::measure(dir, *b)?;
            let worst = row.views.iter().copied().fold(0.0, f64::max);
            line += &format!(
                "  {:<16} {:<12} {:<13}",
                format!("{:.4} ({:.3})", row.median(), worst),
                row.base.as_deref().unwrap_or("-"),
                format!("{:.2} + {:.2}", row.load_s, row.fit_s)
            );
            column.push(row);
        }
        println!("{}", line.trim_end());
    }
    let mut line = format!("{:<22} {:>6}", "median", "");
    for column in &columns {
        line += &format!("  {:<16} {:<12} {:<13}", format!("{:.4}", median(&column.iter().map(Row::median).collect::<Vec<_>>())), "", "");
    }
    println!("{}", line.trim_end());
    let samples: Vec<String> = columns[0].iter().map(|r| r.samples.to_string()).collect();
    println!("samples fitted per set: {}", samples.join(", "));
    Ok(())
}
