//! The 100 MERL materials, as their ABC fits (Löw et al. 2012; `brdf::Abc`) rendered as
//! truth, factored with the thesis's unwarped q(h) and with the default warped one, from one
//! and three paintings of the sphere and from MERL-style dense sampling (`fit --merl`'s grid,
//! k = 16, 8192 pairs), judged on the wide suite's five held-out views (`study::suite`).
//!
//! `cargo run --release --example merl_fits [-- ../shared/data/merl-fits/merl_abc_fits_low2012.csv] [--base]`
//!
//! With `--base`: the warped default without and with the analytic base (`brdf::lobe`,
//! `ggx` and `auto`). With `--theta-d`: without and with a factor of θ_d, and the base.

use brdfpaint::brdf::{Abc, Reflectance, SphereView};
use brdfpaint::factor::{Pattern, Settings};
use brdfpaint::study::median;
use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::study::suite::{dense, measure_on_based, paintings, Row};

fn main() -> brdfpaint::Result<()> {
    let path = std::env::args().skip(1).find(|a| !a.starts_with("--")).unwrap_or_else(|| "../shared/data/merl-fits/merl_abc_fits_low2012.csv".into());
    let text = std::fs::read_to_string(&path).map_err(|e| brdfpaint::Error::io(std::path::Path::new(&path), e))?;
    let materials = Abc::parse_csv(&text)?;
    let named: Vec<(String, &dyn Reflectance)> = materials.iter().map(|m| (m.name.clone(), m as &dyn Reflectance)).collect();
    let painted = |n: usize| Pattern::concat(&paintings(n).iter().map(SphereView::pattern).collect::<Vec<_>>());
    let sources = [("1 painting", painted(1)), ("3 paintings", painted(3)), ("dense", dense(16)?)];
    // `--base` adds the analytic base (`brdf::lobe`) beside the warped default.
    let based = std::env::args().any(|a| a == "--base");
    let mut settings = vec![("unwarped", Settings::warped(1.0), BaseChoice::None), ("warped", Settings::default(), BaseChoice::None)];
    if based {
        settings = vec![
            ("warped", Settings::default(), BaseChoice::None),
            ("+ base ggx", Settings::default(), BaseChoice::Ggx),
            ("+ base auto", Settings::default(), BaseChoice::Auto),
        ];
    }
    // `--theta-d`: the factor of θ_d (`fit --theta-d`) beside the warped default, without
    // and with the base.
    if std::env::args().any(|a| a == "--theta-d") {
        let theta_d = Settings::default().and_difference();
        settings = vec![
            ("warped", Settings::default(), BaseChoice::None),
            ("+ θ_d", theta_d.clone(), BaseChoice::None),
            ("+ base ggx", Settings::default(), BaseChoice::Ggx),
            ("+ θ_d + base ggx", theta_d.clone(), BaseChoice::Ggx),
            ("+ base auto", Settings::default(), BaseChoice::Auto),
            ("+ θ_d + base auto", theta_d, BaseChoice::Auto),
        ];
    }
    let mut columns: Vec<(String, Vec<Row>)> = Vec::new();
    for (source, pattern) in &sources {
        for (label, s, base) in &settings {
            columns.push((format!("{source}: {label}"), measure_on_based(pattern, &named, s, *base, *source == "1 painting")?));
        }
    }
    print!("| material |");
    for (c, _) in &columns {
        print!(" {c} |");
    }
    println!();
    println!("| --- |{}", " ---: |".repeat(columns.len()));
    for (i, m) in materials.iter().enumerate() {
        print!("| {} |", m.name);
        for (_, rows) in &columns {
            print!(" {:.4} |", rows[i].held_out);
        }
        println!();
    }
    print!("| **median** |");
    for (_, rows) in &columns {
        print!(" **{:.4}** |", median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>()));
    }
    println!();
    print!("| worst view, median over materials |");
    for (_, rows) in &columns {
        print!(" {:.3} |", median(&rows.iter().map(|r| r.worst_view().1).collect::<Vec<_>>()));
    }
    println!();
    Ok(())
}
