//! Seeded fuzzing of every input loader (issue 13): valid PNG, JPEG, EXR, .gltf, .glb, MERL,
//! material.json and material texture files are mutated (bit flips, truncations, byte
//! insertions, header field changes, number changes in text) and read through the library's
//! loaders. Every case must end in a value or a one-line error: no panic, no hang (a watchdog
//! aborts a case that runs over [`CASE_LIMIT`]), and nothing written beside the input.
//!
//! The counts are fixed and the seeds too, so a failure names a case that reproduces.

use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

use brdfpaint::brdf::{Analytic, Merl, SphereView};
use brdfpaint::factor::{prepare, Mapping, Settings};
use brdfpaint::images::{Painting, Rgb};
use brdfpaint::material::{Material, Provenance};
use brdfpaint::scene::{frame, sphere_mesh, Preset, Scene};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A case that takes longer than this is a hang.
const CASE_LIMIT: Duration = Duration::from_secs(30);

thread_local! {
    /// Inside a loader call of a fuzz case.
    static IN_CASE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Panics inside a case are collected by the tests, not printed once per case; any other
/// panic (a failed assertion) is printed as usual.
fn quiet_panics() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !IN_CASE.with(|c| c.get()) {
                default(info);
            }
        }));
    });
}

/// Runs one case's loader with its panics caught (and not printed).
fn guarded<T>(f: impl FnOnce() -> T) -> std::thread::Result<T> {
    IN_CASE.with(|c| c.set(true));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    IN_CASE.with(|c| c.set(false));
    r
}

/// One mutation of `seed`'s bytes, chosen by `rng`. Text formats also get their numbers
/// changed (a count, an index, a size) to values a loader must check.
fn mutate(seed: &[u8], rng: &mut ChaCha8Rng, text: bool) -> Vec<u8> {
    let mut b = seed.to_vec();
    let kinds = if text { 5 } else { 4 };
    match rng.random_range(0..kinds) {
        // Bit flips.
        0 => {
            for _ in 0..rng.random_range(1..=8) {
                let i = rng.random_range(0..b.len());
                b[i] ^= 1 << rng.random_range(0..8);
            }
        }
        // Truncation.
        1 => b.truncate(rng.random_range(0..b.len())),
        // Inserted bytes.
        2 => {
            let at = rng.random_range(0..=b.len());
            let n = rng.random_range(1..=16);
            let bytes: Vec<u8> = (0..n).map(|_| rng.random()).collect();
            b.splice(at..at, bytes);
        }
        // A header field: a run of bytes near the start set to 0x00, 0xFF or random.
        3 => {
            let end = b.len().min(128);
            let at = rng.random_range(0..end);
            let n = rng.random_range(1..=8).min(b.len() - at);
            let fill: u8 = match rng.random_range(0..3) {
                0 => 0,
                1 => 0xFF,
                _ => rng.random(),
            };
            b[at..at + n].iter_mut().for_each(|x| *x = fill);
        }
        // A number in the text replaced.
        _ => {
            let digits: Vec<usize> = (0..b.len()).filter(|&i| b[i].is_ascii_digit()).collect();
            if let Some(&at) = digits.get(rng.random_range(0..digits.len().max(1))) {
                let end = (at..b.len()).find(|&i| !b[i].is_ascii_digit()).unwrap_or(b.len());
                let with: &[u8] = match rng.random_range(0..6) {
                    0 => b"4294967296",
                    1 => b"-1",
                    2 => b"999999999999",
                    3 => b"1e308",
                    4 => b"0",
                    _ => b"7",
                };
                b.splice(at..end, with.iter().copied());
            }
        }
    }
    b
}

/// What one family of cases found.
#[derive(Default)]
struct Tally {
    cases: usize,
    errors: usize,
    panics: Vec<String>,
}

/// Runs `cases` mutations of `seed`: each is written to `name` in a fresh directory and read
/// by `load`. Asserts no panic, no hang, one-line errors, nothing else left in the directory.
fn fuzz(family: &str, seed: &[u8], name: &str, text: bool, cases: usize, rng_seed: u64, load: impl Fn(&Path) -> Result<(), String>) {
    quiet_panics();
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    // Watchdog: a case that does not finish in time aborts the run, naming it.
    let progress = Arc::new(AtomicU64::new(0));
    let current = Arc::new(Mutex::new(String::new()));
    let done = Arc::new(AtomicU64::new(0));
    let watchdog = {
        let (progress, current, done) = (progress.clone(), current.clone(), done.clone());
        std::thread::spawn(move || {
            let mut last = (u64::MAX, Instant::now());
            while done.load(Ordering::Relaxed) == 0 {
                let p = progress.load(Ordering::Relaxed);
                if p != last.0 {
                    last = (p, Instant::now());
                } else if last.1.elapsed() > CASE_LIMIT {
                    eprintln!("fuzz: {} hung for {CASE_LIMIT:?}", current.lock().unwrap());
                    std::process::abort();
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        })
    };
    let mut tally = Tally::default();
    let start = Instant::now();
    for case in 0..cases {
        let bytes = mutate(seed, &mut rng, text);
        *current.lock().unwrap() = format!("{family} case {case} (seed {rng_seed})");
        progress.fetch_add(1, Ordering::Relaxed);
        std::fs::write(&path, &bytes).unwrap();
        match guarded(|| load(&path)) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                assert!(!e.contains('\n'), "{family} case {case}: a multi-line error: {e}");
                tally.errors += 1;
            }
            Err(p) => {
                let msg = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                tally.panics.push(format!("case {case}: {msg}"));
            }
        }
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 1, "{family} case {case} left files beside its input: {left:?}");
        tally.cases += 1;
    }
    done.store(1, Ordering::Relaxed);
    watchdog.join().unwrap();
    eprintln!(
        "fuzz {family}: {} cases in {:.1} s, {} refused with one line, {} panics",
        tally.cases,
        start.elapsed().as_secs_f64(),
        tally.errors,
        tally.panics.len()
    );
    assert!(tally.panics.is_empty(), "{family}: {} panics, first: {:?}", tally.panics.len(), &tally.panics[..tally.panics.len().min(5)]);
}

fn painting_seed() -> Painting {
    let (w, h) = (12, 9);
    let pixels = (0..w * h).map(|k| [k as f32 / (w * h) as f32, 0.5, 0.25]).collect();
    let mut p = Painting::opaque(w, h, pixels).unwrap();
    p.alpha[3] = 0.0;
    p
}

fn read_painting(path: &Path) -> Result<(), String> {
    Painting::read(path).map(|_| ()).map_err(|e| e.to_string())
}

#[test]
fn png_paintings() {
    let png16 = painting_seed().encode_png16().unwrap();
    fuzz("PNG 16-bit", &png16, "p.png", false, 1000, 1, read_painting);
    let img = image::RgbaImage::from_fn(16, 12, |x, y| image::Rgba([x as u8 * 9, y as u8 * 13, 77, 255]));
    let mut png8 = Cursor::new(Vec::new());
    img.write_to(&mut png8, image::ImageFormat::Png).unwrap();
    fuzz("PNG 8-bit", png8.get_ref(), "p.png", false, 1000, 2, read_painting);
}

#[test]
fn jpeg_paintings() {
    let img = image::RgbImage::from_fn(24, 16, |x, y| image::Rgb([x as u8 * 9, y as u8 * 13, 77]));
    let mut jpeg = Cursor::new(Vec::new());
    img.write_to(&mut jpeg, image::ImageFormat::Jpeg).unwrap();
    fuzz("JPEG", jpeg.get_ref(), "p.jpg", false, 1500, 3, read_painting);
}

#[test]
fn exr_paintings_and_textures() {
    let exr = painting_seed().encode_exr().unwrap();
    fuzz("EXR painting", &exr, "p.exr", false, 1000, 4, read_painting);
    fuzz("EXR texture", &exr, "t.exr", false, 500, 5, |p| Rgb::read_exr(p).map(|_| ()).map_err(|e| e.to_string()));
}

/// A small scene as .gltf (buffer inline as a data: URI) and the same as .glb.
fn scene_seeds() -> (Vec<u8>, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.gltf");
    frame(vec![sphere_mesh(8, 4)], &Preset::default(), 1.0).write_gltf(&path).unwrap();
    let gltf = std::fs::read(&path).unwrap();
    // The .glb: the JSON without the buffer's uri, and the buffer as the BIN chunk.
    let mut json: serde_json::Value = serde_json::from_slice(&gltf).unwrap();
    let uri = json["buffers"][0]["uri"].as_str().unwrap().to_string();
    let mut bin = base64::decode(uri.split_once(',').unwrap().1).unwrap();
    json["buffers"][0].as_object_mut().unwrap().remove("uri");
    let mut text = serde_json::to_vec(&json).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let mut glb = Vec::new();
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend_from_slice(&(text.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&text);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    (gltf, glb)
}

fn load_scene(path: &Path) -> Result<(), String> {
    // Both readers: the scene (camera and light required) and the model (meshes only).
    let scene = Scene::load(path).map(|_| ()).map_err(|e| e.to_string());
    let model = Scene::load_model(path).map(|_| ()).map_err(|e| e.to_string());
    scene.and(model)
}

#[test]
fn gltf_scenes() {
    let (gltf, glb) = scene_seeds();
    // The seeds themselves load.
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [("s.gltf", &gltf), ("s.glb", &glb)] {
        std::fs::write(dir.path().join(name), bytes).unwrap();
        load_scene(&dir.path().join(name)).unwrap();
    }
    fuzz(".gltf", &gltf, "s.gltf", true, 1500, 6, load_scene);
    fuzz(".glb", &glb, "s.glb", false, 1500, 7, load_scene);
}

#[test]
fn merl_files() {
    let merl = Merl::from_brdf(|_, _| [0.25, 0.5, 0.75]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.binary");
    merl.write(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    // Each case writes and reads 34 MB: fewer cases, the mutations all the same kinds.
    fuzz("MERL", &bytes, "m.binary", false, 60, 8, |p| Merl::read(p).map(|_| ()).map_err(|e| e.to_string()));
}

/// A saved material: its material.json is mutated as text, its first texture as bytes.
#[test]
fn material_files() {
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 30).pattern();
    let values = pattern.shade(|q| brdfpaint::brdf::Reflectance::shading(&Analytic::suite()[2], q));
    let settings = Settings::default();
    let fit = prepare(&pattern, &settings).unwrap().solve(&values, Mapping::Auto).unwrap();
    let material = Material::from_fit(&settings, &fit, Provenance::default()).unwrap();
    let root = tempfile::tempdir().unwrap();
    let saved = root.path().join("mat");
    material.save(&saved).unwrap();
    let json = std::fs::read(saved.join("material.json")).unwrap();
    let textures: Vec<PathBuf> = std::fs::read_dir(&saved)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "exr"))
        .collect();
    // A material reads its textures only from its own directory: the fuzzed json's
    // directory gets copies of them, once.
    let copy_textures = |dir: &Path| {
        for t in &textures {
            std::fs::copy(t, dir.join(t.file_name().unwrap())).unwrap();
        }
    };
    let load = |p: &Path| Material::load(p).map(|_| ()).map_err(|e| e.to_string());
    fuzz_with_files("material.json", &json, "material.json", true, 1000, 9, &copy_textures, load);
    let texture = std::fs::read(&textures[0]).unwrap();
    let texture_name = textures[0].file_name().unwrap().to_str().unwrap().to_string();
    let copy_json_and_others = |dir: &Path| {
        std::fs::write(dir.join("material.json"), &json).unwrap();
        for t in textures.iter().skip(1) {
            std::fs::copy(t, dir.join(t.file_name().unwrap())).unwrap();
        }
    };
    fuzz_with_files("material texture", &texture, &texture_name, false, 500, 10, &copy_json_and_others, |p| {
        Material::load(&p.with_file_name("material.json")).map(|_| ()).map_err(|e| e.to_string())
    });
}

/// [`fuzz`] where the input sits in a directory with other files (`setup` puts them there
/// once); the directory must hold exactly those files after every case.
#[allow(clippy::too_many_arguments)]
fn fuzz_with_files(
    family: &str,
    seed: &[u8],
    name: &str,
    text: bool,
    cases: usize,
    rng_seed: u64,
    setup: &dyn Fn(&Path),
    load: impl Fn(&Path) -> Result<(), String>,
) {
    quiet_panics();
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let path = dir.path().join(name);
    std::fs::write(&path, seed).unwrap();
    load(&path).unwrap_or_else(|e| panic!("{family}: the seed itself fails: {e}"));
    let mut before: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    before.sort();
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let (mut errors, mut panics) = (0, Vec::new());
    let start = Instant::now();
    for case in 0..cases {
        let bytes = mutate(seed, &mut rng, text);
        std::fs::write(&path, &bytes).unwrap();
        let t = Instant::now();
        match guarded(|| load(&path)) {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                assert!(!e.contains('\n'), "{family} case {case}: a multi-line error: {e}");
                errors += 1;
            }
            Err(_) => panics.push(case),
        }
        assert!(t.elapsed() < CASE_LIMIT, "{family} case {case} took {:?}", t.elapsed());
        let mut after: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        after.sort();
        assert_eq!(after, before, "{family} case {case} changed the directory");
    }
    eprintln!(
        "fuzz {family}: {cases} cases in {:.1} s, {errors} refused with one line, {} panics",
        start.elapsed().as_secs_f64(),
        panics.len()
    );
    assert!(panics.is_empty(), "{family}: panics in cases {panics:?}");
}
