//! Paintings made by MyPaint's brush engine (tools/mypaint/), fitted as `brdfpaint fit
//! --scene S --image P` fits them and judged on the held-out presets against the clean truth
//! (issue 34, item 4): the fit was never tuned on these.
//!
//! `cargo run --release --example painted_study -- ROOT [--base auto|none|both] [--brush B]... [--seed N]... [--models] [--truth]`
//!
//! ROOT holds `truth/MODEL/PRESET.gltf` (or `PRESET.light`, from which the scene is built
//! again) and `paintings/MODEL/PRESET-BRUSH-CASE-sSEED.png` (tools/mypaint/make_set.sh).
//! Per case (`texture`: brush texture alone; `faults`: every fault) and base, the median
//! over models of each model's median held-out relative RMS over its paintings, and the
//! worst single held-out view of any painting; the same for the suite's nine models and the
//! four outside the base's families; per brush; with `--models`, per model. `--truth` adds
//! the clean truth itself as case `clean` (what the fit does with no painter at all).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use brdfpaint::factor::cache::Cache;
use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::sample::SceneSampler;
use brdfpaint::study::fidelity::{held_out_presets, painted_presets, StudyView};
use brdfpaint::study::painted::{fit_painting, models, outside, scene, truth_files};
use brdfpaint::study::{held_out_and_worst, median};
use brdfpaint::Error;

/// One painting's file name, taken apart.
struct Name {
    preset: String,
    brush: String,
    case: String,
    seed: u64,
}

fn parse(file: &str) -> Option<Name> {
    let stem = file.strip_suffix(".png")?;
    let mut parts = stem.rsplitn(4, '-');
    let seed = parts.next()?.strip_prefix('s')?.parse().ok()?;
    let (case, brush, preset) = (parts.next()?, parts.next()?, parts.next()?);
    Some(Name { preset: preset.into(), brush: brush.into(), case: case.into(), seed })
}

/// The scene of `model`'s paintings in `preset`: the truth's glTF, or one built from its
/// light's intensity into `tmp`.
fn scene_path(root: &Path, model: &str, preset: &str, tmp: &Path) -> brdfpaint::Result<PathBuf> {
    let p = painted_presets(3).into_iter().find(|p| p.name == preset).ok_or_else(|| Error::input(format!("unknown preset {preset}")))?;
    let [gltf, light, ..] = truth_files(&p).map(|f| root.join("truth").join(model).join(f));
    if gltf.exists() {
        return Ok(gltf);
    }
    let text = std::fs::read_to_string(&light).map_err(|e| Error::io(&light, e))?;
    let intensity: f32 = text.trim().parse().map_err(|_| Error::input(format!("{}: not a number", light.display())))?;
    let path = tmp.join(format!("{model}-{preset}.gltf"));
    scene(&p, intensity)?.write_gltf(&path)?;
    Ok(path)
}

/// One fitted painting's figures.
struct Judged {
    model: String,
    brush: String,
    case: String,
    base: BaseChoice,
    held_out: f64,
    worst: f64,
}

/// The median over models of each model's median, and the worst view, of `rows`.
fn summary<'a>(rows: impl Iterator<Item = &'a Judged>) -> Option<(f64, f64, usize)> {
    let mut by_model: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for r in rows {
        by_model.entry(&r.model).or_default().push(r.held_out);
        worst = worst.max(r.worst);
        n += 1;
    }
    let medians: Vec<f64> = by_model.values().map(|x| median(x)).collect();
    (n > 0).then(|| (median(&medians), worst, n))
}

fn cell(s: Option<(f64, f64, usize)>) -> String {
    s.map_or_else(|| format!("{:>16}", "-"), |(m, w, _)| format!("{m:>8.4} /{w:>6.3}"))
}

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(args.first().filter(|a| !a.starts_with("--")).expect("usage: painted_study ROOT [options]"));
    let values = |flag: &str| -> Vec<String> { args.windows(2).filter(|w| w[0] == flag).map(|w| w[1].clone()).collect() };
    let bases: Vec<BaseChoice> = match values("--base").first().map(String::as_str) {
        None | Some("both") => vec![BaseChoice::Auto, BaseChoice::None],
        Some(b) => vec![b.parse()?],
    };
    let (brushes, seeds) = (values("--brush"), values("--seed"));
    let per_model = args.iter().any(|a| a == "--models");
    let with_truth = args.iter().any(|a| a == "--truth");
    let held_size: usize = values("--held-size").first().map_or(256, |s| s.parse().expect("a number"));

    let mut sampler = SceneSampler::new()?;
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, held_size)).collect::<Result<_, _>>()?;
    let tmp = tempfile::tempdir().map_err(|e| Error::io(std::env::temp_dir(), e))?;
    // The product prepares through a cache (`fit` uses the user's); here a fresh one, so
    // paintings of one scene share their prepared system as a user's repeated fits do.
    let cache = Cache::new(tmp.path().join("cache"));
    let outsiders: Vec<String> = outside().into_iter().map(|m| m.name).collect();

    let mut rows = Vec::new();
    for model in models() {
        let dir = root.join("paintings").join(&model.name);
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir).into_iter().flatten().filter_map(|e| Some(e.ok()?.path())).collect();
        files.sort();
        let mut named: Vec<(PathBuf, Name)> = files.into_iter().filter_map(|f| Some((f.clone(), parse(f.file_name()?.to_str()?)?))).collect();
        if with_truth {
            for p in painted_presets(3) {
                let [_, _, _, clean_png, ..] = truth_files(&p);
                let clean = root.join("truth").join(&model.name).join(clean_png);
                if clean.exists() {
                    named.push((clean, Name { preset: p.name.into(), brush: "truth".into(), case: "clean".into(), seed: 0 }));
                }
            }
        }
        for (path, name) in named {
            let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
            if (!brushes.is_empty() && !brushes.contains(&name.brush)) || (!seeds.is_empty() && !seeds.contains(&name.seed.to_string())) {
                continue;
            }
            let scene = scene_path(&root, &model.name, &name.preset, tmp.path())?;
            for &base in &bases {
                let material = fit_painting(&mut sampler, &scene, &path, base, Some(&cache))?;
                let (held_out, worst) = held_out_and_worst(&material, &model, &held)?;
                if per_model {
                    println!("{:<16} {file:<40} base {:<4}  held-out {held_out:.4}  worst view {worst:.3}", model.name, base.to_string());
                }
                rows.push(Judged { model: model.name.clone(), brush: name.brush.clone(), case: name.case.clone(), base, held_out, worst });
            }
        }
    }
    if rows.is_empty() {
        return Err(Error::input(format!("no paintings under {}", root.join("paintings").display())));
    }

    let mut cases: Vec<String> = rows.iter().map(|r| r.case.clone()).collect();
    cases.sort();
    cases.dedup();
    cases.sort_by_key(|c| ["clean", "texture"].iter().position(|k| k == c).unwrap_or(2));
    let mut brush_names: Vec<String> = rows.iter().map(|r| r.brush.clone()).collect();
    brush_names.sort();
    brush_names.dedup();
    let model_count = rows.iter().map(|r| &r.model).collect::<std::collections::BTreeSet<_>>().len();
    let paintings = rows.iter().filter(|r| r.brush != "truth").count() / bases.len();
    println!(
        "{paintings} paintings of {model_count} models in {} ({} brushes), held out on {} views at {held_size}²; each cell: median over models of each model's median held-out relative RMS / worst held-out view",
        root.display(),
        brush_names.iter().filter(|b| *b != "truth").count(),
        held.len()
    );
    println!("{:<10} {:<5} {:>16} {:>16} {:>16}", "case", "base", "all models", "faults suite", "outside");
    for case in &cases {
        for &base in &bases {
            let of = |keep: &dyn Fn(&Judged) -> bool| summary(rows.iter().filter(|r| &r.case == case && r.base == base && keep(r)));
            println!(
                "{case:<10} {:<5} {} {} {}",
                base.to_string(),
                cell(of(&|_| true)),
                cell(of(&|r| !outsiders.contains(&r.model))),
                cell(of(&|r| outsiders.contains(&r.model)))
            );
        }
    }
    println!("\nper brush (all models):");
    let header: Vec<String> = cases.iter().flat_map(|c| bases.iter().map(move |b| format!("{c} {b}"))).collect();
    println!("{:<12} {}", "brush", header.iter().map(|h| format!("{h:>16}")).collect::<Vec<_>>().join(" "));
    for brush in &brush_names {
        let cells: Vec<String> = cases
            .iter()
            .flat_map(|c| bases.iter().map(move |&b| (c, b)))
            .map(|(c, b)| cell(summary(rows.iter().filter(|r| &r.brush == brush && &r.case == c && r.base == b))))
            .collect();
        println!("{brush:<12} {}", cells.join(" "));
    }
    println!("\nper model (median over brushes and seeds / worst view):");
    println!("{:<16} {}", "model", header.iter().map(|h| format!("{h:>16}")).collect::<Vec<_>>().join(" "));
    for model in models() {
        let cells: Vec<String> = cases
            .iter()
            .flat_map(|c| bases.iter().map(move |&b| (c, b)))
            .map(|(c, b)| cell(summary(rows.iter().filter(|r| r.model == model.name && &r.case == c && r.base == b))))
            .collect();
        if cells.iter().any(|c| c.trim() != "-") {
            println!("{:<16} {}", model.name, cells.join(" "));
        }
    }
    Ok(())
}
