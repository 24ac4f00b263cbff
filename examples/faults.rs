//! Hand-made paintings (issue 11): the analytic subset painted on the sphere with the faults
//! of real paintings (`brdfpaint::study::faults`), fitted by least squares (`Prepared::solve`) and
//! by the robust fit (`Prepared::solve_robust`), judged on held-out lights and views against
//! the clean truth; and light sweeps of materials painted lit from the front.
//!
//! `cargo run --release --example faults [-- SIZE] [--models] [--only CASE] [--read] [--base auto|none|ggx] [--seed N]`
//! `cargo run --release --example faults -- --read --seeds 1-12 [--faults blnst] [--preset front] [--models]`
//!
//! `--seed N` draws the faults (brush strokes, strays, noise) from seed N instead of the
//! study's 11.
//!
//! The analytic base is chosen as `brdfpaint fit` chooses it (`auto`) unless `--base` says.

use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::factor::{Mapping, Robust, Settings};
use brdfpaint::read::Reading;
use brdfpaint::study::median;
use brdfpaint::study::faults::{self, FaultyView, Faults, Row};
use brdfpaint::study::fidelity::{held_out_presets, painted_presets, StudyView};
use brdfpaint::sample::SceneSampler;
use brdfpaint::scene::preset;

fn summary(rows: &[Row]) -> String {
    format!(
        "median {:.4}  worst view {:7.3}  sweep median {:.2} max {:.2}",
        median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>()),
        rows.iter().map(|r| r.worst_view).fold(0.0, f64::max),
        median(&rows.iter().map(|r| r.sweep).collect::<Vec<_>>()),
        rows.iter().map(|r| r.sweep).fold(0.0, f64::max),
    )
}

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // The size is the first bare number (not `--seed`'s).
    let size = args.iter().enumerate().find_map(|(i, a)| a.parse().ok().filter(|_| i == 0 || args[i - 1] != "--seed")).unwrap_or(256);
    let per_model = args.iter().any(|a| a == "--models");
    let only = args.iter().position(|a| a == "--only").and_then(|i| args.get(i + 1)).cloned();
    let seed: Option<u64> = args.iter().position(|a| a == "--seed").and_then(|i| args.get(i + 1)).map(|s| s.parse().expect("--seed takes a number"));
    let seeded = |f: Faults| Faults { seed: seed.unwrap_or(f.seed), ..f };
    let settings = Settings::default();
    // `--base none|auto|ggx`: the analytic base (`brdfpaint fit`'s default, auto, unless told).
    let base_choice: BaseChoice = match args.iter().position(|a| a == "--base") {
        Some(i) => args.get(i + 1).map_or("missing", |s| s.as_str()).parse()?,
        None => BaseChoice::Auto,
    };
    let mut sampler = SceneSampler::new()?;
    let held: Vec<StudyView> =
        held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, size)).collect::<Result<_, _>>()?;
    let models = faults::suite();
    let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
    // ROBUST="huber=6,tukey=3,scale=0.01,levels=256,prior=0.02,margin=0.15,bound=8" overrides the defaults.
    let mut chosen = Robust::default();
    let mut mapping = Mapping::Auto;
    for kv in std::env::var("ROBUST").unwrap_or_default().split(',').filter(|s| !s.is_empty()) {
        let (k, v) = kv.split_once('=').expect("key=value");
        let x: f64 = v.parse().expect("a number");
        match k {
            "huber" => chosen.huber = x as usize,
            "tukey" => chosen.tukey = x as usize,
            "scale" => chosen.min_scale = x,
            "levels" => chosen.max_levels = x as usize,
            "prior" => chosen.light_prior = (x > 0.0).then_some(x),
            "margin" => chosen.inverted_margin = x,
            "bound" => chosen.bound = x,
            "mapping" => mapping = [Mapping::Auto, Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None)][x as usize],
            _ => panic!("unknown key {k}"),
        }
    }
    let robust = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve_robust(v, mapping, &chosen);
    // `--ablate`: the robust fit's parts one at a time.
    let base = Robust { huber: 0, tukey: 0, max_levels: 0, light_prior: None, ..Robust::default() };
    let variants: Vec<(&str, Robust)> = vec![
        ("bound only", base.clone()),
        ("huber", Robust { huber: 8, ..base.clone() }),
        ("huber+tukey", Robust { huber: 6, tukey: 3, ..base.clone() }),
        ("levels", Robust { huber: 8, max_levels: 256, ..base.clone() }),
        ("prior", Robust { light_prior: Some(0.02), ..base.clone() }),
        ("chosen", chosen.clone()),
    ];
    let ablate: Vec<(&str, Box<dyn Fn(&brdfpaint::factor::Prepared, &[[f64; 3]]) -> brdfpaint::Result<brdfpaint::factor::Fit>>)> = variants
        .into_iter()
        .map(|(n, r)| (n, Box::new(move |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve_robust(v, Mapping::Auto, &r)) as Box<_>))
        .collect();
    let mut solvers: Vec<(&str, faults::Solve<'_>)> = vec![("least squares", &plain), ("robust", &robust)];
    // `--read`: paintings read as `brdfpaint fit` reads them (tones smoothed, strays left
    // out, light registered); `--tones`, `--strays`, `--register`: one of them.
    let flag = |f: &str| args.iter().any(|a| a == f);
    let register = Reading {
        smooth_tones: flag("--read") || flag("--tones"),
        register_light: flag("--read") || flag("--register"),
        repaint_strays: flag("--read") || flag("--strays"),
    };
    if args.iter().any(|a| a == "--ablate") {
        solvers = vec![("least squares", &plain)];
        solvers.extend(ablate.iter().map(|(n, f)| (*n, &**f as faults::Solve<'_>)));
    }
    println!("{size}x{size} paintings of {} models, one view (front-left), held-out relative RMS against the clean truth", models.len());
    // `--seeds A-B [--faults blnst]`: the least-squares fit over brush seeds A..=B, the mean of
    // each seed's median; `--faults` picks the faults by letter (brush, light 10° off, noise,
    // strays, tones) instead of `--only`'s named cases.
    if let Some(range) = args.iter().position(|a| a == "--seeds").and_then(|i| args.get(i + 1)) {
        let (a, b) = range.split_once('-').map_or((range.as_str(), range.as_str()), |(a, b)| (a, b));
        let seeds: Vec<u64> = (a.parse().expect("--seeds A-B")..=b.parse().expect("--seeds A-B")).collect();
        let mut cases: Vec<(String, Faults)> = Faults::cases().into_iter().filter(|(c, _)| only.as_deref().is_none_or(|o| o == *c)).map(|(c, f)| (c.to_string(), f)).collect();
        if let Some(letters) = args.iter().position(|a| a == "--faults").and_then(|i| args.get(i + 1)) {
            let all = Faults::all();
            let has = |c: char| letters.contains(c);
            let f = Faults {
                brush: if has('b') { all.brush } else { 0.0 },
                light_off_deg: if has('l') { all.light_off_deg } else { 0.0 },
                noise: if has('n') { all.noise } else { 0.0 },
                strays: if has('s') { all.strays } else { 0 },
                levels: if has('t') { all.levels } else { 0 },
                ..all
            };
            cases = vec![(letters.clone(), f)];
        }
        for (case, f) in cases {
            let mut medians = Vec::new();
            let mut by_model: Vec<Vec<f64>> = vec![Vec::new(); models.len()];
            let mut worst: f64 = 0.0;
            for &seed in &seeds {
                let f = Faults { seed, ..f.clone() };
                let at = match args.iter().position(|a| a == "--preset").and_then(|i| args.get(i + 1)) {
                    Some(name) => preset(name)?,
                    None => painted_presets(1)[0],
                };
                let painted = [FaultyView::new(&mut sampler, &at, size, f.light_off_deg)?];
                let rows = faults::measure(&painted, &held, &models, &settings, &f, &plain, register, base_choice)?;
                let m = median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
                println!("{case:<14} seed {seed:<3} {}", summary(&rows));
                if per_model {
                    println!("    {}", rows.iter().map(|r| format!("{:.3}", r.held_out)).collect::<Vec<_>>().join(" "));
                }
                for (k, r) in rows.iter().enumerate() {
                    by_model[k].push(r.held_out);
                    worst = worst.max(r.worst_view);
                }
                medians.push(m);
            }
            let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len().max(1) as f64;
            println!("{case:<14} seeds {range}: mean median {:.4}, worst view {worst:.3}", mean(&medians));
            for (m, x) in models.iter().zip(&by_model) {
                println!("    {:<16} mean held-out {:.4}", m.name(), mean(x));
            }
        }
        return Ok(());
    }
    for (case, f) in Faults::cases() {
        if only.as_deref().is_some_and(|o| o != case) {
            continue;
        }
        let f = seeded(f);
        let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], size, f.light_off_deg)?];
        for &(name, solve) in &solvers {
            let rows = faults::measure(&painted, &held, &models, &settings, &f, solve, register, base_choice)?;
            println!("{case:<14} {name:<14} {}", summary(&rows));
            if per_model {
                for r in &rows {
                    println!("    {:<16} train {:.4} held-out {:.4} worst view {:.3} sweep {:.2} {}", r.model, r.train, r.held_out, r.worst_view, r.sweep, r.map);
                }
            }
        }
    }
    // Light sweeps of materials painted lit from the front (the `front` preset: the light at
    // the camera), clean and with every fault.
    let front = preset("front")?;
    let mut fronts = vec![("front clean", Faults::clean()), ("front all", Faults::all())];
    if args.iter().any(|a| a == "--front") {
        fronts = Faults::cases().into_iter().collect();
    }
    for (case, f) in fronts {
        if only.as_deref().is_some_and(|o| o != case) {
            continue;
        }
        let f = seeded(f);
        let painted = [FaultyView::new(&mut sampler, &front, size, f.light_off_deg)?];
        for &(name, solve) in &solvers {
            let rows = faults::measure(&painted, &held, &models, &settings, &f, solve, register, base_choice)?;
            println!("{case:<14} {name:<14} {}", summary(&rows));
            if per_model {
                for r in &rows {
                    println!("    {:<16} train {:.4} held-out {:.4} worst view {:.3} sweep {:.2} {}", r.model, r.train, r.held_out, r.worst_view, r.sweep, r.map);
                }
            }
        }
    }
    // Solve times on one painting's samples (the clean front-left view).
    let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], size, 0.0)?];
    let view = faults::paint(&painted[0], &models[1], &Faults::all())?;
    let samples = brdfpaint::sample::Samples::gather(&[view])?;
    let prepared = brdfpaint::factor::prepare(&samples.pattern, &settings)?;
    let time = |f: &dyn Fn()| {
        let mut t: Vec<f64> = (0..15).map(|_| { let s = std::time::Instant::now(); f(); s.elapsed().as_secs_f64() * 1e3 }).collect();
        t.sort_by(f64::total_cmp);
        t[7]
    };
    let map = prepared.solve(&samples.values, Mapping::Offset(None))?.map;
    println!("{} samples: solve auto {:.2} ms, solve_robust auto {:.2} ms, solve_tables {:.3} ms, solve_robust_tables {:.2} ms (medians of 15)",
        samples.len(),
        time(&|| { prepared.solve(&samples.values, Mapping::Auto).unwrap(); }),
        time(&|| { prepared.solve_robust(&samples.values, Mapping::Auto, &chosen).unwrap(); }),
        time(&|| { prepared.solve_tables(&samples.values, &map).unwrap(); }),
        time(&|| { prepared.solve_robust_tables(&samples.values, &map, &chosen).unwrap(); }));
    Ok(())
}
