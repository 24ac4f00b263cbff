//! The clean truths a painter copies (tools/mypaint/README.md): for every model of the
//! painted study ([`brdfpaint::study::painted::models`]) and each of the study's painted
//! presets, the scene and the true shading under its light and under the light turned by
//! the faults study's angle, as linear EXR and 16-bit sRGB PNG (alpha: the sphere).
//!
//! `cargo run --release --example truth_dump -- OUT [--size 256] [--views 1]`
//!
//! Writes OUT/truth/MODEL/PRESET.gltf and PRESET-{clean,off}.{exr,png}.

use std::path::PathBuf;

use brdfpaint::sample::SceneSampler;
use brdfpaint::study::faults::Faults;
use brdfpaint::study::fidelity::painted_presets;
use brdfpaint::study::painted::{models, write_truth};
use brdfpaint::brdf::Reflectance;

fn main() -> brdfpaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str, default: usize| {
        args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).map_or(default, |v| v.parse().expect("a number"))
    };
    let out = PathBuf::from(args.first().filter(|a| !a.starts_with("--")).expect("usage: truth_dump OUT [--size N] [--views N]"));
    let (size, views) = (value("--size", 256), value("--views", 1));
    let mut sampler = SceneSampler::new()?;
    // The "every fault" case's light is the faults study's (10° off).
    let off = Faults::all().light_off_deg;
    for model in models() {
        for preset in painted_presets(views) {
            let dir = out.join("truth").join(&model.name);
            write_truth(&mut sampler, &preset, size, &model as &dyn Reflectance, off, &dir)?;
            println!("{}/{}", dir.display(), preset.name);
        }
    }
    Ok(())
}
