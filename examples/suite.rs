//! The wide suite of issue 15 (23 analytic models) painted on the analytic sphere from one
//! and from three views (the standard three, and three that also see side and back light),
//! judged on five held-out views (rim and side light among them).
//!
//! `cargo run --release --example suite [-- FACTORS]` where FACTORS names the settings:
//! `default` (the thesis's p(l) q(h) r(v)), or one of the candidates listed by `--list`.
//! `--theta-d auto|on|off` (default off) adds a factor of θ_d as `brdfpaint fit --theta-d`
//! does. `--base ggx` fits an analytic GGX lobe first and the product to S / B
//! (`brdf::lobe`); `--base none` (the default) is the thesis's product alone.

use brdfpaint::brdf::Analytic;
use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::factor::{difference_range, DifferenceChoice, Pattern};
use brdfpaint::study::suite::{held_out, measure_based, paintings, peaks_based, sharp_model, summary, wide_paintings};

fn main() -> brdfpaint::Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut base = BaseChoice::None;
    if let Some(i) = args.iter().position(|a| a == "--base") {
        let kind = args.get(i + 1).ok_or_else(|| brdfpaint::Error::input("--base needs a value (none or ggx)"))?;
        base = kind.parse()?;
        args.drain(i..i + 2);
    }
    let mut difference = DifferenceChoice::Off;
    if let Some(i) = args.iter().position(|a| a == "--theta-d") {
        let when = args.get(i + 1).ok_or_else(|| brdfpaint::Error::input("--theta-d needs a value (auto, on or off)"))?;
        difference = when.parse()?;
        args.drain(i..i + 2);
    }
    let name = args.first().cloned().unwrap_or_else(|| "default".into());
    let candidates = brdfpaint::study::suite::candidates();
    if name == "--list" {
        for (n, _) in &candidates {
            println!("{n}");
        }
        return Ok(());
    }
    let Some((_, settings)) = candidates.iter().find(|(n, _)| *n == name) else {
        return Err(brdfpaint::Error::input(format!("unknown settings '{name}' (see --list)")));
    };
    let models = Analytic::wide_suite();
    // `--theta-d auto` decides per set of paintings, as `brdfpaint fit` does.
    let measure = |painted: &[brdfpaint::brdf::SphereView]| {
        let pattern = Pattern::concat(&painted.iter().map(|v| v.pattern()).collect::<Vec<_>>());
        let (settings, added) = difference.apply(settings, &pattern);
        let [lo, hi] = difference_range(&pattern);
        println!("{} paintings: θ_d from {lo:.0}° to {hi:.0}°, factor of θ_d {}", painted.len(), if added { "added" } else { "not added" });
        measure_based(&models, &settings, painted, base)
    };
    let one = measure(&paintings(1))?;
    let three = measure(&paintings(3))?;
    let wide = measure(&wide_paintings())?;
    let views: Vec<&str> = held_out(2).iter().map(|(n, _)| *n).collect();
    println!("settings '{name}', base {base}: held-out relative RMS (pooled over {} views), train, and per view from 3 paintings", views.len());
    print!("{:<22} {:>7} {:>7} {:>7} {:>7} {:>7}", "model", "1 view", "3 views", "3 wide", "train1", "train3");
    for v in &views {
        print!(" {v:>7}");
    }
    println!();
    for ((a, b), c) in one.iter().zip(&three).zip(&wide) {
        print!("{:<22} {:>7.4} {:>7.4} {:>7.4} {:>7.4} {:>7.4}", a.model, a.held_out, b.held_out, c.held_out, a.train, b.train);
        for e in &b.views {
            print!(" {e:>7.4}");
        }
        print!("  wide:");
        for e in &c.views {
            print!(" {e:>7.4}");
        }
        println!();
    }
    let (m1, w1) = summary(&one);
    let (m3, w3) = summary(&three);
    let (mw, ww) = summary(&wide);
    // Speed of one refit on one painting (~7.9k samples), as `brdfpaint bench` times it: log
    // mapping, scatter, solve, linear tables, one mapping.
    let pattern = paintings(1)[0].pattern();
    let prepared = brdfpaint::factor::prepare(&pattern, settings)?;
    let values = pattern.shade(|q| brdfpaint::brdf::Reflectance::shading(&models[4], q));
    let map = brdfpaint::factor::LogMap::Identity { floor: [1e-4; 3] };
    let solve_s = brdfpaint::study::bench::median_time(200, 1.0, || {
        std::hint::black_box(prepared.solve_tables(&values, &map).expect("solve"));
    });
    // The base's own fit (the search over alpha and the linear fit, for each of the seven
    // lobe families `auto` tries), once per fit.
    let base_s = brdfpaint::study::bench::median_time(20, 1.0, || {
        std::hint::black_box(brdfpaint::brdf::lobe::Base::fit_any(&pattern, &values));
    });
    // A whole solve (three mappings, errors on the samples), plain and over a fixed base.
    let plain_s = brdfpaint::study::bench::median_time(50, 1.0, || {
        std::hint::black_box(prepared.solve(&values, brdfpaint::factor::Mapping::Auto).expect("solve"));
    });
    let (lobe, _) = brdfpaint::brdf::lobe::Base::fit(&pattern, &values).expect("a lobe");
    let on_base_s = brdfpaint::study::bench::median_time(50, 1.0, || {
        let fit = brdfpaint::material::based::solve_on_base(&prepared, &pattern, &values, brdfpaint::factor::Mapping::Auto, &lobe, 1.0);
        std::hint::black_box(fit.expect("solve"));
    });
    println!(
        "one painting: {} samples, {} unknowns, prepare {:.2} ms, solve {:.3} ms (median); base fit {:.1} ms; \
         solve with auto mapping {:.2} ms plain, {:.2} ms over a base (medians)",
        prepared.samples(),
        prepared.unknowns(),
        prepared.prepare_s * 1e3,
        solve_s * 1e3,
        base_s * 1e3,
        plain_s * 1e3,
        on_base_s * 1e3
    );
    let sharp = sharp_model();
    for (label, painted) in [("1 view", paintings(1)), ("3 views", paintings(3)), ("3 wide", wide_paintings())] {
        print!("{} peak from {label}, fitted/true per held-out view:", sharp.name());
        for (view, fitted, truth) in peaks_based(&sharp, settings, &painted, base)? {
            print!(" {view} {:.3}", fitted / truth);
        }
        println!();
    }
    println!("median held-out: 1 view {m1:.4}, 3 views {m3:.4}, 3 wide {mw:.4}; worst view: 1 view {w1:.3}, 3 views {w3:.3}, 3 wide {ww:.3}");
    Ok(())
}
