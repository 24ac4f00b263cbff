//! `brdfpaint export`: a material out into other tools: a glTF 2.0 binary (`--gltf`) with
//! the closest metallic-roughness material and the exact factored one packed in it, and a
//! MatCap (`--matcap`) under a light or an environment.

use std::path::{Path, PathBuf};

use brdfpaint::error::{Error, Result};
use brdfpaint::export;
use brdfpaint::material::Material;

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("target").required(true).multiple(true).args(["gltf", "matcap"]))]
pub(super) struct ExportArgs {
    /// Material directory (or its material.json).
    #[arg(value_name = "MAT")]
    material: PathBuf,
    /// Write a glTF 2.0 binary: the model with the closest metallic-roughness material, and
    /// the exact material under the EXT_brdfpaint_factored extension (render and view read it).
    #[arg(long, value_name = "OUT.glb")]
    gltf: Option<PathBuf>,
    /// With --gltf: the model, a built-in name (sphere, bunny, suzanne, teapot, apple, fox) or
    /// a .glb/.gltf file. Default: sphere.
    #[arg(long, value_name = "NAME|M.glb", requires = "gltf")]
    model: Option<PathBuf>,
    /// Write a MatCap: the material on a sphere seen from the front, as MatCap tools expect.
    /// PNG (8-bit sRGB, transparent off the disk) or EXR (linear float; `diffuse` and
    /// `specular` layers when the material has an analytic base).
    #[arg(long, value_name = "OUT.png|OUT.exr")]
    matcap: Option<PathBuf>,
    /// With --matcap: the direction towards the light, X,Y,Z (x right, y up, z to the
    /// viewer). Default: the light of the picture the material was fitted to, else upper front.
    #[arg(long, value_name = "X,Y,Z", requires = "matcap", allow_hyphen_values = true, conflicts_with = "env")]
    light: Option<String>,
    /// With --matcap: light by an environment (.hdr or .exr, 2:1 equirectangular) instead.
    #[arg(long, value_name = "E.hdr", requires = "matcap")]
    env: Option<PathBuf>,
    /// With --matcap: the image's side in pixels (16 to 4096). Default 512.
    #[arg(long, value_name = "N", requires = "matcap")]
    size: Option<usize>,
}

/// The MatCap's light when neither the command nor the material gives one: upper front,
/// 30° above the view.
const UPPER_FRONT: [f64; 3] = [0.0, 0.5, 0.866];

pub(super) fn run(args: ExportArgs) -> Result<()> {
    let material = Material::load(&args.material)?;
    if let Some(out) = &args.matcap {
        matcap(&args, &material, out)?;
    }
    if let Some(out) = &args.gltf {
        gltf(&args, &material, out)?;
    }
    Ok(())
}

fn gltf(args: &ExportArgs, material: &Material, out: &Path) -> Result<()> {
    let is_glb = out.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    if !is_glb {
        return Err(Error::input(format!("--gltf {}: the output is a glTF binary, give a .glb name", out.display())));
    }
    let model = args.model.clone().unwrap_or_else(|| PathBuf::from("sphere"));
    let meshes = brdfpaint::scene::model_meshes(&model)?;
    let report = export::export_gltf(&args.material, material, &meshes, out)?;
    let (covered, all) = match &report.textured {
        Some(t) => {
            print_textured(&t.map);
            (t.covered, t.all)
        }
        None => {
            print_uniform(&report.approximation.pbr);
            (report.approximation.covered, report.approximation.all)
        }
    };
    if report.covered_pairs > 0 {
        let scenes: Vec<String> = report.scenes.iter().map(|s| s.display().to_string()).collect();
        println!(
            "relative RMS against the factored material: {:.4} over the {} direction pairs the paintings covered ({}), {:.4} over all directions",
            covered,
            report.covered_pairs,
            scenes.join(", "),
            all
        );
    } else {
        println!(
            "relative RMS against the factored material: {:.4} over all directions (the paintings' scenes were not found, so the covered directions are unknown)",
            all
        );
    }
    if report.textured.is_some() {
        println!("(one material for the whole surface would be {:.4} over the same directions)", report.approximation.covered);
    }
    if material.detail.is_some() {
        println!("note: the painting's brush texture (fit --texture keep) travels with the exact material only: glTF's materials have no detail that follows the view");
    }
    println!("wrote {} ({} model, {:.1} KiB, exact material under EXT_brdfpaint_factored)", out.display(), model.display(), report.bytes as f64 / 1024.0);
    Ok(())
}

fn print_uniform(p: &export::pbr::Pbr) {
    println!(
        "glTF metallic-roughness: base colour ({:.3}, {:.3}, {:.3}), metallic {:.3}, roughness {:.3}",
        p.base_color[0], p.base_color[1], p.base_color[2], p.metallic, p.roughness
    );
    if let Some(k) = p.specular_color() {
        println!("KHR_materials_specular: dielectric F0 {:.3} (specularColorFactor {k:.2}, grey)", p.specular_f0);
    }
    if let Some(c) = p.coat {
        println!("KHR_materials_clearcoat: factor {:.3}, roughness {:.3}", c.factor, c.roughness);
    }
    if let Some(s) = p.sheen {
        println!("KHR_materials_sheen: colour ({:.3}, {:.3}, {:.3}), roughness {:.3}", s.color[0], s.color[1], s.color[2], s.roughness);
    }
}

/// A textured material in ranges: the 5th to the 95th percentile over its texels.
fn print_textured(map: &export::pbr_map::PbrMap) {
    let range = |f: &dyn Fn(&export::pbr::Pbr) -> f64| {
        let mut v: Vec<f64> = map.texels.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        let at = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
        format!("{:.3}–{:.3}", at(0.05), at(0.95))
    };
    println!(
        "glTF metallic-roughness textures, {0}×{0} texels (5th–95th percentile): base colour R {1}, G {2}, B {3}; metallic {4}; roughness {5}",
        map.res,
        range(&|p| p.base_color[0]),
        range(&|p| p.base_color[1]),
        range(&|p| p.base_color[2]),
        range(&|p| p.metallic),
        range(&|p| p.roughness)
    );
    if map.factors().specular_color().is_some() {
        println!("KHR_materials_specular: dielectric F0 {}, at most {:.3} (specularColorTexture, grey)", range(&|p| p.specular_f0), map.max_f0());
    }
}

fn matcap(args: &ExportArgs, material: &Material, out: &Path) -> Result<()> {
    use export::matcap::{self, Lighting};
    let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let exr = match ext.as_deref() {
        Some("png") => false,
        Some("exr") => true,
        _ => return Err(Error::input(format!("--matcap {}: give a .png or .exr name", out.display()))),
    };
    let size = args.size.unwrap_or(512);
    if !(16..=4096).contains(&size) {
        return Err(Error::input(format!("--size {size}: give 16 to 4096 pixels")));
    }
    let env = args.env.as_deref().map(brdfpaint::images::env::Environment::load).transpose()?;
    let (lighting, said) = match (&env, &args.light) {
        (Some(e), _) => (Lighting::Env(e, 0.0), format!("the environment {}", args.env.as_ref().unwrap().display())),
        (None, Some(text)) => {
            let l = parse_direction(text)?;
            (Lighting::Light(l), format!("light ({:.2}, {:.2}, {:.2}) as given", l.x, l.y, l.z))
        }
        (None, None) => match export::picture_light(&args.material, material) {
            Some(l) => (Lighting::Light(l), format!("the picture's light ({:.2}, {:.2}, {:.2})", l.x, l.y, l.z)),
            None => (Lighting::Light(glam::DVec3::from_array(UPPER_FRONT).normalize()), "an upper-front light (no picture light recorded)".into()),
        },
    };
    let m = matcap::render(material, size, &lighting);
    let bytes = if exr { matcap::exr_bytes(&m)? } else { matcap::png_bytes(&m)? };
    brdfpaint::commit::write_atomic(out, &bytes)?;
    let layers = if exr && m.parts.is_some() { ", layers diffuse and specular" } else { "" };
    println!("wrote {} ({size}x{size} MatCap under {said}{layers})", out.display());
    Ok(())
}

/// `X,Y,Z`, not zero, finite.
fn parse_direction(text: &str) -> Result<glam::DVec3> {
    let v: Vec<f64> = text.split(',').filter_map(|p| p.trim().parse().ok()).collect();
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) && (x, y, z) != (0.0, 0.0, 0.0) && text.split(',').count() == 3 => {
            Ok(glam::DVec3::new(x, y, z).normalize())
        }
        _ => Err(Error::input(format!("--light '{text}' is not a direction X,Y,Z (e.g. -0.5,0.5,1)"))),
    }
}
