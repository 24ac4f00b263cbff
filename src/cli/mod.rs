//! The `brdfpaint` command line (DESIGN.md, Command line). Every subcommand here works end
//! to end; errors are one line on stderr with exit code 1, usage errors exit with 2.

mod bench;
mod demo;
mod fit;
mod render;
mod sheet;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
    /// Render a material on a scene, headless, to PNG or EXR (or a turntable / light sweep).
    Render(render::RenderArgs),
    /// Write the coloring-book sheet to paint on: outline.png, reference.png, mask.png, scene.gltf.
    Sheet(sheet::SheetArgs),
    /// The real-time window: a material on a model, live painting, watch mode.
    View(Box<view::ViewArgs>),
    /// Reproduce the thesis's timing tables (5.1, 5.2) and time the GL shaders on this machine.
    Bench {
        /// Print one JSON array of cases instead of a table.
        #[arg(long)]
        json: bool,
        /// Shorter timing loops: a first look, not numbers to report.
        #[arg(long)]
        quick: bool,
    },
}

/// Run the command line; the process's exit code.
pub fn run() -> ExitCode {
    std::panic::set_hook(Box::new(|info| {
        // A panic the library catches becomes its one-line error instead.
        if !crate::error::panic_is_caught() {
            eprintln!("error: internal error (please report): {info}");
        }
    }));
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
        Command::Demo(args) => demo::run(args),
        Command::Fit(args) => fit::run(*args),
        Command::Render(args) => render::run(args),
        Command::Sheet(args) => sheet::run(args),
        Command::Bench { json, quick } => bench::run(json, quick),
        Command::View(args) => view::run(*args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
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
