//! The 100 MatCaps of the library benchmark (BENCHMARKS.md, "A MatCap library"): the 23
//! Blender MatCaps, and copies of them mirrored, flipped, resized and hue-shifted (the
//! channels rotated), as PNG, JPEG and EXR, written into a folder.
//!
//! ```text
//! cargo run --release --example matcap_set -- /tmp/matcaps100
//! ```

use std::path::Path;

use brdfpaint::images::{encode_srgb8, Painting};
use brdfpaint::library::gallery::area_resample;

const MATCAPS: &str = "../shared/data/matcaps/blender_cc0/exr";
const COUNT: usize = 100;

/// How copy `v` of a MatCap differs: side, mirrored, upside down, channel rotation, format.
const VARIANTS: [(usize, bool, bool, usize, &str); 5] =
    [(512, false, false, 0, "exr"), (512, true, false, 0, "png"), (384, false, false, 1, "png"), (256, true, true, 2, "jpg"), (320, false, true, 1, "png")];

fn main() {
    let out = std::env::args().nth(1).expect("give the folder to write");
    std::fs::create_dir_all(&out).unwrap();
    let mut names: Vec<_> = std::fs::read_dir(MATCAPS).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "exr")).collect();
    names.sort();
    for k in 0..COUNT {
        let (source, v) = (&names[k % names.len()], k / names.len());
        let p = Painting::read(source).unwrap();
        let stem = source.file_stem().unwrap().to_string_lossy();
        let path = Path::new(&out).join(format!("{stem}-{v}.{}", VARIANTS[v].4));
        write(&variant(&p, v), &path);
    }
    println!("wrote {COUNT} MatCaps into {out}");
}

fn variant(p: &Painting, v: usize) -> Painting {
    let (side, mirror, flip, rotate, _) = VARIANTS[v];
    let mut pixels = p.pixels.clone();
    for j in 0..p.height {
        for i in 0..p.width {
            let (si, sj) = (if mirror { p.width - 1 - i } else { i }, if flip { p.height - 1 - j } else { j });
            let c = p.pixels[sj * p.width + si];
            pixels[j * p.width + i] = [c[rotate % 3], c[(rotate + 1) % 3], c[(rotate + 2) % 3]];
        }
    }
    Painting::opaque(side, side, area_resample(&pixels, p.width, p.height, side, side)).unwrap()
}

fn write(p: &Painting, path: &Path) {
    match path.extension().and_then(|e| e.to_str()) {
        Some("exr") => std::fs::write(path, p.encode_exr().unwrap()).unwrap(),
        Some("png") => std::fs::write(path, p.encode_png16().unwrap()).unwrap(),
        _ => {
            let bytes: Vec<u8> = p.pixels.iter().flat_map(|c| c.map(encode_srgb8)).collect();
            image::RgbImage::from_raw(p.width as u32, p.height as u32, bytes).unwrap().save(path).unwrap();
        }
    }
}
