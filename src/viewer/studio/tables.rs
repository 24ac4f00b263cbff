//! The factor tables of the shown material: curves for 1D tables, images for 2D ones.

use egui::{Color32, ColorImage, Pos2, Sense, Stroke, TextureHandle, TextureOptions, Vec2};

use crate::factor::{Domain, Input};
use crate::images::linear_to_srgb;
use crate::material::Material;

/// Textures of the 2D tables, made once per material.
#[derive(Default)]
pub(super) struct TablePlots {
    textures: Vec<Option<TextureHandle>>,
    /// The shown material changed: make the textures again.
    pub dirty: bool,
}

impl TablePlots {
    /// The tables of `material` (borrowed: drawing them copies nothing but the 2D tables'
    /// texels, once per material).
    pub fn ui(&mut self, ui: &mut egui::Ui, material: Option<&Material>) {
        let Some(material) = material else {
            ui.label("No material yet.");
            return;
        };
        if self.dirty {
            self.textures.clear();
            self.dirty = false;
        }
        ui.horizontal(|ui| {
            ui.strong("Factor tables");
            // The analytic base the tables multiply, when there is one (`fit --base`).
            let base = material.terms.first().and_then(|t| t.base).map_or(String::new(), |b| format!(", over the {} lobe, {}", b.lobe.name(), b.width()));
            ui.label(format!(
                "({:?}, {} term{}, mapping {}{base})",
                material.kind,
                material.terms.len(),
                if material.terms.len() == 1 { "" } else { "s" },
                material.terms.first().map_or("-", |t| t.map.name())
            ));
        });
        let height = (ui.available_height() - 24.0).clamp(40.0, 400.0);
        egui::ScrollArea::horizontal().show(ui, |ui| {
            // Captions never wrap: past the panel's width (a material map's many factors)
            // they would wrap word by word into tall columns, and the panel, which grows to
            // its content, would push the 3D view out of the window.
            ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
            ui.horizontal(|ui| {
                let mut k = 0;
                for (ti, term) in material.terms.iter().enumerate() {
                    for f in &term.factors {
                        ui.vertical(|ui| {
                            let name = match f.spec.input {
                                Input::Light => "p(l)",
                                Input::Half => "q(h)",
                                Input::View => "r(v)",
                                Input::Uv => "s(uv)",
                                Input::Difference => "s(θ_d)",
                                Input::HalfDifference => "q(θ_h, θ_d)",
                                Input::Custom(_) => "custom",
                            };
                            let max = f.texels.iter().flat_map(|t| t.iter()).fold(0.0f32, |a, &b| a.max(b));
                            // A warped table's nodes are uniform in t^(1/γ): the curve is drawn over them.
                            let warp = if f.spec.warp == 1.0 { String::new() } else { format!(" warped γ={}", f.spec.warp) };
                            // A leaned half vector h_k ∝ l + k v: where the painter put the highlight.
                            let lean = if f.spec.lean == 1.0 { String::new() } else { format!(" leaned k={:.2}", f.spec.lean) };
                            ui.small(format!("term {ti} {name}: {:?} {}D, {} nodes{warp}{lean}, max {max:.3}", f.spec.param, f.spec.dim(), f.spec.res));
                            if f.spec.dim() == 1 {
                                plot_curves(ui, &f.texels, max, f.spec.domain == Domain::Sphere, Vec2::new(height * 1.8, height - 18.0));
                            } else {
                                let tex = self.texture(ui.ctx(), k, f.spec.res, &f.texels, max);
                                let side = height - 18.0;
                                ui.image((tex, Vec2::splat(side)));
                            }
                        });
                        k += 1;
                    }
                }
            });
        });
    }

    fn texture(&mut self, ctx: &egui::Context, k: usize, res: usize, texels: &[[f32; 3]], max: f32) -> egui::TextureId {
        while self.textures.len() <= k {
            self.textures.push(None);
        }
        let slot = &mut self.textures[k];
        let tex = slot.get_or_insert_with(|| {
            let s = if max > 0.0 { 1.0 / max } else { 1.0 };
            // Row y of the table is its second coordinate: draw it upwards.
            let mut pixels = Vec::with_capacity(res * res);
            for y in (0..res).rev() {
                for x in 0..res {
                    let t = texels.get(y * res + x).copied().unwrap_or_default();
                    let e = t.map(|v| (linear_to_srgb(v * s) * 255.0 + 0.5) as u8);
                    pixels.push(Color32::from_rgb(e[0], e[1], e[2]));
                }
            }
            ctx.load_texture(format!("table {k}"), ColorImage::new([res, res], pixels), TextureOptions::NEAREST)
        });
        tex.id()
    }
}

/// RGB curves of a 1D table over its nodes, scaled to `max`.
fn plot_curves(ui: &mut egui::Ui, texels: &[[f32; 3]], max: f32, sphere: bool, size: Vec2) {
    let (rect, _) = ui.allocate_exact_size(size, Sense::hover());
    let p = ui.painter_at(rect);
    p.rect_filled(rect, 2.0, Color32::from_gray(24));
    let n = texels.len().max(2);
    let colours = [Color32::from_rgb(235, 90, 80), Color32::from_rgb(110, 210, 110), Color32::from_rgb(100, 150, 255)];
    let s = if max > 0.0 { 1.0 / max } else { 1.0 };
    for (c, colour) in colours.iter().enumerate() {
        let points: Vec<Pos2> = texels
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let x = rect.min.x + rect.width() * i as f32 / (n - 1) as f32;
                let y = rect.max.y - 2.0 - (rect.height() - 4.0) * (t[c] * s).clamp(0.0, 1.0);
                Pos2::new(x, y)
            })
            .collect();
        p.line(points, Stroke::new(1.5, *colour));
    }
    if sphere {
        // The horizon of the sphere domain sits at the middle of a radius table (ρ = 1 of 2).
        p.line_segment(
            [Pos2::new(rect.center().x, rect.min.y), Pos2::new(rect.center().x, rect.max.y)],
            Stroke::new(1.0, Color32::from_gray(60)),
        );
    }
}
