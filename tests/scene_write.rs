//! Writing scene.gltf: what is written loads back as the same scene, the file is valid,
//! self-contained glTF, and writing is atomic.

use brdfpaint::scene::{self, Camera, CpuMesh, Light, Projection, Scene};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

/// Equal element by element; the message shows the first difference only.
fn same<T: PartialEq + std::fmt::Debug>(a: &[T], b: &[T], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    if let Some(i) = (0..a.len()).find(|&i| a[i] != b[i]) {
        panic!("{what}: element {i} is {:?}, read back {:?}", a[i], b[i]);
    }
}

fn assert_same_scene(a: &Scene, b: &Scene, what: &str) {
    assert_eq!(a.meshes.len(), b.meshes.len(), "{what}");
    for (k, (ma, mb)) in a.meshes.iter().zip(&b.meshes).enumerate() {
        // Vertex data is stored as raw f32: it comes back bit for bit.
        same(&ma.indices, &mb.indices, &format!("{what} mesh {k} indices"));
        same(&ma.positions, &mb.positions, &format!("{what} mesh {k} positions"));
        same(&ma.normals, &mb.normals, &format!("{what} mesh {k} normals"));
        assert_eq!(ma.uvs.is_some(), mb.uvs.is_some(), "{what} mesh {k}");
        same(ma.uvs.as_deref().unwrap_or(&[]), mb.uvs.as_deref().unwrap_or(&[]), &format!("{what} mesh {k} uvs"));
        assert_eq!(ma.tangents.is_some(), mb.tangents.is_some(), "{what} mesh {k}");
        same(ma.tangents.as_deref().unwrap_or(&[]), mb.tangents.as_deref().unwrap_or(&[]), &format!("{what} mesh {k} tangents"));
    }
    // The camera's rotation goes through a quaternion: equal to float rounding.
    let (ca, cb) = (a.camera.world_from_camera, b.camera.world_from_camera);
    let scale = ca.w_axis.truncate().length().max(1.0);
    assert!(ca.abs_diff_eq(cb, 1e-6 * scale), "{what}: camera\n{ca}\nvs\n{cb}");
    assert_eq!(a.camera.projection, b.camera.projection, "{what}");
    match (a.light, b.light) {
        (
            Light::Directional { direction: da, color: ca, intensity: ia },
            Light::Directional { direction: db, color: cb, intensity: ib },
        ) => {
            assert!((da - db).length() < 1e-6, "{what}: light {da} vs {db}");
            assert_eq!((ca, ia), (cb, ib), "{what}");
        }
        (la, lb) => assert_eq!(la, lb, "{what}"),
    }
}

#[test]
fn every_standard_scene_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for (k, &model) in scene::builtin_models().iter().enumerate() {
        // One preset per model, cycling through them.
        let names = scene::preset_names();
        let preset = names[k % names.len()];
        let scene = Scene::from_preset(model, preset).unwrap();
        let path = dir.path().join(format!("{model}.gltf"));
        scene::write_gltf(&scene, &path).unwrap();
        let back = scene::load(&path).unwrap();
        assert_same_scene(&scene, &back, &format!("{model} {preset}"));
    }
    // Only the written files are left: no temporary files.
    let mut names: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    let mut expected: Vec<String> = scene::builtin_models().iter().map(|m| format!("{m}.gltf")).collect();
    expected.sort();
    assert_eq!(names, expected);
}

/// Two meshes (one without uvs or tangents), a tilted orthographic camera and a point light.
fn hand_scene() -> Scene {
    let mut a = scene::sphere_mesh(12, 6);
    a.transform(Mat4::from_scale_rotation_translation(Vec3::new(1.0, 2.0, 0.5), Quat::from_rotation_x(0.3), Vec3::new(-1.0, 0.0, 2.0)));
    let b = CpuMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.25)],
        normals: vec![Vec3::Z; 4],
        tangents: None,
        uvs: None,
        indices: vec![0, 1, 2, 2, 1, 3],
    };
    Scene {
        meshes: vec![a, b],
        camera: Camera {
            world_from_camera: Mat4::from_rotation_translation(
                Quat::from_euler(glam::EulerRot::YXZ, 0.4, -0.2, 0.1),
                Vec3::new(3.0, 1.0, 7.0),
            ),
            projection: Projection::Orthographic { xmag: 2.5, ymag: 1.25, znear: 0.01, zfar: 50.0 },
        },
        light: Light::Point { position: Vec3::new(1.5, 4.0, -2.0), color: Vec3::new(1.0, 0.9, 0.7), intensity: 123.5 },
    }
}

#[test]
fn point_light_orthographic_camera_and_missing_attributes_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hand_scene();
    let path = dir.path().join("scene.gltf");
    scene.write_gltf(&path).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_same_scene(&scene, &back, "hand scene");
    assert!(back.meshes[1].uvs.is_none() && back.meshes[1].tangents.is_none());

    // A perspective camera without aspect ratio or far plane keeps them absent.
    let mut infinite = scene.clone();
    infinite.camera.projection = Projection::Perspective { yfov: 0.7, aspect: None, znear: 0.05, zfar: None };
    infinite.light = Light::Directional { direction: Vec3::new(0.0, 0.0, 1.0), color: Vec3::ONE, intensity: 2.0 };
    infinite.write_gltf(&path).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_same_scene(&infinite, &back, "infinite perspective, light along +Z");
}

#[test]
fn written_file_is_self_contained_gltf() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hand_scene();
    let path = dir.path().join("scene.gltf");
    scene.write_gltf(&path).unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");
    assert!(doc["extensionsUsed"].as_array().unwrap().iter().any(|e| e == "KHR_lights_punctual"));
    let lights = doc["extensions"]["KHR_lights_punctual"]["lights"].as_array().unwrap();
    assert_eq!(lights.len(), 1);
    assert_eq!(lights[0]["type"], "point");
    assert_eq!(lights[0]["intensity"], 123.5);
    // One buffer, embedded: the file can be moved alone.
    let buffers = doc["buffers"].as_array().unwrap();
    assert_eq!(buffers.len(), 1);
    assert!(buffers[0]["uri"].as_str().unwrap().starts_with("data:application/octet-stream;base64,"));
    // One node per mesh, plus the camera and the light, all in the scene.
    assert_eq!(doc["nodes"].as_array().unwrap().len(), scene.meshes.len() + 2);
    assert_eq!(doc["scenes"][0]["nodes"].as_array().unwrap().len(), scene.meshes.len() + 2);
    let cameras = doc["cameras"].as_array().unwrap();
    assert_eq!(cameras.len(), 1);
    assert_eq!(cameras[0]["type"], "orthographic");
    // POSITION accessors carry min and max (required by glTF), equal to the mesh bounds.
    for (k, mesh) in scene.meshes.iter().enumerate() {
        let accessor = doc["meshes"][k]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
        let (lo, hi) = mesh.bounds().unwrap();
        let read = |v: &serde_json::Value| Vec3::from_array([0, 1, 2].map(|i| v[i].as_f64().unwrap() as f32));
        assert_eq!(read(&doc["accessors"][accessor]["min"]), lo);
        assert_eq!(read(&doc["accessors"][accessor]["max"]), hi);
    }
    // Moved elsewhere, it still loads.
    let moved = dir.path().join("moved");
    std::fs::create_dir(&moved).unwrap();
    std::fs::rename(&path, moved.join("elsewhere.gltf")).unwrap();
    Scene::load(moved.join("elsewhere.gltf")).unwrap();
}

#[test]
fn writing_is_atomic_and_refuses_bad_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.gltf");
    // Overwriting replaces the file whole.
    std::fs::write(&path, "old content").unwrap();
    let scene = Scene::from_preset("teapot", "side").unwrap();
    scene.write_gltf(&path).unwrap();
    assert_eq!(Scene::load(&path).unwrap().meshes[0].positions, scene.meshes[0].positions);

    // A non-finite light is refused, and the previous file is untouched.
    let before = std::fs::read(&path).unwrap();
    let mut bad = scene.clone();
    bad.light = Light::Directional { direction: Vec3::new(f32::NAN, 0.0, -1.0), color: Vec3::ONE, intensity: 1.0 };
    let message = bad.write_gltf(&path).unwrap_err().to_string();
    assert!(message.contains("scene.gltf") && message.contains("light"), "{message}");
    // Inconsistent meshes too.
    let mut bad = scene.clone();
    bad.meshes[0].normals.pop();
    let message = bad.write_gltf(&path).unwrap_err().to_string();
    assert!(message.contains("normals"), "{message}");
    assert_eq!(std::fs::read(&path).unwrap(), before);

    // A directory that does not exist: an error naming the path, nothing written.
    let missing = dir.path().join("no/such/dir/scene.gltf");
    let message = scene.write_gltf(&missing).unwrap_err().to_string();
    assert!(message.contains("no/such/dir/scene.gltf"), "{message}");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, vec![std::ffi::OsString::from("scene.gltf")]);

    // Hand-checked attribute values survive: a uv of exactly 1 and a tangent sign of -1.
    let mut flipped = scene.clone();
    flipped.meshes = vec![CpuMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: vec![Vec3::Z; 3],
        tangents: Some(vec![Vec4::new(1.0, 0.0, 0.0, -1.0); 3]),
        uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE]),
        indices: vec![0, 1, 2],
    }];
    flipped.write_gltf(&path).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_eq!(back.meshes[0].tangents.as_ref().unwrap()[1], Vec4::new(1.0, 0.0, 0.0, -1.0));
    assert_eq!(back.meshes[0].uvs.as_ref().unwrap()[2], Vec2::ONE);
}
