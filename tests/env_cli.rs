//! `brdfpaint render --env`: environment files (OpenEXR and Radiance .hdr), bad input as
//! one line with nothing written, usage errors, exposure and tone mapping.

mod cli_common;
mod gl_common;

use std::path::{Path, PathBuf};

use brdfpaint::factor::{Domain, Input, LogMap, Param};
use brdfpaint::images::env::Environment;
use brdfpaint::images::tone::Tonemap;
use brdfpaint::images::{encode_srgb8, Rgb};
use brdfpaint::material::{Factor, Term};
use gl_common::{smooth_factor, spec, uniform};

/// `brdfpaint` as a user runs it (`cli_common`), with a prepare cache of its own.
fn brdfpaint(args: &[&str]) -> (i32, String, String) {
    let cache = tempfile::tempdir().expect("a cache directory");
    let run = cli_common::brdfpaint(cache.path(), args);
    (run.code, run.stdout, run.stderr)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hdri").join(name)
}

/// Every file name in `dir`, hidden ones (temporaries) included, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// A two-factor material saved in `dir/mat`.
fn material(dir: &Path) -> PathBuf {
    let light = Factor {
        spec: spec(Input::Light, Param::Radius, Domain::Hemisphere, 16),
        texels: (0..16)
            .map(|i| {
                let t = i as f32 / 15.0;
                [0.25 * (1.0 - t * t) / (1.0 + t * t); 3]
            })
            .collect(),
    };
    let half = smooth_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 16));
    let m = uniform(Term { base: None, factors: vec![light, half], map: LogMap::Identity { floor: [1e-3; 3] }, coefficients: None });
    let path = dir.join("mat");
    m.save(&path).unwrap();
    path
}

fn render_args<'a>(mat: &'a Path, env: &'a Path, out: &'a Path) -> Vec<&'a str> {
    vec!["render", s(mat), "--model", "sphere", "--size", "24x24", "--env", s(env), "--out", s(out)]
}

/// Fails with exit code `code`, one line on stderr containing `needle`, nothing in `watch`
/// changed.
fn fails(args: &[&str], code: i32, needle: &str, watch: &Path) {
    let before = listing(watch);
    let (got, stdout, stderr) = brdfpaint(args);
    assert_eq!(got, code, "{args:?}: {stderr}");
    assert!(stdout.is_empty(), "{args:?}: {stdout}");
    assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains(needle), "{args:?}: expected '{needle}' in {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(listing(watch), before, "{args:?} wrote something");
}

/// A flat (uncompressed) Radiance RGBE file of `pixels`, and the values a reader must get
/// back from it: $c \cdot 2^{e - 136}$ per channel.
fn radiance_hdr(width: usize, height: usize, pixels: &[[f32; 3]]) -> (Vec<u8>, Vec<[f32; 3]>) {
    let mut bytes = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n").into_bytes();
    let mut decoded = Vec::new();
    for p in pixels {
        let m = p[0].max(p[1]).max(p[2]);
        if m < 1e-30 {
            bytes.extend([0, 0, 0, 0]);
            decoded.push([0.0; 3]);
            continue;
        }
        // frexp: m = f 2^e with f in [0.5, 1).
        let e = m.log2().floor() as i32 + 1;
        let scale = 256.0 / 2f32.powi(e);
        let c = p.map(|x| (x * scale) as u8);
        bytes.extend([c[0], c[1], c[2], (e + 128) as u8]);
        decoded.push(c.map(|x| x as f32 * 2f32.powi(e - 8)));
    }
    (bytes, decoded)
}

#[test]
fn radiance_hdr_reads_like_the_same_values_in_exr_and_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (16, 8);
    let pixels: Vec<[f32; 3]> = (0..w * h).map(|k| [0.1 + (k % w) as f32 * 0.3, 2.5 - (k / w) as f32 * 0.25, 0.75]).collect();
    let (bytes, decoded) = radiance_hdr(w, h, &pixels);
    let hdr = dir.path().join("sky.hdr");
    std::fs::write(&hdr, bytes).unwrap();
    let exr = dir.path().join("sky.exr");
    Rgb { width: w, height: h, pixels: decoded.clone() }.write_exr(&exr).unwrap();
    let from_hdr = Environment::load(&hdr).unwrap();
    assert_eq!(from_hdr.pixels, decoded, "the .hdr reader");
    assert_eq!(Environment::load(&exr).unwrap(), from_hdr);
    // Renders under the two files are the same image.
    let mat = material(dir.path());
    let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
    for (env, out) in [(&hdr, &a), (&exr, &b)] {
        let (code, _, stderr) = brdfpaint(&render_args(&mat, env, out));
        assert_eq!(code, 0, "{stderr}");
    }
    let (ra, rb) = (Rgb::read_exr(&a).unwrap(), Rgb::read_exr(&b).unwrap());
    assert_eq!(ra, rb);
    assert!(ra.pixels.iter().any(|p| p[0] > 0.05), "the render is black");
}

#[test]
fn bad_environments_are_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let mat = material(root);
    let out_dir = root.join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let out = out_dir.join("r.png");

    // The bundled environment works.
    let (code, stdout, stderr) = brdfpaint(&render_args(&mat, &bundled("city.exr"), &out));
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("under") && out.exists(), "{stdout}");
    std::fs::remove_file(&out).unwrap();

    let bad = |name: &str, bytes: &[u8]| {
        let p = root.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let good = std::fs::read(bundled("city.exr")).unwrap();
    let truncated = bad("truncated.exr", &good[..good.len() / 2]);
    fails(&render_args(&mat, &truncated, &out), 1, "truncated.exr: corrupt or truncated", &out_dir);
    let hdr = radiance_hdr(16, 8, &vec![[1.0; 3]; 128]).0;
    let truncated_hdr = bad("truncated.hdr", &hdr[..hdr.len() - 100]);
    fails(&render_args(&mat, &truncated_hdr, &out), 1, "truncated.hdr", &out_dir);

    let mut png = Vec::new();
    image::RgbImage::new(8, 4).write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    let not_hdr = bad("photo.exr", &png);
    fails(&render_args(&mat, &not_hdr, &out), 1, "photo.exr: a Png image is not an HDR environment", &out_dir);
    let text = bad("notes.hdr", b"hello, not an image");
    fails(&render_args(&mat, &text, &out), 1, "notes.hdr: not an HDR environment", &out_dir);
    let empty = bad("empty.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n");
    fails(&render_args(&mat, &empty, &out), 1, "empty.hdr", &out_dir);
    fails(&render_args(&mat, &root.join("missing.exr"), &out), 1, "missing.exr", &out_dir);

    let exr = |name: &str, w: usize, h: usize, f: &dyn Fn(usize) -> [f32; 3]| {
        let p = root.join(name);
        Rgb { width: w, height: h, pixels: (0..w * h).map(f).collect() }.write_exr(&p).unwrap();
        p
    };
    let square = exr("square.exr", 8, 8, &|_| [1.0; 3]);
    fails(&render_args(&mat, &square, &out), 1, "square.exr: the environment is 8x8; an equirectangular map is exactly twice as wide as high", &out_dir);
    let nan = exr("nan.exr", 8, 4, &|k| if k == 13 { [0.5, f32::NAN, 0.5] } else { [0.5; 3] });
    fails(&render_args(&mat, &nan, &out), 1, "nan.exr: pixel (5, 1) has radiance NaN", &out_dir);
    let inf = exr("inf.exr", 8, 4, &|k| if k == 30 { [f32::INFINITY, 0.5, 0.5] } else { [0.5; 3] });
    fails(&render_args(&mat, &inf, &out), 1, "inf.exr: pixel (6, 3) has radiance inf", &out_dir);
}

#[test]
fn usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let mat = material(root);
    let env = bundled("sunset.exr");
    let (png, exr) = (root.join("r.png"), root.join("r.exr"));
    let base = |out: &Path| -> Vec<String> { ["render", s(&mat), "--model", "sphere", "--size", "16x16", "--out", s(out)].map(String::from).to_vec() };
    let with = |out: &Path, extra: &[&str]| -> Vec<String> {
        let mut a = base(out);
        a.extend(extra.iter().map(|x| x.to_string()));
        a
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (with(&png, &["--env-rotate", "90"]), "--env"),
        (with(&png, &["--background", "env"]), "--background env needs --env"),
        (with(&png, &["--env", s(&env), "--background", "#12345"]), "--background #12345"),
        (with(&exr, &["--env", s(&env), "--tonemap", "aces"]), "an EXR stays linear"),
        (with(&png, &["--env", s(&env), "--tonemap", "filmic"]), "filmic"),
        (with(&png, &["--exposure", "NaN"]), "--exposure"),
        (with(&png, &["--env", s(&env), "--env-samples", "2"]), "--env-samples 2"),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails(&args, 2, needle, root);
    }
}

/// EXR output is linear and scales with the exposure; a PNG is the EXR exposed,
/// tone mapped (Khronos PBR Neutral by default with --env, or as asked) and sRGB-encoded.
#[test]
fn exposure_and_tone_mapping_follow_their_formulas() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let mat = material(root);
    let env = bundled("sunset.exr");
    let run = |out: &Path, extra: &[&str]| {
        let mut args = render_args(&mat, &env, out);
        args.extend(extra);
        let (code, _, stderr) = brdfpaint(&args);
        assert_eq!(code, 0, "{stderr}");
    };
    let (linear, brighter) = (root.join("a.exr"), root.join("b.exr"));
    run(&linear, &["--env-rotate", "30"]);
    run(&brighter, &["--env-rotate", "30", "--exposure", "1.5"]);
    let (a, b) = (Rgb::read_exr(&linear).unwrap(), Rgb::read_exr(&brighter).unwrap());
    let k = 2f32.powf(1.5);
    for (x, y) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            assert!((x[c] * k - y[c]).abs() <= 1e-5 * y[c].abs().max(1.0), "{x:?} x 2^1.5 vs {y:?}");
        }
    }
    assert!(a.pixels.iter().any(|p| p[0] > 1.0), "the sunset has highlights above 1 to tone map");
    for (flag, op) in [(None, Tonemap::Neutral), (Some("aces"), Tonemap::Aces), (Some("none"), Tonemap::None)] {
        let png = root.join(format!("{op:?}.png"));
        let mut extra = vec!["--env-rotate", "30", "--exposure", "1.5"];
        if let Some(f) = flag {
            extra.extend(["--tonemap", f]);
        }
        run(&png, &extra);
        let img = image::open(&png).unwrap().into_rgb8();
        for (p, x) in img.pixels().zip(&b.pixels) {
            let want = op.map(*x).map(encode_srgb8);
            for c in 0..3 {
                assert!((p.0[c] as i32 - want[c] as i32).abs() <= 1, "{op:?}: PNG {:?} vs {want:?} from {x:?}", p.0);
            }
        }
    }
}
