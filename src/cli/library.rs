//! `brdfpaint fit --lit-sphere A.png B.jpg DIR/ … --out LIB`: a MatCap library in one
//! command ([`brdfpaint::library`]): a progress bar on a terminal, one line per picture that
//! fails, and a summary.

use std::path::Path;

use brdfpaint::error::{Error, Result};
use brdfpaint::factor::cache::Cache;
use brdfpaint::library::{self, Failed, Inputs, Job, Outcome};
use brdfpaint::litsphere;
use brdfpaint::pipeline::Options;

/// Longest side a library's pictures are fitted at by default (`--max-side`); one picture
/// alone is fitted at [`brdfpaint::litsphere::MAX_SIDE`]. Half the side is a quarter of the
/// samples: a MatCap's shading is smooth, and 100 of them fit within two minutes on two cores.
pub(super) const MAX_SIDE: usize = 256;

/// Fits every picture of `inputs` into the library `out` as `ask` says (the light when
/// given, the side each is fitted at, how each is read). Errors: the library could not be
/// written, or a picture failed (each has had its line).
pub(super) fn run(inputs: &Inputs, ask: litsphere::Ask, opts: &Options, out: &Path) -> Result<()> {
    library::check_output(out)?;
    for (dir, pictures, others) in &inputs.folders {
        let ignored = match others {
            0 => String::new(),
            1 => " (1 other entry ignored)".into(),
            n => format!(" ({n} other entries ignored)"),
        };
        println!("{}: {pictures} pictures{ignored}", dir.display());
    }
    let n = inputs.pictures.len();
    let cache = Cache::user();
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let job = Job { ask, opts, cache: cache.as_ref(), workers };
    let bar = brdfpaint::util::progress_enabled().then(|| progress_bar(n));
    let tell = |outcome: Outcome| {
        if let Outcome::Failed(f) = outcome {
            let line = failure_line(f);
            match &bar {
                Some(bar) => bar.println(line),
                None => eprintln!("{line}"),
            }
        }
        if let Some(bar) = &bar {
            bar.inc(1);
        }
    };
    let report = library::build(&inputs.pictures, &job, out, &tell)?;
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let failed = report.failed.len();
    if report.fitted.is_empty() {
        return Err(Error::input(format!("none of the {n} pictures could be fitted; nothing written to {}", out.display())));
    }
    println!(
        "fitted {} of {n} pictures into {}: {}, {} and a folder per material",
        report.fitted.len(),
        out.display(),
        out.join(library::GALLERY).display(),
        out.join(library::INDEX).display()
    );
    if failed > 0 {
        return Err(Error::input(format!("{failed} of {n} pictures failed (each named above); the library holds the others")));
    }
    Ok(())
}

/// `picture: reason`, or the reason alone where it names the picture already.
fn failure_line(f: &Failed) -> String {
    let name = f.picture.display().to_string();
    if f.reason.contains(&name) {
        f.reason.clone()
    } else {
        format!("{name}: {}", f.reason)
    }
}

fn progress_bar(n: usize) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(n as u64);
    let style = indicatif::ProgressStyle::with_template("fitting {bar:30} {pos}/{len} pictures {elapsed} (about {eta} left)")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style);
    bar
}
