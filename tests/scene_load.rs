//! Loading glTF scenes: real models, hand-built files with known answers, and bad input.

use std::path::{Path, PathBuf};

use brdfpaint::scene::{self, Light, Projection, Scene};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use serde_json::{json, Value};

// ---------------------------------------------------------------------------------------------
// A tiny glTF builder: accessors into one binary buffer, written as .gltf + .bin or as .glb.

#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    fn push(&mut self, bytes: &[u8], count: usize, ty: &str, component: u32, extra: Value) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() }));
        let mut accessor = json!({ "bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": ty });
        if let (Value::Object(a), Value::Object(e)) = (&mut accessor, extra) {
            a.extend(e);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn vec3(&mut self, v: &[Vec3]) -> usize {
        let lo = v.iter().fold(Vec3::splat(f32::INFINITY), |a, &b| a.min(b));
        let hi = v.iter().fold(Vec3::splat(f32::NEG_INFINITY), |a, &b| a.max(b));
        let bytes: Vec<u8> = v.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
        self.push(&bytes, v.len(), "VEC3", 5126, json!({ "min": lo.to_array(), "max": hi.to_array() }))
    }

    fn vec2(&mut self, v: &[Vec2]) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
        self.push(&bytes, v.len(), "VEC2", 5126, json!({}))
    }

    fn vec4(&mut self, v: &[Vec4]) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
        self.push(&bytes, v.len(), "VEC4", 5126, json!({}))
    }

    fn joints(&mut self, v: &[[u16; 4]]) -> usize {
        let bytes: Vec<u8> = v.iter().flatten().flat_map(|j| j.to_le_bytes()).collect();
        self.push(&bytes, v.len(), "VEC4", 5123, json!({}))
    }

    fn mat4(&mut self, v: &[Mat4]) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|m| m.to_cols_array()).flat_map(f32::to_le_bytes).collect();
        self.push(&bytes, v.len(), "MAT4", 5126, json!({}))
    }

    fn indices(&mut self, v: &[u16]) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|i| i.to_le_bytes()).collect();
        self.push(&bytes, v.len(), "SCALAR", 5123, json!({}))
    }

    /// `doc` with asset, accessors, bufferViews and buffers filled in; `uri` names the .bin.
    fn document(&self, mut doc: Value, uri: Option<&str>) -> Value {
        doc["asset"] = json!({ "version": "2.0" });
        doc["accessors"] = json!(self.accessors);
        doc["bufferViews"] = json!(self.views);
        doc["buffers"] = match uri {
            Some(uri) => json!([{ "byteLength": self.bin.len(), "uri": uri }]),
            None => json!([{ "byteLength": self.bin.len() }]),
        };
        doc
    }

    /// Writes `dir/name.gltf` and `dir/name.bin`; returns the .gltf path.
    fn write_gltf(&self, dir: &Path, name: &str, doc: Value) -> PathBuf {
        let bin = format!("{name}.bin");
        std::fs::write(dir.join(&bin), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_string_pretty(&self.document(doc, Some(&bin))).unwrap()).unwrap();
        path
    }

    /// Writes `dir/name.glb`; returns its path.
    fn write_glb(&self, dir: &Path, name: &str, doc: Value) -> PathBuf {
        self.write_glb_document(dir, name, &self.document(doc, None))
    }

    /// Writes `dir/name.glb` with a complete document (see [`Builder::document`]).
    fn write_glb_document(&self, dir: &Path, name: &str, document: &Value) -> PathBuf {
        let mut text = serde_json::to_vec(document).unwrap();
        while text.len() % 4 != 0 {
            text.push(b' ');
        }
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&((12 + 8 + text.len() + 8 + self.bin.len()) as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&self.bin);
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, out).unwrap();
        path
    }
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

/// The error of `result`, checked to be one line that names `path`'s file.
fn error_naming<T: std::fmt::Debug>(result: brdfpaint::Result<T>, path: &Path) -> String {
    let message = result.expect_err("bad input was accepted").to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(message.contains(name.as_ref()), "message does not name {name}: {message}");
    assert!(!message.contains('\n'), "message is not one line: {message}");
    message
}

fn shared_models() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/models");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipped: {} not found", dir.display());
        None
    }
}

/// One triangle with normal (1,1,1)/√3, tangent (1,-1,0)/√2 and uvs.
fn triangle(b: &mut Builder) -> Value {
    let pos = b.vec3(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let nrm = b.vec3(&[Vec3::ONE.normalize(); 3]);
    let tan = b.vec4(&[Vec3::new(1.0, -1.0, 0.0).normalize().extend(1.0); 3]);
    let uv = b.vec2(&[Vec2::ZERO, Vec2::X, Vec2::Y]);
    let idx = b.indices(&[0, 1, 2]);
    json!({ "primitives": [{ "attributes": { "POSITION": pos, "NORMAL": nrm, "TANGENT": tan, "TEXCOORD_0": uv }, "indices": idx }] })
}

fn quat_json(q: Quat) -> Value {
    json!(q.to_array())
}

const PERSPECTIVE: &str = r#"{ "type": "perspective", "perspective": { "yfov": 0.5, "aspectRatio": 1.5, "znear": 0.1, "zfar": 100.0 } }"#;

/// A scene with a hierarchy, a camera and a light, all with transforms worked out by hand.
fn hierarchy_doc(b: &mut Builder) -> Value {
    let mesh = triangle(b);
    let camera: Value = serde_json::from_str(PERSPECTIVE).unwrap();
    json!({
        "scene": 0,
        "scenes": [{ "nodes": [0, 2, 3, 4] }],
        "nodes": [
            { "name": "parent", "translation": [1.0, 2.0, 3.0], "rotation": quat_json(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)), "children": [1] },
            { "name": "child", "scale": [2.0, 1.0, 1.0], "mesh": 0 },
            // Column-major: translation in the last column.
            { "name": "matrix", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1], "mesh": 0 },
            { "name": "camera", "translation": [0.0, 0.0, 5.0], "rotation": quat_json(Quat::from_rotation_y(std::f32::consts::FRAC_PI_2)), "scale": [3.0, 3.0, 3.0], "camera": 0 },
            { "name": "sun", "rotation": quat_json(Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)), "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "meshes": [mesh],
        "cameras": [camera],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [{ "type": "directional", "color": [1.0, 0.5, 0.25], "intensity": 3.0 }] } }
    })
}

// ---------------------------------------------------------------------------------------------

#[test]
fn node_transforms_are_applied() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let doc = hierarchy_doc(&mut b);
    let gltf = b.write_gltf(dir.path(), "hierarchy", doc.clone());
    let glb = b.write_glb(dir.path(), "hierarchy", doc);
    for path in [gltf, glb] {
        let scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.meshes.len(), 2, "{}", path.display());

        // World = T(1,2,3) · Rz(90°) · S(2,1,1): (x,y,z) -> (1 - y, 2 + 2x, 3 + z).
        let m = &scene.meshes[0];
        let expected = [Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 4.0, 3.0), Vec3::new(0.0, 2.0, 3.0)];
        for (p, e) in m.positions.iter().zip(expected) {
            assert!(close(*p, e, 1e-6), "position {p}, expected {e}");
        }
        // Normals by the inverse transpose R S⁻¹: (1,1,1) -> (0.5,1,1) -> (-1,0.5,1) -> (-2,1,2)/3.
        for n in &m.normals {
            assert!(close(*n, Vec3::new(-2.0, 1.0, 2.0) / 3.0, 1e-6), "normal {n}");
        }
        // Tangents by R S: (1,-1,0) -> (2,-1,0) -> (1,2,0), normalized; w kept.
        for t in m.tangents.as_ref().unwrap() {
            assert!(close(t.truncate(), Vec3::new(1.0, 2.0, 0.0) / 5f32.sqrt(), 1e-6), "tangent {t}");
            assert_eq!(t.w, 1.0);
        }
        assert_eq!(m.uvs.as_deref(), Some(&[Vec2::ZERO, Vec2::X, Vec2::Y][..]));
        assert_eq!(m.indices, vec![0, 1, 2]);

        // The matrix node translates by (10, 0, 0) and nothing else.
        let m = &scene.meshes[1];
        for (p, e) in m.positions.iter().zip([Vec3::new(10.0, 0.0, 0.0), Vec3::new(11.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 0.0)]) {
            assert!(close(*p, e, 1e-6), "matrix node: position {p}, expected {e}");
        }
        assert!(close(m.normals[0], Vec3::ONE.normalize(), 1e-6));

        // Camera at (0,0,5), turned 90° about +Y: looks along -X, +Y up; its scale is dropped.
        let cam = scene.camera;
        assert!(close(cam.position(), Vec3::new(0.0, 0.0, 5.0), 1e-6));
        assert!(close(cam.forward(), -Vec3::X, 1e-6), "forward {}", cam.forward());
        assert!(close(cam.world_from_camera.transform_vector3(Vec3::Y), Vec3::Y, 1e-6));
        assert!(close(cam.world_from_camera.transform_vector3(Vec3::X), -Vec3::Z, 1e-6), "no scale");
        assert_eq!(
            cam.projection,
            Projection::Perspective { yfov: 0.5, aspect: Some(1.5), znear: 0.1, zfar: Some(100.0) }
        );

        // Directional light turned -90° about +X: its -Z points down.
        let Light::Directional { direction, color, intensity } = scene.light else { panic!("{:?}", scene.light) };
        assert!(close(direction, -Vec3::Y, 1e-6), "light direction {direction}");
        assert_eq!((color, intensity), (Vec3::new(1.0, 0.5, 0.25), 3.0));
    }
}

#[test]
fn point_light_orthographic_camera_and_missing_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    // Positions only: normals are generated, uvs and tangents stay absent.
    let pos = b.vec3(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let doc = json!({
        "scenes": [{ "nodes": [0, 1] }],
        "nodes": [
            { "mesh": 0, "scale": [1.0, 1.0, -1.0] },
            { "translation": [0.0, 1.0, 0.0], "children": [2, 3] },
            { "translation": [2.0, 0.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "translation": [0.0, 0.0, 4.0], "camera": 0 }
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": pos } }] }],
        "cameras": [{ "type": "orthographic", "orthographic": { "xmag": 2.0, "ymag": 1.0, "znear": 0.5, "zfar": 9.0 } }],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [{ "type": "point", "intensity": 40.0 }] } }
    });
    let path = b.write_glb(dir.path(), "point", doc);
    let scene = scene::load(&path).unwrap();
    // glTF defaults: colour white. The point light sits at parent + child translation.
    assert_eq!(scene.light, Light::Point { position: Vec3::new(2.0, 1.0, 0.0), color: Vec3::ONE, intensity: 40.0 });
    assert_eq!(scene.camera.projection, Projection::Orthographic { xmag: 2.0, ymag: 1.0, znear: 0.5, zfar: 9.0 });
    assert!(close(scene.camera.position(), Vec3::new(0.0, 1.0, 4.0), 1e-6));
    let m = &scene.meshes[0];
    assert!(m.uvs.is_none() && m.tangents.is_none());
    // Without indices the vertices are the triangle list. The triangle is counter-clockwise
    // seen from +Z in the file; the mirroring scale z -> -z turns its front to -Z, and the
    // loader reverses the winding to keep it counter-clockwise, so the generated normal is -Z.
    assert_eq!(m.indices, vec![0, 2, 1]);
    for n in &m.normals {
        assert!(close(*n, -Vec3::Z, 1e-6), "generated normal {n}");
    }
}

#[test]
fn skinned_mesh_is_posed_by_its_joints_and_ignores_its_node() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let pos = b.vec3(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let joints = b.joints(&[[0, 1, 0, 0], [0, 1, 0, 0], [0, 1, 0, 0]]);
    let weights = b.vec4(&[Vec4::new(1.0, 0.0, 0.0, 0.0), Vec4::new(0.0, 1.0, 0.0, 0.0), Vec4::new(0.5, 0.5, 0.0, 0.0)]);
    let ibm = b.mat4(&[Mat4::IDENTITY, Mat4::from_translation(Vec3::new(-4.0, 0.0, 0.0))]);
    let doc = json!({
        "scenes": [{ "nodes": [0, 1, 2] }],
        "nodes": [
            // The skinned node's own scale must be ignored.
            { "mesh": 0, "skin": 0, "scale": [10.0, 10.0, 10.0] },
            { "name": "joint A", "translation": [0.0, 5.0, 0.0] },
            { "name": "joint B", "translation": [4.0, 0.0, 0.0] }
        ],
        "skins": [{ "joints": [1, 2], "inverseBindMatrices": ibm }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": pos, "JOINTS_0": joints, "WEIGHTS_0": weights } }] }]
    });
    let path = b.write_gltf(dir.path(), "skin", doc);
    let meshes = brdfpaint::scene::model_meshes(&path).unwrap();
    // J_A B_A = T(0,5,0); J_B B_B = T(4,0,0) T(-4,0,0) = I; the half-half vertex gets T(0,2.5,0).
    let expected = [Vec3::new(0.0, 5.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 3.5, 0.0)];
    for (p, e) in meshes[0].positions.iter().zip(expected) {
        assert!(close(*p, e, 1e-6), "skinned position {p}, expected {e}");
    }
}

#[test]
fn generated_sphere_normals_match_analytic() {
    // A UV sphere stored with positions and uvs only: the loader makes the normals (smooth,
    // angle-weighted) and MikkTSpace tangents.
    let sphere = scene::sphere_mesh(64, 32);
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let pos = b.vec3(&sphere.positions);
    let uv = b.vec2(sphere.uvs.as_ref().unwrap());
    let idx = b.indices(&sphere.indices.iter().map(|&i| i as u16).collect::<Vec<_>>());
    let doc = json!({
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": pos, "TEXCOORD_0": uv }, "indices": idx }] }]
    });
    let path = b.write_glb(dir.path(), "sphere", doc);
    let m = scene::model_meshes(&path).unwrap().remove(0);

    // Normals: the analytic normal is the position. The rings are symmetric about each vertex
    // in azimuth; the residual is the latitude asymmetry of a 32-ring tessellation, well
    // under half a degree.
    let mut worst = 0.0f32;
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!((n.length() - 1.0).abs() < 1e-5);
        worst = worst.max(n.dot(p.normalize()).clamp(-1.0, 1.0).acos().to_degrees());
    }
    assert!(worst < 0.5, "worst generated normal is {worst}° from analytic");

    // MikkTSpace tangents: unit, orthogonal to the normal, w = +1, along increasing u, which
    // on this sphere is the azimuthal direction normalize(Y × n). Seam vertices see only one
    // side's triangles, so there the tangent is the chord, within half a segment (π/64).
    let tangents = m.tangents.as_ref().unwrap();
    let uvs = m.uvs.as_ref().unwrap();
    for k in 0..m.positions.len() {
        let (p, n, t) = (m.positions[k], m.normals[k], tangents[k]);
        assert!((t.truncate().length() - 1.0).abs() < 1e-4, "tangent {t} at {p}");
        assert!(t.truncate().dot(n).abs() < 1e-4, "tangent {t} not orthogonal to {n} at {p}");
        assert_eq!(t.w, 1.0, "handedness at {p}");
        if p.y.abs() > 0.999 {
            continue; // the poles, where the azimuth is undefined
        }
        let azimuthal = Vec3::Y.cross(p).normalize();
        let on_seam = uvs[k].x == 0.0 || uvs[k].x == 1.0;
        let bound = if on_seam { (std::f32::consts::PI / 64.0).cos() - 1e-4 } else { 1.0 - 1e-4 };
        assert!(t.truncate().dot(azimuthal) > bound, "tangent {t} at {p}, expected {azimuthal}");
    }
}

#[test]
fn loads_every_shared_model() {
    let Some(dir) = shared_models() else { return };
    // (file, vertices, triangles, world AABB min, max, has uvs), computed independently from
    // the files' JSON and binary data (node transforms applied; skins in rest pose, which for
    // the fox is the identity to 1e-5).
    type Expected = (&'static str, usize, usize, [f32; 3], [f32; 3], bool);
    #[rustfmt::skip]
    let expected: &[Expected] = &[
        ("khronos_boxtextured/BoxTextured.glb", 24, 12, [-0.5, -0.5, -0.5], [0.5, 0.5, 0.5], true),
        ("khronos_duck/Duck.glb", 2399, 4212, [-0.692985, 0.0992937, -0.613282], [0.961799, 1.6397, 0.539252], true),
        ("khronos_fox/Fox.gltf", 1728, 576, [-12.5927, -0.121745, -88.095], [12.5927, 78.9072, 66.6249], true),
        ("khronos_fox/fox_with_normals_keechang/fox-normal.gltf", 1728, 576, [-12.5927, -0.121744, -88.095], [12.5927, 78.9072, 66.6249], true),
        ("pmndrs_suzi/suzi_with_normals.glb", 7503, 14842, [-0.92973, -0.669795, -0.544786], [0.92973, 0.668249, 0.576134], false),
        ("polyhaven_apple/food_apple_01_4k.gltf", 4019, 7012, [-0.0483814, -2.26221e-05, -0.045817], [0.0491798, 0.0853673, 0.0500847], true),
        ("stanford_bunny/bunny_pmndrs_with_normals.glb", 2826, 5648, [-0.913771, -0.891042, -0.696372], [0.917214, 0.939832, 0.698855], false),
    ];
    let mut seen = Vec::new();
    for entry in walk(&dir) {
        let ext = entry.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if !matches!(ext.as_str(), "glb" | "gltf" | "obj" | "ply" | "stl") {
            continue;
        }
        let rel = entry.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/");
        if ext != "glb" && ext != "gltf" {
            // Other mesh formats: a clear error that names the file and says what is read.
            let message = error_naming(scene::model_meshes(&entry), &entry);
            assert!(message.contains("glTF"), "{message}");
            continue;
        }
        let (_, vertices, triangles, lo, hi, has_uvs) =
            *expected.iter().find(|e| e.0 == rel).unwrap_or_else(|| panic!("no expectation for {rel}"));
        seen.push(rel.clone());
        let meshes = scene::model_meshes(&entry).unwrap_or_else(|e| panic!("{e}"));
        // As a model it lacks a camera (the Duck has one) or a light, so as a scene it is a
        // clear error.
        let message = error_naming(Scene::load(&entry), &entry);
        assert!(message.contains("no camera") || message.contains("no light"), "{message}");

        let n: usize = meshes.iter().map(|m| m.positions.len()).sum();
        let t: usize = meshes.iter().map(|m| m.indices.len() / 3).sum();
        assert_eq!((n, t), (vertices, triangles), "{rel}");
        let (mut got_lo, mut got_hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for m in &meshes {
            let (a, b) = m.bounds().unwrap();
            got_lo = got_lo.min(a);
            got_hi = got_hi.max(b);
        }
        let extent = (Vec3::from(hi) - Vec3::from(lo)).max_element();
        let tol = 1e-4 * extent;
        assert!(close(got_lo, lo.into(), tol) && close(got_hi, hi.into(), tol), "{rel}: bounds {got_lo}..{got_hi}");
        for m in &meshes {
            assert_eq!(m.uvs.is_some(), has_uvs, "{rel}");
            assert_eq!(m.tangents.is_some(), has_uvs, "{rel}: tangents exactly where uvs are");
            assert!(m.normals.iter().all(|v| (v.length() - 1.0).abs() < 1e-4), "{rel}: unit normals");
            // Normals agree with the winding: most faces' geometric normals point the way
            // their vertices' normals do (files with normals) or exactly so (generated).
            let agree = m
                .indices
                .chunks_exact(3)
                .filter(|tri| {
                    let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
                    let face = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
                    face.dot(m.normals[a] + m.normals[b] + m.normals[c]) > 0.0
                })
                .count();
            let share = agree as f32 / (m.indices.len() / 3) as f32;
            assert!(share > 0.95, "{rel}: only {share} of faces agree with their normals");
        }
    }
    for e in expected {
        assert!(seen.iter().any(|s| s == e.0), "{} not found", e.0);
    }
}

#[test]
fn bundled_models_are_the_shared_ones() {
    // The bundled copies load to the same geometry as the shared originals.
    let Some(dir) = shared_models() else { return };
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models");
    for (bundled, original) in [
        ("bunny/bunny.glb", "stanford_bunny/bunny_pmndrs_with_normals.glb"),
        ("suzanne/suzanne.glb", "pmndrs_suzi/suzi_with_normals.glb"),
        ("apple/apple.glb", "polyhaven_apple/food_apple_01_4k.gltf"),
        ("fox/fox.glb", "khronos_fox/Fox.gltf"),
    ] {
        let a = scene::model_meshes(assets.join(bundled)).unwrap();
        let b = scene::model_meshes(dir.join(original)).unwrap();
        let name = bundled.split('/').next().unwrap();
        let c = scene::builtin_model(name).unwrap();
        assert_eq!(a.len(), b.len());
        for ((a, b), c) in a.iter().zip(&b).zip(&c) {
            assert_eq!(a.positions, b.positions, "{bundled}");
            assert_eq!(a.normals, b.normals, "{bundled}");
            assert_eq!(a.indices, b.indices, "{bundled}");
            assert_eq!(a.positions, c.positions, "{name} built-in");
        }
    }
    // The teapot: the OBJ's vertices and faces, unchanged.
    let teapot = scene::builtin_model("teapot").unwrap().remove(0);
    let obj = std::fs::read_to_string(dir.join("utah_teapot/teapot_npm_792v.obj")).unwrap();
    let mut v = Vec::new();
    let mut f = Vec::new();
    for line in obj.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => v.push(Vec3::from_array([0, 1, 2].map(|_| it.next().unwrap().parse::<f32>().unwrap()))),
            Some("f") => f.extend([0, 1, 2].map(|_| it.next().unwrap().parse::<u32>().unwrap() - 1)),
            _ => {}
        }
    }
    assert_eq!(teapot.positions, v);
    assert_eq!(teapot.indices, f);
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

// ---------------------------------------------------------------------------------------------
// Bad input: an error naming the file, never a panic.

#[test]
fn incomplete_scenes_say_what_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let full = hierarchy_doc(&mut b);

    let mut no_camera = full.clone();
    no_camera["nodes"][3].as_object_mut().unwrap().remove("camera");
    let path = b.write_gltf(dir.path(), "no_camera", no_camera);
    assert!(error_naming(scene::load(&path), &path).contains("no camera"));

    let mut no_light = full.clone();
    no_light["nodes"][4].as_object_mut().unwrap().remove("extensions");
    let path = b.write_gltf(dir.path(), "no_light", no_light);
    assert!(error_naming(scene::load(&path), &path).contains("no light"));

    let mut no_mesh = full.clone();
    no_mesh["nodes"][1].as_object_mut().unwrap().remove("mesh");
    no_mesh["nodes"][2].as_object_mut().unwrap().remove("mesh");
    let path = b.write_gltf(dir.path(), "no_mesh", no_mesh);
    assert!(error_naming(scene::load(&path), &path).contains("no triangle mesh"));

    // Only points: skipped, and the message says so.
    let mut points = full.clone();
    points["meshes"][0]["primitives"][0]["mode"] = json!(0);
    let path = b.write_gltf(dir.path(), "points", points);
    let message = error_naming(scene::load(&path), &path);
    assert!(message.contains("no triangle mesh") && message.contains("Points"), "{message}");
}

#[test]
fn missing_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let doc = hierarchy_doc(&mut b);

    let path = b.write_gltf(dir.path(), "nobin", doc.clone());
    std::fs::remove_file(dir.path().join("nobin.bin")).unwrap();
    let message = error_naming(scene::load(&path), &path);
    assert!(message.contains("missing buffer file") && message.contains("nobin.bin"), "{message}");

    let mut textured = doc.clone();
    textured["images"] = json!([{ "uri": "paint%20ed.png" }]);
    let path = b.write_gltf(dir.path(), "notex", textured.clone());
    let message = error_naming(scene::load(&path), &path);
    assert!(message.contains("missing texture file") && message.contains("paint ed.png"), "{message}");
    // With the texture present (percent-decoded name) it loads.
    std::fs::write(dir.path().join("paint ed.png"), b"not decoded").unwrap();
    scene::load(&path).unwrap();

    let path = dir.path().join("absent.glb");
    error_naming(scene::load(&path), &path);
}

#[test]
fn corrupt_and_unsupported_files_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::default();
    let doc = hierarchy_doc(&mut b);
    let good = b.write_glb(dir.path(), "good", doc.clone());
    scene::load(&good).unwrap();
    let bytes = std::fs::read(&good).unwrap();

    // Truncated .glb at every length class: header, JSON, binary chunk.
    for len in [0, 4, 11, 12, 19, 20, 40, bytes.len() / 2, bytes.len() - 60, bytes.len() - 1] {
        let path = dir.path().join(format!("truncated{len}.glb"));
        std::fs::write(&path, &bytes[..len]).unwrap();
        error_naming(scene::load(&path), &path);
    }

    // Garbage bytes, seeded.
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let garbage: Vec<u8> = (0..4096)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state as u8
        })
        .collect();
    for (name, data) in [("garbage.glb", &garbage[..]), ("garbage.gltf", &garbage[..]), ("text.gltf", &b"{ \"asset\": "[..])] {
        let path = dir.path().join(name);
        std::fs::write(&path, data).unwrap();
        error_naming(scene::load(&path), &path);
    }

    // A required extension that changes geometry.
    let mut draco = doc.clone();
    draco["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    draco["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_draco_mesh_compression"]);
    let path = b.write_glb(dir.path(), "draco", draco);
    assert!(error_naming(scene::load(&path), &path).contains("KHR_draco_mesh_compression"));

    // An accessor that claims more elements than its buffer holds.
    let mut long = b.document(doc.clone(), None);
    long["accessors"][0]["count"] = json!(1_000_000_000u64);
    let path = b.write_glb_document(dir.path(), "long_accessor", &long);
    assert!(error_naming(scene::load(&path), &path).contains("outside its buffer"));

    // A buffer that claims more bytes than the file has.
    let path = b.write_gltf(dir.path(), "short_bin", doc.clone());
    let bin = dir.path().join("short_bin.bin");
    std::fs::write(&bin, &std::fs::read(&bin).unwrap()[..10]).unwrap();
    error_naming(scene::load(&path), &path);

    // An index past the vertices.
    let mut b2 = Builder::default();
    let pos = b2.vec3(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    let idx = b2.indices(&[0, 1, 7]);
    let bad_index = json!({
        "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": pos }, "indices": idx }] }]
    });
    let path = b2.write_glb(dir.path(), "bad_index", bad_index);
    assert!(error_naming(scene::model_meshes(&path), &path).contains("out of range"));

    // Positions of the wrong type.
    let mut ints = b.document(doc.clone(), None);
    ints["accessors"][0]["componentType"] = json!(5125);
    let path = b.write_glb_document(dir.path(), "int_positions", &ints);
    assert!(error_naming(scene::load(&path), &path).contains("POSITION"));

    // A cycle in the node hierarchy.
    let mut cycle = doc.clone();
    cycle["nodes"][1]["children"] = json!([0]);
    let path = b.write_glb(dir.path(), "cycle", cycle);
    let message = error_naming(scene::load(&path), &path);
    assert!(message.contains("cycle") || message.contains("tree"), "{message}");

    // A bad camera.
    let mut camera = doc.clone();
    camera["cameras"][0]["perspective"]["yfov"] = json!(-1.0);
    let path = b.write_glb(dir.path(), "camera", camera);
    assert!(error_naming(scene::load(&path), &path).contains("yfov"));

    // Not glTF at all, by name.
    let path = dir.path().join("model.obj");
    std::fs::write(&path, "v 0 0 0\n").unwrap();
    assert!(error_naming(scene::load(&path), &path).contains("glTF"));
}

#[test]
fn corrupted_real_files_never_panic() {
    // Seeded corruption of a real .glb: truncations and flipped bytes in the JSON and binary
    // chunks. Each load must return (Ok or Err), and every Err must name the file.
    let glb = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/teapot/teapot.glb")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("corrupt.glb");
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let (mut ok, mut err) = (0, 0);
    for trial in 0..300 {
        let mut bytes = glb.clone();
        if trial % 3 == 0 {
            bytes.truncate((next() as usize) % bytes.len());
        } else {
            // Mostly the JSON chunk (the first ~900 bytes), where structure lives.
            let span = if trial % 3 == 1 { 900.min(bytes.len()) } else { bytes.len() };
            for _ in 0..1 + next() % 4 {
                let at = (next() as usize) % span;
                bytes[at] = next() as u8;
            }
        }
        std::fs::write(&path, &bytes).unwrap();
        match std::panic::catch_unwind(|| scene::model_meshes(&path)) {
            Ok(Ok(_)) => ok += 1,
            Ok(Err(e)) => {
                assert!(e.to_string().contains("corrupt.glb"), "{e}");
                err += 1;
            }
            Err(_) => panic!("trial {trial} panicked"),
        }
    }
    assert!(err > 100, "only {err} of 300 corruptions were caught ({ok} loaded)");
}
