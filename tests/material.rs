//! Materials: CPU evaluation against the fit, save/load round trips, bad files, and the
//! MERL path from measured data to a material.

use brdfpaint::brdf::Reflectance;
use std::path::Path;

use brdfpaint::brdf::{Analytic, Merl, SphereView};
use brdfpaint::factor::{prepare, Mapping, Pattern, Query, Settings};
use brdfpaint::material::{Material, Provenance};
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn fitted(settings: &Settings, model: &Analytic) -> (Material, brdfpaint::factor::Fit) {
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 60).pattern();
    let values = pattern.shade(|q| model.shading(q));
    let fit = prepare(&pattern, settings).unwrap().solve(&values, Mapping::Auto).unwrap();
    let provenance = Provenance { tool: "test".into(), errors: Some(fit.errors), samples: pattern.len(), ..Default::default() };
    (Material::from_fit(settings, &fit, provenance).unwrap(), fit)
}

fn random_queries(n: usize) -> Vec<Query> {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut dir = |lower: bool| {
        let z: f64 = rng.random_range(if lower { -1.0 } else { 0.0 }..1.0);
        let p: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * p.cos(), r * p.sin(), z)
    };
    (0..n).map(|_| Query { l: dir(true), v: dir(false), uv: DVec2::new(0.3, 0.7) }).collect()
}

#[test]
fn material_evaluation_matches_the_fit_to_f32_precision() {
    for settings in [Settings::default(), Settings::uniform(2, 16), Settings::four_factor(1, 32, 8), Settings::with_difference(16), Settings::half_difference(12)] {
        let (material, fit) = fitted(&settings, &Analytic::suite()[1]);
        for q in random_queries(500) {
            let (a, b) = (material.shading(&q), fit.eval(&settings, &q));
            // f32 tables: relative 1e-6 of the product, which for the offset and inverted
            // mappings is of the size of their constant, not of the result.
            let scale = fit.map.constant();
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-6 * (b[c].abs() + scale[c]), "{a:?} vs {b:?}");
            }
        }
    }
}

#[test]
fn save_then_load_gives_back_the_same_material() {
    let dir = tempfile::tempdir().unwrap();
    let settings = [Settings::default(), Settings::uniform(2, 12), Settings::four_factor(1, 16, 8), Settings::with_difference(16), Settings::half_difference(12)];
    for (k, settings) in settings.iter().enumerate() {
        let (material, _) = fitted(settings, &Analytic::suite()[4]);
        let path = dir.path().join(format!("m{k}"));
        material.save(&path).unwrap();
        let loaded = Material::load(&path).unwrap();
        assert!(loaded == material, "{path:?} loads differently");
        // Loading through the json path works too.
        assert!(Material::load(&path.join("material.json")).unwrap() == material);
    }
}

fn edit_json(dir: &Path, f: impl Fn(&mut serde_json::Value)) {
    let p = dir.join("material.json");
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    f(&mut v);
    std::fs::write(&p, serde_json::to_string(&v).unwrap()).unwrap();
}

/// A version 1 material written by the tool before version 2 (tests/data/material-v1:
/// blinn-phong-32 fitted from one view with the default settings) still loads, reads as
/// unwarped tables, evaluates like a fresh fit of the same samples, and is saved again as
/// version 2.
#[test]
fn version_1_materials_still_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/material-v1");
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("material.json")).unwrap()).unwrap();
    assert_eq!(json["version"], 1, "the fixture must stay a version 1 file");
    let old = Material::load(&dir).unwrap();
    assert!(old.terms[0].factors.iter().all(|f| f.spec.warp == 1.0));
    // The fixture came from these very samples and the version 1 default settings (an
    // unwarped half-vector table): the same tables up to f32.
    let (fresh, _) = fitted(&Settings::warped(1.0), &Analytic::suite()[2]);
    for q in random_queries(300) {
        let (a, b) = (old.shading(&q), fresh.shading(&q));
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 1e-5 * (1.0 + b[c].abs()), "{a:?} vs {b:?} at {q:?}");
        }
    }
    let out = tempfile::tempdir().unwrap();
    old.save(out.path()).unwrap();
    let again: serde_json::Value = serde_json::from_slice(&std::fs::read(out.path().join("material.json")).unwrap()).unwrap();
    assert_eq!(again["version"], brdfpaint::material::VERSION);
    assert!(Material::load(out.path()).unwrap().terms == old.terms);
}

/// A warped half-vector table and the half/difference factors survive a save and load, and
/// the warp is written only where it is not 1.
#[test]
fn warped_tables_round_trip() {
    let (material, _) = fitted(&Settings::warped(3.0), &Analytic::suite()[3]);
    let dir = tempfile::tempdir().unwrap();
    material.save(dir.path()).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.path().join("material.json")).unwrap()).unwrap();
    let factors = &json["terms"][0]["factors"];
    assert_eq!(factors[1]["warp"], 3.0);
    assert!(factors[0].get("warp").is_none() && factors[2].get("warp").is_none(), "{factors}");
    assert!(Material::load(dir.path()).unwrap() == material);
}

#[test]
fn bad_material_files_are_one_line_errors() {
    let root = tempfile::tempdir().unwrap();
    let (material, _) = fitted(&Settings::default(), &Analytic::suite()[0]);
    let fresh = |name: &str| {
        let d = root.path().join(name);
        material.save(&d).unwrap();
        d
    };
    let err = |d: &Path| {
        let e = Material::load(d).unwrap_err().to_string();
        assert!(!e.contains('\n'), "{e}");
        e
    };
    let d = fresh("version");
    let next = brdfpaint::material::VERSION + 1;
    edit_json(&d, |v| v["version"] = next.into());
    assert!(err(&d).contains(&format!("version {next}")));
    let d = fresh("format");
    edit_json(&d, |v| v["format"] = "something-else".into());
    assert!(err(&d).contains("not a brdfpaint material"));
    let d = fresh("size");
    edit_json(&d, |v| v["terms"][0]["factors"][1]["res"] = 64.into());
    assert!(err(&d).contains("needs 64x1"));
    let d = fresh("missing");
    std::fs::remove_file(d.join("term0-factor2-view.exr")).unwrap();
    assert!(err(&d).contains("term0-factor2-view.exr"));
    let d = fresh("escape");
    edit_json(&d, |v| v["terms"][0]["factors"][0]["texture"] = "../../etc/passwd".into());
    assert!(err(&d).contains("plain file name"));
    let d = fresh("garbage");
    std::fs::write(d.join("material.json"), b"{ not json").unwrap();
    assert!(err(&d).contains("material.json"));
    let d = fresh("corrupt-texture");
    std::fs::write(d.join("term0-factor0-light.exr"), b"\x76\x2f\x31\x01 truncated").unwrap();
    assert!(err(&d).contains("term0-factor0-light.exr"));
    assert!(err(&root.path().join("nowhere")).contains("nowhere"));
}

#[test]
fn a_failed_save_leaves_the_previous_material_untouched() {
    let root = tempfile::tempdir().unwrap();
    let d = root.path().join("mat");
    let (good, _) = fitted(&Settings::default(), &Analytic::suite()[0]);
    good.save(&d).unwrap();
    let mut bad = good.clone();
    bad.terms[0].factors[0].texels[3] = [f32::NAN; 3];
    assert!(bad.save(&d).is_err());
    assert!(Material::load(&d).unwrap() == good);
    // No temporary directories are left behind.
    let entries: Vec<_> = std::fs::read_dir(root.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(entries.len(), 1, "{entries:?}");
    // A directory that is not a material is never overwritten.
    let other = root.path().join("notes");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("keep.txt"), b"x").unwrap();
    assert!(good.save(&other).is_err());
    assert!(other.join("keep.txt").exists());
}

#[test]
fn measured_data_becomes_a_material_that_matches_it_on_new_directions() {
    // A MERL file tabulated from Blinn-Phong, fitted from its samples, then compared with
    // the model at random (l, v) pairs that are not on the sampling grid.
    let model = Analytic::BlinnPhong { diffuse: [0.4, 0.25, 0.1], specular: [0.2, 0.25, 0.3], exponent: 16.0 };
    let merl = Merl::from_brdf(|l, v| model.brdf(l, v));
    let samples = merl.samples(16).unwrap();
    let (pattern, values) = Pattern::from_samples(&samples).unwrap();
    let settings = Settings::default();
    let fit = prepare(&pattern, &settings).unwrap().solve(&values, Mapping::Auto).unwrap();
    let material = Material::from_fit(&settings, &fit, Provenance::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut num, mut den) = (0.0, 0.0);
    for _ in 0..5000 {
        let mut dir = || {
            let z: f64 = rng.random_range(0.05..1.0);
            let p: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            DVec3::new((1.0 - z * z).sqrt() * p.cos(), (1.0 - z * z).sqrt() * p.sin(), z)
        };
        let q = Query { l: dir(), v: dir(), uv: DVec2::ZERO };
        let (got, want) = (material.shading(&q), model.shading(&q));
        for c in 0..3 {
            num += (got[c] - want[c]).powi(2);
            den += want[c].powi(2);
        }
    }
    let rel = (num / den).sqrt();
    // Blinn-Phong is an exact p(l) q(h) product; what remains is the MERL binning and
    // table interpolation.
    assert!(rel < 0.03, "relative RMS {rel}");
}

/// Version 3 added a term's analytic base (`brdf::lobe`). A version 2 file (the v1
/// fixture's tables under version 2, which is how a v2 file without warps or θ_d factors
/// reads: tests/data/material-v2) loads without a base and shades like the v1 fixture; a
/// based material survives a save and load, base and all, whatever its lobe's family (a
/// version 3 base, without one, is GGX), and a base outside its ranges or of an unknown
/// family is refused on load.
#[test]
fn version_2_loads_and_a_base_round_trips() {
    use brdfpaint::read::lobe::{solve_based, BaseChoice, Blocks};
use brdfpaint::brdf::lobe::{Base, Lobe};
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let v2 = Material::load(&data.join("material-v2")).unwrap();
    let v1 = Material::load(&data.join("material-v1")).unwrap();
    assert!(v2.terms[0].base.is_none() && v2.terms == v1.terms);

    let model = Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.50, 0.42, 0.35], 0.1);
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 60).pattern();
    let values = pattern.shade(|q| model.shading(q));
    let settings = Settings::default();
    let prepared = prepare(&pattern, &settings).unwrap();
    let fit = solve_based(&prepared, &pattern, &values, Mapping::Auto, BaseChoice::Ggx, &Blocks::of_directions(&pattern)).unwrap();
    let material = Material::from_based_fit(&settings, &fit, Provenance::default()).unwrap();
    let base = material.terms[0].base.expect("a base");
    // The material evaluates the based fit exactly (up to the tables' f32).
    for q in random_queries(200) {
        let (a, b) = (material.shading(&q), fit.eval(&settings, &q));
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 1e-5 * (1.0 + b[c].abs()), "{a:?} vs {b:?} at {q:?}");
        }
    }
    let dir = tempfile::tempdir().unwrap();
    material.save(dir.path()).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.path().join("material.json")).unwrap()).unwrap();
    assert_eq!(json["version"], 6);
    assert_eq!(json["terms"][0]["base"]["alpha"], base.alpha);
    assert_eq!(json["terms"][0]["base"]["lobe"], "ggx");
    assert!(Material::load(dir.path()).unwrap() == material);
    // A leaned half vector (version 6) round-trips; a lean on the light factor is refused in
    // one line that names it.
    let mut leaned = material.clone();
    leaned.terms[0].factors[1].spec.lean = 0.5;
    let dir2 = tempfile::tempdir().unwrap();
    leaned.save(dir2.path()).unwrap();
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir2.path().join("material.json")).unwrap()).unwrap();
    assert_eq!(json["terms"][0]["factors"][1]["lean"], 0.5);
    assert!(json["terms"][0]["factors"][0].get("lean").is_none(), "a lean of 1 is absent");
    assert!(Material::load(dir2.path()).unwrap() == leaned);
    edit_json(dir2.path(), |v| v["terms"][0]["factors"][0]["lean"] = serde_json::json!(0.5));
    let e = Material::load(dir2.path()).unwrap_err().to_string();
    assert!(e.contains("lean") && !e.contains('\n'), "{e}");
    // A version 3 file has no lobe: its base is GGX.
    edit_json(dir.path(), |v| {
        v["version"] = serde_json::json!(3);
        v["terms"][0]["base"].as_object_mut().unwrap().remove("lobe");
    });
    assert!(Material::load(dir.path()).unwrap() == material);
    // Another family survives the round trip and shades as its own lobe, not as GGX.
    let mut phong = material.clone();
    phong.terms[0].base = Some(Base { lobe: Lobe::Phong, ..base });
    phong.save(dir.path()).unwrap();
    let again = Material::load(dir.path()).unwrap();
    assert!(again == phong && again.terms[0].base.unwrap().lobe == Lobe::Phong);
    let q = random_queries(200).into_iter().find(|q| (again.shading(q)[0] - material.shading(q)[0]).abs() > 1e-3);
    assert!(q.is_some(), "a Phong base shades differently from a GGX one somewhere");
    edit_json(dir.path(), |v| v["terms"][0]["base"]["lobe"] = serde_json::json!("cook-torrance"));
    let e = Material::load(dir.path()).unwrap_err().to_string();
    assert!(e.contains("material.json"), "{e}");
    edit_json(dir.path(), |v| v["terms"][0]["base"]["lobe"] = serde_json::json!("phong"));
    edit_json(dir.path(), |v| v["terms"][0]["base"]["alpha"] = serde_json::json!(0.0));
    let e = Material::load(dir.path()).unwrap_err().to_string();
    assert!(e.contains("alpha"), "{e}");
}
