//! The coloring-book workflow as a painter does it: open the sheet's page, paint, leave
//! gaps and the lines, save, fit. A painting made on the opaque page (white gaps, black
//! lines left in) must fit about as well as the same painting with transparent gaps.

use std::path::Path;
use std::process::Command;

use brdfpaint::brdf::{Analytic, Reflectance};
use brdfpaint::images::Painting;
use brdfpaint::material::Material;
use brdfpaint::sample::{Erosion, SceneSampler};
use brdfpaint::scene::Scene;

const SIZE: usize = 160;

fn brdfpaint(args: &[&str], cache: &Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(args)
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .env("BRDFPAINT_CACHE", cache)
        .output()
        .unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The painting's exposure: the material it shows is this times the model.
const EXPOSURE: f64 = 0.8;

/// Relative RMS of the material in `dir` against the painted material (the model times
/// [`EXPOSURE`]) at the usable pixels of the sheet's view.
fn error(dir: &Path, model: &Analytic, scene: &Scene, sampler: &mut SceneSampler) -> f64 {
    let m = Material::load(dir).unwrap();
    let g = sampler.geometry(scene, SIZE, SIZE, Erosion::default()).unwrap();
    let pairs = g.pixels.iter().zip(&g.usable).filter(|(_, &u)| u).map(|(p, _)| {
        let q = p.unwrap().query;
        (m.shading(&q), model.shading(&q).map(|x| EXPOSURE * x))
    });
    brdfpaint::study::relative_rms(pairs)
}

#[test]
fn a_painting_on_the_opaque_page_fits_like_one_with_transparent_gaps() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let sheet = dir.path().join("sheet");
    let (code, stdout, stderr) = brdfpaint(&["sheet", "--model", "bunny", "--preset", "front-left", "--size", "160x160", "--out", s(&sheet)], &cache);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("page.png"), "{stdout}");
    let scene = Scene::load(sheet.join("scene.gltf")).unwrap();
    let mut sampler = SceneSampler::new().unwrap();
    let g = sampler.geometry(&scene, SIZE, SIZE, Erosion::NONE).unwrap();
    let model = Analytic::BlinnPhong { diffuse: [0.5, 0.2, 0.1], specular: [0.3, 0.3, 0.3], exponent: 24.0 };

    // The painting: the true shading (exposed to stay below white) where the object is,
    // with unpainted gaps: two discs.
    let gap = |i: usize, j: usize| {
        let d = |cx: f64, cy: f64| ((i as f64 - cx).powi(2) + (j as f64 - cy).powi(2)).sqrt();
        d(70.0, 60.0) < 14.0 || d(95.0, 110.0) < 10.0
    };
    let mut transparent = Painting::opaque(SIZE, SIZE, vec![[0.0; 3]; SIZE * SIZE]).unwrap();
    for (k, px) in g.pixels.iter().enumerate() {
        let (i, j) = (k % SIZE, k / SIZE);
        match px {
            Some(px) if !gap(i, j) => {
                let v = model.shading(&px.query);
                transparent.pixels[k] = [0, 1, 2].map(|c| (EXPOSURE * v[c] * px.light[c]).min(0.95) as f32);
            }
            _ => transparent.alpha[k] = 0.0,
        }
    }
    // The same painting made on the opaque outline.png: gaps stay the page's white, and the
    // page's black lines are left in, over the paint.
    let page = image::open(sheet.join("outline.png")).unwrap().into_rgb8();
    let mut opaque = Painting::opaque(SIZE, SIZE, vec![[1.0; 3]; SIZE * SIZE]).unwrap();
    for k in 0..SIZE * SIZE {
        let line = page.as_raw()[3 * k] < 128;
        opaque.pixels[k] = if line {
            [0.0; 3]
        } else if transparent.alpha[k] > 0.0 {
            transparent.pixels[k]
        } else {
            [1.0; 3]
        };
    }
    let png = |p: &Painting, name: &str| {
        let path = dir.path().join(name);
        // 8-bit, as painting programs save: exact white and black stay exact.
        let bytes: Vec<u8> = p
            .pixels
            .iter()
            .zip(&p.alpha)
            .flat_map(|(c, &a)| {
                let e = |x: f32| (brdfpaint::images::linear_to_srgb(x) * 255.0).round() as u8;
                [e(c[0]), e(c[1]), e(c[2]), (a * 255.0).round() as u8]
            })
            .collect();
        image::RgbaImage::from_raw(SIZE as u32, SIZE as u32, bytes).unwrap().save(&path).unwrap();
        path
    };
    let (a, b) = (png(&transparent, "transparent.png"), png(&opaque, "on-the-page.png"));
    let fit = |image: &Path, out: &str| {
        let out = dir.path().join(out);
        let (code, stdout, stderr) =
            brdfpaint(&["fit", "--scene", s(&sheet.join("scene.gltf")), "--image", s(image), "--out", s(&out)], &cache);
        assert_eq!(code, 0, "{stderr}");
        (out, stdout)
    };
    let (mat_a, out_a) = fit(&a, "a");
    let (mat_b, out_b) = fit(&b, "b");
    assert!(!out_a.contains("sheet's page"), "{out_a}");
    assert!(out_b.contains("made on the sheet's page"), "{out_b}");
    let (ea, eb) = (error(&mat_a, &model, &scene, &mut sampler), error(&mat_b, &model, &scene, &mut sampler));
    eprintln!("transparent gaps {ea:.6}, on the opaque page {eb:.6}");
    // README and BENCHMARKS.md: relative RMS 0.00020 with transparent gaps, 0.00024 on the
    // opaque page ("nearly as well"). Held at those values within their printed digit plus
    // 2% (the fits are deterministic).
    for (what, e, stated) in [("transparent gaps", ea, 0.00020), ("on the page", eb, 0.00024)] {
        assert!((e - stated).abs() <= 5e-6 + 0.02 * stated, "{what}: {e:.6}, stated {stated}");
    }
}
