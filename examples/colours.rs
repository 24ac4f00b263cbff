//! Colours a lit-sphere material invents on the bunny (issue 35; `study::colour`), with
//! the thesis's fit (channels one by one, the mapping of least error) and the default
//! (which leaves it for coupled channels, then the identity mapping, when it invents colours).
//!
//! ```text
//! cargo run --release --example colours -- blender   # the 23 Blender MatCaps (reported on)
//! cargo run --release --example colours -- tuning    # analytic spheres made here (tuned on)
//! cargo run --release --example colours -- blender --png /tmp/colours   # and the bunnies
//! ```
//! Per picture and channel fit: the fraction of lit bunny pixels off the picture's
//! chromaticities under the key light and in the darkest of 8 sweep frames, and the sweep's
//! darkest/brightest.

use std::path::{Path, PathBuf};

use brdfpaint::brdf::{Analytic, Reflectance, SphereView};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::Painting;
use brdfpaint::litsphere::{self, Picture};
use brdfpaint::pipeline::Options;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::Scene;
use brdfpaint::study::colour::{self, Palette, INVENTED};
use glam::{DVec3, Vec3};

const MATCAPS: &str = "../shared/data/matcaps/blender_cc0/exr";
const SIZE: usize = 128;

/// The tuning set: analytic spheres (the truth times a white light) on a black background.
fn tuning(dir: &Path) -> Vec<PathBuf> {
    let grey = |g: f64| [g, g, g];
    let set = [
        ("grey_blinn", Analytic::BlinnPhong { diffuse: [0.42, 0.4, 0.38], specular: grey(0.3), exponent: 40.0 }, DVec3::new(-0.5, 0.5, 1.0)),
        ("grey_ggx_side", Analytic::Ggx { diffuse: grey(0.35), f0: grey(0.4), roughness: 0.35 }, DVec3::new(0.8, 0.2, 0.6)),
        ("tinted_lambert", Analytic::Lambert { albedo: [0.7, 0.45, 0.2] }, DVec3::new(-0.3, 0.6, 1.0)),
        ("teal_ward", Analytic::Ward { diffuse: [0.1, 0.35, 0.4], specular: grey(0.2), alpha: 0.2 }, DVec3::new(0.3, 0.4, 1.0)),
        ("gooch", Analytic::Gooch { warm: [0.9, 0.6, 0.2], cool: [0.1, 0.2, 0.6] }, DVec3::new(-0.5, 0.5, 1.0)),
        ("velvet_red", Analytic::Velvet { diffuse: [0.5, 0.08, 0.08], sheen: [0.6, 0.5, 0.5], roughness: 0.4 }, DVec3::new(0.0, 0.3, 1.0)),
    ];
    set.iter()
        .map(|(name, model, light)| {
            let res = 256;
            let mut p = Painting::opaque(res, res, vec![[0.0; 3]; res * res]).unwrap();
            for px in SphereView::new(*light, res).pixels() {
                p.pixels[px.pixel[1] * res + px.pixel[0]] = model.shading(&px.query).map(|x| x as f32);
            }
            let path = dir.join(format!("{name}.exr"));
            std::fs::write(&path, p.encode_exr().unwrap()).unwrap();
            path
        })
        .collect()
}

fn main() -> brdfpaint::error::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let paths = match args.first().map(String::as_str) {
        Some("tuning") => tuning(tmp.path()),
        Some("dir") => {
            let dir = args.get(1).expect("dir: give the folder of pictures");
            let mut p: Vec<PathBuf> = std::fs::read_dir(dir).expect("the folder").filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|e| ["png", "jpg", "exr"].iter().any(|x| e == *x))).collect();
            p.sort();
            p
        }
        _ => {
            let mut p: Vec<PathBuf> = std::fs::read_dir(MATCAPS).expect("the Blender MatCaps").filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|e| e == "exr")).collect();
            p.sort();
            p
        }
    };
    let png = args.iter().position(|a| a == "--png").and_then(|i| args.get(i + 1)).map(PathBuf::from);
    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let scene = Scene::from_preset("bunny", "front")?;
    let mut gpu = GpuScene::upload(ctx.gl(), &scene)?;
    println!("| picture | independent key | darkest | default key | darkest | darkest/brightest ind. | default | own-scene relative RMS ind. | default |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut count = [0usize; 2];
    let mut own: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for path in &paths {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let palette = Palette::of_painting(&Picture::read(path, litsphere::MAX_SIDE)?.painting);
        let mut row = Vec::new();
        for (k, guard) in [false, true].into_iter().enumerate() {
            // The thesis's fit (channels one by one, the mapping of least error), and the
            // default, which leaves it when it invents colours.
            let opts = Options { keep_colours: guard, ..Options::default() };
            let channels = if guard { "default" } else { "independent" };
            let fit = litsphere::fit(path, None, &opts, None)?;
            own[k].push(fit.fitted.material.provenance.errors.unwrap_or_default().rms_relative);
            // The fit sampled the picture with a context of its own.
            ctx.make_current()?;
            let key = gpu.camera.world_from_camera.transform_vector3(fit.light.as_vec3());
            let shading = renderer.upload(&fit.fitted.material)?;
            let s = colour::sweep(&mut renderer, &mut gpu, &shading, &palette, key, SIZE)?;
            count[k] += (s.worst() > INVENTED) as usize;
            row.push(s);
            if let Some(dir) = &png {
                std::fs::create_dir_all(dir).expect("the PNG folder");
                let side = gpu.camera.world_from_camera.transform_vector3(Vec3::X);
                for (tag, towards) in [("key", key), ("side", side), ("darkest", row[k].darkest_towards)] {
                    gpu.light = brdfpaint::scene::Light::Directional { direction: -towards.normalize(), color: Vec3::ONE, intensity: 1.0 };
                    let image = renderer.factored(&gpu, &shading, 256, 256)?;
                    image.to_rgb().write_png(&dir.join(format!("{name}_{channels}_{tag}.png")))?;
                }
            }
        }
        println!(
            "| {name} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.3} | {:.3} |",
            row[0].key,
            row[0].darkest,
            row[1].key,
            row[1].darkest,
            row[0].darkest_over_brightest,
            row[1].darkest_over_brightest,
            own[0].last().unwrap(),
            own[1].last().unwrap()
        );
    }
    println!("\ninvent colours (> {INVENTED} of lit pixels): independent {} of {}, default {} of {}", count[0], paths.len(), count[1], paths.len());
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!("own-scene relative RMS, median: independent {:.3}, default {:.3}", median(&mut own[0]), median(&mut own[1]));
    Ok(())
}
