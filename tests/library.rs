//! A MatCap library in one command (`fit --lit-sphere DIR/ … --out LIB`, issue 38 item 3):
//! every picture gets the folder a single `fit --lit-sphere` writes, a bad picture one line
//! and the rest go on, names stay distinct, a rerun keeps the user's files, and the gallery
//! and index show what was fitted.

mod cli_common;

use std::path::{Path, PathBuf};

use brdfpaint::images::{encode_srgb8, Painting};
use brdfpaint::library::gallery::{BAND, BACKGROUND, CELL, CELLS};
use brdfpaint::material::Material;
use cli_common::{brdfpaint, Run};

const MATCAPS: &str = "../shared/data/matcaps/blender_cc0/exr";

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A bundled MatCap box-filtered to `side` pixels (512 is a multiple of both sides used).
fn small_matcap(name: &str, side: usize) -> Painting {
    let p = Painting::read(&Path::new(MATCAPS).join(format!("{name}.exr"))).unwrap();
    assert_eq!(p.width % side, 0);
    brdfpaint::litsphere::shrink(&p, side).0
}

fn write_png(p: &Painting, path: &Path) {
    std::fs::write(path, p.encode_png16().unwrap()).unwrap();
}

/// The folder of the first tests: two PNGs (64 and 128 px), an EXR, a corrupt PNG, a text file.
fn picture_folder(root: &Path) -> PathBuf {
    let dir = root.join("matcaps");
    std::fs::create_dir(&dir).unwrap();
    write_png(&small_matcap("clay_studio", 64), &dir.join("clay.png"));
    write_png(&small_matcap("jade", 128), &dir.join("jade.png"));
    std::fs::write(dir.join("toon.exr"), small_matcap("toon", 64).encode_exr().unwrap()).unwrap();
    std::fs::write(dir.join("broken.png"), b"\x89PNG\r\n\x1a\nthis is not a picture").unwrap();
    std::fs::write(dir.join("notes.txt"), "my matcaps").unwrap();
    dir
}

fn library_of(root: &Path, args: &[&str], lib: &Path) -> Run {
    let mut all = vec!["fit", "--lit-sphere"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", s(lib)]);
    brdfpaint(&root.join("cache"), &all)
}

#[test]
fn a_folder_gives_a_material_each_and_one_line_for_the_bad_picture() {
    let root = tempfile::tempdir().unwrap();
    let dir = picture_folder(root.path());
    let lib = root.path().join("lib");
    let run = library_of(root.path(), &[s(&dir)], &lib);
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("4 pictures (1 other entry ignored)"), "{}", run.stdout);
    let failures: Vec<&str> = run.stderr.lines().filter(|l| l.contains("broken.png")).collect();
    assert_eq!(failures.len(), 1, "{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    for name in ["clay", "jade", "toon"] {
        assert!(lib.join(name).join("material.json").is_file(), "{name}");
    }
    assert!(!lib.join("broken").exists());
    assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "my matcaps");
    assert!(!lib.join("notes").exists() && !lib.join("notes.txt").exists());
    let manifest = brdfpaint::library::Manifest::read(&lib).unwrap();
    let names: Vec<&str> = manifest.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["clay", "jade", "toon"]);
    assert!(brdfpaint::commit::temporaries(root.path()).is_empty());
}

/// The largest difference of two materials' tables, relative to the larger value.
fn table_difference(a: &Material, b: &Material) -> f64 {
    assert_eq!(a.terms.len(), b.terms.len());
    let mut worst = 0.0f64;
    for (ta, tb) in a.terms.iter().zip(&b.terms) {
        assert_eq!(ta.factors.len(), tb.factors.len());
        for (fa, fb) in ta.factors.iter().zip(&tb.factors) {
            assert_eq!(fa.spec, fb.spec);
            // Relative to the table's largest value: a node near zero has no relative scale.
            let scale = fa.texels.iter().flatten().fold(1e-12f32, |m, x| m.max(x.abs()));
            for (x, y) in fa.texels.iter().zip(&fb.texels) {
                for c in 0..3 {
                    worst = worst.max(((x[c] - y[c]).abs() / scale) as f64);
                }
            }
        }
    }
    worst
}

/// The names under a folder (the ownership record's content differs by hash, not by name).
fn file_names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// The library of [`picture_folder`] without its corrupt picture: the root, folder, library.
fn good_library() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let root = tempfile::tempdir().unwrap();
    let dir = picture_folder(root.path());
    std::fs::remove_file(dir.join("broken.png")).unwrap();
    let lib = root.path().join("lib");
    let run = library_of(root.path(), &[s(&dir)], &lib);
    assert_eq!(run.code, 0, "{}", run.stderr);
    (root, dir, lib)
}

#[test]
fn each_material_is_what_a_single_fit_of_its_picture_writes() {
    let (root, dir, lib) = good_library();
    for (name, file) in [("clay", "clay.png"), ("jade", "jade.png"), ("toon", "toon.exr")] {
        let single = root.path().join(format!("single-{name}"));
        let one = library_of(root.path(), &[s(&dir.join(file))], &single);
        assert_eq!(one.code, 0, "{}", one.stderr);
        assert_eq!(file_names(&lib.join(name)), file_names(&single), "{name}");
        let (a, b) = (Material::load(&lib.join(name)).unwrap(), Material::load(&single).unwrap());
        let d = table_difference(&a, &b);
        assert!(d < 1e-3, "{name}: tables differ by {d}");
        assert_eq!(a.terms[0].base, b.terms[0].base, "{name}");
        let (ea, eb) = (a.provenance.errors.unwrap(), b.provenance.errors.unwrap());
        assert!((ea.rms_relative - eb.rms_relative).abs() < 1e-6, "{name}: {ea:?} vs {eb:?}");
    }
}

/// 8-bit sRGB pixels of a PNG.
fn png_pixels(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let img = image::open(path).unwrap().to_rgb8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    (w, h, img.pixels().map(|p| p.0).collect())
}

#[test]
fn the_gallery_has_a_row_per_picture_showing_that_picture() {
    let (_root, _, lib) = good_library();
    let (w, h, px) = png_pixels(&lib.join("gallery.png"));
    assert_eq!((w, h), (CELLS * CELL, 3 * (BAND + CELL)));
    // The picture cell, by hand: a 64 px picture is each pixel doubled; a 128 px one is itself.
    let pictures = [small_matcap("clay_studio", 64), small_matcap("jade", 128), small_matcap("toon", 64)];
    for (row, p) in pictures.iter().enumerate() {
        let f = CELL / p.width;
        let (mut worst, mut sum) = (0i32, 0i64);
        for j in 0..CELL {
            for i in 0..CELL {
                let want = p.pixels[(j / f) * p.width + i / f].map(encode_srgb8);
                let got = px[(row * (BAND + CELL) + BAND + j) * w + i];
                for c in 0..3 {
                    let d = (want[c] as i32 - got[c] as i32).abs();
                    worst = worst.max(d);
                    sum += d as i64;
                }
            }
        }
        // 16-bit PNG in, 8-bit out: a code apart at most.
        assert!(worst <= 1, "row {row}: worst {worst}, mean {}", sum as f64 / (3 * CELL * CELL) as f64);
    }
    // The renders show an object on the background: some pixels are not the background.
    let bg = BACKGROUND.map(encode_srgb8);
    for row in 0..3 {
        for cell in 1..3 {
            let y0 = row * (BAND + CELL) + BAND;
            let lit = (0..CELL * CELL).filter(|k| px[(y0 + k / CELL) * w + cell * CELL + k % CELL] != bg).count();
            assert!(lit > CELL * CELL / 10, "row {row} cell {cell}: {lit} pixels of the bunny");
        }
    }
}

/// The targets of `href="…"` and `src="…"` in `html`, percent-decoded.
fn links(html: &str) -> Vec<String> {
    let mut out = Vec::new();
    for attr in ["href=\"", "src=\""] {
        for part in html.split(attr).skip(1) {
            let raw = part.split('"').next().unwrap();
            let bytes = raw.as_bytes();
            let mut decoded = Vec::new();
            let mut k = 0;
            while k < bytes.len() {
                if bytes[k] == b'%' {
                    decoded.push(u8::from_str_radix(&raw[k + 1..k + 3], 16).unwrap());
                    k += 3;
                } else {
                    decoded.push(bytes[k]);
                    k += 1;
                }
            }
            out.push(String::from_utf8(decoded).unwrap());
        }
    }
    out
}

#[test]
fn the_index_links_to_files_that_exist_and_names_every_material() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("pics");
    std::fs::create_dir(&dir).unwrap();
    // A name a URL must encode.
    write_png(&small_matcap("skin", 64), &dir.join("my skin #1.png"));
    write_png(&small_matcap("pearl", 64), &dir.join("pearl.png"));
    let lib = root.path().join("lib");
    let run = library_of(root.path(), &[s(&dir)], &lib);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let html = std::fs::read_to_string(lib.join("index.html")).unwrap();
    assert!(html.contains("<h2>my skin #1</h2>") && html.contains("<h2>pearl</h2>"));
    assert!(!html.contains("http://") && !html.contains("https://"), "no external resources");
    let links = links(&html);
    assert!(links.len() > 2 * 5, "{links:?}");
    for link in &links {
        assert!(!link.starts_with('/') && !link.contains(".."), "{link}");
        let path = lib.join(link);
        assert!(if link.ends_with('/') { path.is_dir() } else { path.is_file() }, "{link} does not resolve");
    }
    assert!(links.iter().any(|l| l == "rows/my skin #1.png") && links.iter().any(|l| l == "my skin #1/material.json"), "{links:?}");
}

#[test]
fn a_png_and_a_jpeg_of_one_name_get_two_folders_and_a_rerun_keeps_the_users_files() {
    let root = tempfile::tempdir().unwrap();
    let (png, jpg) = (root.path().join("a.png"), root.path().join("a.jpg"));
    write_png(&small_matcap("clay_brown", 64), &png);
    let p = small_matcap("metal_lead", 64);
    let bytes: Vec<u8> = p.pixels.iter().flat_map(|c| c.map(encode_srgb8)).collect();
    image::RgbImage::from_raw(64, 64, bytes).unwrap().save(&jpg).unwrap();
    let lib = root.path().join("lib");
    let run = library_of(root.path(), &[s(&png), s(&jpg)], &lib);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(lib.join("a-png/material.json").is_file() && lib.join("a-jpg/material.json").is_file());
    assert!(!lib.join("a").exists());
    std::fs::write(lib.join("mine.txt"), "the user's").unwrap();
    std::fs::write(lib.join("a-png/notes.txt"), "also the user's").unwrap();
    let inode = |p: &Path| std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(p).unwrap());
    let before = inode(&lib.join("a-jpg/material.json"));
    let again = library_of(root.path(), &[s(&png), s(&jpg)], &lib);
    assert_eq!(again.code, 0, "{}", again.stderr);
    assert_eq!(std::fs::read_to_string(lib.join("mine.txt")).unwrap(), "the user's");
    assert_eq!(std::fs::read_to_string(lib.join("a-png/notes.txt")).unwrap(), "also the user's");
    assert_ne!(inode(&lib.join("a-jpg/material.json")), before, "the rerun wrote the material anew");
    assert!(brdfpaint::commit::temporaries(root.path()).is_empty());
    // A folder that is not a library is refused before any work, and left as it was.
    let theirs = root.path().join("theirs");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::write(theirs.join("x.txt"), "x").unwrap();
    let refused = library_of(root.path(), &[s(&png), s(&jpg)], &theirs);
    assert_eq!(refused.code, 1);
    assert_eq!(refused.stderr.trim().lines().count(), 1, "{}", refused.stderr);
    assert_eq!(file_names(&theirs), ["x.txt"]);
}
