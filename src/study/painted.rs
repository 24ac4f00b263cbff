//! Paintings made outside the project (issue 34, item 4): the fit was tuned on our own
//! brush generator ([`super::faults`]), so its figures there say little about paintings
//! with real brush texture. This module holds the two ends of a study on paintings made by
//! another program (`tools/mypaint/`, MyPaint's brush engine):
//!
//! - [`write_truth`]: the clean truth a painter copies, with the scene it is painted in;
//! - [`fit_painting`]: a painting file fitted as `brdfpaint fit --scene S --image P` fits
//!   it, to be judged by [`super::held_out_and_worst`] against the model.
//!
//! The models are the faults study's nine ([`super::faults::suite`]) and four outside the
//! base's seven lobe families ([`outside`]), so the figures do not only measure how well
//! the base recognizes its own families.
//!
//! `cargo run --release --example truth_dump` and `--example painted_study` (tools/mypaint/README.md).

use std::path::Path;

use glam::Vec3;

use super::faults::{self, turned};
use super::fidelity::{sphere_scene, with_light, LIGHT_COLOR};
use crate::brdf::{Analytic, Reflectance};
use crate::error::{Error, Result};
use crate::factor::cache::Cache;
use crate::factor::Query;
use crate::images::Painting;
use crate::material::{Kind, Material};
use crate::pipeline::{self, Options};
use crate::read::Reading;
use crate::read::lobe::BaseChoice;
use crate::sample::scene::geometry_from_gbuffer;
use crate::sample::{Erosion, Neighbours, SceneSampler};
use crate::scene::{Light, Preset, Scene};

/// A true material: the sum of analytic layers' shading (one layer for the suite's models;
/// two for a second lobe that no single family holds).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub name: String,
    pub layers: Vec<Analytic>,
}

impl Model {
    fn one(m: Analytic) -> Model {
        Model { name: m.name(), layers: vec![m] }
    }
}

impl Reflectance for Model {
    fn shading(&self, q: &Query) -> [f64; 3] {
        self.layers.iter().fold([0.0; 3], |acc, m| {
            let s = m.shading(q);
            [acc[0] + s[0], acc[1] + s[1], acc[2] + s[2]]
        })
    }
}

/// Models outside the base's seven lobe families: velvet's sheen and Gooch's tone shading
/// with a highlight (the wide suite's), a clear coat (a sharp GGX lobe over a broad
/// coloured one) and a glazed clay (Oren-Nayar's rough diffuse under a Blinn-Phong highlight).
pub fn outside() -> Vec<Model> {
    let wide = Analytic::wide_suite();
    let named = |n: &str| wide.iter().find(|m| m.name() == n).cloned().map(Model::one);
    let mut out: Vec<Model> = ["velvet-0.35", "gooch-specular"].into_iter().filter_map(named).collect();
    out.push(Model {
        name: "clearcoat".into(),
        layers: vec![
            Analytic::Ggx { diffuse: [0.30, 0.10, 0.06], f0: [0.30, 0.20, 0.10], roughness: 0.7 },
            Analytic::Ggx { diffuse: [0.0; 3], f0: [0.25; 3], roughness: 0.25 },
        ],
    });
    out.push(Model {
        name: "glazed-clay".into(),
        layers: vec![
            Analytic::OrenNayar { albedo: [0.55, 0.35, 0.25], sigma: 0.6 },
            Analytic::BlinnPhong { diffuse: [0.0; 3], specular: [0.15; 3], exponent: 60.0 },
        ],
    });
    out
}

/// The study's models: the faults study's nine, then [`outside`].
pub fn models() -> Vec<Model> {
    faults::suite().into_iter().map(Model::one).chain(outside()).collect()
}

/// The truth paintings' file names in a model's folder, for `preset`: its scene, the light's
/// intensity in it (a line of text: [`scene`] builds the scene again from it, where the
/// scene itself is not kept), and the truth painted under the scene's light (`clean`) and
/// under the light turned by the faults study's angle (`off`), each as a linear EXR and a
/// 16-bit sRGB PNG.
pub fn truth_files(preset: &Preset) -> [String; 6] {
    let p = preset.name;
    [format!("{p}.gltf"), format!("{p}.light"), format!("{p}-clean.exr"), format!("{p}-clean.png"), format!("{p}-off.exr"), format!("{p}-off.png")]
}

/// The scene of the study's paintings in `preset`: the built-in sphere framed for it, lit
/// by [`LIGHT_COLOR`] at `intensity`.
pub fn scene(preset: &Preset, intensity: f32) -> Result<Scene> {
    let mut scene = sphere_scene(preset)?;
    scene.light = with_light(&scene.light, Vec3::from_array(LIGHT_COLOR), intensity);
    Ok(scene)
}

/// Writes `model`'s truth in `preset` at `size`² into `dir` ([`truth_files`]). The light is
/// [`LIGHT_COLOR`] with the intensity that makes the brightest channel of either truth
/// 0.95 (as [`faults::paint`] does), so a painter's 8-bit file clips nothing. Alpha is 1
/// where the pixel sees the front of the sphere, 0 elsewhere. The truth is computed from the
/// scene as written and read back, so the fit's G-buffer is the painter's.
pub fn write_truth(sampler: &mut SceneSampler, preset: &Preset, size: usize, model: &dyn Reflectance, light_off_deg: f64, dir: &Path) -> Result<()> {
    // The G-buffer holds the light's direction, so each light gets its own.
    let mut render = |scene: &Scene, light: Light| -> Result<Vec<Option<[f64; 3]>>> {
        let lit = Scene { light, ..scene.clone() };
        shade(&sampler.gbuffer(&lit, size, size)?, &light, model)
    };
    let colour = Vec3::from_array(LIGHT_COLOR);
    let at_scene = sphere_scene(preset)?;
    let off = sphere_scene(&turned(preset, light_off_deg))?.light;
    let mut peak = 0.0f64;
    for light in [at_scene.light, off] {
        peak = render(&at_scene, with_light(&light, colour, 1.0))?.into_iter().flatten().flatten().fold(peak, f64::max);
    }
    if peak <= 0.0 {
        return Err(Error::Numeric(format!("the truth in {} is black", preset.name)));
    }
    let intensity = (0.95 / peak) as f32;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let [gltf, light, clean_exr, clean_png, off_exr, off_png] = truth_files(preset).map(|f| dir.join(f));
    scene(preset, intensity)?.write_gltf(&gltf)?;
    // `{:?}` writes the shortest text that reads back as the same f32.
    std::fs::write(&light, format!("{intensity:?}\n")).map_err(|e| Error::io(&light, e))?;
    let written = Scene::load(&gltf)?;
    for (light, exr, png) in [(written.light, clean_exr, clean_png), (with_light(&off, colour, intensity), off_exr, off_png)] {
        let pixels = render(&written, light)?;
        let mut painting = Painting::opaque(size, size, pixels.iter().map(|p| p.unwrap_or([0.0; 3]).map(|x| x as f32)).collect())?;
        painting.alpha = pixels.iter().map(|p| if p.is_some() { 1.0 } else { 0.0 }).collect();
        painting.write(&exr)?;
        painting.write(&png)?;
    }
    Ok(())
}

/// The shading times the light at every pixel that sees the front of the object (no
/// erosion: the painter paints up to the outline).
fn shade(g: &crate::render::GBuffer, light: &Light, model: &dyn Reflectance) -> Result<Vec<Option<[f64; 3]>>> {
    let whole = Erosion { radius: 0, neighbours: Neighbours::Eight };
    let geometry = geometry_from_gbuffer(g, light, true, whole)?;
    Ok(geometry
        .pixels
        .iter()
        .map(|p| {
            p.as_ref().map(|px| {
                let s = model.shading(&px.query);
                [0, 1, 2].map(|c| s[c] * px.light[c])
            })
        })
        .collect())
}

/// Fits the painting `image` of `scene` as `brdfpaint fit --scene S --image P --base B`
/// does: loaded with the default erosion, read (tones, light, strays) and fitted as a
/// uniform 1D product with the analytic base `base`, preparing through `cache`.
pub fn fit_painting(sampler: &mut SceneSampler, scene: &Path, image: &Path, base: BaseChoice, cache: Option<&Cache>) -> Result<Material> {
    let mut loaded = pipeline::load_views(sampler, &[(scene.to_path_buf(), image.to_path_buf())], Erosion::default())?;
    loaded.read(&Reading::default(), Kind::Uniform)?;
    let opts = Options { base, ..Options::new(Kind::Uniform, 1, None, None, None)? };
    Ok(pipeline::fit(&loaded.views, &opts, cache)?.material)
}
