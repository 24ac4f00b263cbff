//! Regenerates the bundled paintings in `assets/paintings/` (see `brdfpaint::demo::paintings`):
//! each analytic or MERL-fit material is its true shading on the sphere sheet's G-buffer under
//! seeded brush noise; the MatCap (fitted as a lit sphere) is the picture itself, box-filtered
//! to the sheets' size.
//! Deterministic: running it again gives the same files.
//!
//! `cargo run --release --example make_paintings`

use std::collections::BTreeMap;
use std::path::Path;

use brdfpaint::demo::paintings;
use brdfpaint::images::Rgb;
use brdfpaint::sample::SceneSampler;
use brdfpaint::scene::Scene;

fn main() -> brdfpaint::Result<()> {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/paintings");
    let mut sampler = SceneSampler::new()?;
    // The G-buffer of each view, from the scene as the demo writes and reads it back.
    let tmp = std::env::temp_dir().join(format!("make_paintings-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).map_err(|e| brdfpaint::Error::io(&tmp, e))?;
    let mut gbuffers = Vec::new();
    for k in 0..paintings::views().len() {
        let path = tmp.join(format!("view{k}.gltf"));
        paintings::view_scene(k)?.write_gltf(&path)?;
        let scene = Scene::load(&path)?;
        let g = sampler.gbuffer(&scene, paintings::SIZE, paintings::SIZE)?;
        gbuffers.push((scene, g));
    }
    let _ = std::fs::remove_dir_all(&tmp);

    let mut done = BTreeMap::new();
    for spec in paintings::materials() {
        for p in &spec.paintings {
            if done.contains_key(p.file) {
                continue;
            }
            if spec.kind == paintings::FitKind::LitSphere {
                let picture = brdfpaint::images::Painting::read(&assets.join("matcap/toon.exr"))?;
                let (s, _) = brdfpaint::litsphere::shrink(&picture, paintings::SIZE);
                let path = assets.join(p.file);
                Rgb { width: s.width, height: s.height, pixels: s.pixels }.write_png(&path)?;
                println!("{:<18} {:<34} the MatCap at {}x{}", p.file, spec.truth.describe(), s.width, s.height);
                done.insert(p.file, ());
                continue;
            }
            let (scene, g) = &gbuffers[p.view];
            let brush = p.brush_seed.map(paintings::brush);
            let canvas = paintings::paint(&spec.truth, g, scene, brush.as_ref(), None)?;
            let bytes = canvas.encode_png()?;
            let path = assets.join(p.file);
            std::fs::write(&path, &bytes).map_err(|e| brdfpaint::Error::io(&path, e))?;
            println!(
                "{:<18} {:<34} peak {:.3}  {} painted  {} KiB",
                p.file,
                spec.truth.describe(),
                canvas.peak(),
                canvas.painted.iter().filter(|&&x| x).count(),
                bytes.len() / 1024
            );
            done.insert(p.file, ());
        }
    }
    Ok(())
}
