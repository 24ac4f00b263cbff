//! `brdfpaint view`: the real-time window, live painting and watch mode.

use std::path::PathBuf;
use std::time::Duration;

use brdfpaint::error::{Error, Result};
use brdfpaint::images::env::{bundled, Environment, BUNDLED};
use brdfpaint::images::tone::Tonemap;
use brdfpaint::library;
use brdfpaint::material::Material;
use brdfpaint::scene::model_meshes;
use brdfpaint::viewer::{self, EnvStart, Mode, Options, Start};

#[derive(clap::Args)]
pub(super) struct ViewArgs {
    /// A material directory to show (default: the fit of the bundled example painting), or a
    /// library (`fit --lit-sphere DIR/ --out LIB`) to step through with Page Up / Page Down.
    #[arg(value_name = "MAT")]
    material: Option<PathBuf>,
    /// The model to show it on: a .glb/.gltf file or a built-in name (sphere, bunny, suzanne,
    /// teapot, apple, fox).
    #[arg(long, value_name = "M.glb|NAME", default_value = "bunny")]
    model: String,
    /// Texture coordinates of the models shown: auto (the mesh's, or a spherical projection
    /// where it has none), mesh, spherical or box, as in `render`.
    #[arg(long, value_name = "RULE", default_value = "auto")]
    uv: brdfpaint::scene::UvRule,
    /// Paint (or watch) a view of this scene instead of the standard views.
    #[arg(long, value_name = "S.gltf")]
    scene: Option<PathBuf>,
    /// Refit whenever another program rewrites this painting of --scene.
    #[arg(long, value_name = "P.png", requires = "scene")]
    watch: Option<PathBuf>,
    /// Open a picture of a painted sphere or a MatCap (PNG, JPEG, EXR) as the view to paint:
    /// fitted as `fit --lit-sphere` fits it, its estimated light drawn as a sun over the
    /// sphere, to drag.
    #[arg(long, value_name = "IMAGE", conflicts_with_all = ["scene", "watch"])]
    lit_sphere: Option<PathBuf>,
    /// Start in paint mode.
    #[arg(long)]
    paint: bool,
    /// The model the standard views show for painting.
    #[arg(long, value_name = "NAME", default_value = "sphere")]
    paint_model: String,
    /// Painting size in pixels (square standard views; the height of a --scene view).
    #[arg(long, value_name = "N", default_value_t = brdfpaint::live::DEFAULT_SIZE)]
    size: usize,
    /// Window size.
    #[arg(long, value_name = "WxH", default_value = "1280x800")]
    window: String,
    /// Draw this many frames, then exit (for tests and scripts).
    #[arg(long, value_name = "N")]
    frames: Option<u64>,
    /// With --frames: save the window's pixels (and OUT.json with the camera and light).
    #[arg(long, value_name = "OUT.png", requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Render the 3D view at this fraction of the window's resolution (0.25 to 1; also in the
    /// panel): on software GL a large window's frame costs in proportion to its pixels.
    /// Default: chosen from frame times, to keep 30 frames a second.
    #[arg(long, value_name = "F")]
    render_scale: Option<f32>,
    /// Show the material under an HDR environment: a bundled one (city, sunset) or a 2:1
    /// .hdr/.exr file (also in the panel, or dropped on the window).
    #[arg(long, value_name = "NAME|FILE")]
    env: Option<String>,
    /// Turn the environment about +y by DEG degrees, as `render --env-rotate`.
    #[arg(long, value_name = "DEG", requires = "env", allow_hyphen_values = true)]
    env_rotate: Option<f32>,
    /// Exposure under the environment, in stops, as `render --exposure`.
    #[arg(long, value_name = "EV", requires = "env", allow_hyphen_values = true)]
    exposure: Option<f32>,
    /// Tone mapping under the environment: neutral (default), aces or none.
    #[arg(long, value_name = "NAME", requires = "env", value_parser = Tonemap::NAMES)]
    tonemap: Option<String>,
    /// Environment directions per pixel when the view is still (8 to 1024; default 64, also
    /// in the panel); a moving view takes 8.
    #[arg(long, value_name = "N", requires = "env")]
    env_samples: Option<usize>,
    /// With --frames: keep the window open this many seconds after the last frame.
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, requires = "frames")]
    hold: f64,
}

pub(super) fn run(args: ViewArgs) -> Result<()> {
    // Everything that can fail on input is checked before a window opens.
    let (w, h) = super::parse_size("--window", &args.window, 64..=16384)?;
    let window = [w as u32, h as u32];
    brdfpaint::images::check_size(args.size, args.size)?;
    if !(16..=4096).contains(&args.size) {
        return Err(Error::input(format!("painting size {} is outside 16..=4096", args.size)));
    }
    let is_library = args.material.as_deref().is_some_and(|p| p.join(library::MANIFEST).is_file() && !p.join("material.json").exists());
    let (material, library) = match &args.material {
        Some(p) if is_library => (None, Some(open_library(p)?)),
        Some(p) => (Some((p.display().to_string(), Material::load(p)?)), None),
        None => (None, None),
    };
    let model = (args.model.clone(), model_meshes(&args.model)?);
    model_meshes(&args.paint_model)?;
    let scene = match &args.scene {
        Some(p) => Some((p.display().to_string(), load_scene(p)?)),
        None => None,
    };
    let min = brdfpaint::viewer::MIN_RENDER_SCALE;
    if let Some(s) = args.render_scale.filter(|s| !(min..=1.0).contains(s)) {
        return Err(Error::input(format!("--render-scale {s} is outside {min}..=1")));
    }
    // Read and its light estimated before a window opens: a bad picture is one line.
    let lit_sphere = match &args.lit_sphere {
        Some(p) => Some(brdfpaint::live::SphereSession::open(p, None)?),
        None => None,
    };
    let env = match &args.env {
        Some(name) => {
            let environment =
                if BUNDLED.iter().any(|(n, _)| n == name) { bundled(name)? } else { Environment::load(std::path::Path::new(name))? };
            let rotate_deg = args.env_rotate.unwrap_or(0.0);
            if !rotate_deg.is_finite() {
                return Err(Error::input(format!("--env-rotate {rotate_deg}: give an angle in degrees")));
            }
            let ev = args.exposure.unwrap_or(0.0);
            if !(ev.is_finite() && ev.abs() <= 64.0) {
                return Err(Error::input(format!("--exposure {ev}: give a number of stops from -64 to 64")));
            }
            let tonemap = args.tonemap.as_deref().map(Tonemap::parse).transpose()?.unwrap_or(Tonemap::Neutral);
            let samples = args.env_samples.unwrap_or(brdfpaint::render::env::DEFAULT_SAMPLES);
            let range = brdfpaint::render::env::SAMPLES;
            if !range.contains(&samples) {
                return Err(Error::input(format!(
                    "--env-samples {samples}: give {} to {} directions per pixel",
                    range.start(),
                    range.end()
                )));
            }
            Some(EnvStart { name: name.clone(), environment, rotate_deg, ev, tonemap, samples })
        }
        None => None,
    };
    let mode = if args.paint || args.watch.is_some() { Mode::Paint } else { Mode::View };
    let start = Start {
        model,
        material,
        scene,
        watch: args.watch,
        paint_model: args.paint_model,
        size: args.size,
        mode,
        render_scale: args.render_scale,
        uv: args.uv,
    };
    let hold = if args.hold.is_finite() && args.hold > 0.0 { Duration::from_secs_f64(args.hold.min(3600.0)) } else { Duration::ZERO };
    viewer::run(Options { start, lit_sphere, env, library, window, frames: args.frames.map(|n| n.max(1)), screenshot: args.screenshot, hold })
}

/// The materials of the library at `dir` (`fit --lit-sphere DIR/ --out LIB`), in its
/// gallery's order. A material that no longer loads is one line and left out.
fn open_library(dir: &std::path::Path) -> Result<(String, Vec<(String, Material)>)> {
    let manifest = library::Manifest::read(dir)?;
    let mut materials = Vec::new();
    for entry in &manifest.materials {
        match Material::load(&dir.join(&entry.name)) {
            Ok(m) => materials.push((entry.name.clone(), m)),
            Err(e) => eprintln!("note: {e} (left out of the library)"),
        }
    }
    if materials.is_empty() {
        return Err(Error::input(format!("{}: none of the library's materials loads", dir.display())));
    }
    Ok((dir.display().to_string(), materials))
}

/// Loads `view --scene`'s scene. A scene without a camera or light gets `view`'s own way
/// out: its standard views of the model.
fn load_scene(path: &std::path::Path) -> brdfpaint::Result<brdfpaint::scene::Scene> {
    brdfpaint::scene::Scene::load(path).map_err(|e| match e {
        brdfpaint::Error::Format { path, reason } if reason.contains("preset views instead") => {
            let model = path.display();
            let reason = reason.replace(
                "frame the model in one of the preset views instead",
                &format!("paint its standard views with `view --paint --paint-model {model}`, or only look at it with `view --model {model}`"),
            );
            brdfpaint::Error::Format { path, reason }
        }
        e => e,
    })
}
