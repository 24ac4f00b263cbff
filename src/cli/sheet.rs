//! `brdfpaint sheet`: the coloring-book page to paint on, and the scene it belongs to.

use std::path::PathBuf;

use super::render::{Resolved, SceneArgs};
use brdfpaint::error::Result;
use brdfpaint::gl::HeadlessContext;
use brdfpaint::render::sheet::{check_output, Sheet};
use brdfpaint::render::Renderer;

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("geometry").required(true).args(["scene", "model"]))]
pub(super) struct SheetArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output directory: outline.png, page.png, reference.png, mask.png, scene.gltf. A new or empty
    /// directory, or an earlier sheet (its four files are replaced, other files kept).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

pub(super) fn run(args: SheetArgs) -> Result<()> {
    check_output(&args.out)?;
    let Resolved { scene, width, height, name } = args.scene.resolve()?;
    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let sheet = Sheet::render(&mut renderer, &scene, width, height)?;
    sheet.save(&scene, &args.out)?;
    let dir = args.out.display();
    println!(
        "sheet of {name} at {width}x{height} in {dir}: outline.png, page.png, reference.png (exposure {:.4}), mask.png ({} pixels), scene.gltf",
        sheet.exposure, sheet.coverage
    );
    println!(
        "paint on page.png (lines on a transparent layer) or outline.png; leave gaps and lines as they are, then: brdfpaint fit --scene {dir}/scene.gltf --image painting.png --out MAT"
    );
    Ok(())
}
