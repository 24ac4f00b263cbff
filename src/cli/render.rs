//! `brdfpaint render`: a material on a scene, headless, to PNG or EXR; and the scene options
//! that `render` and `sheet` share.

use std::path::{Path, PathBuf};

use glam::Vec3;

use brdfpaint::error::{Error, Result};
use brdfpaint::gl::{HeadlessContext, Limits};
use brdfpaint::images::env::Environment;
use brdfpaint::images::tone::{exposure_scale, Tonemap};
use brdfpaint::images::{srgb_to_linear, Rgb};
use brdfpaint::material::Material;
use brdfpaint::render::env::{DEFAULT_SAMPLES, SAMPLES};
use brdfpaint::render::orbit::{orbit_centre, orbit_frame};
use brdfpaint::render::{Background, GpuEnvironment, GpuScene, Image, Lighting, Orbit, Renderer};
use brdfpaint::scene::{self, Projection, Scene, UvRule};

use super::Failure;

/// Default image height (and width, unless a scene's camera sets the aspect).
const DEFAULT_SIDE: usize = 512;
/// Largest image side accepted.
pub(super) const MAX_SIDE: usize = 16384;
/// Most frames of a sequence.
const MAX_FRAMES: usize = 10_000;
/// Allowed disagreement of the camera's aspectRatio with W/H (DESIGN.md, Conventions).
const ASPECT_TOLERANCE: f32 = 0.01;
/// Largest exposure, in stops either way (2^64 is far past any radiance a file holds).
const MAX_EV: f32 = 64.0;

/// Where the scene comes from: a glTF scene, or a model framed by a preset.
#[derive(clap::Args)]
pub(super) struct SceneArgs {
    /// A glTF 2.0 scene (.gltf or .glb): meshes, one camera, one light.
    #[arg(long, value_name = "S.gltf", conflicts_with_all = ["model", "preset"])]
    scene: Option<PathBuf>,
    /// A model to frame with --preset: a built-in name (sphere, bunny, suzanne, teapot, apple,
    /// fox) or a .glb/.gltf file (its cameras and lights are ignored).
    #[arg(long, value_name = "M.glb|NAME")]
    model: Option<PathBuf>,
    /// Standard view and light for --model: front-left (default), front-right, front, top,
    /// side, back, rim.
    #[arg(long, value_name = "NAME", requires = "model")]
    preset: Option<String>,
    /// Image size in pixels, WxH: 1 to 16384 per side, at most 4096x4096 pixels in all.
    /// Default 512x512; with --scene and a camera aspectRatio, 512 high at that aspect.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
}

/// A resolved scene and image size.
pub(super) struct Resolved {
    pub scene: Scene,
    pub width: usize,
    pub height: usize,
    /// How to name the scene in messages.
    pub name: String,
}

impl SceneArgs {
    /// Parses the size, loads or frames the scene, and checks the camera's aspect against
    /// the size. Presets are framed at aspect W/H.
    pub(super) fn resolve(&self) -> Result<Resolved> {
        let size = self.size.as_deref().map(parse_size).transpose()?;
        if let Some(path) = &self.scene {
            let scene = scene::load(path)?;
            let file_aspect = match scene.camera.projection {
                Projection::Perspective { aspect, .. } => aspect,
                Projection::Orthographic { .. } => None,
            };
            let (width, height) = match (size, file_aspect) {
                (Some(s), _) => s,
                (None, Some(a)) => (((DEFAULT_SIDE as f32 * a).round() as usize).clamp(1, MAX_SIDE), DEFAULT_SIDE),
                (None, None) => (DEFAULT_SIDE, DEFAULT_SIDE),
            };
            if let Some(a) = file_aspect {
                let image = width as f32 / height as f32;
                if (a - image).abs() > ASPECT_TOLERANCE * a {
                    return Err(Error::format(
                        path,
                        format!(
                            "the camera's aspectRatio is {a:.4} but the image is {width}x{height} (aspect {image:.4}); give --size with the camera's aspect"
                        ),
                    ));
                }
            }
            check_pixels(width, height)?;
            Ok(Resolved { scene, width, height, name: path.display().to_string() })
        } else {
            let model = self.model.as_ref().expect("clap requires --scene or --model");
            let preset_name = self.preset.as_deref().unwrap_or(scene::presets()[0].name);
            let preset = scene::preset(preset_name)?;
            let (width, height) = size.unwrap_or((DEFAULT_SIDE, DEFAULT_SIDE));
            check_pixels(width, height)?;
            let meshes = scene::model_meshes(model)?;
            let scene = scene::frame(meshes, &preset, width as f32 / height as f32);
            Ok(Resolved { scene, width, height, name: format!("{} ({preset_name})", model.display()) })
        }
    }
}

/// `WxH` with both sides in 1..=[`MAX_SIDE`].
pub(super) fn parse_size(text: &str) -> Result<(usize, usize)> {
    super::parse_size("--size", text, 1..=MAX_SIDE)
}

/// The renderer's pixel budget ([`Limits::MAX_PIXELS`]).
fn check_pixels(width: usize, height: usize) -> Result<()> {
    if width * height > Limits::MAX_PIXELS {
        return Err(Error::input(format!(
            "--size {width}x{height}: {} pixels is more than the {} the renderer draws (e.g. 4096x4096)",
            width * height,
            Limits::MAX_PIXELS
        )));
    }
    Ok(())
}

#[derive(clap::Args)]
#[command(group = clap::ArgGroup::new("geometry").required(true).args(["scene", "model", "normals"]))]
pub(super) struct RenderArgs {
    /// Material directory (or its material.json).
    #[arg(value_name = "MAT")]
    material: PathBuf,
    #[command(flatten)]
    scene: SceneArgs,
    /// With --normals: the view of a photograph re-rendered, to compare with it (its size is
    /// the normal map's; PNG 16-bit, sRGB unless --encoding linear).
    #[command(flatten)]
    map: super::photos::MapArgs,
    /// With --normals: the light, X,Y,Z towards it in the normal map's frame, and its colour
    /// × intensity R,G,B (default 1,1,1).
    #[arg(long, value_name = "X,Y,Z[,R,G,B]", requires = "normals", allow_hyphen_values = true)]
    light: Option<String>,
    /// Output image: .png (sRGB, 8-bit, tone mapped into [0, 1]: --tonemap) or .exr (linear
    /// float). Background: --background. With a sequence option, frames are R-000.png,
    /// R-001.png, ...
    #[arg(long, value_name = "R.png|R.exr")]
    out: PathBuf,
    /// N frames with the camera orbiting the model's vertical axis (the light stays).
    #[arg(long, value_name = "N", conflicts_with = "light_sweep")]
    turntable: Option<usize>,
    /// N frames with the light orbiting the model's vertical axis (the camera stays).
    #[arg(long, value_name = "N")]
    light_sweep: Option<usize>,
    /// Texture coordinates: auto (the mesh's, or a spherical projection where it has none),
    /// mesh, spherical or box. Spatially varying materials need them.
    #[arg(long, value_name = "RULE", default_value = "auto")]
    uv: UvRule,
    /// Light the material with an HDR environment: an equirectangular (2:1) OpenEXR or
    /// Radiance .hdr, row 0 at the zenith (+y), the centre column looking along -z. The
    /// scene's light stays as the key light (--key-light).
    #[arg(long, value_name = "E.exr|E.hdr")]
    env: Option<PathBuf>,
    /// Turn the environment about the vertical (+y) axis by DEG degrees, counter-clockwise
    /// seen from above.
    #[arg(long, value_name = "DEG", requires = "env", allow_hyphen_values = true)]
    env_rotate: Option<f32>,
    /// Environment directions sampled per pixel, 8 to 1024 (default 32).
    #[arg(long, value_name = "N", requires = "env")]
    env_samples: Option<usize>,
    /// With --env, keep the scene's light as a key light beside the environment (on, the
    /// default) or drop it (off).
    #[arg(long, value_name = "on|off", requires = "env", value_parser = ["on", "off"])]
    key_light: Option<String>,
    /// Exposure in stops: the image is scaled by 2^EV (PNG and EXR; default 0).
    #[arg(long, value_name = "EV", allow_hyphen_values = true)]
    exposure: Option<f32>,
    /// Tone mapping of a PNG: neutral (Khronos PBR Neutral), aces, or none (clamp). Default
    /// neutral with --env; none without, so a material rendered in the scene it was
    /// painted in reproduces the painting. An EXR stays linear and is never tone mapped.
    #[arg(long, value_name = "NAME", value_parser = Tonemap::NAMES)]
    tonemap: Option<String>,
    /// Behind the object: env (the environment, default with --env), black (default
    /// without), or a colour as #rrggbb (sRGB) or R,G,B (linear floats).
    #[arg(long, value_name = "env|black|COLOR")]
    background: Option<String>,
}

/// What the command line asked behind the object.
#[derive(Clone, Copy, Debug, PartialEq)]
enum BackgroundArg {
    Environment,
    Color(Vec3),
}

/// `env`, `black`, `#rrggbb` (sRGB-encoded, decoded to linear) or `R,G,B` (linear,
/// finite, non-negative).
fn parse_background(text: &str) -> std::result::Result<BackgroundArg, String> {
    let bad = || format!("--background {text}: expected env, black, #rrggbb or R,G,B");
    match text {
        "env" => return Ok(BackgroundArg::Environment),
        "black" => return Ok(BackgroundArg::Color(Vec3::ZERO)),
        _ => {}
    }
    if let Some(hex) = text.strip_prefix('#') {
        if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(bad());
        }
        let channel = |k: usize| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).map_err(|_| bad());
        let rgb = [channel(0)?, channel(1)?, channel(2)?].map(|c| srgb_to_linear(c as f32 / 255.0));
        return Ok(BackgroundArg::Color(Vec3::from_array(rgb)));
    }
    let parts: Vec<f32> = text.split(',').map(|p| p.trim().parse::<f32>()).collect::<std::result::Result<_, _>>().map_err(|_| bad())?;
    match parts[..] {
        [r, g, b] if parts.iter().all(|x| x.is_finite() && *x >= 0.0) => Ok(BackgroundArg::Color(Vec3::new(r, g, b))),
        _ => Err(bad()),
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Format {
    Png,
    Exr,
}

/// How a rendered frame becomes an image file: background, exposure, tone mapping.
struct Develop {
    /// A flat background composited where no object is (drawn by the renderer with --env).
    background: Option<Vec3>,
    scale: f32,
    /// `None` for EXR: linear.
    tonemap: Option<Tonemap>,
}

impl Develop {
    fn apply(&self, image: &Image) -> Rgb {
        let pixels = image
            .pixels
            .iter()
            .map(|p| {
                // Alpha is the object's coverage (0 or 1: no multisampling).
                let c = match self.background {
                    Some(b) if p[3] == 0.0 => b.to_array(),
                    _ => [p[0], p[1], p[2]],
                };
                let c = c.map(|x| x * self.scale);
                self.tonemap.map_or(c, |t| t.map(c))
            })
            .collect();
        Rgb { width: image.width, height: image.height, pixels }
    }
}

pub(super) fn run(args: RenderArgs) -> std::result::Result<(), Failure> {
    if args.map.normals.is_some() {
        return run_photo(args);
    }
    if let Some(flag) = args.map.stray_flag() {
        return Err(Failure::Usage(format!("{flag} applies to renders over a normal map (--normals)")));
    }
    let output = Output::check(&args)?;
    let environment = args.env.as_deref().map(Environment::load).transpose()?;
    let (orbit, frames) = orbit_of(&args)?;
    let (material, json) = load_material(&args.material)?;
    let resolved = scene_for(&args, &material, &json)?;
    let sequence = orbit.map(|_| sequence_of(&args.out));
    let paths = frame_paths(&args.out, sequence.as_ref(), frames);
    let job = Job { output, environment, orbit, frames, material, resolved };
    job.draw(&paths, sequence)?;
    println!("{}", job.report(&args, &paths));
    Ok(())
}

/// The checked options of a scene render that shape its image: file format, background,
/// exposure, tone mapping, and how an environment lights it.
struct Output {
    format: Format,
    background: Option<BackgroundArg>,
    ev: f32,
    tonemap: Option<Tonemap>,
    rotate_deg: f32,
    samples: usize,
    key_light: bool,
}

impl Output {
    fn check(args: &RenderArgs) -> std::result::Result<Output, Failure> {
        let format = match args.out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Format::Png,
            Some("exr") => Format::Exr,
            _ => {
                return Err(Error::input(format!("{}: the output must be a .png or .exr file", args.out.display())).into());
            }
        };
        let background = args.background.as_deref().map(parse_background).transpose().map_err(Failure::Usage)?;
        if background == Some(BackgroundArg::Environment) && args.env.is_none() {
            return Err(Failure::Usage("--background env needs --env".into()));
        }
        let ev = exposure(args)?;
        let tonemap = match (format, args.tonemap.as_deref()) {
            (Format::Exr, Some(_)) => {
                return Err(Failure::Usage("--tonemap applies to PNG output; an EXR stays linear".into()));
            }
            (Format::Exr, None) => None,
            (Format::Png, Some(name)) => Some(Tonemap::parse(name)?),
            (Format::Png, None) => Some(if args.env.is_some() { Tonemap::Neutral } else { Tonemap::None }),
        };
        let rotate_deg = args.env_rotate.unwrap_or(0.0);
        if !rotate_deg.is_finite() {
            return Err(Failure::Usage(format!("--env-rotate {rotate_deg}: give an angle in degrees")));
        }
        let samples = args.env_samples.unwrap_or(DEFAULT_SAMPLES);
        if !SAMPLES.contains(&samples) {
            return Err(Failure::Usage(format!(
                "--env-samples {samples}: give {} to {} directions per pixel",
                SAMPLES.start(),
                SAMPLES.end()
            )));
        }
        let key_light = args.key_light.as_deref() != Some("off");
        Ok(Output { format, background, ev, tonemap, rotate_deg, samples, key_light })
    }

    /// How `environment` lights the scene and what shows behind the object.
    fn lighting<'a>(&self, environment: &'a GpuEnvironment) -> Lighting<'a> {
        Lighting {
            environment,
            rotate_deg: self.rotate_deg,
            key_light: self.key_light,
            background: match self.background {
                Some(BackgroundArg::Color(c)) => Background::Color(c),
                _ => Background::Environment,
            },
            samples: self.samples,
        }
    }

    /// How frames become files; `lit`: under an environment, which draws the background itself.
    fn develop(&self, lit: bool) -> Develop {
        Develop {
            background: match (lit, self.background) {
                (false, Some(BackgroundArg::Color(c))) => Some(c),
                _ => None,
            },
            scale: exposure_scale(self.ev),
            tonemap: self.tonemap,
        }
    }
}

/// `--exposure`, in stops, within [`MAX_EV`] either way (default 0).
fn exposure(args: &RenderArgs) -> std::result::Result<f32, Failure> {
    let ev = args.exposure.unwrap_or(0.0);
    if !(ev.is_finite() && ev.abs() <= MAX_EV) {
        return Err(Failure::Usage(format!("--exposure {ev}: give a number of stops from -{MAX_EV} to {MAX_EV}")));
    }
    Ok(ev)
}

/// The sequence asked for (`--turntable`, `--light-sweep`), if any, and its frames: 1 for a
/// single image.
fn orbit_of(args: &RenderArgs) -> Result<(Option<Orbit>, usize)> {
    let (orbit, frames) = match (args.turntable, args.light_sweep) {
        (Some(n), _) => (Some(Orbit::Camera), n),
        (None, Some(n)) => (Some(Orbit::Light), n),
        (None, None) => (None, 1),
    };
    if orbit.is_some() && !(1..=MAX_FRAMES).contains(&frames) {
        return Err(Error::input(format!("a sequence needs 1 to {MAX_FRAMES} frames, not {frames}")));
    }
    Ok((orbit, frames))
}

/// The material at `path`, checked to be one the renderer draws, and its material.json (what
/// errors about it name).
fn load_material(path: &Path) -> Result<(Material, PathBuf)> {
    let material = Material::load(path)?;
    let json = if path.is_dir() { path.join("material.json") } else { path.to_path_buf() };
    brdfpaint::render::check(&material).map_err(|e| Error::format(&json, e.to_string()))?;
    Ok((material, json))
}

/// The scene, its meshes given texture coordinates by `--uv`, checked to have them where
/// `material` (its material.json `json`) looks them up.
fn scene_for(args: &RenderArgs, material: &Material, json: &Path) -> Result<Resolved> {
    let Resolved { mut scene, width, height, name } = args.scene.resolve()?;
    let (meshes, note) = args.uv.apply(std::mem::take(&mut scene.meshes));
    scene.meshes = meshes;
    if material.needs_uv() {
        if let Some(k) = scene.meshes.iter().position(|m| m.uvs.is_none()) {
            return Err(Error::input(format!(
                "{}: the material looks up texture coordinates (a uv factor or coefficient textures) but mesh {k} of {name} has none; give --uv spherical or --uv box",
                json.display()
            )));
        }
        if let Some(note) = note {
            eprintln!("note: {name}: {note} (--uv chooses the projection)");
        }
    }
    Ok(Resolved { scene, width, height, name })
}

/// The files written: `out`, or one per frame of `sequence`.
fn frame_paths(out: &Path, sequence: Option<&brdfpaint::commit::Sequence>, frames: usize) -> Vec<PathBuf> {
    match sequence {
        None => vec![out.to_path_buf()],
        Some(sequence) => (0..frames).map(|k| out.with_file_name(sequence.name(k, frames))).collect(),
    }
}

/// A scene render, checked and loaded: what [`run`] draws.
struct Job {
    output: Output,
    environment: Option<Environment>,
    orbit: Option<Orbit>,
    frames: usize,
    material: Material,
    resolved: Resolved,
}

impl Job {
    /// Draws each frame and writes it to its path in `paths`.
    fn draw(&self, paths: &[PathBuf], sequence: Option<brdfpaint::commit::Sequence>) -> Result<()> {
        let Resolved { scene, width, height, .. } = &self.resolved;
        let ctx = HeadlessContext::new()?;
        let mut renderer = Renderer::new(ctx.gl())?;
        let gpu_shading = renderer.upload(&self.material)?;
        let mut gpu = GpuScene::upload(ctx.gl(), scene)?;
        let centre = orbit_centre(scene);
        let gpu_env = self.environment.as_ref().map(|e| GpuEnvironment::upload(ctx.gl(), e)).transpose()?;
        let lighting = gpu_env.as_ref().map(|environment| self.output.lighting(environment));
        let develop = self.output.develop(lighting.is_some());

        // Frames go to hidden temporary names and are committed together when all are written:
        // a sequence appears whole or not at all (brdfpaint::commit::StagedFiles).
        let mut staged = match sequence {
            None => brdfpaint::commit::StagedFiles::new(),
            Some(sequence) => brdfpaint::commit::StagedFiles::sequence(sequence),
        };
        for (k, path) in paths.iter().enumerate() {
            if let Some(orbit) = self.orbit {
                (gpu.camera, gpu.light) = orbit_frame(&scene.camera, &scene.light, centre, orbit, k, self.frames);
            }
            let frame = match &lighting {
                Some(lighting) => renderer.lit(&gpu, &gpu_shading, lighting, *width, *height)?,
                None => renderer.factored(&gpu, &gpu_shading, *width, *height)?,
            };
            let image = develop.apply(&frame);
            staged.add(path, |tmp| match self.output.format {
                Format::Png => image.write_png(tmp),
                Format::Exr => image.write_exr(tmp),
            })?;
        }
        staged.commit()
    }

    /// The line [`run`] prints: what was rendered on what, and the files written (`paths`).
    fn report(&self, args: &RenderArgs, paths: &[PathBuf]) -> String {
        let Resolved { width, height, name, .. } = &self.resolved;
        let frames = self.frames;
        let lit = match &args.env {
            Some(e) => format!(" under {}", e.display()),
            None => String::new(),
        };
        let what = match self.orbit {
            None => String::new(),
            Some(Orbit::Camera) => format!(", turntable of {frames} frames"),
            Some(Orbit::Light) => format!(", light sweep of {frames} frames"),
        };
        let first = paths[0].display();
        let outputs =
            if paths.len() == 1 { first.to_string() } else { format!("{first} ... {}", paths[paths.len() - 1].display()) };
        format!("rendered {} on {name}{lit} at {width}x{height}{what}: {outputs}", args.material.display())
    }
}

/// `render MAT --normals N --light L`: only the exposure applies of the scene options.
fn run_photo(args: RenderArgs) -> std::result::Result<(), Failure> {
    let scene_only = [
        (args.turntable.is_some(), "--turntable"),
        (args.light_sweep.is_some(), "--light-sweep"),
        (args.env.is_some(), "--env"),
        (args.tonemap.is_some(), "--tonemap"),
        (args.background.is_some(), "--background"),
        (args.uv != UvRule::default(), "--uv"),
    ];
    if let Some((_, flag)) = scene_only.iter().find(|(given, _)| *given) {
        return Err(Failure::Usage(format!("{flag} applies to scene renders, not to --normals")));
    }
    let ev = exposure(&args)?;
    super::photos::render(&args.material, &args.map, args.light.as_deref(), args.scene.size.as_deref(), exposure_scale(ev), &args.out)
}

/// The frames of `R.png`: `R-007.png` for frame 7 (the index zero-padded to at least 3
/// digits, more when there are more frames).
fn sequence_of(out: &Path) -> brdfpaint::commit::Sequence {
    let part = |s: Option<&std::ffi::OsStr>| s.map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    brdfpaint::commit::Sequence::new(&part(out.file_stem()), &part(out.extension()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_frame_names() {
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert_eq!(parse_size("16384X1").unwrap(), (16384, 1));
        for bad in ["0x10", "10x0", "100000x100000", "16385x2", "x", "12", "axb", "-1x5"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert!(check_pixels(4096, 4096).is_ok() && check_pixels(4097, 4096).is_err());
        assert_eq!(sequence_of(Path::new("out/r.png")).name(7, 24), "r-007.png");
        assert_eq!(sequence_of(Path::new("r.exr")).name(12, 2000), "r-0012.exr");
        assert!(sequence_of(Path::new("r.exr")).contains("r-0012.exr") && !sequence_of(Path::new("r.exr")).contains("r-12.exr"));
    }

    #[test]
    fn backgrounds_parse_as_names_hex_srgb_or_linear_triples() {
        assert_eq!(parse_background("env"), Ok(BackgroundArg::Environment));
        assert_eq!(parse_background("black"), Ok(BackgroundArg::Color(Vec3::ZERO)));
        assert_eq!(parse_background("0.5, 1,2"), Ok(BackgroundArg::Color(Vec3::new(0.5, 1.0, 2.0))));
        // #808080 is sRGB 128/255: linear 0.2158.
        let BackgroundArg::Color(c) = parse_background("#808080").unwrap() else { panic!() };
        assert!((c.x - 0.2158).abs() < 1e-3 && c.x == c.z, "{c}");
        for bad in ["#12345", "#gg0000", "1,2", "1,-2,3", "nan,0,0", "white", ""] {
            assert!(parse_background(bad).is_err(), "{bad}");
        }
    }
}
