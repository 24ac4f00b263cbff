//! `brdfpaint fit`: samples in, material out.

use std::path::PathBuf;
use std::time::Instant;

use clap::ValueEnum;

use crate::brdf::Merl;
use crate::error::{Error, Result};
use crate::factor::{prepare, Mapping, Pattern, Settings};
use crate::material::{Material, Provenance};

#[derive(Clone, Copy, ValueEnum)]
pub(super) enum FactorDim {
    #[value(name = "1d")]
    One,
    #[value(name = "2d")]
    Two,
}

#[derive(clap::Args)]
pub(super) struct FitArgs {
    /// A measured BRDF in the MERL binary format.
    #[arg(long, value_name = "F.binary")]
    merl: PathBuf,
    /// Output material directory.
    #[arg(long, value_name = "MAT")]
    out: PathBuf,
    /// Factor tables: 1D isotropic (radius) or 2D (parabolic).
    #[arg(long, value_enum, default_value = "1d")]
    factors: FactorDim,
    /// Table resolution per axis (default: 128 for 1D, 32 for 2D).
    #[arg(long)]
    res: Option<usize>,
    /// Laplacian smoothing weight of every factor (default: 1e-5 for 1D, 1e-4 for 2D).
    #[arg(long)]
    lambda: Option<f64>,
    /// Log mapping: auto, identity, offset[:A], inverted[:A].
    #[arg(long, default_value = "auto")]
    mapping: Mapping,
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
    let settings = settings(args.factors, args.res, args.lambda)?;
    let merl = Merl::read(&args.merl)?;
    let samples = merl.samples(args.density)?;
    let (pattern, values): (Pattern, _) = Pattern::from_samples(&samples)?;
    let prepared = prepare(&pattern, &settings)?;
    let start = Instant::now();
    let fit = prepared.solve(&values, args.mapping)?;
    let solve_s = start.elapsed().as_secs_f64();
    let provenance = Provenance {
        tool: format!("brdfpaint {}", env!("CARGO_PKG_VERSION")),
        sources: vec![args.merl.display().to_string()],
        errors: Some(fit.errors),
        samples: pattern.len(),
        prepare_s: prepared.prepare_s,
        solve_s,
    };
    let material = Material::from_fit(&settings, &fit, provenance)?;
    material.save(&args.out).map_err(|e| match e {
        Error::Io { .. } | Error::Format { .. } => e,
        other => Error::input(format!("{}: {other}", args.out.display())),
    })?;
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

