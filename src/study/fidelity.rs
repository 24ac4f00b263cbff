//! Fidelity through the real path (DESIGN.md, Quality bars): an analytic BRDF is painted
//! on the built-in sphere in framed preset scenes (the true shading at each G-buffer
//! query, times the scene's light), encoded as a 16-bit PNG or an EXR and decoded again,
//! sampled, fitted with the default settings, and judged on *held-out* scenes: the fitted
//! material against the true shading function at the G-buffer queries of lights and views
//! that were not painted.
//!
//! `cargo run --release --example paint_fidelity` prints the table for the analytic suite.
//! The judge is [`super::held_out_error`].

use glam::Vec3;

use super::held_out_error;
use crate::brdf::{Analytic, Reflectance};
use crate::sample::scene::geometry_from_gbuffer;
use crate::sample::{Erosion, Geometry, PaintedView, Samples, SceneSampler};
use crate::error::{Error, Result};
use crate::factor::{Mapping, Settings};
use crate::images::Painting;
use crate::material::{Material, Provenance};
use crate::render::GBuffer;
use crate::scene::{builtin_model, frame, Light, Preset, Scene};

/// How a synthetic painting goes through a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaintFormat {
    /// 16-bit sRGB PNG: the light is scaled so the brightest pixel is 0.95, no clipping.
    Png16,
    /// Linear float EXR.
    Exr,
}

/// Colour of the synthetic light (not white, so dividing it out is tested).
pub const LIGHT_COLOR: [f32; 3] = [1.0, 0.85, 0.7];

fn preset(name: &'static str, azimuth: f32, elevation: f32, light: [f32; 3]) -> Preset {
    Preset { name, description: "fidelity study", view_azimuth_deg: azimuth, view_elevation_deg: elevation, light_in_view: light }
}

/// The painted presets: the standard front-left view, then two more views with other
/// lights (angles between light and camera 55°, 60° and 25°).
pub fn painted_presets(count: usize) -> Vec<Preset> {
    let all = [
        Preset::default(),
        preset("paint-2", 40.0, 25.0, [0.8, 0.3, 0.5]),
        preset("paint-3", -60.0, -15.0, [0.1, -0.4, 0.9]),
    ];
    all[..count.min(all.len())].to_vec()
}

/// Held-out presets: lights and cameras no painting uses (light-camera angles 46°, 38°,
/// 63°).
pub fn held_out_presets() -> Vec<Preset> {
    vec![
        preset("held-1", 20.0, 10.0, [0.7, 0.2, 0.7]),
        preset("held-2", 200.0, 30.0, [-0.2, -0.6, 0.8]),
        preset("held-3", 0.0, 60.0, [0.0, 0.9, 0.45]),
    ]
}

/// The built-in sphere framed for `preset` (square pictures).
pub fn sphere_scene(preset: &Preset) -> Result<Scene> {
    Ok(frame(builtin_model("sphere")?, preset, 1.0))
}

/// A view of the study: its scene and G-buffer.
pub struct StudyView {
    pub scene: Scene,
    pub gbuffer: GBuffer,
}

impl StudyView {
    /// Render the G-buffer of a preset's sphere scene at `size` × `size`.
    pub fn new(sampler: &mut SceneSampler, preset: &Preset, size: usize) -> Result<StudyView> {
        let scene = sphere_scene(preset)?;
        let gbuffer = sampler.gbuffer(&scene, size, size)?;
        Ok(StudyView { scene, gbuffer })
    }

    /// The geometry under a light of colour [`LIGHT_COLOR`] × `intensity`.
    fn geometry(&self, intensity: f32) -> Result<Geometry> {
        let light = with_light(&self.scene.light, Vec3::from_array(LIGHT_COLOR), intensity);
        geometry_from_gbuffer(&self.gbuffer, &light, true, Erosion::default())
    }
}

/// `light` with colour `c` and intensity `i`.
pub(crate) fn with_light(light: &Light, c: Vec3, i: f32) -> Light {
    match *light {
        Light::Directional { direction, .. } => Light::Directional { direction, color: c, intensity: i },
        Light::Point { position, .. } => Light::Point { position, color: c, intensity: i },
    }
}

/// Paint `model` in each view: the true shading times the light at every pixel that sees a
/// front-facing surface, black elsewhere, opaque; through the file format and back.
pub fn paint(views: &[StudyView], model: &Analytic, format: PaintFormat) -> Result<Vec<PaintedView>> {
    // The largest S × colour over all views sets the intensity of the PNG's light.
    let unit: Vec<Geometry> = views.iter().map(|v| v.geometry(1.0)).collect::<Result<_>>()?;
    let mut peak = 0.0f64;
    for g in &unit {
        for px in g.pixels.iter().flatten() {
            let s = model.shading(&px.query);
            for (&x, &l) in s.iter().zip(&px.light) {
                peak = peak.max(x * l);
            }
        }
    }
    let intensity = match format {
        PaintFormat::Png16 if peak > 0.0 => (0.95 / peak) as f32,
        _ => 1.0,
    };
    let mut out = Vec::new();
    for (k, view) in views.iter().enumerate() {
        let geometry = view.geometry(intensity)?;
        let pixels = geometry
            .pixels
            .iter()
            .map(|p| match p {
                Some(px) => {
                    let s = model.shading(&px.query);
                    [0, 1, 2].map(|c| (s[c] * px.light[c]) as f32)
                }
                None => [0.0; 3],
            })
            .collect();
        let painting = Painting::opaque(geometry.width, geometry.height, pixels)?;
        let (name, bytes) = match format {
            PaintFormat::Png16 => (format!("{}-{k}.png", model.name()), painting.encode_png16()?),
            PaintFormat::Exr => (format!("{}-{k}.exr", model.name()), painting.encode_exr()?),
        };
        let painting = Painting::decode(std::path::Path::new(&name), &bytes)?;
        out.push(PaintedView { name, source: "sphere".into(), geometry, painting });
    }
    Ok(out)
}

/// One row of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub model: String,
    /// Relative RMS on the fitted samples.
    pub train: f64,
    /// Relative RMS on the held-out views.
    pub held_out: f64,
}

/// Fit every model from paintings of `painted` and judge it on `held_out`.
pub fn measure(
    painted: &[StudyView],
    held_out: &[StudyView],
    models: &[Analytic],
    settings: &Settings,
    format: PaintFormat,
) -> Result<Vec<Row>> {
    let mut prepared = None;
    let mut rows = Vec::new();
    for model in models {
        let views = paint(painted, model, format)?;
        let samples = Samples::gather(&views)?;
        // Every painting is opaque, so the pattern is the same for every model: prepare once.
        if prepared.is_none() {
            prepared = Some(crate::factor::prepare(&samples.pattern, settings)?);
        }
        let p = prepared.as_ref().expect("prepared above");
        if p.samples() != samples.len() {
            return Err(Error::Numeric("the sample pattern changed between models".into()));
        }
        let fit = p.solve(&samples.values, Mapping::Auto)?;
        let material = Material::from_fit(settings, &fit, Provenance::default())?;
        rows.push(Row { model: model.name(), train: fit.errors.rms_relative, held_out: held_out_error(&material, model, held_out, None)? });
    }
    Ok(rows)
}

/// The median of the rows' held-out errors.
pub fn held_out_median(rows: &[Row]) -> f64 {
    super::median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>())
}
