//! `brdfpaint bench`.

use brdfpaint::error::{Error, Result};

pub(super) fn run(json: bool, quick: bool, tables: bool, systems: Option<&std::path::Path>) -> Result<()> {
    if let Some(dir) = systems {
        brdfpaint::study::bench::write_systems(dir)?;
    }
    let mut cases = brdfpaint::study::bench::factor_cases(quick)?;
    if tables {
        return print_tables(&cases, json);
    }
    cases.extend(brdfpaint::study::bench::material_map_cases(quick)?);
    let fidelity = brdfpaint::study::bench::fidelity_cases()?;
    // The GL cases need an EGL device; without one the factorization tables still stand.
    let gl = match brdfpaint::study::bench::gl_cases(quick) {
        Ok(gl) => Some(gl),
        Err(e) => {
            eprintln!("warning: GL frame-time cases skipped: {e}");
            None
        }
    };
    let env = match brdfpaint::study::bench::env_cases(quick) {
        Ok(c) => Some(c),
        Err(e) => {
            eprintln!("warning: environment cases skipped: {e}");
            None
        }
    };
    let live = match brdfpaint::study::bench::live_paint_cases(quick) {
        Ok(c) => Some(c),
        Err(e) => {
            eprintln!("warning: live-paint case skipped: {e}");
            None
        }
    };
    let read_fit = match brdfpaint::study::bench::read_fit_cases(quick) {
        Ok(c) => Some(c),
        Err(e) => {
            eprintln!("warning: read + fit cases skipped: {e}");
            None
        }
    };
    if json {
        cases.extend(read_fit.iter().flatten().cloned());
        if let Some((gl_cases, _)) = &gl {
            cases.extend(gl_cases.iter().cloned());
        }
        cases.extend(env.iter().flatten().cloned());
        cases.extend(live.iter().flatten().cloned());
        cases.extend(fidelity);
        println!("{}", serde_json::to_string_pretty(&cases).map_err(|e| Error::input(e.to_string()))?);
    } else {
        print!("{}", brdfpaint::study::bench::table(&cases));
        println!("solve: one RGB refit (log mapping, solve, tables). Thesis: P4 2003, SVD pre-inversion and its fast factorization.");
        println!();
        print!("{}", brdfpaint::study::bench::fidelity_table(&fidelity));
        println!("Table 5.4's metrics on the striped sphere (4 painted views): RMS, max on the samples; held-out: relative RMS, 4 new views.");
        if let Some((gl_cases, device)) = &gl {
            println!();
            print!("{}", brdfpaint::study::bench::gl_table(gl_cases));
            println!("median frame times (clear, draw, glFinish), factored and GGX interleaved, on {device}");
        }
        if let Some(env) = &env {
            println!();
            print!("{}", brdfpaint::study::bench::env_table(env));
            println!("environment: median frames (clear, draw, glFinish) with the key light and the background, interleaved with the point-light frame");
        }
        if let Some(read_fit) = &read_fit {
            println!();
            for c in read_fit {
                println!("{}: {} samples, {:.0} ms (median; `fit --scene` without start-up and files)", c.case, c.samples.unwrap_or(0), c.time_s.unwrap_or(0.0) * 1e3);
            }
        }
        if live.is_some() {
            println!();
        }
        for (k, c) in live.iter().flatten().enumerate() {
            let what = match k {
                0..=2 => "ms stroke -> frame (median; one 60 Hz frame is 16.7 ms)",
                _ => "ms from the pause to the settled material, on the worker",
            };
            println!("{}: {} samples, {:.2} {what}", c.case, c.samples.unwrap_or(0), c.time_s.unwrap_or(0.0) * 1e3);
        }
    }
    Ok(())
}

/// Only the factorization tables.
fn print_tables(cases: &[brdfpaint::study::bench::Case], json: bool) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(cases).map_err(|e| Error::input(e.to_string()))?);
    } else {
        print!("{}", brdfpaint::study::bench::table(cases));
    }
    Ok(())
}
