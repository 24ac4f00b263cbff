//! `brdfpaint fit`: samples in, material out. Two sources: paintings of scenes
//! (`--scene S --image P`, repeatable: thesis 4.1, 4.4) and measured MERL data (`--merl`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::ValueEnum;

use crate::brdf::Merl;
use crate::error::{Error, Result};
use crate::factor::cache::{Cache, Outcome};
use crate::factor::{prepare, Mapping, Pattern, Settings};
use crate::material::{Material, Provenance};
use crate::sample::{self, check_same_model, report, Erosion, Neighbours, Samples, SceneSampler};

#[derive(Clone, Copy, ValueEnum)]
pub(super) enum FactorDim {
    #[value(name = "1d")]
    One,
    #[value(name = "2d")]
    Two,
}

/// Material kinds (DESIGN.md).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum KindArg {
    Uniform,
    FourFactor,
    MaterialMap,
    Hybrid,
}

/// Material-map fitting methods.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum MapFitArg {
    Cluster,
    Greedy,
}

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("source").required(true).multiple(true).args(["merl", "scene"]))]
pub(super) struct FitArgs {
    /// A scene (glTF: meshes, camera, light) a painting was made in; repeat with --image
    /// for several views (paired in order).
    #[arg(long, value_name = "S.gltf", conflicts_with = "merl", requires = "image")]
    scene: Vec<PathBuf>,
    /// The painting (PNG, JPEG: sRGB; EXR: linear) of the preceding --scene; alpha 0 is
    /// "not painted".
    #[arg(long, value_name = "P.png", requires = "scene")]
    image: Vec<PathBuf>,
    /// A measured BRDF in the MERL binary format.
    #[arg(long, value_name = "F.binary")]
    merl: Option<PathBuf>,
    /// Output material directory (with report.png for paintings).
    #[arg(long, value_name = "MAT")]
    out: PathBuf,
    /// Material kind: uniform p(l) q(h) r(v); four-factor (times s(u,v)); material-map (several
    /// uniform terms blended by coefficient textures); hybrid (a material map of four-factor
    /// terms). The last three need paintings of a mesh with texture coordinates.
    #[arg(long, value_enum, default_value = "uniform")]
    kind: KindArg,
    /// Factor tables: 1D isotropic (radius) or 2D (parabolic).
    #[arg(long, value_enum, default_value = "1d")]
    factors: FactorDim,
    /// Table resolution per axis (default: 128 for 1D, 32 for 2D).
    #[arg(long)]
    res: Option<usize>,
    /// Resolution of the uv factor (four-factor, hybrid; default 32), or of the coefficient
    /// textures (material-map; default 256).
    #[arg(long)]
    uv_res: Option<usize>,
    /// Most terms of a material map or hybrid (default 5; fewer when a term stops helping).
    #[arg(long)]
    terms: Option<usize>,
    /// How a material map or hybrid finds its terms: cluster (regions of one material each,
    /// every term fitted to its region: generalizes to new lights and views) or greedy (the
    /// thesis's fit on positive residuals, eqs. 4.2-4.4).
    #[arg(long, value_enum)]
    map_fit: Option<MapFitArg>,
    /// Laplacian smoothing weight of every factor (default: 1e-5 for 1D, 1e-4 for 2D).
    #[arg(long)]
    lambda: Option<f64>,
    /// Log mapping: auto, identity, offset[:A], inverted[:A].
    #[arg(long, default_value = "auto")]
    mapping: Mapping,
    /// Pixels removed along the silhouette: a pixel within N steps (8-neighbourhood) of the
    /// background is not a sample.
    #[arg(long, value_name = "N", default_value_t = 1)]
    erode: usize,
    /// MERL sampling density k: 2k³ (light, view) pairs.
    #[arg(long, default_value_t = 16)]
    density: usize,
}

/// Settings from the common fit options.
pub(super) fn settings(dim: FactorDim, res: Option<usize>, lambda: Option<f64>) -> Result<Settings> {
    let dim = match dim {
        FactorDim::One => 1,
        FactorDim::Two => 2,
    };
    let default_res = if dim == 1 { crate::factor::defaults::RES_1D } else { crate::factor::defaults::RES_2D };
    let mut s = Settings::uniform(dim, res.unwrap_or(default_res));
    if let Some(l) = lambda {
        for f in &mut s.factors {
            f.smooth = l;
        }
    }
    s.validate()?;
    Ok(s)
}

pub(super) fn run(args: FitArgs) -> Result<()> {
    let mut settings = settings(args.factors, args.res, args.lambda)?;
    if args.kind != KindArg::Uniform && args.merl.is_some() {
        return Err(Error::input("--kind other than uniform needs paintings of a mesh with texture coordinates, not --merl"));
    }
    if args.uv_res.is_some() && args.kind == KindArg::Uniform {
        return Err(Error::input("--uv-res applies to the four-factor, material-map and hybrid kinds"));
    }
    if args.terms.is_some() && matches!(args.kind, KindArg::Uniform | KindArg::FourFactor) {
        return Err(Error::input("--terms applies to the material-map and hybrid kinds"));
    }
    if let Some(t) = args.terms.filter(|t| !(1..=crate::render::MAX_TERMS).contains(t)) {
        return Err(Error::input(format!("--terms {t} is outside 1..={} (the most terms the renderer draws)", crate::render::MAX_TERMS)));
    }
    if args.map_fit.is_some() && matches!(args.kind, KindArg::Uniform | KindArg::FourFactor) {
        return Err(Error::input("--map-fit applies to the material-map and hybrid kinds"));
    }
    if matches!(args.kind, KindArg::FourFactor | KindArg::Hybrid) {
        let four = Settings::four_factor(1, 2, args.uv_res.unwrap_or(crate::factor::defaults::RES_UV));
        let mut uv = four.factors[3].clone();
        if args.kind == KindArg::Hybrid {
            uv.smooth = crate::factor::defaults::SMOOTH_UV_HYBRID;
        }
        settings.factors.push(uv);
        settings.validate()?;
    }
    if args.erode > 64 {
        return Err(Error::input(format!("--erode {} is more than the 64 pixels allowed", args.erode)));
    }
    match &args.merl {
        Some(merl) => run_merl(merl, &args, &settings),
        None => {
            if args.scene.len() != args.image.len() {
                clap::Error::raw(
                    clap::error::ErrorKind::WrongNumberOfValues,
                    format!(
                        "{} --scene and {} --image: give one --image after each --scene\n",
                        args.scene.len(),
                        args.image.len()
                    ),
                )
                .exit();
            }
            run_paintings(&args, &settings)
        }
    }
}

fn save(material: &Material, out: &Path) -> Result<()> {
    stage(material, out)?.commit()
}

/// The material staged for `out`, to which the report is added before it is committed.
fn stage(material: &Material, out: &Path) -> Result<crate::commit::StagedDir> {
    material.stage(out).map_err(|e| match e {
        Error::Io { .. } | Error::Format { .. } => e,
        other => Error::input(format!("{}: {other}", out.display())),
    })
}

fn run_merl(merl_path: &Path, args: &FitArgs, settings: &Settings) -> Result<()> {
    let merl = Merl::read(merl_path)?;
    let samples = merl.samples(args.density)?;
    let (pattern, values): (Pattern, _) = Pattern::from_samples(&samples)?;
    let prepared = prepare(&pattern, settings)?;
    let start = Instant::now();
    let fit = prepared.solve(&values, args.mapping)?;
    let solve_s = start.elapsed().as_secs_f64();
    let provenance = Provenance {
        tool: format!("brdfpaint {}", env!("CARGO_PKG_VERSION")),
        sources: vec![merl_path.display().to_string()],
        errors: Some(fit.errors),
        samples: pattern.len(),
        prepare_s: prepared.prepare_s,
        solve_s,
    };
    let material = Material::from_fit(settings, &fit, provenance)?;
    save(&material, &args.out)?;
    println!(
        "{} samples, {} unknowns: prepare {:.1} ms ({}), solve {:.2} ms",
        pattern.len(),
        prepared.unknowns(),
        prepared.prepare_s * 1e3,
        prepared.solver_kind(),
        solve_s * 1e3
    );
    for (map, e) in &fit.tried {
        println!("  mapping {:<8} RMS {:.5}  relative {:.4}  max {:.4}", map.name(), e.rms, e.rms_relative, e.max);
    }
    println!("kept {}; wrote {}", fit.map.name(), args.out.display());
    Ok(())
}

/// Paintings of scenes: sample every view, check they agree, fit through the prepare
/// cache, write the material and its report. Nothing is written unless everything
/// succeeds up to the save.
fn run_paintings(args: &FitArgs, settings: &Settings) -> Result<()> {
    let erosion = Erosion { radius: args.erode, neighbours: Neighbours::Eight };
    let mut sampler = SceneSampler::new()?;
    let mut views = Vec::new();
    let mut first: Option<crate::scene::Scene> = None;
    for (scene_path, image_path) in args.scene.iter().zip(&args.image) {
        let (scene, view) = sampler.load_view(scene_path, image_path, erosion)?;
        match &first {
            None => first = Some(scene),
            Some(f) => check_same_model(f, &args.scene[0].display().to_string(), &scene, &scene_path.display().to_string())?,
        }
        views.push(view);
    }
    let samples = Samples::gather(&views)?;
    if args.kind != KindArg::Uniform && !samples.pattern.has_uv {
        return Err(Error::input(format!(
            "{}: the model has no texture coordinates, which --kind {} needs (a uv table or coefficient textures)",
            args.scene[0].display(),
            args.kind.to_possible_value().map_or(String::new(), |v| v.get_name().to_string())
        )));
    }
    let cache = Cache::user();
    let fitted = sample::fit(&samples, settings, args.mapping, cache.as_ref())?;
    let fit = &fitted.fit;
    let map = match args.kind {
        KindArg::MaterialMap | KindArg::Hybrid => Some(fit_map(args, &samples, &views, &fitted.prepared)?),
        KindArg::Uniform | KindArg::FourFactor => None,
    };
    let mut sources = Vec::new();
    for (s, i) in args.scene.iter().zip(&args.image) {
        sources.push(s.display().to_string());
        sources.push(i.display().to_string());
    }
    let provenance = Provenance {
        tool: format!("brdfpaint {}", env!("CARGO_PKG_VERSION")),
        sources,
        errors: Some(fit.errors),
        samples: samples.len(),
        prepare_s: fitted.prepare_s,
        solve_s: fitted.solve_s,
    };
    let material = match &map {
        Some((m, report)) => {
            let mut m = m.clone();
            m.provenance = Provenance { errors: Some(report.fitted), solve_s: report.seconds, ..provenance };
            let what = match args.map_fit {
                Some(MapFitArg::Greedy) => "terms on positive residuals",
                _ => "region(s), each sample against its region's product",
            };
            for (k, e) in report.errors.iter().enumerate() {
                println!("{} {what}: RMS {:.5}  relative {:.4}  max {:.4}", k + 1, e.rms, e.rms_relative, e.max);
            }
            m
        }
        None => Material::from_fit(settings, fit, provenance)?,
    };
    let per_view = report::view_errors(&samples, &views, &material);
    let image = report::image(&views, &material)?;
    // report.png is part of the material's directory when it appears.
    let staged = stage(&material, &args.out)?;
    staged.write("report.png", |p| image.write_png(p))?;
    staged.commit()?;
    let report_path = args.out.join("report.png");

    for (k, (view, e)) in views.iter().zip(&per_view).enumerate() {
        println!(
            "view {}: {} in {}: {} samples; RMS {:.5}  relative {:.4}  max {:.4}",
            k + 1,
            view.name,
            view.source,
            samples.per_view[k],
            e.rms,
            e.rms_relative,
            e.max
        );
    }
    let cache_note = match &fitted.outcome {
        Outcome::Hit => "cache hit".to_string(),
        Outcome::Miss => "cache miss, stored".to_string(),
        Outcome::Rebuilt(why) => format!("cache file rebuilt ({why})"),
        Outcome::Uncached(why) => format!("not cached: {why}"),
    };
    println!(
        "{} samples, {} unknowns: prepare {:.1} ms ({}, {}), solve {:.2} ms",
        samples.len(),
        fitted.prepared.unknowns(),
        fitted.prepare_s * 1e3,
        fitted.prepared.solver_kind(),
        cache_note,
        fitted.solve_s * 1e3
    );
    let e = material.provenance.errors.unwrap_or(fit.errors);
    match &map {
        Some((m, report)) => println!(
            "{} with {} terms (fitted in {:.1} ms): RMS {:.5}  relative {:.4}  max {:.4}; wrote {} and {}",
            if m.kind == crate::material::Kind::Hybrid { "hybrid" } else { "material map" },
            m.terms.len(),
            report.seconds * 1e3,
            e.rms,
            e.rms_relative,
            e.max,
            args.out.display(),
            report_path.display()
        ),
        None => {
            for (map, e) in &fit.tried {
                println!("  mapping {:<8} RMS {:.5}  relative {:.4}  max {:.4}", map.name(), e.rms, e.rms_relative, e.max);
            }
            println!(
                "kept {}: RMS {:.5}  relative {:.4}  max {:.4}; wrote {} and {}",
                fit.map.name(),
                e.rms,
                e.rms_relative,
                e.max,
                args.out.display(),
                report_path.display()
            );
        }
    }
    Ok(())
}

/// A material map (or hybrid) on the prepared system of the paintings: the pixel grids of
/// the views fill the coefficient textures' gaps.
fn fit_map(
    args: &FitArgs,
    samples: &Samples,
    views: &[sample::PaintedView],
    prepared: &crate::factor::Prepared,
) -> Result<(Material, crate::material::map::MapReport)> {
    use crate::material::map::{self, MapOptions};
    let grids = samples.grids(views);
    let opts = MapOptions {
        terms: args.terms.unwrap_or(MapOptions::default().terms),
        coef_res: args.uv_res.unwrap_or(MapOptions::default().coef_res),
        mapping: args.mapping,
        method: match args.map_fit {
            Some(MapFitArg::Greedy) => map::Method::Greedy,
            Some(MapFitArg::Cluster) | None => map::Method::Cluster,
        },
        ..Default::default()
    };
    map::fit(prepared, &samples.pattern, &samples.values, &grids, &opts)
}
