//! Paintings with the faults of real ones (DESIGN.md, Quality bars; issue 11), generated
//! from analytic models through the fidelity study's path ([`crate::sample::fidelity`]):
//! the true shading at each G-buffer query of the built-in sphere, then
//!
//! - **brush texture**: overlapping strokes that follow the round form, each with its own
//!   gain and tint and bristle streaks along it (anisotropic, multiplicative, smooth along
//!   the stroke), laid one over the other like paint;
//! - **a misregistered light**: the whole shading painted with the light turned a few
//!   degrees about the picture's vertical axis (highlight and terminator a few degrees off);
//! - **stray strokes** of wrong colours (white, black, any colour) across the outline: the
//!   part outside is background, not samples; the part over the object is samples;
//! - **noise** on the display (sRGB) code;
//! - **flat tones**: every channel posterized to a few display levels;
//!
//! through a 16-bit PNG and back, judged on held-out lights and views against the clean
//! truth. `cargo run --release --example faults` prints the study.

use glam::{DVec2, DVec3, Vec3};

use crate::brdf::{Analytic, Reflectance, SphereView};
use crate::util::SplitMix;
use crate::error::{Error, Result};
use crate::factor::{Fit, Prepared, Settings};
use crate::images::{linear_to_srgb, srgb_to_linear, Painting};
use crate::material::{Material, Provenance};
use crate::read::Reading;
use super::fidelity::LIGHT_COLOR;
use super::{held_out_and_worst, StudyView};
use crate::sample::scene::geometry_from_gbuffer;
use crate::sample::{Erosion, Geometry, PaintedView, Samples, SceneSampler};
use crate::scene::{Light, Preset};

/// Which faults a painting has, and how strong.
#[derive(Clone, Debug, PartialEq)]
pub struct Faults {
    pub seed: u64,
    /// Brush texture: standard deviation of a stroke's log gain (its bristle streaks and
    /// tint scale with it); 0: none.
    pub brush: f64,
    /// The shading is painted with the light turned by this many degrees.
    pub light_off_deg: f64,
    /// Stray strokes across the outline.
    pub strays: usize,
    /// Standard deviation of noise on the sRGB code (0..1); 0: none.
    pub noise: f64,
    /// Display levels per channel (6: a posterized painting); 0: not posterized.
    pub levels: u32,
}

impl Faults {
    /// A clean painting (the fidelity study's).
    pub fn clean() -> Faults {
        Faults { seed: 11, brush: 0.0, light_off_deg: 0.0, strays: 0, noise: 0.0, levels: 0 }
    }
    /// Brush texture alone: strokes of ±8% gain, ±4% tint, bristle streaks of ±6%.
    pub fn brush() -> Faults {
        Faults { brush: 0.08, ..Faults::clean() }
    }
    /// The whole shading painted 10° off the scene's light.
    pub fn misregistered() -> Faults {
        Faults { light_off_deg: 10.0, ..Faults::clean() }
    }
    /// Eight stray strokes of wrong colours across the outline.
    pub fn strays() -> Faults {
        Faults { strays: 8, ..Faults::clean() }
    }
    /// Noise of 1% of the display range (about 2.5 8-bit codes).
    pub fn noisy() -> Faults {
        Faults { noise: 0.01, ..Faults::clean() }
    }
    /// Flat tones: 6 display levels per channel.
    pub fn posterized() -> Faults {
        Faults { levels: 6, ..Faults::clean() }
    }
    /// Everything at once.
    pub fn all() -> Faults {
        Faults { seed: 11, brush: 0.08, light_off_deg: 10.0, strays: 8, noise: 0.01, levels: 6 }
    }
    /// The study's cases, named.
    pub fn cases() -> Vec<(&'static str, Faults)> {
        vec![
            ("clean", Faults::clean()),
            ("brush", Faults::brush()),
            ("light 10° off", Faults::misregistered()),
            ("strays", Faults::strays()),
            ("noise", Faults::noisy()),
            ("6 levels", Faults::posterized()),
            ("all", Faults::all()),
        ]
    }
}

/// The study's materials: nine of [`Analytic::suite`], one per family and the extremes
/// (Blinn-Phong 32 and GGX 0.4, between their neighbours, are left out).
pub fn suite() -> Vec<Analytic> {
    Analytic::suite().into_iter().filter(|m| !matches!(m.name().as_str(), "blinn-phong-32" | "ggx-0.4")).collect()
}

/// A painted view: its geometry (what is sampled), and the view whose light the painter
/// actually painted (the same camera; the light turned by `light_off_deg`).
pub struct FaultyView {
    pub view: StudyView,
    pub shading: StudyView,
}

impl FaultyView {
    pub fn new(sampler: &mut SceneSampler, preset: &Preset, size: usize, light_off_deg: f64) -> Result<FaultyView> {
        let view = StudyView::new(sampler, preset, size)?;
        let shading = StudyView::new(sampler, &turned(preset, light_off_deg), size)?;
        Ok(FaultyView { view, shading })
    }
}

/// `preset` with its light turned by `deg` about the picture's vertical axis.
pub fn turned(preset: &Preset, deg: f64) -> Preset {
    let [x, y, z] = preset.light_in_view;
    let (s, c) = (deg.to_radians() as f32).sin_cos();
    Preset { light_in_view: [c * x + s * z, y, -s * x + c * z], ..*preset }
}

fn geometry(view: &StudyView, intensity: f32) -> Result<Geometry> {
    let c = Vec3::from_array(LIGHT_COLOR);
    let light = match view.scene.light {
        Light::Directional { direction, .. } => Light::Directional { direction, color: c, intensity },
        Light::Point { position, .. } => Light::Point { position, color: c, intensity },
    };
    geometry_from_gbuffer(&view.gbuffer, &light, true, Erosion::default())
}

/// Paint `model` in `view` with `faults`, through a 16-bit PNG and back. The brightest
/// clean pixel is 0.95 (as in [`crate::sample::fidelity::paint`]).
pub fn paint(view: &FaultyView, model: &Analytic, faults: &Faults) -> Result<PaintedView> {
    let shading = geometry(&view.shading, 1.0)?;
    let peak = shading
        .pixels
        .iter()
        .flatten()
        .map(|px| {
            let s = model.shading(&px.query);
            (0..3).map(|c| s[c] * px.light[c]).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    let intensity = if peak > 0.0 { (0.95 / peak) as f32 } else { 1.0 };
    let sampled = geometry(&view.view, intensity)?;
    let shading = geometry(&view.shading, intensity)?;
    let (w, h) = (sampled.width, sampled.height);
    let object: Vec<bool> = sampled.pixels.iter().map(|p| p.is_some()).collect();
    let mut rng = SplitMix::new(faults.seed ^ 0x5eed_f00d);
    let mut linear: Vec<[f64; 3]> = shading
        .pixels
        .iter()
        .zip(&object)
        .map(|(p, &on)| match p {
            Some(px) if on => {
                let s = model.shading(&px.query);
                [0, 1, 2].map(|c| s[c] * px.light[c])
            }
            _ => [0.0; 3],
        })
        .collect();
    if faults.brush > 0.0 {
        let gain = brush_field(&mut rng, &object, w, h, faults.brush);
        for ((x, g), &on) in linear.iter_mut().zip(&gain).zip(&object) {
            if on {
                *x = [0, 1, 2].map(|c| x[c] * g[c]);
            }
        }
    }
    if faults.strays > 0 {
        strays(&mut rng, &object, w, h, faults.strays, &mut linear);
    }
    let pixels = linear
        .iter()
        .map(|x| {
            x.map(|v| {
                let mut s = linear_to_srgb(v.clamp(0.0, 1.0) as f32) as f64;
                if faults.noise > 0.0 {
                    s += faults.noise * rng.normal();
                }
                let mut s = s.clamp(0.0, 1.0);
                if faults.levels >= 2 {
                    let l = (faults.levels - 1) as f64;
                    s = (s * l).round() / l;
                }
                srgb_to_linear(s as f32)
            })
        })
        .collect();
    let painting = Painting::opaque(w, h, pixels)?;
    let name = format!("{}-faulty.png", model.name());
    let painting = Painting::decode(std::path::Path::new(&name), &painting.encode_png16()?)?;
    Ok(PaintedView { name, source: "sphere".into(), geometry: sampled, painting })
}

/// One stroke: a quadratic Bézier swept by a round brush.
struct Stroke {
    p: [DVec2; 3],
    half_width: f64,
}

impl Stroke {
    fn polyline(&self) -> Vec<DVec2> {
        (0..=24)
            .map(|k| {
                let t = k as f64 / 24.0;
                let s = 1.0 - t;
                s * s * self.p[0] + 2.0 * s * t * self.p[1] + t * t * self.p[2]
            })
            .collect()
    }

    /// Calls `f(pixel, coverage, t along, signed distance across)` for covered pixels.
    fn cover(&self, w: usize, h: usize, mut f: impl FnMut(usize, f64, f64, f64)) {
        let line = self.polyline();
        let lo = self.p.iter().fold(DVec2::splat(f64::INFINITY), |a, &b| a.min(b)) - DVec2::splat(self.half_width);
        let hi = self.p.iter().fold(DVec2::splat(f64::NEG_INFINITY), |a, &b| a.max(b)) + DVec2::splat(self.half_width);
        let (i0, j0) = (lo.x.floor().max(0.0) as usize, lo.y.floor().max(0.0) as usize);
        let (i1, j1) = ((hi.x.ceil().max(0.0) as usize).min(w), (hi.y.ceil().max(0.0) as usize).min(h));
        for j in j0..j1 {
            for i in i0..i1 {
                let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                let (mut best, mut best_t, mut side) = (f64::INFINITY, 0.0, 0.0);
                for k in 0..line.len() - 1 {
                    let (a, b) = (line[k], line[k + 1]);
                    let ab = b - a;
                    let u = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
                    let d = (p - (a + u * ab)).length();
                    if d < best {
                        best = d;
                        best_t = (k as f64 + u) / (line.len() - 1) as f64;
                        side = ab.perp_dot(p - a).signum() * d;
                    }
                }
                if best < self.half_width {
                    // Soft rim over the outer half of the width; the brush lands and lifts.
                    let x = ((self.half_width - best) / (0.5 * self.half_width)).clamp(0.0, 1.0);
                    let taper = (std::f64::consts::PI * best_t).sin().max(0.0).sqrt();
                    f(j * w + i, x * x * (3.0 - 2.0 * x) * taper, best_t, side);
                }
            }
        }
    }
}

/// Object pixels, their centroid and mean radius.
fn object_frame(object: &[bool], w: usize) -> (Vec<usize>, DVec2, f64) {
    let on: Vec<usize> = (0..object.len()).filter(|&k| object[k]).collect();
    let centre = on.iter().fold(DVec2::ZERO, |c, &k| c + DVec2::new((k % w) as f64, (k / w) as f64)) / on.len().max(1) as f64;
    let radius = (on.len() as f64 / std::f64::consts::PI).sqrt();
    (on, centre, radius)
}

/// The multiplicative gain field of brush texture: strokes following the round form
/// (tangent to circles about the centre, turned up to ±35°), covering the object about
/// three times over. Each stroke has a gain $e^{\sigma n}$ with a tint of half that, and
/// bristle streaks along it: a random profile across the stroke (one value per 1.5 px,
/// interpolated) of amplitude $0.75\sigma$, and paint thinning along it.
fn brush_field(rng: &mut SplitMix, object: &[bool], w: usize, h: usize, sigma: f64) -> Vec<[f64; 3]> {
    let mut m = vec![[1.0; 3]; w * h];
    let (on, centre, radius) = object_frame(object, w);
    if on.is_empty() {
        return m;
    }
    let scale = radius / 100.0;
    let (hw, len) = ((5.0 * scale, 12.0 * scale), (40.0 * scale, 120.0 * scale));
    let stroke_area = 2.0 * 8.5 * scale * 80.0 * scale;
    let count = (3.0 * on.len() as f64 / stroke_area).ceil() as usize;
    for _ in 0..count {
        let k = on[(rng.uniform() * on.len() as f64) as usize % on.len()];
        let start = DVec2::new((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
        let radial = start - centre;
        let tangent = if radial.length() > 1e-6 { radial.perp().normalize() } else { DVec2::X };
        let dir = DVec2::from_angle(rng.range(-0.6, 0.6)).rotate(tangent);
        let l = rng.range(len.0, len.1);
        let bend = rng.range(-0.25, 0.25) * l;
        let stroke = Stroke { p: [start - 0.5 * l * dir, start + bend * dir.perp(), start + 0.5 * l * dir], half_width: rng.range(hw.0, hw.1) };
        let opacity = rng.range(0.5, 0.9);
        let g = sigma * rng.normal();
        let gain = [0, 1, 2].map(|_| (g + 0.5 * sigma * rng.normal()).exp());
        let thinning = 0.5 * sigma * rng.normal();
        let bristles: Vec<f64> = (0..((2.0 * stroke.half_width / 1.5).ceil() as usize + 2)).map(|_| rng.normal()).collect();
        stroke.cover(w, h, |k, cov, t, side| {
            let x = ((side + stroke.half_width) / 1.5).max(0.0);
            let i = (x.floor() as usize).min(bristles.len() - 2);
            let f = (x - i as f64).min(1.0);
            let streak = 0.75 * sigma * ((1.0 - f) * bristles[i] + f * bristles[i + 1]);
            let along = thinning * (t - 0.5);
            let a = cov * opacity;
            for (mc, gc) in m[k].iter_mut().zip(gain) {
                *mc = (1.0 - a) * *mc + a * gc * (streak + along).exp();
            }
        });
    }
    m
}

/// Stray strokes of wrong colours, each starting on the outline and running across it.
fn strays(rng: &mut SplitMix, object: &[bool], w: usize, h: usize, count: usize, linear: &mut [[f64; 3]]) {
    let edge: Vec<usize> = (0..object.len())
        .filter(|&k| {
            let (i, j) = (k % w, k / w);
            object[k] && (i == 0 || j == 0 || i + 1 == w || j + 1 == h || !object[k - 1] || !object[k + 1] || !object[k - w] || !object[k + w])
        })
        .collect();
    if edge.is_empty() {
        return;
    }
    let (_, _, radius) = object_frame(object, w);
    let scale = radius / 100.0;
    for n in 0..count {
        let k = edge[(rng.uniform() * edge.len() as f64) as usize % edge.len()];
        let start = DVec2::new((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
        let dir = DVec2::from_angle(rng.range(0.0, std::f64::consts::TAU));
        let l = rng.range(20.0, 60.0) * scale;
        let stroke = Stroke { p: [start - 0.5 * l * dir, start, start + 0.5 * l * dir], half_width: rng.range(2.0, 6.0) * scale };
        // White, black, and random colours in turn.
        let colour = match n % 3 {
            0 => [0.95; 3],
            1 => [0.0; 3],
            _ => [0, 1, 2].map(|_| rng.uniform().powi(2)),
        };
        stroke.cover(w, h, |k, cov, _, _| {
            for (x, c) in linear[k].iter_mut().zip(colour) {
                *x = (1.0 - cov) * *x + cov * c;
            }
        });
    }
}

/// One row of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub model: String,
    /// Relative RMS on the fitted (faulty) samples.
    pub train: f64,
    /// Relative RMS against the clean truth over all held-out views.
    pub held_out: f64,
    /// The worst single held-out view.
    pub worst_view: f64,
    /// Light sweep of the fitted material: darkest over brightest frame.
    pub sweep: f64,
    /// The mapping the fit chose.
    pub map: &'static str,
}

/// How a study solves: any function of the prepared system and the values.
pub type Solve<'a> = &'a dyn Fn(&Prepared, &[[f64; 3]]) -> Result<Fit>;

/// Fit every model from faulty paintings of `painted` and judge it on `held_out` against
/// the clean truth. The paintings are read as `reading` says first (`brdfpaint fit` reads
/// them with [`Reading::default`]), and the product gets the analytic `base` as
/// [`Material::fit_based`] chooses it (`brdfpaint fit` passes `auto`): a kept base replaces
/// `solve`'s fit with the plain solve over it.
// The study's axes, each a caller's choice: bundling them would only rename them.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    painted: &[FaultyView],
    held_out: &[StudyView],
    models: &[Analytic],
    settings: &Settings,
    faults: &Faults,
    solve: Solve<'_>,
    reading: Reading,
    base: crate::read::lobe::BaseChoice,
) -> Result<Vec<Row>> {
    let mut prepared: Option<Prepared> = None;
    let mut rows = Vec::new();
    let gbuffers: Vec<&crate::render::GBuffer> = painted.iter().map(|v| &v.view.gbuffer).collect();
    for model in models {
        let views: Vec<PaintedView> = painted.iter().map(|v| paint(v, model, faults)).collect::<Result<_>>()?;
        let views = crate::read::Reader::new(reading, &gbuffers).read(views)?.views;
        let samples = Samples::gather(&views)?;
        // As `brdfpaint fit` does: headlit paintings get the light prior.
        let settings = &settings.for_pattern(&samples.pattern);
        // Paintings are opaque: the pattern is the same for every model and fault, unless
        // each model's light was registered.
        if reading.register_light || prepared.as_ref().is_none_or(|p| p.samples() != samples.len() || p.settings() != settings) {
            prepared = Some(crate::factor::prepare(&samples.pattern, settings)?);
        }
        let p = prepared.as_ref().ok_or_else(|| Error::Numeric("no prepared system".into()))?;
        let fit = solve(p, &samples.values)?;
        let mut material = Material::from_fit(settings, &fit, Provenance::default())?;
        // As `brdfpaint fit` does: the analytic base when it explains the painting as well as
        // the painting's roughness allows.
        if let Some(based) = crate::read::lobe::fit_based(p, &samples.pattern, &samples.values, &fit, settings, crate::factor::Mapping::Auto, base, views.len() == 1, Provenance::default())? {
            material = based;
        }
        let (held, worst) = held_out_and_worst(&material, model, held_out)?;
        let sweep = sweep_ratio(&light_sweep(&material, 24, 64));
        rows.push(Row { model: model.name(), train: fit.errors.rms_relative, held_out: held, worst_view: worst, sweep, map: fit.map.name() });
    }
    Ok(rows)
}

/// Mean luminance of `material` on a sphere seen from $+z$ (a `res`² orthographic view) as
/// the light orbits it about the vertical axis in `steps` frames, from the camera (frame 0)
/// round behind the sphere and back: what a light sweep in the viewer shows, on the CPU.
pub fn light_sweep(material: &Material, steps: usize, res: usize) -> Vec<f64> {
    (0..steps)
        .map(|k| {
            let phi = std::f64::consts::TAU * k as f64 / steps as f64;
            let view = SphereView::new(DVec3::new(phi.sin(), 0.0, phi.cos()), res);
            let px = view.pixels();
            let sum: f64 = px
                .iter()
                .map(|p| {
                    let s = material.shading(&p.query);
                    crate::images::luminance(s)
                })
                .sum();
            sum / px.len().max(1) as f64
        })
        .collect()
}

/// Darkest over brightest frame of a sweep (0 for an all-black one).
pub fn sweep_ratio(frames: &[f64]) -> f64 {
    let max = frames.iter().cloned().fold(0.0, f64::max);
    let min = frames.iter().cloned().fold(f64::INFINITY, f64::min);
    if max > 0.0 { min / max } else { 0.0 }
}

