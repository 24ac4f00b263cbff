//! `brdfpaint sheet` and `brdfpaint render` given bad input: one line on stderr, exit 1,
//! nothing written.

mod gl_common;
mod render_common;

use std::path::Path;

use brdfpaint::images::Rgb;
use brdfpaint::material::Material;
use brdfpaint::render::mesh::uv_sphere;
use glam::{DVec3, Vec3};
use render_common::{brdfpaint, fitted_material, listing, ok, s, write_scene};

/// Runs a failing command: exit 1, nothing on stdout, one line on stderr starting with
/// `error: ` and containing `needle`, and no change under `watch`.
fn fails(args: &[&str], needle: &str, watch: &Path) {
    let before = listing(watch);
    let (code, stdout, stderr) = brdfpaint(args);
    assert_eq!(code, 1, "{args:?}: {stderr}");
    assert!(stdout.is_empty(), "{args:?}: {stdout}");
    assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains(needle), "{args:?}: expected '{needle}' in {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(listing(watch), before, "{args:?} wrote something");
}

#[test]
fn bad_input_is_one_line_exit_1_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let (mat, _) = fitted_material(root);
    let out_dir = root.join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let r_png = out_dir.join("r.png");
    let sheet_dir = out_dir.join("sheet");
    let good = root.join("good.gltf");
    write_scene(
        &good,
        uv_sphere(Vec3::ZERO, 1.0, 32, 16),
        DVec3::new(0.0, 0.0, 4.0),
        Some(1.0),
        gl_common::sun(DVec3::Z, [1.0; 3]),
    );
    // The good inputs work.
    ok(&["render", s(&mat), "--scene", s(&good), "--size", "32x32", "--out", s(&out_dir.join("ok.png"))]);
    std::fs::remove_file(out_dir.join("ok.png")).unwrap();

    let render = |scene: &Path| {
        vec![
            "render".to_string(),
            s(&mat).into(),
            "--scene".into(),
            s(scene).into(),
            "--size".into(),
            "32x32".into(),
            "--out".into(),
            s(&r_png).into(),
        ]
    };
    let sheet = |scene: &Path| {
        vec![
            "sheet".to_string(),
            "--scene".into(),
            s(scene).into(),
            "--size".into(),
            "32x32".into(),
            "--out".into(),
            s(&sheet_dir).into(),
        ]
    };
    let check_both = |scene: &Path, needle: &str| {
        for args in [render(scene), sheet(scene)] {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            fails(&args, needle, &out_dir);
        }
    };

    // Corrupt and truncated glTF.
    let corrupt = root.join("corrupt.gltf");
    std::fs::write(&corrupt, b"{ this is not json").unwrap();
    check_both(&corrupt, "corrupt.gltf");
    let text = std::fs::read_to_string(&good).unwrap();
    let truncated = root.join("truncated.gltf");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    check_both(&truncated, "truncated.gltf");
    check_both(&root.join("missing.gltf"), "missing.gltf");

    // A scene without a camera, a light, or a mesh.
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let edit = |name: &str, f: &dyn Fn(&mut serde_json::Value)| {
        let mut j = json.clone();
        f(&mut j);
        let p = root.join(name);
        std::fs::write(&p, serde_json::to_string(&j).unwrap()).unwrap();
        p
    };
    let strip_nodes = |j: &mut serde_json::Value, key: &str| {
        for n in j["nodes"].as_array_mut().unwrap() {
            n.as_object_mut().unwrap().remove(key);
        }
    };
    let no_camera = edit("nocamera.gltf", &|j| {
        j.as_object_mut().unwrap().remove("cameras");
        strip_nodes(j, "camera");
    });
    check_both(&no_camera, "no camera");
    let no_light = edit("nolight.gltf", &|j| {
        j.as_object_mut().unwrap().remove("extensions");
        j.as_object_mut().unwrap().remove("extensionsUsed");
        strip_nodes(j, "extensions");
    });
    check_both(&no_light, "no light");
    let no_mesh = edit("nomesh.gltf", &|j| {
        j.as_object_mut().unwrap().remove("meshes");
        strip_nodes(j, "mesh");
    });
    check_both(&no_mesh, "nomesh.gltf");

    // Broken materials: a missing texture, another version, a wrong texture size.
    let copy = |name: &str| {
        let d = root.join(name);
        std::fs::create_dir(&d).unwrap();
        for e in std::fs::read_dir(&mat).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), d.join(e.file_name())).unwrap();
        }
        d
    };
    let bad_material = |m: &Path, needle: &str| {
        fails(&["render", s(m), "--scene", s(&good), "--size", "32x32", "--out", s(&r_png)], needle, &out_dir);
    };
    let missing = copy("missing-texture");
    std::fs::remove_file(missing.join("term0-factor1-half.exr")).unwrap();
    bad_material(&missing, "term0-factor1-half.exr");
    let version = copy("version");
    let j = std::fs::read_to_string(version.join("material.json")).unwrap();
    let (now, next) = (brdfpaint::material::VERSION, brdfpaint::material::VERSION + 1);
    std::fs::write(version.join("material.json"), j.replace(&format!("\"version\": {now}"), &format!("\"version\": {next}"))).unwrap();
    bad_material(&version, &format!("version {next}"));
    let size = copy("size");
    Rgb { width: 5, height: 1, pixels: vec![[1.0; 3]; 5] }.write_exr(&size.join("term0-factor0-light.exr")).unwrap();
    bad_material(&size, "5x1");
    bad_material(&root.join("no-such-material"), "no-such-material");

    // Sizes, presets, outputs.
    for cmd in ["render", "sheet"] {
        let head: Vec<&str> = if cmd == "render" { vec!["render", s(&mat)] } else { vec!["sheet"] };
        let out = if cmd == "render" { s(&r_png) } else { s(&sheet_dir) };
        let check = |extra: &[&str], needle: &str| {
            let args: Vec<&str> = head.iter().chain(extra).chain(&["--out", out]).copied().collect();
            fails(&args, needle, &out_dir);
        };
        check(&["--model", "sphere", "--size", "0x10"], "0x10");
        check(&["--model", "sphere", "--size", "100000x100000"], "100000x100000");
        check(&["--model", "sphere", "--size", "5000x5000"], "5000x5000");
        check(&["--model", "sphere", "--preset", "sunset"], "front-left, front-right");
        check(&["--model", "cow"], "teapot");
        // The camera's aspectRatio is 1; a 2:1 image disagrees.
        check(&["--scene", s(&good), "--size", "64x32"], "aspect");
    }
    // A material that needs uvs on a model without them (the bunny), when only the mesh's
    // own may be used (--uv mesh; the default projects them: tests/cli_render.rs
    // `uv_rule_projects_coordinates_where_a_model_has_none`).
    let uv_mat = root.join("uv-mat");
    let mut m = Material::load(&mat).unwrap();
    m.terms[0].coefficients = Some(brdfpaint::material::Coefficients::grey(2, &[1.0; 4]));
    m.save(&uv_mat).unwrap();
    fails(
        &["render", s(&uv_mat), "--model", "bunny", "--uv", "mesh", "--size", "32x32", "--out", s(&r_png)],
        "texture coordinates",
        &out_dir,
    );
    fails(&["render", s(&mat), "--model", "sphere", "--out", s(&out_dir.join("r.jpg"))], ".png or .exr", &out_dir);
    fails(&["render", s(&mat), "--model", "sphere", "--turntable", "0", "--out", s(&r_png)], "frames", &out_dir);
    // A render into a directory that does not exist.
    fails(
        &["render", s(&mat), "--model", "sphere", "--size", "8x8", "--out", s(&out_dir.join("nowhere/r.png"))],
        "r.png",
        &out_dir,
    );

    // A sheet onto an existing directory that is not a sheet.
    let mine = out_dir.join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), b"keep me").unwrap();
    fails(&["sheet", "--model", "sphere", "--size", "16x16", "--out", s(&mine)], "not a sheet directory", &out_dir);
    assert_eq!(std::fs::read(mine.join("notes.txt")).unwrap(), b"keep me");
    fails(
        &["sheet", "--model", "sphere", "--size", "16x16", "--out", s(&mine.join("notes.txt"))],
        "not a directory",
        &out_dir,
    );

    // Usage errors exit with 2.
    assert_eq!(brdfpaint(&["render", s(&mat), "--out", "x.png"]).0, 2, "no scene");
    assert_eq!(brdfpaint(&["render", s(&mat), "--scene", s(&good), "--model", "sphere", "--out", "x.png"]).0, 2);
    assert_eq!(
        brdfpaint(&[
            "render",
            s(&mat),
            "--model",
            "sphere",
            "--turntable",
            "2",
            "--light-sweep",
            "2",
            "--out",
            "x.png"
        ])
        .0,
        2
    );
    assert_eq!(brdfpaint(&["sheet", "--model", "sphere"]).0, 2, "no --out");
}
