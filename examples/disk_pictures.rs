//! Pictures of a sphere in context with a KNOWN circle, and how well `fit --lit-sphere`
//! finds it ([`brdfpaint::litsphere::Picture::read`]): a shaded sphere (Lambert with a
//! highlight, two-tone toon, a painterly noisy one) sitting on a table with a soft cast
//! shadow, on flat paper with grain, a vertical gradient or painted strokes, in the middle,
//! cut by the picture's edge, or hidden at the bottom by something in front; saved as JPEG
//! (quality 70 to 90).
//!
//! ```text
//! cargo run --release --example disk_pictures -- OUT FIRST_SEED LAST_SEED [small]
//! ```
//! writes OUT/*.jpg and OUT/truth.csv (name, cx, cy, r in pixels, centres at +0.5, and
//! front: the y from which something in front hides the sphere, empty when nothing does),
//! then prints each picture's error (the centre's distance and the radius's, over the
//! radius) and the worst per style, background and layout, and how many of the disk's
//! pixels showing the thing in front are still samples and how many of the sphere's are
//! not. `small` makes pictures of about 200×160 (the ones kept in tests/data/disks).
//!
//! ```text
//! cargo run --release --example disk_pictures -- --judge DIR
//! ```
//! judges pictures made elsewhere, listed in DIR/truth.csv the same way (MyPaint's painted
//! exemplars, `tools/mypaint/make_exemplars.sh`), grouped by the words of their names.

use std::f64::consts::PI;
use std::path::Path;

use brdfpaint::litsphere::{Disk, Picture, MAX_SIDE};
use brdfpaint::study::front::FrontPixels;
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const STYLES: [&str; 3] = ["lambert", "toon", "painterly"];
const BACKGROUNDS: [&str; 3] = ["paper", "gradient", "strokes"];
const LAYOUTS: [&str; 3] = ["middle", "edge", "hidden"];

/// A sphere in its scene: the circle, the light, and what surrounds it.
struct Layout {
    w: usize,
    h: usize,
    cx: f64,
    cy: f64,
    r: f64,
    horizon: f64,
    light: DVec3,
    /// Rows from here down are hidden by something in front (a box's edge), if any.
    hidden_from: Option<f64>,
}

fn layout(rng: &mut ChaCha8Rng, small: bool, kind: &str) -> Layout {
    let (w, h) = if small { (rng.random_range(180..230), rng.random_range(150..190)) } else { (rng.random_range(320..480), rng.random_range(260..400)) };
    let (wf, hf) = (w as f64, h as f64);
    let r = rng.random_range(0.22..0.36) * wf.min(hf);
    let horizon = rng.random_range(0.42..0.65) * hf;
    let mut cx = rng.random_range(0.35..0.65) * wf;
    // On the table: the contact point below the horizon, above the picture's bottom.
    let mut cy = (rng.random_range(horizon + 0.1 * r..(hf - 0.06 * hf).max(horizon + 0.2 * r)) - r).max(r * 0.6);
    let mut hidden_from = None;
    match kind {
        "edge" => match rng.random_range(0..3) {
            0 => cx = r * rng.random_range(0.75..0.95),
            1 => cx = wf - r * rng.random_range(0.75..0.95),
            _ => cy = hf - r * rng.random_range(0.75..0.95),
        },
        "hidden" => hidden_from = Some(cy + r * rng.random_range(0.45..0.75)),
        _ => {}
    }
    let side: f64 = if rng.random_bool(0.5) { -1.0 } else { 1.0 };
    let light = DVec3::new(side * rng.random_range(0.3..0.9), rng.random_range(0.3..0.9), rng.random_range(0.4..1.0)).normalize();
    Layout { w, h, cx, cy, r, horizon, light, hidden_from }
}

/// Smooth value noise in [-1, 1] at (x, y) in cells of `scale` pixels.
fn noise(seed: u64, x: f64, y: f64, scale: f64) -> f64 {
    let hash = |i: i64, j: i64| {
        let mut z = (i as u64).wrapping_mul(0x9E3779B97F4A7C15) ^ (j as u64).wrapping_mul(0xC2B2AE3D27D4EB4F) ^ seed.wrapping_mul(0x165667B19E3779F9);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let (u, v) = (x / scale, y / scale);
    let (i, j) = (u.floor() as i64, v.floor() as i64);
    let (fx, fy) = (u - i as f64, v - j as f64);
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let a = hash(i, j) * (1.0 - sx) + hash(i + 1, j) * sx;
    let b = hash(i, j + 1) * (1.0 - sx) + hash(i + 1, j + 1) * sx;
    a * (1.0 - sy) + b * sy
}

/// A random colour near `base` (linear RGB), each channel times 1 ± `spread`.
fn near(rng: &mut ChaCha8Rng, base: [f64; 3], spread: f64) -> [f64; 3] {
    base.map(|c| (c * rng.random_range(1.0 - spread..1.0 + spread)).clamp(0.0, 1.0))
}

/// The wall and table behind and under the sphere, linear RGB per pixel.
fn background(rng: &mut ChaCha8Rng, l: &Layout, kind: &str, seed: u64) -> Vec<[f64; 3]> {
    let wall = near(rng, [0.75, 0.68, 0.55], 0.25);
    let table = near(rng, [0.45, 0.35, 0.25], 0.4);
    let (wall2, table2) = (near(rng, wall.map(|c| c * 0.6), 0.2), near(rng, table.map(|c| c * 1.4), 0.2));
    let mut px = vec![[0.0; 3]; l.w * l.h];
    for j in 0..l.h {
        for i in 0..l.w {
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let on_table = y > l.horizon;
            let (a, b) = if on_table { (table, table2) } else { (wall, wall2) };
            let t = if on_table { (y - l.horizon) / (l.h as f64 - l.horizon) } else { y / l.horizon };
            let c = match kind {
                "gradient" => [0, 1, 2].map(|k| a[k] * (1.0 - t) + b[k] * t),
                _ => a.map(|c| c * (1.0 + 0.06 * noise(seed + 7, x, y, 40.0))),
            };
            // Paper grain: a few percent per pixel.
            let grain = 1.0 + 0.04 * noise(seed + 11, x, y, 1.3);
            px[j * l.w + i] = c.map(|c| c * grain);
        }
    }
    if kind == "strokes" {
        strokes(rng, l, &mut px);
    }
    px
}

/// Painted strokes: elongated soft-edged dabs of colours near what they cover.
fn strokes(rng: &mut ChaCha8Rng, l: &Layout, px: &mut [[f64; 3]]) {
    let n = l.w * l.h / 300;
    for _ in 0..n {
        let (sx, sy) = (rng.random_range(0.0..l.w as f64), rng.random_range(0.0..l.h as f64));
        let angle = rng.random_range(-0.6..0.6f64) + if rng.random_bool(0.2) { PI / 2.0 } else { 0.0 };
        let (len, width) = (rng.random_range(8.0..40.0), rng.random_range(2.0..6.0));
        let base = px[(sy as usize).min(l.h - 1) * l.w + (sx as usize).min(l.w - 1)];
        let colour = near(rng, base, 0.2);
        let (ca, sa) = (angle.cos(), angle.sin());
        let reach = len as isize + 2;
        for dj in -reach..=reach {
            for di in -reach..=reach {
                let (i, j) = (sx as isize + di, sy as isize + dj);
                if i < 0 || j < 0 || i >= l.w as isize || j >= l.h as isize {
                    continue;
                }
                let (u, v) = (di as f64 * ca + dj as f64 * sa, -di as f64 * sa + dj as f64 * ca);
                let d = (u / len).powi(2) + (v / width).powi(2);
                let cover = (1.5 - 1.5 * d).clamp(0.0, 1.0) * 0.8;
                let k = j as usize * l.w + i as usize;
                px[k] = [0, 1, 2].map(|c| px[k][c] * (1.0 - cover) + colour[c] * cover);
            }
        }
    }
}

/// The sphere's colour at the normal `n` in `style` (linear RGB).
fn shade(style: &str, n: DVec3, l: &Layout, albedo: [f64; 3], ambient: f64, seed: u64, (x, y): (f64, f64)) -> [f64; 3] {
    let ndl = n.dot(l.light);
    let hv = (l.light + DVec3::Z).normalize();
    let ndh = n.dot(hv).max(0.0);
    match style {
        "toon" => {
            let tone = if ndl > 0.2 { 1.0 } else { 0.35 };
            if ndh > 0.975 {
                return [1.0, 1.0, 0.95];
            }
            albedo.map(|c| c * tone)
        }
        "painterly" => {
            let strokes = 0.12 * noise(seed + 3, x * 0.7 + y * 0.3, y - x * 0.2, 6.0) + 0.08 * noise(seed + 5, x, y, 2.0);
            let lit = (ambient + (1.0 - ambient) * ndl.max(0.0)) * (1.0 + strokes);
            let spec = 0.4 * ndh.powf(20.0);
            albedo.map(|c| (c * lit + spec).clamp(0.0, 1.0))
        }
        _ => {
            let lit = ambient + (1.0 - ambient) * ndl.max(0.0);
            let spec = 0.6 * ndh.powf(60.0);
            albedo.map(|c| (c * lit + spec).clamp(0.0, 1.0))
        }
    }
}

/// The picture of one sphere, sRGB 8-bit, and its layout.
fn picture(seed: u64, style: &str, bg: &str, kind: &str, small: bool) -> (image::RgbImage, Layout) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let l = layout(&mut rng, small, kind);
    let mut px = background(&mut rng, &l, bg, seed);
    let albedo = near(&mut rng, [0.6, 0.35, 0.25], 0.5);
    let ambient = rng.random_range(0.03..0.25);
    let shadow_side = -l.light.x.signum();
    let (sx, sy) = (l.cx + shadow_side * l.r * rng.random_range(0.3..0.8), l.cy + l.r * 0.97);
    let (ax, ay) = (l.r * rng.random_range(1.1..1.6), l.r * rng.random_range(0.2..0.35));
    let depth = rng.random_range(0.5..0.8);
    let occluder = near(&mut rng, [0.3, 0.25, 0.2], 0.5);
    for j in 0..l.h {
        for i in 0..l.w {
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let k = j * l.w + i;
            // The cast shadow: a soft ellipse on the table, darkest at the contact.
            if y > l.horizon {
                let e = ((x - sx) / ax).powi(2) + ((y - sy) / ay).powi(2);
                let dark = depth * (1.0 - e).clamp(0.0, 1.0).powf(0.7);
                px[k] = px[k].map(|c| c * (1.0 - dark));
            }
            let d = ((x - l.cx).powi(2) + (y - l.cy).powi(2)).sqrt();
            let cover = (l.r - d + 0.5).clamp(0.0, 1.0);
            if cover > 0.0 {
                let (nx, ny) = ((x - l.cx) / l.r, -(y - l.cy) / l.r);
                let n = DVec3::new(nx, ny, (1.0 - nx * nx - ny * ny).max(0.0).sqrt()).normalize();
                let c = shade(style, n, &l, albedo, ambient, seed, (x, y));
                px[k] = [0, 1, 2].map(|ch| px[k][ch] * (1.0 - cover) + c[ch] * cover);
            }
            if l.hidden_from.is_some_and(|h| y > h) {
                px[k] = occluder.map(|c| c * (1.0 + 0.05 * noise(seed + 13, x, y, 3.0)));
            }
        }
    }
    let img = image::RgbImage::from_fn(l.w as u32, l.h as u32, |i, j| {
        image::Rgb(px[j as usize * l.w + i as usize].map(|c| brdfpaint::images::encode_srgb8(c as f32)))
    });
    (img, l)
}

/// How far the circle `Picture::read` finds is from the truth (the larger of the centre's
/// distance and the radius's difference, over the radius; infinite if refused), printed; and
/// how the disk's pixels were told from what stands in front of the sphere, whose top is at
/// `front` (none: nothing in front).
fn judge(path: &Path, name: &str, cx: f64, cy: f64, r: f64, front: Option<f64>) -> (f64, Front) {
    match Picture::read(path, MAX_SIDE) {
        Ok(p) => {
            let d = p.disk;
            let (dc, dr) = (((d.cx - cx).powi(2) + (d.cy - cy).powi(2)).sqrt(), (d.r - r).abs());
            let f = Front::of(&p, Disk { cx, cy, r }, front);
            println!("{name}: truth ({cx:.1}, {cy:.1}) r {r:.1}; found ({:.1}, {:.1}) r {:.1} from {:.0}% ({:?}): off {:.2}% / {:.2}% of r{}", d.cx, d.cy, d.r, 100.0 * p.seen, p.outline, 100.0 * dc / r, 100.0 * dr / r, f.describe(front));
            (dc.max(dr) / r, f)
        }
        Err(e) => {
            println!("{name}: truth ({cx:.1}, {cy:.1}) r {r:.1}; REFUSED: {e}");
            (f64::INFINITY, Front::default())
        }
    }
}

/// How the disk's pixels were told from what stands in front of the sphere, and whether
/// something was found in front.
#[derive(Clone, Copy, Debug, Default)]
struct Front {
    pixels: FrontPixels,
    found: bool,
}

impl Front {
    fn of(p: &Picture, truth: Disk, front: Option<f64>) -> Front {
        Front { pixels: FrontPixels::of(p, &truth, front), found: p.hidden.is_some() }
    }

    fn describe(&self, front: Option<f64>) -> String {
        let f = &self.pixels;
        match (front, self.found) {
            (None, false) => String::new(),
            _ => format!("; in front: {} of {} pixels kept, sphere: {} of {} lost", f.thing_kept, f.thing, f.sphere_lost, f.sphere),
        }
    }
}

/// The worst error per group and the counts within 2%, off by more than 5%, and refused.
struct Tally {
    worst: std::collections::BTreeMap<String, f64>,
    /// Over the pictures with something in front, and over those without.
    fronted: FrontPixels,
    fronted_pictures: usize,
    fronted_found: usize,
    clear: FrontPixels,
    clear_found: usize,
    total: usize,
    within: usize,
    wrong: usize,
    refused: usize,
}

impl Tally {
    fn new() -> Tally {
        Tally { worst: Default::default(), fronted: FrontPixels::default(), fronted_pictures: 0, fronted_found: 0, clear: FrontPixels::default(), clear_found: 0, total: 0, within: 0, wrong: 0, refused: 0 }
    }

    fn add(&mut self, err: f64, front: (Option<f64>, Front), groups: &[String]) {
        let (sum, found) = if front.0.is_some() {
            self.fronted_pictures += 1;
            (&mut self.fronted, &mut self.fronted_found)
        } else {
            (&mut self.clear, &mut self.clear_found)
        };
        *found += usize::from(front.1.found);
        *sum += front.1.pixels;
        self.total += 1;
        self.within += (err <= 0.02) as usize;
        self.wrong += (err > 0.05 && err.is_finite()) as usize;
        self.refused += err.is_infinite() as usize;
        for key in groups {
            let w = self.worst.entry(key.clone()).or_insert(0.0);
            *w = w.max(err);
        }
    }

    fn print(&self, set: &str) {
        for (k, w) in &self.worst {
            println!("worst, {k}: {:.2}% of r", 100.0 * w);
        }
        println!(
            "{set}: {} of {} pictures with centre and radius within 2% of the radius, {} off by more than 5%, {} refused",
            self.within, self.total, self.wrong, self.refused
        );
        let share = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
        let (f, c) = (&self.fronted, &self.clear);
        println!(
            "{set}: something in front in {} pictures, found in {}: {:.1}% of its pixels in the disk kept as samples, {:.1}% of the sphere's left out; nothing in front in {}, something found in {} ({:.1}% of their spheres' pixels left out)",
            self.fronted_pictures, self.fronted_found, share(f.thing_kept, f.thing), share(f.sphere_lost, f.sphere),
            self.total - self.fronted_pictures, self.clear_found, share(c.sphere_lost, c.sphere)
        );
    }
}

/// `--judge DIR`: the pictures of DIR/truth.csv (name,cx,cy,r), made elsewhere
/// (tools/mypaint/make_exemplars.sh), grouped by the dash-separated words of their names.
fn judge_folder(dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let csv = std::fs::read_to_string(dir.join("truth.csv"))?;
    let mut tally = Tally::new();
    for line in csv.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let (name, cx, cy, r, front) = match f[..] {
            [name, cx, cy, r] => (name, cx, cy, r, ""),
            [name, cx, cy, r, front] => (name, cx, cy, r, front),
            _ => return Err(format!("truth.csv: not name,cx,cy,r[,front]: {line}").into()),
        };
        let front = (!front.trim().is_empty()).then(|| front.trim().parse::<f64>()).transpose()?;
        let (err, found) = judge(&dir.join(name), name, cx.parse()?, cy.parse()?, r.parse()?, front);
        let stem = name.trim_end_matches(".jpg");
        let seed = |w: &str| w.strip_prefix('s').is_some_and(|n| n.parse::<u64>().is_ok());
        let groups: Vec<String> = stem.split('-').filter(|w| !seed(w)).map(|w| format!("group {w}")).collect();
        tally.add(err, (front, found), &groups);
    }
    tally.print(&dir.display().to_string());
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, dir] = &args[..] {
        if flag == "--judge" {
            return judge_folder(Path::new(dir));
        }
    }
    let (out, first, last) = match &args[..] {
        [o, a, b, ..] => (Path::new(o).to_path_buf(), a.parse::<u64>()?, b.parse::<u64>()?),
        _ => return Err("usage: disk_pictures OUT FIRST_SEED LAST_SEED [small] | disk_pictures --judge DIR".into()),
    };
    let small = args.get(3).is_some_and(|s| s == "small");
    std::fs::create_dir_all(&out)?;
    let mut truth = String::from("name,cx,cy,r,front\n");
    let mut tally = Tally::new();
    for seed in first..=last {
        for (s, style) in STYLES.iter().enumerate() {
            for (b, bg) in BACKGROUNDS.iter().enumerate() {
                for (k, kind) in LAYOUTS.iter().enumerate() {
                    let pic_seed = seed * 1000 + (s * 100 + b * 10 + k) as u64;
                    let (img, l) = picture(pic_seed, style, bg, kind, small);
                    let name = format!("{style}_{bg}_{kind}_{seed}.jpg");
                    let path = out.join(&name);
                    let quality = 70 + (pic_seed % 21) as u8;
                    let mut bytes = Vec::new();
                    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, quality).encode_image(&img)?;
                    std::fs::write(&path, bytes)?;
                    let front = l.hidden_from.map_or(String::new(), |y| format!("{y:.3}"));
                    truth.push_str(&format!("{name},{:.3},{:.3},{:.3},{front}\n", l.cx, l.cy, l.r));
                    let (err, found) = judge(&path, &name, l.cx, l.cy, l.r, l.hidden_from);
                    tally.add(err, (l.hidden_from, found), &[format!("style {style}"), format!("background {bg}"), format!("layout {kind}")]);
                }
            }
        }
    }
    std::fs::write(out.join("truth.csv"), truth)?;
    tally.print(&format!("seeds {first}..={last}"));
    Ok(())
}
