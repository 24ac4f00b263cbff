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

#[test]
fn a_scene_without_camera_or_light_names_views_own_options() {
    // A model file is not a scene: `view` says how to paint or look at it with its own
    // options (it has no --preset, which `render` and `fit` suggest).
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.gltf");
    // A glTF with a mesh and no camera: the sphere's preset scene written, its camera removed
    // (buffers stay beside it, under the same names).
    let scene = brdfpaint::scene::Scene::from_preset("sphere", "front").unwrap();
    let full = dir.path().join("full.gltf");
    scene.write_gltf(&full).unwrap();
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&full).unwrap()).unwrap();
    json.as_object_mut().unwrap().remove("cameras");
    for node in json["nodes"].as_array_mut().unwrap() {
        node.as_object_mut().unwrap().remove("camera");
    }
    std::fs::write(&model, serde_json::to_vec(&json).unwrap()).unwrap();
    let (code, err) = view(&["--scene", model.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("no camera") && !err.contains("--preset"), "{err}");
    assert!(err.contains("--paint-model") && err.contains("--model"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
