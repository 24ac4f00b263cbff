//! Issue 33, data loss: no user file is ever removed, renamed or overwritten by `fit`,
//! `render`, `sheet` or `demo`, whatever a material.json or a hidden file in the folder says;
//! the tool's own earlier outputs are still replaced whole. Each case names the file that a
//! build before the ownership record lost.

use std::path::{Path, PathBuf};

use brdfpaint::brdf::{Analytic, Merl, Reflectance, SphereView};
use brdfpaint::images::Painting;
use brdfpaint::material::Material;
use glam::DVec3;
use rand::{Rng, SeedableRng};

mod cli_common;

use cli_common::{brdfpaint, Run};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn ok(r: Run) -> Run {
    assert_eq!(r.code, 0, "stderr: {}", r.stderr);
    r
}

fn one_line_error(r: &Run, needle: &str) {
    assert_eq!(r.code, 1, "stdout: {} stderr: {}", r.stdout, r.stderr);
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.contains(needle), "{}", r.stderr);
}

/// A Lambertian sphere lit from the upper left on a black square: a lit-sphere picture.
fn lit_sphere_png(dir: &Path) -> PathBuf {
    let (w, res) = (64, 56);
    let mut p = Painting::opaque(w, w, vec![[0.0; 3]; w * w]).unwrap();
    let model = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
    for px in SphereView::new(DVec3::new(-0.5, 0.5, 1.0), res).pixels() {
        p.pixels[(4 + px.pixel[1]) * w + 4 + px.pixel[0]] = model.shading(&px.query).map(|x| x as f32);
    }
    let path = dir.join("sphere.png");
    std::fs::write(&path, p.encode_png16().unwrap()).unwrap();
    path
}

fn merl_file(dir: &Path) -> PathBuf {
    let merl = dir.join("lambert.binary");
    Merl::from_brdf(|_, _| [0.2, 0.3, 0.4]).write(&merl).unwrap();
    merl
}

/// A dead process's id: a child that has exited and been reaped.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// Item 1: a refit keeps the user's scene.gltf (even when it is the `--scene` input, and even
/// where the tool wrote it) and files or folders named like tables.
#[test]
fn a_refit_keeps_the_scene_it_reads_and_files_named_like_tables() {
    let root = tempfile::tempdir().unwrap();
    let (cache, dir) = (root.path().join("cache"), root.path());
    let picture = lit_sphere_png(dir);
    let mat = dir.join("mat");
    ok(brdfpaint(&cache, &["fit", "--lit-sphere", s(&picture), "--out", s(&mat)]));
    let scene = std::fs::read(mat.join("scene.gltf")).unwrap();
    std::fs::create_dir(mat.join("term1-sketches.exr")).unwrap();
    std::fs::write(mat.join("term1-sketches.exr/a.txt"), "sketch").unwrap();
    std::fs::write(mat.join("term0-factor0-light.exr.bak"), "backup").unwrap();
    // The scene the lit-sphere fit wrote is the input of a scene fit into the same folder.
    ok(brdfpaint(&cache, &["fit", "--scene", s(&mat.join("scene.gltf")), "--image", s(&picture), "--out", s(&mat)]));
    assert_eq!(std::fs::read(mat.join("scene.gltf")).unwrap(), scene);
    assert_eq!(std::fs::read_to_string(mat.join("term1-sketches.exr/a.txt")).unwrap(), "sketch");
    assert_eq!(std::fs::read_to_string(mat.join("term0-factor0-light.exr.bak")).unwrap(), "backup");
    Material::load(&mat).unwrap();

    // A scene.gltf the user put in a material folder: a lit-sphere fit, which writes its
    // own scene.gltf there, refuses in one line rather than replace it.
    let theirs = dir.join("theirs");
    ok(brdfpaint(&cache, &["fit", "--merl", s(&merl_file(dir)), "--density", "6", "--out", s(&theirs)]));
    std::fs::write(theirs.join("scene.gltf"), "the user's scene").unwrap();
    let json = std::fs::read(theirs.join("material.json")).unwrap();
    one_line_error(&brdfpaint(&cache, &["fit", "--lit-sphere", s(&picture), "--out", s(&theirs)]), "scene.gltf");
    assert_eq!(std::fs::read_to_string(theirs.join("scene.gltf")).unwrap(), "the user's scene");
    assert_eq!(std::fs::read(theirs.join("material.json")).unwrap(), json);
    assert!(brdfpaint::commit::temporaries(dir).is_empty());
}

/// Item 2: a material.json that names the user's files as textures makes no refit touch
/// them, in a folder the tool wrote (its record) and in one it did not (no record).
#[test]
fn a_crafted_material_json_claims_nothing() {
    let root = tempfile::tempdir().unwrap();
    let (cache, dir) = (root.path().join("cache"), root.path());
    let merl = merl_file(dir);
    let fit = |out: &Path| brdfpaint(&cache, &["fit", "--merl", s(&merl), "--density", "6", "--out", s(out)]);
    let crafted = serde_json::json!({
        "format": "brdfpaint-material", "version": 4, "kind": "uniform",
        "terms": [{"mapping": "identity", "factors": [
            {"input": "light", "dim": 1, "res": 8, "param": "radius", "texture": "notes.txt"},
            {"input": "half", "dim": 1, "res": 8, "param": "radius", "texture": "paintings"},
            {"input": "view", "dim": 1, "res": 8, "param": "radius", "texture": "term0-factor0-light.exr"}
        ], "coefficients": {"res": 4, "texture": "term0-coefficients.exr"}}]
    });
    let recorded = dir.join("recorded");
    ok(fit(&recorded));
    let unrecorded = dir.join("unrecorded");
    std::fs::create_dir(&unrecorded).unwrap();
    for mat in [&recorded, &unrecorded] {
        std::fs::write(mat.join("material.json"), crafted.to_string()).unwrap();
        std::fs::write(mat.join("notes.txt"), "notes").unwrap();
        std::fs::create_dir(mat.join("paintings")).unwrap();
        std::fs::write(mat.join("paintings/p.png"), "art").unwrap();
        assert!(Material::load(mat).is_err());
        ok(fit(mat));
        Material::load(mat).unwrap();
        assert_eq!(std::fs::read_to_string(mat.join("notes.txt")).unwrap(), "notes", "{}", mat.display());
        assert_eq!(std::fs::read_to_string(mat.join("paintings/p.png")).unwrap(), "art", "{}", mat.display());
    }
}

/// Item 3: a journal planted under the tool's temporary names moves, overwrites or deletes
/// nothing of the user's.
#[test]
fn a_planted_journal_touches_no_users_file() {
    let root = tempfile::tempdir().unwrap();
    let (cache, dir) = (root.path().join("cache"), root.path());
    let merl = merl_file(dir);
    let mat = dir.join("mat");
    ok(brdfpaint(&cache, &["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)]));
    let dead = dead_pid();
    for folder in [dir, mat.as_path()] {
        std::fs::write(folder.join("precious.txt"), "precious").unwrap();
        std::fs::write(folder.join("other.txt"), "other").unwrap();
        let journal = "precious.txt\tother.txt\nother.txt\t\n../x\tother.txt\n";
        std::fs::write(folder.join(format!(".brdfpaint-{dead}-0-seq-other.txt")), journal).unwrap();
    }
    ok(brdfpaint(&cache, &["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)]));
    let frames = dir.join("r.png");
    ok(brdfpaint(&cache, &["render", s(&mat), "--model", "sphere", "--size", "16x16", "--turntable", "2", "--out", s(&frames)]));
    for folder in [dir, mat.as_path()] {
        assert_eq!(std::fs::read_to_string(folder.join("precious.txt")).unwrap(), "precious");
        assert_eq!(std::fs::read_to_string(folder.join("other.txt")).unwrap(), "other");
        assert!(brdfpaint::commit::temporaries(folder).is_empty());
    }
}

/// A turntable written over a longer one leaves only its own frames (the tool's earlier
/// frames go), never a frame the user changed or added, and refuses to overwrite one.
#[test]
fn a_shorter_turntable_replaces_the_tools_frames_only() {
    let root = tempfile::tempdir().unwrap();
    let (cache, dir) = (root.path().join("cache"), root.path());
    let mat = dir.join("mat");
    ok(brdfpaint(&cache, &["fit", "--merl", s(&merl_file(dir)), "--density", "6", "--out", s(&mat)]));
    let out = dir.join("frames");
    std::fs::create_dir(&out).unwrap();
    let render = |n: &str| brdfpaint(&cache, &["render", s(&mat), "--model", "sphere", "--size", "16x16", "--turntable", n, "--out", s(&out.join("r.png"))]);
    ok(render("8"));
    std::fs::write(out.join("r-005.png"), "painted over by the user").unwrap();
    std::fs::write(out.join("r-009.png"), "the user's").unwrap();
    ok(render("4"));
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).filter(|n| !n.starts_with('.')).collect();
        v.sort();
        v
    };
    assert_eq!(names(&out), ["r-000.png", "r-001.png", "r-002.png", "r-003.png", "r-005.png", "r-009.png"]);
    assert_eq!(std::fs::read_to_string(out.join("r-005.png")).unwrap(), "painted over by the user");
    // A user's file at a frame's name: refused in one line, nothing changed.
    std::fs::write(out.join("r-001.png"), "the user's own").unwrap();
    let before = std::fs::read(out.join("r-000.png")).unwrap();
    one_line_error(&render("4"), "r-001.png");
    assert_eq!(std::fs::read_to_string(out.join("r-001.png")).unwrap(), "the user's own");
    assert_eq!(std::fs::read(out.join("r-000.png")).unwrap(), before);
    assert!(brdfpaint::commit::temporaries(&out).is_empty());
}

/// What a planted entry is.
#[derive(Clone, Copy, Debug)]
enum Plant {
    File,
    Folder,
    EmptyFolder,
    Link,
}

/// A name like the tool's own: its tables, its bookkeeping, its other outputs, or plain.
fn plant_name(rng: &mut impl Rng) -> String {
    const STEMS: [&str; 10] = ["term0-factor0-light", "term3-factor1-half", "term1-coefficients", "term1-sketches", "report", "scene", ".brdfpaint-notes", ".brdfpaint-owned", "notes", "r-007"];
    const TAILS: [&str; 8] = [".exr", ".png", ".gltf", ".json", ".txt", ".exr.bak", "", ".bak"];
    let name = format!("{}{}", STEMS[rng.random_range(0..STEMS.len())], TAILS[rng.random_range(0..TAILS.len())]);
    if rng.random_bool(0.3) { format!("{name}{}", rng.random_range(0..100)) } else { name }
}

fn plant(path: &Path, kind: Plant, content: &str, outside: &Path) {
    match kind {
        Plant::File => std::fs::write(path, content).unwrap(),
        Plant::Folder => {
            std::fs::create_dir(path).unwrap();
            std::fs::write(path.join("inside.txt"), content).unwrap();
        }
        Plant::EmptyFolder => std::fs::create_dir(path).unwrap(),
        Plant::Link => std::os::unix::fs::symlink(outside, path).unwrap(),
    }
}

fn survives(path: &Path, kind: Plant, content: &str, outside: &Path) -> bool {
    match kind {
        Plant::File => std::fs::read_to_string(path).is_ok_and(|c| c == content),
        Plant::Folder => std::fs::read_to_string(path.join("inside.txt")).is_ok_and(|c| c == content),
        Plant::EmptyFolder => path.is_dir(),
        Plant::Link => std::fs::read_link(path).is_ok_and(|t| t == outside),
    }
}

/// The property: random files, folders and links, named like the tool's own, planted in a
/// material, a sheet and a frames folder, all survive a rerun of the command that made it
/// (which either succeeds, or refuses in one line where a plant sits at a name it writes).
#[test]
fn planted_entries_all_survive() {
    let root = tempfile::tempdir().unwrap();
    let (cache, dir) = (root.path().join("cache"), root.path());
    let merl = merl_file(dir);
    let outside = dir.join("outside.txt");
    std::fs::write(&outside, "outside").unwrap();
    let mat = dir.join("mat");
    let sheet = dir.join("sheet");
    let frames = dir.join("frames");
    std::fs::create_dir(&frames).unwrap();
    // Each folder, the command that writes it, and the names it documents as replaced
    // whatever they hold (README, "File access and outputs"), which are not planted; nor is
    // the ownership record's reserved name.
    let commands: [(&Path, Vec<String>, &[&str]); 3] = [
        (&mat, ["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)].map(String::from).to_vec(), &["material.json", "report.png"]),
        (&sheet, ["sheet", "--model", "sphere", "--size", "24x24", "--out", s(&sheet)].map(String::from).to_vec(), &["outline.png", "reference.png", "mask.png", "scene.gltf", "page.png"]),
        (&frames, ["render", s(&mat), "--model", "sphere", "--size", "12x12", "--turntable", "3", "--out", s(&frames.join("r.png"))].map(String::from).to_vec(), &[]),
    ];
    let run = |args: &[String]| brdfpaint(&cache, &args.iter().map(String::as_str).collect::<Vec<_>>());
    for (_, args, _) in &commands {
        ok(run(args));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(33);
    for round in 0..6 {
        for (folder, args, replaced) in &commands {
            let mut planted = Vec::new();
            for k in 0..6 {
                let name = plant_name(&mut rng);
                let path = folder.join(&name);
                if std::fs::symlink_metadata(&path).is_ok() || replaced.contains(&name.as_str()) || name == ".brdfpaint-owned" {
                    continue;
                }
                let kind = [Plant::File, Plant::Folder, Plant::EmptyFolder, Plant::Link][rng.random_range(0..4)];
                let content = format!("round {round} plant {k}");
                plant(&path, kind, &content, &outside);
                planted.push((path, kind, content));
            }
            let r = run(args);
            assert!(r.code == 0 || (r.code == 1 && r.stderr.lines().count() == 1 && r.stderr.contains("not replacing it")), "{args:?}: {}", r.stderr);
            for (path, kind, content) in &planted {
                assert!(survives(path, *kind, content, &outside), "round {round}: {} ({kind:?}) lost by {args:?}", path.display());
            }
            assert_eq!(std::fs::read_to_string(&outside).unwrap(), "outside");
        }
    }
    Material::load(&mat).unwrap();
}
