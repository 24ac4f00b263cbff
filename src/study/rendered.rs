//! Truth made by another renderer (issue 37): spheres of materials outside the base's seven
//! lobe families (rough conductors with measured complex IOR, a very rough one among them,
//! rough plastic with internal scattering, a sharp one among them, the principled BSDF with
//! clearcoat, with sheen and metallic, a two-layer blend), rendered by Mitsuba 3 in the
//! fidelity study's scenes and under side, rim and grazing light ([`harder`]), committed as
//! linear EXR (`tests/data/mitsuba/`, made by `tools/mitsuba/render_suite.py`), so tests and
//! CI need no Mitsuba.
//!
//! The scenes are written here ([`write_scenes`]) and the renderer reads camera, light and
//! mesh from those very files: the two sides cannot disagree on framing. A material is fitted
//! from one or three painted views as `brdfpaint fit --scene S --image P` fits it (loaded,
//! read, fitted with the default options and the chosen `--base`) and judged on each
//! held-out render by [`super::rendered_error`]. The suite's Lambertian sphere is the
//! convention check: rendered there, it must equal this crate's Lambert shading
//! ([`convention_check`]).
//!
//! `cargo run --release --example mitsuba_suite` prints the table.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde_json::Value;

use super::fidelity::{held_out_presets, painted_presets, sphere_scene, LIGHT_COLOR};
use super::{median, rendered_error};
use crate::brdf::Analytic;
use crate::error::{Error, Result};
use crate::read::lobe::BaseChoice;
use crate::material::Kind;
use crate::pipeline::{self, Options};
use crate::read::Reading;
use crate::sample::{Erosion, PaintedView, SceneSampler};
use crate::scene::{Light, Preset, Scene};

/// The suite's views: the three painted presets of the fidelity study (the first alone is
/// the one-view fit), then its three held-out presets (light 38°–63° from the camera), then
/// the [`harder`] ones.
pub fn presets() -> Vec<Preset> {
    painted_presets(3).into_iter().chain(held_out_presets()).chain(harder()).collect()
}

fn preset(name: &'static str, azimuth: f32, elevation: f32, light: [f32; 3]) -> Preset {
    Preset { name, description: "rendered suite, side and rim light", view_azimuth_deg: azimuth, view_elevation_deg: elevation, light_in_view: light }
}

/// Held-out views under side, rim and grazing light, where Fresnel and the lobes' grazing
/// shapes show and a fit from front-lit paintings extrapolates: the light 90° (side), 115°
/// and 140° (rim) and 150° (grazing: a thin lit crescent, the most the silhouette band leaves) from the camera.
pub fn harder() -> Vec<Preset> {
    vec![
        preset("side-90", 30.0, 15.0, [-1.0, 0.2, 0.0]),
        preset("rim-115", -45.0, 5.0, [0.8, 0.35, -0.41]),
        preset("rim-140", 120.0, 20.0, [-0.5, 0.4, -0.77]),
        preset("grazing-150", -150.0, 35.0, [0.296, -0.403, -0.866]),
    ]
}

/// How many of [`presets`] are the fidelity study's held-out presets; the [`harder`] ones
/// follow them.
pub const FRONT_HELD_OUT: usize = 3;

/// How many of [`presets`] are painted; the rest are held out.
pub const PAINTED: usize = 3;

/// The fidelity study's sphere scene for `preset`, lit by its coloured light
/// ([`LIGHT_COLOR`], intensity 1), so that dividing the light out is part of the test.
pub fn scene(preset: &Preset) -> Result<Scene> {
    let mut scene = sphere_scene(preset)?;
    if let Light::Directional { direction, .. } = scene.light {
        scene.light = Light::Directional { direction, color: Vec3::from_array(LIGHT_COLOR), intensity: 1.0 };
    }
    Ok(scene)
}

/// Writes each of [`presets`] as `dir/NAME.gltf`; their paths, in order.
pub fn write_scenes(dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    presets()
        .iter()
        .map(|p| {
            let path = dir.join(format!("{}.gltf", p.name));
            scene(p)?.write_gltf(&path)?;
            Ok(path)
        })
        .collect()
}

/// A rendered suite on disk: `suite.json` (what was rendered, by which renderer) and
/// `MATERIAL/PRESET.exr` per material and view.
pub struct Suite {
    pub dir: PathBuf,
    /// The materials fitted, in the manifest's order.
    pub materials: Vec<String>,
    /// The convention check's Lambertian albedo and its directory's name.
    pub check: (String, [f64; 3]),
}

impl Suite {
    /// Reads `dir/suite.json`.
    pub fn load(dir: &Path) -> Result<Suite> {
        let path = dir.join("suite.json");
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let json: Value = serde_json::from_str(&text).map_err(|e| Error::format(&path, e.to_string()))?;
        let bad = |what: &str| Error::format(&path, format!("suite.json: {what}"));
        let materials = json["materials"]
            .as_array()
            .ok_or_else(|| bad("no materials list"))?
            .iter()
            .map(|m| m["name"].as_str().map(String::from).ok_or_else(|| bad("a material without a name")))
            .collect::<Result<Vec<_>>>()?;
        let check = &json["check"];
        let name = check["name"].as_str().ok_or_else(|| bad("no check name"))?.to_string();
        let albedo: Vec<f64> = check["albedo"].as_array().ok_or_else(|| bad("no check albedo"))?.iter().filter_map(Value::as_f64).collect();
        let albedo: [f64; 3] = albedo.try_into().map_err(|_| bad("the check's albedo is not RGB"))?;
        Ok(Suite { dir: dir.to_path_buf(), materials, check: (name, albedo) })
    }

    /// The render of `material` in `preset`'s scene.
    pub fn image(&self, material: &str, preset: &Preset) -> PathBuf {
        self.dir.join(material).join(format!("{}.exr", preset.name))
    }

    /// The (scene, render) pairs of `material`: scenes in `scenes` ([`write_scenes`]).
    fn pairs(&self, material: &str, scenes: &Path, presets: &[Preset]) -> Vec<(PathBuf, PathBuf)> {
        presets.iter().map(|p| (scenes.join(format!("{}.gltf", p.name)), self.image(material, p))).collect()
    }

    /// The held-out renders of `material`, read as truth: every object pixel but the
    /// silhouette (default erosion), no page or stroke reading.
    fn held_out(&self, sampler: &mut SceneSampler, material: &str, scenes: &Path) -> Result<Vec<PaintedView>> {
        self.pairs(material, scenes, &presets()[PAINTED..])
            .iter()
            .map(|(s, i)| sampler.load_view(s, i, Erosion::default()).map(|(_, v)| v))
            .collect()
    }
}

/// The Lambertian sphere rendered by the other renderer against this crate's Lambert shading
/// of the same albedo: [`rendered_error`] per view, painted and held out. Noise level
/// (float rounding of a half-float EXR) when both agree on camera, pixel centres, light
/// direction and irradiance, π and linear values; an image flip or a missing π shows as
/// order 1.
pub fn convention_check(suite: &Suite, sampler: &mut SceneSampler, scenes: &Path) -> Result<Vec<f64>> {
    let (name, albedo) = &suite.check;
    let lambert = Analytic::Lambert { albedo: *albedo };
    let views: Vec<PaintedView> = suite
        .pairs(name, scenes, &presets())
        .iter()
        .map(|(s, i)| sampler.load_view(s, i, Erosion::default()).map(|(_, v)| v))
        .collect::<Result<_>>()?;
    rendered_error(&lambert, &views)
}

/// One material of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub material: String,
    /// Relative RMS on the fitted samples.
    pub train: f64,
    /// Relative RMS on each held-out view.
    pub views: Vec<f64>,
    /// The analytic base the fit kept, if any.
    pub base: Option<String>,
}

impl Row {
    /// The median over held-out views.
    pub fn median(&self) -> f64 {
        median(&self.views)
    }
    /// The median over the held-out views lit from the front half (the fidelity study's).
    pub fn front(&self) -> f64 {
        median(&self.views[..FRONT_HELD_OUT.min(self.views.len())])
    }
    /// The median over the side, rim and grazing views ([`harder`]).
    pub fn rim(&self) -> f64 {
        median(&self.views[FRONT_HELD_OUT.min(self.views.len())..])
    }
    /// The worst held-out view.
    pub fn worst(&self) -> f64 {
        self.views.iter().copied().fold(0.0, f64::max)
    }
}

/// Fits every material of `suite` from its first `painted` views (1 to [`PAINTED`]) as
/// `brdfpaint fit --scene S --image P [--base B]` does, and judges each on the held-out
/// renders. `scenes` holds the suite's scene files ([`write_scenes`]).
pub fn measure(suite: &Suite, sampler: &mut SceneSampler, scenes: &Path, painted: usize, base: BaseChoice) -> Result<Vec<Row>> {
    if !(1..=PAINTED).contains(&painted) {
        return Err(Error::input(format!("the suite has 1 to {PAINTED} painted views, not {painted}")));
    }
    let opts = Options { base, ..Options::new(Kind::Uniform, 1, None, None, None)? };
    let mut rows = Vec::new();
    for material in &suite.materials {
        let pairs = suite.pairs(material, scenes, &presets()[..painted]);
        let mut loaded = pipeline::load_views(sampler, &pairs, Erosion::default())?;
        loaded.read(&Reading::default(), opts.kind)?;
        let fitted = pipeline::fit(&loaded.views, &opts, None)?;
        let held = suite.held_out(sampler, material, scenes)?;
        let base = fitted.material.terms.first().and_then(|t| t.base).map(|b| b.lobe.name().to_string());
        rows.push(Row { material: material.clone(), train: fitted.errors().rms_relative, views: rendered_error(&fitted.material, &held)?, base });
    }
    Ok(rows)
}

/// The median over materials of each material's median over held-out views.
pub fn median_of_medians(rows: &[Row]) -> f64 {
    median(&rows.iter().map(Row::median).collect::<Vec<_>>())
}

/// The worst held-out view of any material.
pub fn worst_view(rows: &[Row]) -> f64 {
    rows.iter().map(Row::worst).fold(0.0, f64::max)
}
