//! Issue 33, "trust, round 2" (items 4–8 and the smaller ones): crafted inputs that
//! panicked, hung or took gigabytes, and loose files real exporters write. Each case asserts
//! the exit code, the one-line message and, for the bombs, the peak memory the kernel
//! measured for the run.

mod measured_common;

use std::io::Write;
use std::path::{Path, PathBuf};

use brdfpaint::brdf::Merl;
use brdfpaint::images::env::Environment;
use brdfpaint::scene::{frame, sphere_mesh, Preset, Scene};
use serde_json::{json, Value};

use measured_common::*;

/// A small MERL file (a Lambertian table) and the material `fit --merl` makes of it.
fn merl_material(dir: &Path) -> PathBuf {
    let merl = dir.join("lambert.binary");
    Merl::from_brdf(|_, _| [0.2, 0.3, 0.4]).write(&merl).unwrap();
    let mat = dir.join("mat");
    let r = run(dir, &["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)], MINUTE);
    assert_eq!(r.code, 0, "{}", r.stderr);
    mat
}

/// Item 4: a picture too narrow to hold a sphere panicked `fit --lit-sphere` (index out of
/// bounds on a shrunk picture with no rows).
#[test]
fn lit_sphere_strips_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h, shorter) in [(1000, 1, 0), (16384, 1, 0), (1, 16384, 0), (600, 20, 10)] {
        let path = dir.path().join(format!("strip-{w}x{h}.png"));
        write_png(&path, w, h, false, |_, _| [200, 100, 50]);
        let r = run(dir.path(), &["fit", "--lit-sphere", s(&path), "--out", s(&dir.path().join("out"))], MINUTE);
        let size = format!("strip-{w}x{h}.png is {w}x{h}: too small or too narrow to hold a sphere");
        assert_one_line_error(&r, &[&size, &format!("its shorter side is {shorter} pixels; a sphere needs 16")]);
    }
}

/// Item 5: a prepare-cache entry that is a FIFO hung `fit`; a link to /dev/zero read until
/// memory ran out. Both are rebuilt over, as a corrupt entry is.
#[test]
fn cache_entries_that_are_fifos_or_devices_are_rebuilt() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let sheet = dir.path().join("sheet");
    let r = run(dir.path(), &["sheet", "--model", "sphere", "--size", "96x96", "--out", s(&sheet)], MINUTE);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let (scene, painting) = (sheet.join("scene.gltf"), sheet.join("reference.png"));
    let fit = || run(&cache, &["fit", "--scene", s(&scene), "--image", s(&painting), "--out", s(&dir.path().join("mat"))], MINUTE);
    let r = fit();
    assert!(r.code == 0 && r.stdout.contains("cache miss, stored"), "{}{}", r.stdout, r.stderr);
    let entries: Vec<PathBuf> = std::fs::read_dir(&cache).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(entries.len(), 1, "{entries:?}");
    let entry = &entries[0];
    std::fs::remove_file(entry).unwrap();
    let fifo = std::ffi::CString::new(s(entry)).unwrap();
    // SAFETY: a NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
    let r = fit();
    assert!(r.code == 0 && r.stdout.contains("cache file rebuilt (is a FIFO (named pipe); only regular files are read)"), "{}{}", r.stdout, r.stderr);
    assert!(std::fs::symlink_metadata(entry).unwrap().is_file());
    std::fs::remove_file(entry).unwrap();
    std::os::unix::fs::symlink("/dev/zero", entry).unwrap();
    let r = fit();
    assert!(r.code == 0 && r.stdout.contains("cache file rebuilt (is a device; only regular files are read)"), "{}{}", r.stdout, r.stderr);
    assert!(r.peak_mib < BOMB_PEAK_MIB, "peaked at {} MiB", r.peak_mib);
    assert!(fit().stdout.contains("cache hit"));
}

/// Item 6: a material.json of 64 terms naming one 4096² coefficient texture decoded every
/// texture (12.5 GB) before the renderer's 8-term limit refused it. Counts, resolutions and
/// texture headers are now checked before any pixel is decoded.
#[test]
fn a_material_of_many_terms_is_refused_before_any_texture_is_decoded() {
    let dir = tempfile::tempdir().unwrap();
    let mat = merl_material(dir.path());
    let json_path = mat.join("material.json");
    let original: Value = serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    exr::prelude::write_rgb_file(mat.join("coef.exr"), 4096, 4096, |_, _| (0.5f32, 0.5f32, 0.5f32)).unwrap();
    let mut term = original["terms"][0].clone();
    term["coefficients"] = json!({ "res": 4096, "texture": "coef.exr" });
    let mut many = original.clone();
    many["kind"] = json!("material-map");
    many["terms"] = Value::Array(vec![term.clone(); 64]);
    std::fs::write(&json_path, serde_json::to_string(&many).unwrap()).unwrap();
    let render = |mat: &Path| {
        let out = dir.path().join("r.png");
        run(dir.path(), &["render", s(mat), "--model", "sphere", "--size", "32x32", "--out", s(&out)], MINUTE)
    };
    let r = render(&mat);
    assert_refused_small(&r, &["material.json: material has 64 terms; 1 to 8 are read"]);

    // A texture whose header disagrees with its factor is refused from the header: the
    // pixels after it are cut off, and never read.
    let mut one = original.clone();
    one["terms"][0]["coefficients"] = json!({ "res": 64, "texture": "coef.exr" });
    one["kind"] = json!("material-map");
    std::fs::write(&json_path, serde_json::to_string(&one).unwrap()).unwrap();
    let bytes = std::fs::read(mat.join("coef.exr")).unwrap();
    std::fs::write(mat.join("coef.exr"), &bytes[..bytes.len() / 2]).unwrap();
    assert_refused_small(&render(&mat), &["coef.exr: texture is 4096x4096 but its coefficients need 64x64"]);
}

/// Smaller item: a texture name with a newline gave a two-line error; control characters
/// in names are written as escapes.
#[test]
fn a_name_with_a_newline_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let mat = merl_material(dir.path());
    let json_path = mat.join("material.json");
    let mut json: Value = serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    json["terms"][0]["factors"][0]["texture"] = json!("bad\nname\u{1b}[2J.exr");
    std::fs::write(&json_path, serde_json::to_string(&json).unwrap()).unwrap();
    let r = run(dir.path(), &["render", s(&mat), "--model", "sphere", "--size", "32x32", "--out", s(&dir.path().join("r.png"))], MINUTE);
    assert_one_line_error(&r, &["mat/bad\\nname\\u{1b}[2J.exr: No such file or directory"]);
}

/// A Radiance header of `lines` comment-free attribute lines, then a 4×2 image.
fn radiance_with_header_lines(path: &Path, lines: usize) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    f.write_all(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").unwrap();
    for _ in 0..lines {
        f.write_all(b"a\n").unwrap();
    }
    f.write_all(b"\n-Y 2 +X 4\n").unwrap();
    f.write_all(&[128, 128, 128, 128].repeat(8)).unwrap();
}

/// Item 7: a 64 MiB Radiance file of 32 million header lines took 2.6 GB; the header is
/// bounded. A header of ordinary length still reads.
#[test]
fn a_radiance_header_of_millions_of_lines_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mat = merl_material(dir.path());
    let bomb = dir.path().join("bomb.hdr");
    radiance_with_header_lines(&bomb, 32 << 20);
    let r = run(dir.path(), &["render", s(&mat), "--model", "sphere", "--size", "32x32", "--env", s(&bomb), "--out", s(&dir.path().join("r.png"))], MINUTE);
    assert_refused_small(&r, &["bomb.hdr: Radiance header longer than 64 KiB"]);
    let fine = dir.path().join("fine.hdr");
    radiance_with_header_lines(&fine, 100);
    let env = Environment::load(&fine).unwrap();
    assert_eq!((env.width, env.height), (4, 2));
    assert!(env.pixels.iter().flatten().all(|&v| v == 0.5), "{:?}", env.pixels);
}

/// Smaller item: the common 8192×4096 map was refused by the 4096×4096 decode cap; it is
/// averaged to 4096×2048 as it is read. The left half of this map is 0.5, the right 0.25.
#[test]
fn an_8k_environment_is_read_at_half_size() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("8k.hdr");
    let (w, h) = (8192usize, 4096usize);
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    write!(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").unwrap();
    // New-style RLE: per row a (2, 2, w / 256, w % 256) marker, then each of R, G, B, E as
    // runs of at most 127 (a count byte above 128, then the value).
    let runs = |value: u8, mut n: usize, out: &mut Vec<u8>| {
        while n > 0 {
            let k = n.min(127);
            out.extend_from_slice(&[128 + k as u8, value]);
            n -= k;
        }
    };
    let mut row = vec![2, 2, (w >> 8) as u8, (w & 255) as u8];
    for exponent in [false, false, false, true] {
        // 0.5 is mantissa 128 with exponent 128; 0.25 the same mantissa with exponent 127.
        let (left, right) = if exponent { (128, 127) } else { (128, 128) };
        runs(left, w / 2, &mut row);
        runs(right, w / 2, &mut row);
    }
    for _ in 0..h {
        f.write_all(&row).unwrap();
    }
    drop(f);
    let env = Environment::load(&path).unwrap();
    assert_eq!((env.width, env.height), (4096, 2048));
    assert!(env.pixels.iter().enumerate().all(|(k, p)| *p == [if k % 4096 < 2048 { 0.5 } else { 0.25 }; 3]));
}

/// Smaller item: an environment negative everywhere rendered black without a word; a map
/// mostly negative is refused, while codec ringing (a few negative pixels) reads as 0.
#[test]
fn a_negative_environment_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let negative = dir.path().join("negative.exr");
    exr::prelude::write_rgb_file(&negative, 8, 4, |_, _| (-1.0f32, -1.0f32, -1.0f32)).unwrap();
    let e = Environment::load(&negative).unwrap_err().to_string();
    assert_eq!(e, format!("{}: 100% of the environment's pixels are negative; radiance is never negative (small negative codec ringing is read as 0, a mostly negative map is refused)", negative.display()));
    let ringing = dir.path().join("ringing.exr");
    exr::prelude::write_rgb_file(&ringing, 8, 4, |x, y| if (x, y) == (3, 1) { (-80.0f32, 2.0f32, 2.0f32) } else { (2.0f32, 2.0f32, 2.0f32) }).unwrap();
    let env = Environment::load(&ringing).unwrap();
    assert_eq!(env.pixels[8 + 3], [0.0, 2.0, 2.0]);
}

/// The JSON of a framed sphere scene (one camera node, one light node), buffers inline.
fn sphere_scene(dir: &Path) -> Value {
    let path = dir.join("base.gltf");
    frame(vec![sphere_mesh(16, 8)], &Preset::default(), 1.0).write_gltf(&path).unwrap();
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

fn write_json(path: &Path, json: &Value) -> PathBuf {
    std::fs::write(path, serde_json::to_string(json).unwrap()).unwrap();
    path.to_path_buf()
}

/// Item 8: one mesh instanced by 20,000 nodes took 65 s and 7.5 GB for a 32×32 render. The
/// instanced triangles are counted from the accessors first, and refused over the limit.
#[test]
fn a_mesh_instanced_by_twenty_thousand_nodes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut json = sphere_scene(dir.path());
    let mesh_node = json["nodes"].as_array().unwrap().iter().position(|n| n.get("mesh").is_some()).unwrap();
    let first = json["nodes"].as_array().unwrap().len();
    for k in 0..20_000 {
        json["nodes"].as_array_mut().unwrap().push(json!({ "mesh": 0, "translation": [k as f32 * 0.01, 0.0, 0.0] }));
    }
    let roots = json["scenes"][0]["nodes"].as_array_mut().unwrap();
    roots.extend((first..first + 20_000).map(Value::from));
    let path = write_json(&dir.path().join("instanced.gltf"), &json);
    assert!(json["nodes"][mesh_node]["mesh"] == 0);
    let triangles = sphere_mesh(16, 8).indices.len() / 3 * 20_001;
    let r = run(dir.path(), &["sheet", "--scene", s(&path), "--size", "32x32", "--out", s(&dir.path().join("sheet"))], MINUTE);
    let reason = format!("instanced.gltf: the scene's 20001 mesh nodes instance {triangles} triangles; at most 4194304 are read");
    assert_refused_small(&r, &[&reason]);
}

/// Smaller item: a scene with two cameras or two lights silently used the first; a note on
/// stderr now says which.
#[test]
fn a_second_camera_or_light_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let mut json = sphere_scene(dir.path());
    let nodes = json["nodes"].as_array().unwrap().clone();
    let camera_node = nodes.iter().position(|n| n.get("camera").is_some()).unwrap();
    let light_node = nodes.iter().position(|n| n.pointer("/extensions/KHR_lights_punctual").is_some()).unwrap();
    for k in [camera_node, light_node] {
        json["nodes"].as_array_mut().unwrap().push(nodes[k].clone());
        let last = json["nodes"].as_array().unwrap().len() - 1;
        json["scenes"][0]["nodes"].as_array_mut().unwrap().push(last.into());
    }
    let path = write_json(&dir.path().join("two.gltf"), &json);
    let r = run(dir.path(), &["sheet", "--scene", s(&path), "--size", "32x32", "--out", s(&dir.path().join("sheet"))], MINUTE);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let name = |what: &str, k: usize| format!("{what} 0 at node {k} ('{what}')");
    let expected = [
        format!("note: {} has 2 cameras; {} is used (the first in node order), the others are ignored", path.display(), name("camera", camera_node)),
        format!("note: {} has 2 lights; {} is used (the first in node order), the others are ignored", path.display(), name("light", light_node)),
    ];
    assert_eq!(r.stderr.lines().collect::<Vec<_>>(), expected);
}

/// Smaller item: `--merl` on a FIFO or /dev/zero said "0 bytes (truncated?)"; it names the
/// file type, and nothing is read.
#[test]
fn merl_from_a_fifo_or_a_device_names_the_type() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.binary");
    let c = std::ffi::CString::new(s(&fifo)).unwrap();
    // SAFETY: a NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let out = dir.path().join("mat");
    let r = run(dir.path(), &["fit", "--merl", s(&fifo), "--out", s(&out)], MINUTE);
    assert_one_line_error(&r, &["pipe.binary: is a FIFO (named pipe); only regular files are read"]);
    let r = run(dir.path(), &["fit", "--merl", "/dev/zero", "--out", s(&out)], MINUTE);
    assert_one_line_error(&r, &["/dev/zero: is a device; only regular files are read"]);
    assert!(!out.exists());
}

/// Smaller item: `--lambda -1` and `--erode -1` failed as "unexpected argument"; they are
/// read as numbers and refused by value.
#[test]
fn negative_lambda_and_erode_are_refused_by_value() {
    let dir = tempfile::tempdir().unwrap();
    let base = ["fit", "--merl", "x.binary", "--out", "m"];
    let r = run(dir.path(), &[&base[..], &["--lambda", "-1"]].concat(), MINUTE);
    assert_one_line_error(&r, &["--lambda -1: the smoothing weight is a finite number, 0 or more"]);
    let r = run(dir.path(), &[&base[..], &["--erode", "-1"]].concat(), MINUTE);
    assert_one_line_error(&r, &["--erode -1: give 0 to 64 pixels"]);
    let r = run(dir.path(), &[&base[..], &["--erode", "65"]].concat(), MINUTE);
    assert_one_line_error(&r, &["--erode 65: give 0 to 64 pixels"]);
}

/// Smaller item: integers written as floats (`"mesh": 0.0`, `"count": 3.0`) failed to
/// parse; the scene loads as the one written with integers.
#[test]
fn integers_written_as_floats_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let json = sphere_scene(dir.path());
    fn floats(v: &mut Value) {
        match v {
            Value::Number(n) if n.is_u64() => *v = json!(n.as_u64().unwrap() as f64),
            Value::Array(a) => a.iter_mut().for_each(floats),
            Value::Object(o) => o.values_mut().for_each(floats),
            _ => {}
        }
    }
    let mut loose = json.clone();
    floats(&mut loose);
    let text = serde_json::to_string(&loose).unwrap();
    assert!(text.contains("\"mesh\":0.0") && text.contains("\"componentType\":5126.0"), "{text}");
    let a = Scene::load(write_json(&dir.path().join("ints.gltf"), &json)).unwrap();
    let b = Scene::load(write_json(&dir.path().join("floats.gltf"), &loose)).unwrap();
    assert_eq!(a.meshes[0].positions, b.meshes[0].positions);
    assert_eq!(a.meshes[0].indices, b.meshes[0].indices);
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.light, b.light);
}

/// Bytes of `values` little endian, padded to 4 bytes per element.
fn packed<T: Copy, const N: usize>(values: &[[T; N]], to_le: impl Fn(T) -> Vec<u8>) -> Vec<u8> {
    let mut out = Vec::new();
    for v in values {
        let mut e: Vec<u8> = v.iter().flat_map(|&c| to_le(c)).collect();
        e.resize(e.len().div_ceil(4) * 4, 0);
        out.extend(e);
    }
    out
}

/// Smaller item: KHR_mesh_quantization meshes (gltfpack's output: 16-bit positions scaled
/// by their node, 8-bit normalized normals, 16-bit normalized texture coordinates) were
/// refused; they load as the float mesh they quantize, within the quantization step.
#[test]
fn quantized_meshes_load_as_their_float_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = sphere_mesh(16, 8);
    let uvs = mesh.uvs.clone().unwrap();
    let step = mesh.positions.iter().map(|p| p.abs().max_element()).fold(0.0f32, f32::max) / 32767.0;
    let positions: Vec<[i16; 3]> = mesh.positions.iter().map(|p| p.to_array().map(|c| (c / step).round() as i16)).collect();
    let normals: Vec<[i8; 3]> = mesh.normals.iter().map(|n| n.to_array().map(|c| (c * 127.0).round() as i8)).collect();
    let texcoords: Vec<[u16; 2]> = uvs.iter().map(|t| t.to_array().map(|c| (c * 65535.0).round() as u16)).collect();
    let indices: Vec<u8> = mesh.indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect();
    let parts = [
        packed(&positions, |c: i16| c.to_le_bytes().to_vec()),
        packed(&normals, |c: i8| c.to_le_bytes().to_vec()),
        packed(&texcoords, |c: u16| c.to_le_bytes().to_vec()),
        indices,
    ];
    let (mut bin, mut views) = (Vec::new(), Vec::new());
    for (part, stride) in parts.iter().zip([Some(8), Some(4), Some(4), None]) {
        let mut view = json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": part.len() });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        views.push(view);
        bin.extend_from_slice(part);
        bin.resize(bin.len().div_ceil(4) * 4, 0);
    }
    let n = positions.len();
    let (lo, hi) = (positions.iter().fold([i16::MAX; 3], |a, p| [0, 1, 2].map(|k| a[k].min(p[k]))), positions.iter().fold([i16::MIN; 3], |a, p| [0, 1, 2].map(|k| a[k].max(p[k]))));
    let doc = json!({
        "asset": { "version": "2.0", "generator": "gltfpack-like" },
        "extensionsUsed": ["KHR_mesh_quantization"], "extensionsRequired": ["KHR_mesh_quantization"],
        "buffers": [{ "byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bin)) }],
        "bufferViews": views,
        "accessors": [
            { "bufferView": 0, "componentType": 5122, "count": n, "type": "VEC3", "min": lo, "max": hi },
            { "bufferView": 1, "componentType": 5120, "normalized": true, "count": n, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5123, "normalized": true, "count": n, "type": "VEC2" },
            { "bufferView": 3, "componentType": 5123, "count": mesh.indices.len(), "type": "SCALAR" },
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2 }, "indices": 3 }] }],
        "nodes": [{ "mesh": 0, "scale": [step, step, step] }],
        "scenes": [{ "nodes": [0] }], "scene": 0,
    });
    let path = write_json(&dir.path().join("quantized.gltf"), &doc);
    let loaded = Scene::load_model(&path).unwrap();
    assert_eq!(loaded.len(), 1);
    let q = &loaded[0];
    assert_eq!(q.indices, mesh.indices);
    let worst = |a: &[glam::Vec3], b: &[glam::Vec3]| a.iter().zip(b).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0f32, f32::max);
    // Rounding moves a position by half a step, a normal by half of 1/127 per component
    // before it is normalized again.
    assert!(worst(&q.positions, &mesh.positions) <= 0.5 * step * 1.001, "{} vs step {step}", worst(&q.positions, &mesh.positions));
    assert!(worst(&q.normals, &mesh.normals) < 1.0 / 127.0, "{}", worst(&q.normals, &mesh.normals));
    let uv_error = q.uvs.as_ref().unwrap().iter().zip(&uvs).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0f32, f32::max);
    assert!(uv_error <= 0.5 / 65535.0 * 1.001, "{uv_error}");
}
