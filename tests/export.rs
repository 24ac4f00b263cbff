//! `brdfpaint export`: a lit sphere painted with a known glTF material comes back out as
//! that material; the .glb passes the Khronos validator and carries the exact material.

mod cli_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use brdfpaint::brdf::{Analytic, Reflectance, SphereView, Striped};
use brdfpaint::factor::{prepare, Query, Settings};
use brdfpaint::export::coverage::Directions;
use brdfpaint::export::pbr::{Coat, Pbr};
use brdfpaint::export::{gltf, pbr_fit, pbr_map};
use brdfpaint::material::map::{self, MapOptions};
use brdfpaint::material::packed;
use brdfpaint::images::Painting;
use brdfpaint::material::packed::split_glb;
use brdfpaint::material::Material;
use cli_common::brdfpaint;
use glam::{DVec2, DVec3};

/// The target's material: glTF base colour, roughness, F0 of a dielectric (issue 38).
const BASE: [f64; 3] = [0.8, 0.25, 0.1];
const ROUGHNESS: f64 = 0.5;
const F0: f64 = 0.04;
/// The picture's light, towards it, picture frame (x right, y up, z to the viewer).
const LIGHT: [f64; 3] = [-0.4, 0.5, 0.77];

/// A GGX sphere in the painter's convention: pixel = base colour × cos θ_l for the diffuse
/// part, i.e. π × the BRDF × cos θ_l ([`Analytic::Ggx`]'s diffuse is ρ/π; glTF's α =
/// roughness² as here).
fn ggx_lit_sphere(res: usize, f0: f64) -> Painting {
    let model = Analytic::Ggx { diffuse: BASE, f0: [f0; 3], roughness: ROUGHNESS };
    lit_sphere(res, |q| model.shading(q).map(|x| std::f64::consts::PI * x))
}

/// A lit sphere whose pixel at each normal is `pixel` under [`LIGHT`], seen from the front:
/// the disk inscribed in the square, on a transparent background.
fn lit_sphere(res: usize, pixel: impl Fn(&Query) -> [f64; 3]) -> Painting {
    let mut p = Painting::opaque(res, res, vec![[0.0; 3]; res * res]).unwrap();
    p.alpha = vec![0.0; res * res];
    let light = DVec3::from_array(LIGHT).normalize();
    for j in 0..res {
        for i in 0..res {
            let (x, y) = (2.0 * (i as f64 + 0.5) / res as f64 - 1.0, 1.0 - 2.0 * (j as f64 + 0.5) / res as f64);
            let rr = x * x + y * y;
            if rr >= 1.0 {
                continue;
            }
            let q = SphereView::query(DVec3::new(x, y, (1.0 - rr).sqrt()), light, DVec3::Z);
            p.pixels[j * res + i] = pixel(&q).map(|x| x as f32);
            p.alpha[j * res + i] = 1.0;
        }
    }
    p
}

/// `picture` fitted as a lit sphere under [`LIGHT`] and exported to `NAME.glb` in `dir`: the
/// export's run and the file.
fn fitted_and_exported(dir: &Path, picture: &Painting, name: &str, fit: &[&str]) -> (cli_common::Run, PathBuf) {
    let png = dir.join(format!("{name}.png"));
    std::fs::write(&png, picture.encode_png16().unwrap()).unwrap();
    let mat = dir.join("mat");
    let l = format!("{},{},{}", LIGHT[0], LIGHT[1], LIGHT[2]);
    let mut args = vec!["fit", "--lit-sphere", png.to_str().unwrap(), "--light", &l, "--out", mat.to_str().unwrap()];
    args.extend_from_slice(fit);
    let run = brdfpaint(dir, &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let glb = dir.join(format!("{name}.glb"));
    let run = brdfpaint(dir, &["export", mat.to_str().unwrap(), "--gltf", glb.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    eprintln!("{}", run.stdout);
    (run, glb)
}

/// The Khronos validator's report on `file`, or `None` (with a message) when node or the
/// validator is not installed (tools/setup.sh installs both).
fn validate(file: &Path) -> Option<serde_json::Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/gltf-validator/validate.js");
    let installed = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/gltf-validator/node_modules/gltf-validator");
    let node_ok = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    if !node_ok || !installed.is_dir() {
        eprintln!("SKIPPED the glTF validator: node or tools/gltf-validator/node_modules missing (run tools/setup.sh)");
        return None;
    }
    let out = Command::new("node").arg(&script).arg(file).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("validator output is not JSON ({e}): {}", String::from_utf8_lossy(&out.stderr)));
    Some(report)
}

fn assert_valid(file: &Path) {
    if let Some(report) = validate(file) {
        let errors = report["issues"]["numErrors"].as_u64().unwrap();
        assert_eq!(errors, 0, "{}: {:#}", file.display(), report["issues"]);
    }
}

/// The PBR material of an exported .glb: base colour, metallic, roughness.
fn pbr_of(file: &Path) -> ([f64; 3], f64, f64) {
    let bytes = std::fs::read(file).unwrap();
    let (json, _) = split_glb(&bytes).unwrap();
    let p = &json["materials"][0]["pbrMetallicRoughness"];
    let c: Vec<f64> = p["baseColorFactor"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    (
        [c[0], c[1], c[2]],
        p["metallicFactor"].as_f64().unwrap(),
        p["roughnessFactor"].as_f64().unwrap(),
    )
}

/// A fit of the target sphere: (directory, material).
fn fitted_sphere(dir: &Path) -> (PathBuf, PathBuf) {
    fitted_sphere_with(dir, F0)
}

/// A fit of the target sphere with dielectric F0 `f0`: (directory, material).
fn fitted_sphere_with(dir: &Path, f0: f64) -> (PathBuf, PathBuf) {
    let png = dir.join("ggx.png");
    std::fs::write(&png, ggx_lit_sphere(256, f0).encode_png16().unwrap()).unwrap();
    let mat = dir.join("mat");
    let light = format!("{},{},{}", LIGHT[0], LIGHT[1], LIGHT[2]);
    let run = brdfpaint(dir, &["fit", "--lit-sphere", png.to_str().unwrap(), "--light", &light, "--out", mat.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    (png, mat)
}

#[test]
fn a_painted_ggx_sphere_exports_its_gltf_material() {
    let dir = tempfile::tempdir().unwrap();
    let (_, mat) = fitted_sphere(dir.path());
    let glb = dir.path().join("ggx.glb");
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--gltf", glb.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    eprintln!("{}", run.stdout);
    let (base, metallic, roughness) = pbr_of(&glb);
    for c in 0..3 {
        assert!((base[c] - BASE[c]).abs() <= 0.1 * BASE[c], "base colour {base:?} vs {BASE:?}\n{}", run.stdout);
    }
    assert!((roughness - ROUGHNESS).abs() <= 0.1, "roughness {roughness}\n{}", run.stdout);
    assert!(metallic <= 0.2, "metallic {metallic}\n{}", run.stdout);
    assert!(run.stdout.contains("over the ") && run.stdout.contains("over all directions"), "{}", run.stdout);
    assert_valid(&glb);

    // The exact material travels in the file: loaded back, it is the fitted one.
    let exact = Material::load(&mat).unwrap();
    let packed = Material::load(&glb).unwrap();
    assert_eq!(exact.terms, packed.terms);
}

#[test]
fn a_varnish_brighter_than_core_gltf_exports_khr_materials_specular() {
    // F0 = 0.2 (index of refraction about 2.6): core glTF's dielectric stops at 0.04, so the
    // extension carries it, as specularColorFactor 0.2 / 0.04 = 5 (grey).
    let dir = tempfile::tempdir().unwrap();
    let (_, mat) = fitted_sphere_with(dir.path(), 0.2);
    let glb = dir.path().join("varnish.glb");
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--gltf", glb.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let (base, metallic, roughness) = pbr_of(&glb);
    // The picture's diffuse (Analytic::Ggx, ρ/π) has no (1 − F) factor and glTF's has: the
    // fit puts back about 1 / (1 − F0), capped at 1.
    let want = BASE.map(|b| (b / (1.0 - 0.2)).min(1.0));
    for c in 0..3 {
        assert!((base[c] - want[c]).abs() <= 0.1 * want[c], "base colour {base:?} vs {want:?}\n{}", run.stdout);
    }
    assert!((roughness - ROUGHNESS).abs() <= 0.1 && metallic <= 0.2, "roughness {roughness}, metallic {metallic}\n{}", run.stdout);
    let (json, _) = split_glb(&std::fs::read(&glb).unwrap()).unwrap();
    let k = json["materials"][0]["extensions"]["KHR_materials_specular"]["specularColorFactor"][0].as_f64().unwrap();
    assert!((k - 5.0).abs() <= 1.0, "specularColorFactor {k}\n{}", run.stdout);
    assert!(json["extensionsUsed"].as_array().unwrap().iter().any(|e| e == "KHR_materials_specular"));
    assert!(run.stdout.contains("KHR_materials_specular"), "{}", run.stdout);
    assert_valid(&glb);
    // Core glTF's own dielectric needs no extension.
    std::fs::create_dir(dir.path().join("core")).unwrap();
    let (_, core) = fitted_sphere(&dir.path().join("core"));
    let core_glb = dir.path().join("core.glb");
    assert_eq!(brdfpaint(dir.path(), &["export", core.to_str().unwrap(), "--gltf", core_glb.to_str().unwrap()]).code, 0);
    let (json, _) = split_glb(&std::fs::read(&core_glb).unwrap()).unwrap();
    assert!(json["materials"][0]["extensions"].get("KHR_materials_specular").is_none(), "{}", json["materials"][0]);
}

/// The images of an exported .glb, decoded, in the order of its `images` array.
fn images_of(file: &Path) -> Vec<image::RgbImage> {
    let bytes = std::fs::read(file).unwrap();
    let (json, _) = split_glb(&bytes).unwrap();
    // The BIN chunk follows the 12-byte header, the JSON chunk and the BIN chunk's 8-byte header.
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let bin = &bytes[20 + json_len + 8..];
    json["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|im| {
            let view = &json["bufferViews"][im["bufferView"].as_u64().unwrap() as usize];
            let offset = view["byteOffset"].as_u64().unwrap() as usize;
            let len = view["byteLength"].as_u64().unwrap() as usize;
            image::load_from_memory(&bin[offset..offset + len]).unwrap().into_rgb8()
        })
        .collect()
}

#[test]
fn a_material_map_exports_a_pbr_material_per_texel() {
    // The striped object of tests/material_map.rs: glossy dark varnish (Blinn-Phong n = 40)
    // and matte orange wood (Lambert) in eight bands of u, fitted as a material map, and its
    // PBR material fitted on the directions its paintings covered.
    let object = Striped::wood();
    let (pattern, values, grids) = object.paint(&Striped::painted_views(90));
    let prepared = prepare(&pattern, &Settings::default()).unwrap();
    let (material, _) = map::fit(&prepared, &pattern, &values, &grids, &MapOptions::default()).unwrap();
    let covered = Directions { weights: vec![1.0; pattern.queries.len()], queries: pattern.queries, scenes: Vec::new() };
    let all = Directions::all();
    let textured = pbr_map::fit(&material, Some(&covered), &all, pbr_map::resolution(&material));
    let one = pbr_fit::fit(&material, Some(&covered), &all);
    eprintln!("per texel {:.4} (all directions {:.4}), one material {:.4}", textured.covered, textured.all, one.covered);
    // Measured 0.120 per texel and 0.514 for one material: the bar for the demo's
    // physical materials is 0.15.
    assert!(textured.covered <= 0.15 && textured.covered < 0.5 * one.covered, "per texel {}, one material {}", textured.covered, one.covered);

    // Each band's texels against the band's true material, on the painted directions a
    // texel away from the band's edges (where a texture blends the two materials).
    let res = textured.map.res as f64;
    for region in 0..2 {
        let truth = if region == 0 { &object.a } else { &object.b };
        let inside: Vec<_> = covered.queries.iter().filter(|q| {
            let e = q.uv.x * 8.0;
            object.region(q.uv.x) == region && (e - e.round()).abs() / 8.0 > 1.5 / res
        }).copied().collect();
        let dirs = Directions { weights: vec![1.0; inside.len()], queries: inside, scenes: Vec::new() };
        let to_truth = pbr_fit::relative_rms(&textured.map, truth, &dirs);
        eprintln!("region {region}: per texel vs truth {to_truth:.4} ({} directions)", dirs.len());
        // Measured 0.115 (the varnish: a Blinn-Phong lobe and a dark diffuse under glTF's
        // GGX, which chooses a grey metal) and 0.020 (the Lambert wood).
        let bound = if region == 0 { 0.15 } else { 0.05 };
        assert!(to_truth <= bound, "region {region}: {to_truth} against its true material");
    }
    for band in 0..8 {
        // Each band's middle, half-way up.
        let p = textured.map.at(DVec2::new((band as f64 + 0.5) / 8.0, 0.5));
        eprintln!("band {band}: {p:?}");
        if object.region((band as f64 + 0.5) / 8.0) == 1 {
            assert!(p.metallic <= 0.2, "band {band}: {p:?}");
        } else {
            // Blinn-Phong n = 40 is GGX of α ≈ sqrt(2 / (n + 2)) = 0.22: roughness √α = 0.47.
            assert!((p.roughness - 0.47).abs() <= 0.1, "band {band}: {p:?}");
        }
    }

    // The .glb holds the map as textures, decoded to the same texels, and is valid.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("wood.glb");
    let meshes = brdfpaint::scene::model_meshes(Path::new("sphere")).unwrap();
    let glb = gltf::Glb { meshes: &meshes, pbr: textured.map.factors(), textures: Some(textured.map.textures().unwrap()), factored: packed::pack(&material).unwrap() };
    gltf::write(&file, &glb).unwrap();
    assert_valid(&file);
    let images = images_of(&file);
    let n = textured.map.res;
    assert_eq!((images[0].width() as usize, images[1].height() as usize), (n, n));
    let srgb = |code: u8| brdfpaint::images::srgb_to_linear(code as f32 / 255.0) as f64;
    for (k, p) in textured.map.texels.iter().enumerate().step_by(97) {
        let (x, y) = ((k % n) as u32, (k / n) as u32);
        let (c, m) = (images[0].get_pixel(x, y), images[1].get_pixel(x, y));
        assert!((0..3).all(|i| (srgb(c[i]) - p.base_color[i]).abs() < 1e-6), "texel {k}: {c:?} vs {p:?}");
        assert!((m[1] as f64 / 255.0 - p.roughness).abs() < 1e-6 && (m[2] as f64 / 255.0 - p.metallic).abs() < 1e-6, "texel {k}: {m:?} vs {p:?}");
    }

    // The command writes the textured material for a saved map (no scenes here: over all
    // directions) and says what one material would have missed.
    let mat = dir.path().join("wood");
    material.save(&mat).unwrap();
    let out = dir.path().join("cli.glb");
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--gltf", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("textures, ") && run.stdout.contains("one material for the whole surface would be"), "{}", run.stdout);
    let (json, _) = split_glb(&std::fs::read(&out).unwrap()).unwrap();
    assert!(json["materials"][0]["pbrMetallicRoughness"].get("baseColorTexture").is_some(), "{}", json["materials"][0]);
    assert_valid(&out);
}

/// The relative RMS after `label` in the export's report ("… {label} 0.1234 …").
fn reported(stdout: &str, label: &str) -> f64 {
    let at = stdout.find(label).unwrap_or_else(|| panic!("no '{label}' in\n{stdout}")) + label.len();
    stdout[at..].split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_coated_lit_sphere_exports_khr_materials_clearcoat() {
    // A rough red base under a sharp full clear coat, drawn as a lit sphere in painter units
    // (the pixel is the glTF material's S = π f cos θ_l).
    let truth = Pbr { coat: Some(Coat { factor: 1.0, roughness: 0.35 }), ..Pbr::core([0.3, 0.06, 0.03], 0.0, 0.7) };
    let dir = tempfile::tempdir().unwrap();
    let (run, glb) = fitted_and_exported(dir.path(), &lit_sphere(256, |q| truth.shading(q)), "coated", &[]);
    // One light shows a sharp coat over a rough base much as a rougher base under a weaker
    // coat, and the factored material is itself 0.076 from the truth there: the coat is
    // asked to be there and the base colour kept, not the truth's parameters (measured:
    // coat 0.45 of roughness 0.31 over base roughness 0.45; base colour within 2%, 15%, 33%).
    let (json, _) = split_glb(&std::fs::read(&glb).unwrap()).unwrap();
    let coat = &json["materials"][0]["extensions"]["KHR_materials_clearcoat"];
    let factor = coat["clearcoatFactor"].as_f64().unwrap_or(0.0);
    assert!(factor >= 0.25 && coat["clearcoatRoughnessFactor"].as_f64().unwrap() < 0.5, "coat {coat}\n{}", run.stdout);
    assert!(json["extensionsUsed"].as_array().unwrap().iter().any(|e| e == "KHR_materials_clearcoat"));
    let (base, metallic, _) = pbr_of(&glb);
    assert!(metallic <= 0.2 && (base[0] - 0.3).abs() <= 0.03, "base {base:?}, metallic {metallic}\n{}", run.stdout);
    assert!(reported(&run.stdout, "factored material:") <= 0.08, "{}", run.stdout);
    assert_valid(&glb);
}

#[test]
fn a_velvet_lit_sphere_exports_khr_materials_sheen() {
    // The analytic velvet (Lambert and the Charlie sheen lobe) drawn as a lit sphere in
    // painter units: pixel = π × its shading.
    let velvet = Analytic::Velvet { diffuse: [0.30, 0.05, 0.12], sheen: [0.30, 0.15, 0.25], roughness: 0.35 };
    let dir = tempfile::tempdir().unwrap();
    // Fitted as the thesis does: by default this one view's fit, whose channels one by one
    // invent colours under moved lights (20% of a sphere's lit pixels), is fitted again with
    // the identity mapping, which keeps no sheen (BENCHMARKS.md, "Colours under every light").
    let picture = lit_sphere(256, |q| velvet.shading(q).map(|x| std::f64::consts::PI * x));
    let (run, glb) = fitted_and_exported(dir.path(), &picture, "velvet", &["--channels", "independent"]);
    let (json, _) = split_glb(&std::fs::read(&glb).unwrap()).unwrap();
    let sheen = &json["materials"][0]["extensions"]["KHR_materials_sheen"];
    let colour: Vec<f64> = sheen["sheenColorFactor"].as_array().map_or(Vec::new(), |a| a.iter().map(|x| x.as_f64().unwrap()).collect());
    // The sheen keeps the velvet's hue: red over blue over green.
    assert!(colour.len() == 3 && colour[0] > colour[2] && colour[2] > colour[1], "sheen {sheen}\n{}", run.stdout);
    assert!(json["extensionsUsed"].as_array().unwrap().iter().any(|e| e == "KHR_materials_sheen"));
    assert!(reported(&run.stdout, "factored material:") <= 0.1, "{}", run.stdout);
    assert_valid(&glb);
}

#[test]
fn export_onto_a_model_file_renders_its_exact_material() {
    let dir = tempfile::tempdir().unwrap();
    let (_, mat) = fitted_sphere(dir.path());
    let glb = dir.path().join("bunny.glb");
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--gltf", glb.to_str().unwrap(), "--model", "bunny"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_valid(&glb);
    // The .glb is both the material and the model of `render`, and draws as the directory does.
    let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
    let g = glb.to_str().unwrap();
    let run = brdfpaint(dir.path(), &["render", g, "--model", g, "--size", "96x96", "--out", a.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let run = brdfpaint(dir.path(), &["render", mat.to_str().unwrap(), "--model", g, "--size", "96x96", "--out", b.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let (a, b) = (image::open(&a).unwrap().into_rgb32f(), image::open(&b).unwrap().into_rgb32f());
    assert_eq!(a.as_raw(), b.as_raw());
    assert!(a.as_raw().iter().any(|&x| x > 0.05), "the render is black");
}

#[test]
fn export_refuses_bad_input_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let missing = brdfpaint(dir.path(), &["export", &format!("{d}/nothing"), "--gltf", &format!("{d}/o.glb")]);
    let (_, mat) = fitted_sphere(dir.path());
    let m = mat.to_str().unwrap();
    let wrong_ext = brdfpaint(dir.path(), &["export", m, "--gltf", &format!("{d}/o.gltf")]);
    let no_dir = brdfpaint(dir.path(), &["export", m, "--gltf", &format!("{d}/no/such/dir/o.glb")]);
    let bad_model = brdfpaint(dir.path(), &["export", m, "--gltf", &format!("{d}/o.glb"), "--model", "nonesuch"]);
    for run in [missing, wrong_ext, no_dir, bad_model] {
        assert_eq!(run.code, 1, "{}", run.stderr);
        assert_eq!(run.stderr.trim().lines().count(), 1, "{}", run.stderr);
        assert!(run.stderr.starts_with("error: ") && !run.stderr.contains("panicked"), "{}", run.stderr);
    }
    assert!(!dir.path().join("o.glb").exists());
}

#[test]
fn a_matcap_of_a_lit_sphere_fit_gives_its_picture_back() {
    let dir = tempfile::tempdir().unwrap();
    let (_, mat) = fitted_sphere(dir.path());
    let exr = dir.path().join("m.exr");
    // No --light: the picture's own light, from the scene beside the material.
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--matcap", exr.to_str().unwrap(), "--size", "256"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("the picture's light"), "{}", run.stdout);
    let got = image::open(&exr).unwrap().into_rgba32f();
    let want = ggx_lit_sphere(256, F0);
    let (mut se, mut sv, mut n) = (0.0f64, 0.0f64, 0);
    for j in 0..256usize {
        for i in 0..256usize {
            // Inside the disk, two pixels in from the silhouette (the fit leaves out one).
            let (x, y) = ((i as f64 + 0.5) / 128.0 - 1.0, 1.0 - (j as f64 + 0.5) / 128.0);
            if (x * x + y * y).sqrt() > 1.0 - 2.0 / 128.0 {
                continue;
            }
            let g = got.get_pixel(i as u32, j as u32);
            let w = want.pixels[j * 256 + i];
            for c in 0..3 {
                se += (g[c] as f64 - w[c] as f64).powi(2);
                sv += (w[c] as f64).powi(2);
            }
            n += 1;
        }
    }
    let matcap = (se / sv).sqrt();
    let fit = Material::load(&mat).unwrap().provenance.errors.unwrap().rms_relative;
    eprintln!("{n} pixels: MatCap against the picture {matcap:.4}, the fit's own {fit:.4}");
    assert!(n > 45_000);
    // Measured 0.0023 against the fit's own 0.0022 on its samples (0.0022 over the pixels
    // three in from the silhouette, about the fit's samples): within the fit's error, give or
    // take the extra ring of rim pixels.
    assert!(matcap <= 1.15 * fit, "MatCap {matcap:.4} vs the fit's {fit:.4}");
    let png = dir.path().join("m.png");
    let run = brdfpaint(dir.path(), &["export", mat.to_str().unwrap(), "--matcap", png.to_str().unwrap(), "--light", "0.5,0.2,1", "--size", "64"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let relit = image::open(&png).unwrap().into_rgba8();
    assert_eq!((relit.width(), relit.height()), (64, 64));
    assert_eq!(relit.get_pixel(0, 0)[3], 0, "off the disk is transparent");
}
