//! The command line, run as a user runs it: exit codes, one-line errors, outputs.

use brdfpaint::brdf::Reflectance;
use std::process::Command;

use brdfpaint::brdf::{Analytic, Merl};
use brdfpaint::factor::Query;
use brdfpaint::material::Material;
use glam::{DVec2, DVec3};

fn brdfpaint(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint")).args(args).output().expect("run brdfpaint");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

#[test]
fn fit_merl_writes_a_material_that_reproduces_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let model = Analytic::Ggx { diffuse: [0.3, 0.2, 0.1], f0: [0.4, 0.4, 0.4], roughness: 0.5 };
    let merl_path = dir.path().join("ggx.binary");
    Merl::from_brdf(|l, v| model.brdf(l, v)).write(&merl_path).unwrap();
    let out = dir.path().join("mat");
    let (code, stdout, stderr) = brdfpaint(&["fit", "--merl", merl_path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("8192 samples"), "{stdout}");
    let m = Material::load(&out).unwrap();
    assert_eq!(m.provenance.samples, 8192);
    // Compare with the model at directions off the sampling grid.
    let dir_at = |t: f64, p: f64| DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..40 {
        for j in 0..40 {
            let q = Query { l: dir_at(0.03 + i as f64 * 0.035, 0.3), v: dir_at(0.02 + j as f64 * 0.035, 2.0 + i as f64 * 0.01), uv: DVec2::ZERO };
            let (got, want) = (m.shading(&q), model.shading(&q));
            for c in 0..3 {
                num += (got[c] - want[c]).powi(2);
                den += want[c].powi(2);
            }
        }
    }
    let rel = (num / den).sqrt();
    assert!(rel < 0.1, "relative RMS {rel}");
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("short.binary");
    std::fs::write(&bad, vec![0u8; 4096]).unwrap();
    let out = dir.path().join("mat");
    let (code, stdout, stderr) = brdfpaint(&["fit", "--merl", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(stdout.is_empty());
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains("short.binary") && stderr.contains("truncated"), "{stderr}");
    assert!(!out.exists());
    for args in [
        vec!["fit", "--merl", "x.binary", "--out", "m", "--res", "0"],
        vec!["fit", "--merl", "x.binary", "--out", "m", "--res", "100000000"],
        vec!["fit", "--merl", "x.binary", "--out", "m", "--lambda", "nan"],
    ] {
        let (code, _, stderr) = brdfpaint(&args);
        assert_eq!(code, 1, "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
    }
    // Usage errors exit with 2.
    assert_eq!(brdfpaint(&["fit"]).0, 2);
    assert_eq!(brdfpaint(&["fit", "--merl", "x", "--out", "m", "--mapping", "cubic"]).0, 2);
    assert_eq!(brdfpaint(&["nonsense"]).0, 2);
    let (code, stdout, _) = brdfpaint(&["--help"]);
    assert_eq!(code, 0);
    assert!(stdout.contains("bench") && stdout.contains("fit"));
}

#[test]
fn bench_json_has_the_documented_fields() {
    let (code, stdout, stderr) = brdfpaint(&["bench", "--json", "--quick"]);
    assert_eq!(code, 0, "{stderr}");
    let cases: Vec<serde_json::Value> = serde_json::from_str(&stdout).expect("one JSON array");
    // Table 5.1: 4 resolutions x (3-factor, 4-factor); Table 5.2: 2 x 3 sample counts + 4;
    // the 256² four-factor product at two sample counts; Table 5.3: 4 term counts x 2
    // resolutions x 2 fits; Table 5.4: 5 term counts x 2 fits + the four-factor product; GL:
    // factored (1D, 2D) against GGX at 512² and 1024²; environments: preparation of the two
    // bundled ones and 3 frame cases; the live-paint stroke -> frame case; read + fit of a
    // 512² painting, as rendered and in flat tones; the live full fit after a pause, and a
    // stroke while it runs; the stroke with coupled channels.
    assert_eq!(cases.len(), 62);
    let name = |c: &&serde_json::Value| c["case"].as_str().unwrap().to_string();
    let (maps, rest): (Vec<_>, Vec<_>) = cases.iter().partition(|c| name(c).starts_with("table5.3"));
    let (fidelity, rest): (Vec<_>, Vec<_>) = rest.into_iter().partition(|c| name(c).starts_with("table5.4"));
    let (factor, rest): (Vec<_>, Vec<_>) = rest.into_iter().partition(|c| name(c).starts_with("table") || name(c).contains("uv=256"));
    let (live, rest): (Vec<_>, Vec<_>) = rest.into_iter().partition(|c| name(c).starts_with("live paint"));
    let (read_fit, rest): (Vec<_>, Vec<_>) = rest.into_iter().partition(|c| name(c).starts_with("read + fit"));
    assert_eq!(read_fit.len(), 2);
    for c in &read_fit {
        assert!(c["time_s"].as_f64().unwrap() > 0.0 && c["samples"].as_u64().unwrap() > 100_000, "{c}");
    }
    let (env, gl): (Vec<_>, Vec<_>) = rest.into_iter().partition(|c| name(c).starts_with("env prepare") || name(c).starts_with("gl env"));
    assert_eq!(env.len(), 5);
    for c in &env {
        // Preparation cases carry prepare_s; frame cases time_s and the ratio to the point light.
        let prepared = c["prepare_s"].as_f64().is_some_and(|t| t > 0.0);
        let framed = c["time_s"].as_f64().is_some_and(|t| t > 0.0) && c["ratio"].as_f64().is_some_and(|r| r > 1.0);
        assert!(prepared || framed, "{c}");
    }
    assert_eq!(gl.len(), 4);
    // The stroke, the stroke while the full fit runs, the stroke with coupled channels,
    // the full fit after the pause.
    assert_eq!(live.len(), 4);
    assert_eq!(factor.len(), 20);
    for c in &live {
        assert!(c["time_s"].as_f64().unwrap() > 0.0 && c["samples"].as_u64().unwrap() > 10_000, "{c}");
    }
    assert_eq!(maps.len(), 16);
    for c in &maps {
        assert!(c["terms"].as_u64().unwrap() >= 5 && c["time_s"].as_f64().unwrap() > 0.0, "{c}");
    }
    assert_eq!(fidelity.len(), 11);
    for c in &fidelity {
        for field in ["rms", "max", "held_out"] {
            assert!(c[field].as_f64().is_some_and(|x| x > 0.0 && x.is_finite()), "{field} in {c}");
        }
    }
    // The four-factor 256² case carries what the issue asks for.
    let big = cases.iter().find(|c| c["case"].as_str().unwrap().contains("uv=256")).expect("the 256² case");
    assert_eq!(big["unknowns"], 3 * 128 + 256 * 256);
    for c in &gl {
        assert!(c["time_s"].as_f64().unwrap() > 0.0 && c["ratio"].as_f64().unwrap() > 0.0, "{c}");
    }
    for c in &factor {
        for field in ["case", "samples", "res", "unknowns", "prepare_s", "solve_s"] {
            assert!(c.get(field).is_some(), "{field} missing in {c}");
        }
        assert!(c["solve_s"].as_f64().unwrap() > 0.0 && c["prepare_s"].as_f64().unwrap() > 0.0);
    }
    let t51 = cases.iter().find(|c| c["case"] == "table5.1 3x1D M=128").expect("the M=128 case");
    assert_eq!(t51["unknowns"], 384);
    assert_eq!(t51["thesis_s"], 0.4375);
}
