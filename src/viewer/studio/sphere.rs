//! Lit spheres and MatCaps in the viewer: a dropped picture of a sphere (or one opened from
//! the panel's "Lit sphere" section) becomes the one view to paint, fitted as `brdfpaint fit
//! --lit-sphere` fits it ([`crate::live::sphere`]). The estimated light is drawn as a sun
//! over the sphere; dragging the sun moves the light, and the fit follows in the background.
//! The disk the picture was read with is drawn too: dragging its outline changes its radius,
//! dragging its centre cross moves it (the sun wins where they meet), and on release the
//! picture is read again with that disk, as `fit --disk` would read it.
//! The 3D view is lit from the same direction (in its camera's frame), so the model shows
//! the material as the picture shows it.

use std::path::{Path, PathBuf};

use egui::{Color32, Pos2, Rect, Stroke, Vec2};
use glam::DVec3;

use super::super::camera::LightControl;
use super::easel::Easel;
use super::{short, Mode, Studio};
use crate::error::Result;
use crate::images::Painting;
use crate::litsphere::{self, Disk, Picture};
use crate::live::sphere::VIEW_NAME;
use crate::live::{check_painting_size, SphereSession};
use crate::render::Renderer;

/// Pointer distance within which a press grabs the sun, points.
const GRAB: f32 = 14.0;

/// The viewer's lit-sphere state.
#[derive(Default)]
pub(super) struct Sphere {
    /// The open lit sphere, while its view is the one painted.
    pub session: Option<SphereSession>,
    /// A dropped picture that could be a lit sphere or a painting of the active view, until
    /// the user says which.
    asking: Option<(PathBuf, Picture)>,
    /// The path typed in the panel.
    path: String,
    /// The sun is being dragged.
    dragging: bool,
    /// The disk's outline or centre is being dragged.
    circle: Option<CircleDrag>,
    /// A disk dragged to and released, to read the picture with (in its pixels as fitted).
    dropped_disk: Option<Disk>,
}

/// What of the disk a drag holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Handle {
    /// The centre cross: the disk moves.
    Centre,
    /// The outline: the radius changes.
    Rim,
}

/// A drag of the disk: what it holds, the disk and pointer it started from, and the disk
/// it has reached (drawn while dragging).
#[derive(Clone, Copy, Debug)]
struct CircleDrag {
    handle: Handle,
    start: Disk,
    press: Pos2,
    now: Disk,
}

impl CircleDrag {
    /// The disk with the pointer at `p` (`scale`: points per picture pixel).
    fn follow(&mut self, p: Pos2, centre: Pos2, scale: f32) {
        let s = f64::from(scale.max(1e-6));
        self.now = match self.handle {
            Handle::Centre => {
                let d = p - self.press;
                Disk { cx: self.start.cx + f64::from(d.x) / s, cy: self.start.cy + f64::from(d.y) / s, ..self.start }
            }
            // A sphere is found only with a radius of 4 pixels or more.
            Handle::Rim => Disk { r: (f64::from(p.distance(centre)) / s).max(4.0), ..self.start },
        };
    }
}

/// What a dropped picture is.
enum Dropped {
    Painting,
    Sphere(Picture),
    /// Either: ask.
    Either(Picture),
}

/// A picture whose sphere [`litsphere::find_disk`] finds is a lit sphere, unless it could
/// also be a painting of the active view: of the view's size rule, with the disk where the
/// view's object is (a painting of a sphere's view). Then the user is asked.
fn classify(easel: &Easel, path: &Path) -> Result<Dropped> {
    let original = Painting::read(path)?;
    let Ok(picture) = Picture::new(path.display().to_string(), &original, litsphere::MAX_SIDE) else {
        return Ok(Dropped::Painting);
    };
    let name = path.display().to_string();
    let could_paint = easel.session.views.get(easel.active).is_some_and(|v| {
        check_painting_size(v, &name, original.width, original.height).is_ok() && overlap(&picture, &v.hit, v.width, v.height) >= 0.9
    });
    Ok(if could_paint { Dropped::Either(picture) } else { Dropped::Sphere(picture) })
}

/// Intersection over union of the picture's disk and a `w` × `h` object mask, the disk
/// scaled to the mask's grid.
fn overlap(picture: &Picture, hit: &[bool], w: usize, h: usize) -> f64 {
    let s = picture.painting.width as f64 / w as f64;
    let d = picture.disk;
    let (mut both, mut either) = (0usize, 0usize);
    for j in 0..h {
        for i in 0..w {
            let (x, y) = ((i as f64 + 0.5) * s - d.cx, (j as f64 + 0.5) * s - d.cy);
            let inside = x * x + y * y < d.r * d.r;
            both += (inside && hit[j * w + i]) as usize;
            either += (inside || hit[j * w + i]) as usize;
        }
    }
    both as f64 / either.max(1) as f64
}

/// The sun's place over the sphere: the light's direction seen from the viewer, on the disk.
fn sun_at(centre: Pos2, radius: f32, light: DVec3) -> Pos2 {
    centre + Vec2::new(light.x as f32, -light.y as f32) * radius
}

/// The light whose sun is at `p`: in front of the sphere (or behind it, with `behind`),
/// on its rim when `p` is outside the disk.
fn light_at(centre: Pos2, radius: f32, p: Pos2, behind: bool) -> DVec3 {
    let d = (p - centre) / radius.max(1.0);
    let mut xy = glam::DVec2::new(d.x as f64, -d.y as f64);
    if xy.length() > 1.0 {
        xy = xy.normalize();
    }
    let z = (1.0 - xy.length_squared()).max(0.0).sqrt();
    DVec3::new(xy.x, xy.y, if behind { -z } else { z })
}

impl Studio {
    /// The open lit sphere, if its view is the one painted.
    pub fn lit_sphere(&self) -> Option<&SphereSession> {
        self.sphere.session.as_ref()
    }

    /// Opens a dropped picture: a lit sphere or MatCap, a painting for the active view, or,
    /// when it could be either, asks ([`classify`]).
    pub(super) fn open_picture(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        match classify(&self.easel, path)? {
            Dropped::Painting => self.open_painting(renderer, path),
            Dropped::Sphere(picture) => self.open_sphere(renderer, picture),
            Dropped::Either(picture) => {
                self.note(format!("{}: a lit sphere, or a painting of view '{}'?", path.display(), self.easel.view_label(self.easel.active)));
                self.sphere.asking = Some((path.to_path_buf(), picture));
                Ok(())
            }
        }
    }

    /// Opens the picture at `path` as a lit sphere or MatCap, whatever it looks like.
    pub fn open_lit_sphere(&mut self, renderer: &mut Renderer, path: &Path) -> Result<()> {
        let picture = Picture::read(path, litsphere::MAX_SIDE)?;
        self.open_sphere(renderer, picture)
    }

    /// Starts a lit-sphere session already opened (its light estimated): its view becomes
    /// the only one to paint, and the live material its fit.
    pub fn start_lit_sphere(&mut self, renderer: &mut Renderer, sphere: SphereSession) -> Result<()> {
        let view = sphere.view(renderer, sphere.light())?;
        let e = &mut self.easel;
        e.session = sphere.paint_session(&self.fit.settings(), e.session.mapping());
        // `fit` reads a lit sphere through its own path, not as a scene's painting.
        e.session.set_full_fit(false);
        e.view_names.clear();
        e.watcher = None;
        e.scene_mode = true;
        e.add_view(VIEW_NAME, view);
        // A full fit, prepared in the background.
        e.canvas_changed = true;
        e.refine_needed = true;
        let l = sphere.light();
        let how = match &sphere.estimate {
            Some(est) => format!(
                "light estimated at ({:.2}, {:.2}, {:.2}), sure to within {:.0}°: drag the sun to correct it",
                l.x, l.y, l.z, est.spread_deg
            ),
            None => format!("light ({:.2}, {:.2}, {:.2}) as given", l.x, l.y, l.z),
        };
        let name = sphere.picture.name.clone();
        self.sphere.session = Some(sphere);
        self.sphere.asking = None;
        self.light_stage();
        self.mode = Mode::Paint;
        if !self.catalogue.shows_live() {
            self.catalogue.material = 0;
            self.shown_material_changed();
        }
        self.note(format!("lit sphere {}: {how}", short(&name)));
        Ok(())
    }

    fn open_sphere(&mut self, renderer: &mut Renderer, picture: Picture) -> Result<()> {
        self.start_lit_sphere(renderer, SphereSession::from_picture(picture, None)?)
    }

    /// Back to the standard views of the paint model.
    fn close_sphere(&mut self, renderer: &mut Renderer) {
        self.sphere.session = None;
        self.sphere.dragging = false;
        self.sphere.circle = None;
        self.easel.scene_mode = false;
        let model = self.easel.paint_model.clone();
        let restarted = self.easel.restart(renderer, model, crate::scene::preset_names()[0]);
        // The standard views are fitted by the fit controls' settings, without the lit-sphere rule.
        if let Err(e) = restarted.and_then(|()| self.easel.session.set_settings(self.fit.settings())) {
            self.status.fail(e.to_string());
        }
    }

    /// The settings the fit controls ask for, under the lit-sphere rule while one is open.
    pub(super) fn fit_settings(&self) -> crate::factor::Settings {
        let s = self.fit.settings();
        match &self.sphere.session {
            Some(sphere) => sphere.settings(&s),
            None => s,
        }
    }

    /// The 3D view's light from the lit sphere's direction, turned into the orbit camera's
    /// frame (the picture's frame is its camera's).
    fn light_stage(&mut self) {
        let Some(s) = &self.sphere.session else { return };
        let towards = self.stage.orbit.world_from_camera().transform_vector3(s.light().as_vec3());
        let intensity = self.stage.light.intensity;
        self.stage.light = LightControl { intensity, ..LightControl::towards(towards) };
    }

    /// Moves the lit sphere's light to `light` (towards the light, the picture's frame: x
    /// right, y up, z to the viewer); the fit follows in the background.
    pub fn set_sphere_light(&mut self, light: DVec3) -> Result<()> {
        let Some(s) = self.sphere.session.as_mut() else {
            return Err(crate::Error::input("no lit sphere is open"));
        };
        s.set_light(light)?;
        self.light_stage();
        Ok(())
    }

    /// Whether a light asked for waits to be applied (frames must keep coming).
    pub(super) fn sphere_waiting(&self) -> bool {
        self.sphere.session.as_ref().is_some_and(|s| s.waiting())
    }

    /// Applies the light asked for when the paint session can take it: before the tick
    /// polls for a finished prepare, so a prepare that lands is solved before the next one
    /// replaces it.
    pub(super) fn sphere_tick(&mut self, renderer: &mut Renderer) {
        if self.easel.view_names.first().map(String::as_str) != Some(VIEW_NAME) {
            // The easel moved on (another model's views): the lit sphere is closed.
            self.sphere.session = None;
            return;
        }
        let Some(s) = self.sphere.session.as_mut() else { return };
        let e = &mut self.easel;
        let solved = !e.refine_needed;
        match s.update(renderer, &mut e.session, 0, solved) {
            Ok(true) => {
                e.generation += 1;
                e.canvas_changed = true;
                e.refine_needed = true;
            }
            Ok(false) => {}
            Err(err) => self.status.fail(format!("cannot light the sphere: {err}")),
        }
    }

    /// The sun over the sphere on the canvas, and its drag. `true` while the sun is dragged
    /// (the brush must not paint).
    pub(super) fn sphere_canvas(&mut self, ui: &egui::Ui, rect: Rect, scale: f32) -> bool {
        let Some(s) = self.sphere.session.as_ref() else { return false };
        let d = s.picture.disk;
        let centre = rect.min + Vec2::new(d.cx as f32, d.cy as f32) * scale;
        let radius = d.r as f32 * scale;
        let light = s.light();
        let sun = sun_at(centre, radius, light);
        let (pressed, down, origin, pointer) =
            ui.input(|i| (i.pointer.primary_pressed(), i.pointer.primary_down(), i.pointer.press_origin(), i.pointer.latest_pos()));
        if pressed && origin.is_some_and(|o| o.distance(sun) <= GRAB) {
            self.sphere.dragging = true;
        }
        let circle = self.disk_canvas(ui, rect, scale, (pressed, down, origin, pointer));
        if self.sphere.dragging && !down {
            self.sphere.dragging = false;
        }
        if self.sphere.dragging {
            if let Some(p) = pointer {
                let l = light_at(centre, radius, p, light.z < 0.0);
                if let Err(e) = self.set_sphere_light(l) {
                    self.status.fail(e.to_string());
                }
            }
        }
        // Drawn after the drag, where the sun is now.
        let light = self.sphere.session.as_ref().map_or(light, |s| s.light());
        let sun = sun_at(centre, radius, light);
        let painter = ui.painter_at(rect);
        let hot = self.sphere.dragging || pointer.is_some_and(|p| p.distance(sun) <= GRAB);
        let colour = if hot { Color32::from_rgb(255, 236, 150) } else { Color32::from_rgb(255, 200, 60) };
        let dark = Stroke::new(3.0, Color32::from_black_alpha(140));
        let line = Stroke::new(1.5, colour);
        // From the sphere's centre to the sun: where the light comes from.
        painter.line_segment([centre, sun], dark);
        painter.line_segment([centre, sun], line);
        for k in 0..8 {
            let a = std::f32::consts::TAU * k as f32 / 8.0;
            let ray = Vec2::new(a.cos(), a.sin());
            painter.line_segment([sun + ray * 8.0, sun + ray * 12.0], line);
        }
        if light.z >= 0.0 {
            painter.circle(sun, 6.0, colour, dark);
        } else {
            // Behind the sphere: a hollow sun.
            painter.circle_stroke(sun, 6.0, Stroke::new(2.0, colour));
        }
        self.sphere.dragging || circle
    }

    /// The disk's outline and centre cross on the canvas, and their drag (after the sun's:
    /// a press that grabbed the sun grabs nothing else). `true` while the disk is dragged.
    fn disk_canvas(&mut self, ui: &egui::Ui, rect: Rect, scale: f32, (pressed, down, origin, pointer): (bool, bool, Option<Pos2>, Option<Pos2>)) -> bool {
        let Some(s) = self.sphere.session.as_ref() else { return false };
        let d = s.picture.disk;
        let at = |d: &Disk| (rect.min + Vec2::new(d.cx as f32, d.cy as f32) * scale, d.r as f32 * scale);
        let (centre, radius) = at(&d);
        if pressed && !self.sphere.dragging {
            if let Some(o) = origin {
                let handle = if o.distance(centre) <= GRAB {
                    Some(Handle::Centre)
                } else if (o.distance(centre) - radius).abs() <= GRAB * 0.5 {
                    Some(Handle::Rim)
                } else {
                    None
                };
                self.sphere.circle = handle.map(|handle| CircleDrag { handle, start: d, press: o, now: d });
            }
        }
        if let (Some(drag), Some(p)) = (self.sphere.circle.as_mut(), pointer) {
            drag.follow(p, centre, scale);
        }
        if !down {
            if let Some(drag) = self.sphere.circle.take() {
                if drag.now != drag.start {
                    self.sphere.dropped_disk = Some(drag.now);
                }
            }
        }
        let shown = self.sphere.circle.map_or(d, |c| c.now);
        let (c, r) = at(&shown);
        let painter = ui.painter_at(rect);
        let hot = self.sphere.circle.is_some();
        let colour = if hot { Color32::from_rgb(150, 230, 255) } else { Color32::from_rgba_unmultiplied(120, 200, 255, 170) };
        painter.circle_stroke(c, r, Stroke::new(3.0, Color32::from_black_alpha(100)));
        painter.circle_stroke(c, r, Stroke::new(1.2, colour));
        for arm in [Vec2::X, Vec2::Y] {
            painter.line_segment([c - arm * 9.0, c + arm * 9.0], Stroke::new(3.0, Color32::from_black_alpha(100)));
            painter.line_segment([c - arm * 9.0, c + arm * 9.0], Stroke::new(1.5, colour));
        }
        hot
    }

    /// Reads the picture again with the disk dragged to, if one was released: a new session
    /// (its light estimated again), as `fit --lit-sphere --disk` reads it. A disk the
    /// picture cannot take is one line in the status, and the session stays.
    pub(super) fn apply_dropped_disk(&mut self, renderer: &mut Renderer) {
        let Some(disk) = self.sphere.dropped_disk.take() else { return };
        let Some(s) = self.sphere.session.as_ref() else { return };
        let (name, f) = (s.picture.name.clone(), s.picture.scale);
        // In the file's pixels, as --disk gives it.
        let given = Disk { cx: disk.cx * f, cy: disk.cy * f, r: disk.r * f };
        let opened = Picture::read_in(Path::new(&name), litsphere::MAX_SIDE, Some(given))
            .and_then(|p| SphereSession::from_picture(p, None))
            .and_then(|session| self.start_lit_sphere(renderer, session));
        match opened {
            Ok(()) => self.note(format!("{}: disk at ({:.1}, {:.1}), radius {:.1}, as dragged", short(&name), given.cx, given.cy, given.r)),
            Err(e) => self.status.fail(e.to_string()),
        }
    }

    /// The panel's "Lit sphere" section: the open entry, and for an open lit sphere its
    /// light, how sure the estimate is, and the ways to correct it.
    pub(super) fn sphere_panel(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        let open = self.sphere.session.is_some();
        // Its own id while a lit sphere is open, so the section opens with it.
        egui::CollapsingHeader::new("Lit sphere").id_salt(("lit sphere", open)).default_open(open).show(ui, |ui| {
            if let Some(s) = &self.sphere.session {
                let l = s.light();
                ui.label(format!("light ({:.2}, {:.2}, {:.2})", l.x, l.y, l.z));
                ui.small(format!("{:.0}° from the view; x right, y up, z to the viewer", l.z.clamp(-1.0, 1.0).acos().to_degrees()));
                match &s.estimate {
                    Some(e) => {
                        ui.small(format!(
                            "estimated at ({:.2}, {:.2}, {:.2}), sure to within {:.0}°; {:.0}% of the disk follows one light",
                            e.direction.x,
                            e.direction.y,
                            e.direction.z,
                            e.spread_deg,
                            100.0 * e.inliers
                        ));
                    }
                    None => {
                        ui.small("given, not estimated");
                    }
                }
                let refitting = s.waiting() || self.easel.session.preparing();
                ui.small(if refitting { "refitting for the new light..." } else { "Drag the sun on the sphere to move the light; the outline or its centre cross to correct the disk." });
                let mut behind = l.z < 0.0;
                let estimate = s.estimate.map(|e| e.direction).filter(|&e| e != l);
                let mut next = None;
                if ui.checkbox(&mut behind, "light behind the sphere").changed() {
                    next = Some(DVec3::new(l.x, l.y, -l.z));
                }
                let mut close = false;
                ui.horizontal(|ui| {
                    if ui.add_enabled(estimate.is_some(), egui::Button::new("Back to the estimate")).clicked() {
                        next = estimate;
                    }
                    close = ui.button("Close").clicked();
                });
                if let Some(n) = next {
                    if let Err(e) = self.set_sphere_light(n) {
                        self.status.fail(e.to_string());
                    }
                }
                if close {
                    self.close_sphere(renderer);
                    return;
                }
                ui.separator();
            }
            ui.small("Open a picture of a sphere or a MatCap (PNG, JPEG, EXR), or drop it on the window:");
            ui.horizontal(|ui| {
                ui.add(egui::TextEdit::singleline(&mut self.sphere.path).desired_width(150.0).hint_text("sphere.png"));
                if ui.button("Open").clicked() {
                    let path = PathBuf::from(self.sphere.path.trim());
                    match self.open_lit_sphere(renderer, &path) {
                        Ok(()) => self.status.error = None,
                        Err(e) => self.status.fail(e.to_string()),
                    }
                }
            });
        });
    }

    /// A dropped picture that could be a lit sphere or a painting: asks which.
    pub(super) fn sphere_ask(&mut self, renderer: &mut Renderer, ui: &egui::Ui) {
        let Some((path, _)) = &self.sphere.asking else { return };
        let view = self.easel.view_label(self.easel.active);
        let text = format!("{} shows a sphere. Open it as:", short(&path.display().to_string()));
        let mut answer = None;
        egui::Modal::new(egui::Id::unique("lit sphere or painting")).show(ui.ctx(), |ui| {
            ui.label(text);
            ui.horizontal(|ui| {
                if ui.button("Lit sphere").clicked() {
                    answer = Some(true);
                }
                if ui.button(format!("Painting of view '{view}'")).clicked() {
                    answer = Some(false);
                }
                if ui.button("Cancel").clicked() {
                    self.sphere.asking = None;
                }
            });
        });
        let Some(as_sphere) = answer else { return };
        let Some((path, picture)) = self.sphere.asking.take() else { return };
        let result = if as_sphere { self.open_sphere(renderer, picture) } else { self.open_painting(renderer, &path) };
        if let Err(e) = result {
            self.status.fail(e.to_string());
        }
    }
}
