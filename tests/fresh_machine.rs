//! A machine without Mesa's EGL or GL driver (issue 14, item 1): every command that renders
//! says in one line which Debian packages to install, with the command. The libraries are
//! hidden in a mount namespace (`unshare --mount --map-root-user`, bind mounts over them),
//! so the check does not depend on what this machine has; where namespaces are not
//! permitted the test says so and checks only the README (the message itself is unit-tested
//! in `gl::context`).

use std::path::{Path, PathBuf};
use std::process::Command;

const INSTALL: &str = "sudo apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri";

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Where the dynamic loader finds `lib`, from `ldconfig -p`.
fn library(lib: &str) -> Option<PathBuf> {
    let out = Command::new("ldconfig").arg("-p").output().ok()?;
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .filter(|l| l.trim_start().starts_with(&format!("{lib} ")) && l.contains("x86-64"))
        .filter_map(|l| l.split("=> ").nth(1))
        .map(|p| PathBuf::from(p.trim()))
        .next()
}

fn namespaces_work() -> bool {
    Command::new("unshare").args(["--mount", "--map-root-user", "true"]).output().is_ok_and(|o| o.status.success())
}

/// Runs brdfpaint with `hide` (a shell command of mounts) done first in a private mount
/// namespace; returns exit code and stderr.
fn run_hidden(hide: &str, args: &[&str]) -> (i32, String) {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let script = format!("{hide} && exec '{}' {}", env!("CARGO_BIN_EXE_brdfpaint"), quoted.join(" "));
    let out = Command::new("unshare")
        .args(["--mount", "--map-root-user", "sh", "-c", &script])
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .output()
        .unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn missing_gl_libraries_name_the_packages_to_install() {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    assert!(readme.contains(INSTALL), "the README's install section gives the same command");
    if !namespaces_work() {
        eprintln!("skipped the hidden-library runs: unshare --mount --map-root-user is not permitted here");
        return;
    }
    let (Some(egl), Some(mesa)) = (library("libEGL.so.1"), library("libEGL_mesa.so.0")) else {
        panic!("this machine has no Mesa EGL to hide (ldconfig -p finds no libEGL.so.1 / libEGL_mesa.so.0)");
    };
    let dri = std::fs::canonicalize(egl.parent().unwrap()).unwrap().join("dri");
    let hides = [
        ("no libEGL (libegl1)", format!("mount --bind /dev/null '{}'", egl.display())),
        ("no Mesa EGL vendor (libegl-mesa0)", format!("mount --bind /dev/null '{}'", mesa.display())),
        ("no Mesa driver (libgl1-mesa-dri)", format!("mount -t tmpfs none '{}'", dri.display())),
    ];
    let dir = tempfile::tempdir().unwrap();
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/bunny/bunny.glb");
    // Inputs made with GL before it is hidden.
    let sheet = dir.path().join("sheet");
    let ok = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(["sheet", "--model", s(&bunny), "--preset", "front", "--size", "64x64", "--out", s(&sheet)])
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .env("BRDFPAINT_CACHE", dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let mat = dir.path().join("mat");
    let merl = dir.path().join("m.binary");
    brdfpaint::brdf::Merl::from_brdf(|_, _| [0.2, 0.3, 0.4]).write(&merl).unwrap();
    let ok = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)])
        .output()
        .unwrap();
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let scene = sheet.join("scene.gltf");
    let painting = sheet.join("reference.png");
    let out = dir.path().join("out.png");
    let commands: Vec<Vec<&str>> = vec![
        vec!["sheet", "--model", s(&bunny), "--preset", "front", "--out", s(&out)],
        vec!["fit", "--scene", s(&scene), "--image", s(&painting), "--out", s(&out)],
        vec!["render", s(&mat), "--model", s(&bunny), "--preset", "front", "--out", s(&out)],
    ];
    for (what, hide) in &hides {
        for args in &commands {
            let (code, stderr) = run_hidden(hide, args);
            assert_eq!(code, 1, "{what}, {args:?}: {stderr}");
            // Mesa may print its own warnings first; ours is the last line, and one line.
            let last = stderr.lines().last().unwrap_or_default();
            assert!(
                last.starts_with("error: OpenGL: cannot create a headless GL context (") && last.ends_with(INSTALL),
                "{what}, {args:?}: {stderr}"
            );
            assert!(!out.exists(), "{what}, {args:?}: nothing is written");
        }
    }
}
