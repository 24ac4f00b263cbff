//! The side panel: mode, model and material, camera and light, fit, paint tools, timing; and
//! the status block pinned to its foot.

use std::path::PathBuf;

use egui::{Color32, RichText};

use super::super::display::MIN_SCALE;
use super::tools::{Tool, RADIUS};
use super::{short, Mode, Studio};
use crate::render::Renderer;
use crate::scene::{builtin_models, preset_names};

/// Width of the label column of the panel's labelled rows, points: wide enough for the
/// longest label on one line ("paint model").
const LABEL_WIDTH: f32 = 84.0;

/// One budget frame at 60 Hz, milliseconds.
const FRAME_60HZ_MS: f64 = 1000.0 / 60.0;

/// A label in a column of its own width, then `add` in the rest of the row: labels never
/// share a line with a widget that squeezes them into wrapping mid-word.
pub(super) fn labelled<R>(ui: &mut egui::Ui, label: &str, add: impl FnOnce(&mut egui::Ui) -> R) -> R {
    ui.horizontal(|ui| {
        ui.add_sized([LABEL_WIDTH, ui.spacing().interact_size.y], egui::Label::new(label).truncate());
        add(ui)
    })
    .inner
}

/// What a combo box adds to its `width`: the arrow icon and the button's own padding,
/// points. Combo boxes also truncate their text: a long material name would otherwise widen
/// the box past the panel's clipped edge, and the hints below would wrap out of sight.
const COMBO_ARROW: f32 = 20.0;

/// Width left for a combo box after its label, points.
pub(super) fn combo_width(ui: &egui::Ui) -> f32 {
    (ui.available_width() - LABEL_WIDTH - 2.0 * ui.spacing().item_spacing.x - COMBO_ARROW).max(60.0)
}

/// A labelled combo box of `names`, `current` selected; the index picked (`current` when
/// nothing was). Names are shortened in the box and the list ([`short`]); the whole name of
/// the selection shows on hover.
pub(super) fn choice(ui: &mut egui::Ui, label: &str, names: &[&str], current: usize) -> usize {
    let width = combo_width(ui);
    let mut pick = current;
    let whole = names.get(current).copied().unwrap_or("");
    labelled(ui, label, |ui| {
        egui::ComboBox::from_id_salt(label)
            .width(width)
            .truncate()
            .selected_text(short(whole))
            .show_ui(ui, |ui| {
                for (k, name) in names.iter().enumerate() {
                    ui.selectable_value(&mut pick, k, short(name));
                }
            })
            .response
            .on_hover_text(whole);
    });
    pick
}

impl Studio {
    pub(super) fn controls(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let v = ui.selectable_value(&mut self.mode, Mode::View, "View");
            let p = ui.selectable_value(&mut self.mode, Mode::Paint, "Paint");
            self.layout.mode_buttons = [Some(self.to_pixels(v.rect)), Some(self.to_pixels(p.rect))];
            ui.label("(Tab)");
        });
        ui.separator();

        egui::CollapsingHeader::new("Model and material").default_open(true).show(ui, |ui| self.catalogue_ui(renderer, ui));
        self.sphere_panel(renderer, ui);
        egui::CollapsingHeader::new("Camera and light").default_open(true).show(ui, |ui| self.camera_ui(ui));
        egui::CollapsingHeader::new("Environment").default_open(true).show(ui, |ui| self.environment_ui(renderer, ui));
        egui::CollapsingHeader::new("Fit").default_open(true).show(ui, |ui| {
            let change = self.fit.ui(ui);
            let settings = self.fit_settings();
            let e = &mut self.easel;
            if change.settings {
                if let Err(err) = e.session.set_settings(settings) {
                    self.status.fail(err.to_string());
                }
            }
            if change.mapping {
                e.session.set_mapping(self.fit.mapping);
            }
            e.refine_needed |= change.settings || change.mapping || change.refit;
            // The session adds s(θ_d) by itself, as `fit` does (the sliders never do): say so
            // beside the count.
            let difference = |m: &crate::material::Material| m.terms.iter().any(|t| t.factors.iter().any(|f| f.spec.input == crate::factor::Input::Difference));
            if e.session.material().is_some_and(difference) {
                ui.small(format!("+ {} for s(θ_d): the painted views show side or back light", crate::factor::defaults::RES_DIFFERENCE));
            }
        });
        if self.mode == Mode::Paint {
            egui::CollapsingHeader::new("Paint").default_open(true).show(ui, |ui| self.paint_ui(renderer, ui));
        }
        egui::CollapsingHeader::new("Timing").default_open(false).show(ui, |ui| self.timing_ui(ui));
    }

    fn catalogue_ui(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        let models: Vec<&str> = self.catalogue.models.iter().map(|m| m.name.as_str()).collect();
        let pick = choice(ui, "model", &models, self.catalogue.model);
        if pick != self.catalogue.model {
            if let Err(e) = self.select_model(renderer, pick) {
                self.status.fail(e.to_string());
            }
        }
        let materials: Vec<&str> = self.catalogue.materials.iter().map(|m| m.name.as_str()).collect();
        let pick = choice(ui, "material", &materials, self.catalogue.material);
        self.select_material(pick);
        ui.small("Drop a .glb/.gltf model, a material directory or a painting on the window to open it.");
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.save_material).desired_width(150.0));
            if ui.button("Save material").clicked() {
                self.save_material_now();
            }
        });
    }

    fn camera_ui(&mut self, ui: &mut egui::Ui) {
        ui.small("Drag: orbit · Shift/middle-drag: pan · wheel: zoom · right-drag: move the light · Alt-drag: turn the environment");
        let light = &mut self.stage.light;
        let mut az = light.azimuth.to_degrees();
        let mut el = light.elevation.to_degrees();
        let a = ui.add(egui::Slider::new(&mut az, -180.0..=180.0).text("light azimuth °"));
        let e = ui.add(egui::Slider::new(&mut el, -89.0..=89.0).text("light elevation °"));
        if a.changed() || e.changed() {
            light.azimuth = az.to_radians();
            light.elevation = el.to_radians();
        }
        ui.add(egui::Slider::new(&mut light.intensity, 0.0..=4.0).text("light intensity"));
        let scale = &mut self.stage.render_scale;
        let mut value = scale.scale();
        let mut auto = scale.is_auto();
        ui.horizontal(|ui| {
            let slider = ui
                .add(egui::Slider::new(&mut value, MIN_SCALE..=1.0).text("render scale"))
                .on_hover_text("Render the model at this fraction of the window's resolution: faster on software GL");
            if slider.changed() {
                auto = false;
            }
            ui.checkbox(&mut auto, "auto").on_hover_text("Pick the scale from frame times, to keep 30 frames a second");
        });
        if !auto && (value != scale.scale() || scale.is_auto()) {
            scale.set_fixed(value);
        } else if auto {
            scale.set_auto();
        }
        if ui.button("Reset view").clicked() {
            self.stage.reset_view();
        }
    }

    fn paint_ui(&mut self, renderer: &mut Renderer, ui: &mut egui::Ui) {
        if !self.easel.scene_mode {
            let models = builtin_models();
            let current = models.iter().position(|n| *n == self.easel.paint_model).unwrap_or(usize::MAX);
            let pick = choice(ui, "paint model", models, current);
            if pick != current {
                if let Err(e) = self.easel.restart(renderer, models[pick].to_string(), preset_names()[0]) {
                    self.status.fail(e.to_string());
                }
            }
            ui.label("views (every painted view feeds the fit):");
            ui.horizontal_wrapped(|ui| {
                for name in preset_names() {
                    let open = self.easel.view_names.iter().position(|n| n == name);
                    let label = if open.is_some_and(|k| self.easel.is_painted(k)) {
                        RichText::new(format!("{name} *")).strong().color(Color32::from_rgb(250, 170, 80))
                    } else {
                        RichText::new(name.to_string())
                    };
                    let selected = open == Some(self.easel.active);
                    if ui.selectable_label(selected, label).clicked() {
                        if let Err(e) = self.easel.open_view(renderer, name) {
                            self.status.fail(e.to_string());
                        }
                    }
                }
            });
        }
        let tools = &mut self.tools;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut tools.tool, Tool::Brush, "Brush (B)");
            ui.selectable_value(&mut tools.tool, Tool::Eraser, "Eraser (E)");
            ui.selectable_value(&mut tools.tool, Tool::Fill, "Fill (F)");
        });
        ui.horizontal(|ui| {
            ui.color_edit_button_rgb(&mut tools.brush.color);
            ui.label("colour (right-click the canvas to pick)");
        });
        ui.add(egui::Slider::new(&mut tools.brush.radius, RADIUS).logarithmic(true).text("size ([ ])"));
        ui.add(egui::Slider::new(&mut tools.brush.hardness, 0.0..=1.0).text("hardness"));
        ui.add(egui::Slider::new(&mut tools.brush.opacity, 0.0..=1.0).text("opacity"));
        let (can_undo, can_redo) = self
            .easel
            .session
            .views
            .get(self.easel.active)
            .map_or((false, false), |v| (v.canvas.can_undo(), v.canvas.can_redo()));
        ui.horizontal(|ui| {
            if ui.add_enabled(can_undo, egui::Button::new("Undo")).clicked() {
                self.easel.undo();
            }
            if ui.add_enabled(can_redo, egui::Button::new("Redo")).clicked() {
                self.easel.redo();
            }
            if ui.button("Fill all").clicked() {
                self.easel.fill_all(self.tools.brush, false);
            }
            if ui.button("Clear").clicked() {
                self.easel.fill_all(self.tools.brush, true);
            }
        });
        if ui.button("Start from the reference").clicked() {
            self.easel.start_from_reference();
        }
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.tools.show_outline, "outline");
            ui.checkbox(&mut self.tools.show_reference, "reference");
        });
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.tools.save_painting).desired_width(150.0));
            if ui.button("Save painting").clicked() {
                self.save_painting_now();
            }
        });
        ui.small("Saves the active view's painting and its scene (.gltf beside it) for `brdfpaint fit`.");
    }

    /// The stroke → frame breakdown (the pinned status block has the summary).
    fn timing_ui(&mut self, ui: &mut egui::Ui) {
        let t = &self.meter.timings;
        if t.count == 0 {
            ui.label("Paint a stroke to measure stroke -> frame.");
            return;
        }
        egui::Grid::new("timing").num_columns(2).show(ui, |ui| {
            for (name, v) in [
                ("stroke", t.stroke_ms),
                ("samples", t.values_ms),
                ("solve", t.solve_ms),
                ("upload", t.upload_ms),
                ("frame: 3D view", t.view_ms),
                ("frame: whole window", t.frame_ms),
            ] {
                ui.label(name);
                ui.label(format!("{v:.2} ms"));
                ui.end_row();
            }
        });
    }

    /// Pinned to the panel's foot: the stroke → frame summary, the frame rate and render
    /// scale, the status line and the last error. Lines are always there (blank until they
    /// have something to say) so the block keeps its height.
    pub(super) fn status_ui(&mut self, ui: &mut egui::Ui) {
        ui.add_space(2.0);
        let t = &self.meter.timings;
        let (text, colour) = if t.count == 0 {
            ("stroke -> frame: paint a stroke to measure".to_string(), Color32::from_gray(150))
        } else {
            let ok = t.total_ms <= FRAME_60HZ_MS;
            let colour = if ok { Color32::from_rgb(90, 200, 110) } else { Color32::from_rgb(230, 120, 80) };
            (format!("stroke -> frame {:.1} ms ({} samples)", t.total_ms, t.samples), colour)
        };
        ui.colored_label(colour, text);
        let scale = &self.stage.render_scale;
        let rate = match scale.median_frame_ms() {
            Some(ms) => format!("frame {ms:.0} ms ({:.0} fps)", 1000.0 / ms.max(1e-3)),
            None => "frame: measuring".to_string(),
        };
        let how = if scale.is_auto() { "auto" } else { "fixed" };
        ui.label(format!("{rate} · render scale {:.2} ({how})", scale.scale()));
        if let Some(r) = &self.meter.last {
            let what = if r.exact { "exact" } else { "preparing the new pixels..." };
            ui.small(format!(
                "fit: {} samples, mapping {}, {what}{}",
                r.samples,
                r.map.map_or("-", |m| m.name()),
                r.errors.map_or(String::new(), |e| format!(", relative RMS {:.3}", e.rms_relative))
            ));
        } else {
            ui.small("fit: -");
        }
        ui.separator();
        if let Some(e) = &self.status.error {
            ui.colored_label(Color32::from_rgb(240, 110, 90), e);
        }
        ui.label(self.status());
        ui.add_space(2.0);
    }

    fn save_material_now(&mut self) {
        let path = PathBuf::from(self.save_material.trim());
        let saved = match self.current_material() {
            Some(m) => m.save(&path).map_err(|e| format!("cannot save the material: {e}")),
            None => Err("nothing to save: no material yet".to_string()),
        };
        match saved {
            Ok(()) => {
                self.status.error = None;
                self.note(format!("saved material to {}", path.display()));
            }
            Err(e) => self.status.fail(e),
        }
    }

    fn save_painting_now(&mut self) {
        let path = PathBuf::from(self.tools.save_painting.trim());
        let Some(v) = self.easel.session.views.get(self.easel.active) else { return };
        let result = v.canvas.painting().write(&path).and_then(|()| v.scene.write_gltf(path.with_extension("gltf")));
        match result {
            Ok(()) => {
                self.status.error = None;
                self.note(format!("saved {} and {}", path.display(), path.with_extension("gltf").display()));
            }
            Err(e) => self.status.fail(format!("cannot save the painting: {e}")),
        }
    }
}
