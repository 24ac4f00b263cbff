//! The `brdfpaint` command line (DESIGN.md, Command line): part of the binary, not the
//! library. It parses, calls the library (the fit path is [`brdfpaint::pipeline`]) and
//! prints. Errors are one line on stderr with exit code 1, usage errors exit with 2.

mod bench;
mod demo;
mod export;
mod fit;
mod library;
mod photos;
mod render;
mod sheet;
#[cfg(feature = "viewer")]
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use brdfpaint::Error;

/// Why a subcommand failed: a usage error (exit code 2) or a failure of the work (1).
pub enum Failure {
    Usage(String),
    Error(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Error(e)
    }
}

#[derive(Parser)]
#[command(name = "brdfpaint", version, about = "Paint or photograph an object, get a real-time factored BRDF")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The main job, headless: fit the bundled paintings and retarget them (DIR/contact.png).
    ///
    /// Writes the sphere's sheet, the bundled paintings, their fitted materials, renders on
    /// the sphere, bunny, suzanne and teapot under new lights, contact.png and summary.txt
    /// into DIR, and prints the summary.
    Demo(demo::DemoArgs),
    /// Fit a material to paintings of scenes, or to measured data.
    Fit(Box<fit::FitArgs>),
    /// A material out into other tools: a glTF 2.0 binary with its closest PBR material.
    Export(export::ExportArgs),
    /// Render a material on a scene, headless, to PNG or EXR (or a turntable / light sweep).
    Render(render::RenderArgs),
    /// Write the coloring-book sheet to paint on: outline.png, reference.png, mask.png, scene.gltf.
    Sheet(sheet::SheetArgs),
    /// The real-time window: a material on a model, live painting, watch mode.
    #[cfg(feature = "viewer")]
    View(Box<view::ViewArgs>),
    /// Reproduce the thesis's timing tables (5.1, 5.2) and time the GL shaders on this machine.
    Bench {
        /// Print one JSON array of cases instead of a table.
        #[arg(long)]
        json: bool,
        /// Shorter timing loops: a first look, not numbers to report.
        #[arg(long)]
        quick: bool,
        /// Only the factorization cases of thesis tables 5.1 and 5.2 (and the 256² product).
        #[arg(long)]
        tables: bool,
        /// Also write the systems of tables 5.1 and 5.2 into this folder, for the reference
        /// implementation `tools/reference/cholesky.py` to time.
        #[arg(long, value_name = "DIR")]
        systems: Option<std::path::PathBuf>,
    },
}

/// `WxH` (or `WXH`) with both sides in `range`: the one size rule of `--size` and
/// `--window`. Errors name the flag.
pub(crate) fn parse_size(flag: &str, text: &str, range: std::ops::RangeInclusive<usize>) -> brdfpaint::Result<(usize, usize)> {
    let bad = || Error::input(format!("{flag} {text}: expected WxH, e.g. 512x512"));
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (usize, usize) = (w.trim().parse().map_err(|_| bad())?, h.trim().parse().map_err(|_| bad())?);
    if !range.contains(&w) || !range.contains(&h) {
        return Err(Error::input(format!(
            "{flag} {text}: width and height must be {} to {} pixels",
            range.start(),
            range.end()
        )));
    }
    Ok((w, h))
}

/// Run the command line; the process's exit code.
pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            // No subcommand at all: the help is the answer.
            let _ = e.print();
            return ExitCode::from(2);
        }
        Err(e) if e.use_stderr() => {
            eprintln!("{}", one_line_usage_error(&e));
            return ExitCode::from(2);
        }
        Err(e) => {
            // --help and --version.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    let result = match cli.command {
        Command::Demo(args) => demo::run(args).map_err(Failure::from),
        Command::Fit(args) => fit::run(*args),
        Command::Export(args) => export::run(args).map_err(Failure::from),
        Command::Render(args) => render::run(args),
        Command::Sheet(args) => sheet::run(args).map_err(Failure::from),
        Command::Bench { json, quick, tables, systems } => bench::run(json, quick, tables, systems.as_deref()).map_err(Failure::from),
        #[cfg(feature = "viewer")]
        Command::View(args) => view::run(*args).map_err(Failure::from),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Error(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

/// clap's message for a usage error as one line: the error and the arguments it names,
/// without the usage block and tips (DESIGN.md: errors are one readable line).
fn one_line_usage_error(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let mut parts = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if !line.is_empty() && !line.starts_with("tip:") {
            parts.push(line);
        }
    }
    let message = parts.join(" ");
    if message.starts_with("error:") {
        message
    } else {
        format!("error: {message}")
    }
}
