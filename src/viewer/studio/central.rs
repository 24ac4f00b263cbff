//! The central area: the canvas to paint on (paint mode) and the 3D view.

use std::time::Instant;

use egui::{Color32, ColorImage, PointerButton, Pos2, Rect, Sense, Stroke, TextureHandle, TextureOptions, Vec2};

use super::easel::Easel;
use super::environment::DEGREES_PER_POINT;
use super::tools::Tool;
use super::{short, Mode, Studio};
use crate::images::linear_to_srgb;
use crate::live::{CanvasRect, WatchStatus};
use super::super::display::WindowRect;

impl Studio {
    pub(super) fn central(&mut self, ui: &mut egui::Ui) {
        let avail = ui.available_rect_before_wrap();
        let view_area = if self.mode == Mode::Paint && self.easel.session.views.get(self.easel.active).is_some() {
            let v = &self.easel.session.views[self.easel.active];
            let aspect = v.width as f32 / v.height as f32;
            let h = avail.height().min(avail.width() * 0.5 / aspect);
            let canvas = Rect::from_min_size(avail.min, Vec2::new(h * aspect, h));
            self.canvas_ui(ui, canvas);
            Rect::from_min_max(Pos2::new(canvas.max.x + 4.0, avail.min.y), avail.max)
        } else {
            avail
        };
        self.view_ui(ui, view_area);
    }

    fn view_ui(&mut self, ui: &mut egui::Ui, rect: Rect) {
        let px = self.to_pixels(rect);
        if px.width <= 0 || px.height <= 0 {
            self.layout.view_rect = None;
            return;
        }
        self.layout.view_rect = Some(px);
        self.navigate(ui, rect);
        self.draw_sun(ui, rect, px);
        let name = format!("{} · {}", short(self.model_name()), short(self.material_name()));
        let painter = ui.painter_at(rect);
        painter.text(
            rect.left_top() + Vec2::new(8.0, 6.0),
            egui::Align2::LEFT_TOP,
            name,
            egui::FontId::proportional(13.0),
            Color32::from_gray(200),
        );
        self.draw_meter(&painter, rect);
        self.draw_status_line(&painter, rect);
    }

    /// Drags and scrolls on the 3D view turn the camera, the light or the environment.
    fn navigate(&mut self, ui: &mut egui::Ui, rect: Rect) {
        let response = ui.interact(rect, ui.scope_id().with("3d view"), Sense::click_and_drag());
        let d = response.drag_delta();
        let (shift, alt) = ui.input(|i| (i.modifiers.shift, i.modifiers.alt));
        if response.dragged_by(PointerButton::Primary) && alt {
            // Alt: Shift is taken by pan, the right button by the light.
            self.env.turn(d.x * DEGREES_PER_POINT);
        } else if response.dragged_by(PointerButton::Primary) && !shift {
            self.stage.orbit.rotate(d.x * 0.01, d.y * 0.01);
        } else if response.dragged_by(PointerButton::Middle) || (response.dragged_by(PointerButton::Primary) && shift) {
            self.stage.orbit.pan(d.x, d.y, rect.height());
        } else if response.dragged_by(PointerButton::Secondary) {
            self.stage.light.drag(d.x * 0.01, -d.y * 0.01);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.stage.orbit.zoom((-scroll * 0.002).exp());
                self.env.moving = true;
            }
        }
        // A moving view takes fewer environment directions (environment module docs).
        self.env.moving |= response.dragged() && d != Vec2::ZERO;
    }

    /// The light's direction, drawn as a small sun beside the object (`px`: the view's pixels).
    fn draw_sun(&self, ui: &egui::Ui, rect: Rect, px: WindowRect) {
        let camera = self.stage.orbit.camera(rect.width() / rect.height());
        if let Ok(view) = crate::render::View::new(&camera, px.width as usize, px.height as usize) {
            let project = |p: glam::Vec3| {
                let c = view.view_proj * p.extend(1.0);
                (c.w > 0.0).then(|| {
                    Pos2::new(rect.min.x + (c.x / c.w * 0.5 + 0.5) * rect.width(), rect.min.y + (0.5 - c.y / c.w * 0.5) * rect.height())
                })
            };
            let centre = self.stage.orbit.target;
            let sun = centre + self.stage.light.direction() * self.stage.orbit.radius * 1.35;
            if let (Some(a), Some(b)) = (project(centre), project(sun)) {
                let p = ui.painter_at(rect);
                p.line_segment([a, b], Stroke::new(1.0, Color32::from_rgba_unmultiplied(255, 220, 120, 90)));
                p.circle_filled(b, 6.0, Color32::from_rgb(255, 214, 90));
            }
        }
    }

    /// The live-painting budget, where the eye is: the last stroke's way to the screen.
    fn draw_meter(&self, painter: &egui::Painter, rect: Rect) {
        if self.mode == Mode::Paint && self.meter.timings.count > 0 {
            let t = &self.meter.timings;
            let ok = t.total_ms <= 1000.0 / 60.0;
            let text = format!(
                "stroke -> frame {:.1} ms{}\nstroke {:.2} · samples {:.2} · solve {:.2} · upload {:.2} · frame {:.1} (3D {:.1}) · {} samples",
                t.total_ms,
                if ok { "" } else { " (over 16.7)" },
                t.stroke_ms,
                t.values_ms,
                t.solve_ms,
                t.upload_ms,
                t.frame_ms,
                t.view_ms,
                t.samples
            );
            let colour = if ok { Color32::from_rgb(120, 200, 130) } else { Color32::from_rgb(235, 140, 90) };
            let galley = painter.layout(text, egui::FontId::proportional(12.0), colour, rect.width() - 16.0);
            painter.galley(rect.left_top() + Vec2::new(8.0, 24.0), galley, colour);
        }
    }

    /// Errors, and in watch mode what the last look at the file found, along the bottom.
    fn draw_status_line(&self, painter: &egui::Painter, rect: Rect) {
        let watcher = self.easel.watcher.as_ref();
        let failed = watcher.is_some_and(|w| matches!(w.status(), WatchStatus::Failed(_)));
        let line = match (&self.status.error, watcher) {
            (Some(e), _) => Some((e.clone(), true)),
            (None, Some(_)) => Some((self.status(), failed)),
            _ => None,
        };
        if let Some((text, bad)) = line {
            let colour = if bad { Color32::from_rgb(240, 110, 90) } else { Color32::from_gray(190) };
            let galley = painter.layout(text, egui::FontId::proportional(13.0), colour, rect.width() - 16.0);
            let pos = rect.left_bottom() + Vec2::new(8.0, -8.0 - galley.size().y);
            painter.galley(pos, galley, colour);
        }
    }

    fn canvas_ui(&mut self, ui: &mut egui::Ui, rect: Rect) {
        let k = self.easel.active;
        let guides = (self.tools.show_outline, self.tools.show_reference);
        let tex = self.canvas_textures.update(ui.ctx(), &mut self.easel, k, guides);
        let response = ui.interact(rect, ui.scope_id().with("canvas"), Sense::click_and_drag());
        if let Some(tex) = tex {
            ui.painter().image(tex, rect, Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
        }
        let view = &self.easel.session.views[k];
        let (w, h) = (view.width as f32, view.height as f32);
        let scale = rect.width() / w;
        let to_canvas = |p: Pos2| glam::Vec2::new((p.x - rect.min.x) / scale, (p.y - rect.min.y) / scale);
        let pointer = response.interact_pointer_pos().or(response.hover_pos());
        let down = ui.input(|i| i.pointer.button_down(PointerButton::Primary));
        // A lit sphere's sun takes the pointer from the brush while it is grabbed.
        let light = self.sphere_canvas(ui, rect, scale);
        match self.tools.tool {
            _ if light => {}
            Tool::Brush | Tool::Eraser => {
                if response.is_pointer_button_down_on() && down {
                    if let Some(p) = pointer {
                        let t = Instant::now();
                        let canvas = &mut self.easel.session.views[k].canvas;
                        if !canvas.stroking() {
                            canvas.begin_stroke(self.tools.stroke_brush());
                        }
                        canvas.stroke_to(to_canvas(p));
                        self.meter.stroke_ms += t.elapsed().as_secs_f64() * 1e3;
                        self.easel.canvas_changed = true;
                    }
                } else if self.easel.session.views[k].canvas.stroking() {
                    self.easel.session.views[k].canvas.end_stroke();
                    self.easel.stroke_ended = true;
                }
            }
            Tool::Fill => {
                if response.clicked_by(PointerButton::Primary) {
                    if let Some(p) = pointer {
                        let c = to_canvas(p);
                        if c.x >= 0.0 && c.y >= 0.0 && c.x < w && c.y < h {
                            let t = Instant::now();
                            let region = self.easel.session.views[k].fill_region(c.x as usize, c.y as usize);
                            self.easel.session.views[k].canvas.fill(self.tools.brush, &region);
                            self.meter.stroke_ms += t.elapsed().as_secs_f64() * 1e3;
                            self.easel.canvas_changed = true;
                            self.easel.stroke_ended = true;
                        }
                    }
                }
            }
        }
        // Right-click: pick the painted colour (or the reference's) under the pointer.
        if response.clicked_by(PointerButton::Secondary) {
            if let Some(p) = pointer {
                let c = to_canvas(p);
                if c.x >= 0.0 && c.y >= 0.0 && c.x < w && c.y < h {
                    let view = &self.easel.session.views[k];
                    let i = c.y as usize * view.width + c.x as usize;
                    let p = view.canvas.painting();
                    self.tools.brush.color = if p.alpha[i] > 0.0 { p.pixels[i] } else { view.reference[i] };
                }
            }
        }
        if let Some(p) = response.hover_pos() {
            if self.tools.tool != Tool::Fill && !light {
                ui.painter_at(rect).circle_stroke(p, self.tools.brush.radius * scale, Stroke::new(1.0, Color32::from_gray(90)));
            }
        }
        let label = format!("painting: view '{}'", self.easel.view_label(k));
        ui.painter_at(rect).text(
            rect.left_top() + Vec2::new(6.0, 4.0),
            egui::Align2::LEFT_TOP,
            label,
            egui::FontId::proportional(13.0),
            Color32::from_gray(90),
        );
    }
}

/// A view's canvas texture, the guides it was drawn with, and the easel's generation it
/// belongs to.
struct CanvasTexture {
    texture: TextureHandle,
    guides: (bool, bool),
    generation: u64,
}

/// Per view: its canvas texture.
#[derive(Default)]
pub(super) struct CanvasTextures {
    textures: Vec<Option<CanvasTexture>>,
}

impl CanvasTextures {
    /// Redraws the changed part of view `k`'s canvas texture (all of it when the guides or
    /// the views changed): guides under the painting, outlines over it, sRGB-encoded. The
    /// texture, when view `k` exists.
    pub fn update(&mut self, ctx: &egui::Context, easel: &mut Easel, k: usize, guides: (bool, bool)) -> Option<egui::TextureId> {
        let generation = easel.generation;
        let view = easel.session.views.get_mut(k)?;
        if self.textures.len() <= k {
            self.textures.resize_with(k + 1, || None);
        }
        let full = self.textures[k].as_ref().is_none_or(|t| t.guides != guides || t.generation != generation);
        let dirty = view.canvas.take_dirty();
        let rect = if full { Some(CanvasRect { x0: 0, y0: 0, x1: view.width, y1: view.height }) } else { dirty };
        if let Some(r) = rect {
            let (w, h) = (r.x1 - r.x0, r.y1 - r.y0);
            let mut pixels = Vec::with_capacity(w * h);
            let painting = view.canvas.painting();
            for j in r.y0..r.y1 {
                for i in r.x0..r.x1 {
                    let idx = j * view.width + i;
                    let base = if guides.1 && view.hit[idx] {
                        // The reference, lightened, so paint stands out against it.
                        let c = view.reference[idx];
                        [0.55 + 0.45 * c[0], 0.55 + 0.45 * c[1], 0.55 + 0.45 * c[2]]
                    } else {
                        [1.0; 3]
                    };
                    let p = painting.pixels[idx];
                    let a = painting.alpha[idx].clamp(0.0, 1.0);
                    let mut c = [0, 1, 2].map(|q| base[q] * (1.0 - a) + p[q] * a);
                    if guides.0 && view.lines[idx] {
                        c = c.map(|x| x * 0.12);
                    }
                    let e = c.map(|x| (linear_to_srgb(x) * 255.0 + 0.5) as u8);
                    pixels.push(Color32::from_rgb(e[0], e[1], e[2]));
                }
            }
            let image = ColorImage::new([w, h], pixels);
            match &mut self.textures[k] {
                Some(t) if !full => t.texture.set_partial([r.x0, r.y0], image, TextureOptions::LINEAR),
                slot => {
                    let texture = ctx.load_texture(format!("canvas {k}"), image, TextureOptions::LINEAR);
                    *slot = Some(CanvasTexture { texture, guides, generation });
                }
            }
        }
        self.textures[k].as_ref().map(|t| t.texture.id())
    }
}
