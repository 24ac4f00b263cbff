//! Brush texture kept (`fit --lit-sphere --texture keep`, issue 36) on paintings made by
//! MyPaint's brush engine (tools/mypaint): per painting, the high-pass contrast of its
//! texture (over its fit) and of the bunny's (with the detail over without), and how far a
//! light sweep round the bunny still darkens it ([`brdfpaint::study::texture`]).
//!
//! ```text
//! cargo run --release --example texture_kept -- DATA [CASE]
//! ```
//! DATA is `tools/mypaint/make_set.sh`'s folder (DATA/paintings/MODEL/*.png); CASE (default
//! `texture`) picks the paintings whose name holds `-CASE-`.

use std::path::PathBuf;

use brdfpaint::gl::HeadlessContext;
use brdfpaint::litsphere::{self, Ask};
use brdfpaint::pipeline::Options;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::Scene;
use brdfpaint::study::{median, texture};

const SIZE: usize = 512;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(data) = args.first().map(PathBuf::from) else {
        return Err("usage: texture_kept DATA [CASE]".into());
    };
    let case = format!("-{}-", args.get(1).map_or("texture", String::as_str));
    let mut paintings: Vec<PathBuf> = Vec::new();
    for model in std::fs::read_dir(data.join("paintings"))? {
        for file in std::fs::read_dir(model?.path())? {
            let path = file?.path();
            if path.file_name().is_some_and(|n| n.to_string_lossy().contains(&case)) {
                paintings.push(path);
            }
        }
    }
    paintings.sort();
    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let scene = Scene::from_preset("bunny", "front-left")?;
    let mut gpu = GpuScene::upload(ctx.gl(), &scene)?;
    println!("painting,painting_contrast,kept_contrast,kept_ratio,sweep_kept,sweep_dropped,painting_scale,kept_scale");
    let (mut ratios, mut sweeps) = (Vec::new(), Vec::new());
    for path in &paintings {
        let ask = Ask { keep_texture: true, ..Ask::default() };
        let lit = match litsphere::fit_in(path, &ask, &Options::default(), None) {
            Ok(lit) => lit,
            Err(e) => {
                println!("{},refused: {e}", path.display());
                continue;
            }
        };
        // The fit drew its samples on a context of its own.
        ctx.make_current()?;
        let painted = texture::painting_texture(&lit.view, &lit.fitted.material);
        let dropped = brdfpaint::material::Material { detail: None, ..lit.fitted.material.clone() };
        let shading = renderer.upload(&lit.fitted.material)?;
        gpu.light = scene.light;
        let with = renderer.factored(&gpu, &shading, SIZE, SIZE)?;
        let without = renderer.factored(&gpu, &renderer.upload(&dropped)?, SIZE, SIZE)?;
        let kept = texture::render_texture(&with, &without);
        let sweep = texture::sweep_ratio(&mut renderer, &mut gpu, &shading, 256, 8)?;
        let plain = renderer.upload(&dropped)?;
        let sweep_dropped = texture::sweep_ratio(&mut renderer, &mut gpu, &plain, 256, 8)?;
        let name = path.strip_prefix(&data).unwrap_or(path).display().to_string();
        println!("{name},{:.4},{:.4},{:.2},{sweep:.3},{sweep_dropped:.3},{:.3},{:.3}", painted.contrast, kept.contrast, kept.contrast / painted.contrast, painted.scale, kept.scale);
        ratios.push(kept.contrast / painted.contrast);
        sweeps.push(sweep);
    }
    let worst = |v: &[f64], f: fn(f64, f64) -> f64, start: f64| v.iter().cloned().fold(start, f);
    println!(
        "{} paintings: kept/painting contrast median {:.2}, range {:.2} to {:.2}; sweep darkest/brightest median {:.3}, worst {:.3}",
        ratios.len(),
        median(&ratios),
        worst(&ratios, f64::min, f64::INFINITY),
        worst(&ratios, f64::max, 0.0),
        median(&sweeps),
        worst(&sweeps, f64::max, 0.0)
    );
    Ok(())
}
