//! `brdfpaint demo`, run as a user runs it: once into a fresh directory and once more into
//! the same one (shared by the tests below), and once into a directory it must refuse.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use brdfpaint::demo::contact::Layout;
use brdfpaint::demo::paintings::{self, Truth};
use brdfpaint::images::Painting;
use brdfpaint::factor::{Mapping, Settings};
use brdfpaint::material::{Kind, Material};
use brdfpaint::study::fidelity::held_out_presets;
use brdfpaint::study::{held_out_error, StudyView};
use brdfpaint::sample::{Erosion, Samples, SceneSampler};
use glam::DVec2;

mod cli_common;

use cli_common::{brdfpaint, Run};

/// Two runs of the demo into the same directory, with an empty prepare cache before the first.
struct Runs {
    dir: PathBuf,
    first: Run,
    second: Run,
}

fn runs() -> &'static Runs {
    static RUNS: OnceLock<Runs> = OnceLock::new();
    RUNS.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("demo-test");
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        let (dir, cache) = (root.join("out"), root.join("cache"));
        let args = ["demo", "--out", dir.to_str().unwrap()];
        let first = brdfpaint(&cache, &args);
        assert_eq!(first.code, 0, "first run failed: {}", first.stderr);
        let second = brdfpaint(&cache, &args);
        assert_eq!(second.code, 0, "second run failed: {}", second.stderr);
        Runs { dir, first, second }
    })
}

fn names() -> Vec<&'static str> {
    paintings::materials().iter().map(|m| m.name).collect()
}

/// Columns of a summary row, counted from its end (the description before them has spaces).
const SAMPLES: usize = 8;
const CACHE: usize = 6;
const RMS: usize = 4;
const HELD_OUT: usize = 1;

/// Column `from_end` (1: the last) of material `name`'s summary row.
fn column<'a>(summary: &'a str, name: &str, from_end: usize) -> &'a str {
    let row = summary_row(summary, name);
    row[row.len() - from_end]
}

/// The summary line of material `name`, split into its columns.
fn summary_row<'a>(summary: &'a str, name: &str) -> Vec<&'a str> {
    let line = summary
        .lines()
        .find(|l| l.split_whitespace().next() == Some(name))
        .unwrap_or_else(|| panic!("no summary line for {name} in\n{summary}"));
    line.split_whitespace().collect()
}

fn png_size(path: &Path) -> (u32, u32) {
    image::image_dimensions(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn writes_every_file_at_its_size() {
    let d = &runs().dir;
    let side = paintings::SIZE as u32;
    let rows = names().len();
    let (w, h) = Layout { rows, cell: paintings::SIZE }.size();
    assert_eq!(png_size(&d.join("contact.png")), (w as u32, h as u32));
    assert_eq!(png_size(&d.join("contact-small.png")), (w as u32 / 2, h as u32 / 2));
    for view in paintings::views() {
        for f in brdfpaint::render::SHEET_FILES {
            assert!(d.join(view.dir).join(f).is_file(), "{}/{f}", view.dir);
        }
        assert_eq!(png_size(&d.join(view.dir).join("outline.png")), (side, side));
    }
    for spec in paintings::materials() {
        for p in &spec.paintings {
            assert_eq!(std::fs::read(d.join("paintings").join(p.file)).unwrap(), p.bytes, "{}", p.file);
            assert_eq!(png_size(&d.join("paintings").join(p.file)), (side, side));
        }
        let mat = d.join("materials").join(spec.name);
        let material = Material::load(&mat).unwrap_or_else(|e| panic!("{}: {e}", mat.display()));
        assert_eq!(material.provenance.samples.to_string(), column(&runs().first.stdout, spec.name, SAMPLES));
        assert!(mat.join("report.png").is_file());
        for model in ["sphere", "bunny", "suzanne", "teapot"] {
            assert_eq!(
                png_size(&d.join("renders").join(format!("{}-{model}.png", spec.name))),
                (side, side),
                "{model}"
            );
        }
        // Under the bundled environments: square renders, one per environment.
        for (env, _) in brdfpaint::images::env::BUNDLED {
            let (w, h) = png_size(&d.join("renders").join(format!("{}-{env}.png", spec.name)));
            assert!(w == h && w >= 64, "{}-{env}.png is {w}x{h}", spec.name);
        }
    }
    // environments.png: a row per environment, a column per material, square cells.
    let (w, h) = png_size(&d.join("environments.png"));
    let (rows, cols) = (brdfpaint::images::env::BUNDLED.len() as u32, paintings::materials().len() as u32);
    assert_eq!(w * rows, h * cols, "environments.png is {w}x{h}");
    let summary = std::fs::read_to_string(d.join("summary.txt")).unwrap();
    assert_eq!(summary, runs().second.stdout, "summary.txt is what the second run printed");
    assert!(summary.starts_with(brdfpaint::demo::MARK));
    assert!(summary.lines().count() <= 24, "one screen:\n{summary}");
    // The last line names what DIR holds: every file and directory in it, nothing missing.
    let wrote = summary.lines().last().unwrap();
    let listed = wrote.split_once("/: ").unwrap_or_else(|| panic!("{wrote}")).1;
    let mut listed: Vec<&str> = listed.split(", ").map(|f| f.trim_end_matches('/')).collect();
    // Hidden bookkeeping (the ownership record) aside.
    let mut present: Vec<String> =
        std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).filter(|n| !n.starts_with('.')).collect();
    listed.sort();
    present.sort();
    assert_eq!(listed, present, "{wrote}");
    // Nothing left behind beside DIR.
    let siblings: Vec<_> = std::fs::read_dir(d.parent().unwrap()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(siblings.iter().all(|n| !n.to_string_lossy().contains(".tmp-")), "{siblings:?}");
}

/// Held-out relative RMS of a recovered material against its true shading, computed here
/// with the library's fidelity code (not the demo's), on the demo's held-out views, from the
/// material the demo wrote and the truth its paintings were made from.
fn held_out(name: &str) -> f64 {
    let spec = paintings::materials().into_iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}"));
    let mut sampler = SceneSampler::new().unwrap();
    let held: Vec<StudyView> =
        held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, 128).unwrap()).collect();
    let material = Material::load(&runs().dir.join("materials").join(name)).unwrap();
    held_out_error(&material, &spec.truth, &held, None).unwrap()
}

/// The held-out column of README's demo table, uniform materials with a known truth.
const README_HELD_OUT: [(&str, f64); 5] =
    [("plastic", 0.0094), ("gooch", 0.0107), ("gold-paint", 0.0216), ("gold-paint-2-views", 0.0111), ("purple-paint", 0.0131)];

/// Every held-out figure README's demo table prints, recomputed here and held at its
/// value: within 0.00005 plus 1%, the table's last printed digit and the drift of a
/// deterministic fit across machines' float rounding. The summary prints the same numbers.
#[test]
fn held_out_errors_are_readmes_recomputed_independently() {
    let summary = &runs().first.stdout;
    for (name, stated) in README_HELD_OUT {
        let e = held_out(name);
        eprintln!("{name}: held-out {e:.5} (README {stated})");
        assert!((e - stated).abs() <= 5e-5 + 0.01 * stated, "{name}: held-out {e:.5}, README states {stated}");
        let reported: f64 = column(summary, name, HELD_OUT).parse().unwrap();
        assert!((reported - e).abs() < 1e-4 + 1e-9, "{name}: summary says {reported}, recomputed {e:.5}");
    }
    // Unknown truth: no held-out number.
    assert!(matches!(paintings::materials().iter().find(|m| m.name == "toon").unwrap().truth, Truth::Matcap { .. }));
    assert_eq!(column(summary, "toon", HELD_OUT), "-");
}

#[test]
fn analytic_paintings_generalize_despite_brush_noise() {
    // Bound: 5% relative RMS on lights and views nobody painted (README: 0.0066 and 0.0107,
    // held by `held_out_errors_are_readmes_recomputed_independently`).
    const BOUND: f64 = 0.05;
    for name in ["plastic", "gooch"] {
        let e = held_out(name);
        assert!(e < BOUND, "{name}: held-out relative RMS {e:.4} >= {BOUND}");
    }
    assert!(matches!(paintings::materials()[0].truth, Truth::Analytic(_)));
}

#[test]
fn measured_like_paint_generalizes_from_one_view_and_two() {
    // Thesis 4.4: a second view constrains the factors that one view leaves free. On one
    // brushed painting the analytic lobe now does it (`read::lobe::TEXTURE_CREDIT`): the
    // product alone held the brush in rings. Recomputed from the MERL truth, not read back.
    let (one, two) = (held_out("gold-paint"), held_out("gold-paint-2-views"));
    assert!(one < 0.05 && two < 0.05, "gold paint held-out: 1 view {one}, 2 views {two}");
    assert!(held_out("purple-paint") < 0.1);
    assert!(matches!(paintings::materials()[2].truth, Truth::Abc { .. }));
}

#[test]
fn contact_sheet_cells_are_the_paintings_and_renders() {
    let d = &runs().dir;
    let contact = image::open(d.join("contact.png")).unwrap().to_rgb8();
    let names = names();
    let layout = Layout { rows: names.len(), cell: paintings::SIZE };
    let row = names.iter().position(|&n| n == "gooch").unwrap();
    // Column 2 is the bunny: every object pixel of the render is the sheet's pixel.
    let render = image::open(d.join("renders/gooch-bunny.png")).unwrap().to_rgb8();
    let (x0, y0) = layout.origin(row, 2);
    let (x0, y0) = (x0 as u32, y0 as u32);
    let mut checked = 0;
    for (i, j, p) in render.enumerate_pixels() {
        if p.0.iter().any(|&c| c > 8) {
            assert_eq!(contact.get_pixel(x0 + i, y0 + j), p, "pixel ({i}, {j}) of gooch-bunny.png");
            checked += 1;
        }
    }
    assert!(checked > 5000, "only {checked} object pixels");
    // Column 0 is the painting: its painted pixels are the sheet's.
    let painting = image::open(d.join("paintings/plastic.png")).unwrap().to_rgba8();
    let (x0, y0) = layout.origin(0, 0);
    let (x0, y0) = (x0 as u32, y0 as u32);
    let centre = painting.get_pixel(128, 128).0;
    assert_eq!(centre[3], 255);
    assert_eq!(contact.get_pixel(x0 + 128, y0 + 128).0, [centre[0], centre[1], centre[2]]);
}

#[test]
fn second_run_hits_the_prepare_cache() {
    for name in names() {
        let (first, second) = (&runs().first.stdout, &runs().second.stdout);
        assert_eq!(column(first, name, CACHE), "miss", "{name}:\n{first}");
        assert_eq!(column(second, name, CACHE), "hit", "{name}:\n{second}");
        // Same pattern, same paint: the same fit (RMS, relative RMS, max).
        for k in [RMS, RMS - 1, RMS - 2] {
            assert_eq!(column(first, name, k), column(second, name, k), "{name}");
        }
    }
}

#[test]
fn refuses_a_directory_that_is_not_a_demo() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("mine");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("notes.txt"), "keep me").unwrap();
    let run = brdfpaint(&root.path().join("cache"), &["demo", "--out", dir.to_str().unwrap()]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.starts_with("error: ") && run.stderr.contains("not a demo directory"), "{}", run.stderr);
    assert!(run.stdout.is_empty());
    let left: Vec<_> = std::fs::read_dir(root.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("mine")], "nothing else written");
    let files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(files, vec![std::ffi::OsString::from("notes.txt")]);
    assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "keep me");
    // A file is refused too.
    let file = dir.join("notes.txt");
    let run = brdfpaint(&root.path().join("cache"), &["demo", "--out", file.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("not a directory"), "{}", run.stderr);
}

#[test]
fn bundled_paintings_are_reproducible() {
    // make_paintings's recipe, redone here: the same bytes as the bundled file.
    let mut sampler = SceneSampler::new().unwrap();
    let spec = paintings::materials().into_iter().find(|m| m.name == "plastic").unwrap();
    let p = spec.paintings[0];
    let scene = paintings::view_scene(p.view).unwrap();
    let g = sampler.gbuffer(&scene, paintings::SIZE, paintings::SIZE).unwrap();
    let brush = paintings::brush(p.brush_seed.unwrap());
    let canvas = paintings::paint(&spec.truth, &g, &scene, Some(&brush), None).unwrap();
    let ours = Painting::decode(Path::new("ours.png"), &canvas.encode_png().unwrap()).unwrap();
    let bundled = Painting::decode(Path::new(p.file), p.bytes).unwrap();
    assert_eq!(ours, bundled, "{} differs from its recipe: run cargo run --release --example make_paintings", p.file);
    // Some pixels are unpainted gaps on the object, not only background.
    let gaps = (0..g.pixels.len()).filter(|&k| g.pixels[k].hit && bundled.alpha[k] == 0.0).count();
    assert!(gaps > 20, "{gaps} gap pixels");
}

/// The lacquered wood: the demo's material map, and one uniform product fitted here (library
/// code, no cache) to the same paintings in the same scenes, with its error on them.
struct Wood {
    map: Material,
    uniform: Material,
    uniform_train: f64,
    held: Vec<StudyView>,
    /// Where the paintings saw the surface.
    painted: brdfpaint::study::Coverage,
}

fn wood() -> &'static Wood {
    static WOOD: OnceLock<Wood> = OnceLock::new();
    WOOD.get_or_init(|| {
        let d = &runs().dir;
        let spec = paintings::materials().into_iter().find(|m| m.name == "lacquered-wood").unwrap();
        let mut sampler = SceneSampler::new().unwrap();
        let views: Vec<_> = spec
            .paintings
            .iter()
            .map(|p| {
                let scene = d.join(paintings::views()[p.view].dir).join("scene.gltf");
                sampler.load_view(&scene, &d.join("paintings").join(p.file), Erosion::default()).unwrap().1
            })
            .collect();
        let samples = Samples::gather(&views).unwrap();
        let settings = Settings::uniform(1, brdfpaint::factor::defaults::RES_1D);
        let fitted = brdfpaint::pipeline::solve(&samples, &settings, Mapping::Auto, None).unwrap();
        let uniform = Material::from_fit(&settings, &fitted.fit, Default::default()).unwrap();
        let held = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, 128).unwrap()).collect();
        Wood {
            map: Material::load(&d.join("materials/lacquered-wood")).unwrap(),
            uniform,
            uniform_train: fitted.fit.errors.rms_relative,
            held,
            painted: brdfpaint::study::Coverage::of(&views),
        }
    })
}

#[test]
fn spatially_varying_wood_is_a_material_map_that_fits_its_paintings_better() {
    let w = wood();
    let summary = &runs().first.stdout;
    assert_eq!(w.map.kind, Kind::MaterialMap);
    assert!(w.map.terms.len() >= 2, "{} term(s)", w.map.terms.len());
    assert_eq!(summary_row(summary, "lacquered-wood")[1], format!("map/{}", w.map.terms.len()));
    assert_eq!(summary_row(summary, "plastic")[1], "uniform");
    // On the painted samples the map beats one product clearly: it gives each stripe its
    // own material (measured: relative RMS 0.04 against 0.41 uniform).
    let map_train: f64 = column(summary, "lacquered-wood", RMS - 1).parse().unwrap();
    assert!(map_train < 0.2 * w.uniform_train, "map {map_train} vs uniform {}", w.uniform_train);
}

#[test]
fn spatially_varying_wood_holds_under_new_lights() {
    let w = wood();
    let summary = &runs().first.stdout;
    let truth = paintings::wood();
    let judge = |m: &Material, t: &Truth| brdfpaint::study::held_out_error(m, t, &w.held, Some(&w.painted)).unwrap();
    let (map, uniform) = (judge(&w.map, &truth), judge(&w.uniform, &truth));
    let reported: f64 = column(summary, "lacquered-wood", HELD_OUT).parse().unwrap();
    assert!((reported - map).abs() < 1e-3, "summary says {reported}, recomputed {map}");
    let line = format!("lacquered-wood: held-out {map:.4} as a material map, {uniform:.4} as one uniform product.");
    assert!(summary.contains(&line), "no line {line:?} in\n{summary}");
    // Under lights and from views nobody painted, on the part of the surface the paintings
    // saw, the map is far closer to the truth than one product: each stripe's term is its
    // own material's BRDF. README: 0.2599 (0.26) against 0.56, held at those values within
    // their printed digits plus 1%.
    eprintln!("lacquered-wood: held-out map {map:.5}, uniform {uniform:.5}");
    assert!((map - 0.2599).abs() <= 5e-5 + 0.01 * 0.2599, "held-out: map {map:.4}, README 0.2599");
    assert!((uniform - 0.56).abs() <= 0.005 + 0.01 * 0.56, "held-out: uniform {uniform:.4}, README 0.56");
    // The truth is evaluated at each pixel's uv, and the map has learnt where the stripes
    // are: against the stripes swapped (lacquer where the bare wood is) it is far off.
    let swapped = Truth::Banded(brdfpaint::brdf::Striped { a: paintings::bare_wood(), b: paintings::lacquer(), bands: paintings::WOOD_BANDS });
    let against_swapped = judge(&w.map, &swapped);
    assert!(against_swapped > 2.0 * map, "against swapped stripes {against_swapped}, against the stripes {map}");
}

#[test]
fn spatially_varying_wood_coefficients_separate_the_stripes() {
    // Mid-stripe, on the lacquered stripe 2 (azimuth -90° to -45°) and the bare stripe 3
    // (-45° to 0°), which both paintings see, from above the equator to it: the terms that
    // carry one stripe are not those that carry the other (five terms for two materials:
    // a material may take several terms, e.g. for its brush noise, but no term is shared).
    let w = wood();
    let truth = paintings::wood_stripes();
    let bands = paintings::WOOD_BANDS as f64;
    let (lacquered, bare) = (2.5 / bands, 3.5 / bands);
    assert_eq!(truth.band(lacquered), 2);
    assert_eq!(truth.region(lacquered), 0, "stripe 2 is lacquered");
    assert_eq!(truth.band(bare), 3);
    assert_eq!(truth.region(bare), 1, "stripe 3 is bare");
    let coefficients = |u: f64, v: f64| -> Vec<f64> {
        w.map.terms.iter().map(|t| t.coefficients.as_ref().expect("a material map term has coefficients").lookup(DVec2::new(u, v)).iter().sum::<f64>() / 3.0).collect()
    };
    let present = |c: &[f64]| -> Vec<usize> {
        let top = c.iter().cloned().fold(0.0, f64::max);
        (0..c.len()).filter(|&k| c[k] > 0.1 * top).collect()
    };
    for v in [0.3, 0.4, 0.5] {
        let (g, m) = (coefficients(lacquered, v), coefficients(bare, v));
        let (pg, pm) = (present(&g), present(&m));
        assert!(pg.iter().all(|k| !pm.contains(k)), "v = {v}: a term on both stripes: lacquer {g:?}, bare {m:?}");
    }
}

/// A linear value from an 8-bit sRGB code.
fn linear(code: u8) -> f64 {
    brdfpaint::images::srgb_to_linear(code as f32 / 255.0) as f64
}

/// Whether the glyph of `c`, `scale` pixels per font pixel, is at `(x, y)` of `image`: light
/// pixels (sRGB code above 150) where the font's bitmap has ink, near-black ones (below 24)
/// elsewhere in its cell.
fn glyph_at(image: &image::RgbImage, x: u32, y: u32, c: char, scale: u32) -> bool {
    use brdfpaint::images::text::{glyph, GLYPH_HEIGHT, GLYPH_WIDTH};
    let bits = glyph(c);
    (0..GLYPH_HEIGHT as u32 * scale).all(|j| {
        (0..GLYPH_WIDTH as u32 * scale).all(|i| {
            let ink = bits[(j / scale) as usize] >> (GLYPH_WIDTH as u32 - 1 - i / scale) & 1 == 1;
            let p = image.get_pixel(x + i, y + j).0;
            if ink {
                p.iter().all(|&v| v > 150)
            } else {
                p.iter().all(|&v| v < 24)
            }
        })
    })
}

#[test]
fn contact_sheet_names_its_rows_and_columns() {
    use brdfpaint::demo::contact::LABEL;
    let d = &runs().dir;
    let contact = image::open(d.join("contact.png")).unwrap().to_rgb8();
    let small = image::open(d.join("contact-small.png")).unwrap().to_rgb8();
    let names = names();
    let layout = Layout { rows: names.len(), cell: paintings::SIZE };
    for (row, name) in names.iter().enumerate() {
        let (x, y) = layout.title(row);
        let (x, y) = LABEL.text_origin(x, y);
        // Each letter of the name, one advance (6 font pixels at scale 2) after the last.
        for (k, c) in name.chars().enumerate() {
            let xk = (x + k * 12) as u32;
            assert!(glyph_at(&contact, xk, y as u32, c, 2), "{name}: letter {k} {c:?} not drawn at ({xk}, {y})");
        }
        let first = name.chars().next().unwrap();
        assert!(glyph_at(&small, x as u32 / 2, y as u32 / 2, first, 1), "{name}: not in contact-small.png");
        // The title sits above the row's cells, not over them.
        assert!(y + LABEL.height() <= layout.origin(row, 0).1);
    }
    // The check tells letters apart: row 0's title does not start with a 'g'.
    let (x, y) = LABEL.text_origin(layout.title(0).0, layout.title(0).1);
    assert!(!glyph_at(&contact, x as u32, y as u32, 'g', 2));
    let columns = brdfpaint::demo::contact_columns();
    assert_eq!(columns[..2], ["painting", "fit, painted view"]);
    for (col, name) in columns.iter().enumerate() {
        let (x, y) = layout.header(col, name);
        let (x, y) = LABEL.text_origin(x, y);
        let first = name.chars().next().unwrap();
        assert!(glyph_at(&contact, x as u32, y as u32, first, 2), "column {col} {name:?}");
        // Centred over its column.
        let (cx, _) = layout.origin(0, col);
        let w = LABEL.size(name).0;
        assert!((x - LABEL.pad + w / 2).abs_diff(cx + paintings::SIZE / 2) <= 1, "column {col} {name:?} not centred");
    }
}

/// How far a row's fit tile may be from its painting tile, relative to the painting's mean
/// (linear): the largest channel's difference of mean colours, and the mean per-pixel
/// difference. Measured (`cargo test --release --test demo contact -- --nocapture`): mean
/// colours within 1.0% (the wood; 0.06-0.45% for the others), pixels within 1.5-2.5% (brush
/// noise); against the other view's painting, 97% pixel by pixel.
const MEAN_BOUND: f64 = 0.03;
const PIXEL_BOUND: f64 = 0.05;
/// The MatCap is fitted as a lit sphere in its own scene; a smooth product only approximates
/// its flat toon bands: measured 1.6% and 14%.
const MEAN_BOUND_MATCAP: f64 = 0.05;
const PIXEL_BOUND_MATCAP: f64 = 0.2;

#[test]
fn contact_sheet_rows_compare_painting_and_fit_in_the_same_view() {
    // Per row, over the pixels the shown painting painted and the fit's render covers: the
    // fit tile's mean colour is the painting tile's, and pixel by pixel they are close. For
    // the rows painted in two views, the other view's painting is far off pixel by pixel,
    // which is what a fit seen from the other view would be.
    let d = &runs().dir;
    let contact = image::open(d.join("contact.png")).unwrap().to_rgb8();
    let specs = paintings::materials();
    let layout = Layout { rows: specs.len(), cell: paintings::SIZE };
    let read = |p: &str| image::open(d.join("paintings").join(p)).unwrap().to_rgba8();
    let half = paintings::SIZE as f64 / 2.0;
    for (row, spec) in specs.iter().enumerate() {
        let shown = read(spec.paintings.last().unwrap().file);
        let render = image::open(d.join("renders").join(format!("{}-sphere.png", spec.name))).unwrap().to_rgb8();
        let (px, py) = layout.origin(row, 0);
        let (fx, fy) = layout.origin(row, 1);
        let (mut n, mut painted, mut fit, mut abs, mut abs_other) = (0.0, [0.0f64; 3], [0.0f64; 3], 0.0, 0.0);
        let other = (spec.paintings.len() > 1).then(|| read(spec.paintings[0].file));
        for (i, j, p) in shown.enumerate_pixels() {
            let covered = render.get_pixel(i, j).0.iter().any(|&c| c > 8);
            if p.0[3] < 255 || !covered || other.as_ref().is_some_and(|o| o.get_pixel(i, j).0[3] < 255) {
                continue;
            }
            // A lit sphere's picture is paint only on its disk (the MatCap's corners are not).
            let r = (i as f64 + 0.5 - half).hypot(j as f64 + 0.5 - half);
            if spec.kind == paintings::FitKind::LitSphere && r > 0.95 * half {
                continue;
            }
            let a = contact.get_pixel(px as u32 + i, py as u32 + j).0.map(linear);
            let b = contact.get_pixel(fx as u32 + i, fy as u32 + j).0.map(linear);
            assert_eq!(a, p.0[..3].iter().map(|&c| linear(c)).collect::<Vec<_>>()[..], "painting tile of {}", spec.name);
            n += 1.0;
            for c in 0..3 {
                painted[c] += a[c];
                fit[c] += b[c];
                abs += (a[c] - b[c]).abs() / 3.0;
            }
            if let Some(o) = &other {
                abs_other += (0..3).map(|c| (linear(o.get_pixel(i, j).0[c]) - b[c]).abs() / 3.0).sum::<f64>();
            }
        }
        assert!(n > 10_000.0, "{}: only {n} pixels", spec.name);
        let (painted, fit, abs, abs_other) = (painted.map(|x| x / n), fit.map(|x| x / n), abs / n, abs_other / n);
        let mean = (painted.iter().sum::<f64>() / 3.0).max(1e-3);
        let worst = (0..3).map(|c| (painted[c] - fit[c]).abs()).fold(0.0, f64::max) / mean;
        println!(
            "{:<18} mean painting {painted:.4?} fit {fit:.4?}: {:.2}% of the mean; pixel |diff| {:.2}% (other view {:.2}%)",
            spec.name,
            100.0 * worst,
            100.0 * abs / mean,
            100.0 * abs_other / mean
        );
        // Bounds: measured on this demo (see the printout, `--nocapture`).
        let (mean_bound, pixel_bound) = if spec.name == "toon" { (MEAN_BOUND_MATCAP, PIXEL_BOUND_MATCAP) } else { (MEAN_BOUND, PIXEL_BOUND) };
        assert!(worst < mean_bound, "{}: mean colours differ by {:.2}% of the mean", spec.name, 100.0 * worst);
        assert!(abs / mean < pixel_bound, "{}: pixel |diff| {:.2}% of the mean", spec.name, 100.0 * abs / mean);
        if other.is_some() {
            assert!(abs_other > 10.0 * abs, "{}: the other view's painting is nearly as close as the shown one", spec.name);
        }
    }
}

/// `fit` says when a painting is not one uniform material (issue 11's diagnostics): the
/// striped wood fitted as one product gets the warning with its next step, the plastic
/// does not; both get their coverage line.
#[test]
fn a_uniform_fit_of_the_striped_wood_warns_and_names_the_next_step() {
    use brdfpaint::pipeline::{fit, load_views, Options};
    let d = &runs().dir;
    let mut sampler = SceneSampler::new().unwrap();
    let scene = d.join("sheet").join("scene.gltf");
    let mut notes = |painting: &str| {
        let loaded = load_views(&mut sampler, &[(scene.clone(), d.join("paintings").join(painting))], Erosion::default()).unwrap();
        let fitted = fit(&loaded.views, &Options::default(), None).unwrap();
        (fitted.material.provenance.notes, fitted.notes)
    };
    let (wood, typed) = notes("wood.png");
    assert!(wood.iter().any(|n| n.contains("samples of the") && n.contains("silhouette band")), "{wood:#?}");
    assert!(wood.iter().any(|n| n.contains("not look like one uniform material")), "{wood:#?}");
    assert!(typed.iter().any(|n| n.is_warning() && n.remedy() == Some(brdfpaint::note::Remedy::MaterialMap)), "{typed:#?}");
    let (plastic, typed) = notes("plastic.png");
    assert!(!plastic.iter().any(|n| n.contains("warning")), "{plastic:#?}");
    assert!(!typed.iter().any(|n| n.is_warning()), "{typed:#?}");
}
