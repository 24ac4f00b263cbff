//! The environment the 3D view shows its material under (issue 16): "none" (the key light
//! alone on the viewer's background, as before) or an HDR panorama, bundled (`assets/hdri/`)
//! or read from a `.hdr`/`.exr` file (the panel's path, a drop on the window, `view --env`).
//! The view draws it with the renderer's own environment pass ([`Renderer::draw_lit`]), with
//! the scene's light as the key light: live painting shows the painted light beside the
//! environment. Exposure and tone mapping develop the view's linear pixels as `render`
//! develops its PNGs ([`crate::images::tone`]).
//!
//! The pass costs tens of point-light frames on a software rasterizer, so while the view
//! moves (a drag, the wheel, the rotation slider, a stroke being painted) it takes [`MOVING_SAMPLES`] directions per
//! pixel, and the full count again on the first still frame.
//!
//! [`Renderer::draw_lit`]: crate::render::Renderer::draw_lit

use std::path::{Path, PathBuf};

use super::super::display::Develop;
use super::panel::{choice, combo_width, labelled};
use super::Studio;
use crate::error::{Error, Result};
use crate::gl::Gl;
use crate::images::env::{self as hdr, Environment};
use crate::images::tone::{exposure_scale, Tonemap};
use crate::render::env::DEFAULT_SAMPLES;
use crate::render::{Background, GpuEnvironment, Lighting, Renderer};

/// Directions per pixel while the view moves: the fewest that give each strategy one (an
/// eighth of the default), 3.7× the frame rate of 64 on llvmpipe (BENCHMARKS.md); the
/// softer highlights it leaves are gone on the next still frame.
pub const MOVING_SAMPLES: usize = 8;

/// Directions per pixel a still view may take (each count compiles its own programs, so
/// a few steps rather than a slider).
pub const STILL_SAMPLES: [usize; 4] = [32, 64, 128, 256];

/// Degrees the environment turns per point of an Alt-drag across the view.
pub const DEGREES_PER_POINT: f32 = 0.5;

/// The name of no environment.
pub const NONE: &str = "none";

/// Largest exposure in the panel, stops either way.
const MAX_EV: f32 = 8.0;

/// An environment to start with (`view --env`), read and checked before the window opens.
pub struct EnvStart {
    pub name: String,
    pub environment: Environment,
    pub rotate_deg: f32,
    pub ev: f32,
    pub tonemap: Tonemap,
    /// Directions per pixel when still ([`crate::render::env::SAMPLES`]).
    pub samples: usize,
}

/// The viewer's environment: which one, on the GPU, and how it is shown.
pub struct Env {
    /// [`NONE`], a bundled name, or the file it was read from.
    name: String,
    gpu: Option<GpuEnvironment>,
    /// Turn about $+y$, degrees in [-180, 180) (`images::env`, Convention).
    pub rotate_deg: f32,
    /// Exposure, stops.
    pub ev: f32,
    pub tonemap: Tonemap,
    /// The environment behind the object, else the viewer's background.
    pub show_background: bool,
    /// Directions per pixel when the view is still.
    pub samples: usize,
    /// The view moves in this frame (the UI sets it; [`Env::drawn`] clears it).
    pub moving: bool,
    /// The last frame had fewer directions: a still one is owed.
    owed: bool,
    /// The path typed in the panel.
    path: String,
}

impl Default for Env {
    fn default() -> Env {
        Env {
            name: NONE.into(),
            gpu: None,
            rotate_deg: 0.0,
            ev: 0.0,
            tonemap: Tonemap::Neutral,
            show_background: true,
            samples: DEFAULT_SAMPLES,
            moving: false,
            owed: false,
            path: String::new(),
        }
    }
}

/// `deg` in [-180, 180); 0 for a non-finite angle.
pub fn wrap_degrees(deg: f32) -> f32 {
    if deg.is_finite() {
        (deg + 180.0).rem_euclid(360.0) - 180.0
    } else {
        0.0
    }
}

impl Env {
    /// [`NONE`], a bundled name, or the file the environment was read from.
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn is_on(&self) -> bool {
        self.gpu.is_some()
    }

    /// Shows `environment` (read and checked), named `name`. On an error nothing changes.
    pub fn set(&mut self, gl: &Gl, name: String, environment: &Environment) -> Result<()> {
        self.gpu = Some(GpuEnvironment::upload(gl, environment)?);
        self.name = name;
        Ok(())
    }

    /// [`NONE`] or a bundled environment by name. On an error nothing changes.
    pub fn choose(&mut self, gl: &Gl, name: &str) -> Result<()> {
        if name == NONE {
            self.gpu = None;
            self.name = NONE.into();
            return Ok(());
        }
        self.set(gl, name.to_string(), &hdr::bundled(name)?)
    }

    /// An environment file (.hdr or .exr, 2:1). On an error (unreadable, not HDR, not 2:1,
    /// NaN pixels) the shown environment stays.
    pub fn open(&mut self, gl: &Gl, path: &Path) -> Result<()> {
        let environment = Environment::load(path)?;
        self.set(gl, path.display().to_string(), &environment)
    }

    /// Turns the environment by `deg` about $+y$.
    pub fn turn(&mut self, deg: f32) {
        self.rotate_deg = wrap_degrees(self.rotate_deg + deg);
    }

    /// Directions per pixel for the frame drawn now.
    pub fn samples_now(&self) -> usize {
        if self.moving {
            MOVING_SAMPLES.min(self.samples)
        } else {
            self.samples
        }
    }

    /// How the view is lit now; `None` without an environment (the key light alone).
    pub fn lighting(&self) -> Option<Lighting<'_>> {
        let environment = self.gpu.as_ref()?;
        Some(Lighting {
            environment,
            rotate_deg: self.rotate_deg,
            // The painting's (or the panel's) light stays: the material is judged under it.
            key_light: true,
            // Alpha stays 0 there, so the viewer's background shows through (Develop::opaque).
            background: if self.show_background { Background::Environment } else { Background::Color(glam::Vec3::ZERO) },
            samples: self.samples_now(),
        })
    }

    /// How the view's pixels reach the window: as before without an environment (the
    /// painting's values, clamped), else exposed and tone mapped as `render --env` does.
    pub fn develop(&self) -> Develop {
        match self.gpu {
            None => Develop::default(),
            Some(_) => Develop { scale: exposure_scale(self.ev), tonemap: self.tonemap, opaque: self.show_background },
        }
    }

    /// A frame was drawn: a full one is owed when it had fewer directions.
    pub fn drawn(&mut self) {
        self.owed = self.gpu.is_some() && self.samples_now() < self.samples;
        self.moving = false;
    }

    /// A still frame with the full count of directions is owed (frames must keep coming).
    pub fn owed(&self) -> bool {
        self.owed
    }
}

fn tonemap_name(t: Tonemap) -> &'static str {
    match t {
        Tonemap::Neutral => "neutral",
        Tonemap::Aces => "aces",
        Tonemap::None => "none",
    }
}

impl Studio {
    /// The shown environment and its settings.
    pub fn environment(&self) -> &Env {
        &self.env
    }

    /// Opens an environment file (the panel's path or a drop); on an error the shown one
    /// stays and the error is the status's one line.
    pub fn open_environment(&mut self, renderer: &Renderer, path: &Path) -> Result<()> {
        self.env.open(renderer.gl(), path)?;
        self.status.error = None;
        self.note(format!("environment {}", path.display()));
        Ok(())
    }

    /// Starts with `view --env`'s environment.
    pub fn start_environment(&mut self, renderer: &Renderer, start: EnvStart) -> Result<()> {
        self.env.set(renderer.gl(), start.name, &start.environment)?;
        self.env.rotate_deg = wrap_degrees(start.rotate_deg);
        if !(start.ev.is_finite() && start.ev.abs() <= 64.0) {
            return Err(Error::input(format!("exposure {} EV: give a number of stops from -64 to 64", start.ev)));
        }
        self.env.ev = start.ev;
        self.env.tonemap = start.tonemap;
        if !crate::render::env::SAMPLES.contains(&start.samples) {
            return Err(Error::input(format!("{} environment directions per pixel: give 8 to 1024", start.samples)));
        }
        self.env.samples = start.samples;
        Ok(())
    }

    /// The panel's "Environment" section.
    pub(super) fn environment_ui(&mut self, renderer: &Renderer, ui: &mut egui::Ui) {
        let width = combo_width(ui);
        // A panorama opened from a file is not in the list: the box shows its name until
        // another is picked.
        let names: Vec<&str> = std::iter::once(NONE).chain(hdr::BUNDLED.iter().map(|(name, _)| *name)).collect();
        let current = names.iter().position(|n| *n == self.env.name);
        let pick = match current {
            Some(k) => names[choice(ui, "environment", &names, k)].to_string(),
            None => {
                let mut named = names.clone();
                named.push(&self.env.name);
                let k = choice(ui, "environment", &named, named.len() - 1);
                named[k].to_string()
            }
        };
        if pick != self.env.name {
            match self.env.choose(renderer.gl(), &pick) {
                Ok(()) => {
                    self.status.error = None;
                    self.note(format!("environment {pick}"));
                }
                Err(e) => self.status.fail(e.to_string()),
            }
        }
        let mut open = false;
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.env.path).hint_text("panorama.hdr or .exr").desired_width(180.0));
            open = ui.button("Open...").clicked();
        });
        if open {
            let path = PathBuf::from(self.env.path.trim());
            if let Err(e) = self.open_environment(renderer, &path) {
                self.status.fail(e.to_string());
            }
        }
        ui.small("or drop a 2:1 .hdr/.exr panorama on the window");
        if !self.env.is_on() {
            return;
        }
        ui.small("Alt-drag the view: turn the environment");
        let env = &mut self.env;
        let mut deg = env.rotate_deg;
        let turned = ui.add(egui::Slider::new(&mut deg, -180.0..=180.0).text("rotation °"));
        if turned.changed() {
            env.rotate_deg = wrap_degrees(deg);
        }
        env.moving |= turned.dragged();
        ui.add(egui::Slider::new(&mut env.ev, -MAX_EV..=MAX_EV).step_by(0.1).text("exposure EV"));
        let mut tonemap = env.tonemap;
        labelled(ui, "tone mapping", |ui| {
            egui::ComboBox::from_id_salt("tone mapping").width(width).selected_text(tonemap_name(tonemap)).show_ui(ui, |ui| {
                for t in [Tonemap::Neutral, Tonemap::Aces, Tonemap::None] {
                    ui.selectable_value(&mut tonemap, t, tonemap_name(t));
                }
            });
        });
        env.tonemap = tonemap;
        ui.checkbox(&mut env.show_background, "environment behind the object");
        let mut samples = env.samples;
        labelled(ui, "directions", |ui| {
            egui::ComboBox::from_id_salt("directions").width(width).selected_text(samples.to_string()).show_ui(ui, |ui| {
                // A count from `view --env-samples` outside the steps stays choosable.
                for n in STILL_SAMPLES.into_iter().chain((!STILL_SAMPLES.contains(&env.samples)).then_some(env.samples)) {
                    ui.selectable_value(&mut samples, n, n.to_string());
                }
            });
        });
        env.samples = samples;
        ui.small(format!("per pixel when still; {MOVING_SAMPLES} while the view moves"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_wrap_into_one_turn() {
        assert_eq!(wrap_degrees(190.0), -170.0);
        assert_eq!(wrap_degrees(-190.0), 170.0);
        assert_eq!(wrap_degrees(180.0), -180.0);
        assert_eq!(wrap_degrees(f32::NAN), 0.0);
    }

    #[test]
    fn a_moving_view_takes_fewer_directions() {
        let mut env = Env { moving: true, ..Env::default() };
        assert_eq!(env.samples_now(), MOVING_SAMPLES);
        env.moving = false;
        assert_eq!(env.samples_now(), DEFAULT_SAMPLES);
    }
}
