//! The suite another renderer made (issue 37; `brdfpaint::study::rendered`): Mitsuba 3
//! spheres of materials outside the base's lobe families, fitted from one and from three
//! painted views as `brdfpaint fit` fits them, judged on seven held-out renders (three lit
//! from the front half, four under side, rim and grazing light), with the medians of each
//! group below the table.
//!
//! `cargo run --release --example mitsuba_suite [-- --dir tests/data/mitsuba] [--base auto|none|ggx] [--per-view]`
//!   prints the convention check and the table, with the chosen base (`auto`, `brdfpaint
//!   fit`'s default, unless told) and with `--base none` beside it (and each held-out view's
//!   error, with `--per-view`);
//! `cargo run --release --example mitsuba_suite -- scenes DIR`
//!   writes the suite's scenes as DIR/PRESET.gltf, for `tools/mitsuba/render_suite.py`.

use std::path::PathBuf;
use std::time::Instant;

use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::sample::SceneSampler;
use brdfpaint::study::median;
use brdfpaint::study::rendered::{self, median_of_medians, worst_view, Row, Suite};

/// `--base`'s spelling of a choice.
fn name(b: BaseChoice) -> &'static str {
    match b {
        BaseChoice::Auto => "auto",
        BaseChoice::None => "none",
        BaseChoice::Ggx => "ggx",
    }
}

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("scenes") {
        let dir = PathBuf::from(args.get(1).expect("scenes DIR"));
        for p in rendered::write_scenes(&dir)? {
            println!("{}", p.display());
        }
        return Ok(());
    }
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let dir = PathBuf::from(value("--dir").unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mitsuba").into()));
    let base: BaseChoice = value("--base").as_deref().unwrap_or("auto").parse()?;
    let suite = Suite::load(&dir)?;
    let scenes = tempfile::tempdir().map_err(|e| brdfpaint::Error::io(std::env::temp_dir(), e))?;
    rendered::write_scenes(scenes.path())?;
    let mut sampler = SceneSampler::new()?;

    let check = rendered::convention_check(&suite, &mut sampler, scenes.path())?;
    let names: Vec<&str> = rendered::presets().iter().map(|p| p.name).collect();
    println!("convention check: Lambert rendered by Mitsuba against brdfpaint's Lambert shading, relative RMS per view");
    for (n, e) in names.iter().zip(&check) {
        println!("  {n:<11} {e:.2e}");
    }

    // Per number of painted views: the chosen base, then `--base none` beside it.
    let bases = if base == BaseChoice::None { vec![base] } else { vec![base, BaseChoice::None] };
    let mut tables: Vec<(usize, BaseChoice, Vec<Row>)> = Vec::new();
    for painted in [1, rendered::PAINTED] {
        for &b in &bases {
            let start = Instant::now();
            let rows = rendered::measure(&suite, &mut sampler, scenes.path(), painted, b)?;
            eprintln!("{painted} view(s), base {}: {:.1} s", name(b), start.elapsed().as_secs_f64());
            tables.push((painted, b, rows));
        }
    }
    println!(
        "\nheld-out relative RMS over object pixels: per material the median over the {} held-out views (its worst view), and the lobe the base kept",
        names.len() - rendered::PAINTED
    );
    let mut line = format!("{:<26}", "material");
    for (painted, b, _) in &tables {
        line += &format!(" {:<16}", format!("{painted} view{}, {}", if *painted > 1 { "s" } else { "" }, name(*b)));
        if *b != BaseChoice::None {
            line += &format!(" {:<17}", "lobe");
        }
    }
    println!("{line}");
    let cell = |x: f64, worst: f64| format!("{x:.4} ({worst:.3})");
    for (m, material) in suite.materials.iter().enumerate() {
        let mut line = format!("{material:<26}");
        for (_, b, rows) in &tables {
            let r = &rows[m];
            line += &format!(" {:<16}", cell(r.median(), r.worst()));
            if *b != BaseChoice::None {
                line += &format!(" {:<17}", r.base.as_deref().unwrap_or("-"));
            }
        }
        println!("{}", line.trim_end());
    }
    let mut line = format!("{:<26}", "median (worst view)");
    for (_, b, rows) in &tables {
        line += &format!(" {:<16}", cell(median_of_medians(rows), worst_view(rows)));
        if *b != BaseChoice::None {
            line += &format!(" {:<17}", "");
        }
    }
    println!("{}", line.trim_end());
    for (what, of) in [("median, held-1..3", Row::front as fn(&Row) -> f64), ("median, side..grazing", Row::rim)] {
        let mut line = format!("{what:<26}");
        for (_, b, rows) in &tables {
            line += &format!(" {:<16}", format!("{:.4}", median(&rows.iter().map(of).collect::<Vec<_>>())));
            if *b != BaseChoice::None {
                line += &format!(" {:<17}", "");
            }
        }
        println!("{}", line.trim_end());
    }
    let mut line = format!("{:<26}", "on the painted samples");
    for (_, b, rows) in &tables {
        line += &format!(" {:<16}", format!("{:.4}", median(&rows.iter().map(|r| r.train).collect::<Vec<_>>())));
        if *b != BaseChoice::None {
            line += &format!(" {:<17}", "");
        }
    }
    println!("{}", line.trim_end());
    if args.iter().any(|a| a == "--per-view") {
        for (painted, b, rows) in &tables {
            println!("\nper held-out view, {painted} view(s), base {}", name(*b));
            let mut line = format!("{:<26}", "material");
            for n in &names[rendered::PAINTED..] {
                line += &format!(" {n:>11}");
            }
            println!("{line}");
            for r in rows {
                let cells: String = r.views.iter().map(|e| format!(" {e:>11.4}")).collect();
                println!("{:<26}{cells}", r.material);
            }
        }
    }
    Ok(())
}
