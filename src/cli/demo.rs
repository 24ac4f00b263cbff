//! `brdfpaint demo`: the main job on bundled paintings, headless (see [`brdfpaint::demo`]).

use std::path::PathBuf;

use brdfpaint::demo;
use brdfpaint::error::Result;
use brdfpaint::factor::cache::Cache;

#[derive(clap::Args)]
pub(super) struct DemoArgs {
    /// Output directory: a new or empty directory, or an earlier demo's (replaced whole).
    #[arg(long, value_name = "DIR", default_value = demo::DEFAULT_DIR)]
    out: PathBuf,
}

pub(super) fn run(args: DemoArgs) -> Result<()> {
    // Refuse a wrong directory before any work (and before starting GL).
    demo::check_output(&args.out)?;
    let report = demo::run(&args.out, Cache::user().as_ref())?;
    print!("{}", report.summary);
    Ok(())
}
