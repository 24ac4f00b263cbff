//! `brdfpaint view` input errors: one line naming the file and the reason, before any window
//! opens (so they hold without a display too).

use std::process::Command;

fn view(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint")).arg("view").args(args).env_remove("DISPLAY").output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn bad_inputs_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing-here");
    let (code, err) = view(&[missing.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("nothing-here") && err.trim().lines().count() == 1, "{err}");

    let (code, err) = view(&["--model", "dodecahedron"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("dodecahedron") && err.contains("bunny"), "{err}");

    let bad_scene = dir.path().join("broken.gltf");
    std::fs::write(&bad_scene, b"{ not json").unwrap();
    let (code, err) = view(&["--scene", bad_scene.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("broken.gltf"), "{err}");

    let (code, err) = view(&["--window", "12x34"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("12x34"), "{err}");
}

#[test]
fn usage_errors_exit_with_2() {
    let (code, err) = view(&["--watch", "p.png"]);
    assert_eq!(code, 2, "--watch needs --scene: {err}");
    let (code, err) = view(&["--screenshot", "out.png"]);
    assert_eq!(code, 2, "--screenshot needs --frames: {err}");
}

#[test]
fn without_a_display_the_error_says_so() {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.starts_with("error: ") && err.contains("window"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
