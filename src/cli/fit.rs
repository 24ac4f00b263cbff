//! `brdfpaint fit`: samples in, material out. The sources: paintings of scenes
//! (`--scene S --image P`, repeatable: thesis 4.1, 4.4), measured MERL data (`--merl`), lit
//! spheres (`--lit-sphere`) and photographs over a normal map (`--normals`, `--photos`:
//! [`super::photos`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::ValueEnum;

use super::photos::{self, LightArg, MapArgs};
use super::Failure;
use brdfpaint::brdf::Merl;
use brdfpaint::error::{Error, Result};
use brdfpaint::factor::cache::{Cache, Outcome};
use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::factor::{prepare, Channels, DifferenceChoice, Fit, Mapping, Pattern, Settings};
use brdfpaint::library;
use brdfpaint::litsphere;
use brdfpaint::read::lobe;
use brdfpaint::note::{Note, Remedy};
use brdfpaint::material::{map, Kind, Material};
use brdfpaint::pipeline::{self, Options};
use brdfpaint::sample::{Erosion, Neighbours, SceneSampler};

#[derive(Clone, Copy, ValueEnum)]
pub(super) enum FactorDim {
    #[value(name = "1d")]
    One,
    #[value(name = "2d")]
    Two,
}

/// Material kinds (DESIGN.md).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum KindArg {
    Uniform,
    FourFactor,
    MaterialMap,
    Hybrid,
}

/// How a lit sphere is read (`--style`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum StyleArg {
    Physical,
    Stylized,
    Auto,
}

/// Whether a lit sphere's brush texture travels with its material (`--texture`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum TextureArg {
    Keep,
    Drop,
}

/// Material-map fitting methods.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum MapFitArg {
    Cluster,
    Greedy,
}

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("source").required(true).multiple(true).args(["merl", "scene", "lit_sphere", "normals", "photos"]))]
pub(super) struct FitArgs {
    /// A scene (glTF: meshes, camera, light) a painting was made in; repeat with --image
    /// for several views (paired in order).
    #[arg(long, value_name = "S.gltf", conflicts_with_all = ["merl", "normals", "photos"], requires = "image")]
    scene: Vec<PathBuf>,
    /// The painting (PNG, JPEG: sRGB; EXR: linear) of the preceding --scene; alpha 0 is
    /// "not painted". With --normals: a photograph, lit by the --light that follows it.
    #[arg(long, value_name = "P.png", conflicts_with_all = ["merl", "lit_sphere", "photos"])]
    image: Vec<PathBuf>,
    /// A measured BRDF in the MERL binary format.
    #[arg(long, value_name = "F.binary", conflicts_with_all = ["lit_sphere", "normals", "photos"])]
    merl: Option<PathBuf>,
    /// A picture of a painted or photographed sphere, or a MatCap (PNG, JPEG, EXR; the disk
    /// anywhere, on a transparent or plain background): its scene is built, and written as
    /// MAT/scene.gltf. Several pictures, or a folder (its PNG, JPEG and EXR files), make a
    /// library: --out LIB gets LIB/NAME/ per picture, LIB/gallery.png and LIB/index.html.
    #[arg(long, value_name = "IMAGE|DIR", num_args = 1.., conflicts_with_all = ["scene", "normals", "photos"])]
    lit_sphere: Vec<PathBuf>,
    /// With --lit-sphere: the longest side a picture is fitted at, 16 to 4096 pixels (a
    /// larger one is box-filtered down). Default 512 for one picture, 256 for a library.
    #[arg(long, value_name = "N", requires = "lit_sphere")]
    max_side: Option<usize>,
    /// With --lit-sphere: the direction towards the light, X,Y,Z in the picture's frame (x
    /// right, y up, z towards the viewer); estimated from the shading when not given.
    /// With --normals: the light of the preceding --image, X,Y,Z towards it in the normal
    /// map's frame, and its colour × intensity R,G,B (divided out; default 1,1,1).
    #[arg(long, value_name = "X,Y,Z[,R,G,B]", value_parser = photos::parse_light, allow_hyphen_values = true, conflicts_with_all = ["merl", "scene", "photos"])]
    light: Vec<LightArg>,
    /// With --lit-sphere: the sphere's outline, a circle of centre CX,CY and radius R in the
    /// picture's pixels (x right, y down from its top-left corner), instead of the one found.
    /// Everything outside it is not a sample.
    #[arg(long, value_name = "CX,CY,R", value_parser = parse_disk, allow_hyphen_values = true, requires = "lit_sphere")]
    disk: Option<litsphere::Disk>,
    /// With --lit-sphere: how the picture is read. physical: as shading, smooth, under a
    /// physical prior; stylized: as drawn (toon, cel): the light from its tone edges, tables
    /// as fine as the picture, its hard terminator and highlight kept; auto: stylized when
    /// 90% of the disk lies in a few (2 to 8) flat tones covering at most half its range of
    /// values, and a note says what was decided.
    #[arg(long, value_enum, default_value = "auto", requires = "lit_sphere")]
    style: StyleArg,
    /// With --lit-sphere: keep the painting's brush texture (its detail over the fitted
    /// material, finer than the shading) and carry it to every model, looked up by the surface
    /// normal in view space as a MatCap is; render and view multiply the relit material by it.
    /// drop (the default): the material alone.
    #[arg(long, value_enum, default_value = "drop", requires = "lit_sphere")]
    texture: TextureArg,
    /// A folder of photographs in the photometric-stereo layout (DiLiGenT's): the images,
    /// filenames.txt naming them, light_directions.txt (one x y z per image),
    /// light_intensities.txt (one r g b per image), mask.png and a normal map (normal.exr,
    /// normal.txt, normal.png or Normal_gt.png; --normals overrides it).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "image", "lit_sphere", "merl"])]
    photos: Option<PathBuf>,
    #[command(flatten)]
    map: MapArgs,
    /// With --scene: fit with each scene's light exactly as given. By default a painting
    /// shaded a few degrees (up to 20) off the scene's light is fitted with the light it was
    /// painted with, when that explains it clearly better, and a note says so.
    #[arg(long, requires = "scene")]
    keep_light: bool,
    /// With --scene: fit a painting of a few flat tones per channel (3 to 12 levels) as
    /// painted. By default its tones are read as the smooth shading between their edges.
    #[arg(long, requires = "scene")]
    keep_tones: bool,
    /// With --scene: fit every painted pixel as painted. By default strokes the fit misses
    /// far more than the rest of the painting (paint over the outline, a stray accent) are
    /// repainted with the shading around them, and a note says how many pixels.
    #[arg(long, requires = "scene")]
    keep_strokes: bool,
    /// Output material directory (with report.png for paintings).
    #[arg(long, value_name = "MAT")]
    out: PathBuf,
    /// Material kind: uniform p(l) q(h) r(v); four-factor (times s(u,v)); material-map (several
    /// uniform terms blended by coefficient textures); hybrid (a material map of four-factor
    /// terms). The last three need paintings of a mesh with texture coordinates.
    #[arg(long, value_enum, default_value = "uniform")]
    kind: KindArg,
    /// Factor tables: 1D isotropic (radius) or 2D (parabolic).
    #[arg(long, value_enum, default_value = "1d")]
    factors: FactorDim,
    /// Table resolution per axis (default: 128 for 1D, 32 for 2D).
    #[arg(long)]
    res: Option<usize>,
    /// A factor of θ_d, the angle between the light and the half vector (half/difference
    /// coordinates), for Fresnel and grazing terms: auto (added to a uniform fit when the
    /// paintings' θ_d spans 20° or more and reaches 45°, as under side or back light), on (`--theta-d`
    /// alone; any kind, --merl too), off (the thesis's p(l) q(h) r(v)).
    #[arg(long, value_name = "WHEN", default_value = "auto", default_missing_value = "on", num_args = 0..=1)]
    theta_d: DifferenceChoice,
    /// Resolution of the uv factor (four-factor, hybrid; default 32), or of the coefficient
    /// textures (material-map; default 256).
    #[arg(long)]
    uv_res: Option<usize>,
    /// Most terms of a material map or hybrid (default 5; fewer when a term stops helping).
    #[arg(long)]
    terms: Option<usize>,
    /// How a material map or hybrid finds its terms: cluster (regions of one material each,
    /// every term fitted to its region: generalizes to new lights and views) or greedy (the
    /// thesis's fit on positive residuals, eqs. 4.2-4.4).
    #[arg(long, value_enum)]
    map_fit: Option<MapFitArg>,
    /// Laplacian smoothing weight of every factor (default: 1e-5 for 1D, 1e-4 for 2D).
    #[arg(long, allow_negative_numbers = true)]
    lambda: Option<f64>,
    /// Log mapping: auto (the one of least error), identity, offset[:A], inverted[:A]
    /// [default: auto]
    #[arg(long)]
    mapping: Option<Mapping>,
    /// Colour channels: independent (each channel on its own, as in the thesis) or coupled
    /// (the shading's shape fitted on luminance, its colour one table at a time, the
    /// painting's colour where the paintings leave it open). Default: independent; for a
    /// lit sphere also coupled (then with the identity mapping) when independent channels
    /// would take colours the picture does not have under a moved light
    #[arg(long, value_name = "HOW")]
    channels: Option<Channels>,
    /// An analytic base under the product of a uniform fit (the product is fitted to
    /// S / B): auto (the lobe of the classic family, GGX, Blinn-Phong, Phong, Ward,
    /// Ashikhmin-Shirley, Oren-Nayar or Minnaert, that fits the paintings as closely as their
    /// brush texture and noise allow, else none), none (the thesis's product), ggx (a GGX
    /// lobe always; better on measured materials, BENCHMARKS.md). Material maps, hybrids and
    /// lit spheres fit no base.
    #[arg(long, default_value = "auto")]
    base: BaseChoice,
    /// Pixels removed along the silhouette: a pixel within N steps (8-neighbourhood) of the
    /// background is not a sample.
    #[arg(long, value_name = "N", default_value_t = 1, allow_negative_numbers = true)]
    erode: i64,
    /// MERL sampling density k: 2k³ (light, view) pairs.
    #[arg(long, default_value_t = 16)]
    density: usize,
}

impl FactorDim {
    fn dim(self) -> usize {
        match self {
            FactorDim::One => 1,
            FactorDim::Two => 2,
        }
    }
}

impl KindArg {
    fn kind(self) -> Kind {
        match self {
            KindArg::Uniform => Kind::Uniform,
            KindArg::FourFactor => Kind::FourFactor,
            KindArg::MaterialMap => Kind::MaterialMap,
            KindArg::Hybrid => Kind::Hybrid,
        }
    }
}

/// Most pixels `--erode` removes along the silhouette.
const MAX_ERODE: i64 = 64;

/// Checks the flags against each other and builds the pipeline's options.
fn options(args: &FitArgs) -> Result<Options> {
    if args.kind != KindArg::Uniform && (args.merl.is_some() || !args.lit_sphere.is_empty()) {
        return Err(Error::input(
            "--kind other than uniform needs paintings of a mesh with texture coordinates, not --merl or --lit-sphere",
        ));
    }
    if args.uv_res.is_some() && args.kind == KindArg::Uniform {
        return Err(Error::input("--uv-res applies to the four-factor, material-map and hybrid kinds"));
    }
    if args.terms.is_some() && matches!(args.kind, KindArg::Uniform | KindArg::FourFactor) {
        return Err(Error::input("--terms applies to the material-map and hybrid kinds"));
    }
    if let Some(t) = args.terms.filter(|t| !(1..=brdfpaint::render::MAX_TERMS).contains(t)) {
        return Err(Error::input(format!("--terms {t} is outside 1..={} (the most terms the renderer draws)", brdfpaint::render::MAX_TERMS)));
    }
    if args.map_fit.is_some() && matches!(args.kind, KindArg::Uniform | KindArg::FourFactor) {
        return Err(Error::input("--map-fit applies to the material-map and hybrid kinds"));
    }
    if let Some(l) = args.lambda.filter(|l| !(l.is_finite() && *l >= 0.0)) {
        return Err(Error::input(format!("--lambda {l}: the smoothing weight is a finite number, 0 or more")));
    }
    let mut opts = Options::new(args.kind.kind(), args.factors.dim(), args.res, args.lambda, args.uv_res)?;
    opts.difference = args.theta_d;
    opts.mapping = args.mapping.unwrap_or_default();
    opts.settings.channels = args.channels.unwrap_or_default();
    opts.keep_colours = args.channels.is_none() && args.mapping.is_none_or(|m| m == Mapping::Auto);
    opts.map.terms = args.terms.unwrap_or(opts.map.terms);
    opts.map.method = match args.map_fit {
        Some(MapFitArg::Greedy) => map::Method::Greedy,
        Some(MapFitArg::Cluster) | None => map::Method::Cluster,
    };
    if let Some(n) = args.max_side.filter(|n| !(litsphere::MIN_SIDE..=4096).contains(n)) {
        return Err(Error::input(format!("--max-side {n}: give {} to 4096 pixels", litsphere::MIN_SIDE)));
    }
    if !(0..=MAX_ERODE).contains(&args.erode) {
        return Err(Error::input(format!("--erode {}: give 0 to {MAX_ERODE} pixels", args.erode)));
    }
    Ok(opts)
}

pub(super) fn run(args: FitArgs) -> std::result::Result<(), Failure> {
    let opts = options(&args)?;
    let photographs = args.map.normals.is_some() || args.photos.is_some();
    if let Some(flag) = args.map.stray_flag().filter(|_| !photographs) {
        return Err(Failure::Usage(format!("{flag} applies to photographs: give --normals N or --photos DIR")));
    }
    if !args.lit_sphere.is_empty() && (args.light.len() > 1 || args.light.iter().any(|l| l.rgb.is_some())) {
        return Err(Failure::Usage("--lit-sphere takes one --light X,Y,Z (its colour comes from the picture; with several pictures it lights them all)".into()));
    }
    let lit_only = [(args.disk.is_some(), "--disk"), (args.style != StyleArg::Auto, "--style"), (args.texture != TextureArg::Drop, "--texture")];
    if let Some((_, flag)) = lit_only.iter().find(|(given, _)| *given && args.lit_sphere.is_empty()) {
        return Err(Failure::Usage(format!("{flag} applies to lit spheres and MatCaps: give --lit-sphere IMAGE")));
    }
    if !args.light.is_empty() && args.lit_sphere.is_empty() && !photographs {
        return Err(Failure::Usage("--light applies to --lit-sphere and to photographs (--normals N --image P --light X,Y,Z)".into()));
    }
    if photographs {
        let input = photos::input(&args.map, args.photos.as_deref(), &args.image, &args.light)?;
        let (views, notes) = photos::load(&input, erosion(&args))?;
        return Ok(fit_and_save(&args, &opts, &views, notes, &input.files())?);
    }
    match (&args.merl, args.lit_sphere.as_slice()) {
        // Dense MERL-style sampling shows every θ_d, but its factor is added only when asked
        // for: it lowers the median of the MERL set and loses a third of its materials by more
        // than 10% (BENCHMARKS.md, "Automatic θ_d").
        (Some(merl), _) => {
            let settings = match args.theta_d {
                DifferenceChoice::On => opts.settings.and_difference(),
                DifferenceChoice::Auto | DifferenceChoice::Off => opts.settings.clone(),
            };
            Ok(run_merl(merl, &args, &settings)?)
        }
        (None, [_, ..]) => {
            let inputs = library::gather(&args.lit_sphere)?;
            match inputs.pictures.as_slice() {
                [one] if !inputs.is_library() => Ok(run_lit_sphere(&one.path, &args, &opts)?),
                _ if args.disk.is_some() => Err(Failure::Usage("--disk gives the circle of one picture, not of a library".into())),
                _ => {
                    let ask = litsphere::Ask { max_side: args.max_side.unwrap_or(super::library::MAX_SIDE), disk: None, ..lit_ask(&args) };
                    Ok(super::library::run(&inputs, ask, &opts, &args.out)?)
                }
            }
        }
        (None, []) => {
            if args.scene.len() != args.image.len() {
                return Err(Failure::Usage(format!(
                    "{} --scene and {} --image: give one --image after each --scene",
                    args.scene.len(),
                    args.image.len()
                )));
            }
            Ok(run_paintings(&args, &opts)?)
        }
    }
}

fn run_merl(merl_path: &Path, args: &FitArgs, settings: &Settings) -> Result<()> {
    let merl = Merl::read(merl_path)?;
    let samples = merl.samples(args.density)?;
    let (pattern, values): (Pattern, _) = Pattern::from_samples(&samples)?;
    let prepared = prepare(&pattern, settings)?;
    let start = Instant::now();
    let fit = prepared.solve(&values, args.mapping.unwrap_or_default())?;
    let solve_s = start.elapsed().as_secs_f64();
    let provenance =
        pipeline::provenance(vec![merl_path.display().to_string()], Some(fit.errors), pattern.len(), prepared.prepare_s, solve_s);
    let plain = Material::from_fit(settings, &fit, provenance.clone())?;
    let blocks = lobe::Blocks::of_directions(&pattern);
    let judged = lobe::Judged { pattern: &pattern, values: &values, blocks: &blocks };
    let material = lobe::fit_based(&prepared, judged, settings, args.mapping.unwrap_or_default(), args.base, Cache::user().as_ref(), provenance)?.unwrap_or(plain);
    pipeline::save_material(&material, &args.out, &[merl_path])?;
    println!(
        "{} samples, {} unknowns: prepare {:.1} ms ({}), solve {:.2} ms",
        pattern.len(),
        prepared.unknowns(),
        prepared.prepare_s * 1e3,
        prepared.solver_kind(),
        solve_s * 1e3
    );
    print_mappings(&fit);
    print_base(&material);
    println!("kept {}; wrote {}", fit.map.name(), args.out.display());
    Ok(())
}

/// What `fit --lit-sphere` asks of one picture.
fn lit_ask(args: &FitArgs) -> litsphere::Ask {
    litsphere::Ask {
        light: args.light.first().map(|l| l.direction),
        disk: args.disk,
        max_side: args.max_side.unwrap_or(litsphere::MAX_SIDE),
        style: match args.style {
            StyleArg::Physical => litsphere::Style::Physical,
            StyleArg::Stylized => litsphere::Style::Stylized,
            StyleArg::Auto => litsphere::Style::Auto,
        },
        res_given: args.res.is_some(),
        smooth_given: args.lambda.is_some(),
        keep_texture: args.texture == TextureArg::Keep,
    }
}

/// A lit sphere or MatCap: find the disk, read it as shading or as drawn, estimate the light
/// (or take --light), fit, and write the material with its report and the scene it was
/// fitted in.
fn run_lit_sphere(image: &Path, args: &FitArgs, opts: &Options) -> Result<()> {
    let lit = litsphere::fit_in(image, &lit_ask(args), opts, Cache::user().as_ref())?;
    let how = match lit.outline {
        litsphere::Outline::Alpha => "its alpha",
        litsphere::Outline::Background => "its background",
        litsphere::Outline::Edges => "the arc its edges show",
        litsphere::Outline::Faint => "a faint arc of its edges, no clear one (the viewer draws the circle; drag it there or give --disk CX,CY,R)",
        litsphere::Outline::Inscribed => "the MatCap layout: the disk inscribed in the square (no other circle shows clearly more of an outline)",
        litsphere::Outline::Given => "--disk",
    };
    println!("{}: outline from {how}; fitted at {}x{} pixels", image.display(), lit.view.painting.width, lit.view.painting.height);
    let l = lit.light;
    match &lit.estimate {
        Some(e) => println!(
            "light estimated at ({:.2}, {:.2}, {:.2}) (x right, y up, z to the viewer){}, sure to within {:.0} degrees; {:.0}% of the disk follows one light (the rest: highlights, strokes, rim light). Correct it with --light X,Y,Z",
            l.x,
            l.y,
            l.z,
            if e.behind { ", behind the sphere" } else { "" },
            e.spread_deg,
            100.0 * e.inliers
        ),
        None => println!("light ({:.2}, {:.2}, {:.2}) as given", l.x, l.y, l.z),
    }
    let fitted = &lit.fitted;
    for note in &fitted.notes {
        say(note);
    }
    lit.save(image, &args.out)?;
    let (report_path, scene_path) = (args.out.join("report.png"), args.out.join("scene.gltf"));
    let e = fitted.errors();
    print_mappings(&fitted.solved.fit);
    println!(
        "{} samples; kept {}: RMS {:.5}  relative {:.4}  max {:.4}; wrote {}, {} and {}",
        fitted.samples.len(),
        fitted.solved.fit.map.name(),
        e.rms,
        e.rms_relative,
        e.max,
        args.out.display(),
        report_path.display(),
        scene_path.display()
    );
    Ok(())
}

/// `CX,CY,R`: three finite numbers, the radius above 0.
fn parse_disk(text: &str) -> std::result::Result<litsphere::Disk, String> {
    let bad = || format!("'{text}' is not a disk CX,CY,R (centre and radius in pixels, e.g. 240,200,150)");
    let v: Vec<f64> = text.split(',').map(|p| p.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| bad())?;
    match v[..] {
        [cx, cy, r] if cx.is_finite() && cy.is_finite() && r.is_finite() && r > 0.0 => Ok(litsphere::Disk { cx, cy, r }),
        [_, _, _] => Err(format!("'{text}': the centre must be finite and the radius above 0")),
        _ => Err(bad()),
    }
}

/// Prints a note, with the option that changes what it describes.
pub(super) fn say(note: &Note) {
    let hint = note.remedy().map(|r| match r {
        Remedy::KeepTones => "--keep-tones fits the tones as painted",
        Remedy::KeepLight => "--keep-light uses the scene's as given",
        Remedy::KeepStrokes => "--keep-strokes fits them as painted",
        Remedy::Erode => "--erode sets the silhouette band",
        Remedy::SecondView => "add one with --scene S2 --image P2",
        Remedy::NoDifferenceFactor => "--theta-d off leaves it out",
        Remedy::MaterialMap => "try --kind material-map",
        Remedy::CameraDirection => "for a world-space normal map give --camera-dir X,Y,Z, toward the camera in the map's frame",
        Remedy::Encoding => "--encoding srgb|linear says how",
        Remedy::GiveDisk => "--disk CX,CY,R gives it",
        Remedy::GiveLight => "--light X,Y,Z gives it",
        Remedy::Style => "--style physical|stylized chooses",
        Remedy::Colours => "--channels independent keeps the thesis's fit",
    });
    let prefix = if note.is_warning() { "" } else { "note: " };
    match hint {
        Some(hint) => println!("{prefix}{note} ({hint})"),
        None => println!("{prefix}{note}"),
    }
}

/// One line on the material's analytic base, when it has one.
fn print_base(material: &Material) {
    if let Some(b) = material.terms.first().and_then(|t| t.base) {
        let e = material.provenance.errors.unwrap_or_default();
        println!(
            "base {}: {}, diffuse {:.3?}, specular {:.3?}, Fresnel {:.3?}; with the product RMS {:.5}  relative {:.4}",
            b.lobe.name(),
            b.width(),
            b.diffuse,
            b.specular,
            b.fresnel,
            e.rms,
            e.rms_relative
        );
    }
}

fn print_mappings(fit: &Fit) {
    for (map, e) in &fit.tried {
        println!("  mapping {:<8} RMS {:.5}  relative {:.4}  max {:.4}", map.name(), e.rms, e.rms_relative, e.max);
    }
}

/// Paintings of scenes through the pipeline; nothing is written unless everything succeeds
/// up to the save.
fn run_paintings(args: &FitArgs, opts: &Options) -> Result<()> {
    let mut sampler = SceneSampler::new()?;
    let erosion = erosion(args);
    let pairs: Vec<(PathBuf, PathBuf)> = args.scene.iter().cloned().zip(args.image.iter().cloned()).collect();
    let mut loaded = pipeline::load_views(&mut sampler, &pairs, erosion)?;
    loaded.read(&brdfpaint::read::Reading { smooth_tones: !args.keep_tones, register_light: !args.keep_light, repaint_strays: !args.keep_strokes }, opts.kind)?;
    let pipeline::Loaded { views, notes, .. } = loaded;
    for note in &notes {
        say(note);
    }
    let inputs: Vec<&Path> = args.scene.iter().chain(&args.image).map(PathBuf::as_path).collect();
    fit_and_save(args, opts, &views, notes, &inputs)
}

/// The silhouette erosion of --erode.
fn erosion(args: &FitArgs) -> Erosion {
    // Checked to lie in 0..=MAX_ERODE by `options`.
    Erosion { radius: args.erode as usize, neighbours: Neighbours::Eight }
}

/// Fits views read (and noted) by the caller through the pipeline, writes the material,
/// keeping `inputs` found in the output folder, and prints the errors.
fn fit_and_save(args: &FitArgs, opts: &Options, views: &[brdfpaint::sample::PaintedView], notes: Vec<Note>, inputs: &[&Path]) -> Result<()> {
    let opts = &Options { base: args.base, ..opts.clone() };
    let mut fitted = pipeline::fit(views, opts, Cache::user().as_ref())?;
    print_base(&fitted.material);
    // How the paintings were read goes into material.json too, before the fit's own notes.
    fitted.prepend_notes(&notes);
    if let Some((report, _)) = &fitted.map {
        let what = match opts.map.method {
            map::Method::Greedy => "terms on positive residuals",
            map::Method::Cluster => "region(s), each sample against its region's product",
        };
        for (k, e) in report.errors.iter().enumerate() {
            println!("{} {what}: RMS {:.5}  relative {:.4}  max {:.4}", k + 1, e.rms, e.rms_relative, e.max);
        }
    }
    for note in &fitted.notes[notes.len()..] {
        say(note);
    }
    let per_view = fitted.view_errors(views);
    let report_path = fitted.save(views, &args.out, inputs)?;

    for (k, (view, e)) in views.iter().zip(&per_view).enumerate() {
        println!(
            "view {}: {} in {}: {} samples; RMS {:.5}  relative {:.4}  max {:.4}",
            k + 1,
            view.name,
            view.source,
            fitted.samples.per_view[k],
            e.rms,
            e.rms_relative,
            e.max
        );
    }
    let solved = &fitted.solved;
    let cache_note = match &solved.outcome {
        Outcome::Hit => "cache hit".to_string(),
        Outcome::Miss => "cache miss, stored".to_string(),
        Outcome::Rebuilt(why) => format!("cache file rebuilt ({why})"),
        Outcome::Uncached(why) => format!("not cached: {why}"),
    };
    println!(
        "{} samples, {} unknowns: prepare {:.1} ms ({}, {}), solve {:.2} ms",
        fitted.samples.len(),
        solved.prepared.unknowns(),
        solved.prepare_s * 1e3,
        solved.prepared.solver_kind(),
        cache_note,
        solved.solve_s * 1e3
    );
    let e = fitted.errors();
    let m = &fitted.material;
    match &fitted.map {
        Some((report, _)) => println!(
            "{} with {} terms (fitted in {:.1} ms): RMS {:.5}  relative {:.4}  max {:.4}; wrote {} and {}",
            if m.kind == Kind::Hybrid { "hybrid" } else { "material map" },
            m.terms.len(),
            report.seconds * 1e3,
            e.rms,
            e.rms_relative,
            e.max,
            args.out.display(),
            report_path.display()
        ),
        None => {
            // The mappings tried by the plain product; with a base, the material's own
            // mapping (chosen the same way for S / B) is the one kept.
            print_mappings(&solved.fit);
            println!(
                "kept {}: RMS {:.5}  relative {:.4}  max {:.4}; wrote {} and {}",
                m.terms[0].map.name(),
                e.rms,
                e.rms_relative,
                e.max,
                args.out.display(),
                report_path.display()
            );
        }
    }
    Ok(())
}
