//! `brdfpaint demo`: the whole story on bundled paintings, headless, in seconds.
//!
//! 1. The coloring-book sheet of the standard scene (the built-in sphere, `front-left`, 256²)
//!    and of a second view ([`paintings::views`]).
//! 2. The bundled paintings ([`paintings::materials`]): analytic models and MERL fits painted
//!    with brush noise and unpainted gaps, a spatially varying "lacquered wood" (glossy and
//!    matte stripes in u, [`paintings::wood`]) painted from both views, and a Blender MatCap.
//! 3. Each material is fitted exactly as `brdfpaint fit --scene DIR/sheet/scene.gltf --image
//!    DIR/paintings/P.png` fits it: sampled through the G-buffer, prepared through the cache
//!    (a standard scene is prepared once, ever), solved in milliseconds; the wood as `--kind
//!    material-map` on the same prepared system. Where the truth is known, the material is
//!    judged against it on three lights and views nobody painted, at each pixel's whole
//!    query (uv included); the wood, on the pixels whose surface point a painting saw, and
//!    also as one uniform product, for comparison.
//! 4. The recovered materials are rendered on the sphere they were painted on (from the view
//!    whose painting the contact sheet shows beside it, [`shown_view`]) and retargeted
//!    onto the bunny, Suzanne and the teapot under new lights ([`retargets`]); those have no
//!    uvs, and get the sphere's by spherical projection, so a material map wraps around them.
//! 5. A contact sheet ([`contact`]), labelled, and a one-screen summary.
//! 6. Each material on the sphere under the two bundled HDR environments (`assets/hdri/`),
//!    without the key light, tone mapped with Khronos PBR Neutral ([`environments`]).
//!
//! ```text
//! DIR/summary.txt            the summary (its first line marks DIR as a demo directory)
//! DIR/contact.png            rows = materials (named, with what they were painted from);
//!                            painting | fit, painted view | bunny | suzanne | teapot
//! DIR/contact-small.png      the same at half size
//! DIR/sheet/, DIR/sheet-2/   outline.png, reference.png, mask.png, scene.gltf
//! DIR/paintings/*.png        the bundled paintings (wood.png, wood-2.png: the spatially varying one)
//! DIR/materials/NAME/        material.json, factor EXRs (and coefficient textures of a
//!                            material map: materials/lacquered-wood/), report.png
//! DIR/renders/NAME-MODEL.png the renders of the contact sheet
//! DIR/environments.png       rows = environments (city, sunset), columns = materials
//! DIR/renders/NAME-ENV.png   the sphere under each environment
//! ```
//!
//! DIR is written as a whole: everything goes into a temporary sibling first, which then
//! replaces DIR. Only a new or empty directory, or an earlier demo directory, is written.

pub mod brush;
pub mod contact;
pub mod paintings;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::{Error, Result};
use crate::factor::cache::{Cache, Outcome};
use crate::factor::{defaults, Errors, Settings};
use crate::images::Painting;
use crate::material::{Kind, Material};
use crate::pipeline;
use crate::render::{GpuScene, Image, Sheet};
use crate::scene::UvRule;
use crate::study::fidelity::held_out_presets;
use crate::study::{held_out_error, Coverage, StudyView};
use crate::sample::{Erosion, PaintedView, SceneSampler};
use crate::scene::{builtin_model, frame, Preset, Scene};
use paintings::{FitKind, MaterialSpec, SIZE};

/// Where `brdfpaint demo` writes by default.
pub const DEFAULT_DIR: &str = "demo-out";
/// The first line of every demo's summary.txt begins with this; it is what marks a
/// directory as a demo directory that a new demo may replace.
pub const MARK: &str = "brdfpaint demo";
/// Side of the held-out views, pixels (enough pixels to judge, cheap to evaluate).
const HELD_OUT_SIZE: usize = 128;

/// A model the recovered materials are retargeted onto, framed by its own preset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Retarget {
    pub model: &'static str,
    pub preset: Preset,
}

/// The retarget scenes, in contact-sheet order: each under a light no painting used.
pub fn retargets() -> [Retarget; 3] {
    let preset = |name, description, az, el, light| Preset {
        name,
        description,
        view_azimuth_deg: az,
        view_elevation_deg: el,
        light_in_view: light,
    };
    [
        Retarget { model: "bunny", preset: preset("demo-bunny", "light upper right", 20.0, 10.0, [0.9, 0.8, 0.6]) },
        Retarget {
            model: "suzanne",
            preset: preset("demo-suzanne", "light right, low", -20.0, 12.0, [1.0, 0.15, 0.55]),
        },
        Retarget { model: "teapot", preset: preset("demo-teapot", "light left, low", 25.0, 20.0, [-0.85, 0.3, 0.75]) },
    ]
}

/// One fitted material's line of the summary.
#[derive(Clone, Debug)]
pub struct Row {
    pub name: String,
    pub description: String,
    /// Views fitted together.
    pub views: usize,
    pub samples: usize,
    /// `uniform`, or `map/N` for a material map of N terms.
    pub kind: String,
    /// Seconds to prepare (or load from the cache) and to solve.
    pub prepare_s: f64,
    pub solve_s: f64,
    pub outcome: Outcome,
    /// Errors on the painted samples.
    pub errors: Errors,
    /// Relative RMS against the true shading on the held-out views, where it is known.
    pub held_out: Option<f64>,
    /// For a material map: the same held-out error of one uniform product fitted to the same
    /// paintings (what the map gains by varying over the surface).
    pub uniform_held_out: Option<f64>,
}

impl Row {
    /// `hit`, `miss`, `rebuilt` or `none` (no cache).
    pub fn cache_word(&self) -> &'static str {
        match self.outcome {
            Outcome::Hit => "hit",
            Outcome::Miss => "miss",
            Outcome::Rebuilt(_) => "rebuilt",
            Outcome::Uncached(_) => "none",
        }
    }
}

/// What a demo run did.
#[derive(Clone, Debug)]
pub struct Report {
    pub rows: Vec<Row>,
    /// The summary text (also DIR/summary.txt).
    pub summary: String,
    pub total_s: f64,
}

/// What is at the output path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// Nothing, or an empty directory.
    Fresh,
    /// An earlier demo directory.
    Demo,
}

/// Whether a demo may be written to `dir`: nothing is there, an empty directory, or an
/// earlier demo (a summary.txt whose first line begins with [`MARK`]). Anything else is
/// refused with one line, before any work.
pub fn check_output(dir: &Path) -> Result<()> {
    target(dir).map(|_| ())
}

fn target(dir: &Path) -> Result<Target> {
    if crate::commit::output_dir_is_fresh(dir)? {
        return Ok(Target::Fresh);
    }
    let marked = crate::fsio::read_regular(&dir.join("summary.txt"), 1 << 20).is_ok_and(|s| s.starts_with(MARK.as_bytes()));
    if marked {
        Ok(Target::Demo)
    } else {
        Err(Error::input(format!(
            "{} exists and is not a demo directory (no summary.txt written by brdfpaint demo); not overwriting it",
            dir.display()
        )))
    }
}

/// Runs the demo into `dir`, preparing through `cache` (`None`: prepare every time). The
/// demo is staged beside `dir` and replaces it whole; the user's files in an earlier demo
/// are kept ([`crate::commit::StagedDir`]).
pub fn run(dir: &Path, cache: Option<&Cache>) -> Result<Report> {
    let expected = target(dir)?;
    let claim = crate::commit::Claim::new(&[], crate::commit::Legacy::Rewritten);
    let staged = crate::commit::StagedDir::new(dir, claim)?;
    let report = run_into(staged.path(), dir, cache)?;
    // The directory may have changed while the demo ran.
    if target(dir)? != expected {
        return Err(Error::input(format!("{} changed while the demo ran; not overwriting it", dir.display())));
    }
    staged.commit()?;
    Ok(report)
}

/// Timings of the stages, seconds.
#[derive(Default)]
struct Stages {
    sheets: f64,
    fits: f64,
    held_out: f64,
    renders: f64,
    contact: f64,
    environments: f64,
}

fn run_into(tmp: &Path, dir: &Path, cache: Option<&Cache>) -> Result<Report> {
    let start = Instant::now();
    let mut stages = Stages::default();
    let mut sampler = SceneSampler::new()?;

    // 1. The sheets of the painted views.
    let t = Instant::now();
    let scene_paths = sheets(&mut sampler, tmp)?;
    stages.sheets = t.elapsed().as_secs_f64();

    // 2-3. The paintings, fitted as `brdfpaint fit` fits them.
    let t = Instant::now();
    let specs = paintings::materials();
    let fitted = fit_materials(&mut sampler, &specs, tmp, &scene_paths, cache)?;
    stages.fits = t.elapsed().as_secs_f64();

    // Held-out lights and views: the truth against the material where nobody painted.
    let t = Instant::now();
    let rows = held_out_rows(&mut sampler, &specs, &fitted)?;
    stages.held_out = t.elapsed().as_secs_f64();

    // 4. Renders: on the painted sphere, seen from the view (and under the light) of the
    // painting the contact sheet shows beside it, and retargeted.
    let t = Instant::now();
    let (gpu_scenes, renders) = renders(sampler.renderer(), &specs, &fitted, &scene_paths, tmp)?;
    stages.renders = t.elapsed().as_secs_f64();

    // 5. The contact sheet: each row's painting is its last view's, beside the fit seen
    // from that view under that view's light.
    let t = Instant::now();
    contact_sheet(&specs, &fitted, &renders, tmp)?;
    stages.contact = t.elapsed().as_secs_f64();

    // 6. Under the bundled environments.
    let t = Instant::now();
    let spheres: Vec<&GpuScene> = specs.iter().map(|spec| &gpu_scenes[shown_view(spec)]).collect();
    let materials: Vec<(&str, &Material, Option<&Scene>)> =
        specs.iter().zip(&fitted).map(|(spec, f)| (spec.name, &f.material, f.scene.as_ref())).collect();
    environments(sampler.renderer(), &materials, &spheres, tmp)?;
    stages.environments = t.elapsed().as_secs_f64();

    let total_s = start.elapsed().as_secs_f64();
    let summary = summary(&rows, &stages, dir, cache, total_s);
    crate::commit::write_atomic(&tmp.join("summary.txt"), summary.as_bytes())?;
    Ok(Report { rows, summary, total_s })
}

/// Renders and saves the sheet of each painted view into `tmp`; returns their scene.gltf
/// paths, in view order.
fn sheets(sampler: &mut SceneSampler, tmp: &Path) -> Result<Vec<PathBuf>> {
    let mut scene_paths = Vec::new();
    for (k, view) in paintings::views().iter().enumerate() {
        let scene = paintings::view_scene(k)?;
        let sheet = Sheet::render(sampler.renderer(), &scene, SIZE, SIZE)?;
        let path = tmp.join(view.dir);
        sheet.save(&scene, &path)?;
        scene_paths.push(path.join("scene.gltf"));
    }
    Ok(scene_paths)
}

/// Writes the bundled paintings into `tmp/paintings/` and fits each material of `specs`
/// from them ([`fit_material`]).
fn fit_materials(
    sampler: &mut SceneSampler,
    specs: &[MaterialSpec],
    tmp: &Path,
    scene_paths: &[PathBuf],
    cache: Option<&Cache>,
) -> Result<Vec<Fitted>> {
    let settings = Settings::uniform(1, defaults::RES_1D);
    let paintings_dir = tmp.join("paintings");
    std::fs::create_dir_all(&paintings_dir).map_err(|e| Error::io(&paintings_dir, e))?;
    for spec in specs {
        for p in &spec.paintings {
            let path = paintings_dir.join(p.file);
            if !path.exists() {
                crate::commit::write_atomic(&path, p.bytes)?;
            }
        }
    }
    let mut fitted = Vec::new();
    for spec in specs {
        fitted.push(fit_material(sampler, spec, tmp, scene_paths, &settings, cache)?);
    }
    Ok(fitted)
}

/// The summary's rows: each fitted material's, with its held-out errors where the truth is
/// known.
fn held_out_rows(sampler: &mut SceneSampler, specs: &[MaterialSpec], fitted: &[Fitted]) -> Result<Vec<Row>> {
    let held: Vec<StudyView> =
        held_out_presets().iter().map(|p| StudyView::new(sampler, p, HELD_OUT_SIZE)).collect::<Result<_>>()?;
    let mut rows = Vec::new();
    for (spec, f) in specs.iter().zip(fitted) {
        // A spatially varying material is known only where it was painted: it is judged on
        // the held-out pixels whose surface point some painting saw (a held-out view of the
        // back of the sphere shows stripes nobody painted).
        let painted = spec.truth.is_spatial().then(|| Coverage::of(&f.views));
        let judge = |m: &Material| -> Result<Option<f64>> {
            spec.truth.known().map(|t| held_out_error(m, t, &held, painted.as_ref())).transpose()
        };
        let held_out = judge(&f.material)?;
        let uniform_held_out = match &f.uniform {
            Some(u) => judge(u)?,
            None => None,
        };
        rows.push(Row { held_out, uniform_held_out, ..f.row.clone() });
    }
    Ok(rows)
}

/// Renders each fitted material on its painted sphere and on the retargets, writing
/// `renders/NAME-MODEL.png`; returns the scenes uploaded (the painted views', then the
/// retargets') and each material's renders, in contact-sheet order.
fn renders(
    renderer: &mut crate::render::Renderer,
    specs: &[MaterialSpec],
    fitted: &[Fitted],
    scene_paths: &[PathBuf],
    tmp: &Path,
) -> Result<(Vec<GpuScene>, Vec<Vec<Image>>)> {
    let renders_dir = tmp.join("renders");
    std::fs::create_dir_all(&renders_dir).map_err(|e| Error::io(&renders_dir, e))?;
    let mut scenes: Vec<Scene> = scene_paths.iter().map(Scene::load).collect::<Result<_>>()?;
    for r in retargets() {
        scenes.push(frame(UvRule::Auto.apply(builtin_model(r.model)?).0, &r.preset, 1.0));
    }
    let gpu_scenes: Vec<GpuScene> = scenes.iter().map(|s| GpuScene::upload(renderer.gl(), s)).collect::<Result<_>>()?;
    let mut renders: Vec<Vec<Image>> = Vec::new();
    for (spec, f) in specs.iter().zip(fitted) {
        let gpu = renderer.upload(&f.material)?;
        let own = f.scene.as_ref().map(|s| GpuScene::upload(renderer.gl(), s)).transpose()?;
        let sphere = (own.as_ref().unwrap_or(&gpu_scenes[shown_view(spec)]), "sphere");
        let retargeted = gpu_scenes[scene_paths.len()..].iter().zip(retargets()).map(|(s, r)| (s, r.model));
        let mut row = Vec::new();
        for (scene, model) in std::iter::once(sphere).chain(retargeted) {
            let image = renderer.factored(scene, &gpu, SIZE, SIZE)?;
            image.to_rgb().write_png(&renders_dir.join(format!("{}-{model}.png", spec.name)))?;
            row.push(image);
        }
        renders.push(row);
    }
    Ok((gpu_scenes, renders))
}

/// Composes the contact sheet of the paintings and `renders`, and writes it as `contact.png`
/// and `contact-small.png`.
fn contact_sheet(specs: &[MaterialSpec], fitted: &[Fitted], renders: &[Vec<Image>], tmp: &Path) -> Result<()> {
    let columns = contact_columns();
    let sheet_rows: Vec<contact::Row> = specs
        .iter()
        .zip(fitted)
        .zip(renders)
        .map(|((spec, f), r)| contact::Row {
            name: spec.name.to_string(),
            caption: contact_caption(spec, &f.row.description),
            tiles: std::iter::once(contact::Tile::Painting(f.last_painting())).chain(r.iter().map(contact::Tile::Render)).collect(),
        })
        .collect();
    let sheet = contact::compose(SIZE, &columns.each_ref().map(String::as_str), &sheet_rows)?;
    sheet.write_png(&tmp.join("contact.png"))?;
    contact::downsample(&sheet, 2)?.write_png(&tmp.join("contact-small.png"))
}

/// Side of the environment renders, pixels: small, so the demo stays a few seconds.
const ENV_SIZE: usize = 96;
/// Directions per pixel of the environment renders (under half the default: at this size the
/// difference does not show, and the demo stays fast).
const ENV_SAMPLES: usize = 24;

/// Renders each material (name, material, its own scene if it has one) on its sphere
/// under each bundled environment, environment behind, no key light; writes
/// `renders/NAME-ENV.png` and `environments.png` (a row per environment).
fn environments(renderer: &mut crate::render::Renderer, materials: &[(&str, &Material, Option<&Scene>)], spheres: &[&GpuScene], tmp: &Path) -> Result<()> {
    use crate::images::env::{bundled, BUNDLED};
    use crate::images::tone::Tonemap;
    use crate::render::{GpuEnvironment, Lighting};
    let (cols, rows) = (materials.len(), BUNDLED.len());
    let mut sheet = crate::images::Rgb::new(cols * ENV_SIZE, rows * ENV_SIZE)?;
    for (row, (env_name, _)) in BUNDLED.iter().enumerate() {
        let env = GpuEnvironment::upload(renderer.gl(), &bundled(env_name)?)?;
        let lighting = Lighting { samples: ENV_SAMPLES, ..Lighting::new(&env) };
        for (col, ((name, material, own), sphere)) in materials.iter().zip(spheres).enumerate() {
            let gpu = renderer.upload(material)?;
            let own = own.map(|s| GpuScene::upload(renderer.gl(), s)).transpose()?;
            let image = renderer.lit(own.as_ref().unwrap_or(sphere), &gpu, &lighting, ENV_SIZE, ENV_SIZE)?;
            let mut rgb = image.to_rgb();
            for p in &mut rgb.pixels {
                *p = Tonemap::Neutral.map(*p);
            }
            rgb.write_png(&tmp.join("renders").join(format!("{name}-{env_name}.png")))?;
            for j in 0..ENV_SIZE {
                let at = (row * ENV_SIZE + j) * sheet.width + col * ENV_SIZE;
                sheet.pixels[at..at + ENV_SIZE].copy_from_slice(&rgb.pixels[j * ENV_SIZE..(j + 1) * ENV_SIZE]);
            }
        }
    }
    sheet.write_png(&tmp.join("environments.png"))
}

/// The painted view the contact sheet shows for `spec`: its last painting's.
pub fn shown_view(spec: &MaterialSpec) -> usize {
    spec.paintings.last().expect("a material has a painting").view
}

/// The names of the contact sheet's columns.
pub fn contact_columns() -> [String; contact::COLUMNS] {
    let [a, b, c] = retargets().map(|r| format!("{}, new light", r.model));
    ["painting".into(), "fit, painted view".into(), a, b, c]
}

/// What a contact sheet row says after its material's name: what was painted, in which
/// views (named by their sheet directories), and which view the row shows.
fn contact_caption(spec: &MaterialSpec, description: &str) -> String {
    if spec.kind == FitKind::LitSphere {
        return format!("{description}, fitted as a lit sphere");
    }
    let dirs: Vec<String> = spec.paintings.iter().map(|p| format!("{}/", paintings::views()[p.view].dir)).collect();
    match dirs.as_slice() {
        [one] => format!("{description}, painted in {one}"),
        _ => format!(
            "{}, painted in {}; {}/ shown",
            description.trim_end_matches(" (ABC)"),
            dirs.join(" and "),
            paintings::views()[shown_view(spec)].dir
        ),
    }
}

/// A fitted material and what the summary says about it.
struct Fitted {
    material: Material,
    /// For a material map: the uniform product of the same samples, for comparison.
    uniform: Option<Material>,
    views: Vec<PaintedView>,
    /// A lit sphere's own scene (the sheets' scenes otherwise).
    scene: Option<Scene>,
    row: Row,
}

impl Fitted {
    fn last_painting(&self) -> &Painting {
        &self.views.last().expect("a material has a painting").painting
    }
}

/// Fits one material from its paintings through [`crate::pipeline`], exactly as `brdfpaint
/// fit --scene S --image P [--scene S2 --image P2]` fits it with the default settings,
/// writing `materials/NAME/` with its report.png.
fn fit_material(
    sampler: &mut SceneSampler,
    spec: &MaterialSpec,
    tmp: &Path,
    scene_paths: &[PathBuf],
    settings: &Settings,
    cache: Option<&Cache>,
) -> Result<Fitted> {
    if spec.kind == FitKind::LitSphere {
        return fit_lit_sphere(spec, tmp, settings, cache);
    }
    let pairs: Vec<(PathBuf, PathBuf)> =
        spec.paintings.iter().map(|p| (scene_paths[p.view].clone(), tmp.join("paintings").join(p.file))).collect();
    let mut loaded = pipeline::load_views(sampler, &pairs, Erosion::default())?;
    // The analytic base as `brdfpaint fit` chooses it (a material map fits none).
    let mut opts = pipeline::Options { settings: settings.clone(), base: crate::read::lobe::BaseChoice::Auto, ..Default::default() };
    if let FitKind::MaterialMap { terms } = spec.kind {
        opts.kind = Kind::MaterialMap;
        opts.map.terms = terms;
    }
    // Read as `brdfpaint fit` reads paintings (tones, the painter's light).
    loaded.read(&crate::read::Reading::default(), opts.kind)?;
    let mut views = loaded.views;
    // Name the files as they are in DIR, not in the temporary directory.
    for (view, p) in views.iter_mut().zip(&spec.paintings) {
        view.name = format!("paintings/{}", p.file);
        view.source = format!("{}/scene.gltf", paintings::views()[p.view].dir);
    }
    let fitted = pipeline::fit(&views, &opts, cache)?;
    fitted.save(&views, &tmp.join("materials").join(spec.name), &[])?;
    let kind = match fitted.material.kind {
        Kind::MaterialMap | Kind::Hybrid => format!("map/{}", fitted.material.terms.len()),
        Kind::Uniform | Kind::FourFactor => "uniform".to_string(),
    };
    let row = Row {
        name: spec.name.to_string(),
        description: spec.truth.describe(),
        views: views.len(),
        samples: fitted.samples.len(),
        kind,
        prepare_s: fitted.solved.prepare_s,
        solve_s: fitted.solve_s(),
        outcome: fitted.solved.outcome.clone(),
        errors: fitted.errors(),
        held_out: None,
        uniform_held_out: None,
    };
    let uniform = fitted.map.map(|(_, u)| u);
    Ok(Fitted { material: fitted.material, uniform, views, scene: None, row })
}

/// Fits a MatCap as `brdfpaint fit --lit-sphere DIR/paintings/P` does, at the contact
/// sheet's size, writing `materials/NAME/` with its report.png and scene.gltf.
fn fit_lit_sphere(spec: &MaterialSpec, tmp: &Path, settings: &Settings, cache: Option<&Cache>) -> Result<Fitted> {
    let p = spec.paintings.last().expect("a material has a painting");
    let opts = pipeline::Options { settings: settings.clone(), ..Default::default() };
    let lit = crate::litsphere::fit_sized(&tmp.join("paintings").join(p.file), None, &opts, cache, SIZE)?;
    let mut view = lit.view;
    view.name = format!("paintings/{}", p.file);
    view.source = format!("{} (lit sphere)", view.name);
    let views = vec![view];
    let staged = lit.fitted.stage(&views, &tmp.join("materials").join(spec.name))?;
    staged.write("scene.gltf", |path| lit.scene.write_gltf(path))?;
    staged.commit()?;
    let f = &lit.fitted;
    let row = Row {
        name: spec.name.to_string(),
        description: spec.truth.describe(),
        views: 1,
        samples: f.samples.len(),
        kind: "uniform".to_string(),
        prepare_s: f.solved.prepare_s,
        solve_s: f.solve_s(),
        outcome: f.solved.outcome.clone(),
        errors: f.errors(),
        held_out: None,
        uniform_held_out: None,
    };
    Ok(Fitted { material: lit.fitted.material, uniform: None, views, scene: Some(lit.scene), row })
}

/// The one-screen summary.
fn summary(rows: &[Row], stages: &Stages, dir: &Path, cache: Option<&Cache>, total_s: f64) -> String {
    let mut s = String::new();
    summary_header(&mut s, stages, cache);
    summary_table(&mut s, rows);
    summary_legend(&mut s, rows);
    summary_timings(&mut s, stages, total_s);
    let _ = writeln!(s, "wrote {}/: contact.png, contact-small.png, environments.png, summary.txt, sheet/, sheet-2/, paintings/, materials/, renders/", dir.display());
    s
}

/// The summary's first lines: the mark, the sheets and factors, and the prepare cache.
fn summary_header(s: &mut String, stages: &Stages, cache: Option<&Cache>) {
    let _ = writeln!(s, "{MARK} {}: paint a sphere, fit, retarget", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(
        s,
        "sheets: sphere front-left and a second view, {SIZE}x{SIZE} ({:.0} ms); factors p(l) q(h) r(v), 1D, {} nodes",
        stages.sheets * 1e3,
        defaults::RES_1D
    );
    let _ = match cache {
        Some(c) => {
            // The cache's directory: where any of its files goes.
            let file = c.path(&crate::factor::Pattern::default(), &Settings::default());
            writeln!(s, "prepared systems cached in {}", file.parent().unwrap_or(Path::new(".")).display())
        }
        None => writeln!(s, "no prepare cache (no home directory): every system prepared afresh"),
    };
    let _ = writeln!(s);
}

/// The summary's table: a line per fitted material.
fn summary_table(s: &mut String, rows: &[Row]) {
    let _ = writeln!(
        s,
        "{:<18} {:<7} {:<25} {:>7} {:>8} {:>5} {:>8} {:>8} {:>6} {:>6} {:>8}",
        "material", "kind", "painted from", "samples", "prep ms", "cache", "solve ms", "RMS", "rel", "max", "held-out"
    );
    for row in rows {
        let what = if row.views > 1 {
            format!("{}, {} views", row.description.trim_end_matches(" (ABC)"), row.views)
        } else {
            row.description.clone()
        };
        let held = row.held_out.map_or("-".to_string(), |h| format!("{h:.4}"));
        let _ = writeln!(
            s,
            "{:<18} {:<7} {:<25} {:>7} {:>8.1} {:>5} {:>8.2} {:>8.5} {:>6.4} {:>6.3} {:>8}",
            row.name,
            row.kind,
            truncate(&what, 25),
            row.samples,
            row.prepare_s * 1e3,
            row.cache_word(),
            row.solve_s * 1e3,
            row.errors.rms,
            row.errors.rms_relative,
            row.errors.max,
            held
        );
    }
}

/// What the table's columns mean, and what each material map gains over a uniform product.
fn summary_legend(s: &mut String, rows: &[Row]) {
    let _ = writeln!(s);
    let _ = writeln!(s, "RMS, rel (relative RMS) and max: the fit against its painted samples (linear RGB).");
    let _ = writeln!(
        s,
        "held-out: relative RMS against the true shading on {} lights and views nobody painted.",
        held_out_presets().len()
    );
    let _ = writeln!(s, "kind: uniform, one product p(l) q(h) r(v); map/N, a material map of N products blended by uv textures.");
    for row in rows {
        if let (Some(m), Some(u)) = (row.held_out, row.uniform_held_out) {
            let _ = writeln!(s, "{}: held-out {m:.4} as a material map, {u:.4} as one uniform product.", row.name);
            let _ = writeln!(s, "  (judged where the paintings saw the surface: the back of the sphere was never painted)");
        }
    }
    let _ = writeln!(s, "The MatCap is fitted as a lit sphere: its light estimated from the picture.");
}

/// The renders' and stages' timings.
fn summary_timings(s: &mut String, stages: &Stages, total_s: f64) {
    let models: Vec<String> = retargets()
        .iter()
        .map(|r| format!("{} ({})", r.model, r.preset.description.trim_start_matches("light ")))
        .collect();
    let _ = writeln!(s, "renders at {SIZE}x{SIZE}, new lights: {}: {:.0} ms", models.join(", "), stages.renders * 1e3);
    let _ = writeln!(
        s,
        "under environments (city, sunset) at {ENV_SIZE}x{ENV_SIZE}, {ENV_SAMPLES} directions: {:.0} ms",
        stages.environments * 1e3
    );
    let _ = writeln!(
        s,
        "fits {:.0} ms, held-out checks {:.0} ms, contact sheet {:.0} ms; total {:.2} s",
        stages.fits * 1e3,
        stages.held_out * 1e3,
        stages.contact * 1e3,
        total_s
    );
}

fn truncate(text: &str, n: usize) -> String {
    if text.chars().count() <= n {
        text.to_string()
    } else {
        let mut t: String = text.chars().take(n - 1).collect();
        t.push('…');
        t
    }
}
