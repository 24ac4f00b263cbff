//! The bundled paintings (`assets/paintings/`): what each one shows, the scene it was painted
//! in, and how it was made. `cargo run --release --example make_paintings` regenerates the
//! files with [`paint`]; the demo fits them.
//!
//! Every painting is a 256² 8-bit sRGB PNG of the built-in sphere framed by a preset
//! ([`views`]), lit by that scene's white directional light of intensity 1:
//! - analytic models (Blinn-Phong plastic, Gooch warm-to-cool with its unlit side painted
//!   blue) and measured-like materials (the ABC fits of two MERL materials, [`Abc`]) are
//!   their true shading function $S(l, v)$ at each pixel's G-buffer query (the wood's,
//!   [`Truth::Banded`], also depends on the query's uv), under
//!   [`brush`](mod@super::brush) noise: soft strokes of ±5% intensity and ±3% tint, and a few
//!   unpainted (alpha 0) gaps;
//! - the MatCap is one of Blender's CC0 MatCaps (`toon`), a picture of a sphere seen from
//!   the front, mapped onto the sphere scene's pixels through each pixel's view-space
//!   normal, and read as if the scene's light had lit it.

use glam::Vec3;

use super::brush::{self, Brush};
use crate::brdf::{Abc, Analytic, Reflectance, Striped};
use crate::error::{Error, Result};
use crate::factor::Query;
use crate::images::{encode_srgb8, Rgb};
use crate::render::GBuffer;
use crate::scene::{Preset, Scene};

/// Side of every bundled painting, pixels.
pub const SIZE: usize = 256;

/// A scene the paintings are painted in: the built-in sphere framed by `preset`, with its
/// sheet written to `DIR/<dir>/`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub dir: &'static str,
    pub preset: Preset,
}

/// The painted views: the standard front-left sheet, and a second view for thesis 4.4
/// (camera 60° to the left and 15° below, light from below the camera): the pair of the
/// fidelity study ([`crate::study::fidelity::painted_presets`]) that halves the gold
/// paint's held-out error.
pub fn views() -> [View; 2] {
    [
        View { dir: "sheet", preset: Preset::default() },
        View {
            dir: "sheet-2",
            preset: Preset {
                name: "demo-second-view",
                description: "camera 60° to the left and 15° below, light from below the camera",
                view_azimuth_deg: -60.0,
                view_elevation_deg: -15.0,
                light_in_view: [0.1, -0.4, 0.9],
            },
        },
    ]
}

/// The scene of view `k`: the built-in sphere framed by its preset at aspect 1.
pub fn view_scene(k: usize) -> Result<Scene> {
    Ok(crate::scene::frame(crate::scene::builtin_model("sphere")?, &views()[k].preset, 1.0))
}

/// What a painting shows.
#[derive(Clone, Debug, PartialEq)]
pub enum Truth {
    /// An analytic model's shading function.
    Analytic(Analytic),
    /// The ABC fit of a MERL material, painted `exposure` times brighter: the material the
    /// painting shows is `exposure` × the fit.
    Abc { model: Abc, exposure: f64 },
    /// A MatCap: no known shading function.
    Matcap { name: &'static str },
    /// A spatially varying material: stripes of equal width in the surface's $u$ (on the
    /// sphere, slices of azimuth) of two analytic models.
    Banded(Striped),
}

impl Truth {
    /// The shading function the painting shows, where it is known (not for a MatCap).
    pub fn known(&self) -> Option<&dyn Reflectance> {
        self.is_known().then_some(self as &dyn Reflectance)
    }

    /// Whether the shading varies over the surface (a material map fits it).
    pub fn is_spatial(&self) -> bool {
        matches!(self, Truth::Banded(_))
    }

    /// Whether the shading function is known.
    pub fn is_known(&self) -> bool {
        !matches!(self, Truth::Matcap { .. })
    }

    /// A short description for the summary (at most 25 characters).
    pub fn describe(&self) -> String {
        match self {
            Truth::Analytic(Analytic::BlinnPhong { exponent, .. }) => format!("Blinn-Phong, n = {exponent}"),
            Truth::Analytic(Analytic::Gooch { .. }) => "Gooch warm-to-cool".into(),
            Truth::Analytic(a) => a.name(),
            Truth::Abc { model, .. } => format!("MERL {} (ABC)", model.name),
            Truth::Matcap { name } => format!("MatCap {name} (CC0)"),
            Truth::Banded(stripes) => format!("wood, {} bands", stripes.bands),
        }
    }
}

impl Reflectance for Truth {
    /// The shading function $S(l, v; u, v)$ the painting shows at query `q`; only
    /// [`Truth::Banded`] depends on the query's uv. NaN for a MatCap, whose shading is not
    /// known: ask [`Truth::known`] first.
    fn shading(&self, q: &Query) -> [f64; 3] {
        match self {
            Truth::Analytic(a) => a.shading(q),
            Truth::Abc { model, exposure } => model.shading(q).map(|x| x * exposure),
            Truth::Matcap { .. } => [f64::NAN; 3],
            Truth::Banded(stripes) => stripes.shading(q),
        }
    }
}

/// One bundled painting file.
#[derive(Clone, Copy, Debug)]
pub struct PaintingFile {
    /// File name in `assets/paintings/` (and `DIR/paintings/`).
    pub file: &'static str,
    /// Index into [`views`].
    pub view: usize,
    /// The PNG, compiled in.
    pub bytes: &'static [u8],
    /// Seed of its brush noise; `None` for the MatCap, which is painted already.
    pub brush_seed: Option<u64>,
}

/// How the demo fits a material: `brdfpaint fit --kind uniform` or `--kind material-map`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitKind {
    /// One product $p(l)\,q(h)\,r(v)$ for the whole surface.
    Uniform,
    /// A material map of at most `terms` products blended by coefficient textures
    /// (thesis 4.2.2): for paintings whose material varies over the surface.
    MaterialMap { terms: usize },
    /// `brdfpaint fit --lit-sphere`: the painting is a picture of a sphere (a MatCap), its
    /// scene built and its light estimated from the picture itself.
    LitSphere,
}

/// A material the demo recovers: its name, what it is, how it is fitted, and the paintings
/// it is fitted to (one, or several views of it: thesis 4.4).
#[derive(Clone, Debug)]
pub struct MaterialSpec {
    /// Directory name in `DIR/materials/` and row name in the summary.
    pub name: &'static str,
    pub truth: Truth,
    pub kind: FitKind,
    pub paintings: Vec<PaintingFile>,
}

macro_rules! painting {
    ($file:literal, $view:expr, $seed:expr) => {
        PaintingFile {
            file: $file,
            view: $view,
            bytes: include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/paintings/", $file)),
            brush_seed: $seed,
        }
    };
}

/// The blue plastic.
pub fn plastic() -> Analytic {
    Analytic::BlinnPhong { diffuse: [0.06, 0.22, 0.55], specular: [0.4, 0.4, 0.4], exponent: 40.0 }
}

/// The warm-to-cool painting: orange where lit, blue on the unlit side.
pub fn gooch() -> Analytic {
    Analytic::Gooch { warm: [0.95, 0.5, 0.1], cool: [0.06, 0.14, 0.65] }
}

/// The lacquered stripes of the wood: a dark warm glossy Blinn-Phong.
pub fn lacquer() -> Analytic {
    Analytic::BlinnPhong { diffuse: [0.10, 0.08, 0.05], specular: [0.4, 0.4, 0.4], exponent: 40.0 }
}

/// The bare stripes of the wood: a light brown Lambert.
pub fn bare_wood() -> Analytic {
    Analytic::Lambert { albedo: [0.55, 0.35, 0.15] }
}

/// The spatially varying painting: eight stripes around the sphere (45° of azimuth each),
/// lacquered from $u = 0$, then bare, like the test object of `tests/material_map.rs`. The
/// highlight of the front-left view falls on a bare stripe (azimuth -45° to 0°), that of
/// the second view on a lacquered one (-90° to -45°): together they show how each material
/// answers the light where it is brightest.
pub fn wood() -> Truth {
    Truth::Banded(wood_stripes())
}

/// The wood's stripes.
pub fn wood_stripes() -> Striped {
    Striped { a: lacquer(), b: bare_wood(), bands: WOOD_BANDS }
}

/// Stripes of the wood.
pub const WOOD_BANDS: usize = 8;

fn abc(name: &str, exposure: f64) -> Truth {
    Truth::Abc { model: Abc::bundled(name).expect("a bundled ABC material"), exposure }
}

/// The materials of the demo, in contact-sheet order.
pub fn materials() -> Vec<MaterialSpec> {
    let gold = painting!("gold-paint.png", 0, Some(3));
    vec![
        MaterialSpec {
            name: "plastic",
            truth: Truth::Analytic(plastic()),
            kind: FitKind::Uniform,
            paintings: vec![painting!("plastic.png", 0, Some(1))],
        },
        MaterialSpec {
            name: "gooch",
            truth: Truth::Analytic(gooch()),
            kind: FitKind::Uniform,
            paintings: vec![painting!("gooch.png", 0, Some(2))],
        },
        MaterialSpec {
            name: "gold-paint",
            truth: abc("gold-paint", GOLD_EXPOSURE),
            kind: FitKind::Uniform,
            paintings: vec![gold],
        },
        MaterialSpec {
            name: "gold-paint-2-views",
            truth: abc("gold-paint", GOLD_EXPOSURE),
            kind: FitKind::Uniform,
            paintings: vec![gold, painting!("gold-paint-2.png", 1, Some(4))],
        },
        MaterialSpec {
            name: "purple-paint",
            truth: abc("purple-paint", PURPLE_EXPOSURE),
            kind: FitKind::Uniform,
            paintings: vec![painting!("purple-paint.png", 0, Some(5))],
        },
        // Both views: a material map knows a texel only where some painting saw it, and the
        // second view paints a further 60° of the stripes.
        MaterialSpec {
            name: "lacquered-wood",
            truth: wood(),
            kind: FitKind::MaterialMap { terms: WOOD_TERMS },
            paintings: vec![painting!("wood.png", 0, Some(6)), painting!("wood-2.png", 1, Some(7))],
        },
        MaterialSpec {
            name: "toon",
            truth: Truth::Matcap { name: "toon" },
            kind: FitKind::LitSphere,
            // The MatCap itself, at the sheets' size: a lit sphere with its own scene.
            paintings: vec![painting!("toon-matcap.png", 0, None)],
        },
    ]
}

/// Most terms of the wood's material map.
pub const WOOD_TERMS: usize = 5;

/// Exposure of the gold paint: its brightest pixel at about 0.9 in either view.
pub const GOLD_EXPOSURE: f64 = 3.0;
/// Exposure of the purple paint.
pub const PURPLE_EXPOSURE: f64 = 2.5;

/// A painting in memory: linear RGB and a painted mask, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 3]>,
    pub painted: Vec<bool>,
}

impl Canvas {
    /// An 8-bit sRGB RGBA PNG (what a paint program saves): alpha 255 where painted, 0
    /// (and black) elsewhere. Values are clamped to [0, 1].
    pub fn encode_png(&self) -> Result<Vec<u8>> {
        let mut raw = Vec::with_capacity(self.pixels.len() * 4);
        for (p, &on) in self.pixels.iter().zip(&self.painted) {
            if on {
                raw.extend([encode_srgb8(p[0]), encode_srgb8(p[1]), encode_srgb8(p[2]), 255]);
            } else {
                raw.extend([0, 0, 0, 0]);
            }
        }
        let img = image::RgbaImage::from_raw(self.width as u32, self.height as u32, raw)
            .ok_or_else(|| Error::input("pixel buffer does not match the painting size"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .map_err(|e| Error::input(format!("PNG encoding failed: {e}")))?;
        Ok(out.into_inner())
    }

    /// The largest painted channel value (before clamping).
    pub fn peak(&self) -> f32 {
        self.pixels.iter().zip(&self.painted).filter(|(_, &on)| on).flat_map(|(p, _)| *p).fold(0.0, f32::max)
    }
}

/// The light's colour × intensity of a scene (white, 1, for the framed scenes).
fn light_rgb(scene: &Scene) -> [f64; 3] {
    let (crate::scene::Light::Directional { color, intensity, .. }
    | crate::scene::Light::Point { color, intensity, .. }) = scene.light;
    (color * intensity).as_dvec3().to_array()
}

/// Paints `truth` in the scene whose G-buffer is `g`: every pixel whose centre sees the
/// object is painted with the true shading times the light that reaches it, times the
/// brush's gain field; the brush's gaps and the background are unpainted. A MatCap
/// (`matcap`, a linear image of a sphere seen from the front) is looked up with the pixel's
/// view-space normal instead, and is not brushed.
pub fn paint(truth: &Truth, g: &GBuffer, scene: &Scene, brush: Option<&Brush>, matcap: Option<&Rgb>) -> Result<Canvas> {
    let (w, h) = (g.width, g.height);
    let object: Vec<bool> = g.pixels.iter().map(|p| p.hit).collect();
    let (gain, gaps) = match brush {
        Some(b) => {
            let (colour, gaps) = brush::strokes(b, &object, w, h);
            (brush::gain_field(&colour, w, h), brush::gap_mask(&gaps, w, h))
        }
        None => (vec![[1.0; 3]; w * h], vec![false; w * h]),
    };
    let light = light_rgb(scene);
    let camera_from_world = scene.camera.camera_from_world();
    let mut pixels = vec![[0.0f32; 3]; w * h];
    let mut painted = vec![false; w * h];
    for (k, px) in g.pixels.iter().enumerate() {
        if !px.hit || gaps[k] {
            continue;
        }
        let value: [f64; 3] = match (truth, matcap) {
            (Truth::Matcap { .. }, Some(m)) => {
                let n = camera_from_world.transform_vector3(px.normal).normalize_or(Vec3::Z);
                sample_matcap(m, n.x as f64, n.y as f64)
            }
            (Truth::Matcap { name }, None) => {
                return Err(Error::input(format!("the MatCap {name} needs its image to be painted")));
            }
            (t, _) => {
                // Rim pixels whose interpolated normal turns from the eye (v_z <= 0) are
                // painted as if seen at a grazing angle, so the silhouette has no black dots;
                // they are not samples anyway.
                let l = px.l.as_dvec3().normalize_or(glam::DVec3::Z);
                let v = px.v.as_dvec3();
                let v = glam::DVec3::new(v.x, v.y, v.z.max(1e-3)).normalize_or(glam::DVec3::Z);
                let uv = glam::DVec2::new(px.uv.x as f64, px.uv.y as f64);
                let s = t.shading(&Query { l, v, uv });
                let f = px.falloff as f64;
                [0, 1, 2].map(|c| s[c] * light[c] * f)
            }
        };
        pixels[k] = [0, 1, 2].map(|c| (value[c] * gain[k][c]) as f32);
        painted[k] = true;
    }
    Ok(Canvas { width: w, height: h, pixels, painted })
}

/// Bilinear lookup of a MatCap at view-space normal $(n_x, n_y)$: the disc inscribed in the
/// image, $n_x$ to the right and $n_y$ up.
pub fn sample_matcap(m: &Rgb, nx: f64, ny: f64) -> [f64; 3] {
    let x = (0.5 + 0.5 * nx) * m.width as f64 - 0.5;
    let y = (0.5 - 0.5 * ny) * m.height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f64, j: f64| {
        let i = (i.max(0.0) as usize).min(m.width - 1);
        let j = (j.max(0.0) as usize).min(m.height - 1);
        m.pixels[j * m.width + i]
    };
    let (a, b, c, d) = (at(x0, y0), at(x0 + 1.0, y0), at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0));
    [0, 1, 2].map(|k| {
        let top = a[k] as f64 * (1.0 - fx) + b[k] as f64 * fx;
        let bottom = c[k] as f64 * (1.0 - fx) + d[k] as f64 * fx;
        top * (1.0 - fy) + bottom * fy
    })
}

/// The brush of a painting with seed `seed`.
pub fn brush(seed: u64) -> Brush {
    Brush { seed, ..Brush::default() }
}
