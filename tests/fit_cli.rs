//! `brdfpaint fit --scene S --image P`, run as a user runs it: the material, report.png,
//! errors in provenance and on the terminal, the prepare cache, several views, and every
//! bad input (one line on stderr naming the file, exit 1, nothing written).

use brdfpaint::brdf::Reflectance;
use std::path::{Path, PathBuf};

use brdfpaint::brdf::Analytic;
use brdfpaint::images::{Painting, Rgb};
use brdfpaint::material::Material;
use brdfpaint::sample::{Erosion, SceneSampler};
use brdfpaint::scene::{frame, sphere_mesh, Light, Preset, Scene};
use glam::Vec3;

mod cli_common;

use cli_common::brdfpaint;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A sphere scene file framed for `preset` with a coloured light of `intensity`.
fn write_scene(dir: &Path, name: &str, preset: &Preset, intensity: f32) -> PathBuf {
    let mut scene = frame(vec![sphere_mesh(64, 32)], preset, 1.0);
    if let Light::Directional { direction, .. } = scene.light {
        scene.light = Light::Directional { direction, color: Vec3::new(1.0, 0.9, 0.8), intensity };
    }
    let path = dir.join(name);
    scene.write_gltf(&path).unwrap();
    path
}

/// Paint `model` in the scene file at `size`²: the true shading times the light at every
/// front-facing pixel, black elsewhere. `.png` gives an 8-bit sRGB PNG (what a paint
/// program saves), `.exr` linear float.
fn paint(scene: &Path, model: &Analytic, size: usize, out: &Path) -> Painting {
    paint_with(scene, size, out, |q| model.shading(q))
}

/// Paint the shading `shade` gives at each pixel's query, times the light.
fn paint_with(scene: &Path, size: usize, out: &Path, shade: impl Fn(&brdfpaint::factor::Query) -> [f64; 3]) -> Painting {
    let scene = Scene::load(scene).unwrap();
    let mut sampler = SceneSampler::new().unwrap();
    let g = sampler.geometry(&scene, size, size, Erosion::NONE).unwrap();
    let pixels: Vec<[f32; 3]> = g
        .pixels
        .iter()
        .map(|p| {
            p.map_or([0.0; 3], |p| {
                let v = shade(&p.query);
                [0, 1, 2].map(|c| (v[c] * p.light[c]) as f32)
            })
        })
        .collect();
    let painting = Painting::opaque(size, size, pixels.clone()).unwrap();
    if out.extension().unwrap() == "exr" {
        painting.write(out).unwrap();
    } else {
        Rgb { width: size, height: size, pixels }.write_png(out).unwrap();
    }
    painting
}

fn blinn_phong() -> Analytic {
    Analytic::suite()[2].clone()
}

#[test]
fn fit_writes_the_material_its_report_and_its_errors() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "scene.gltf", &Preset::default(), 1.2);
    let painting = dir.path().join("painting.png");
    paint(&scene, &blinn_phong(), 128, &painting);
    let out = dir.path().join("mat");
    let r = brdfpaint(&dir.path().join("cache"), &["fit", "--scene", s(&scene), "--image", s(&painting), "--out", s(&out)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stderr.is_empty(), "{}", r.stderr);
    assert!(r.stdout.contains("view 1: ") && r.stdout.contains("painting.png") && r.stdout.contains("relative"), "{}", r.stdout);
    assert!(r.stdout.contains("cache miss"), "{}", r.stdout);
    let m = Material::load(&out).unwrap();
    let e = m.provenance.errors.expect("errors in provenance");
    // 8-bit sRGB quantization of a smooth painting: measured 0.004.
    assert!(e.rms_relative < 0.02 && e.rms > 0.0 && e.max >= e.rms, "{e:?}");
    // Disc of radius 0.85 * 64 px, eroded by one: pi 53.4^2 = 8960.
    assert!((m.provenance.samples as f64 - 8960.0).abs() < 200.0, "{}", m.provenance.samples);
    assert_eq!(m.provenance.sources, vec![s(&scene).to_string(), s(&painting).to_string()]);
    let json = std::fs::read_to_string(out.join("material.json")).unwrap();
    assert!(json.contains("\"rms_relative\""), "{json}");
    // The report: painting | fit | residual with 4 px gaps inside a 4 px margin, and words at
    // scale 1 (labels 13 px high) with 4 px gaps: the panels' names, the view's title, and a
    // legend of two lines below: 4 + 13 + 4 + 13 + 4 + 128 + 4 + 4 + 30 + 4.
    let report = image::open(out.join("report.png")).unwrap();
    assert_eq!((report.width(), report.height()), (4 + 3 * 128 + 8 + 4, 128 + 80));
}

#[test]
fn a_repainted_scene_hits_the_prepare_cache() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let scene = write_scene(dir.path(), "scene.gltf", &Preset::default(), 1.0);
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    paint(&scene, &Analytic::suite()[0], 96, &a);
    paint(&scene, &Analytic::suite()[8], 96, &b);
    let out = dir.path().join("mat");
    let first = brdfpaint(&cache, &["fit", "--scene", s(&scene), "--image", s(&a), "--out", s(&out)]);
    assert_eq!(first.code, 0, "{}", first.stderr);
    assert!(first.stdout.contains("cache miss"), "{}", first.stdout);
    assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 1);
    let second = brdfpaint(&cache, &["fit", "--scene", s(&scene), "--image", s(&b), "--out", s(&out)]);
    assert_eq!(second.code, 0, "{}", second.stderr);
    assert!(second.stdout.contains("cache hit"), "{}", second.stdout);
    assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 1);
    // The material was replaced by the second painting's.
    assert_eq!(Material::load(&out).unwrap().provenance.sources[1], s(&b));
}

#[test]
fn several_views_concatenate() {
    let dir = tempfile::tempdir().unwrap();
    let other = Preset { light_in_view: [0.8, 0.3, 0.5], view_azimuth_deg: 40.0, ..Preset::default() };
    let (s1, s2) = (write_scene(dir.path(), "one.gltf", &Preset::default(), 1.0), write_scene(dir.path(), "two.gltf", &other, 0.8));
    let (p1, p2) = (dir.path().join("one.exr"), dir.path().join("two.png"));
    let model = Analytic::suite()[7].clone(); // Ward
    paint(&s1, &model, 96, &p1);
    paint(&s2, &model, 96, &p2);
    let out = dir.path().join("mat");
    let args = ["fit", "--scene", s(&s1), "--image", s(&p1), "--scene", s(&s2), "--image", s(&p2), "--out", s(&out)];
    let r = brdfpaint(&dir.path().join("cache"), &args);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stdout.contains("view 2: ") && r.stdout.contains("two.png"), "{}", r.stdout);
    let m = Material::load(&out).unwrap();
    assert_eq!(m.provenance.sources.len(), 4);
    let report = image::open(out.join("report.png")).unwrap();
    // Each further view adds its title and a gap (13 + 4 + 4); the legend's first line (340
    // px at scale 1) is wider than three 96 px panels.
    assert_eq!((report.width(), report.height()), (4 + 340 + 4, 2 * 96 + 80 + 21));
}

/// `--theta-d` adds a factor of θ_d after p(l) q(h) r(v) (whose q(h) is warped), and the
/// material stores it: from a front-lit and a side-lit painting of GGX, whose Fresnel term
/// depends on θ_d, the fit with it is at least as close to the paintings as without. Unasked
/// (`auto`), the two paintings' θ_d (about 10° and 50°) get it, with a note saying why, and
/// the front-lit painting alone (one θ_d) does not; its note says instead that it cannot
/// show the lobe's Fresnel.
#[test]
fn theta_d_adds_a_difference_factor() {
    let dir = tempfile::tempdir().unwrap();
    let side = Preset { light_in_view: [1.0, 0.2, -0.15], ..Preset::default() };
    let (s1, s2) = (write_scene(dir.path(), "front.gltf", &Preset::default(), 1.0), write_scene(dir.path(), "side.gltf", &side, 1.0));
    let (p1, p2) = (dir.path().join("front.exr"), dir.path().join("side.exr"));
    let model = Analytic::Ggx { diffuse: [0.3, 0.2, 0.1], f0: [0.04; 3], roughness: 0.5 };
    paint(&s1, &model, 96, &p1);
    paint(&s2, &model, 96, &p2);
    let fit = |out: &Path, extra: &[&str]| {
        let mut args = vec!["fit", "--scene", s(&s1), "--image", s(&p1), "--scene", s(&s2), "--image", s(&p2), "--out", s(out)];
        args.extend_from_slice(extra);
        let r = brdfpaint(&dir.path().join("cache"), &args);
        assert_eq!(r.code, 0, "{}", r.stderr);
        Material::load(out).unwrap()
    };
    let with = fit(&dir.path().join("with"), &["--theta-d"]);
    let without = fit(&dir.path().join("without"), &["--theta-d", "off"]);
    let inputs = |m: &Material| m.terms[0].factors.iter().map(|f| f.spec.input.name().to_string()).collect::<Vec<_>>();
    assert_eq!(inputs(&with), ["light", "half", "view", "difference"]);
    assert_eq!(inputs(&without), ["light", "half", "view"]);
    let auto = fit(&dir.path().join("auto"), &[]);
    assert_eq!(inputs(&auto), ["light", "half", "view", "difference"]);
    assert!(auto.provenance.notes.iter().any(|n| n.contains("s(θ_d) was added")), "{:?}", auto.provenance.notes);
    let out = dir.path().join("front-only");
    let r = brdfpaint(&dir.path().join("cache"), &["fit", "--scene", s(&s1), "--image", s(&p1), "--out", s(&out)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let front = Material::load(&out).unwrap();
    assert_eq!(inputs(&front), ["light", "half", "view"]);
    assert!(!front.provenance.notes.iter().any(|n| n.contains("θ_d")), "{:?}", front.provenance.notes);
    // The front-lit painting's GGX lobe has no Fresnel it could see, and the note says so;
    // the side-lit painting shows it.
    let fresnel = |m: &Material| m.provenance.notes.iter().any(|n| n.contains("too close to see Fresnel"));
    assert_eq!(front.terms[0].base.map(|b| b.lobe), Some(brdfpaint::brdf::lobe::Lobe::Ggx), "{:?}", front.terms[0].base);
    assert!(fresnel(&front), "{:?}", front.provenance.notes);
    assert!(!fresnel(&auto), "{:?}", auto.provenance.notes);
    assert_eq!(with.terms[0].factors[1].spec.warp, brdfpaint::factor::defaults::WARP_HALF);
    let (a, b) = (with.provenance.errors.unwrap().rms_relative, without.provenance.errors.unwrap().rms_relative);
    assert!(a <= b * 1.01, "with theta_d {a}, without {b}");
}

/// Every bad input: exit 1, one line on stderr that names the file, nothing written.
#[test]
fn bad_input_is_one_line_naming_the_file_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = write_scene(d, "scene.gltf", &Preset::default(), 1.0);
    let good = dir.path().join("good.exr");
    let painting = paint(&scene, &blinn_phong(), 64, &good);

    let with = |name: &str, f: &dyn Fn(&mut Painting)| -> PathBuf {
        let mut p = painting.clone();
        f(&mut p);
        let path = d.join(name);
        p.write(&path).unwrap();
        path
    };
    let transparent = with("transparent.png", &|p| p.alpha.fill(0.0));
    let corner = with("corner.png", &|p| {
        for (k, a) in p.alpha.iter_mut().enumerate() {
            *a = if k % 64 < 5 && k / 64 < 5 { 1.0 } else { 0.0 };
        }
    });
    let black = with("black.png", &|p| p.pixels.fill([0.0; 3]));
    let white = with("white.png", &|p| p.pixels.fill([1.0; 3]));
    let wide = d.join("wide.png");
    Rgb::new(80, 60).unwrap().write_png(&wide).unwrap();
    // NaN in an EXR: write the raw float through the encoder.
    let nan = with("nan.exr", &|p| p.pixels[64 * 32 + 32][1] = f32::NAN);
    let truncated = d.join("truncated.png");
    let bytes = std::fs::read(&black).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let corrupt = d.join("corrupt.png");
    std::fs::write(&corrupt, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let teapot = d.join("teapot.gltf");
    Scene::from_preset("teapot", "front-left").unwrap().write_gltf(&teapot).unwrap();
    let broken_scene = d.join("broken.gltf");
    std::fs::write(&broken_scene, b"{ \"asset\": ").unwrap();

    let (missing_scene, missing_png) = (d.join("missing.gltf"), d.join("missing.png"));
    let out = d.join("mat");
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (vec!["--scene", s(&scene), "--image", s(&wide)], "wide.png is 80x60 but the scene camera's aspect is 1.0", "wide.png"),
        (vec!["--scene", s(&scene), "--image", s(&transparent)], "transparent", "transparent.png"),
        (vec!["--scene", s(&scene), "--image", s(&corner)], "misses the object", "corner.png"),
        (vec!["--scene", s(&scene), "--image", s(&black)], "black", "black.png"),
        (vec!["--scene", s(&scene), "--image", s(&white)], "saturated", "white.png"),
        (vec!["--scene", s(&scene), "--image", s(&nan)], "NaN", "nan.exr"),
        (vec!["--scene", s(&scene), "--image", s(&truncated)], "truncated", "truncated.png"),
        (vec!["--scene", s(&scene), "--image", s(&corrupt)], "corrupt", "corrupt.png"),
        (vec!["--scene", s(&scene), "--image", s(&good), "--scene", s(&teapot), "--image", s(&good)], "another model", "teapot.gltf"),
        (vec!["--scene", s(&broken_scene), "--image", s(&good)], "broken.gltf", "broken.gltf"),
        (vec!["--scene", s(&missing_scene), "--image", s(&good)], "missing.gltf", "missing.gltf"),
        (vec!["--scene", s(&scene), "--image", s(&missing_png)], "missing.png", "missing.png"),
        (vec!["--scene", s(&scene), "--image", s(&good), "--uv-res", "64"], "applies to the four-factor", "four-factor"),
        (vec!["--scene", s(&scene), "--image", s(&good), "--res", "0"], "resolution", "resolution"),
        // Limits: terms the renderer draws, coefficient texture and uv table sizes.
        (vec!["--scene", s(&scene), "--image", s(&good), "--kind", "material-map", "--terms", "9"], "outside 1..=8", "--terms"),
        (vec!["--scene", s(&scene), "--image", s(&good), "--kind", "material-map", "--uv-res", "5000"], "outside 2..=4096", "coefficient texture"),
        (vec!["--scene", s(&scene), "--image", s(&good), "--kind", "four-factor", "--uv-res", "5000"], "outside 2..=1024", "uv"),
        (vec!["--scene", s(&teapot), "--image", s(&good), "--kind", "material-map"], "no texture coordinates", "teapot.gltf"),
    ];
    for (args, reason, file) in cases {
        let mut all = vec!["fit"];
        all.extend(&args);
        all.extend(["--out", s(&out)]);
        let r = brdfpaint(&d.join("cache"), &all);
        assert_eq!(r.code, 1, "{args:?}: {}{}", r.stdout, r.stderr);
        assert_eq!(r.stderr.lines().count(), 1, "{args:?}: {}", r.stderr);
        assert!(r.stderr.starts_with("error: ") && r.stderr.contains(reason) && r.stderr.contains(file), "{args:?}: {}", r.stderr);
        assert!(r.stdout.is_empty(), "{args:?}: {}", r.stdout);
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    // Usage errors exit with 2.
    for args in [
        vec!["fit", "--scene", s(&scene), "--out", "m"],
        vec!["fit", "--image", s(&good), "--out", "m"],
        vec!["fit", "--scene", s(&scene), "--image", s(&good), "--scene", s(&scene), "--out", "m"],
        vec!["fit", "--scene", s(&scene), "--image", s(&good), "--merl", "x.binary", "--out", "m"],
        vec!["fit", "--out", "m"],
        // Lit-sphere flags on a scene painting.
        vec!["fit", "--scene", s(&scene), "--image", s(&good), "--texture", "keep", "--out", "m"],
        vec!["fit", "--scene", s(&scene), "--image", s(&good), "--style", "stylized", "--out", "m"],
        vec!["fit", "--scene", s(&scene), "--image", s(&good), "--disk", "10,10,5", "--out", "m"],
    ] {
        let r = brdfpaint(&d.join("cache"), &args);
        assert_eq!(r.code, 2, "{args:?}: {}", r.stderr);
    }
    // The good painting does fit.
    let r = brdfpaint(&d.join("cache"), &["fit", "--scene", s(&scene), "--image", s(&good), "--out", s(&out)]);
    assert_eq!(r.code, 0, "{}", r.stderr);
}

/// A painting whose albedo varies over the surface: `model` times a brightness that steps
/// between 1 and 0.4 in bands of u (a known albedo texture), at EXR precision.
fn paint_banded(scene: &Path, model: &Analytic, size: usize, out: &Path) {
    paint_with(scene, size, out, |q| {
        let albedo = if (q.uv.x * 6.0).floor() as i64 % 2 == 0 { 1.0 } else { 0.4 };
        model.shading(q).map(|v| albedo * v)
    });
}

#[test]
fn spatially_varying_kinds_fit_a_banded_painting_better_than_uniform() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = write_scene(d, "scene.gltf", &Preset::default(), 1.0);
    let painting = d.join("banded.exr");
    paint_banded(&scene, &Analytic::suite()[0], 128, &painting);
    let fit = |kind: &str, extra: &[&str]| {
        let out = d.join(kind);
        let mut args = vec!["fit", "--scene", s(&scene), "--image", s(&painting), "--out", s(&out), "--kind", kind];
        args.extend(extra);
        let r = brdfpaint(&d.join("cache"), &args);
        assert_eq!(r.code, 0, "{kind}: {}", r.stderr);
        Material::load(&out).unwrap()
    };
    let uniform = fit("uniform", &[]);
    let four = fit("four-factor", &["--uv-res", "48"]);
    let map = fit("material-map", &["--terms", "3", "--uv-res", "128"]);
    let hybrid = fit("hybrid", &["--terms", "2", "--uv-res", "32"]);
    let rel = |m: &Material| m.provenance.errors.unwrap().rms_relative;
    assert_eq!(four.kind, brdfpaint::material::Kind::FourFactor);
    assert_eq!(map.kind, brdfpaint::material::Kind::MaterialMap);
    assert_eq!(hybrid.kind, brdfpaint::material::Kind::Hybrid);
    assert!(rel(&hybrid) < 0.5 * rel(&uniform), "hybrid {} vs uniform {}", rel(&hybrid), rel(&uniform));
    assert!(map.terms.len() >= 2 && map.terms.len() <= 3, "{}", map.terms.len());
    // A Lambertian sphere whose albedo steps between 1 and 0.4: one uniform product cannot
    // follow the bands (training relative RMS measured 0.25); s(u, v) does (0.07), and so
    // do three material-map terms (0.05) and two hybrid terms (0.05).
    assert!(rel(&uniform) > 0.2, "uniform {}", rel(&uniform));
    assert!(rel(&four) < 0.5 * rel(&uniform), "four-factor {} vs uniform {}", rel(&four), rel(&uniform));
    assert!(rel(&map) < 0.5 * rel(&uniform), "material map {} vs uniform {}", rel(&map), rel(&uniform));
}

/// Stray strokes (a black bar across the lit side, a white one down the shadow, both over
/// the outline) are repainted by default, said
/// on stdout and in material.json, and the material is closer to the truth on held-out
/// lights and views than with `--keep-strokes`.
#[test]
fn stray_strokes_are_repainted_unless_kept() {
    use brdfpaint::study::fidelity::{held_out_presets, StudyView};
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "scene.gltf", &Preset::default(), 1.2);
    let painting = dir.path().join("strays.png");
    let model = blinn_phong();
    let clean = paint(&scene, &model, 128, &painting);
    let mut pixels = clean.pixels.clone();
    for (k, px) in pixels.iter_mut().enumerate() {
        let (i, j) = (k % 128, k / 128);
        if (84..90).contains(&j) && (5..70).contains(&i) {
            *px = [0.0; 3];
        }
        if (92..97).contains(&i) && (50..125).contains(&j) {
            *px = [0.95; 3];
        }
    }
    let clean_path = dir.path().join("clean.png");
    Rgb { width: 128, height: 128, pixels: clean.pixels.clone() }.write_png(&clean_path).unwrap();
    Rgb { width: 128, height: 128, pixels }.write_png(&painting).unwrap();
    let cache = dir.path().join("cache");
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, 64).unwrap()).collect();
    let mut errors = Vec::new();
    let fitted = |image: &Path, out: &Path, more: &[&str]| {
        let mut args = vec!["fit", "--scene", s(&scene), "--image", s(image), "--out", s(out)];
        args.extend_from_slice(more);
        brdfpaint(&cache, &args)
    };
    let out = dir.path().join("clean");
    assert_eq!(fitted(&clean_path, &out, &[]).code, 0);
    let truth = brdfpaint::study::held_out_error(&Material::load(&out).unwrap(), &model, &held, None).unwrap();
    for keep in [false, true] {
        let out = dir.path().join(if keep { "kept" } else { "read" });
        let mut args = vec!["fit", "--scene", s(&scene), "--image", s(&painting), "--out", s(&out)];
        if keep {
            args.push("--keep-strokes");
        }
        let r = brdfpaint(&cache, &args);
        assert_eq!(r.code, 0, "{}", r.stderr);
        let m = Material::load(&out).unwrap();
        let said = m.provenance.notes.iter().any(|n| n.contains("stray strokes"));
        assert_eq!(r.stdout.contains("stray strokes"), !keep, "{}", r.stdout);
        assert_eq!(said, !keep, "{:?}", m.provenance.notes);
        errors.push(brdfpaint::study::held_out_error(&m, &model, &held, None).unwrap());
    }
    eprintln!("held-out relative RMS: clean {truth:.4}, repainted {:.4}, kept {:.4}", errors[0], errors[1]);
    // Measured: clean 0.0019, repainted 0.0065, kept 0.38 (rings over the whole sphere).
    assert!(errors[0] < 0.02 && errors[0] < 0.1 * errors[1], "{errors:?}");
}

/// `fit --base` (issue 15): 8-bit PNG paintings of a GGX sphere (front light and side light,
/// dim enough that the highlight does not clip) get the analytic base under `auto`, the
/// default, and `fit` says so (the lobe's misfit is measured 0.013 here, quantization
/// included, under `AUTO_MISFIT` = 0.015); `--base none` gives the plain product; a
/// painting of no lobe family gets none under `auto`. Judged
/// under a rim light no painting shows (the wide suite's rim view), the based material is
/// much closer to the truth: measured relative RMS 0.167 against 0.652 for the plain
/// product (bounds with margin on both sides). A Blinn-Phong painting gets a Blinn-Phong
/// lobe of its exponent, a velvet painting none.
#[test]
fn base_auto_keeps_the_lobe_of_the_paintings_family_only() {
    use brdfpaint::brdf::lobe::Lobe;
    use brdfpaint::study::{sphere_rms, suite::held_out};
    let dir = tempfile::tempdir().unwrap();
    let side = Preset { light_in_view: [1.0, 0.2, -0.15], ..Preset::default() };
    let (s1, s2) = (write_scene(dir.path(), "front.gltf", &Preset::default(), 0.3), write_scene(dir.path(), "side.gltf", &side, 0.3));
    let fit = |model: &Analytic, out: &str, extra: &[&str]| {
        let (p1, p2) = (dir.path().join(format!("{out}-front.png")), dir.path().join(format!("{out}-side.png")));
        paint(&s1, model, 96, &p1);
        paint(&s2, model, 96, &p2);
        let out = dir.path().join(out);
        let mut args = vec!["fit", "--scene", s(&s1), "--image", s(&p1), "--scene", s(&s2), "--image", s(&p2), "--out", s(&out)];
        args.extend_from_slice(extra);
        let r = brdfpaint(&dir.path().join("cache"), &args);
        assert_eq!(r.code, 0, "{}", r.stderr);
        (Material::load(&out).unwrap(), r.stdout)
    };
    let ggx = Analytic::Ggx { diffuse: [0.3, 0.2, 0.1], f0: [0.5, 0.4, 0.3], roughness: 0.4 };
    let (based, said) = fit(&ggx, "based", &[]);
    let (plain, _) = fit(&ggx, "plain", &["--base", "none"]);
    let base = based.terms[0].base.expect("auto keeps the lobe for a GGX painting");
    assert!(said.contains("base ggx: alpha"), "{said}");
    assert!((base.alpha - 0.16).abs() < 0.01, "alpha {} for roughness 0.4", base.alpha);
    assert!(plain.terms[0].base.is_none());
    // The truth: `fit` divides a painting by the scene's light, so a material is S itself.
    let truth = |q: &brdfpaint::factor::Query| ggx.shading(q);
    let rim = held_out(64).into_iter().find(|(n, _)| *n == "rim").unwrap().1;
    let (e_based, e_plain) = (sphere_rms(&[rim], truth, |q| based.shading(q)), sphere_rms(&[rim], truth, |q| plain.shading(q)));
    eprintln!("rim view: based {e_based:.4}, plain {e_plain:.4}");
    assert!(e_based < 0.3 && e_plain > 0.5, "rim view: based {e_based:.4}, plain {e_plain:.4}");
    // A Blinn-Phong painting gets a lobe of its own family, of its exponent.
    let (bp, said) = fit(&blinn_phong(), "blinn-phong", &[]);
    let base = bp.terms[0].base.expect("auto keeps a Blinn-Phong lobe for a Blinn-Phong painting");
    assert!(base.lobe == Lobe::BlinnPhong && (Lobe::exponent(base.alpha) / 32.0 - 1.0).abs() < 0.05, "{base:?}");
    assert!(said.contains("base blinn-phong: exponent 3"), "{said}");
    // A velvet painting (a sheen lobe), which no lobe family explains, gets none.
    let velvet = Analytic::Velvet { diffuse: [0.30, 0.05, 0.12], sheen: [0.60, 0.35, 0.50], roughness: 0.35 };
    let (v, _) = fit(&velvet, "velvet", &[]);
    assert!(v.terms[0].base.is_none(), "{:?}", v.terms[0].base);
}
